"""The contact search of a wheelset in compiled code: the pose under given
interpenetrations, the contact loci, the patches and their geometry, with no Python
between them (:func:`search_patches`).

The same steps as :func:`railcontact.geometry.find_contact` under prescribed
interpenetrations, on the same tabulated profile splines and with the same
definitions, so that the two give the same patches to their tolerances:

* the pose (:mod:`railcontact.geometry.pose`): the vertical position follows from
  the right side's minimum vertical gap, the roll from secant steps on the
  difference of the two sides' gaps (a bracketed search where they do not settle),
  every minimum over the wheel samples of the locus
  (:func:`railcontact.geometry.locus._min_gap_kernel`), searched within the wheel
  samples of the last locus where the roll is close to its own;
* the loci at the pose, over the samples within the interpenetration plus
  ``REGION_MARGIN`` of the closest approach
  (:func:`railcontact.geometry.locus.compute_locus`);
* the interpenetration regions, combined where closer than the combine distance
  (:mod:`railcontact.geometry.regions`), and each region's patch as
  :func:`railcontact.geometry.search._make_patch` makes it: CONTACT's weighted
  reference point and contact angle, the curvatures of the exact undeformed
  distance by finite differences at the deepest point, the approach along the
  normal and the kinematic creepages.

The rigid-contact case, the turning of nearby patches' angles and profiles that
differ between the sides are not here: their searches run in Python
(:func:`railcontact.geometry.find_contact`).  Under a prescribed roll (one wheel)
:func:`~railcontact.geometry.find_contact` takes the pose and the locus from
:func:`side_min_gap` and :func:`side_locus` and makes the patches itself.

Inputs are named tuples (:class:`PassProfiles`, :class:`PassPose`) and a small
float array (the memo of the search, :data:`MEMO_SIZE`), so that every kernel takes
at most twelve named inputs.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from ..profiles.profile import ppoly_at
from .contact import ContactGeometry, WheelsetContact
from .gap import DEEPEST_GAP, FD_STEP, GapEvaluator, PatchFrame, Spline, _gap_kernel
from .locus import (LOCUS_STEP, _locus_gaps, _locus_kernel, _min_gap_kernel, _slopes_at,
                    _slopes_for, _slopes_part, _wheel_samples, side_pose)
from .track import rotation
from .pose import REGION_MARGIN, ROLL_SLOPE, WINDOW_ROLL
from .patch_curvature import (at_fraction, deepest_fraction, deepest_gap,  # noqa: F401
                              force_curvature, region_curvature)
from .regions import GAP_WEIGHT

#: the profiles of a wheelset on its track, one wheel and one rail profile (right
#: convention) shared by both sides: the wheel samples every ``LOCUS_STEP``
#: (``eta``: lateral position from the wheelset centre, ``rho``: radius, ``yw``,
#: ``zw``: profile coordinates), the cubic splines (breaks, coefficients) of rail
#: and wheel, and the locus rule: ``ws`` the wheel profile's slopes at the samples
#: for CONTACT's locus (``Wheelset.locus = "contact"``), None (the default) for
#: each wheel circle's lowest point (:func:`railcontact.geometry.locus._locus_kernel`)
PassProfiles = namedtuple("PassProfiles", "eta rho yw zw rb rc wb wc ws", defaults=(None,))

#: the wheelset's state and dimensions (SI): ``shift``, ``yaw``; the rail offsets
#: ``y_off_left``, ``y_off_right`` (side frames), the wheel-profile offset ``e`` and
#: the nominal radius ``r0``; ``velocity``, ``pitch_velocity``, ``lateral_velocity``,
#: ``yaw_rate``; ``combine`` (combine distance [m])
PassPose = namedtuple("PassPose", "shift yaw y_off_left y_off_right e r0 velocity "
                      "pitch_velocity lateral_velocity yaw_rate combine")

#: the memo of successive searches of one case: [0] the last roll, [1] the last
#: secant slope, per side s (0 left, 1 right) at 2 + 6 s: the roll of the last locus,
#: its first and end wheel samples, the roll it serves within, and the first and end
#: samples of its minimum's neighbourhood (``MIN_WINDOW``)
MEMO_SIZE = 15
#: the memo's count of the roll search's evaluations (each both sides' minimum gap)
M_GAPS = 14

#: the roll search of a case's later searches looks for each side's minimum gap
#: among the wheel samples whose gap was within this [m] of the last locus's minimum
#: (and ``MIN_MARGIN`` samples on either side), widened where the minimum falls on
#: its edge; the loci at the pose found then show whether a deeper point was missed
#: (then the search is made again over the locus windows)
MIN_WINDOW = 1.5e-5
MIN_MARGIN = 16
#: ... and the samples between the locus's local minima within its window
#: (:func:`_note_minimum`)

#: a locus deeper than its side's target by more than this [m] shows a missed
#: minimum (the roll search's tolerance puts the sides' gaps within ~1e-12 m)
MISSED_DEPTH = 1e-10

#: the loci of a search hold the wheel samples within the side's interpenetration
#: plus this [m] of the closest approach: the regions (negative gap) and a margin
#: (the geometry layer's loci take ``REGION_MARGIN``, for the reuse of their
#: windows; the regions are the same)
LOCUS_MARGIN = 3e-5

#: a locus's wheel samples for the next search: those within its window and this
#: many on either side
TRIM_MARGIN = 48

#: the searches' loci compute the samples within this many of a sample of every
#: 8th (the coarse pass) whose gap lies within the window plus ``SPARSE_SLACK`` [m]
#: of the coarse minimum (the minimum-gap search takes 2 um between coarse points
#: 8 samples apart, :func:`railcontact.geometry.locus.min_gap`; five times that here)
SPARSE_BLOCK = 10
SPARSE_SLACK = 1e-5

#: fields of a patch row of :func:`search_patches` (and of the case kernels)
PATCH_FIELDS = ("side", "approach", "A", "B", "contact_angle", "y_rail", "y_wheel",
                "z_rail", "z_wheel", "rolling_radius", "x", "y", "z", "weight", "xi",
                "eta", "phi", "velocity", "spin_derivative", "i0", "i1", "x_m", "ys_min",
                "ys_max", "yr_first", "yr_last", "B_force")
NPF = len(PATCH_FIELDS)
#: the column of each field (compiled code reads these constants)
P_SIDE = 0
P_APPROACH = 1
P_A = 2
P_B = 3
P_CONTACT_ANGLE = 4
P_Y_RAIL = 5
P_Y_WHEEL = 6
P_Z_RAIL = 7
P_Z_WHEEL = 8
P_ROLLING_RADIUS = 9
P_X = 10
P_Y = 11
P_Z = 12
P_WEIGHT = 13
P_XI = 14
P_ETA = 15
P_PHI = 16
P_VELOCITY = 17
P_SPIN_DERIVATIVE = 18
P_I0 = 19
P_I1 = 20
P_X_M = 21
P_YS_MIN = 22
P_YS_MAX = 23
P_YR_FIRST = 24
P_YR_LAST = 25
P_B_FORCE = 26

#: at most this many patches per side
MAX_PATCHES = 8


def new_memo(roll: float = 0.0) -> np.ndarray:
    """A fresh memo (:data:`MEMO_SIZE`) whose roll search starts at ``roll``."""
    m = np.zeros(MEMO_SIZE)
    m[0], m[1] = roll, ROLL_SLOPE
    m[2:] = np.nan
    m[M_GAPS] = 0.0
    return m


def pass_profiles(wheelset, track) -> PassProfiles:
    """The :class:`PassProfiles` of a wheelset on a track whose sides share their
    profiles (None where they do not)."""
    wheel, rail = wheelset.wheel("right"), track.rail("right")
    if wheelset.wheel("left") is not wheel or track.rail("left") is not rail:
        return None
    yw, zw, eta, rho = _wheel_samples(wheel, LOCUS_STEP, wheelset.wheel_offset,
                                      wheelset.nominal_radius)
    return PassProfiles(eta, rho, yw, zw, rail._breaks, rail._coefs, wheel._breaks,
                        wheel._coefs, _slopes_for(wheelset, wheel, LOCUS_STEP))


@njit(cache=True, nogil=True)
def rotation_matrix(yaw, roll):
    """Rz(yaw) Rx(roll) (:func:`railcontact.geometry.track.rotation`)."""
    cy, sy, cr, sr = math.cos(yaw), math.sin(yaw), math.cos(roll), math.sin(roll)
    R = np.empty((3, 3))
    R[0, 0], R[0, 1], R[0, 2] = cy, -sy * cr, sy * sr
    R[1, 0], R[1, 1], R[1, 2] = sy, cy * cr, -cy * sr
    R[2, 0], R[2, 1], R[2, 2] = 0.0, sr, cr
    return R


@njit(cache=True, nogil=True)
def side_frame(pose, s, z, roll):
    """The wheelset's axes R, centre O and the rail offset in the frame of side s
    (0 left, mirrored; 1 right) at vertical position z and roll."""
    if s == 1:
        R = rotation_matrix(pose.yaw, roll)
        O = np.array([0.0, pose.shift, z - pose.r0])
        return R, O, pose.y_off_right
    R = rotation_matrix(-pose.yaw, -roll)
    O = np.array([0.0, -pose.shift, z - pose.r0])
    return R, O, pose.y_off_left


@njit(cache=True, nogil=True, inline="always")
def _narrow_min_gap(prof, R, O, y_off, c0, c1):
    """Minimum vertical gap over the wheel samples [c0, c1), the range widened
    (doubled) while the coarse minimum lies at one of its ends (not the wheel's)."""
    n = prof.eta.size
    while True:
        gc = _locus_gaps(prof.eta[c0:c1:8], prof.rho[c0:c1:8],
                         _slopes_part(prof.ws, c0, c1, 8), R, O, y_off, prof.rb,
                         prof.rc)
        if gc.size == 0 or not math.isfinite(np.min(gc)):
            if c0 == 0 and c1 == n:
                return np.inf
            c0, c1 = 0, n               # the window is off the rail here: every sample
            continue
        j = np.argmin(gc)
        grow_lo = j == 0 and c0 > 0
        grow_hi = j == gc.size - 1 and c1 < n
        if not (grow_lo or grow_hi):
            break
        w = c1 - c0
        if grow_lo:
            c0 = max(c0 - w, 0)
        if grow_hi:
            c1 = min(c1 + w, n)
    return _min_gap_kernel(prof.eta[c0:c1], prof.rho[c0:c1], _slopes_part(prof.ws, c0, c1, 1),
                           R, O, y_off, prof.rb, prof.rc)


@njit(cache=True, nogil=True, inline="always")
def side_min_gap(prof, pose, s, roll, memo):
    """Minimum vertical gap [m] of side s at roll (vertical position 0), around the
    last locus's minimum (``MIN_WINDOW``); without one in the memo, around the
    minimum of a coarse pass over the wheel (every 8th sample), which the memo
    takes."""
    R, O, y_off = side_frame(pose, s, 0.0, roll)
    k = 2 + 6 * s
    if not memo[k + 4] == memo[k + 4]:
        n = prof.eta.size
        gc = _locus_gaps(prof.eta[::8], prof.rho[::8],
                         _slopes_part(prof.ws, 0, n, 8), R, O, y_off, prof.rb,
                         prof.rc)
        g = np.min(gc)
        if not math.isfinite(g):
            return np.inf
        first, last = -1, -1
        for j in range(gc.size):
            if gc[j] <= g + MIN_WINDOW:
                if first < 0:
                    first = j
                last = j
        memo[k + 4] = max(8 * first - 8 - MIN_MARGIN, 0)
        memo[k + 5] = min(8 * last + 9 + MIN_MARGIN, n)
    return _narrow_min_gap(prof, R, O, y_off, int(memo[k + 4]), int(memo[k + 5]))


@njit(cache=True, nogil=True)
def illinois_update(x, f, a, fa, b, fb, side):
    """One bracket update of Illinois' regula falsi (Dowell & Jarratt 1971): the
    trial ``x`` with residual ``f`` replaces the end of the bracket whose residual
    has its sign (``a``, ``fa``: the end with a negative residual; ``b``, ``fb``:
    the other), and where it replaces the same end as the step before (``side``:
    -1 the negative end, 1 the other, 0 none yet), the other end's residual is
    halved, so that the false position does not stall at one end.  Returns
    (a, fa, b, fb, side).  The roll search (:func:`solve_roll`) and the strip
    models' run ends (:func:`railcontact.normal.strip_batch._run_end`) step with
    it."""
    if f < 0.0:
        if side == -1:
            fb *= 0.5
        return x, f, b, fb, -1
    if side == 1:
        fa *= 0.5
    return a, fa, x, f, 1


@njit(cache=True, nogil=True, inline="always")
def _roll_residual(prof, pose, targets, roll, memo):
    memo[M_GAPS] += 1.0
    gl = side_min_gap(prof, pose, 0, roll, memo)
    gr = side_min_gap(prof, pose, 1, roll, memo)
    return (gl + targets[0]) - (gr + targets[1]), gr


@njit(cache=True, nogil=True)
def solve_roll(prof, pose, targets, tol, memo):
    """Roll [rad] and vertical position [m] such that each side's minimum gap is
    minus its target (:func:`railcontact.geometry.pose.solve_pose`); NaN where no
    roll within 0.1 rad is found or the wheel runs off the rail."""
    roll0 = memo[0]
    x0 = roll0
    f0, g0 = _roll_residual(prof, pose, targets, x0, memo)
    if not (f0 == f0 and math.isfinite(f0)):
        return math.nan, math.nan
    if f0 == 0.0:
        return x0, g0 + targets[1]
    slope = memo[1]
    x1 = x0 - f0 / slope
    if abs(x1 - x0) <= 0.01 * tol:
        return x0, g0 + targets[1]
    # the bracket of the root that the secant steps find (the residual grows with
    # the roll): a step that leaves it is the bracket's regula falsi point
    # instead, and the bracketed search below starts from it (where the deepest
    # point passes between the flange and its root, the residual's slope jumps and
    # the secant steps cycle about the kink)
    blo, bhi, fblo, fbhi = -math.inf, math.inf, math.nan, math.nan
    if f0 < 0:
        blo, fblo = x0, f0
    else:
        bhi, fbhi = x0, f0
    # secant steps (as _secant_roll)
    for _ in range(8):
        f1, g1 = _roll_residual(prof, pose, targets, x1, memo)
        if not math.isfinite(f1):
            break
        if f1 == 0.0:
            return x1, g1 + targets[1]
        if f1 < 0 and x1 > blo:
            blo, fblo = x1, f1
        elif f1 > 0 and x1 < bhi:
            bhi, fbhi = x1, f1
        if f1 == f0 and abs(x1 - x0) <= tol:
            return x1, g1 + targets[1]
        if f1 == f0 or abs(x1 - roll0) > 0.05:
            break
        last = (f1 - f0) / (x1 - x0)
        x0, f0, x1 = x1, f1, x1 - f1 / last
        g0 = g1
        if abs(x1 - x0) <= tol:
            if 0.1 * ROLL_SLOPE < last < 10 * ROLL_SLOPE:
                memo[1] = last
            return x0, g0 + targets[1]
        if blo < bhi and math.isfinite(blo) and math.isfinite(bhi) and not blo < x1 < bhi:
            x1 = (blo * fbhi - bhi * fblo) / (fbhi - fblo)
            if not blo < x1 < bhi:
                x1 = 0.5 * (blo + bhi)
    # bracketed search (as _bracketed_roll): bisection with secant steps
    if math.isfinite(blo) and math.isfinite(bhi) and blo < bhi:
        lo, hi, flo, fhi = blo, bhi, fblo, fbhi
    else:
        span = 2e-3
        lo, hi = roll0 - span, roll0 + span
        flo, _ = _roll_residual(prof, pose, targets, lo, memo)
        while flo > 0:
            lo -= 4 * span
            if lo < -0.1:
                return math.nan, math.nan
            flo, _ = _roll_residual(prof, pose, targets, lo, memo)
        fhi, _ = _roll_residual(prof, pose, targets, hi, memo)
        while fhi < 0:
            hi += 4 * span
            if hi > 0.1:
                return math.nan, math.nan
            fhi, _ = _roll_residual(prof, pose, targets, hi, memo)
    if not (math.isfinite(flo) and math.isfinite(fhi)):
        return math.nan, math.nan
    side = 0
    x_prev = math.nan
    for it in range(200):
        # Illinois' regula falsi (superlinear), every third step a bisection (the
        # bracket halves at least that often), until the bracket or the step is
        # within the tolerance
        if it % 3 == 2:
            x = 0.5 * (lo + hi)
        else:
            x = (lo * fhi - hi * flo) / (fhi - flo) if fhi != flo else 0.5 * (lo + hi)
            if not lo < x < hi:
                x = 0.5 * (lo + hi)
        f, g = _roll_residual(prof, pose, targets, x, memo)
        if not math.isfinite(f):
            return math.nan, math.nan
        if f == 0.0 or hi - lo <= tol or abs(x - x_prev) <= 0.5 * tol:
            return x, g + targets[1]
        x_prev = x
        lo, flo, hi, fhi, side = illinois_update(x, f, lo, flo, hi, fhi, side)
    return math.nan, math.nan


@njit(cache=True, nogil=True)
def _fill_blocks(prof, R, O, y_off, i0, i1, idx, gc, limit):
    """The locus over the wheel samples [i0, i1) at the samples within
    ``SPARSE_BLOCK`` of the coarse points ``idx`` whose gaps ``gc`` are at most
    ``limit``; elsewhere the gap is +inf (beyond every window) and the rest NaN.
    Returns (theta, point, y_rail, gap, slope)."""
    m = i1 - i0
    th = np.full(m, np.nan)
    P = np.full((3, m), np.nan)
    yr = np.full(m, np.nan)
    gap = np.full(m, np.inf)
    sl = np.full(m, np.nan)
    need = np.zeros(m, dtype=np.bool_)
    for c in range(idx.size):
        if gc[c] <= limit:
            lo = max(idx[c] - SPARSE_BLOCK, i0)
            hi = min(idx[c] + SPARSE_BLOCK + 1, i1)
            need[lo - i0:hi - i0] = True
    a = 0
    while a < m:
        if not need[a]:
            a += 1
            continue
        b = a
        while b < m and need[b]:
            b += 1
        t, Pb, y, g, q = _locus_kernel(prof.eta[i0 + a:i0 + b], prof.rho[i0 + a:i0 + b],
                                       _slopes_part(prof.ws, i0 + a, i0 + b, 1), R, O, y_off,
                                       prof.rb, prof.rc)
        th[a:b] = t
        P[:, a:b] = Pb
        yr[a:b] = y
        gap[a:b] = g
        sl[a:b] = q
        a = b
    return th, P, yr, gap, sl


@njit(cache=True, nogil=True)
def side_locus(prof, pose, s, z, roll, window, memo, dense=True):
    """The locus of side s at the pose (:func:`railcontact.geometry.locus.compute_locus`
    with ``window``): (i0, i1, theta, point, y_rail, gap, slope, R, O, y_off); the
    memo takes its wheel samples.  Not ``dense``: the samples away from every
    part within the window (by a pass over every 8th sample, ``SPARSE_SLACK``) are
    not computed (gap +inf, the rest NaN): the regions and the patches are the
    same."""
    R, O, y_off = side_frame(pose, s, z, roll)
    k = 2 + 6 * s
    n = prof.eta.size
    if memo[k] == memo[k] and abs(roll - memo[k]) <= memo[k + 3]:
        i0, i1 = int(memo[k + 1]), int(memo[k + 2])
        if dense:
            th, P, yr, gap, sl = _locus_kernel(prof.eta[i0:i1], prof.rho[i0:i1],
                                                _slopes_part(prof.ws, i0, i1, 1), R, O, y_off,
                                                prof.rb, prof.rc)
            ends = (gap[0], gap[-1]) if gap.size else (np.inf, np.inf)
            gmin = np.min(gap) if gap.size else np.inf
        else:
            idx = np.empty((i1 - i0 + 7) // 8 + 1, dtype=np.int64)
            c = 0
            for j in range(i0, i1, 8):
                idx[c] = j
                c += 1
            if i1 - 1 > idx[c - 1]:
                idx[c] = i1 - 1
                c += 1
            idx = idx[:c]
            gc = _locus_gaps(prof.eta[idx], prof.rho[idx],
                             _slopes_at(prof.ws, idx), R, O,
                             y_off, prof.rb, prof.rc)
            cmin = np.min(gc)
            th, P, yr, gap, sl = _fill_blocks(prof, R, O, y_off, i0, i1, idx, gc,
                                              cmin + window + SPARSE_SLACK)
            ends = (gc[0], gc[-1])
            gmin = min(np.min(gap), cmin)
        if gap.size:
            edge = gmin + window
            if (i0 == 0 or ends[0] > edge) and (i1 == n or ends[1] > edge):
                memo[k], memo[k + 3] = roll, WINDOW_ROLL * window / REGION_MARGIN
                _note_minimum(gap, i0, n, memo, k, window)
                # the next locus: the samples within the window and a margin
                first, last = -1, -1
                for j in range(gap.size):
                    if gap[j] <= edge:
                        if first < 0:
                            first = j
                        last = j
                if first >= 0:
                    memo[k + 1] = max(i0 + first - TRIM_MARGIN, 0)
                    memo[k + 2] = min(i0 + last + TRIM_MARGIN + 1, n)
                return i0, i1, th, P, yr, gap, sl, R, O, y_off
    stride = 8
    idx = np.arange(0, n, stride)
    gc = _locus_gaps(prof.eta[::stride], prof.rho[::stride],
                     _slopes_part(prof.ws, 0, n, stride), R, O, y_off, prof.rb,
                     prof.rc)
    gmin = np.min(gc)
    first, last = -1, -1
    for j in range(gc.size):
        if gc[j] <= gmin + window:
            if first < 0:
                first = j
            last = j
    i0, i1 = 0, n
    if first >= 0:
        i0 = max(first * stride - 2 * stride, 0)
        i1 = min(last * stride + 2 * stride + 1, n)
    if dense:
        th, P, yr, gap, sl = _locus_kernel(prof.eta[i0:i1], prof.rho[i0:i1],
                                           _slopes_part(prof.ws, i0, i1, 1), R, O, y_off, prof.rb,
                                           prof.rc)
    else:
        th, P, yr, gap, sl = _fill_blocks(prof, R, O, y_off, i0, i1, idx, gc,
                                          gmin + window + SPARSE_SLACK)
    memo[k], memo[k + 1], memo[k + 2] = roll, i0, i1
    memo[k + 3] = WINDOW_ROLL * window / REGION_MARGIN
    _note_minimum(gap, i0, n, memo, k, window)
    return i0, i1, th, P, yr, gap, sl, R, O, y_off


@njit(cache=True, nogil=True)
def _note_minimum(gap, i0, n, memo, k, window):
    """The memo takes the wheel samples within ``MIN_WINDOW`` of the locus's minimum,
    and, where the locus has other local minima of the gap within ``window`` [m]
    (the locus's own) of it, the samples between them: any of them may be the
    deepest point at the next pose (the flange and its root, whose depths cross as
    the wheelset rolls), and a minimum outside the roll search's samples makes its
    minimum gap jump where the deeper one passes the window's edge."""
    g = np.min(gap)
    first, last = -1, -1
    for j in range(gap.size):
        if gap[j] <= g + MIN_WINDOW:
            if first < 0:
                first = j
            last = j
    if first < 0:
        memo[k + 4] = np.nan
        return
    edge = g + window
    for j in range(1, gap.size - 1):
        # a local minimum between computed samples (the sparse locus leaves +inf
        # where it computes none)
        if gap[j] <= edge and gap[j] <= gap[j - 1] and gap[j] <= gap[j + 1] and \
                gap[j - 1] < np.inf and gap[j + 1] < np.inf:
            first = min(first, j)
            last = max(last, j)
    memo[k + 4] = max(i0 + first - MIN_MARGIN, 0)
    memo[k + 5] = min(i0 + last + MIN_MARGIN + 1, n)


@njit(cache=True, nogil=True)
def _end_point(gap, P, yr, i, k):
    """:func:`railcontact.geometry.regions._end_point`."""
    gi, gk = gap[i], gap[k]
    t = gi / (gi - gk) if (math.isfinite(gk) and gk > 0 > gi) else 0.0
    zi = gap[i] + P[2, i]
    zk = gap[k] + P[2, k]
    y = yr[i] + t * (yr[k] - yr[i])
    z = zi + t * (zk - zi) if math.isfinite(zk) else zi
    return y, z


@njit(cache=True, nogil=True)
def locus_regions(gap, P, yr, combine):
    """Index ranges [i0, i1] (rows of an (m, 2) array) of the interpenetration
    regions, combined where their facing ends lie closer than ``combine`` [m]
    (:func:`railcontact.geometry.regions.contact_regions`, not rigid)."""
    n = gap.size
    out = np.empty((n // 2 + 2, 2), dtype=np.int64)
    m = 0
    i = 0
    while i < n:
        if gap[i] < 0.0:
            j = i
            while j + 1 < n and gap[j + 1] < 0.0:
                j += 1
            if m > 0:
                yi, zi = _end_point(gap, P, yr, out[m - 1, 1], out[m - 1, 1] + 1)
                yj, zj = _end_point(gap, P, yr, i, i - 1)
                if math.hypot(yj - yi, zj - zi) < combine:
                    out[m - 1, 1] = j
                    i = j + 1
                    continue
            out[m, 0], out[m, 1] = i, j
            m += 1
            i = j + 1
        else:
            i += 1
    if m == 0:
        imin = np.argmin(gap)
        out[0, 0], out[0, 1] = imin, imin
        m = 1
    return out[:m]


@njit(cache=True, nogil=True)
def _curvatures(x0, y0, C, t, nv, y_off, R, O, pose, prof):
    """(A, B, h) of the gap at (x0, y0) by the five-point stencil
    (:func:`railcontact.geometry.gap.curvatures_fd`)."""
    hx, hy = FD_STEP
    xs = np.array([x0, x0 + hx, x0 - hx, x0, x0])
    ys = np.array([y0, y0, y0, y0 + hy, y0 - hy])
    Rt = np.ascontiguousarray(R.T)
    h = _gap_kernel(xs, ys, PatchFrame(C, t, nv, y_off, Rt, O, pose.e, pose.r0),
                    Spline(prof.rb, prof.rc), Spline(prof.wb, prof.wc))
    for i in range(5):
        if h[i] < DEEPEST_GAP:
            h[i] = 1.0
    A = (h[1] + h[2] - 2 * h[0]) / (2 * hx * hx)
    B = (h[3] + h[4] - 2 * h[0]) / (2 * hy * hy)
    return A, B, h[0]


@njit(cache=True, nogil=True)
def make_patch(prof, pose, s, loc, i0, i1, z, roll, row):
    """The patch of locus region [i0, i1] of side s into ``row``
    (:data:`PATCH_FIELDS`): :func:`railcontact.geometry.search._make_patch` under
    prescribed interpenetrations, with the creepages of the wheelset's motion."""
    j0, j1, th, P, yr, gap, slope, R, O, y_off = loc
    sgn = 1.0 if s == 1 else -1.0
    im = i0
    for i in range(i0, i1 + 1):
        if gap[i] < gap[im]:
            im = i
    if i1 == i0:
        j = min(max(im, 1), gap.size - 2)
        den = gap[j - 1] - 2 * gap[j] + gap[j + 1]
        frac = 0.5 * (gap[j - 1] - gap[j + 1]) / den if den > 0 else 0.0
        frac = min(max(frac, -1.0), 1.0)
        y_ref = yr[j] + frac * (yr[j + 1] - yr[j - 1]) / 2
        x_ref = P[0, j]
        _, sr, _ = ppoly_at(y_ref, prof.rb, prof.rc, -1)
        a_ref = math.atan(sr)
        weight = 1.0
    else:
        ws = 0.0
        wy = 0.0
        wx = 0.0
        wa = 0.0
        for i in range(i0, i1 + 1):
            w = (-min(gap[i], 0.0)) ** GAP_WEIGHT
            ws += w
            wy += w * yr[i]
            wx += w * P[0, i]
            wa += w * math.atan(slope[i])
        weight = ws * abs(prof.yw[j0 + 1] - prof.yw[j0])
        y_ref, x_ref, a_ref = wy / ws, wx / ws, wa / ws
    z_ref, _, _ = ppoly_at(y_ref, prof.rb, prof.rc, -1)
    C = np.array([x_ref, y_off + y_ref, z_ref])
    ca, sa = math.cos(a_ref), math.sin(a_ref)
    nv = np.array([0.0, -sa, ca])
    t = np.array([0.0, ca, sa])
    # wheel coordinates of the reference point: L = R^T (C - O)
    L1 = R[0, 1] * (C[0] - O[0]) + R[1, 1] * (C[1] - O[1]) + R[2, 1] * (C[2] - O[2])
    y_w = L1 - pose.e
    z_w, _, _ = ppoly_at(y_w, prof.wb, prof.wc, -1)
    # the locus's minimum between the samples (continuous in the pose)
    f = deepest_fraction(gap, im)
    y_min = at_fraction(yr, im, f)
    zr_m, _, _ = ppoly_at(y_min, prof.rb, prof.rc, -1)
    d0 = at_fraction(P[0], im, f) - C[0]
    d1 = y_off + y_min - C[1]
    d2 = zr_m - C[2]
    x_m = d0
    y_m = d1 * t[1] + d2 * t[2]
    A, B, h_m = _curvatures(x_m, y_m, C, t, nv, y_off, R, O, pose, prof)
    if not (A > 0.0 and B > 0.0 and abs(h_m) < 0.5):
        A, B, _ = _curvatures(0.0, 0.0, C, t, nv, y_off, R, O, pose, prof)
        h_m = math.nan
    approach = -h_m
    vertical = -deepest_gap(gap, im) * math.cos(math.atan(at_fraction(slope, im, f)))
    if not math.isfinite(approach) or (approach <= 0.0 < vertical):
        approach = vertical
    approach = max(0.0, approach)
    delta = sgn * a_ref
    if not (A > 0.0 and B > 0.0):
        ylo, yhi = yr[i0], yr[i0]
        for i in range(i0, i1 + 1):
            ylo, yhi = min(ylo, yr[i]), max(yhi, yr[i])
        half_y = 0.5 * (yhi - ylo) / ca
        if not B > 0.0:
            B = max(approach, 1e-9) / max(half_y, 1e-4) ** 2
        if not A > 0.0:
            A = ca / (2.0 * (pose.r0 + z_w))
    # the kinematic creepages at Q = C + approach n (side frame), normal n_tr (track)
    q0, q1, q2 = C[0], C[1] + approach * nv[1], C[2] + approach * nv[2]
    cy, sy = math.cos(pose.yaw), math.sin(pose.yaw)
    cr, sr = math.cos(roll), math.sin(roll)
    om = pose.pitch_velocity
    w0 = -sy * cr * om
    w1 = cy * cr * om
    w2 = sr * om + pose.yaw_rate
    dx, dy, dz = q0, sgn * q1 - pose.shift, q2 - (z - pose.r0)
    rot0 = w1 * dz - w2 * dy
    v0 = pose.velocity + rot0
    v1 = pose.lateral_velocity + (w2 * dx - w0 * dz)
    v2 = w0 * dy - w1 * dx
    V = 0.5 * (abs(pose.velocity) + abs(rot0))
    c, sd = math.cos(delta), math.sin(delta)
    row[P_SIDE] = s
    row[P_APPROACH] = approach
    row[P_A] = A
    row[P_B] = B
    row[P_CONTACT_ANGLE] = delta
    row[P_Y_RAIL] = y_ref
    row[P_Y_WHEEL] = y_w
    row[P_Z_RAIL] = z_ref
    row[P_Z_WHEEL] = z_w
    row[P_ROLLING_RADIUS] = pose.r0 + z_w
    row[P_X] = C[0]
    row[P_Y] = sgn * C[1]
    row[P_Z] = C[2]
    row[P_WEIGHT] = weight
    row[P_XI] = -v0 / V
    row[P_ETA] = -(v1 * c + v2 * sd) / V
    row[P_PHI] = -(w1 * sgn * nv[1] + w2 * nv[2]) / V
    row[P_VELOCITY] = V
    row[P_SPIN_DERIVATIVE] = (w1 * c + w2 * sd) / V
    row[P_I0] = j0 + i0
    row[P_I1] = j0 + i1
    ylo, yhi = yr[i0], yr[i0]
    for i in range(i0, i1 + 1):
        ylo, yhi = min(ylo, yr[i]), max(yhi, yr[i])
    row[P_X_M] = x_m
    row[P_YS_MIN] = ylo
    row[P_YS_MAX] = yhi
    row[P_YR_FIRST] = yr[i0]
    row[P_YR_LAST] = yr[i1]
    row[P_B_FORCE] = force_curvature(loc, i0, i1, im, B)


@njit(cache=True, nogil=True)
def search_patches(prof, pose, targets, memo, out):
    """The wheelset's pose under the interpenetrations ``targets`` [m] (left,
    right) and its patches into ``out`` (rows of :data:`PATCH_FIELDS`, at most
    :data:`MAX_PATCHES` per side, left side first).  The roll search starts at the
    memo's roll, and the memo keeps what the next search of the case reuses.
    Returns (patches, vertical position [m], roll [rad]); no patches (-1) where the
    pose is not found."""
    for attempt in range(2):
        roll, z = solve_roll(prof, pose, targets, 1e-12, memo)
        if not math.isfinite(roll) and attempt == 0:
            # the memo's windows and secant slope may not serve this pose (a
            # far step): the roll searched again over the wheel, from the memo's roll
            memo[1] = ROLL_SLOPE
            memo[6] = np.nan
            memo[12] = np.nan
            roll, z = solve_roll(prof, pose, targets, 1e-12, memo)
        if not math.isfinite(roll):
            return -1, math.nan, math.nan
        memo[0] = roll
        loc0 = side_locus(prof, pose, 0, z, roll, targets[0] + LOCUS_MARGIN, memo, False)
        loc1 = side_locus(prof, pose, 1, z, roll, targets[1] + LOCUS_MARGIN, memo, False)
        if loc0[5].size == 0 or loc1[5].size == 0:
            return -1, z, roll
        # a point deeper than the roll search's minimum: searched again over the
        # locus windows
        missed = (np.min(loc0[5]) + targets[0] < -MISSED_DEPTH
                  or np.min(loc1[5]) + targets[1] < -MISSED_DEPTH)
        if not missed:
            break
        memo[6] = np.nan
        memo[12] = np.nan
    m = 0
    for s in range(2):
        loc = loc0 if s == 0 else loc1
        gap, P, yr = loc[5], loc[3], loc[4]
        regions = locus_regions(gap, P, yr, pose.combine)
        for r in range(min(regions.shape[0], MAX_PATCHES)):
            make_patch(prof, pose, s, loc, regions[r, 0], regions[r, 1], z, roll, out[m])
            m += 1
    return m, z, roll


@njit(cache=True, nogil=True)
def row_frame(row, pose, z, roll, frame, extent):
    """The packed gap frame of a patch row of :func:`search_patches` at the pose
    (vertical position z [m], roll [rad]) into ``frame`` (24: C, t, n, y_off, R^T, O,
    e, r0, as :attr:`railcontact.geometry.gap.GapEvaluator.frame` of the row's
    :func:`patch_geometry`) and its extent (x_min, x_max, y_min, y_max) [m] into
    ``extent``; returns the side's sign (-1 left, 1 right)."""
    s = int(row[P_SIDE])
    sgn = 1.0 if s == 1 else -1.0
    R, O, y_off = side_frame(pose, s, z, roll)
    a_ref = sgn * row[P_CONTACT_ANGLE]
    ca, sa = math.cos(a_ref), math.sin(a_ref)
    frame[0], frame[1], frame[2] = row[P_X], sgn * row[P_Y], row[P_Z]
    frame[3], frame[4], frame[5] = 0.0, ca, sa
    frame[6], frame[7], frame[8] = 0.0, -sa, ca
    frame[9] = y_off
    for i in range(3):
        for j in range(3):
            frame[10 + 3 * i + j] = R[j, i]
    frame[19], frame[20], frame[21] = O[0], O[1], O[2]
    frame[22], frame[23] = pose.e, pose.r0
    y_ref = row[P_Y_RAIL]
    e0 = sgn * (row[P_YS_MIN] - y_ref)
    e1 = sgn * (row[P_YS_MAX] - y_ref)
    half_x = math.sqrt(max(row[P_APPROACH], 0.0) / max(row[P_A], 1e-9))
    extent[0] = row[P_X_M] - half_x
    extent[1] = row[P_X_M] + half_x
    extent[2] = min(e0, e1) / ca
    extent[3] = max(e0, e1) / ca
    return sgn


#: local minima of the gap deeper than the global minimum plus this are candidates of
#: the first estimate [m] (:data:`railcontact.geometry.search.CANDIDATE_DEPTH`)
CANDIDATE_DEPTH = 3e-4


@njit(cache=True, nogil=True)
def locus_curvatures(loc, i, r0, zw):
    """(A, B) [1/m] at locus index i in the normal section
    (:func:`railcontact.geometry.search._locus_curvatures`); ``zw`` the locus's wheel
    heights."""
    gap, yr, slope = loc[5], loc[4], loc[6]
    ang = math.atan(slope[i])
    A = math.cos(ang) / (2.0 * (r0 + zw[i]))
    # least-squares parabola in t = dy / 0.25 mm through the samples within 0.25 mm
    S = np.zeros((3, 3))
    rhs = np.zeros(3)
    cnt = 0
    for j in range(gap.size):
        if abs(yr[j] - yr[i]) <= 2.5e-4 and math.isfinite(gap[j]):
            tt = (yr[j] - yr[i]) / 2.5e-4
            v = (tt * tt, tt, 1.0)
            for p in range(3):
                rhs[p] += v[p] * gap[j]
                for q in range(3):
                    S[p, q] += v[p] * v[q]
            cnt += 1
    B = 0.0
    if cnt >= 5:
        det = (S[0, 0] * (S[1, 1] * S[2, 2] - S[1, 2] * S[2, 1])
               - S[0, 1] * (S[1, 0] * S[2, 2] - S[1, 2] * S[2, 0])
               + S[0, 2] * (S[1, 0] * S[2, 1] - S[1, 1] * S[2, 0]))
        if det != 0.0:
            c0 = (rhs[0] * (S[1, 1] * S[2, 2] - S[1, 2] * S[2, 1])
                  - S[0, 1] * (rhs[1] * S[2, 2] - S[1, 2] * rhs[2])
                  + S[0, 2] * (rhs[1] * S[2, 1] - S[1, 1] * rhs[2])) / det
            B = c0 / 2.5e-4 ** 2 * math.cos(ang) ** 3
    return A, max(B, 1e-3)


@njit(cache=True, nogil=True)
def gap_candidates(gap):
    """Indices of the locus's local minima within ``CANDIDATE_DEPTH`` of its minimum
    that stand out by at least 0.1 um within 0.1 mm on both sides (the prominence of
    :func:`railcontact.geometry.search._candidates`), and the minimum's."""
    n = gap.size
    imin = np.argmin(gap)
    gmin = gap[imin]
    out = np.empty(n, dtype=np.int64)
    m = 0
    for i in range(1, n - 1):
        g = gap[i]
        if not (g <= gmin + CANDIDATE_DEPTH and g < gap[i - 1] and g <= gap[i + 1]):
            continue
        left = g
        for j in range(max(i - 4, 0), i):
            left = max(left, gap[j] if math.isfinite(gap[j]) else 1.0)
        right = g
        for j in range(i + 1, min(i + 5, n)):
            right = max(right, gap[j] if math.isfinite(gap[j]) else 1.0)
        if min(left, right) - g >= 1e-7 or i == imin:
            out[m] = i
            m += 1
    found = False
    for k in range(m):
        found = found or out[k] == imin
    if not found:
        out[m] = imin
        m += 1
    return out[:m]


# ---------------------------------------------------------------------------------
# the patches of a compiled search as the geometry layer's objects


def patch_geometry(row, wheelset, track, pose, territory=(-math.inf, math.inf)):
    """The :class:`~railcontact.geometry.contact.ContactGeometry` of a patch row of
    :func:`search_patches` at the wheelset pose ``pose``
    (:class:`~railcontact.geometry.track.WheelsetPose`), as
    :func:`railcontact.geometry.search._make_patch` makes it (a patch of one
    region; ``territory``: its lateral bounds on the rail profile [m])."""
    side = "right" if row[P_SIDE] == 1 else "left"
    sgn = 1.0 if side == "right" else -1.0
    y_ws, z_ws, roll_s, yaw_s = side_pose(side, pose.lateral_shift, pose.vertical, pose.roll,
                                          pose.yaw)
    frame = _Frame(np.array([0.0, y_ws, z_ws - wheelset.nominal_radius]),
                   rotation(yaw_s, roll_s))
    a_ref = sgn * float(row[P_CONTACT_ANGLE])
    y_ref = float(row[P_Y_RAIL])
    C = np.array([float(row[P_X]), sgn * float(row[P_Y]), float(row[P_Z])])
    gapf = GapEvaluator(wheelset, track, side, frame, C, a_ref)
    ca = math.cos(a_ref)
    approach, A = float(row[P_APPROACH]), float(row[P_A])
    ext_y = (sgn * (float(row[P_YS_MIN]) - y_ref), sgn * (float(row[P_YS_MAX]) - y_ref))
    half_x = math.sqrt(max(approach, 0.0) / max(A, 1e-9))
    x_m = float(row[P_X_M])
    extent = (x_m - half_x, x_m + half_x, min(ext_y) / ca, max(ext_y) / ca)
    lim = sorted(sgn * (v - y_ref) / ca for v in territory)
    return ContactGeometry(curvatures=(A, float(row[P_B])), side=side,
                           force_curvature=float(row[P_B_FORCE]),
                           contact_angle=float(row[P_CONTACT_ANGLE]),
                           rolling_radius=float(row[P_ROLLING_RADIUS]), y_rail=y_ref,
                           y_wheel=float(row[P_Y_WHEEL]), z_rail=float(row[P_Z_RAIL]),
                           z_wheel=float(row[P_Z_WHEEL]),
                           position=np.array([C[0], sgn * C[1], C[2]]), approach=approach,
                           weight=float(row[P_WEIGHT]),
                           creepage=(float(row[P_XI]), float(row[P_ETA]), float(row[P_PHI])),
                           velocity=float(row[P_VELOCITY]), extent=extent,
                           gap_function=gapf, spin_derivative=float(row[P_SPIN_DERIVATIVE]),
                           bounds=tuple(lim), interaction=(),
                           local_contact_angle=gapf.contact_angle_at)


class _Frame:
    """The wheelset's centre and axes in a side frame, as a locus holds them (what
    :class:`~railcontact.geometry.gap.GapEvaluator` reads)."""

    def __init__(self, origin, axes):
        self.origin, self.axes = origin, axes


def rows_contact(rows, wheelset, track, pose, loads, interpenetration):
    """The :class:`~railcontact.geometry.contact.WheelsetContact` of the patch rows of
    one :func:`search_patches` (combine distance 0: a patch per region), with each
    patch's territory halfway to its side's neighbours
    (:func:`railcontact.geometry.regions.territories`); each wheel's patches from
    the field side, as the geometry layer numbers them (the rows run along the locus
    from the gauge side)."""
    patches = []
    lands = row_territories(rows)
    for s in (0, 1):
        side = [patch_geometry(r, wheelset, track, pose, lands[i])
                for i, r in enumerate(rows) if r[P_SIDE] == s]
        patches.extend(reversed(side))
    return WheelsetContact(pose, patches, {}, dict(loads), dict(interpenetration))


def row_territories(rows) -> list:
    """Each patch row's territory on the rail profile [m] (lateral bounds, for
    :func:`patch_geometry`): halfway from its region's span (:data:`P_YR_FIRST`,
    :data:`P_YR_LAST`) to the nearest span of another row on the same side, or
    unbounded where there is none (:func:`railcontact.geometry.regions.territories`'
    rule).  A patch solved on a grid of its own (the exact normal model,
    :func:`railcontact.normal.potential_area.own_gap`) takes only its own
    interpenetration region inside it: without it, a grid reaching a neighbour's
    region would load that region a second time."""
    spans = [(min(r[P_YR_FIRST], r[P_YR_LAST]), max(r[P_YR_FIRST], r[P_YR_LAST]))
             for r in rows]
    out = []
    for r, (lo, hi) in zip(rows, spans):
        below = [h for q, (l, h) in zip(rows, spans) if q[P_SIDE] == r[P_SIDE] and h < lo]
        above = [l for q, (l, h) in zip(rows, spans) if q[P_SIDE] == r[P_SIDE] and l > hi]
        out.append((0.5 * (lo + max(below)) if below else -math.inf,
                    0.5 * (hi + min(above)) if above else math.inf))
    return out
