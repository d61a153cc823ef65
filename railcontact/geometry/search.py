"""Contact search: wheelset position, contact patches and their geometry.

Algorithm
---------
1. For a wheelset pose (lateral shift, yaw given; vertical position and roll
   unknown) the contact locus of each side gives the vertical gap g(y_w) along the
   wheel profile (:mod:`railcontact.geometry.locus`).
2. Vertical position and roll are solved so that the deepest interpenetration of
   each side equals its target: zero (rigid contact, both wheels touch) or the
   elastic approach that carries the given vertical wheel load.  The approach is
   found with Hertz's theory applied to every local minimum of the gap
   (multi-Hertzian), so that two-point contact shares the load between tread and
   flange.
3. Each connected interpenetration region of the locus is a contact patch (regions
   closer than ``combine_distance`` are merged).  Its reference point and contact
   angle are the weighted means over the region with CONTACT's default weight, the
   integral of the squared interpenetration over x for a parabolic gap in x,
   (-g)^2.5 (``GAP_WEIGHT``; CONTACT's "weighted centre, weighted angle",
   ``compute_wgt_center_1d``, whose linear option integrates the interpenetration
   itself, (-g)^1.5).
4. Per patch: lateral positions on wheel and rail, rolling radius, principal
   relative curvatures (finite differences of the exact gap), kinematic creepages,
   and the undeformed distance h(x, y) on any grid of the tangent plane, computed
   from the rail cylinder and the wheel's surface of revolution with yaw and roll.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field

import numpy as np
from numba import njit
from scipy.optimize import brentq
from scipy.signal import find_peaks

from ..errors import ContactNotFoundError, InputError
from ..materials import STEEL, Material
from ..hertz_theory import hertz_ellipse
from ..profiles.profile import ppoly_at
from .contact import ContactGeometry, interaction_factor
from .locus import LOCUS_WINDOW, Locus, compute_locus, min_gap
from .track import SIDES, Track, Wheelset, WheelsetPose
from .turning import turned_angles

log = logging.getLogger(__name__)

#: local minima of the gap deeper than the global minimum plus this are candidates [m]
CANDIDATE_DEPTH = 3e-4
#: finite-difference steps for the curvatures of the gap [m] (rolling, lateral)
FD_STEP = (2e-3, 2e-4)


@dataclass
class WheelsetContact:
    """Result of the contact search for one wheelset position.

    Attributes
    ----------
    pose : WheelsetPose
        Lateral shift and yaw as given; vertical position and roll as solved.
    patches : list of ContactGeometry
        All contact patches, left side first, each side from field to gauge side.
    loci : dict
        The contact locus of each side (side frame).
    loads : dict or None
        The vertical wheel load [N] of each side the search was given, else None.
    interpenetration : dict or None
        The vertical interpenetration [m] of each side the patches were cut at.

    How the solve layer's vertical-force iteration ended is not the search's: see
    :class:`railcontact.solve.VerticalBalance`.
    """

    pose: WheelsetPose
    patches: list
    loci: dict = field(repr=False, default_factory=dict)
    loads: dict | None = None
    interpenetration: dict | None = None

    def side_patches(self, side: str) -> list:
        return [p for p in self.patches if p.side == side]

    def equivalent_point(self, side: str) -> dict:
        """Weighted combination of a side's patches (CONTACT's patch-combination rule).

        Returns rolling radius [m], contact angle [rad] and y positions [m].
        """
        ps = self.side_patches(side)
        if not ps:
            raise ContactNotFoundError(f"no contact on the {side} side")
        w = np.array([p.weight for p in ps])
        w = w / w.sum()
        return {k: float(np.dot(w, [getattr(p, k) for p in ps]))
                for k in ("rolling_radius", "contact_angle", "y_rail", "y_wheel")}


# ----------------------------------------------------------------- helpers
def _locus_curvatures(loc: Locus, i: int, r0: float):
    """Relative curvatures (A, B) [1/m] at locus index i, in the normal section."""
    ang = math.atan(loc.slope[i])
    rho = r0 + loc.z_wheel[i]
    A = math.cos(ang) / (2.0 * rho)
    sel = np.abs(loc.y_rail - loc.y_rail[i]) <= 2.5e-4
    sel &= np.isfinite(loc.gap)
    if sel.sum() >= 5:
        # least-squares parabola g ~ c0 t^2 + c1 t + c2 in t = dy / 0.25 mm (normal
        # equations: a 3 x 3 system, well conditioned in the scaled t)
        t = (loc.y_rail[sel] - loc.y_rail[i]) / 2.5e-4
        V = np.stack((t * t, t, np.ones_like(t)), axis=1)
        c = np.linalg.solve(V.T @ V, V.T @ loc.gap[sel])
        B = c[0] / 2.5e-4 ** 2 * math.cos(ang) ** 3
    else:
        B = 0.0
    return A, max(B, 1e-3)


def _candidates(loc: Locus):
    g = np.where(np.isfinite(loc.gap), loc.gap, 1.0)
    peaks, _ = find_peaks(-g, prominence=1e-7)
    gmin = loc.gap_min
    idx = [int(i) for i in peaks if g[i] <= gmin + CANDIDATE_DEPTH]
    if loc.i_min not in idx:
        idx.append(loc.i_min)
    return sorted(idx)


def _approach_for_load(loc: Locus, load: float, r0: float, material: Material) -> float:
    """Vertical interpenetration [m] of the deepest point that carries ``load`` [N]."""
    cands = _candidates(loc)
    gmin = loc.gap_min
    data = []
    Es = material.contact_modulus
    for i in cands:
        A, B = _locus_curvatures(loc, i, r0)
        # at fixed curvatures Hertz's force grows as the approach^(3/2): one solution
        # gives its factor
        k = hertz_ellipse(A, B, Es, penetration=1e-4).force / 1e-6
        data.append((loc.gap[i] - gmin, k, math.cos(math.atan(loc.slope[i]))))

    def vertical_force(d):
        total = 0.0
        for off, k, c in data:
            pen = (d - off) * c
            if pen > 0:
                total += k * pen * math.sqrt(pen) * c
        return total

    hi = 1e-4
    while vertical_force(hi) < load:
        hi *= 2.0
        if hi > 0.05:
            raise ContactNotFoundError(f"wheel load {load:g} N cannot be carried "
                                       "(interpenetration above 50 mm)")
    return brentq(lambda d: vertical_force(d) - load, 0.0, hi, xtol=1e-13)


#: exponent of the interpenetration in the weights of a patch's reference point and
#: contact angle: CONTACT's default weights each locus sample by the integral of the
#: squared interpenetration over x, which for a parabolic gap in x grows as (-g)^2.5
#: (its reference points on the Manchester 10 kN sweep are reproduced to 4 um except
#: where it combines two regions into one patch; (-g)^1.5 put them 0.06-1.1 mm away on
#: the 10-20 mm wide tread patches)
GAP_WEIGHT = 2.5

#: the loci of the multi-Hertzian estimate cover the wheel samples within this [m] of
#: the closest approach: every candidate (a local minimum within CANDIDATE_DEPTH of
#: it) with the samples of its curvature fit, and the same candidates (their
#: prominence is decided within 0.1 mm of them)
ESTIMATE_WINDOW = CANDIDATE_DEPTH + 2e-4

#: the loci of given interpenetrations cover the wheel samples whose vertical gap is
#: within the interpenetration plus this [m] of the closest approach (the regions
#: of negative gap and a margin around them)
REGION_MARGIN = 2e-4

#: a locus's wheel-sample range serves the minimum-gap search within this roll [rad]
#: of its own, for a locus window of REGION_MARGIN (proportionally more for a wider
#: window): a roll of 1e-4 moves the wheel sideways by r0 roll (46 um) and turns it
#: (the wheel is 0.14 m wide: 14 um); on rail slopes up to 3 (the gauge corner) the
#: gaps shift relative to each other by under 0.15 mm, three quarters of the window
WINDOW_ROLL = 1e-4

#: rate [m/rad] at which the difference of the two sides' vertical gaps changes with
#: the roll: about the lateral distance between the contact points (the start of the
#: secant steps of :func:`_solve_pose`)
ROLL_SLOPE = 1.5


@dataclass
class _PoseMemo:
    """What successive searches of one case (one track, shift and yaw) carry over."""

    track: Track
    #: minimum vertical gaps of both sides by roll
    gaps: dict = field(default_factory=dict)
    #: per side the last locus's (roll, wheel-sample range, roll it serves within)
    windows: dict = field(default_factory=dict)
    #: the last roll search's secant slope [m/rad]
    slope: float = ROLL_SLOPE


def _memo(wheelset, track, y_ws, yaw) -> _PoseMemo:
    """The wheelset's memo for this track, shift and yaw (the track itself is held,
    so that the identity check is sound; bounded in size)."""
    if len(wheelset.gap_memo) > 64:
        wheelset.gap_memo.clear()
    memo = wheelset.gap_memo.get((y_ws, yaw))
    if memo is None or memo.track is not track or len(memo.gaps) > 256:
        memo = wheelset.gap_memo[(y_ws, yaw)] = _PoseMemo(track)
    return memo


def _solve_pose(wheelset, track, y_ws, yaw, targets, roll0=0.0, tol=1e-12,
                roll_given=None, sides=SIDES, loci_window=None):
    """Vertical position and roll such that min gap of each side = -target.

    The vertical gap of both sides decreases by exactly dz when the wheelset moves
    down by dz, so z follows from the roll angle; the remaining condition
    gap_left - gap_right = t_right - t_left increases monotonically with roll and
    is solved by secant steps from ``roll0``, or where they do not settle (a jump of
    the contact point) by a bracketed root search.

    ``loci_window``: what the loci hold.  None: every part of the wheel within
    ``LOCUS_WINDOW`` of the rail; ``"regions"``: the interpenetration regions only
    (the patches), the samples within the side's interpenetration plus
    ``REGION_MARGIN`` of its closest approach; a number [m]: within that of the
    closest approach (``ESTIMATE_WINDOW``: the candidates of the multi-Hertzian
    estimate), and at least the regions.
    """
    memo = _memo(wheelset, track, y_ws, yaw)
    cache, windows = memo.gaps, memo.windows

    def window(side):
        if loci_window is None:
            return LOCUS_WINDOW
        regions = targets[side] + REGION_MARGIN
        return regions if loci_window == "regions" else max(float(loci_window), regions)

    if roll_given is not None:
        (side,) = sides
        g = min_gap(wheelset, track, side, y_ws, 0.0, roll_given, yaw)
        if not np.isfinite(g):
            raise ContactNotFoundError(f"no wheel-rail overlap found on the {side} side at "
                                       f"lateral shift {y_ws * 1e3:.3f} mm")
        z = g + targets[side]
        loci = {side: compute_locus(wheelset, track, side, y_ws, z, roll_given, yaw,
                                    window=window(side))}
        return z, roll_given, loci

    def samples(side, roll):
        # the last locus's wheel samples hold the minimum at a roll close enough to
        # its own (below)
        w = windows.get(side)
        return w[1] if w is not None and abs(roll - w[0]) <= w[2] else None

    def gaps(roll):
        if roll not in cache:
            g = {s: min_gap(wheelset, track, s, y_ws, 0.0, roll, yaw, samples=samples(s, roll))
                 for s in SIDES}
            if not all(np.isfinite(v) for v in g.values()):
                raise ContactNotFoundError(
                    f"no wheel-rail overlap found at lateral shift {y_ws * 1e3:.3f} mm: the "
                    "wheel runs off the rail profile (check gauge, flange-back distance and "
                    "profiles)")
            cache[roll] = g
        return cache[roll]

    def f(roll):
        g = gaps(roll)
        return (g["left"] + targets["left"]) - (g["right"] + targets["right"])

    # secant steps from the start roll (f is nearly linear in the roll, with the slope
    # of the lateral distance between the contact points, about 1.5 m): two or three
    # evaluations where the start is close (successive searches of one case)
    roll, slope = _secant_roll(f, roll0, tol, memo.slope)
    if slope is not None:
        memo.slope = slope
    if roll is None:
        # no convergence (a jump of the contact point on the way): bracketed search
        roll = _bracketed_roll(f, roll0, tol, y_ws)
    g = gaps(roll)
    z = g["right"] + targets["right"]
    loci = {s: compute_locus(wheelset, track, s, y_ws, z, roll, yaw, window=window(s),
                             samples=samples(s, roll)) for s in SIDES}
    for s in SIDES:
        # a locus covering the gaps within w of its closest approach serves rolls
        # within WINDOW_ROLL w / REGION_MARGIN of its own (gap shifts under 0.75 w)
        windows[s] = (roll, loci[s].samples, WINDOW_ROLL * window(s) / REGION_MARGIN)
    return z, roll, loci


def _secant_roll(f, roll0, tol, slope=ROLL_SLOPE, steps=8):
    """Root of f(roll) by secant steps from ``roll0``, the first with ``slope`` (the
    last search's, else ``ROLL_SLOPE``).  Returns the root (None when the steps do
    not settle to ``tol``) and the last secant slope (None without one)."""
    x0, f0 = roll0, f(roll0)
    if f0 == 0.0:
        return x0, None
    x1 = x0 - f0 / slope
    last = None
    for _ in range(steps):
        f1 = f(x1)
        if f1 == 0.0:
            return x1, last
        if f1 == f0 or abs(x1 - roll0) > 0.05:
            return None, None
        last = (f1 - f0) / (x1 - x0)
        x0, f0, x1 = x1, f1, x1 - f1 / last
        if abs(x1 - x0) <= tol:
            # evaluated, and within the last step of the root
            return x0, last if 0.1 * ROLL_SLOPE < last < 10 * ROLL_SLOPE else None
    return None, None


def _bracketed_roll(f, roll0, tol, y_ws):
    """Root of the increasing f(roll) by bracketing from ``roll0`` and Brent's method."""
    span = 2e-3
    lo, hi = roll0 - span, roll0 + span
    while f(lo) > 0:
        lo -= 4 * span
        if lo < -0.1:
            raise ContactNotFoundError(f"wheelset roll not found at lateral shift {y_ws * 1e3:.3f} mm")
    while f(hi) < 0:
        hi += 4 * span
        if hi > 0.1:
            raise ContactNotFoundError(f"wheelset roll not found at lateral shift {y_ws * 1e3:.3f} mm")
    return brentq(f, lo, hi, xtol=tol, rtol=1e-15, maxiter=200)


