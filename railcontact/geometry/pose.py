"""The wheelset's pose under given interpenetrations: its vertical position and
roll such that each side's deepest interpenetration equals its target
(:func:`solve_pose`), from the contact loci of both sides
(:mod:`railcontact.geometry.locus`)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from ..core.errors import ContactNotFoundError
from .locus import LOCUS_WINDOW, compute_locus, min_gap
from .track import SIDES, Track


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
#: secant steps of :func:`solve_pose`)
ROLL_SLOPE = 1.5



@dataclass
class PoseMemo:
    """What successive searches of one case (one track, shift and yaw) carry over."""

    track: Track
    #: minimum vertical gaps of both sides by roll
    gaps: dict = field(default_factory=dict)
    #: per side the last locus's (roll, wheel-sample range, roll it serves within)
    windows: dict = field(default_factory=dict)
    #: the last roll search's secant slope [m/rad]
    slope: float = ROLL_SLOPE
    #: per (side, prescribed roll) the compiled search's memo and the side's minimum
    #: gap at vertical position 0 (:func:`railcontact.geometry.search.find_contact`
    #: under a prescribed roll)
    fixed_roll: dict = field(default_factory=dict)
    #: the compiled search's memo under a free roll
    #: (:func:`railcontact.geometry.search.find_contact` at prescribed
    #: interpenetrations): its loci's wheel samples and secant slope (None: none yet)
    search: object = None



def locus_window(loci_window, target: float) -> float:
    """The window [m] of a side's locus (:func:`solve_pose`'s ``loci_window``) under
    the interpenetration ``target`` [m]."""
    if loci_window is None:
        return LOCUS_WINDOW
    regions = target + REGION_MARGIN
    return regions if loci_window == "regions" else max(float(loci_window), regions)


def _memo(wheelset, track, y_ws, yaw) -> PoseMemo:
    """The wheelset's memo for this track, shift and yaw (the track itself is held,
    so that the identity check is sound; bounded in size)."""
    if len(wheelset.gap_memo) > 64:
        wheelset.gap_memo.clear()
    memo = wheelset.gap_memo.get((y_ws, yaw))
    if memo is None or memo.track is not track or len(memo.gaps) + len(memo.fixed_roll) > 256:
        memo = wheelset.gap_memo[(y_ws, yaw)] = PoseMemo(track)
    return memo



def solve_pose(wheelset, track, y_ws, yaw, targets, roll0=0.0, tol=1e-12,
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
        return locus_window(loci_window, targets[side])

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
