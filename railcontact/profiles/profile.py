"""The :class:`Profile` type: a wheel or rail cross-section in SI units.

Conventions (see ``docs/conventions.md``)
-----------------------------------------
* ``y`` [m] is the lateral coordinate, increasing towards the *field side* of a
  right wheel / right rail.  A left wheel or rail uses the mirrored profile.
* ``z`` [m] points *downwards* for both bodies: into the rail head for a rail, and
  away from the axle for a wheel (so a wheel's rolling radius is ``r0 + z``).
* Wheel origin: the tape circle (for S1002, 70 mm from the flange back).
  Rail origin: the highest point of the rail head as mounted (after inclination).

A profile is evaluated through a cubic spline ``z(y)``: :meth:`Profile.z`,
:meth:`Profile.slope` and :meth:`Profile.curvature`.  Interpolating splines are
used by default; :meth:`Profile.smoothed` smooths along the arc length with the
weighted smoothing spline of CONTACT (cut-off wavelength a physical length, split
at kinks; :mod:`railcontact.profiles.processing`).  Points that fold back in y
(a measured gauge face or flange back) give the surface the other body sees.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from numba import njit
from scipy import interpolate

from ..core.errors import ProfileError
from .processing import ChordSpline, Smoothing, find_kinks, smooth_points, visible_surface

log = logging.getLogger(__name__)

#: plausible extent of a wheel or rail profile [m]
MIN_WIDTH, MAX_WIDTH = 0.01, 0.4       # 10 mm: a rail head on a 1:5 scaled roller rig
MAX_HEIGHT = 0.2


@njit(cache=True, nogil=True)
def _segment(breaks, xi):
    """Index of the polynomial piece holding xi (end points to the end pieces)."""
    n = breaks.size - 1
    return min(max(np.searchsorted(breaks, xi, side="right") - 1, 0), n - 1)


@njit(cache=True, nogil=True)
def ppoly_at(xi, breaks, c, k=-1):
    """Value, slope and interval of a cubic piecewise polynomial at the scalar xi
    (NaN outside).  ``k`` is a guess of the interval (a neighbouring point's): the
    search walks from it for up to 16 intervals before falling back to bisection."""
    n = breaks.size - 1
    if not (breaks[0] <= xi <= breaks[n]):
        return np.nan, np.nan, k
    if 0 <= k < n:
        for _ in range(16):                     # walk from the guess ...
            if xi < breaks[k] and k > 0:
                k -= 1
            elif xi >= breaks[k + 1] and k < n - 1:
                k += 1
            else:
                break
    if not (0 <= k < n and breaks[k] <= xi and (xi < breaks[k + 1] or k == n - 1)):
        k = _segment(breaks, xi)                # ... or search
    t = xi - breaks[k]
    return ((((c[0, k] * t + c[1, k]) * t + c[2, k]) * t + c[3, k]),
            (3.0 * c[0, k] * t + 2.0 * c[1, k]) * t + c[2, k], k)


@dataclass(eq=False)
class Profile:
    """Wheel or rail profile z(y) in SI units.

    Parameters
    ----------
    y, z : array_like
        Lateral and vertical (downward) coordinates [m], in order along the
        surface.  Duplicate points are removed; where the points fold back in y the
        visible surface is kept (:func:`~railcontact.profiles.processing.visible_surface`:
        a rail seen from above, a wheel from the rail); a curve crossing itself is an
        error.
    kind : {"wheel", "rail"}
        Which body the profile belongs to.
    name : str
        Label used in messages and results.
    smoothing : float, optional
        L_filt [m] of the smoothing spline along the arc length that the profile is
        evaluated through (CONTACT's weighted spline: fluctuations of wavelength
        L_filt are halved; kinks are kept); 0 (default) interpolates the points.

    A profile is immutable (its arrays are read-only): built-in profiles and parsed
    files are cached and shared by the cases that name them.  Methods such as
    ``shifted``, ``rotated`` and ``resampled`` return new profiles.
    """

    y: np.ndarray
    z: np.ndarray
    kind: str = "rail"
    name: str = "profile"
    smoothing: float = 0.0
    _spline: object = field(init=False, repr=False, default=None)
    #: the points along the surface before the visible surface is taken (where they
    #: fold back in y: CONTACT keeps them in its spline and its chord lengths)
    _curve: tuple = field(init=False, repr=False, default=None)

    def __post_init__(self) -> None:
        if self.kind not in ("wheel", "rail"):
            raise ProfileError(f"profile kind {self.kind!r}: expected 'wheel' or 'rail'")
        y = np.asarray(self.y, dtype=float).ravel()
        z = np.asarray(self.z, dtype=float).ravel()
        if y.shape != z.shape:
            raise ProfileError(f"profile {self.name!r}: y and z differ in length "
                               f"({y.size} and {z.size})")
        if y.size < 8:
            raise ProfileError(f"profile {self.name!r}: {y.size} points; expected at least 8")
        if not (np.all(np.isfinite(y)) and np.all(np.isfinite(z))):
            bad = int(np.flatnonzero(~(np.isfinite(y) & np.isfinite(z)))[0])
            raise ProfileError(f"profile {self.name!r}: point {bad + 1} is NaN or infinite; "
                               "expected finite coordinates")
        if y[-1] < y[0]:
            y, z = y[::-1], z[::-1]
        keep = np.concatenate(([True], np.hypot(np.diff(y), np.diff(z)) > 1e-9))
        y, z = y[keep], z[keep]
        self._curve = (y, z)
        # points that fold back in y (a measured gauge face or flange back): the
        # surface the other body sees (processing.visible_surface)
        y, z = visible_surface(y, z, self.kind, self.name)
        width, height = y[-1] - y[0], np.ptp(z)
        if not (MIN_WIDTH <= width <= MAX_WIDTH) or height > MAX_HEIGHT:
            raise ProfileError(
                f"profile {self.name!r}: width {width:.4g} m and height {height:.4g} m are "
                f"implausible; expected a width of {MIN_WIDTH * 1e3:.0f}-{MAX_WIDTH * 1e3:.0f} mm "
                "(are the units right? files in mm must be read with units='mm')")
        if self.smoothing < 0 or not np.isfinite(self.smoothing):
            raise ProfileError(f"profile smoothing {self.smoothing!r}: expected a length >= 0 m")
        self.y, self.z = y, z
        self._spline = self._fit()
        pp = interpolate.PPoly.from_spline(self._spline)
        keep = np.concatenate(([True], np.diff(pp.x) > 0))   # drop repeated end knots
        xk = pp.x[keep]
        ck = pp.c[:, keep[:-1]][:, :xk.size - 1]
        self._breaks = np.ascontiguousarray(xk)
        self._coefs = np.ascontiguousarray(ck)
        # the Python paths evaluate through scipy's PPoly (NaN outside); compiled
        # callers take the breaks and coefficients to ppoly_at
        self._pp = interpolate.PPoly(self._coefs, self._breaks, extrapolate=False)
        # a profile is immutable: parsed files and built-in profiles are cached and
        # shared by every case that names them, so an edit in place would reach them
        for a in (self.y, self.z, self._breaks, self._coefs):
            a.setflags(write=False)

    # ------------------------------------------------------------------ spline
    def _fit(self):
        y, z = self.y, self.z
        if self.smoothing > 0:
            # smoothing spline along the arc length, split at the kinks (CONTACT's
            # weighted spline: lambda = (L / 2 pi)^4 halves wavelength L), sampled
            # densely; the function through its visible surface, held to the
            # points' range [y_min, y_max] (the smoothed ends move by far less than
            # a sample: cut there, or continued flat)
            ys, zs = smooth_points(y, z, Smoothing("weighted", self.smoothing),
                                   find_kinks(y, z))
            ys, zs = visible_surface(ys, zs, self.kind, self.name)
            inside = (ys > y[0]) & (ys < y[-1])
            zl, zr = np.interp([y[0], y[-1]], ys, zs)
            y, z = (np.concatenate(([y[0]], ys[inside], [y[-1]])),
                    np.concatenate(([zl], zs[inside], [zr])))
        return interpolate.make_interp_spline(y, z, k=3)

    @property
    def y_min(self) -> float:
        return float(self.y[0])

    @property
    def y_max(self) -> float:
        return float(self.y[-1])

    def _eval(self, y, nu: int):
        """The spline's derivative ``nu`` at y (scipy's PPoly); NaN outside the points."""
        y = np.asarray(y, dtype=float)
        out = self._pp(y, nu)
        out[(y < self.y[0]) | (y > self.y[-1])] = np.nan
        return out if y.ndim else out[()]

    def z_at(self, y):
        """Height z(y) [m]; NaN outside the profile."""
        return self._eval(y, 0)

    def slope(self, y):
        """Slope dz/dy [-]; NaN outside the profile."""
        return self._eval(y, 1)

    def z_and_slope(self, y):
        """Height z(y) [m] and slope dz/dy [-] together; NaN outside."""
        y = np.asarray(y, dtype=float)
        return self._eval(y, 0), self._eval(y, 1)

    def second_derivative(self, y):
        """d2z/dy2 [1/m]; NaN outside the profile."""
        return self._eval(y, 2)

    def curvature(self, y):
        """Signed curvature z'' / (1 + z'^2)^(3/2) [1/m] (positive: centre below, z down)."""
        d1, d2 = self.slope(y), self.second_derivative(y)
        return d2 / (1.0 + d1 * d1) ** 1.5

    # ---------------------------------------------------------- transformations
    def _new(self, y, z, name=None, smoothing=None) -> "Profile":
        return Profile(y, z, kind=self.kind, name=name or self.name,
                       smoothing=self.smoothing if smoothing is None else smoothing)

    def smoothed(self, length: float) -> "Profile":
        """Return the profile smoothed along its arc length with cut-off wavelength
        ``length`` [m] (L_filt of CONTACT's weighted smoothing spline; its points
        stay, its evaluation is smoothed)."""
        if not (length > 0):
            raise ProfileError(f"smoothing length {length!r}: expected a length > 0 m")
        return self._new(self.y, self.z, smoothing=length)

    def resampled(self, step: float | None = None, n: int | None = None) -> "Profile":
        """Return the profile resampled at uniform arc-length spacing.

        Give either ``step`` [m] or the number of points ``n``.
        """
        yf = np.linspace(self.y[0], self.y[-1], 20 * self.y.size)
        zf = self.z_at(yf)
        s = np.concatenate(([0.0], np.cumsum(np.hypot(np.diff(yf), np.diff(zf)))))
        if n is None:
            if step is None or not step > 0:
                raise ProfileError(f"resampling step {step!r}: expected a length > 0 m")
            n = max(int(round(s[-1] / step)) + 1, 8)
        si = np.linspace(0.0, s[-1], n)
        return self._new(np.interp(si, s, yf), np.interp(si, s, zf), smoothing=0.0)

    def mirrored(self) -> "Profile":
        """Profile mirrored about y = 0 (right <-> left body)."""
        return self._new(-self.y[::-1], self.z[::-1])

    def shifted(self, dy: float = 0.0, dz: float = 0.0) -> "Profile":
        """Profile with its origin moved: returns points (y + dy, z + dz)."""
        return self._new(self.y + dy, self.z + dz)

    def rotated(self, angle: float) -> "Profile":
        """Rotate about the origin by ``angle`` [rad] about +x (x along the track).

        With y to the field side and z down, a positive angle raises the field side:
        this is a rail inclined (canted) towards the track centre by ``angle``.
        """
        c, s = np.cos(angle), np.sin(angle)
        y = c * self.y + s * self.z
        z = -s * self.y + c * self.z
        return self._new(y, z)

    def with_origin_at_top(self) -> "Profile":
        """Shift so that the highest point (minimum z) is the origin."""
        yy = np.linspace(self.y[0], self.y[-1], 40 * self.y.size)
        zz = self.z_at(yy)
        i = int(np.nanargmin(zz))
        # refine with the zero of the slope around the sampled minimum
        lo, hi = yy[max(i - 1, 0)], yy[min(i + 1, yy.size - 1)]
        from scipy.optimize import brentq
        y0 = yy[i]
        if self.slope(lo) < 0 < self.slope(hi):
            y0 = brentq(lambda t: float(self.slope(t)), lo, hi, xtol=1e-12)
        return self.shifted(-y0, -float(self.z_at(y0)))

    @cached_property
    def _arc_table(self):
        """(y, s) of the arc-length table on 20 points per profile point, built once
        (a profile is immutable)."""
        yf = np.linspace(self.y[0], self.y[-1], 20 * self.y.size)
        s = np.concatenate(([0.0], np.cumsum(np.hypot(np.diff(yf), np.diff(self.z_at(yf))))))
        return yf, s

    @cached_property
    def chord_spline(self) -> ChordSpline:
        """CONTACT's parametric spline of the points, y(s) and z(s) along their summed
        chord length (:class:`~railcontact.profiles.processing.ChordSpline`), built
        once: through the points as given (a part that folds back in y included)."""
        return ChordSpline(*self._curve, kind=self.kind)

    def arc_length(self, y):
        """Curvilinear coordinate along the profile from its first point [m]."""
        yf, s = self._arc_table
        return np.interp(y, yf, s)

    def __repr__(self) -> str:
        return (f"Profile({self.name!r}, kind={self.kind!r}, {self.y.size} points, "
                f"y = [{self.y[0] * 1e3:.2f}, {self.y[-1] * 1e3:.2f}] mm)")