def _end_point(loc: Locus, i: int, k: int):
    """Rail-surface point (y, z) [m] where the interpenetration region ending at
    locus sample i ends towards its neighbour k = i +- 1: the zero of the gap
    interpolated between them, so that it moves continuously with the
    interpenetration."""
    zr = loc.gap + loc.point[2]
    gi, gk = loc.gap[i], loc.gap[k]
    t = gi / (gi - gk) if np.isfinite(gk) and gk > 0 > gi else 0.0
    return (loc.y_rail[i] + t * (loc.y_rail[k] - loc.y_rail[i]),
            zr[i] + t * (zr[k] - zr[i]) if np.isfinite(zr[k]) else zr[i])


def _end_distance(loc: Locus, i: int, j: int) -> float:
    """Distance [m] between the facing ends of two interpenetration regions, the
    one ending at locus sample i and the one starting at sample j > i, on the rail
    surface: CONTACT measures it in y and z, so that a region on the flange flank,
    below one on the gauge corner, lies apart from it however close their lateral
    positions (its ends interpolated, :func:`_end_point`)."""
    (yi, zi), (yj, zj) = _end_point(loc, i, i + 1), _end_point(loc, j, j - 1)
    return float(math.hypot(yj - yi, zj - zi))


def _regions(loc: Locus, rigid: bool, combine_distance: float):
    """Index ranges [i0, i1] of the interpenetration regions of a locus, each with
    the joins inside it where regions closer than ``combine_distance`` were
    combined: (rail-profile position halfway between the facing ends [m], their
    distance [m], :func:`_end_distance`)."""
    if rigid:
        return [(loc.i_min, loc.i_min, ())]
    inside = loc.gap < 0.0
    if not inside.any():
        return [(loc.i_min, loc.i_min, ())]
    d = np.diff(inside.astype(int))
    starts = list(np.flatnonzero(d == 1) + 1)
    ends = list(np.flatnonzero(d == -1))
    if inside[0]:
        starts.insert(0, 0)
    if inside[-1]:
        ends.append(inside.size - 1)
    runs = [[int(a), int(b)] for a, b in zip(starts, ends)]
    merged = [runs[0] + [[]]]
    for a, b in runs[1:]:
        end = merged[-1][1]
        dist = _end_distance(loc, end, a)
        if dist < combine_distance:
            merged[-1][1] = b
            merged[-1][2].append((0.5 * float(loc.y_rail[a] + loc.y_rail[end]), float(dist)))
        else:
            merged.append([a, b, []])
    return [(a, b, tuple(j)) for a, b, j in merged]


