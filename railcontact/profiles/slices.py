"""Rails that vary along the track: profiles ("slices") at positions s.

A variable rail (a crossing nose, a wing rail, a switch blade) is given by
cross-sections at positions s along the track, each a rail profile in the usual
convention (y to the field side of a right rail, z down, SI units).  Between the
slices the surface is interpolated as CONTACT does
(:class:`railcontact.geometry.sliced_surface.SlicedSurface`).

Sources
-------
* CONTACT's slices file ``.slcs`` (:func:`read_slices`; its user guide, appendix
  "Specification of the file <varprof>.slcs"):

  .. code-block:: text

     U_OFFSET  U_SCALE             % u_fc = U_SCALE (U_OFFSET + U_SLC) [mm]
     NSLC
     NFEAT  {NKINK  NACCEL}
     U_INTPOL {PERTURB}            % 1: interpolating spline along u
     [ U_SLC  'RFNAME' ]           % NSLC times, file names relative to the .slcs
     {[ P_KINK ], [ P_ACCEL ]}     % when NKINK, NACCEL > 0 (kept, not used)
     [ U_SLC  S_F(1..NFEAT) ]      % NSLC times when NFEAT > 1: the 'features' [mm],
                                   % summed chord lengths from the slice's first point;
                                   % negative: the slice lacks that feature (and the
                                   % parts beside it: an 'interruption')

  Lines starting with ``%`` are comments.  Slices must be given in increasing u.
* A list in a case file, ``rail.slices = [{s = -0.1, profile = "nose_1.prr"}, ...]``
  (:func:`slices_from_list`).

Every slice profile is read by :func:`read_slice_profile`, the one place where the
profile readers of :mod:`railcontact.profiles.io` are called (options such as
mirroring and scaling of the profile readers pass through it).
"""

from __future__ import annotations

import logging
import math
import re
import shlex
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..core.errors import ProfileError
from ..core.files import write_text
from .io import read_profile, write_profile
from .library import get_profile
from .profile import Profile

log = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class RailSlices:
    """Profiles of a rail at positions along the track.

    Attributes
    ----------
    s : ndarray (n,)
        Positions [m] of the slices along the track, strictly increasing.
    profiles : tuple of Profile
        The rail cross-section at each position (right-rail convention, SI units).
    features : ndarray (n, nfeat) or None
        Break points [m] of each slice: summed chord lengths from its first point
        (gauge side) at which the slice is divided into 'parts' resampled
        separately (CONTACT's features); None: one part, the whole slice.  A
        negative value marks a feature that the slice lacks: the parts on either
        side of it do not exist there (CONTACT's 'interruptions' of a rail along
        the track, e.g. a crossing nose that begins between two slices).
    name : str
    """

    s: np.ndarray
    profiles: tuple
    features: np.ndarray | None = None
    name: str = "slices"
    source: str = field(default="", compare=False)

    def __post_init__(self) -> None:
        s = np.asarray(self.s, dtype=float)
        if s.ndim != 1 or s.size < 2 or len(self.profiles) != s.size:
            raise ProfileError(f"rail slices {self.name!r}: expected at least two slices, each "
                               f"with a position s (got {s.size} positions, "
                               f"{len(self.profiles)} profiles)")
        if not np.all(np.isfinite(s)):
            raise ProfileError(f"rail slices {self.name!r}: a slice position is not finite")
        if np.any(np.diff(s) < 1e-6):
            i = int(np.flatnonzero(np.diff(s) < 1e-6)[0])
            raise ProfileError(f"rail slices {self.name!r}: positions must increase by at least "
                               f"1 um; slice {i + 2} at s = {s[i + 1]:.6g} m follows {s[i]:.6g} m")
        for p in self.profiles:
            if not isinstance(p, Profile) or p.kind != "rail":
                raise ProfileError(f"rail slices {self.name!r}: every slice must be a rail "
                                   "profile")
        if self.features is not None:
            f = np.asarray(self.features, dtype=float)
            if f.ndim != 2 or f.shape[0] != s.size or f.shape[1] < 2:
                raise ProfileError(f"rail slices {self.name!r}: expected features of shape "
                                   f"({s.size}, >= 2), got {f.shape}")
            if np.any(np.isnan(f)):
                raise ProfileError(f"rail slices {self.name!r}: a feature is NaN; expected a "
                                   "chord length [m], or a negative value for a feature that "
                                   "the slice lacks")
            whole = (f[:, :-1] >= 0) & (f[:, 1:] >= 0)
            if not whole.any(axis=1).all():
                i = int(np.flatnonzero(~whole.any(axis=1))[0])
                raise ProfileError(
                    f"rail slices {self.name!r}: slice {i + 1} (s = {s[i]:.6g} m) has no part: "
                    "expected two successive features (s_f >= 0) at least")
            object.__setattr__(self, "features", f)
        object.__setattr__(self, "s", s)
        object.__setattr__(self, "profiles", tuple(self.profiles))

    def __len__(self) -> int:
        return self.s.size


