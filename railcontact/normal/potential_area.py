"""The potential contact area of the exact normal model: where a patch's grid lies
and how it grows.

The gap of a patch on its own part of the tangent plane (:func:`own_gap`, the other
regions of its wheel raised out of reach), the sub-regions of a combined patch
(:func:`subregions`), the sides where a contact reaches the grid's edge and the
grown box (:func:`grown_box`), whether a previous solution's grid fits a new
problem (:func:`fits`), and the strip edges of a contact mask.
"""

from __future__ import annotations


import numpy as np
from numba import njit

from .influence import box_bounds



@njit(cache=True, nogil=True)
def strip_edges(contact, x):
    """Leading and trailing edges [m] of the contact in each strip (column of the
    mask; element centres ``x`` plus half an element), zero in strips without
    contact."""
    mx, my = contact.shape
    half = 0.5 * (x[1] - x[0]) if mx > 1 else 0.0
    lead = np.zeros(my)
    trail = np.zeros(my)
    for j in range(my):
        first = -1
        last = -1
        for i in range(mx):
            if contact[i, j]:
                if first < 0:
                    first = i
                last = i
        if first >= 0:
            lead[j] = x[last] + half
            trail[j] = x[first] - half
    return lead, trail



@njit(cache=True, nogil=True)
def inside_bounds(h, foreign):
    """First and last row, first and last column of the elements of the gap ``h``
    (rows x, columns y) that overlap (h < 0) in a column that is not ``foreign``
    (bool, one per column); -1 each where none does."""
    mask = np.zeros(h.shape, dtype=np.bool_)
    for i in range(h.shape[0]):
        for j in range(h.shape[1]):
            mask[i, j] = h[i, j] < 0 and not foreign[j]
    return box_bounds(mask)



@njit(cache=True, nogil=True)
def _zero_between(s0, s1, g0, g1):
    """Where g crosses zero between the samples s0 (g0) and s1 (g1), linearly."""
    return s0 + (s1 - s0) * g0 / (g0 - g1)



def crossings(s, g, i0, i1):
    """Where g (negative from index i0 to i1, positive just outside) crosses zero on
    either side, linearly interpolated between the samples s."""
    return (_zero_between(s[i0 - 1], s[i0], g[i0 - 1], g[i0]),
            _zero_between(s[i1], s[i1 + 1], g[i1], g[i1 + 1]))



@njit(cache=True, nogil=True)
def _row_min(h, i, rows):
    """The smallest of row ``i`` of h (``rows``) or of its column i (NaN where one
    is NaN, as ``ndarray.min``)."""
    n = h.shape[1] if rows else h.shape[0]
    m = h[i, 0] if rows else h[0, i]
    for k in range(1, n):
        v = h[i, k] if rows else h[k, i]
        if v != v:
            return v
        if v < m:
            m = v
    return m



@njit(cache=True, nogil=True)
def region_ends(xs, ys, h, i0, i1, j0, j1):
    """The ends (lo_x, hi_x, lo_y, hi_y) [m] of the region where the gap h on the
    lines ``xs``, ``ys`` is negative (rows i0 to i1, columns j0 to j1, inside the
    lines): where the smallest gap along the other axis crosses zero,
    :func:`crossings` of ``h.min(axis=1)`` and ``h.min(axis=0)``, those minima
    taken on the four rows and columns the crossings read."""
    return (_zero_between(xs[i0 - 1], xs[i0], _row_min(h, i0 - 1, True), _row_min(h, i0, True)),
            _zero_between(xs[i1], xs[i1 + 1], _row_min(h, i1, True), _row_min(h, i1 + 1, True)),
            _zero_between(ys[j0 - 1], ys[j0], _row_min(h, j0 - 1, False),
                          _row_min(h, j0, False)),
            _zero_between(ys[j1], ys[j1 + 1], _row_min(h, j1, False),
                          _row_min(h, j1 + 1, False)))



@njit(cache=True, nogil=True)
def coarse_lines(c, half):
    """``AREA_SAMPLES`` lines from c - 2 half to c + 2 half [m], as
    ``c + np.linspace(-2 * half, 2 * half, AREA_SAMPLES)`` gives them (the same
    arithmetic: i * step + start, the last at the end)."""
    n = AREA_SAMPLES
    start, stop = -2 * half, 2 * half
    step = (stop - start) / (n - 1)
    out = np.empty(n)
    for i in range(n - 1):
        out[i] = c + (i * step + start)
    out[n - 1] = c + stop
    return out



#: samples per direction of the gap over twice the patch's extent each side, from
#: which the potential contact area is found (:meth:`ExactNormalModel._area_from_gap`)
AREA_SAMPLES = 49



#: with the force given, the pressure iteration runs on the box of the region where
#: the undeformed distance is below this many times the search's approach (and
#: again on the whole grid where the solved approach exceeds that)
FORCE_BOX = 1.2



#: a grid is reused (``ExactNormalModel.solve(reuse_grid=...)``) while the potential
#: contact area spans at least this fraction of it in each direction
REUSE_FILL = 0.8