#: Newton steps of the gap evaluation stop after a correction below this [m]: the
#: convergence is quadratic, so the error left is of order kappa * NEWTON_TOL^2 with
#: kappa <= 1e3 1/m the profile curvatures, below 1e-13 m
NEWTON_TOL = 1e-8


class _GapEvaluator:
    """Undeformed distance along the normal in a patch's tangent plane."""

    def __init__(self, wheelset: Wheelset, track: Track, side: str, loc: Locus,
                 center: np.ndarray, angle_side: float):
        self.rail = track.rail(side)
        self.wheel = wheelset.wheel(side)
        self.y_off = track.rail_offset(side)
        self.r0 = wheelset.nominal_radius
        self.e = wheelset.wheel_offset
        self.O, self.R = loc.origin, loc.axes
        self.C = center
        self.sign = 1.0 if side == "right" else -1.0
        self.n = np.array([0.0, -math.sin(angle_side), math.cos(angle_side)])
        self.t = np.array([0.0, math.cos(angle_side), math.sin(angle_side)])
        self.angle = angle_side
        self.y_ref = float(center[1] - self.y_off)
        # the frame packed for the multi-patch kernel: C, t, n, y_off, R^T, O, e, r0
        self.Rt = np.ascontiguousarray(self.R.T)
        self.frame = np.concatenate([self.C, self.t, self.n, [self.y_off], self.Rt.ravel(),
                                     self.O, [self.e, self.r0]]).astype(float)

    def contact_angle_at(self, y):
        """Local contact angle [rad] (track convention, as ``contact_angle``) at
        patch coordinate ``y`` [m]: the rail-surface inclination where the strip at
        y meets the rail, y_rail ~ y_ref + y cos(delta) on the side's profile axis."""
        ys = self.sign * np.asarray(y, dtype=float)
        yr = self.y_ref + ys * math.cos(self.angle)
        return self.sign * np.arctan(self.rail.slope(yr))

    def __call__(self, x, y):
        x = np.asarray(x, dtype=float)
        ys = self.sign * np.asarray(y, dtype=float)
        if x.ndim == 2 and ys.ndim == 2 and x.shape[1] == 1 and ys.shape[0] == 1:
            # a grid x[:, None], y[None, :]: line by line, the rail distance once per
            # line and every projection started from the neighbouring line's
            return _sane(_gap_lines_kernel(np.ascontiguousarray(x.T), np.ascontiguousarray(ys),
                                           self.frame[None, :], self.rail._breaks,
                                           self.rail._coefs, self.wheel._breaks,
                                           self.wheel._coefs)[0])
        x, ys = np.broadcast_arrays(x, ys)
        h = self.points(np.ascontiguousarray(x.ravel()), np.ascontiguousarray(ys.ravel()),
                        signed=True)
        return h.reshape(x.shape)

    def points(self, x, ys, signed=False):
        """The gap at points (x[i], y[i]) (1-D float arrays; ``signed``: y already
        in the side's lateral sense, as ``__call__`` passes it)."""
        if not signed:
            ys = self.sign * ys
        return _sane(_gap_kernel(x, ys, self.C, self.t, self.n, self.y_off, self.rail._breaks,
                                 self.rail._coefs, self.Rt, self.O, self.e, self.r0,
                                 self.wheel._breaks, self.wheel._coefs))


