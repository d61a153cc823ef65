"""Contact locus: the lowest point of each wheel circle relative to the rail.

For straight track the rail is a cylinder along x, so for every wheel cross-section
(lateral wheel-profile position y_w, radius r0 + z_w) the vertical gap to the rail
is minimal at one angle theta of the wheel circle.  With the wheelset axes R
(columns: axle-fixed x, y, z) the stationarity of the vertical gap gives

    tan(theta) = (s R10 - R20) / (s R12 - R22),

with s the rail slope dz/dy at the point, iterated because s depends on where the
point falls.  This uses the wheel's surface of revolution with yaw and roll (no 2-D
cross-section approximation); the gap along the locus is the vertical distance.

CONTACT's locus (``Wheelset.locus = "contact"``, its ``locus_prismatic``) takes at
each wheel cross-section the point whose surface normal is perpendicular to the
rolling direction x, whatever the rail below it: with w' = dz_w/dy_w the wheel
profile's slope, the normal of the surface of revolution is proportional to
u - w' R[:, 1] (u the radial direction at theta), so that

    sin(theta) R00 + cos(theta) R02 = w' R01,

and its x on the wheel is kept within half the radius (CONTACT's clipping of
near-vertical sections).  Both loci meet where wheel and rail touch; they differ
in the interpenetration around it, most with yaw on the flange, where the
lowest points of neighbouring circles fall far apart along x.

The kernels walk the wheel's samples in order and look the rail profile up in
the previous sample's piece, written out in their loops where it holds the
point, else through ``ppoly_at`` (a compiled call that takes arrays and is not
inlined costs atomic reference counts of every array, more than the lookup; the
piece holding a point is unique, so the guess moves no result).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numba import njit

from ..core.errors import ContactNotFoundError
from ..profiles.profile import ppoly_at
from .track import Track, Wheelset, rotation

#: sampling step of the wheel profile along the locus [m]
LOCUS_STEP = 2.5e-5


#: the contact loci: each wheel circle's lowest point above the rail, or CONTACT's
#: (the point whose normal is perpendicular to the rolling direction)
LOCUS_RULES = ("lowest", "contact")


@lru_cache(maxsize=32)
def _wheel_samples(wheel, step, offset, r0):
    """The wheel profile's samples (y_w, z_w) every ``step`` [m], with their lateral
    positions from the wheelset centre (``offset`` + y_w) and radii (``r0`` + z_w)."""
    n = int((wheel.y_max - wheel.y_min) / step) + 1
    yw = np.linspace(wheel.y_min, wheel.y_max, n)
    zw = wheel.z_at(yw)
    return yw, zw, offset + yw, r0 + zw


@lru_cache(maxsize=32)
def _wheel_slopes(wheel, step):
    """The wheel profile's slopes dz_w/dy_w at the samples of :func:`_wheel_samples`
    (0 where undefined)."""
    n = int((wheel.y_max - wheel.y_min) / step) + 1
    s = np.asarray(wheel.slope(np.linspace(wheel.y_min, wheel.y_max, n)), dtype=float)
    return np.where(np.isfinite(s), s, 0.0)


def _slopes_for(wheelset, wheel, step):
    """The wheel slopes the locus kernels take: the profile's for CONTACT's locus,
    None (the lowest points) otherwise."""
    if getattr(wheelset, "locus", "lowest") == "contact":
        return _wheel_slopes(wheel, step)
    return None


@njit(cache=True, nogil=True)
def _slopes_part(ws, lo, hi, step):
    """The wheel slopes ``ws[lo:hi:step]`` of the samples a locus kernel takes, or
    None where ``ws`` is (the lowest points: the branch is resolved when the kernels
    are compiled, so that the lowest points' kernel carries no test of the rule)."""
    if ws is None:
        return None
    return ws[lo:hi:step]


@njit(cache=True, nogil=True)
def _slopes_at(ws, idx):
    """The wheel slopes ``ws[idx]`` at the samples ``idx``, or None where ``ws`` is."""
    if ws is None:
        return None
    return ws[idx]


@njit(cache=True, nogil=True, inline="always")
def _locus_arrays(n):
    """The locus kernels' outputs for n samples: theta, point (3, n), rail
    coordinate, gap and slope (uninitialised)."""
    return np.empty(n), np.empty((3, n)), np.empty(n), np.empty(n), np.empty(n)


@njit(cache=True, nogil=True)
def _contact_locus_kernel(eta, rho, wslope, R, O, y_off, rb, rc):
    """CONTACT's locus (module docstring): angle theta, wheel point, rail
    coordinate, vertical gap and rail slope at the samples' points whose normal is
    perpendicular to x (``wslope`` the wheel profile's slopes)."""
    n = eta.size
    theta, P, yr, gap, slope = _locus_arrays(n)
    h = math.sqrt(R[0, 0] * R[0, 0] + R[0, 2] * R[0, 2])
    phase = math.atan2(R[0, 2], R[0, 0])
    k = -1
    nr = rb.size - 1
    for i in range(n):
        c = min(max(wslope[i] * R[0, 1] / h, -1.0), 1.0)
        th = math.asin(c) - phase
        st = math.sin(th)
        if abs(st) > 0.5:
            # x on the wheel within half its radius (near-vertical sections)
            st = 0.5 if st > 0 else -0.5
            th = math.asin(st)
        ct = math.cos(th)
        P[0, i] = O[0] + eta[i] * R[0, 1] + rho[i] * (st * R[0, 0] + ct * R[0, 2])
        P[1, i] = O[1] + eta[i] * R[1, 1] + rho[i] * (st * R[1, 0] + ct * R[1, 2])
        P[2, i] = O[2] + eta[i] * R[2, 1] + rho[i] * (st * R[2, 0] + ct * R[2, 2])
        theta[i] = th
        yr[i] = P[1, i] - y_off
        # ppoly_at(yr[i], rb, rc, k), written out where the previous point's
        # piece k holds the point (module docstring)
        xr = yr[i]
        if 0 <= k < nr and rb[k] <= xr and (xr < rb[k + 1] or (k == nr - 1 and xr <= rb[nr])):
            q = xr - rb[k]
            zr = ((rc[0, k] * q + rc[1, k]) * q + rc[2, k]) * q + rc[3, k]
            s = (3.0 * rc[0, k] * q + 2.0 * rc[1, k]) * q + rc[2, k]
        else:
            zr, s, k = ppoly_at(xr, rb, rc, k)
        gap[i] = zr - P[2, i] if zr == zr else np.inf
        slope[i] = s if s == s else 0.0
    return theta, P, yr, gap, slope


@njit(cache=True, nogil=True)
def _locus_kernel(eta, rho, wslope, R, O, y_off, rb, rc):
    """Angle theta, wheel point, rail coordinate, vertical gap and rail slope:
    each wheel circle's lowest point above the rail, or CONTACT's locus where the
    wheel slopes ``wslope`` are given (one per sample; None: the lowest points).
    The one locus kernel of the package (its gaps alone: :func:`_locus_gaps`):
    the Python-orchestrated search (:func:`compute_locus`, :func:`min_gap`) and
    the compiled pass (:mod:`railcontact.geometry.wheel_pass`) both call it.

    For the lowest points the rail slope s starts extrapolated from the last two
    points' (25 um apart), and the iteration on it ends, without another
    evaluation of the rail profile, once the point would move by under 1e-12 m:
    the rail height there is that of the point 1e-12 m away (a difference below
    1e-11 m on slopes up to 10).  The iteration contracts by about
    rho yaw^2 |z_r''| per pass (0.04 at 6 mrad on the gauge corner); without yaw
    (R[1, 0] = R[2, 0] = 0) theta does not depend on s and one pass gives the
    point."""
    if wslope is not None:
        return _contact_locus_kernel(eta, rho, wslope, R, O, y_off, rb, rc)
    return _lowest_points(eta, rho, R, O, y_off, rb, rc, True)


@njit(cache=True, nogil=True)
def _locus_gaps(eta, rho, wslope, R, O, y_off, rb, rc):
    """The vertical gaps of :func:`_locus_kernel`, bit for bit, for the searches
    that read no other (the minimum gaps): the lowest points' angle theta is not
    computed (``math.atan``, some 5 of 41 ns a sample)."""
    if wslope is not None:
        return _contact_locus_kernel(eta, rho, wslope, R, O, y_off, rb, rc)[3]
    return _lowest_points(eta, rho, R, O, y_off, rb, rc, False)[3]


@njit(cache=True, nogil=True, inline="always")
def _lowest_points(eta, rho, R, O, y_off, rb, rc, full):
    """:func:`_locus_kernel`'s lowest points where ``full`` (a constant of its
    callers, into which it is inlined), else their gaps alone (:func:`_locus_gaps`:
    the other outputs empty, neither allocated nor stored, some 100 ns a call of
    the roll search's many short ones)."""
    n = eta.size
    gap = np.empty(n)
    if full:
        theta, P, yr, _, slope = _locus_arrays(n)
    else:
        theta, P, yr, _, slope = _locus_arrays(0)
    k = -1                      # rail interval of the previous point (the search starts there)
    nr = rb.size - 1
    fixed = R[1, 0] == 0.0 and R[2, 0] == 0.0
    s = 0.0
    s1 = 0.0                    # the slopes at the last two points
    s2 = 0.0
    for i in range(n):
        s = 2.0 * s1 - s2 if i >= 2 else s1
        tn = 0.0
        py = 0.0
        pz = 0.0
        px = 0.0
        zr = np.nan
        for it in range(4):
            tn_new = (s * R[1, 0] - R[2, 0]) / (s * R[1, 2] - R[2, 2])
            ct = 1.0 / math.sqrt(1.0 + tn_new * tn_new)      # theta = atan(tn) in (-pi/2, pi/2)
            st = tn_new * ct
            py_new = O[1] + eta[i] * R[1, 1] + rho[i] * (st * R[1, 0] + ct * R[1, 2])
            if it >= 1 and abs(py_new - py) <= 1e-12:
                break
            tn = tn_new
            px = O[0] + eta[i] * R[0, 1] + rho[i] * (st * R[0, 0] + ct * R[0, 2])
            py = py_new
            pz = O[2] + eta[i] * R[2, 1] + rho[i] * (st * R[2, 0] + ct * R[2, 2])
            # ppoly_at(py - y_off, rb, rc, k), written out where the previous
            # point's piece k holds the point (module docstring)
            xr = py - y_off
            if 0 <= k < nr and rb[k] <= xr and (xr < rb[k + 1] or (k == nr - 1 and xr <= rb[nr])):
                q = xr - rb[k]
                zr = ((rc[0, k] * q + rc[1, k]) * q + rc[2, k]) * q + rc[3, k]
                s = (3.0 * rc[0, k] * q + 2.0 * rc[1, k]) * q + rc[2, k]
            else:
                zr, s, k = ppoly_at(xr, rb, rc, k)
            if s != s:
                s = 0.0
            if fixed:
                break
        if full:
            theta[i] = math.atan(tn)
            P[0, i] = px
            P[1, i] = py
            P[2, i] = pz
            yr[i] = py - y_off
            slope[i] = s
        gap[i] = zr - pz if zr == zr else np.inf
        s2, s1 = s1, s
    return theta, P, yr, gap, slope


#: the minimum-gap search's coarse pass takes every this many wheel samples, and
#: refines around the coarse points within ``MIN_GAP_WINDOW`` [m] of the coarse
#: minimum (compile-time constants of :func:`_min_gap_kernel`)
MIN_GAP_STRIDE = 8
MIN_GAP_WINDOW = 2e-6


@njit(cache=True, nogil=True)
def _min_gap_kernel(eta, rho, wslope, R, O, y_off, rb, rc):
    """Minimum vertical gap along the locus: coarse pass every ``MIN_GAP_STRIDE``
    samples, then every sample around the coarse points within ``MIN_GAP_WINDOW``
    [m] of the coarse minimum (``wslope`` as in :func:`_locus_kernel`)."""
    n = eta.size
    st = MIN_GAP_STRIDE
    gc = _locus_gaps(eta[::st], rho[::st], _slopes_part(wslope, 0, n, st), R, O, y_off, rb,
                     rc)
    gmin = np.inf
    for g in gc:
        if g < gmin:
            gmin = g
    best = np.inf
    for c in range(gc.size):
        if gc[c] <= gmin + MIN_GAP_WINDOW:
            lo = max(st * c - st, 0)
            hi = min(st * c + st + 1, n)
            gf = _locus_gaps(eta[lo:hi], rho[lo:hi], _slopes_part(wslope, lo, hi, 1), R, O,
                             y_off, rb, rc)
            for g in gf:
                if g < best:
                    best = g
    return best


@dataclass
class Locus:
    """Contact locus of one side, in the side frame (lateral axis to the field side).

    Arrays along the wheel profile: ``y_wheel``, ``z_wheel`` (profile coordinates),
    ``theta`` (angle on the wheel circle), ``point`` (3 x n, the wheel point),
    ``y_rail`` (rail-profile coordinate below it), ``gap`` (vertical, m, negative
    means interpenetration; +inf outside the rail), ``slope`` (rail dz/dy).

    ``row_weight`` and ``row_x`` (None for a wheel of revolution): where the
    interpenetration along x is not a parabola about the lowest point (an
    out-of-round wheel), each sample's weight in a patch's reference point and
    angle, the integral over x of its squared interpenetration [m^5], and the x [m]
    of that integral's centre (CONTACT's 2-D gap function, ``compute_wgt_center_2d``);
    :meth:`weights` and :meth:`x_centres` give them, or the parabola's.
    """

    y_wheel: np.ndarray
    z_wheel: np.ndarray
    theta: np.ndarray
    point: np.ndarray
    y_rail: np.ndarray
    gap: np.ndarray
    slope: np.ndarray
    origin: np.ndarray          # wheelset centre in the side frame
    axes: np.ndarray            # rotation matrix of the wheelset in the side frame
    samples: tuple = (0, 0)     # the wheel-profile samples [i0, i1) it covers
    row_weight: np.ndarray | None = None
    row_x: np.ndarray | None = None

    def weights(self, sl: slice, exponent: float) -> np.ndarray:
        """Weights of the samples ``sl`` in a patch's reference point and angle:
        ``row_weight`` where given, else (-g)^exponent (the integral over x of the
        squared interpenetration of a parabola in x, up to a factor common to the
        patch, for ``exponent`` 2.5)."""
        if self.row_weight is not None:
            return self.row_weight[sl]
        return (-np.minimum(self.gap[sl], 0.0)) ** exponent

    def x_centres(self, sl: slice) -> np.ndarray:
        """x [m] of the samples ``sl`` in a patch's reference point: ``row_x`` where
        given, else the wheel point's (the lowest point of the parabola)."""
        return (self.row_x if self.row_x is not None else self.point[0])[sl]

    @property
    def i_min(self) -> int:
        return int(np.argmin(self.gap))

    @property
    def gap_min(self) -> float:
        return float(self.gap[self.i_min])


def side_pose(side: str, lateral_shift: float, vertical: float, roll: float, yaw: float):
    """Wheelset pose expressed in the side frame (mirrored for the left side)."""
    if side == "right":
        return lateral_shift, vertical, roll, yaw
    return -lateral_shift, vertical, -roll, -yaw


#: the fine locus covers the part of the wheel whose coarse gap is within this of the minimum
LOCUS_WINDOW = 1e-3


def compute_locus(wheelset: Wheelset, track: Track, side: str, lateral_shift: float,
                  vertical: float, roll: float, yaw: float, step: float = LOCUS_STEP,
                  stride: int = 8, window: float = LOCUS_WINDOW,
                  samples: tuple | None = None) -> Locus:
    """Contact locus and vertical gap for one side at the given wheelset pose.

    A coarse pass (every ``stride``-th wheel sample) finds the part of the wheel that
    comes within ``window`` [m] of the rail's closest approach (default
    ``LOCUS_WINDOW``); the locus is computed at full resolution there only.

    ``samples``: the wheel-profile samples [i0, i1) of a locus at a nearby pose
    (:attr:`Locus.samples`), tried first without the coarse pass: they serve where
    the gap at both of their ends (that are not the wheel's) exceeds the closest
    approach by more than ``window``, so that they hold every sample within it.
    """
    wheel, rail = wheelset.wheel(side), track.rail(side)
    y_ws, z_ws, roll_s, yaw_s = side_pose(side, lateral_shift, vertical, roll, yaw)
    r0 = wheelset.nominal_radius
    yw, zw, eta, rho = _wheel_samples(wheel, step, wheelset.wheel_offset, r0)
    ws = _slopes_for(wheelset, wheel, step)
    R = rotation(yaw_s, roll_s)
    O = np.array([0.0, y_ws, z_ws - r0])
    y_off = track.rail_offset(side)
    if samples is not None:
        i0, i1 = samples
        sl = slice(i0, i1)
        theta, P, yr, gap, s = _locus_kernel(eta[sl], rho[sl], None if ws is None else ws[sl],
                                             R, O, y_off, rail._breaks, rail._coefs)
        if gap.size:
            edge = float(np.min(gap)) + window
            if (i0 == 0 or gap[0] > edge) and (i1 == yw.size or gap[-1] > edge):
                return _out_of_round(wheelset, Locus(yw[sl], zw[sl], theta, P, yr, gap, s, O,
                                                     R, (i0, i1)))
    _, _, _, gc, _ = _locus_kernel(eta[::stride], rho[::stride],
                                   None if ws is None else ws[::stride], R, O, y_off,
                                   rail._breaks, rail._coefs)
    near = np.flatnonzero(gc <= np.min(gc) + window)
    i0, i1 = 0, yw.size
    if near.size:
        i0 = max(int(near[0]) * stride - 2 * stride, 0)
        i1 = min(int(near[-1]) * stride + 2 * stride + 1, yw.size)
        sl = slice(i0, i1)
        yw, zw, eta, rho = yw[sl], zw[sl], eta[sl], rho[sl]
        ws = ws[sl] if ws is not None else None
    theta, P, yr, gap, s = _locus_kernel(eta, rho, ws, R, O, y_off, rail._breaks, rail._coefs)
    return _out_of_round(wheelset, Locus(yw, zw, theta, P, yr, gap, s, O, R, (i0, i1)))


def _out_of_round(wheelset: Wheelset, loc: Locus) -> Locus:
    """The locus of an out-of-round wheel (``wheelset.out_of_round``), else ``loc``."""
    if wheelset.out_of_round is None:
        return loc
    return wheelset.out_of_round.locus(loc, wheelset.nominal_radius)


def min_gap(wheelset: Wheelset, track: Track, side: str, lateral_shift: float, vertical: float,
            roll: float, yaw: float, step: float = LOCUS_STEP,
            samples: tuple | None = None) -> float:
    """Minimum vertical gap [m] of one side (fast: coarse pass, local refinement;
    :func:`_min_gap_kernel`).

    ``samples``: search the wheel-profile samples [i0, i1) only (the range of a
    locus at a nearby pose, :attr:`Locus.samples`, which holds every sample within
    its window of its minimum)."""
    wheel, rail = wheelset.wheel(side), track.rail(side)
    y_ws, z_ws, roll_s, yaw_s = side_pose(side, lateral_shift, vertical, roll, yaw)
    r0 = wheelset.nominal_radius
    _, _, eta, rho = _wheel_samples(wheel, step, wheelset.wheel_offset, r0)
    ws = _slopes_for(wheelset, wheel, step)
    if samples is not None:
        eta, rho = eta[samples[0]:samples[1]], rho[samples[0]:samples[1]]
        ws = ws[samples[0]:samples[1]] if ws is not None else None
    R = rotation(yaw_s, roll_s)
    O = np.array([0.0, y_ws, z_ws - r0])
    return float(_min_gap_kernel(eta, rho, ws, R, O, track.rail_offset(side), rail._breaks,
                                 rail._coefs))


def depth_at(wheelset: Wheelset, track: Track, side: str, lateral_shift: float, vertical: float,
             roll: float, yaw: float) -> float:
    """The deepest interpenetration [m] of one side with the wheelset at the vertical
    position ``vertical`` [m] (CONTACT's Z_WS): how far it stands below where that
    side touches (negative: off its rail).  No overlap anywhere along the profiles is
    a :class:`~railcontact.core.errors.ContactNotFoundError`."""
    g0 = min_gap(wheelset, track, side, lateral_shift, 0.0, roll, yaw)
    if not math.isfinite(g0):
        raise ContactNotFoundError(f"no wheel-rail overlap found on the {side} side at lateral "
                                   f"shift {lateral_shift * 1e3:.3f} mm")
    return vertical - g0
