"""Out-of-round wheels: wheel profiles ("slices") at angles around the circumference.

CONTACT's wheel slices file ``.slcw`` (its user guide, "Wheel slices-file" and
the appendix on ``<varprof>.slcs/.slcw``) has the structure of a rail slices file
(:mod:`railcontact.profiles.slices`), with angles theta_wc around the wheel in the
place of positions along the track:

.. code-block:: text

   TH_OFFSET  TH_SCALE           % theta_wc = TH_SCALE (TH_OFFSET + TH_SLC) [rad]
   NSLC
   NFEAT  {NKINK  NACCEL}
   TH_INTPOL                     % 1: interpolating, 2: approximating spline
   [ TH_SLC  'WFNAME' ]          % NSLC times, increasing; file names relative to it

Each slice is a wheel profile in the usual convention (its z the radial height
with respect to the nominal radius).  The surface is defined on theta_wc in
[-pi, pi) and extended periodically; where the slices cover a smaller interval
[theta_0, theta_1] (a local defect such as a wheel flat) the surface is constant
outside it.  :meth:`WheelSlices.radial_deviation` gives the difference of the
profile at theta from a reference profile on that rule (CONTACT's approximating
spline along theta, or linear between slices).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.interpolate import BSpline

from ..core.errors import ProfileError
from .io import read_profile
from .profile import Profile
from .slices import _numbers, _tokens, slice_lines

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class WheelSlices:
    """Wheel profiles at angles ``theta`` [rad] (increasing) around the circumference.

    Parameters
    ----------
    theta : array    angles theta_wc [rad] of the slices, increasing
    profiles : tuple of Profile   the wheel profile of each slice
    name : str
    approximating : bool
        Along theta, CONTACT's approximating spline (TH_INTPOL = 2): the cubic
        B-spline with knots at the slices whose control points are the slices'
        heights (a little smoothing: at a slice (z_(k-1) + 4 z_k + z_(k+1)) / 6 for
        equal spacing); else linear between the slices.
    """

    theta: np.ndarray
    profiles: tuple
    name: str = "wheel slices"
    approximating: bool = False

    def __post_init__(self):
        th = np.asarray(self.theta, dtype=float)
        if th.ndim != 1 or th.size < 2 or th.size != len(self.profiles):
            raise ProfileError(f"wheel slices {self.name!r}: expected at least 2 angles and "
                               f"one profile each, got {th.size} and {len(self.profiles)}")
        if np.any(np.diff(th) <= 0):
            i = int(np.flatnonzero(np.diff(th) <= 0)[0])
            raise ProfileError(f"wheel slices {self.name!r}: angles must increase; slice "
                               f"{i + 2} at {th[i + 1]:.6g} rad follows {th[i]:.6g} rad")
        for p in self.profiles:
            if not isinstance(p, Profile) or p.kind != "wheel":
                raise ProfileError(f"wheel slices {self.name!r}: every slice must be a wheel "
                                   "profile")
        object.__setattr__(self, "theta", th)
        object.__setattr__(self, "profiles", tuple(self.profiles))

    def __len__(self) -> int:
        return self.theta.size

    @property
    def y_range(self) -> tuple:
        """The lateral range [m] that every slice covers."""
        return (max(p.y_min for p in self.profiles), min(p.y_max for p in self.profiles))

    def heights(self, y) -> np.ndarray:
        """z of every slice at lateral positions y [m]: (slices, len(y)); NaN outside
        a slice."""
        y = np.atleast_1d(np.asarray(y, dtype=float))
        out = np.full((len(self), y.size), np.nan)
        for k, p in enumerate(self.profiles):
            ok = (y >= p.y_min) & (y <= p.y_max)
            out[k, ok] = p.z_at(y[ok])
        return out

    def radial_deviation(self, theta, y, reference: Profile) -> np.ndarray:
        """z(theta, y) - z_ref(y) [m] at angles theta [rad] (wrapped to [-pi, pi);
        constant beyond the slices' interval where they do not cover it) and lateral
        positions y [m] (arrays of one shape): linear between the slices."""
        th, y = np.broadcast_arrays(np.asarray(theta, float), np.asarray(y, float))
        t = np.mod(th + math.pi, 2 * math.pi) - math.pi
        t = np.clip(t, self.theta[0], self.theta[-1])
        if self.approximating:
            return self._approximated(t, y) - reference.z_at(y)
        k = np.clip(np.searchsorted(self.theta, t, side="right") - 1, 0, len(self) - 2)
        w = (t - self.theta[k]) / (self.theta[k + 1] - self.theta[k])
        out = np.empty(th.shape)
        ref = reference.z_at(y)
        for j in np.unique(k):                # the few slice pairs the points lie between
            m = k == j
            z0 = self.profiles[j].z_at(y[m])
            z1 = self.profiles[j + 1].z_at(y[m])
            out[m] = (1 - w[m]) * z0 + w[m] * z1 - ref[m]
        return out


    def _approximated(self, t, y):
        """z at (t, y) of the approximating B-spline along theta (control points
        the slices, the end ones doubled: the spline ends at the end slices)."""
        th = self.theta
        knots = np.concatenate([[th[0]] * 4, th[1:-1], [th[-1]] * 4])
        D = BSpline.design_matrix(t.ravel(), knots, 3).tocsc()
        ctrl = np.concatenate([[0], np.arange(len(self)), [len(self) - 1]])
        yf = y.ravel()
        out = np.zeros(yf.size)
        for col in np.flatnonzero(np.diff(D.indptr)):   # the few splines near t
            rows = D.indices[D.indptr[col]:D.indptr[col + 1]]
            w = D.data[D.indptr[col]:D.indptr[col + 1]]
            out[rows] += w * self.profiles[ctrl[col]].z_at(yf[rows])
        return out.reshape(t.shape)


def _parse(path: Path):
    """(theta [rad], slice files) of a wheel slices file."""
    if not path.is_file():
        raise ProfileError(f"wheel slices file {str(path)!r} does not exist")
    groups = _tokens(path)
    if len(groups) < 5:
        raise ProfileError(f"{path}: expected TH_OFFSET TH_SCALE, NSLC, NFEAT, TH_INTPOL and "
                           "the slices; the file is too short")
    it = iter(groups)
    ln, t = next(it)
    th_offset, th_scale = _numbers(path, ln, t, 2, "TH_OFFSET, TH_SCALE")
    if not th_scale > 0:
        raise ProfileError(f"{path}: line {ln}: TH_SCALE = {th_scale}: expected a factor > 0")
    ln, t = next(it)
    nslc = int(_numbers(path, ln, t, 1, "NSLC")[0])
    if nslc < 2:
        raise ProfileError(f"{path}: line {ln}: NSLC = {nslc}: expected at least 2 slices")
    ln, t = next(it)
    nfeat = int(_numbers(path, ln, t, 1, "NFEAT, NKINK, NACCEL")[0])
    if nfeat > 1:
        raise ProfileError(f"{path}: line {ln}: NFEAT = {nfeat}: features of wheel slices are "
                           "not supported; expected 0 or 1")
    ln, t = next(it)
    intpol = int(_numbers(path, ln, t, 1, "TH_INTPOL")[0])
    if intpol not in (1, 2):
        raise ProfileError(f"{path}: line {ln}: TH_INTPOL = {intpol}: expected 1 or 2")
    if intpol == 1:
        log.info("%s: TH_INTPOL = 1 (interpolating spline) read as linear interpolation",
                 path.name)
    th, names = slice_lines(path, it, nslc, "TH_SLC")
    theta = th_scale * (th_offset + np.asarray(th))
    files = []
    for name in names:
        p = Path(name.replace("\\", "/"))
        files.append(p if p.is_absolute() else path.parent / p)
    return theta, files, intpol == 2


def slice_files(path) -> list:
    """The slice profile files [Path] a wheel slices file names, in its order."""
    return _parse(Path(path))[1]


def read_wheel_slices(path, units: str = "auto", **options) -> WheelSlices:
    """Read a CONTACT wheel slices file (``.slcw``) into :class:`WheelSlices`.

    The angles are theta = TH_SCALE (TH_OFFSET + TH_SLC) [rad]; each slice is read by
    :func:`railcontact.profiles.io.read_profile` as a wheel profile (``options``:
    its ``z_down``, ``mirror_y``, ``options`` as for the wheel's WFNAME).
    ``TH_INTPOL = 2``: CONTACT's approximating spline along theta; ``TH_INTPOL =
    1`` (its interpolating spline) is read as linear interpolation between the
    slices (logged); features (NFEAT > 1) are not supported (error)."""
    path = Path(path)
    theta, files, approx = _parse(path)
    profiles = [read_profile(f, kind="wheel", units=units, **options) for f in files]
    log.info("%s: %d wheel slices, theta = [%.4g, %.4g] rad", path.name, len(files),
             theta[0], theta[-1])
    return WheelSlices(theta, profiles, path.name, approx)