#: an undeformed distance below this [m] is no interpenetration of the patch: the
#: normal through the tangent-plane point met another part of a surface (far from a
#: steep patch, e.g. the other wall of a groove); taken as missing the surface
DEEPEST_GAP = -5e-3


def _sane(h: np.ndarray) -> np.ndarray:
    """The gap with points whose normal met another part of a surface (an
    interpenetration deeper than ``DEEPEST_GAP``) taken as missing it (1 m)."""
    return np.where(h < DEEPEST_GAP, 1.0, h)


@njit(cache=True, nogil=True)
def _rail_distance(ysp, C, t, n, y_off, rb, rc, tr, k=-1):
    """Distance along n from the tangent-plane point C + ysp t to the rail surface
    (the rail is straight along x, so x does not enter): Newton on
    z_r(P_y + tr n_y - y_off) = P_z + tr n_z from the estimate ``tr``, starting the
    profile lookup at interval ``k``.  Returns the distance and the interval."""
    p1 = C[1] + ysp * t[1]
    p2 = C[2] + ysp * t[2]
    for _ in range(8):
        zr, dzr, k = ppoly_at(p1 + tr * n[1] - y_off, rb, rc, k)
        step = (zr - (p2 + tr * n[2])) / (dzr * n[1] - n[2])
        tr -= step
        if not abs(step) > NEWTON_TOL:
            break
    return tr, k


@njit(cache=True, nogil=True)
def _wheel_distance(xp, ysp, C, t, n, Rt, O, e, r0, wb, wc, tw, k=-1):
    """Distance along n from the tangent-plane point C + xp (1, 0, 0) + ysp t to
    the wheel surface (radius r0 + z_w(eta - e) in wheelset axes), by Newton from
    the estimate ``tw``, starting the profile lookup at interval ``k``.  Returns the
    distance and the interval."""
    nl0 = Rt[0, 0] * n[0] + Rt[0, 1] * n[1] + Rt[0, 2] * n[2]
    nl1 = Rt[1, 0] * n[0] + Rt[1, 1] * n[1] + Rt[1, 2] * n[2]
    nl2 = Rt[2, 0] * n[0] + Rt[2, 1] * n[1] + Rt[2, 2] * n[2]
    d0 = C[0] + xp - O[0]
    d1 = C[1] + ysp * t[1] - O[1]
    d2 = C[2] + ysp * t[2] - O[2]
    l0 = Rt[0, 0] * d0 + Rt[0, 1] * d1 + Rt[0, 2] * d2
    l1 = Rt[1, 0] * d0 + Rt[1, 1] * d1 + Rt[1, 2] * d2
    l2 = Rt[2, 0] * d0 + Rt[2, 1] * d1 + Rt[2, 2] * d2
    return _wheel_newton(l0, l1, l2, nl0, nl1, nl2, e, r0, wb, wc, tw, k)


@njit(cache=True, nogil=True)
def _wheel_newton(l0, l1, l2, nl0, nl1, nl2, e, r0, wb, wc, tw, k):
    """:func:`_wheel_distance` from the point l and the direction nl in wheelset
    axes (the point's projection along n onto the wheel, by Newton)."""
    for _ in range(8):
        a0 = l0 + tw * nl0
        a2 = l2 + tw * nl2
        rho = math.sqrt(a0 * a0 + a2 * a2)
        zw, dzw, k = ppoly_at(l1 + tw * nl1 - e, wb, wc, k)
        step = (rho - (r0 + zw)) / ((a0 * nl0 + a2 * nl2) / rho - dzw * nl1)
        tw -= step
        if not abs(step) > NEWTON_TOL:
            break
    return tw, k


@njit(cache=True, nogil=True)
def _gap_kernel(x, ys, C, t, n, y_off, rb, rc, Rt, O, e, r0, wb, wc):
    """Distance along the normal n between rail and wheel surfaces through the
    tangent-plane points C + x (1, 0, 0) + ys t (1 m where a surface is missed)."""
    h = np.empty(x.size)
    kr = -1
    kw = -1
    for i in range(x.size):
        tr, kr = _rail_distance(ys[i], C, t, n, y_off, rb, rc, 0.0, kr)
        tw, kw = _wheel_distance(x[i], ys[i], C, t, n, Rt, O, e, r0, wb, wc, 0.0, kw)
        g = tr - tw
        h[i] = g if math.isfinite(g) else 1.0
    return h


@njit(cache=True, nogil=True)
def _equally_spaced(ys):
    """Whether the lines ys are equally spaced (to 1e-9 of their spacing)."""
    if ys.size < 3:
        return False
    d = ys[1] - ys[0]
    for j in range(2, ys.size):
        if abs(ys[j] - ys[j - 1] - d) > 1e-9 * abs(d):
            return False
    return True