def read_slice_profile(path, units: str = "auto", mirror_y: bool = False,
                       z_down: bool | None = True, **options) -> Profile:
    """Read one slice of a variable rail with the profile readers of
    :mod:`railcontact.profiles.io` (the one place slices are read; further reader
    options in ``options`` are passed on).  CONTACT's slices hold z down
    (``MIRRORZ = -1``), which is the default here."""
    return read_profile(path, kind="rail", units=units, z_down=z_down, mirror_y=mirror_y,
                        **options)


def _tokens(path: Path):
    """The value groups of a slices file: one list of tokens per non-comment line."""
    out = []
    for ln, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
        s = line.split("%")[0].strip()
        if not s:
            continue
        try:
            toks = shlex.split(s, posix=True)
        except ValueError:
            toks = s.split()
        out.append((ln, toks))
    return out


def _leading(toks) -> list:
    """The leading numbers of a line (a label may follow them)."""
    vals = []
    for t in toks:
        try:
            vals.append(float(t.rstrip(",")))
        except ValueError:
            break
    return vals


def slice_lines(path, it, nslc: int, what: str):
    """The positions (each line's first number, ``what``: U_SLC or TH_SLC) and the
    profile file names of the ``nslc`` slice lines next in ``it`` (the value groups
    of :func:`_tokens`) of a rail or wheel slices file."""
    pos, names = [], []
    for _ in range(nslc):
        try:
            ln, t = next(it)
        except StopIteration:
            raise ProfileError(f"{path}: expected {nslc} slices, found {len(pos)}") from None
        lead = _leading(t)
        if not lead or len(t) < 2:
            raise ProfileError(f"{path}: line {ln}: expected {what} and a file name")
        pos.append(lead[0])
        names.append(t[1])
    return pos, names


def _numbers(path, ln, toks, n, what):
    """The first ``n`` numbers of a line (at least ``n`` expected)."""
    vals = _leading(toks)
    if len(vals) < n:
        bad = toks[len(vals)] if len(vals) < len(toks) else "end of line"
        raise ProfileError(f"{path}: line {ln}: {what}: expected {n} numbers, found "
                           f"{len(vals)} before {bad!r}")
    return vals[:n]


