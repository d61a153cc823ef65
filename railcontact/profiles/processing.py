"""Measured profiles as CONTACT reads them: the points taken along the arc length.

A measured profile is a sequence of points (y_i, z_i) along the surface.  Near a
vertical face (a rail's gauge face, a wheel's flange back) the lateral coordinate
need not increase monotonically: the measurement folds back, or its noise runs
back and forth.  The functions here treat the points as a plane curve
parametrised by its summed chord length s (CONTACT's ``s_prf``):

* :func:`remove_close_points` and :func:`remove_zigzags` repair the data (a
  point repeated where two measured sections were stitched gives a "zig-zag":
  two successive changes of inclination beyond a threshold, replaced by the
  mean of the two points);
* :func:`find_kinks` finds the true corners of the curve (a change of
  inclination above ``kink_high`` with no change above ``kink_low`` within
  ``kink_width`` on either side), where smoothing splits the curve;
* :func:`smooth_points` smooths y(s) and z(s) between the kinks with a cubic
  smoothing spline (Reinsch): it minimises
  ``sum_i w_i |x_i - f(s_i)|^2 + lambda * integral |f''(s)|^2 ds`` with
  ``w_i = 1`` ("unweighted", CONTACT's ISMOOTH = 0, ``lambda`` given) or
  ``w_i = ds_i`` and ``lambda = (L / 2 pi)^4`` ("weighted", ISMOOTH = 1, which
  halves fluctuations of wavelength L; Vollebregt, Proc. CM2022);
* :func:`visible_surface` turns a curve that folds back into the function
  z(y) that the other body can touch: a rail seen from above (the smallest z at
  each y, z down), a wheel seen from below (the largest z); a hidden undercut
  (below a folded gauge face or behind a flange back) is dropped;
* :func:`process_points` chains them with mirroring, scale and orientation
  (:class:`ProfileOptions`) into a :class:`~railcontact.profiles.profile.Profile`.

All lengths are in metres.  A smoothing ``lambda`` of CONTACT's unweighted
spline is in length^3: 10 mm^3 (a typical value for MiniProf data at 0.3-0.5 mm
spacing) is 1e-8 m^3.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np
from scipy import interpolate

from ..core.errors import ProfileError

log = logging.getLogger(__name__)

#: points closer than this [m] to the previous point kept are dropped (CONTACT:
#: 1e-4 mm)
CLOSE_POINTS = 1e-7
#: default threshold [rad] of the zig-zag repair (CONTACT: 150 deg)
ZIGZAG_ANGLE = math.radians(150.0)
#: default kink thresholds [rad] and window half-width [m] (CONTACT: 30 deg, 6 deg,
#: 2 mm)
KINK_HIGH = math.radians(30.0)
KINK_WIDTH = 2e-3
#: step [m] along the arc length at which a smoothed curve is sampled (at least
#: twice per data interval)
SAMPLE_STEP = 5e-5
#: a part of a folded curve visible over less than this width [m] at an end of the
#: visible surface is dropped (:func:`visible_surface`)
SLIVER = 5e-4

_METHODS = ("unweighted", "weighted")


@dataclass(frozen=True)
class Smoothing:
    """A smoothing spline along the arc length.

    Parameters
    ----------
    method : {"weighted", "unweighted"}
        ``"weighted"``: weights ds_i and ``value`` = L_filt [m], the wavelength
        whose fluctuations are halved (CONTACT's ISMOOTH = 1).
        ``"unweighted"``: unit weights and ``value`` = lambda [m^3] (CONTACT's
        ISMOOTH = 0; its effect depends on the point spacing: lambda * mean(ds)
        acts as the weighted (L / 2 pi)^4).
    value : float
        L_filt [m] or lambda [m^3]; 0 interpolates.
    """

    method: str = "weighted"
    value: float = 0.0

    def __post_init__(self):
        if self.method not in _METHODS:
            raise ProfileError(f"profile smoothing method {self.method!r}: expected one of "
                               f"{list(_METHODS)}")
        if not (isinstance(self.value, (int, float)) and math.isfinite(self.value)
                and self.value >= 0):
            raise ProfileError(f"profile smoothing {self.value!r}: expected a value >= 0 "
                               f"({'m' if self.method == 'weighted' else 'm^3'})")

    @property
    def active(self) -> bool:
        return self.value > 0

    def lam(self) -> float:
        """The penalty lambda of the spline [m^3] (weighted: (L / 2 pi)^4 [m^4] per
        unit weight length)."""
        return (self.value / (2 * math.pi)) ** 4 if self.method == "weighted" else self.value


@dataclass(frozen=True)
class ProfileOptions:
    """How a measured profile is brought into railcontact's form (CONTACT's profile
    inputs).

    Parameters
    ----------
    mirror_y : bool, optional
        Mirror the lateral axis (a left-side measurement, or a MiniProf file with
        the track centre to the right).  None: as the reader decides (a wheel whose
        flange lies at positive y is mirrored).
    mirror_z : bool, optional
        Mirror the vertical axis.  None: detected (z down: into the rail head and
        away from the wheel axle).
    scale : float
        Factor applied to the coordinates after the unit conversion (CONTACT's
        SCALE, e.g. for a file in inches read as millimetres, 25.4).
    smoothing : Smoothing, optional
        Smoothing spline along the arc length; None interpolates the points.
    zigzag : float
        Angle threshold [rad] of the zig-zag repair; >= pi disables it.
    kink_high, kink_low : float
        Kink thresholds [rad]: a change of inclination above ``kink_high`` with none
        above ``kink_low`` (default ``kink_high`` / 5) within ``kink_width`` [m].
        ``kink_high`` >= pi disables kink detection.
    """

    mirror_y: bool | None = None
    mirror_z: bool | None = None
    scale: float = 1.0
    smoothing: Smoothing | None = None
    zigzag: float = ZIGZAG_ANGLE
    kink_high: float = KINK_HIGH
    kink_low: float | None = None
    kink_width: float = KINK_WIDTH

    def __post_init__(self):
        if not (isinstance(self.scale, (int, float)) and math.isfinite(self.scale)
                and self.scale > 0):
            raise ProfileError(f"profile scale {self.scale!r}: expected a factor > 0")
        for name in ("zigzag", "kink_high", "kink_width"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ProfileError(f"profile {name} {v!r}: expected a value > 0")
        if self.kink_low is not None and not (math.isfinite(self.kink_low)
                                              and self.kink_low >= 0):
            raise ProfileError(f"profile kink_low {self.kink_low!r}: expected a value >= 0")

    @property
    def low(self) -> float:
        return self.kink_high / 5.0 if self.kink_low is None else float(self.kink_low)

    @classmethod
    def from_table(cls, table: dict, where: str) -> "ProfileOptions":
        """Options from a case file's profile table (``[wheel]`` or ``[rail]``):
        ``mirror_y``, ``mirror_z`` (true/false, or "auto"), ``scale``, ``smoothing``
        (L_filt [m], or ``{method = "unweighted", lambda = ...}`` /
        ``{method = "weighted", length = ...}``), ``zigzag`` [rad] and ``kinks =
        {high, low, width}``."""
        def flag(key):
            v = table.get(key, "auto")
            if v == "auto":
                return None
            if not isinstance(v, bool):
                raise ProfileError(f"{where}.{key} = {v!r}: expected true, false or 'auto'")
            return v

        def number(v, key):
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise ProfileError(f"{where}.{key} = {v!r}: expected a number")
            return float(v)

        sm = table.get("smoothing")
        smoothing = None
        if sm is not None:
            if isinstance(sm, dict):
                unknown = set(sm) - {"method", "lambda", "length"}
                if unknown:
                    raise ProfileError(f"{where}.smoothing: unknown key(s) {sorted(unknown)}; "
                                       "expected method and lambda [m^3] or length [m]")
                method = sm.get("method", "weighted" if "length" in sm else "unweighted")
                key = "length" if method == "weighted" else "lambda"
                if key not in sm:
                    raise ProfileError(f"{where}.smoothing: method {method!r} needs {key}")
                smoothing = Smoothing(method, number(sm[key], f"smoothing.{key}"))
            else:
                smoothing = Smoothing("weighted", number(sm, "smoothing"))
        kinks = table.get("kinks", {})
        if not isinstance(kinks, dict) or set(kinks) - {"high", "low", "width"}:
            raise ProfileError(f"{where}.kinks = {kinks!r}: expected a table with high, low "
                               "[rad] and width [m]")
        return cls(mirror_y=flag("mirror_y"), mirror_z=flag("mirror_z"),
                   scale=number(table.get("scale", 1.0), "scale"), smoothing=smoothing,
                   zigzag=number(table.get("zigzag", ZIGZAG_ANGLE), "zigzag"),
                   kink_high=number(kinks.get("high", KINK_HIGH), "kinks.high"),
                   kink_low=None if "low" not in kinks else number(kinks["low"], "kinks.low"),
                   kink_width=number(kinks.get("width", KINK_WIDTH), "kinks.width"))


# ------------------------------------------------------------------ curve basics
def arc_length(y, z) -> np.ndarray:
    """Summed chord length s_i [m] of the points (s_0 = 0)."""
    return np.concatenate(([0.0], np.cumsum(np.hypot(np.diff(y), np.diff(z)))))


def _inclination_changes(y, z):
    """Change of inclination [rad] at each interior point, in (-pi, pi]."""
    a = np.arctan2(np.diff(z), np.diff(y))
    d = np.diff(a)
    return (d + np.pi) % (2 * np.pi) - np.pi


def remove_close_points(y, z, distance: float = CLOSE_POINTS):
    """Drop each point closer than ``distance`` [m] to the last point kept."""
    y, z = np.asarray(y, dtype=float), np.asarray(z, dtype=float)
    step = np.hypot(np.diff(y), np.diff(z))
    if np.all(step >= distance):
        return y, z
    keep = [0]
    for i in range(1, y.size):       # rare: only where the fast path above failed
        if math.hypot(y[i] - y[keep[-1]], z[i] - z[keep[-1]]) >= distance:
            keep.append(i)
    return y[keep], z[keep]


def remove_zigzags(y, z, threshold: float = ZIGZAG_ANGLE):
    """Replace each zig-zag, two successive changes of inclination both larger than
    ``threshold`` [rad] (a point repeated with a slight offset where two measured
    sections were stitched), by the mean of its two middle points.  Returns the
    points and the number of zig-zags removed."""
    y, z = np.asarray(y, dtype=float), np.asarray(z, dtype=float)
    if y.size <= 3 or threshold >= math.pi:
        return y, z, 0
    d = np.abs(_inclination_changes(y, z))           # at points 1 .. n-2
    big = d > threshold
    # segment k (points k, k+1) with big changes at both its ends
    cand = np.flatnonzero(big[:-1] & big[1:]) + 1    # k: points k and k+1 merge
    if cand.size == 0:
        return y, z, 0
    keep = np.ones(y.size, dtype=bool)
    ny, nz = y.copy(), z.copy()
    last = -2
    n = 0
    for k in cand:                       # a handful per profile
        if k <= last + 1 or k + 1 >= y.size - 1:
            continue
        ny[k], nz[k] = 0.5 * (y[k] + y[k + 1]), 0.5 * (z[k] + z[k + 1])
        keep[k + 1] = False
        last = k + 1
        n += 1
    return ny[keep], nz[keep], n


def find_kinks(y, z, high: float = KINK_HIGH, low: float | None = None,
               width: float = KINK_WIDTH) -> np.ndarray:
    """Indices of the kinks of the curve, its first and last point included.

    A kink is a point where the inclination changes by more than ``high`` [rad]
    while it changes by no more than ``low`` (default ``high`` / 5) at the other
    points within ``width`` [m] on either side: an isolated corner (a true edge of
    the profile) as opposed to roughness, which smoothing should reduce.
    """
    y, z = np.asarray(y, dtype=float), np.asarray(z, dtype=float)
    n = y.size
    low = high / 5.0 if low is None else low
    out = [0]
    if n >= 3 and high < math.pi:
        d = np.abs(_inclination_changes(y, z))       # d[i - 1] at point i
        for i in np.flatnonzero(d > high) + 1:       # few candidates
            dist = np.hypot(y - y[i], z - z[i])
            near = (dist < width) & (np.arange(n) >= 1) & (np.arange(n) <= n - 2)
            near[i] = False
            if np.any(d[np.flatnonzero(near) - 1] > low):
                continue
            if i - out[-1] == 2:
                out.append(i - 1)        # no section of one interval between kinks
            out.append(int(i))
    if out[-1] != n - 1:
        out.append(n - 1)
    return np.asarray(out, dtype=int)


def smooth_points(y, z, smoothing: Smoothing | None, kinks=None, step: float | None = None):
    """The curve through (or smoothed from) the points, sampled along its arc length.

    Between successive kinks (indices into the points, first and last included;
    default none) y(s) and z(s) are fitted by one natural cubic spline each, a
    smoothing spline where ``smoothing`` is active (see :class:`Smoothing`; held
    at the kink points, so that the sections meet at the corner), else
    interpolating; a section of fewer than five points is kept as it is.  The
    splines are sampled every ``step`` [m] of arc length (default: the smaller of
    ``SAMPLE_STEP`` and half the median point spacing) and at the kinks.

    Returns the sampled points (y, z) [m].
    """
    y, z = np.asarray(y, dtype=float), np.asarray(z, dtype=float)
    s = arc_length(y, z)
    ds = np.diff(s)
    if step is None:
        step = min(SAMPLE_STEP, 0.5 * float(np.median(ds)))
    kinks = np.asarray([0, y.size - 1] if kinks is None else kinks, dtype=int)
    lam = smoothing.lam() if smoothing is not None and smoothing.active else 0.0
    ys, zs = [], []
    # the spline is set up in millimetres, where the numbers are of order one
    for a, b in zip(kinks[:-1], kinks[1:]):
        sec = slice(a, b + 1)
        ss, pts = s[sec] * 1e3, np.column_stack((y[sec], z[sec])) * 1e3
        n = ss.size
        m = max(int(math.ceil((ss[-1] - ss[0]) / (step * 1e3))), 1)
        si = np.linspace(ss[0], ss[-1], m + 1)
        if n < 5:
            out = np.column_stack([np.interp(si, ss, pts[:, k]) for k in (0, 1)])
        elif lam > 0:
            if smoothing.method == "weighted":
                w = np.empty(n)
                w[1:-1] = 0.5 * (ss[2:] - ss[:-2])
                w[0], w[-1] = 0.5 * (ss[1] - ss[0]), 0.5 * (ss[-1] - ss[-2])
                lam_mm = lam * 1e12
            else:
                w = np.ones(n)
                lam_mm = lam * 1e9
            # a section ending at a kink passes through the kink point (the corner
            # stays where it is and the sections meet there)
            pin = 1e8 * float(w.max())
            if a > 0:
                w[0] = pin
            if b < y.size - 1:
                w[-1] = pin
            spl = interpolate.make_smoothing_spline(ss, pts, w=w, lam=lam_mm)
            out = spl(si)
        else:
            out = interpolate.make_interp_spline(ss, pts, k=3, bc_type="natural")(si)
        if ys:                       # the kink point starts the next section
            out = out[1:]
        ys.append(out[:, 0] * 1e-3)
        zs.append(out[:, 1] * 1e-3)
    return np.concatenate(ys), np.concatenate(zs)


# ------------------------------------------------------------ the visible surface
def _runs(y):
    """Index ranges [a, b] of the maximal runs of strictly monotone y."""
    d = np.sign(np.diff(y))
    cut = np.flatnonzero(d[1:] != d[:-1]) + 1           # points where the direction turns
    starts = np.concatenate(([0], cut))
    ends = np.concatenate((cut, [y.size - 1]))
    return [(int(a), int(b)) for a, b in zip(starts, ends) if d[a] != 0 or b > a]


def _crossing_segments(y, z, runs):
    """A pair of segments of different runs that cross each other (the curve has a
    loop), or None.  Within a run y is monotone, so the curve cannot cross itself."""
    for r in range(len(runs)):
        for q in range(r + 1, len(runs)):
            i = np.arange(*runs[r])
            j = np.arange(*runs[q])
            lo = max(min(y[runs[r][0]], y[runs[r][1]]), min(y[runs[q][0]], y[runs[q][1]]))
            hi = min(max(y[runs[r][0]], y[runs[r][1]]), max(y[runs[q][0]], y[runs[q][1]]))
            if hi < lo:
                continue
            # the segments that reach into the common y-range
            i = i[(np.maximum(y[i], y[i + 1]) >= lo) & (np.minimum(y[i], y[i + 1]) <= hi)]
            j = j[(np.maximum(y[j], y[j + 1]) >= lo) & (np.minimum(y[j], y[j + 1]) <= hi)]
            if i.size == 0 or j.size == 0:
                continue
            y0i, y1i = np.minimum(y[i], y[i + 1]), np.maximum(y[i], y[i + 1])
            y0j, y1j = np.minimum(y[j], y[j + 1]), np.maximum(y[j], y[j + 1])
            ii, jj = np.nonzero((y0i[:, None] <= y1j[None, :]) & (y0j[None, :] <= y1i[:, None]))
            if ii.size == 0:
                continue
            I, J = i[ii], j[jj]
            ry, rz = y[I + 1] - y[I], z[I + 1] - z[I]
            sy, sz = y[J + 1] - y[J], z[J + 1] - z[J]
            qy, qz = y[J] - y[I], z[J] - z[I]
            den = ry * sz - rz * sy
            with np.errstate(divide="ignore", invalid="ignore"):
                t = (qy * sz - qz * sy) / den
                u = (qy * rz - qz * ry) / den
            eps = 1e-9
            hit = (den != 0) & (t > eps) & (t < 1 - eps) & (u > eps) & (u < 1 - eps)
            if hit.any():
                k = int(np.flatnonzero(hit)[0])
                return int(I[k]), int(J[k])
    return None


def visible_surface(y, z, kind: str, name: str = "profile"):
    """The function z(y) of the surface the other body touches, from points that
    may fold back in y.

    A rail is seen from above (z down: the smallest z at each y), a wheel from
    below, from the rail (the largest z): the part of a folded face that another
    part covers (the undercut below a folded gauge face, the continuation behind
    a flange back) is hidden.  Where the visible surface passes from one part of
    the curve to another, their crossing is inserted.  A part visible over less
    than ``SLIVER`` at an end is dropped (a point added under an overhanging head
    to extend a measured gauge face would otherwise end the surface with a step).  A curve whose segments
    cross each other (a loop) is not a profile: ProfileError.

    Returns (y, z) with y strictly increasing.
    """
    y, z = np.asarray(y, dtype=float), np.asarray(z, dtype=float)
    if y.size >= 2 and y[-1] < y[0]:
        y, z = y[::-1], z[::-1]
    dy = np.diff(y)
    if np.all(dy > 0):
        return y, z
    runs = _runs(y)
    bad = _crossing_segments(y, z, runs)
    if bad is not None:
        i = bad[0]
        raise ProfileError(f"profile {name!r} crosses itself near y = {y[i] * 1e3:.3f} mm, "
                           f"z = {z[i] * 1e3:.3f} mm (point {i + 1}): a loop is not a profile; "
                           "expected a curve along the surface")
    sgn = 1.0 if kind == "rail" else -1.0        # seen side: min of sgn * z
    w = sgn * z
    parts = []
    for a, b in runs:
        ya, wa = y[a:b + 1], w[a:b + 1]
        if ya[-1] < ya[0]:
            ya, wa = ya[::-1], wa[::-1]
        parts.append((ya, wa))
    Y = np.unique(np.concatenate([p[0] for p in parts]))
    W = np.full((len(parts), Y.size), np.inf)
    for k, (ya, wa) in enumerate(parts):
        inside = (Y >= ya[0]) & (Y <= ya[-1])
        W[k, inside] = np.interp(Y[inside], ya, wa)
    best = np.argmin(W, axis=0)
    # a part visible only as a sliver at an end of the profile (a point added below an
    # overhanging head to extend a gauge face) is dropped: the surface ends where the
    # part above it ends, instead of with a step down to the sliver
    for end in (0, -1):
        change = np.flatnonzero(best[1:] != best[:-1])
        if change.size == 0:
            break
        k = change[0] + 1 if end == 0 else change[-1]
        # (an end point the next part shares, where the two parts meet, stays)
        shared = np.isfinite(W[best[k], end])
        if not shared and abs(Y[k] - Y[end]) < SLIVER:
            keep = np.arange(Y.size) >= k if end == 0 else np.arange(Y.size) <= k
            Y, W, best = Y[keep], W[:, keep], best[keep]
    env = W[best, np.arange(Y.size)]
    # insert the crossing where the visible part changes between two lines
    ch = np.flatnonzero(best[1:] != best[:-1])
    ys, ws = [Y], [env]
    for j in ch:
        p, q = best[j], best[j + 1]
        d0 = W[p, j] - W[q, j]
        d1 = W[p, j + 1] - W[q, j + 1]
        if np.isfinite(d0) and np.isfinite(d1) and d0 != d1 and d0 * d1 < 0:
            t = d0 / (d0 - d1)
            ys.append([Y[j] + t * (Y[j + 1] - Y[j])])
            ws.append([W[p, j] + t * (W[p, j + 1] - W[p, j])])
    yv = np.concatenate(ys)
    wv = np.concatenate(ws)
    order = np.argsort(yv, kind="stable")
    yv, wv = yv[order], wv[order]
    keep = np.concatenate(([True], np.diff(yv) > 1e-12))
    yv, zv = yv[keep], sgn * wv[keep]
    hidden = y.size - int(np.isin(y, yv).sum())
    log.info("profile %s folds back in y; the surface visible from the %s kept (%d of %d "
             "points hidden)", name, "top" if kind == "rail" else "rail", hidden, y.size)
    return yv, zv


# ----------------------------------------------------------------- orientation
def z_points_down(y, z, kind: str) -> bool:
    """Whether the vertical axis of measured points already points down (into the
    rail head, away from the wheel axle): a rail's side faces reach down from its
    head (z grows from the head towards both ends), a wheel's flange reaches out
    (its largest z lies inside, its smallest at a side)."""
    y, z = np.asarray(y, dtype=float), np.asarray(z, dtype=float)
    n = z.size
    if kind == "wheel":
        fmin, fmax = np.argmin(z) / n, np.argmax(z) / n
        if fmin < 0.05 or fmin > 0.95:
            return True
        if fmax < 0.05 or fmax > 0.95:
            return False
        mid = int(round(n * 0.5 * (fmin + fmax)))
        return not z[min(mid, n - 1)] > 0.5 * (z.min() + z.max())
    tol = 1e-3 * max(float(np.ptp(z)), 1e-8)

    def change(idx, ref):
        for i in idx:
            d = z[i] - z[ref]
            if abs(d) > tol:
                return np.sign(d)
        return 0.0

    head = change(range(1, max(int(0.1 * n), 2)), 0)
    tail = change(range(n - 2, min(int(0.9 * n), n - 2) - 1, -1), n - 1)
    vote = head if (head == tail or tail == 0) else tail if head == 0 else head
    # interior lower than the ends (z decreasing inwards): z points down
    return vote <= 0


# ------------------------------------------------------- CONTACT's parametric spline
class ChordSpline:
    """The profile as CONTACT's interpolating spline takes it: y(s) and z(s) cubic
    in the summed chord length s of the points (CONTACT's ``s_prf``), natural (free
    ends, zero second derivative) in each section between the kinks
    (:func:`find_kinks`), through every point (CONTACT's spline with SMOOTH = 0;
    of a smoothed profile, the spline through its points before smoothing).

    ``s`` is 0 where the points cross y = 0 when y increases strictly along them,
    else at the point nearest the origin (CONTACT's ``grid_make_arclength``), so
    that a rail's s is CONTACT's ``sr``.  Used where CONTACT's rules read the
    profile along s: the wheel samples of its planar undeformed distance
    (:class:`railcontact.geometry.gap.SampledWheelGap`), the gauge point
    (:func:`railcontact.geometry.track.contact_gauge_point`) and the rail's s of a
    transient case's grid.  Lengths in metres.
    """

    #: sub-samples per interval of the table that inverts y(s)
    TABLE = 16

    def __init__(self, y, z, kind: str = "rail"):
        y, z = np.asarray(y, dtype=float), np.asarray(z, dtype=float)
        if y.size < 4 or y.shape != z.shape:
            raise ProfileError(f"chord-length spline of {y.size} points: expected at least 4 "
                               "points with y and z alike")
        self.y, self.z, self.kind = y, z, kind
        s = arc_length(y, z)
        if np.all(np.diff(y) > 0) and y[0] <= 0.0 <= y[-1]:
            s0 = float(np.interp(0.0, y, s))
        else:
            s0 = float(s[int(np.argmin(y * y + z * z))])
        self.s = s - s0
        kinks = find_kinks(y, z)
        self._sections = [(interpolate.CubicSpline(self.s[a:b + 1], y[a:b + 1], bc_type="natural"),
                           interpolate.CubicSpline(self.s[a:b + 1], z[a:b + 1], bc_type="natural"))
                          for a, b in zip(kinks[:-1], kinks[1:])]
        self._bounds = self.s[kinks]
        # a dense table of the curve for the inverse s(y)
        t = (self.s[:-1, None] + np.diff(self.s)[:, None]
             * (np.arange(self.TABLE)[None, :] / self.TABLE)).ravel()
        self._stab = np.concatenate((t, self.s[-1:]))
        self._ytab, self._ztab = self.point(self._stab)

    def _section(self, s):
        return np.clip(np.searchsorted(self._bounds, s, side="right") - 1, 0,
                       len(self._sections) - 1)

    def point(self, s, nu: int = 0):
        """(y, z) [m] at chord lengths ``s`` [m] (``nu``: their derivative), each on
        its section's spline (continued beyond the ends)."""
        s = np.asarray(s, dtype=float)
        k = self._section(s)
        y, z = np.empty(s.shape), np.empty(s.shape)
        for j in np.unique(k):
            sel = k == j
            sy, sz = self._sections[j]
            y[sel], z[sel] = sy(s[sel], nu), sz(s[sel], nu)
        return y, z

    def s_at_y(self, y):
        """Chord length s [m] where the curve reaches lateral position ``y`` [m], on
        the part of it the other body sees where it folds back (a rail seen from
        above: the smallest z; a wheel from the rail: the largest); ``y`` beyond the
        profile: its first or last point's s (as CONTACT's ``spline_get_s_at_y``
        returns)."""
        y = np.asarray(y, dtype=float)
        out = np.array([self._s_at(float(v)) for v in y.ravel()])
        return out.reshape(y.shape) if y.ndim else float(out[0])

    def _s_at(self, y: float) -> float:
        yt, st = self._ytab, self._stab
        d = yt - y
        cross = np.flatnonzero((d[:-1] <= 0) != (d[1:] <= 0))
        if cross.size == 0:                 # beyond the profile: the nearer end
            return float(st[0] if abs(y - yt[0]) <= abs(y - yt[-1]) else st[-1])
        t = d[cross] / (d[cross] - d[cross + 1])
        s = st[cross] + t * (st[cross + 1] - st[cross])
        z = self._ztab[cross] + t * (self._ztab[cross + 1] - self._ztab[cross])
        k = int(np.argmin(z) if self.kind == "rail" else np.argmax(z))
        lo, hi = float(st[cross[k]]), float(st[cross[k] + 1])
        sk = float(s[k])
        for _ in range(3):          # Newton on y(s) = y within the table interval
            ys, dys = self.point(sk)[0], self.point(sk, 1)[0]
            if not abs(dys) > 1e-6:
                break
            sk = min(max(sk - (float(ys) - y) / float(dys), lo), hi)
        return sk