#: ... and reaches beyond it by at most this fraction of its half-widths (the
#: potential area is the interpenetration region widened by the margin, so the
#: contact stays well inside): a grid is built to fit its potential area exactly
#: (docs/tuning.md, section "Normal: exact")
REUSE_OVERHANG = 0.02



def subregions(geometry, y):
    """(cols, factors) of a combined patch whose sub-regions interact reduced
    (``geometry.interaction``: the sub-regions' borders [m] in patch coordinate y
    and the factor across each), for the grid columns ``y``; None where the grid's
    columns interact fully.  Sub-regions a < b interact with the product of the
    factors across the borders between them."""
    inter = geometry.interaction
    if not inter or all(f == 1.0 for _, f in inter):
        return None
    borders = np.array([b for b, _ in inter])
    cols = np.searchsorted(borders, np.asarray(y, dtype=float)).astype(np.int64)
    k = len(inter) + 1
    fm = np.ones((k, k))
    for a in range(k):
        for b in range(a + 1, k):
            fm[a, b] = fm[b, a] = float(np.prod([f for _, f in inter[a:b]]))
    return cols, fm



def cut_regions(regions, cols):
    """``regions`` of :func:`subregions` for the columns ``cols`` (a slice) of the
    grid."""
    if regions is None:
        return None
    c = regions[0][cols]
    return None if c.size == 0 or c.min() == c.max() else (c, regions[1])



def own_gap(geometry, x, y) -> np.ndarray:
    """The undeformed distance [m] on the grid lines ``x``, ``y`` of a patch, raised
    outside the patch's own band (``geometry.bounds``) to its largest value inside:
    a grid reaching into a neighbouring patch's interpenetration region would
    otherwise load it a second time (the raised gap keeps the iteration's gap scale)."""
    h = geometry.gap(x[:, None], y[None, :])
    out = geometry.foreign(y)
    if out.any():
        h[:, out] = h[:, ~out].max() if not out.all() else 1.0
    return h



#: how often :meth:`ExactNormalModel.solve` enlarges a potential contact area that the
#: contact reaches the edge of
GROWTH_STEPS = 3



def edge_sides(contact):
    """Which sides of the grid (x low, x high, y low, y high) the contact reaches."""
    return _edge_sides(np.ascontiguousarray(contact, dtype=np.bool_))


@njit(cache=True, nogil=True)
def _edge_sides(contact):
    """:func:`edge_sides`, compiled."""
    mx, my = contact.shape
    lo_x = hi_x = lo_y = hi_y = False
    for j in range(my):
        lo_x = lo_x or contact[0, j]
        hi_x = hi_x or contact[mx - 1, j]
    for i in range(mx):
        lo_y = lo_y or contact[i, 0]
        hi_y = hi_y or contact[i, my - 1]
    return lo_x, hi_x, lo_y, hi_y



def plausible_growth(before, after, displacement: bool) -> bool:
    """Whether the solution on an enlarged potential area continues the truncated
    one: with the approach given, the force grows by at most a factor 2 (the
    truncated contact held most of it); with the force given, the approach falls
    and stays above a fifth of the truncated one."""
    if displacement:
        return after.normal_force <= 2.0 * before.normal_force + 1e-12
    return 0.2 * before.penetration <= after.penetration <= before.penetration * (1 + 1e-6)



def grown_box(x, y, sides):
    """Centre and half-extents [m] of the potential area of the grid lines x, y
    enlarged by half its width on each of the ``sides`` (x low, x high, y low, y
    high) the contact reaches."""
    dx, dy = x[1] - x[0], y[1] - y[0]
    lo_x, hi_x = x[0] - 0.5 * dx, x[-1] + 0.5 * dx
    lo_y, hi_y = y[0] - 0.5 * dy, y[-1] + 0.5 * dy
    wx, wy = hi_x - lo_x, hi_y - lo_y
    lo_x -= 0.5 * wx * sides[0]
    hi_x += 0.5 * wx * sides[1]
    lo_y -= 0.5 * wy * sides[2]
    hi_y += 0.5 * wy * sides[3]
    return ((0.5 * (lo_x + hi_x), 0.5 * (lo_y + hi_y)), (0.5 * (hi_x - lo_x), 0.5 * (hi_y - lo_y)))



def fits(sol, cx, cy, ex, ey, grid) -> bool:
    """Whether the potential area [cx - ex, cx + ex] x [cy - ey, cy + ey] lies in the
    grid of the solution ``sol`` and fills at least REUSE_FILL of it (and the grid has
    the requested number of elements)."""
    x, y = sol.x, sol.y
    if x.size < 2 or y.size < 2:
        return False
    if grid is not None and tuple(int(g) for g in grid) != (x.size, y.size):
        return False
    hx = 0.5 * (x[-1] - x[0]) + 0.5 * (x[1] - x[0])      # half-widths over the elements
    hy = 0.5 * (y[-1] - y[0]) + 0.5 * (y[1] - y[0])
    mx, my = 0.5 * (x[0] + x[-1]), 0.5 * (y[0] + y[-1])
    f = 1.0 + REUSE_OVERHANG
    inside = abs(cx - mx) + ex <= f * hx and abs(cy - my) + ey <= f * hy
    return bool(inside and ex >= REUSE_FILL * hx and ey >= REUSE_FILL * hy)