@njit(cache=True, nogil=True)
def _gap_lines_kernel(x, ys, F, rb, rc, wb, wc):
    """Gaps of many patches sharing one rail and one wheel profile on lines of
    constant y: out[k, i, j] at (x[k, i], ys[k, j]) with row k of the packed frames
    ``F`` (``_GapEvaluator.frame``).  The rail distance is computed once per line;
    every projection starts from its neighbours' solutions: along the line (the
    wheel is smooth in x) where three points before it on the line are solved,
    else from the neighbouring lines."""
    nx = x.shape[1]
    h = np.empty((x.shape[0], nx, ys.shape[1]))
    tw = np.zeros((3, nx))              # the last three lines' wheel distances
    kw = np.full(nx, -1)
    tr = np.zeros(3)
    for k in range(x.shape[0]):
        f = F[k]
        C, t, n, O = f[0:3], f[3:6], f[6:9], f[19:22]
        Rt = f[10:19].reshape((3, 3))
        y_off, e, r0 = f[9], f[22], f[23]
        kr = -1
        quadratic = _equally_spaced(ys[k])
        along = _equally_spaced(x[k])
        # n and the tangent-plane axes in wheelset axes: a point's wheelset
        # coordinates are linear in its (x, y)
        nl0 = Rt[0, 0] * n[0] + Rt[0, 1] * n[1] + Rt[0, 2] * n[2]
        nl1 = Rt[1, 0] * n[0] + Rt[1, 1] * n[1] + Rt[1, 2] * n[2]
        nl2 = Rt[2, 0] * n[0] + Rt[2, 1] * n[1] + Rt[2, 2] * n[2]
        for j in range(ys.shape[1]):
            # Newton starts from the last lines' solutions, extrapolated quadratically
            # on equally spaced lines (else the last line's)
            if quadratic and j >= 3:
                c0, c1, c2 = 3.0, -3.0, 1.0
            else:
                c0, c1, c2 = (1.0 if j >= 1 else 0.0), 0.0, 0.0
            r, kr = _rail_distance(ys[k, j], C, t, n, y_off, rb, rc,
                                   c0 * tr[0] + c1 * tr[1] + c2 * tr[2], kr)
            if not math.isfinite(r):
                # the line misses the rail profile: gap 1 m (below) and the next
                # lines start afresh
                c0, c1, c2 = 0.0, 0.0, 0.0
            tr[2], tr[1], tr[0] = tr[1], tr[0], (r if math.isfinite(r) else 0.0)
            d1 = C[1] + ys[k, j] * t[1] - O[1]
            d2 = C[2] + ys[k, j] * t[2] - O[2]
            run = 0                     # solved points in a row before i on this line
            for i in range(nx):
                if along and run >= 3:
                    # quadratic extrapolation along the line (equally spaced x)
                    start = 3.0 * tw[0, i - 1] - 3.0 * tw[0, i - 2] + tw[0, i - 3]
                else:
                    start = c0 * tw[0, i] + c1 * tw[1, i] + c2 * tw[2, i]
                d0 = C[0] + x[k, i] - O[0]
                w, kw[i] = _wheel_newton(Rt[0, 0] * d0 + Rt[0, 1] * d1 + Rt[0, 2] * d2,
                                         Rt[1, 0] * d0 + Rt[1, 1] * d1 + Rt[1, 2] * d2,
                                         Rt[2, 0] * d0 + Rt[2, 1] * d1 + Rt[2, 2] * d2,
                                         nl0, nl1, nl2, e, r0, wb, wc, start, kw[i])
                g = r - w
                h[k, i, j] = g if math.isfinite(g) else 1.0
                tw[2, i], tw[1, i] = tw[1, i], tw[0, i]
                tw[0, i] = w if math.isfinite(w) else 0.0
                run = run + 1 if math.isfinite(w) else 0
    return h


def sample_gap_lines(patches, x, y) -> np.ndarray:
    """Undeformed distance [m] of many patches at once on lines of constant y:
    ``x`` (patches, nx) and ``y`` (patches, ny) in each patch's tangent-plane
    coordinates give h of shape (patches, nx, ny).  Patches of the geometry layer
    are evaluated in one compiled loop per rail/wheel profile pair; others (bodies
    cases) through their ``gap`` method."""
    x = np.ascontiguousarray(x, dtype=float)
    y = np.ascontiguousarray(y, dtype=float)
    h = np.empty((x.shape[0], x.shape[1], y.shape[1]))
    groups: dict = {}
    for k, p in enumerate(patches):
        f = p.gap_function
        if isinstance(f, _GapEvaluator):
            groups.setdefault((id(f.rail), id(f.wheel)), []).append(k)
        else:
            h[k] = p.gap(x[k][:, None], y[k][None, :])
    for idx in groups.values():
        f0 = patches[idx[0]].gap_function
        frames = np.array([patches[k].gap_function.frame for k in idx])
        sign = np.array([patches[k].gap_function.sign for k in idx])
        h[idx] = _sane(_gap_lines_kernel(x[idx], np.ascontiguousarray(sign[:, None] * y[idx]),
                                         frames, f0.rail._breaks, f0.rail._coefs,
                                         f0.wheel._breaks, f0.wheel._coefs))
    return h


def sample_strip_spin(patches, y) -> np.ndarray:
    """Spin creepage [1/m] of many patches per strip, at patch coordinates ``y``
    (patches, strips), as :meth:`ContactGeometry.spin_at` with each patch's own spin:
    the local contact angles of patches on the same rail profile come from one
    vectorised evaluation of its slope."""
    y = np.asarray(y, dtype=float)
    out = np.empty(y.shape)
    groups: dict = {}
    for k, p in enumerate(patches):
        f = p.gap_function
        if (isinstance(f, _GapEvaluator) and math.isfinite(p.spin_derivative)
                and getattr(p.local_contact_angle, "__self__", None) is f):
            groups.setdefault(id(f.rail), []).append(k)
        else:
            out[k] = p.spin_at(y[k], p.creepage[2] if p.creepage is not None else 0.0)
    for idx in groups.values():
        pars = np.array([(p.gap_function.sign, p.gap_function.y_ref,
                          math.cos(p.gap_function.angle), p.contact_angle,
                          p.creepage[2] if p.creepage is not None else 0.0,
                          p.spin_derivative) for p in (patches[k] for k in idx)])
        sign, yref, cosa, delta, phi, dphi = (pars[:, i, None] for i in range(6))
        # local angle sign * atan(s) with s the rail's slope: D = that - delta, and
        # cos D, sin D without the angles (1 / sqrt(1 + s^2) = cos(atan s))
        s = sign * patches[idx[0]].gap_function.rail.slope(yref + sign * y[idx] * cosa)
        c = 1.0 / np.sqrt(1.0 + s * s)
        cd = np.where(np.isfinite(s), c * (np.cos(delta) + s * np.sin(delta)), 1.0)
        sd = np.where(np.isfinite(s), c * (s * np.cos(delta) - np.sin(delta)), 0.0)
        out[idx] = phi * cd + dphi * sd      # off the profile (NaN slope): the patch spin
    return out


