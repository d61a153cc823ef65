"""The strip models for many patches at once: forces, area and p_max only.

The per-patch models of :mod:`railcontact.normal.semi_hertzian` lay their strips
on a full grid and build a :class:`~railcontact.normal.base.NormalSolution` for
every patch.  For sweeps, wear loops and dynamics, where only the patch results
are needed, this module runs the same models (``kik-piotrowski``, ``kpec``,
``stripes``, ``analyn``; the one implementation of their equations,
:func:`railcontact.normal.strip_theory.strip_pressures`) on all patches together;
only the sampling of the gap differs:

* the gap of every patch is sampled at three points along x on each of ``strips``
  strips, in one compiled loop per profile pair
  (:func:`railcontact.geometry.gap.sample_gap_lines`); a parabola through the three
  samples gives each strip's minimum g(y), its position x_m(y) and the longitudinal
  curvature A(y); the lateral curvature B(y) is the second difference across the
  strips at x_m(y);
* the semi-elliptic pressure of strip j has half-length l_j around x_m(y_j) and
  maximum p_j, so that F_n = sum (pi/2) p_j l_j dy and the area is sum 2 l_j dy.

The results agree with the per-patch models within their grid resolution (tested in
``tests/normal/test_strip_batch.py``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numba import njit

from ..core.errors import InputError
from ..geometry.gap import DEEPEST_GAP, Spline, _gap_lines_kernel, profile_groups
from ..geometry.wheel_pass import illinois_update
from ..core.hertz_theory import hertz_ellipses
from .strip_theory import MIN_CURVATURE, STRIP_MODELS, parabola_min, strip_pressures



@dataclass
class StripSolution:
    """Strip-wise semi-elliptic pressures of many patches (SI units).

    Arrays of shape (patches, strips): ``y`` strip centres, ``x_mid`` strip centres
    along x, ``half`` half-lengths (0: no contact), ``p_strip`` maximum pressure
    per strip and ``A``, ``B`` the gap's local relative curvatures [1/m] (along x at
    the strip's minimum, and across the strips); per patch: ``dy`` strip width,
    ``normal_force``, ``area``, ``pmax``, ``penetration``.
    """

    y: np.ndarray
    dy: np.ndarray
    x_mid: np.ndarray
    half: np.ndarray
    p_strip: np.ndarray
    penetration: np.ndarray
    A: np.ndarray
    B: np.ndarray
    #: (a, b) [m] per patch where the patches are ellipses cut in strips
    #: (:func:`hertz_ellipse_strips`): area, p_max and the equivalent ellipse are then
    #: the ellipse's own
    semi_axes: tuple | None = None

    @property
    def normal_force(self) -> np.ndarray:
        return 0.5 * math.pi * np.sum(self.p_strip * self.half, axis=1) * self.dy

    @property
    def area(self) -> np.ndarray:
        if self.semi_axes is not None:
            return math.pi * self.semi_axes[0] * self.semi_axes[1]
        return 2.0 * np.sum(self.half, axis=1) * self.dy

    @property
    def pmax(self) -> np.ndarray:
        if self.semi_axes is not None:
            area = self.area
            with np.errstate(divide="ignore", invalid="ignore"):
                return np.where(area > 0, 1.5 * self.normal_force / area, 0.0)
        return self.p_strip.max(axis=1, initial=0.0)

    def equivalent_ellipses(self):
        """Semi-axes (a, b) [m] of the equivalent ellipse of every patch (area and
        length/width ratio of the contact, as :func:`~railcontact.tangential.fastsim.
        equivalent_ellipse`); zero where there is no contact."""
        if self.semi_axes is not None:
            return self.semi_axes
        n = self.half.shape[0]
        out = np.empty((5, n))
        _totals_kernel(np.ascontiguousarray(self.x_mid), np.ascontiguousarray(self.half),
                       np.ascontiguousarray(self.p_strip),
                       np.ascontiguousarray(np.broadcast_to(self.dy, (n,)), dtype=float), out)
        return out[3], out[4]


@njit(cache=True, nogil=True)
def strip_totals(x_mid, half, peak, dy):
    """One patch's normal force F_n [N], area [m^2], p_max [Pa] and equivalent
    ellipse (a, b) [m] from its semi-elliptic strips: F_n = sum (pi/2) p_j l_j dy,
    area = sum 2 l_j dy, and the ellipse of that area with the contact's length/width
    ratio (:func:`~railcontact.tangential.fastsim.equivalent_ellipse`); zero where no
    strip is in contact."""
    F = 0.0
    area = 0.0
    pmax = 0.0
    lead, trail = -np.inf, np.inf
    first, last = -1, -1
    for j in range(half.size):
        F += peak[j] * half[j]
        pmax = max(pmax, peak[j])
        if half[j] > 0.0:
            area += half[j]
            lead = max(lead, x_mid[j] + half[j])
            trail = min(trail, x_mid[j] - half[j])
            if first < 0:
                first = j
            last = j
    F *= 0.5 * math.pi * dy
    area *= 2.0 * dy
    if first < 0:
        return F, area, pmax, 0.0, 0.0
    L = lead - trail
    W = (last - first + 1) * dy
    r = math.sqrt(area / math.pi)
    return F, area, pmax, r * math.sqrt(L / W), r * math.sqrt(W / L)


@njit(cache=True, nogil=True)
def _totals_kernel(x_mid, half, peak, dy, out):
    for k in range(half.shape[0]):
        out[0, k], out[1, k], out[2, k], out[3, k], out[4, k] = strip_totals(
            x_mid[k], half[k], peak[k], dy[k])


class StripGrid(NamedTuple):
    """How the batch path lays the strips of a patch (:func:`strip_geometry`)."""

    #: strips across the patch
    strips: int
    #: the lateral window is the geometry's extent widened by this fraction
    margin: float
    #: at most this many widenings (x 1.6) while a patch reaches the window's edge
    widen: int
    #: lay the strips again on the ends of the patch's run of strips (its edges
    #: interpolated) widened by ``margin``: the strips' sums continuous in the
    #: approach (without it they move with the geometry's extent, a sampled one:
    #: steps of up to 0.05 % of the force, measured on ANALYN, which the compiled
    #: case's balance to 1e-4 cannot cross; the compiled pass refines, the batch
    #: path keeps its window)
    refine: bool = False


#: fields of a patch's window of :func:`strip_window_geometry` (a float array)
WINDOW_FIELDS = ("approach", "penetration", "A", "B", "x_min", "x_max", "y_min", "y_max")


@njit(cache=True, nogil=True)
def strip_lines(h, y, d, dy, pen, centre, q):
    """The strip quantities of one patch from its gap sampled on three lines per
    strip, ``h`` (3, strips) at x = x_c + (0, -d, +d) [m] (approach added), the
    strips at ``y`` [m] (width ``dy``): into ``q`` (4, strips) the position x_m
    (offset from x_c), the smallest gap g (``pen`` + 1 m outside the patch's run
    of strips), A and B [1/m] (:func:`strip_geometry`).  ``centre``: (y_c, the
    half-width of the geometry's extent).  Returns whether the run reaches an
    outer strip (the window is to be widened) and the run's lateral ends [m]
    (where g crosses ``pen``, interpolated; NaN where no strip is in contact)."""
    n = y.size
    yc, core = centre
    for j in range(n):
        t, c1, c2, g = parabola_min(h[1, j], h[0, j], h[2, j], d, 2.0 * d)
        q[0, j] = t
        q[1, j] = g
        q[2, j] = max(c2, MIN_CURVATURE)
    at = np.empty(3)
    for j in range(n):
        t = q[0, j]
        jc = min(max(j, 1), n - 2)
        for k in range(3):
            i = jc - 1 + k
            _, c1, c2, _ = parabola_min(h[1, i], h[0, i], h[2, i], d, 2.0 * d)
            at[k] = h[0, i] + c1 * t + c2 * t * t
        q[3, j] = max(0.5 * (at[2] - 2.0 * at[1] + at[0]) / (dy * dy), MIN_CURVATURE)
    # the patch is the run of interpenetrating strips through the deepest strip of
    # the extent; other regions of the tangent plane (another patch, the flange
    # seen from the tread's plane) are not part of it
    jd = 0
    best = np.inf
    for j in range(n):
        if abs(y[j] - yc) <= core and q[1, j] < best:
            best = q[1, j]
            jd = j
    lo, hi = 0, n - 1
    for j in range(jd - 1, -1, -1):
        if not q[1, j] < pen:
            lo = j + 1
            break
    for j in range(jd + 1, n):
        if not q[1, j] < pen:
            hi = j - 1
            break
    inrun = q[1, jd] < pen
    # the run's ends where g crosses pen, linear between the strips (continuous in
    # the gap, unlike the strips' positions)
    y_lo = y_hi = math.nan
    if inrun:
        y_lo = y[lo] - 0.5 * dy
        if lo > 0:
            y_lo = y[lo] - dy * (pen - q[1, lo]) / (q[1, lo - 1] - q[1, lo])
        y_hi = y[hi] + 0.5 * dy
        if hi < n - 1:
            y_hi = y[hi] + dy * (pen - q[1, hi]) / (q[1, hi + 1] - q[1, hi])
    for j in range(n):
        if not (inrun and lo <= j <= hi):
            q[1, j] = pen + 1.0                    # outside the run: no contact (1 m)
    return inrun and (lo == 0 or hi == n - 1), y_lo, y_hi


@njit(cache=True, nogil=True)
def window_of(win, margin):
    """(x_c, d, y_c, half-width, half-width of the extent) [m] of a patch's first
    window (``win``: :data:`WINDOW_FIELDS`)."""
    dpos = max(win[1], 1e-9)
    xc = 0.5 * (win[4] + win[5])
    dx = max(0.5 * (win[5] - win[4]), math.sqrt(dpos / win[2]))
    yc = 0.5 * (win[6] + win[7])
    core = max(0.5 * (win[7] - win[6]), math.sqrt(dpos / win[3]))
    return xc, dx, yc, core * (1.0 + margin), core


@njit(cache=True, nogil=True)
def _line_minimum(frame, sign, rail, wheel, xs, y, approach):
    """The strip quantity g at lateral position y [m]: the smallest gap (approach
    added) of the parabola through the gap at ``xs`` (1, 3) = x_c + (0, -d, +d)
    (``frame``: the packed frame, (1, 24))."""
    ys = np.empty((1, 1))
    ys[0, 0] = sign * y
    h = _gap_lines_kernel(xs, ys, frame, rail.breaks, rail.coefs, wheel.breaks,
                          wheel.coefs)[0]
    v = np.empty(3)
    for k in range(3):
        v[k] = (1.0 if h[k, 0] < DEEPEST_GAP else h[k, 0]) + approach
    d = xs[0, 2] - xs[0, 0]
    return parabola_min(v[1], v[0], v[2], d, 2.0 * d)[3]


@njit(cache=True, nogil=True)
def _run_end(frame, sign, rail, wheel, xs, inside, outside, win):
    """Where the strip quantity g crosses the penetration between the lateral
    positions ``inside`` (g below it; its g known) and ``outside`` (above): by
    Illinois' regula falsi (bisection where the outside misses a surface), to
    1e-9 m."""
    b = outside
    fb = _line_minimum(frame, sign, rail, wheel, xs, b, win[0]) - win[1]
    if not fb >= 0.0:
        return b
    return _falsi(frame, sign, rail, wheel, xs, inside, (b, fb), win)


@njit(cache=True, nogil=True)
def _falsi(frame, sign, rail, wheel, xs, inside, outside, win):
    """:func:`_run_end`'s regula falsi from a bracket: ``inside`` and ``outside``
    the lateral positions [m] and their g minus the penetration [m] (below 0 and
    at least 0)."""
    a, fa = inside
    b, fb = outside
    pen = win[1]
    side = 0
    for _ in range(30):
        if abs(b - a) <= 1e-9:
            break
        x = (a * fb - b * fa) / (fb - fa) if fb < 1e-3 else 0.5 * (a + b)
        fx = _line_minimum(frame, sign, rail, wheel, xs, x, win[0]) - pen
        a, fa, b, fb, side = illinois_update(x, fx, a, fa, b, fb, side)
    return (a * fb - b * fa) / (fb - fa) if fb < 1e-3 else 0.5 * (a + b)


#: the warm start's first step [-] from a run's end of the last evaluation, as a
#: fraction of that run's width (:func:`strip_window_ends`)
WARM_STEP = 0.01
#: at most this many steps (each 4 times longer, at most a quarter of the run's
#: width) to bracket a run's end from the last evaluation's
WARM_TRIES = 5


@njit(cache=True, nogil=True)
def _bracket_end(frame, sign, rail, wheel, xs, guess, outward, width, win):
    """The run's end near ``guess`` [m] (the last evaluation's end; ``outward``
    +1 or -1: the direction out of the run): a bracket by steps from the guess,
    then :func:`_falsi`.  Returns (found, end [m])."""
    pen = win[1]
    y0 = guess
    f0 = _line_minimum(frame, sign, rail, wheel, xs, y0, win[0]) - pen
    h = WARM_STEP * width
    for _ in range(WARM_TRIES):
        if not (f0 == f0):
            return False, math.nan
        y1 = y0 + outward * h if f0 < 0.0 else y0 - outward * h
        f1 = _line_minimum(frame, sign, rail, wheel, xs, y1, win[0]) - pen
        if f0 < 0.0 and f1 >= 0.0:
            return True, _falsi(frame, sign, rail, wheel, xs, (y0, f0), (y1, f1), win)
        if f0 >= 0.0 and f1 < 0.0:
            return True, _falsi(frame, sign, rail, wheel, xs, (y1, f1), (y0, f0), win)
        y0, f0 = y1, f1
        h = min(4.0 * h, 0.25 * width)
    return False, math.nan


@njit(cache=True, nogil=True)
def _sample_lines(F, sign, rail, wheel, xs, w, win, y, ys):
    """The strips laid across the lateral window ``w`` (:data:`LATERAL_FIELDS`,
    :func:`lay_strips`, their centres into ``y``) and the gap on the three lines
    ``xs`` through them, the approach added (:func:`strip_window_geometry`):
    (3, strips), and the strip width [m]."""
    n = y.size
    dy = lay_strips(w, y)
    for j in range(n):
        ys[0, j] = sign * y[j]
    h = _gap_lines_kernel(xs, ys, F, rail.breaks, rail.coefs, wheel.breaks,
                          wheel.coefs)[0]
    for k in range(3):
        for j in range(n):
            h[k, j] = (1.0 if h[k, j] < DEEPEST_GAP else h[k, j]) + win[0]
    return h, dy


@njit(cache=True, nogil=True)
def strip_window_geometry(frame, sign, rail, wheel, win, grid, y, q):
    """The strip quantities of one patch of the geometry layer (its packed gap
    frame ``frame`` and side ``sign``, :class:`~railcontact.geometry.gap.GapEvaluator`;
    the profiles' :class:`~railcontact.geometry.gap.Spline` ``rail`` and ``wheel``)
    with the window ``win`` (:data:`WINDOW_FIELDS`) and the :class:`StripGrid`
    ``grid``: the strips' centres into ``y`` and (x_m, g, A, B) into ``q`` (4,
    strips), as :func:`strip_geometry`.  Returns the strip width [m]."""
    return strip_window_ends(frame, sign, rail, wheel, win, grid, y, q, np.full(3, np.nan))


@njit(cache=True, nogil=True)
def strip_window_ends(frame, sign, rail, wheel, win, grid, y, q, ends):
    """:func:`strip_window_geometry` started from the run's ends of an earlier
    evaluation of the same patch (``ends`` (3,): the two ends [m] in the strips'
    lateral coordinate, NaN: none; the third is set to 1 where the warm start was
    kept, else 0), a warm start of the refined layout (``grid.refine``)
    for a time history: each end bracketed by steps from the earlier one
    (:data:`WARM_STEP`) and found on the gap as by the cold path
    (:func:`_falsi`, 1e-9 m), the strips laid on them once.  The warm start
    replaces the first sampling of the strips (3 x strips gap points) and the
    ends' brackets from it; it is kept where the earlier ends and the ends found
    lie within the cold path's first window (the region's extent widened by
    ``grid.margin``: a run of another region, or of two regions that have since
    parted, is not taken) and the strips' run agrees with the ends to a strip
    width, else the cold path runs.  The run's ends found (either path; NaN where the
    strips were not laid on them) go back into ``ends``.  Returns the strip
    width [m]."""
    n = grid.strips
    w = lateral_window(win, grid)
    xs = np.empty((1, 3))
    ys = np.empty((1, n))
    F = frame.reshape((1, frame.size))
    xs[0, 0], xs[0, 1], xs[0, 2] = w[0], w[0] - w[1], w[0] + w[1]
    lo_w, hi_w = w[2] - w[3], w[2] + w[3]
    if grid.refine and ends[0] > lo_w and ends[1] < hi_w and ends[1] > ends[0]:
        width = ends[1] - ends[0]
        ok_lo, y_lo = _bracket_end(F, sign, rail, wheel, xs, ends[0], -1.0, width, win)
        ok_hi, y_hi = _bracket_end(F, sign, rail, wheel, xs, ends[1], 1.0, width, win) \
            if ok_lo else (False, math.nan)
        if ok_lo and ok_hi and y_hi > y_lo:
            warm = w.copy()
            warm[2], warm[4] = 0.5 * (y_lo + y_hi), 0.5 * (y_hi - y_lo)
            warm[3] = warm[4] * (1.0 + grid.margin)
            h, dy = _sample_lines(F, sign, rail, wheel, xs, warm, win, y, ys)
            edge, r_lo, r_hi = strip_lines(h, y, w[1], dy, win[1], (warm[2], warm[4]), q)
            if not edge and abs(r_lo - y_lo) <= dy and abs(r_hi - y_hi) <= dy and \
                    y_lo > lo_w and y_hi < hi_w:
                ends[0], ends[1], ends[2] = y_lo, y_hi, 1.0
                for j in range(n):
                    q[0, j] += w[0]
                return dy
    finder = (F, sign, rail, wheel, xs)
    dy = 0.0
    for it in range(grid.widen + 2):
        h, dy = _sample_lines(F, sign, rail, wheel, xs, w, win, y, ys)
        if not next_window(w, grid, it, (h, y, dy, win), q, finder):
            break
    refined = grid.refine and w[5] == 0.0
    ends[0] = w[2] - w[4] if refined else math.nan
    ends[1] = w[2] + w[4] if refined else math.nan
    ends[2] = 0.0
    for j in range(n):
        q[0, j] += w[0]
    return dy


#: fields of a patch's lateral window while its strips are laid (:func:`lateral_window`,
#: a float array): x_c, d [m] (the gap sampled at x_c + (0, -d, +d)), y_c, the
#: half-width, the half-width of the extent [m], and 1 while the window is still to be
#: laid again on the run's ends (:attr:`StripGrid.refine`), else 0
LATERAL_FIELDS = ("x_c", "d", "y_c", "half_width", "core", "refine")


@njit(cache=True, nogil=True)
def lateral_window(win, grid):
    """A patch's first lateral window (:data:`LATERAL_FIELDS`) from its window
    ``win`` (:data:`WINDOW_FIELDS`) and the :class:`StripGrid` ``grid``
    (:func:`window_of`)."""
    w = np.empty(len(LATERAL_FIELDS))
    w[0], w[1], w[2], w[3], w[4] = window_of(win, grid.margin)
    w[5] = 1.0 if grid.refine else 0.0
    return w


@njit(cache=True, nogil=True)
def lay_strips(w, y):
    """The strips' centres [m] across the lateral window ``w``
    (:data:`LATERAL_FIELDS`) into ``y``; returns their width [m]."""
    n = y.size
    for j in range(n):
        y[j] = w[2] + w[3] * (-1.0 + (2.0 * j + 1.0) / n)
    return 2.0 * w[3] / n


@njit(cache=True, nogil=True)
def _gap_ends(ends, y, q, dy, win):
    """The lateral ends [m] of a patch's run of interpenetrating strips (``q`` of
    :func:`strip_lines`, the strips at ``y``, width ``dy``) where the strip
    quantity g crosses the penetration, found on the gap of the geometry layer
    itself (``ends`` = (frame, sign, rail, wheel, xs), :func:`_run_end`)."""
    F, sign, rail, wheel, xs = ends
    lo, hi = y.size, -1
    for j in range(y.size):
        if q[1, j] < win[1]:
            lo = min(lo, j)
            hi = max(hi, j)
    y_lo = _run_end(F, sign, rail, wheel, xs, (y[lo], q[1, lo] - win[1]), y[lo] - dy, win)
    y_hi = _run_end(F, sign, rail, wheel, xs, (y[hi], q[1, hi] - win[1]), y[hi] + dy, win)
    return y_lo, y_hi


@njit(cache=True, nogil=True)
def next_window(w, grid, it, lines, q, ends):
    """One pass of a patch's strips and its next lateral window: the strip
    quantities into ``q`` (:func:`strip_lines`) from ``lines`` = (h, y, dy, win),
    the gap h sampled on the strips at y [m] (width dy [m]) laid across the
    lateral window ``w`` (:data:`LATERAL_FIELDS`, changed in place; ``win``:
    :data:`WINDOW_FIELDS`) in pass ``it``.  The window is laid again on the run's
    ends, widened by ``grid.margin`` (:class:`StripGrid`), on the first pass that
    finds the run inside it where ``grid.refine``; widened x 1.6 while the run
    reaches an outer strip, ``grid.widen`` times at the most.  ``ends`` selects
    how the run's ends are found: None, interpolated between the strips
    (:func:`strip_lines`); (frame, sign, rail, wheel, xs) of the geometry layer,
    on the gap itself (:func:`_gap_ends`).  Returns whether to lay the strips
    again."""
    h, y, dy, win = lines
    edge, y_lo, y_hi = strip_lines(h, y, w[1], dy, win[1], (w[2], w[4]), q)
    if w[5] != 0.0 and not edge and y_hi > y_lo:
        # the strips again, on the run's ends: their positions relative to the
        # contact's edges, and with them the strip sums, continuous in the gap
        if ends is not None:
            y_lo, y_hi = _gap_ends(ends, y, q, dy, win)
        w[2], w[4] = 0.5 * (y_lo + y_hi), 0.5 * (y_hi - y_lo)
        w[3] = w[4] * (1.0 + grid.margin)
        w[5] = 0.0
        return True
    if not edge or it == grid.widen:
        return False
    w[3] *= 1.6
    return True


@njit(cache=True, nogil=True)
def _frames_geometry(frames, signs, rail, wheel, wins, grid, y, q, dy):
    for k in range(frames.shape[0]):
        dy[k] = strip_window_geometry(frames[k], signs[k], rail, wheel, wins[k], grid, y[k],
                                      q[k])


def strip_geometry(patches, strips: int = 40, penetration=None, margin: float = 0.15,
                   widen: int = 4):
    """Strip quantities of many patches from their exact gaps.

    Returns ``y`` (patches, strips) [m], ``dy`` (patches,), ``x_m``, ``g`` (the
    smallest gap + approach per strip, ~0 at the deepest point), ``A``, ``B``
    [1/m].  The lateral window covers the interpenetration region of each patch
    at ``penetration`` [m] (default: the geometry's approach), from the geometry's
    extent, widened (x 1.6, up to ``widen`` times) until the outer strips are
    free.  The patch is the run of interpenetrating strips through the deepest
    strip within the extent; strips outside it get g = penetration + 1 m (no
    contact).  Patches of the geometry layer run in one compiled loop per profile
    pair (:func:`strip_window_geometry`, the compiled case's kernel); others
    (bodies cases) sample their ``gap`` and share :func:`strip_lines`.
    """
    n = len(patches)
    if strips < 5:
        raise InputError(f"strips {strips!r}: expected at least 5")
    app = np.array([p.approach for p in patches], float)
    pen = app if penetration is None else np.asarray(penetration, float)
    A0 = np.array([max(p.curvatures[0], MIN_CURVATURE) for p in patches], float)
    B0 = np.array([max(p.curvatures[1], MIN_CURVATURE) for p in patches], float)
    ext = np.array([p.extent if p.extent is not None else (0.0, 0.0, 0.0, 0.0)
                    for p in patches], float).reshape(n, 4)
    wins = np.ascontiguousarray(np.column_stack([app, np.broadcast_to(pen, (n,)), A0, B0,
                                                 ext]))
    grid = StripGrid(int(strips), float(margin), int(widen))
    y = np.empty((n, strips))
    q = np.empty((n, 4, strips))
    dy = np.empty(n)
    groups, others = profile_groups(patches)
    for k in others:
        dy[k] = _sampled_geometry(patches[k], wins[k], grid, y[k], q[k])
    for idx in groups:
        f0 = patches[idx[0]].gap_function
        frames = np.array([patches[k].gap_function.frame for k in idx])
        signs = np.array([patches[k].gap_function.sign for k in idx], float)
        yk, qk, dk = y[idx], q[idx], dy[idx]
        _frames_geometry(frames, signs, Spline(f0.rail._breaks, f0.rail._coefs),
                         Spline(f0.wheel._breaks, f0.wheel._coefs), wins[idx], grid, yk, qk,
                         dk)
        y[idx], q[idx], dy[idx] = yk, qk, dk
    return y, dy, q[:, 0], q[:, 1], q[:, 2], q[:, 3]


def _sampled_geometry(patch, win, grid, y, q):
    """:func:`strip_window_geometry` of a patch whose gap is a Python function (a
    bodies case): its ``gap`` sampled, :func:`strip_lines` on the samples."""
    w = lateral_window(win, grid)
    dy = 0.0
    for it in range(grid.widen + 2):
        dy = lay_strips(w, y)
        h = np.ascontiguousarray(patch.gap(w[0] + w[1] * np.array([0.0, -1.0, 1.0])[:, None],
                                           y[None, :]), dtype=float) + win[0]
        if not next_window(w, grid, it, (h, y, dy, win), q, None):
            break
    q[0] += w[0]
    return dy


def patch_hertz_ellipses(patches, contact_modulus: float, penetration):
    """Hertz's semi-axes a, b [m] and forces [N] of many patches at the
    penetrations [m]: the force with each patch's ``force_curvature`` where it has
    one (:mod:`railcontact.geometry.patch_curvature`), the ellipse with its
    curvatures scaled to that force (a, b ~ F^(1/3)), as
    :func:`railcontact.cases.compiled_case.patch_hertz` and
    :class:`railcontact.normal.hertz.Hertz` have it."""
    n = len(patches)
    A = np.fromiter((p.curvatures[0] for p in patches), float, n)
    B = np.fromiter((p.curvatures[1] for p in patches), float, n)
    a, b, F = hertz_ellipses(A, B, contact_modulus, penetration)
    Bf = np.fromiter((getattr(p, "force_curvature", None) or B[i] for i, p in
                      enumerate(patches)), float, n)
    Bf = np.where(Bf > 0.0, Bf, B)
    if np.any(Bf != B):
        _, _, Fs = hertz_ellipses(A, Bf, contact_modulus, penetration)
        both = (F > 0) & (Fs > 0)
        with np.errstate(divide="ignore", invalid="ignore"):
            scale = np.where(both, np.cbrt(Fs / F), 1.0)
        a, b, F = a * scale, b * scale, np.where(both, Fs, F)
    return a, b, F


def hertz_ellipse_strips(patches, contact_modulus: float, strips: int = 40) -> StripSolution:
    """Hertz's ellipses of many patches (at the geometry's approach) cut in
    ``strips`` strips across: strip j at y_j has half-length a sqrt(1 - (y_j/b)^2)
    and peak pressure p0 sqrt(1 - (y_j/b)^2), scaled so that the strips carry the
    Hertz force exactly; for the strip creep laws (``fastrip``) on Hertz patches."""
    patches = list(patches)
    n = len(patches)
    A = np.fromiter((p.curvatures[0] for p in patches), float, n)
    B = np.fromiter((p.curvatures[1] for p in patches), float, n)
    pen = np.maximum(np.fromiter((p.approach for p in patches), float, n), 0.0)
    a, b, F = patch_hertz_ellipses(patches, contact_modulus, pen)
    u = -1.0 + (2.0 * np.arange(strips) + 1.0) / strips
    r = np.sqrt(1.0 - u * u)[None, :]
    y = b[:, None] * u[None, :]
    dy = 2.0 * b / strips
    half = a[:, None] * r
    with np.errstate(divide="ignore", invalid="ignore"):
        p0 = np.where(F > 0, F / (0.5 * math.pi * a * dy * np.sum(r * r)), 0.0)
    return StripSolution(y, dy, np.zeros_like(y), half, p0[:, None] * r, pen,
                         np.broadcast_to(A[:, None], y.shape),
                         np.broadcast_to(B[:, None], y.shape), semi_axes=(a, b))


def solve_strips(model: str, patches, contact_modulus: float, penetration=None,
                 strips: int = 40, elements: int = 20, eps: float = 0.55) -> StripSolution:
    """One strip model on many patches at given approaches.

    Parameters
    ----------
    model : {"kik-piotrowski", "kpec", "stripes", "analyn"}
    patches : sequence of ContactGeometry
    contact_modulus : float
        E* [Pa].
    penetration : array_like, optional
        Approach per patch [m]; default the geometry's approach.
    strips : int
        Strips across each patch's interpenetration region.
    elements : int
        Elements per strip for Kik-Piotrowski's displacement sum.
    eps : float
        Kik-Piotrowski's scaling factor.
    """
    if model not in STRIP_MODELS:
        raise InputError(f"batch strip model {model!r}: expected one of {', '.join(STRIP_MODELS)}")
    patches = list(patches)
    if not patches:
        raise InputError("solve_strips: no patches given")
    pen = (np.array([p.approach for p in patches], float) if penetration is None
           else np.broadcast_to(np.asarray(penetration, float), (len(patches),)).copy())
    if not np.all(np.isfinite(pen)) or np.any(pen < 0):
        raise InputError("penetration: expected finite values >= 0 m")
    y, dy, xm, g, A, B = strip_geometry(patches, strips, pen)
    half, pm = strip_pressures(model, y, dy, xm, g - pen[:, None], A, B, contact_modulus,
                               eps=eps, elements=elements)
    return StripSolution(y, dy, xm, half, pm, pen, A, B)