def read_slices(path, units: str = "auto", mirror_y: bool = False, **options) -> RailSlices:
    """Read a CONTACT slices file (``.slcs``) into :class:`RailSlices`.

    Parameters
    ----------
    path : str or Path
    units : {"auto", "mm", "m"}
        Length unit of the slice profile files (``"auto"``: from the file type or
        the profile width, as :func:`railcontact.profiles.io.read_profile`).
    mirror_y : bool
        Mirror the slices laterally (a left-side rail given in left coordinates).

    The positions are converted to metres: s = U_SCALE (U_OFFSET + U_SLC) / 1000.
    ``U_INTPOL = 2`` (CONTACT's approximating spline) is read as 1 (interpolating,
    logged).  Surface perturbations (``PERTURB``) are not supported (error).
    """
    path = Path(path)
    if not path.is_file():
        raise ProfileError(f"slices file {str(path)!r} does not exist")
    groups = _tokens(path)
    if len(groups) < 4:
        raise ProfileError(f"{path}: expected U_OFFSET U_SCALE, NSLC, NFEAT, U_INTPOL and "
                           "the slices; the file is too short")
    it = iter(groups)
    ln, t = next(it)
    u_offset, u_scale = _numbers(path, ln, t, 2, "U_OFFSET, U_SCALE")
    if not u_scale > 0:
        raise ProfileError(f"{path}: line {ln}: U_SCALE = {u_scale}: expected a factor > 0")
    ln, t = next(it)
    (nslc,) = _numbers(path, ln, t, 1, "NSLC")
    nslc = int(nslc)
    if nslc < 2:
        raise ProfileError(f"{path}: line {ln}: NSLC = {nslc}: expected at least 2 slices")
    ln, t = next(it)
    counts = [int(v) for v in _numbers(path, ln, t, 1, "NFEAT, NKINK, NACCEL")
              + _leading(t)[1:3]]
    nfeat, nkink, naccel = (counts + [0, 0])[:3]
    ln, t = next(it)
    vals = _numbers(path, ln, t, 1, "U_INTPOL, PERTURB") + _leading(t)[1:2]
    if int(vals[0]) not in (1, 2):
        raise ProfileError(f"{path}: line {ln}: U_INTPOL = {vals[0]:g}: expected 1 or 2")
    if int(vals[0]) == 2:
        log.warning("%s: U_INTPOL = 2 (approximating spline) read as 1 (interpolating)",
                    path.name)
    if len(vals) > 1 and int(vals[1]) != 0:
        raise ProfileError(f"{path}: line {ln}: PERTURB = {vals[1]:g}: surface perturbations "
                           "are not supported; expected 0")
    u, names = slice_lines(path, it, nslc, "U_SLC")
    for count in (nkink, naccel):
        if count > 0:
            next(it, None)                      # part numbers of kinks / accelerations
    feats = None
    if nfeat > 1:
        rows = []
        for k in range(nslc):
            try:
                ln, t = next(it)
            except StopIteration:
                raise ProfileError(f"{path}: expected feature positions for {nslc} slices, "
                                   f"found {k}") from None
            vals = _numbers(path, ln, t, nfeat + 1, "U_SLC and S_F")
            if abs(vals[0] - u[k]) > 1e-9 * max(1.0, abs(u[k])):
                raise ProfileError(f"{path}: line {ln}: feature row for U_SLC = {vals[0]:g}; "
                                   f"expected slice {k + 1} at {u[k]:g}")
            rows.append(vals[1:])
        feats = np.array(rows) * 1e-3           # mm -> m
    s = (u_offset + np.asarray(u)) * u_scale * 1e-3
    base = path.parent
    profiles = []
    for name in names:
        p = Path(name.replace("\\", "/"))
        profiles.append(read_slice_profile(p if p.is_absolute() else base / p, units=units,
                                           mirror_y=mirror_y, **options))
    log.info("%s: %d slices, s = [%.4g, %.4g] m, %d features per slice", path.name, nslc,
             s[0], s[-1], max(nfeat, 0))
    return RailSlices(s, tuple(profiles), feats, name=path.stem, source=str(path))


def slices_from_list(entries, base_dir: Path | None = None, units: str = "auto",
                     name: str = "slices") -> RailSlices:
    """:class:`RailSlices` from a list of ``{s = position [m], profile = file}`` (a case
    file's ``slices``), with optional ``features = [...]`` [m] per entry."""
    if not isinstance(entries, (list, tuple)) or len(entries) < 2:
        raise ProfileError(f"{name}: expected a list of at least two slices "
                           "{s = position [m], profile = file}")
    s, profiles, feats = [], [], []
    for k, e in enumerate(entries):
        if not isinstance(e, dict) or "s" not in e or "profile" not in e:
            raise ProfileError(f"{name}[{k}] = {e!r}: expected {{s = position [m], profile = "
                               "file}")
        v = e["s"]
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise ProfileError(f"{name}[{k}].s = {v!r}: expected a position in m")
        s.append(float(v))
        prof = e["profile"]
        if isinstance(prof, Profile):
            profiles.append(prof)
        else:
            p = Path(str(prof))
            if base_dir is not None and not p.is_absolute():
                p = Path(base_dir) / p
            profiles.append(read_slice_profile(p, units=e.get("units", units)))
        feats.append(e.get("features"))
    features = None
    if any(f is not None for f in feats):
        if any(f is None for f in feats):
            raise ProfileError(f"{name}: give features for every slice or for none")
        features = np.array(feats, dtype=float)
    return RailSlices(np.array(s), tuple(profiles), features, name=name)


def is_slices_file(spec) -> bool:
    """Whether a rail specification names a slices file."""
    return isinstance(spec, (str, Path)) and re.search(r"\.slcs$", str(spec), re.I) is not None