def _curvatures_fd(gapf, x0, y0):
    """Curvatures (A, B) [1/m] of the gap and the gap itself at (x0, y0): one
    vectorised evaluation of the five-point stencil."""
    hx, hy = FD_STEP
    xs = np.array([x0, x0 + hx, x0 - hx, x0, x0])
    ys = np.array([y0, y0, y0, y0 + hy, y0 - hy])
    h = gapf.points(xs, ys)
    A = (h[1] + h[2] - 2 * h[0]) / (2 * hx * hx)
    B = (h[3] + h[4] - 2 * h[0]) / (2 * hy * hy)
    return float(A), float(B), float(h[0])


def _creepage(side, q_side, n_tr, delta_tr, pose, r0, velocity, pitch_velocity,
              lateral_velocity, yaw_rate):
    """Kinematic creepages (xi, eta, phi), rolling velocity V and d(phi)/d(delta) at
    the contact point ``q_side`` (side frame), normal ``n_tr`` (track frame)."""
    sgn = 1.0 if side == "right" else -1.0
    # omega = R (0, pitch_velocity, 0) + (0, 0, yaw_rate), R the wheelset's axes
    cy, sy = math.cos(pose.yaw), math.sin(pose.yaw)
    cr, sr = math.cos(pose.roll), math.sin(pose.roll)
    w0 = -sy * cr * pitch_velocity
    w1 = cy * cr * pitch_velocity
    w2 = sr * pitch_velocity + yaw_rate
    # d = Q - O, O the wheelset centre; v = (V, lateral velocity, 0) + omega x d
    dx, dy, dz = (float(q_side[0]), sgn * float(q_side[1]) - pose.lateral_shift,
                  float(q_side[2]) - (pose.vertical - r0))
    rot0 = w1 * dz - w2 * dy
    v0 = velocity + rot0
    v1 = lateral_velocity + (w2 * dx - w0 * dz)
    v2 = w0 * dy - w1 * dx
    V = 0.5 * (abs(velocity) + abs(rot0))
    c, s = math.cos(delta_tr), math.sin(delta_tr)
    xi = -v0 / V
    eta = -(v1 * c + v2 * s) / V
    phi = -(w0 * n_tr[0] + w1 * n_tr[1] + w2 * n_tr[2]) / V
    # d(phi)/d(delta): the spin on a surface element whose normal is turned by
    # d(delta) about x is phi cos + dphi sin (n' = -s for the normal (0, -sin, cos))
    dphi = (w1 * c + w2 * s) / V
    return (float(xi), float(eta), float(phi)), float(V), float(dphi)


def find_contact(wheelset: Wheelset, track: Track, lateral_shift: float = 0.0,
                 yaw: float = 0.0, vertical_force=None, material: Material = STEEL,
                 velocity: float = 30.0, pitch_velocity: float | None = None,
                 lateral_velocity: float = 0.0, yaw_rate: float = 0.0,
                 combine_distance: float = 0.0,
                 full_interaction_distance: float | None = None,
                 interpenetration: dict | None = None, roll: float | None = None,
                 side: str = "both", roll_start: float = 0.0,
                 load_iterations: int = 10, turn_distance: float = 0.0,
                 separation_angle: float = math.pi / 2) -> WheelsetContact:
    """Find the wheelset position and all contact patches.

    Parameters
    ----------
    wheelset, track : Wheelset, Track
    lateral_shift : float
        Wheelset lateral displacement y [m], positive to the right.
    yaw : float
        Yaw angle [rad]; positive turns the front to the right.
    vertical_force : float or (float, float), optional
        Vertical wheel load [N] (one value for both wheels, or (left, right)).  When
        given, the elastic approach is included (multi-Hertzian); otherwise the
        wheelset rests rigidly on both rails.
    material : Material
    velocity : float
        Forward speed V [m/s].
    pitch_velocity : float, optional
        Wheelset angular velocity about its axle [rad/s]; default pure rolling at the
        nominal radius, -V / r0.
    lateral_velocity, yaw_rate : float
        [m/s], [rad/s] for the kinematic creepages.
    combine_distance : float
        Interpenetration regions whose facing ends are closer than this [m] form one
        patch (default 0: every region is its own patch; CONTACT combines within
        8 mm).
    full_interaction_distance : float, optional
        Within a combined patch, sub-regions closer than this [m] interact fully in
        the normal problem, and between it and ``combine_distance`` reduced
        (:func:`railcontact.geometry.contact.interaction_factor`; CONTACT: 4 mm);
        default ``combine_distance`` (full interaction).
    interpenetration : dict, optional
        Prescribed vertical interpenetration [m] of the deepest point per side
        (``{"left": d, "right": d}``) instead of one derived from ``vertical_force``;
        used by :func:`railcontact.solve` to meet the vertical force with the
        normal and tangential model of the case.
    roll : float, optional
        Prescribed roll angle [rad].  Then only one wheel (``side``) is considered and
        its vertical position alone is solved (CONTACT's single-wheel mode).
    side : {"both", "left", "right"}
        Wheels to consider; a prescribed roll needs "left" or "right".
    roll_start : float
        Estimate of the roll angle [rad] where the search for it starts (e.g. the
        roll of an earlier search of the same case); it changes the work, not the
        result.
    load_iterations : int
        Limit of the fixed-point iterations between the multi-Hertzian
        interpenetrations and the wheelset position under ``vertical_force`` (they
        stop earlier when the interpenetrations change by less than 1 nm).  One
        gives a first estimate (what :func:`railcontact.solve` needs: its own
        vertical-force iteration follows with the chosen models).
    turn_distance : float
        Separate patches of a wheel whose facing ends lie between
        ``combine_distance`` and this [m] apart have their contact angles turned
        towards their weighted mean (CONTACT's D_TURN,
        :func:`railcontact.geometry.turning.turned_angles`); 0 (default): no turning.
    separation_angle : float
        ... except where their angles differ by more than this [rad] (CONTACT's
        A_SEP).
    """
    for name, v, lim in (("wheelset.lateral_shift", lateral_shift, 0.05),
                         ("wheelset.yaw", yaw, 0.1)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and abs(v) <= lim):
            raise InputError(f"{name} = {v!r}: expected |value| <= {lim}")
    if not (isinstance(velocity, (int, float)) and math.isfinite(velocity) and velocity > 0):
        raise InputError(f"wheelset.velocity = {velocity!r} m/s: expected a value > 0")
    loads = None
    if vertical_force is not None:
        vf = np.atleast_1d(np.asarray(vertical_force, dtype=float))
        if vf.size == 1:
            vf = np.repeat(vf, 2)
        if vf.size != 2 or not np.all(np.isfinite(vf)) or np.any(vf <= 0):
            raise InputError(f"wheelset.vertical_force = {vertical_force!r}: expected a load > 0 N"
                             " per wheel, or (left, right)")
        loads = {"left": float(vf[0]), "right": float(vf[1])}
    r0 = wheelset.nominal_radius
    if pitch_velocity is None:
        pitch_velocity = -velocity / r0
    if side not in ("both", "left", "right"):
        raise InputError(f"wheelset.side = {side!r}: expected 'left', 'right' or 'both'")
    if roll is not None:
        if side == "both":
            raise InputError("wheelset.roll is prescribed: give wheelset.side = 'left' or "
                             "'right' (with a given roll only one wheel can be in equilibrium)")
        if not (math.isfinite(roll) and abs(roll) <= 0.1):
            raise InputError(f"wheelset.roll = {roll!r}: expected |roll| <= 0.1 rad")
    sides = SIDES if roll is None else (side,)
    pose_kw = {"roll_given": roll, "sides": sides}
    if not (isinstance(load_iterations, int) and load_iterations >= 1):
        raise InputError(f"load_iterations = {load_iterations!r}: expected an integer >= 1")
    if not (isinstance(roll_start, (int, float)) and abs(roll_start) <= 0.1):
        raise InputError(f"roll_start = {roll_start!r}: expected |roll| <= 0.1 rad")

    targets = {"left": 0.0, "right": 0.0}
    if interpenetration is not None:
        targets = {s: float(interpenetration.get(s, 0.0)) for s in SIDES}
        if not all(math.isfinite(v) and v >= 0 for v in targets.values()):
            raise InputError(f"interpenetration = {interpenetration!r}: expected values >= 0 m")
        loads = loads or {s: math.nan for s in SIDES}
    # the rigid pose under a load is only the start of the multi-Hertzian estimate:
    # its roll to 1e-8 rad (gaps to 15 nm), the poses of the patches' to 1e-12
    estimate = loads is not None and interpenetration is None
    z, roll, loci = _solve_pose(wheelset, track, lateral_shift, yaw, targets,
                                roll0=float(roll_start), tol=1e-8 if estimate else 1e-12,
                                loci_window="regions" if interpenetration is not None
                                else ESTIMATE_WINDOW if estimate else None, **pose_kw)
    if estimate:
        for k in range(load_iterations):
            new = dict(targets)
            new.update({s: _approach_for_load(loci[s], loads[s], r0, material) for s in sides})
            change = max(abs(new[s] - targets[s]) for s in sides)
            targets = new
            # the last iteration's loci need to hold the patches only
            z, roll, loci = _solve_pose(wheelset, track, lateral_shift, yaw, targets,
                                        roll0=roll, loci_window="regions"
                                        if k == load_iterations - 1 else ESTIMATE_WINDOW,
                                        **pose_kw)
            if change < 1e-9:
                break
    pose = WheelsetPose(lateral_shift, z, roll, yaw)

    patches = []
    full = combine_distance if full_interaction_distance is None else full_interaction_distance
    for sd in sides:
        loc = loci[sd]
        regions = _regions(loc, loads is None, combine_distance)
        angles = [None] * len(regions)
        if turn_distance > combine_distance and len(regions) > 1 and loads is not None:
            aw = [_weighted_angle(loc, i0, i1) for i0, i1, _ in regions]
            angles = turned_angles([a for a, _ in aw], [w for _, w in aw],
                                   [_end_distance(loc, p[1], q[0])
                                    for p, q in zip(regions[:-1], regions[1:])],
                                   combine_distance, turn_distance, separation_angle)
        for (i0, i1, joins), lim, angle in zip(regions, _territories(loc, regions), angles):
            factors = [(y, interaction_factor(d, full, combine_distance)) for y, d in joins]
            patches.append(_make_patch(wheelset, track, sd, loc, i0, i1, pose, loads is None,
                                       velocity, pitch_velocity, lateral_velocity, yaw_rate,
                                       lim, factors, angle))
    return WheelsetContact(pose, patches, loci, loads, targets)


def _territories(loc: Locus, regions) -> list:
    """Rail-profile lateral bounds (y_min, y_max) [m] of each region's territory:
    halfway between its ends and the facing ends of the neighbouring regions of the
    same locus (unbounded without a neighbour on that side)."""
    spans = [(float(min(loc.y_rail[a], loc.y_rail[b])), float(max(loc.y_rail[a], loc.y_rail[b])))
             for a, b, _ in regions]
    out = []
    for lo, hi in spans:
        below = [h for l, h in spans if h < lo]
        above = [l for l, h in spans if l > hi]
        out.append((0.5 * (lo + max(below)) if below else -math.inf,
                    0.5 * (hi + min(above)) if above else math.inf))
    return out


def _weighted_angle(loc: Locus, i0: int, i1: int):
    """Weighted contact angle [rad] (side frame) and total weight of the region
    [i0, i1] of a locus (the weights of :func:`_make_patch`)."""
    sl = slice(i0, i1 + 1)
    w = (-np.minimum(loc.gap[sl], 0.0)) ** GAP_WEIGHT
    if not w.sum() > 0:
        return float(np.arctan(loc.slope[loc.i_min])), 0.0
    return (float(np.dot(w, np.arctan(loc.slope[sl])) / w.sum()),
            float(w.sum() * abs(loc.y_wheel[1] - loc.y_wheel[0])))