def write_slices(slices: RailSlices, path, units: str = "mm") -> Path:
    """Write a slices file (``.slcs``, CONTACT's format) and one SIMPACK profile
    file per slice in a folder beside it (``<stem>/<stem>_<k>.prr``); positions in
    mm (U_SCALE 1).  Returns the path of the ``.slcs`` file."""
    path = Path(path)
    folder = path.with_suffix("")
    folder.mkdir(parents=True, exist_ok=True)
    lines = [f"% rail slices {slices.name!r} written by railcontact", "",
             "   0.000   1.0   U_OFFSET [usr], U_SCALE [mm/usr], usr = mm",
             f"   {len(slices)}   NSLC",
             f"   {0 if slices.features is None else slices.features.shape[1]}   0   0   "
             "NFEAT, NKINK, NACCEL",
             "   1   U_INTPOL", "", "% slice positions U_SLC [mm] and file names"]
    for k, (sk, prof) in enumerate(zip(slices.s, slices.profiles), 1):
        name = f"{folder.name}/{folder.name}_{k}.prr"
        write_profile(prof, path.parent / name, units=units)
        lines.append(f"  {sk * 1e3:.6f}   '{name}'")
    if slices.features is not None:
        lines += ["", "% features S_F [mm] per slice"]
        for sk, f in zip(slices.s, slices.features):
            lines.append(f"  {sk * 1e3:.6f}   " + "  ".join(f"{v * 1e3:.6f}" for v in f))
    return write_text(path, "\n".join(lines) + "\n")


def _nose_section(width: float, drop: float, crown: float, corner: float,
                  depth: float = 0.04):
    """Points (y, z) [m] of a crossing nose's cross-section centred at y = 0: a crown
    of radius ``crown`` across ``width``, corner arcs of radius ``corner`` turning
    to 80 degree flanks, ``drop`` below the running level."""
    half = 0.5 * width
    r = min(corner, 0.45 * width)
    flat = half - r
    y = np.linspace(-half - 0.012, half + 0.012, 801)
    u = np.abs(y)
    z = drop + u ** 2 / (2 * crown)
    zc = drop + flat ** 2 / (2 * crown)
    th = math.radians(80.0)
    e = u - flat
    arc = (e > 0) & (e <= r * math.sin(th))
    z = np.where(arc, zc + r - np.sqrt(np.maximum(r * r - e * e, 0.0)), z)
    e_end, z_end = r * math.sin(th), zc + r - r * math.cos(th)
    z = np.where(e > e_end, np.minimum(z_end + (e - e_end) * math.tan(th), drop + depth), z)
    return y, z


def artificial_crossing(length: float = 0.5, n: int = 41, angle: float = 1 / 9,
                        nose_gauge: float = -0.026, flangeway: float = 0.042,
                        tip_width: float = 0.004, tip_drop: float = 0.006,
                        rise: float = 1 / 60, final_drop: float = 0.002,
                        crown: float = 0.2, corner: float = 0.005, wing: str = "60E1"):
    """An artificial common crossing for the right wheel of a straight route:
    the wing rail (a ``wing`` head, not inclined) diverging to the field side at
    ``angle`` from s = 0, and the nose on the gauge side: its gauge flank straight
    at ``nose_gauge`` [m], its width growing from ``tip_width`` at s = 0 at
    ``angle``, its crown starting ``tip_drop`` below the running level and rising
    at ``rise`` to ``final_drop`` below it (rail-profile coordinates of a rail
    placed at the wheel's tape circle; the flangeway at the tip ``flangeway``).

    Returns (nose, wing rail) as :class:`RailSlices` over s in [-0.05, ``length``]
    [m] (``n`` slices).  With an S1002 wheel at its nominal position the wheel
    runs down the diverging wing rail (its tread's cone), passes to the nose about
    0.09 m after the tip and is lifted by 2 mm on the rising nose: the 'dip' of a
    crossing.
    """
    s = np.linspace(-0.05, float(length), int(n))
    head = get_profile(wing, "rail", inclination=0.0)
    noses, wings = [], []
    for si in s:
        d = max(float(si), 0.0)
        w = tip_width + d * angle
        drop = max(tip_drop - rise * d, final_drop)
        y, z = _nose_section(w, drop, crown, corner)
        noses.append(Profile(y + nose_gauge + 0.5 * w, z, kind="rail", name=f"nose@{si:.4f}"))
        y_wing = nose_gauge + tip_width + flangeway + 0.036 + d * angle
        wings.append(head.shifted(y_wing, 0.0))
    return (RailSlices(s, tuple(noses), name="nose"),
            RailSlices(s, tuple(wings), name="wing rail"))