def _make_patch(wheelset, track, side, loc, i0, i1, pose, rigid, velocity, pitch_velocity,
                lateral_velocity, yaw_rate, territory=(-math.inf, math.inf),
                joins=(), angle=None) -> ContactGeometry:
    """The geometry of the patch of locus region [i0, i1]; ``angle``: its contact
    angle [rad] in the side frame instead of the weighted one (a turned angle,
    :mod:`railcontact.geometry.turning`)."""
    sl = slice(i0, i1 + 1)
    g = loc.gap[sl]
    im = i0 + int(np.argmin(g))
    ang = np.arctan(loc.slope[sl])
    if rigid or i1 == i0:
        # parabolic refinement of the minimum
        j = min(max(im, 1), loc.gap.size - 2)
        g3 = loc.gap[j - 1:j + 2]
        den = g3[0] - 2 * g3[1] + g3[2]
        frac = 0.5 * (g3[0] - g3[2]) / den if den > 0 else 0.0
        frac = float(np.clip(frac, -1.0, 1.0))
        y_ref = float(loc.y_rail[j] + frac * (loc.y_rail[j + 1] - loc.y_rail[j - 1]) / 2)
        x_ref = float(loc.point[0, j])
        a_ref = float(np.arctan(track.rail(side).slope(y_ref)))
        weight = 1.0
    else:
        w = (-np.minimum(g, 0.0)) ** GAP_WEIGHT
        weight = float(w.sum() * abs(loc.y_wheel[1] - loc.y_wheel[0]))
        y_ref = float(np.dot(w, loc.y_rail[sl]) / w.sum())
        x_ref = float(np.dot(w, loc.point[0, sl]) / w.sum())
        a_ref = float(np.dot(w, ang) / w.sum()) if angle is None else float(angle)
    rail = track.rail(side)
    y_off = track.rail_offset(side)
    z_ref = float(rail.z_at(y_ref))
    C = np.array([x_ref, y_off + y_ref, z_ref])
    gapf = _GapEvaluator(wheelset, track, side, loc, C, a_ref)
    # wheel coordinates of the reference point
    L = loc.axes.T @ (C - loc.origin)
    y_w = float(L[1] - wheelset.wheel_offset)
    z_w = float(wheelset.wheel(side).z_at(y_w))
    rolling_radius = wheelset.nominal_radius + z_w
    # curvatures at the deepest point, in the patch's tangent-plane coordinates
    sgn = 1.0 if side == "right" else -1.0
    Pm = np.array([loc.point[0, im], y_off + loc.y_rail[im], float(rail.z_at(loc.y_rail[im]))])
    d = Pm - C
    x_m = float(d[0])
    y_m = sgn * float(d @ gapf.t)
    A, B, h_m = _curvatures_fd(gapf, x_m, y_m)
    if not (A > 0.0 and B > 0.0 and abs(h_m) < 0.5):
        # the stencil at the deepest point left a surface (a patch spanning a strongly
        # curved part of the profile, e.g. flange root to flange, whose deepest point
        # projects beyond the rail profile's end): the curvatures at the reference
        # point, on the rail by construction; the approach from the fallback below
        log.debug("%s patch: no curvatures at its deepest point; taken at its reference "
                  "point", side)
        A, B, _ = _curvatures_fd(gapf, 0.0, 0.0)
        h_m = math.nan
    approach = -h_m
    # robust fallback: vertical interpenetration of the deepest locus point projected on n
    vertical = -float(loc.gap[im]) * math.cos(math.atan(float(loc.slope[im])))
    if not math.isfinite(approach) or (approach <= 0.0 < vertical):
        approach = vertical
    approach = max(0.0, approach)
    n_side = gapf.n
    delta_tr = sgn * a_ref
    n_tr = np.array([0.0, sgn * n_side[1], n_side[2]])
    Q = C + approach * n_side
    creep, V, dphi = _creepage(side, Q, n_tr, delta_tr, pose, wheelset.nominal_radius, velocity,
                         pitch_velocity, lateral_velocity, yaw_rate)
    ys = loc.y_rail[sl]
    ext_y = (sgn * (ys.min() - y_ref), sgn * (ys.max() - y_ref))
    if not (A > 0.0 and B > 0.0):
        # a conformal or rough patch (measured profiles): the curvatures of the
        # paraboloid that has the interpenetration region's extent at its approach
        # (so that the approximate models, and the vertical-force iteration's
        # Hertzian start, see a patch of the right size)
        half_y = 0.5 * (max(ext_y) - min(ext_y)) / math.cos(a_ref)
        B = B if B > 0.0 else max(approach, 1e-9) / max(half_y, 1e-4) ** 2
        A = A if A > 0.0 else math.cos(a_ref) / (2.0 * (wheelset.nominal_radius + z_w))
        log.debug("%s patch: curvatures of its interpenetration region's extent "
                  "(%.3g, %.3g) 1/m", side, A, B)
    half_x = math.sqrt(max(approach, 0.0) / max(A, 1e-9))
    extent = (x_m - half_x, x_m + half_x, min(ext_y) / math.cos(a_ref) if rigid is False else 0.0,
              max(ext_y) / math.cos(a_ref) if rigid is False else 0.0)
    pos_tr = np.array([C[0], sgn * C[1], C[2]])
    # the territory in patch coordinates (y along t, sgn-mirrored as the extent)
    lim = sorted(sgn * (v - y_ref) / math.cos(a_ref) for v in territory)
    inter = tuple(sorted((sgn * (v - y_ref) / math.cos(a_ref), f) for v, f in joins))
    return ContactGeometry(curvatures=(A, B), side=side, contact_angle=delta_tr,
                           rolling_radius=rolling_radius, y_rail=y_ref, y_wheel=y_w,
                           z_rail=z_ref, z_wheel=z_w, position=pos_tr, approach=approach,
                           weight=weight, creepage=creep, velocity=V, extent=extent,
                           gap_function=gapf, spin_derivative=dphi, bounds=tuple(lim),
                           interaction=inter,
                           local_contact_angle=gapf.contact_angle_at)
