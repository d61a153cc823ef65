"""Exact (boundary-element) normal contact: ``normal="exact"``.

Kalker's variational formulation of the normal problem for two identical elastic
half-spaces (Kalker 1990, ch. 2 and 5): on a grid of mx x my equal rectangles with
piecewise-constant pressure p, find p >= 0 with the deformed distance
e = h + A p - delta >= 0 and p e = 0, where h is the undeformed distance (from the
geometry layer's exact gap function), A the influence matrix of uniform pressures on
rectangles (:mod:`railcontact.normal.influence`) and delta the approach.

Solver: the constrained conjugate-gradient method of Polonsky & Keer (Wear 231,
1999), in its force-controlled form (the mean gap over the contact area is the
unknown approach) or displacement-controlled form (approach given).  Matrix-vector
products are FFT convolutions, so the cost per iteration is O(N log N); with the
approach given they run on the bounding box of the overlap h < delta, which holds
the contact.  A solution that does not reach the tolerance is flagged
(``converged=False``) and logged.
"""

from __future__ import annotations

import logging
import math
import time

import numpy as np
from numba import njit

from ..errors import InputError
from ..materials import STEEL, Material
from ..status import SolverStatus
from .base import NormalSolution, bilinear, make_grid, register, same_grid
from ..hertz_theory import hertz_ellipse
from .influence import bounding_box, normal_operator, normal_operator_block

log = logging.getLogger(__name__)


def polonsky_keer(op, h, dA, force=None, tol=1e-9, maxiter=2000, p0=None, scale=None,
                  regions=None, pressure_limit=math.inf):
    """Solve the discrete normal contact problem.

    Parameters
    ----------
    op : Convolution   p -> A p [m]
    h : ndarray        undeformed distance [m]; for a given approach delta pass
                       h - delta and ``force=None``
    dA : float         element area [m^2]
    force : float      total force [N] (force-controlled), or None
    scale : float      gap scale [m] of the convergence test (default max |h|)
    regions : (cols, factors), optional
                       reduced interaction between the sub-regions of a combined
                       patch: ``cols`` (int, one per grid column) the sub-region of
                       each column, ``factors`` (k x k) the factor on the
                       displacements that a sub-region's pressure causes in another
                       (1 on the diagonal; :func:`railcontact.geometry.contact.interaction_factor`)
    pressure_limit : float
                       upper bound [Pa] of the pressure (elastic-perfectly-plastic
                       contact, :mod:`railcontact.normal.plasticity`; default inf:
                       elastic); with the approach given only (``force=None``)

    Returns
    -------
    p [Pa], approach [m] (force-controlled; else 0), iterations, converged

    The iteration runs compiled (:func:`_pk_kernel`), its FFT products by
    rocket-fft's ``numpy.fft`` for Numba.
    """
    h = np.ascontiguousarray(h, dtype=float)
    plimit = float(pressure_limit)
    if not plimit > 0:
        raise InputError(f"pressure limit {pressure_limit!r} Pa: expected a value > 0")
    if force is not None and math.isfinite(plimit):
        raise InputError("a pressure limit needs the approach given (force=None): the "
                         "force-controlled iteration scales the pressure as a whole")
    if p0 is None:
        if force is not None:
            p = np.where(h <= np.min(h) + 0.5 * (np.median(h) - np.min(h)), 1.0, 0.0)
            p *= force / (p.sum() * dA)
        else:
            p = np.maximum(-h, 0.0) / op.diag * 0.5
    else:
        p = np.array(p0, dtype=float)
    p = np.ascontiguousarray(np.minimum(p, plimit))
    scale = float(np.max(np.abs(h))) if scale is None else float(scale)
    if regions is None:
        cols, fm = np.zeros(h.shape[1], dtype=np.int64), np.ones((1, 1))
    else:
        cols = np.ascontiguousarray(regions[0], dtype=np.int64)
        fm = np.ascontiguousarray(regions[1], dtype=float)
        if cols.shape != (h.shape[1],) or fm.shape != (fm.shape[0], fm.shape[0]) \
                or cols.min() < 0 or cols.max() >= fm.shape[0]:
            raise InputError(f"regions: expected one sub-region index per grid column "
                             f"({h.shape[1]}) and a square factor matrix covering them")
    gbar, it, converged = _pk_kernel(op.khat, op.shape, h, float(dA),
                                     0.0 if force is None else float(force), force is not None,
                                     float(tol), int(maxiter), p, scale, op.kernel, cols, fm,
                                     plimit)
    approach = gbar if force is not None else 0.0
    return p, approach, int(it), bool(converged)


@njit(cache=True, nogil=True)
def _convolve(p, khat, shape, buf):
    """A p by a zero-padded real FFT (``buf``: the padded work array, zero outside
    the grid of p)."""
    mx, my = p.shape
    buf[:mx, :my] = p
    f = np.fft.rfft2(buf)
    f *= khat
    return np.fft.irfft2(f, s=shape)[:mx, :my]


@njit(cache=True, nogil=True)
def _apply(p, khat, shape, buf, cols, fm):
    """A p, with the displacements that one sub-region's pressure causes in another
    scaled by ``fm`` (one convolution per sub-region; the plain product where the
    patch is one region)."""
    k = fm.shape[0]
    if k == 1:
        return _convolve(p, khat, shape, buf)
    mx, my = p.shape
    u = np.zeros((mx, my))
    q = np.zeros((mx, my))
    for a in range(k):
        for j in range(my):
            for i in range(mx):
                q[i, j] = p[i, j] if cols[j] == a else 0.0
        ua = _convolve(q, khat, shape, buf)
        for j in range(my):
            f = fm[a, cols[j]]
            for i in range(mx):
                u[i, j] += f * ua[i, j]
    return u


@njit(cache=True, nogil=True)
def _mean_on(a, S):
    """Mean of a over the elements where S is true (at least one)."""
    s = 0.0
    n = 0
    for i in range(a.shape[0]):
        for j in range(a.shape[1]):
            if S[i, j]:
                s += a[i, j]
                n += 1
    return s / n


@njit(cache=True, nogil=True)
def _add_direct(u, f, idx, dq, kernel, cols, fm):
    """u += f A dq for dq nonzero only at the flat indices ``idx`` (values ``dq``):
    each element's displacements summed directly from the kernel (offsets centred
    at (kernel rows - 1) / 2), scaled between sub-regions as in :func:`_apply`."""
    mx, my = u.shape
    ci = (kernel.shape[0] - 1) // 2
    cj = (kernel.shape[1] - 1) // 2
    one = fm.shape[0] == 1
    for k in range(idx.size):
        i0 = idx[k] // my
        j0 = idx[k] % my
        a = f * dq[k]
        if one:
            for i in range(mx):
                row = ci + i - i0
                for j in range(my):
                    u[i, j] += a * kernel[row, cj + j - j0]
        else:
            for i in range(mx):
                row = ci + i - i0
                for j in range(my):
                    u[i, j] += a * fm[cols[j0], cols[j]] * kernel[row, cj + j - j0]


#: Polonsky-Keer updates the displacements of a step directly (from the kernel) where
#: at most this fraction of the elements were clipped or loaded, else by an FFT
DIRECT_FRACTION = 0.02


@njit(cache=True, nogil=True)
def _pk_kernel(khat, shape, h, dA, force, controlled, tol, maxiter, p, scale, kernel, cols,
               fm, plimit):
    """Constrained conjugate gradients of Polonsky & Keer on the pressure ``p``
    (the initial estimate, overwritten with the solution).

    Conjugate directions on the set S of loaded elements; an element whose pressure
    would turn negative is set to zero, an unloaded element with a negative gap
    (an overlap) is loaded and the directions restart.  Force-controlled: the
    approach is the mean gap over S and the pressure is scaled to the force.
    After a step A p = f (A p_old - tau A t + A d), with f the force scaling (1
    displacement-controlled) and d the changes of the clipped and loaded elements:
    A d summed directly where they are few (``DIRECT_FRACTION`` of the elements),
    else A p by a convolution; refreshed by a convolution every 10 steps.
    ``cols``, ``fm``: sub-regions of the columns and their interaction factors
    (:func:`_apply`; one region: the plain operator).
    ``plimit``: the upper bound of the pressure (inf: elastic).  An element that
    reaches the limit is clipped to it (it may overlap: plastic flow) and leaves
    the directions; an element at the limit whose gap opens joins them again (it
    may unload; the directions restart), so that at the solution p = 0 with a gap,
    0 < p < limit without one, or p = limit with an overlap.  Only with the
    approach given (``controlled`` False).
    Returns the approach (mean gap, force-controlled), iterations, converged.
    """
    mx, my = h.shape
    buf = np.zeros(shape)
    t = np.zeros((mx, my))
    u = np.zeros((mx, my))
    g = np.zeros((mx, my))
    pn = np.zeros((mx, my))
    S = np.zeros((mx, my), dtype=np.bool_)
    Sp = np.zeros((mx, my), dtype=np.bool_)    # the last iteration's S
    limit = int(DIRECT_FRACTION * mx * my)
    idx = np.zeros(limit + 1, dtype=np.int64)  # the elements clipped or loaded
    dq = np.zeros(limit + 1)                   # and their changes beyond -tau t
    scale = max(scale, 1e-12)
    G_old = 1.0
    restart = True
    converged = False
    gbar = 0.0
    fresh = 0
    valid = False
    it = 0
    for it in range(1, maxiter + 1):
        if not valid or fresh >= 10:
            u[:, :] = _apply(p, khat, shape, buf, cols, fm)
            fresh = 0
        nS = 0
        for i in range(mx):
            for j in range(my):
                g[i, j] = u[i, j] + h[i, j]
                # an element at the limit whose gap opens joins the directions
                # (it may unload), as an element between the bounds
                at = p[i, j] >= plimit
                S[i, j] = (0.0 < p[i, j] and not at) or (at and g[i, j] > 0.0)
                if at and S[i, j] and not Sp[i, j]:
                    restart = True
                nS += S[i, j]
        if nS == 0:
            # no free element: the solution where no element at zero overlaps and
            # none at the limit has a gap; else start from the deepest free overlap
            gmin = np.inf
            kkt = True
            for i in range(mx):
                for j in range(my):
                    if p[i, j] < plimit:
                        gmin = min(gmin, g[i, j])
                        kkt = kkt and g[i, j] >= 0.0
                    else:
                        kkt = kkt and g[i, j] <= 0.0
            if not controlled and kkt:
                converged = True             # e.g. no overlap anywhere: p = 0
                break
            for i in range(mx):
                for j in range(my):
                    S[i, j] = p[i, j] < plimit and g[i, j] <= gmin + 1e-15
                    nS += S[i, j]
        if controlled:
            gbar = _mean_on(g, S)
            g -= gbar
        G = 0.0
        for i in range(mx):
            for j in range(my):
                if S[i, j]:
                    G += g[i, j] * g[i, j]
        Sp[:, :] = S
        beta = 0.0 if restart else G / G_old
        for i in range(mx):
            for j in range(my):
                t[i, j] = g[i, j] + beta * t[i, j] if S[i, j] else 0.0
        G_old = G
        r = _apply(t, khat, shape, buf, cols, fm)
        rbar = 0.0
        if controlled:
            rbar = _mean_on(r, S)
            r -= rbar
        den = 0.0
        num = 0.0
        for i in range(mx):
            for j in range(my):
                if S[i, j]:
                    den += r[i, j] * t[i, j]
                    num += g[i, j] * t[i, j]
        if den == 0.0:
            converged = True
            break
        tau = num / den
        restart = False
        total = 0.0
        nd = 0                                  # elements clipped or loaded
        for i in range(mx):
            for j in range(my):
                q0 = p[i, j] - tau * t[i, j]
                q = q0
                if q < 0.0:
                    q = 0.0                     # clipped
                elif q > plimit:
                    q = plimit                  # clipped at the limit: plastic
                if q == 0.0 and g[i, j] < 0.0:
                    q = min(-tau * g[i, j], plimit)  # an overlap: load the element
                    restart = True
                if q != q0:
                    if nd < limit:
                        idx[nd] = i * my + j
                        dq[nd] = q - q0
                    nd += 1
                total += q
                pn[i, j] = q
        f = force / (total * dA) if controlled and total > 0.0 else 1.0
        diff = 0.0
        ref = 0.0
        for i in range(mx):
            for j in range(my):
                q = pn[i, j] * f
                diff += abs(q - p[i, j])
                ref += q
                p[i, j] = q
        if nd <= limit:
            # p changed by -tau t (then scaled by f) and by dq on the few elements
            # clipped or loaded: A p follows from A t, the product before the mean
            # was taken off, and the direct sum of those elements' displacements
            # (refreshed every 10 steps)
            for i in range(mx):
                for j in range(my):
                    u[i, j] = f * (u[i, j] - tau * (r[i, j] + rbar))
            _add_direct(u, f, idx[:nd], dq[:nd], kernel, cols, fm)
            fresh += 1
            valid = True
        else:
            valid = False
        ref = max(ref, 1e-300)
        if diff / ref < tol and G <= (tol * scale) ** 2 * max(nS, 1):
            converged = True
            break
    return gbar, it, converged


@njit(cache=True, nogil=True)
def _strip_edges(contact, x):
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


def _crossings(s, g, i0, i1):
    """Where g (negative from index i0 to i1, positive just outside) crosses zero on
    either side, linearly interpolated between the samples s."""
    lo = s[i0 - 1] + (s[i0] - s[i0 - 1]) * g[i0 - 1] / (g[i0 - 1] - g[i0])
    hi = s[i1] + (s[i1 + 1] - s[i1]) * g[i1] / (g[i1] - g[i1 + 1])
    return lo, hi


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
#: contact stays well inside): a grid is built to fit its potential area exactly,
#: and the next pass's area, after the small change of the approach, overhangs it
#: by a median 0.08 %
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


def _cut(regions, cols):
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


def _edge_sides(contact):
    """Which sides of the grid (x low, x high, y low, y high) the contact reaches."""
    return (contact[0, :].any(), contact[-1, :].any(), contact[:, 0].any(),
            contact[:, -1].any())


def _plausible_growth(before, after, displacement: bool) -> bool:
    """Whether the solution on an enlarged potential area continues the truncated
    one: with the approach given, the force grows by at most a factor 2 (the
    truncated contact held most of it); with the force given, the approach falls
    and stays above a fifth of the truncated one."""
    if displacement:
        return after.normal_force <= 2.0 * before.normal_force + 1e-12
    return 0.2 * before.penetration <= after.penetration <= before.penetration * (1 + 1e-6)


def _grown_box(x, y, sides):
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


def _fits(sol, cx, cy, ex, ey, grid) -> bool:
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


@register("exact")
class ExactNormalModel:
    """Kalker's exact theory of the normal contact problem on a boundary-element grid.

    Parameters
    ----------
    tol : float        relative tolerance of the pressure iteration (default 1e-5: the
                       pressure's relative change per iteration, and the rms gap on
                       the contact area relative to the gap's range); on S1002/60E1
                       patches on 40 x 40 grids the force is then within 2e-6 and
                       the pressure within 1e-4 p_max of a 1e-10 solution
    maxiter : int      iteration limit
    margin : float     the potential contact area extends the expected contact by
                       this fraction on each side
    pressure_limit : float, optional
                       upper bound [Pa] of the pressure: elastic-perfectly-plastic
                       contact (:mod:`railcontact.normal.plasticity`, e.g.
                       ``pressure_limit(yield_stress)``); default none (elastic).
                       With the force given, the approach that carries it is
                       found by Brent's method on displacement-controlled solves.
    """

    def __init__(self, tol: float = 1e-5, maxiter: int = 3000, margin: float = 0.25,
                 pressure_limit: float | None = None):
        if not (0 < tol < 1e-2):
            raise InputError(f"exact tol {tol!r}: expected a value in (0, 0.01)")
        self.tol, self.maxiter, self.margin = tol, int(maxiter), margin
        if pressure_limit is None:
            pressure_limit = math.inf
        if isinstance(pressure_limit, bool) or not (isinstance(pressure_limit, (int, float))
                                                    and pressure_limit > 0):
            raise InputError(f"exact pressure_limit = {pressure_limit!r} Pa: expected a "
                             "pressure > 0 (or none: elastic)")
        self.pressure_limit = float(pressure_limit)

    def _potential_area(self, geometry, material, normal_force, penetration,
                        continuous=False):
        """Centre and half-extents [m] of the potential contact area."""
        ext = geometry.extent
        app = geometry.approach
        if ext is not None and app > 0 and geometry.gap_function is not None:
            return self._area_from_gap(geometry, penetration if penetration is not None
                                       else app, continuous)
        A, B = geometry.curvatures
        hz = hertz_ellipse(A, B, material.contact_modulus, force=normal_force,
                           penetration=penetration)
        f = 1.0 + self.margin
        return (0.0, 0.0), (hz.a * f, hz.b * f)

    def _area_from_gap(self, geometry, penetration, continuous=False):
        """Bounding box of the interpenetration region h + approach - penetration < 0
        (which contains the contact area), from a coarse sampling of the exact gap,
        widened by the margin.  ``continuous``: its ends interpolated between the
        samples, so that the box moves continuously with the penetration (the exact
        solver's contact lies in the region; the vertical-force iteration needs a
        force that is continuous in the approach); else one sample beyond the last
        sample inside."""
        x0, x1, y0, y1 = geometry.extent
        cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
        hx, hy = max(0.5 * (x1 - x0), 1e-4), max(0.5 * (y1 - y0), 1e-4)
        for _ in range(6):
            xs = cx + np.linspace(-2 * hx, 2 * hx, AREA_SAMPLES)
            ys = cy + np.linspace(-2 * hy, 2 * hy, AREA_SAMPLES)
            h = geometry.gap(xs[:, None], ys[None, :]) + geometry.approach - penetration
            inside = (h < 0) & ~geometry.foreign(ys)[None, :]
            if not inside.any():
                break
            ix = np.flatnonzero(inside.any(axis=1))
            iy = np.flatnonzero(inside.any(axis=0))
            if ix[0] == 0 or ix[-1] == xs.size - 1:
                hx *= 2
            if iy[0] == 0 or iy[-1] == ys.size - 1:
                hy *= 2
            if 0 < ix[0] and ix[-1] < xs.size - 1 and 0 < iy[0] and iy[-1] < ys.size - 1:
                dx, dy = xs[1] - xs[0], ys[1] - ys[0]
                if continuous:
                    return self._region_box(xs, ys, h, ix, iy, dx, dy)
                lo_x, hi_x = xs[ix[0]] - dx, xs[ix[-1]] + dx
                lo_y, hi_y = ys[iy[0]] - dy, ys[iy[-1]] + dy
                return self._widened(lo_x, hi_x, lo_y, hi_y)
        return (cx, cy), (hx * (1 + self.margin), hy * (1 + self.margin))

    def _region_box(self, xs, ys, h, ix, iy, sx, sy):
        """Potential area from the gap h on the lines xs, ys, negative on the rows ix
        and columns iy (inside the lines): the region's ends where the smallest gap
        along the other axis crosses zero, interpolated between the lines, plus 1.5
        coarse samples (sx, sy: where the first sample outside lies on average),
        widened by the margin.  Returns its centre and half-extents [m]."""
        lo_x, hi_x = _crossings(xs, h.min(axis=1), ix[0], ix[-1])
        lo_y, hi_y = _crossings(ys, h.min(axis=0), iy[0], iy[-1])
        return self._widened(lo_x - 1.5 * sx, hi_x + 1.5 * sx, lo_y - 1.5 * sy, hi_y + 1.5 * sy)

    def _widened(self, lo_x, hi_x, lo_y, hi_y):
        """Centre and half-extents [m] of a box widened by the margin."""
        f = 1.0 + self.margin
        return ((0.5 * (lo_x + hi_x), 0.5 * (lo_y + hi_y)),
                (0.5 * (hi_x - lo_x) * f, 0.5 * (hi_y - lo_y) * f))

    def _kept_grid_gap(self, geometry, penetration, sol, grid):
        """The undeformed distance on the grid of ``sol`` (an earlier pass of the same
        patch) where that grid is kept: the potential area of :meth:`_area_from_gap`,
        its ends found on this grid instead of the coarse samples (the same padding:
        1.5 coarse samples, then the margin), fits it by :func:`_fits`.  None where
        it does not, or where the interpenetration region reaches the grid's border
        (then the coarse sampling decides)."""
        app = geometry.approach
        if geometry.extent is None or geometry.gap_function is None or not app > 0:
            return None
        x, y = sol.x, sol.y
        if x.size < 3 or y.size < 3:
            return None
        h0 = own_gap(geometry, x, y) + app
        h = h0 - (app if penetration is None else penetration)
        box = bounding_box(h < 0)
        if box is None or box[0].start == 0 or box[0].stop == x.size or box[1].start == 0 \
                or box[1].stop == y.size:
            return None
        ix, iy = np.arange(x.size)[box[0]], np.arange(y.size)[box[1]]
        x0, x1, y0, y1 = geometry.extent
        sx = 4.0 * max(0.5 * (x1 - x0), 1e-4) / (AREA_SAMPLES - 1)   # the coarse spacing
        sy = 4.0 * max(0.5 * (y1 - y0), 1e-4) / (AREA_SAMPLES - 1)
        (cx, cy), (ex, ey) = self._region_box(x, y, h, ix, iy, sx, sy)
        return h0 if _fits(sol, cx, cy, ex, ey, grid) else None

    def _displacement_controlled(self, grid_key, h, dA, p0, regions=None):
        """Polonsky-Keer with the approach given, on the bounding box of the overlap
        h < 0: the contact lies in it (the displacements of a pressure are positive
        everywhere), so outside it the pressure is zero and the iteration is that on
        the whole grid, with smaller FFTs (the convergence test keeps the whole
        grid's gap scale).  Returns p on the grid, iterations, converged."""
        box = bounding_box(h < 0)
        if box is None:                     # no overlap: p = 0 (reported at once)
            p, _, it, ok = polonsky_keer(normal_operator(*grid_key), h, dA, None, self.tol,
                                         self.maxiter, p0=p0)
            return p, it, ok
        op = normal_operator_block(*grid_key, *h[box].shape)
        q, _, it, ok = polonsky_keer(op, h[box], dA, None, self.tol, self.maxiter,
                                     p0=None if p0 is None else p0[box],
                                     scale=float(np.max(np.abs(h))),
                                     regions=_cut(regions, box[1]),
                                     pressure_limit=self.pressure_limit)
        p = np.zeros(h.shape)
        p[box] = q
        return p, it, ok

    def _force_controlled(self, grid_key, h0, dA, force, p0, approach, regions=None):
        """Polonsky-Keer with the force given, on the bounding box of h0 <
        FORCE_BOX x ``approach`` (the search's approach): where the solved approach
        is below that, the contact, which lies where h0 is below the solved
        approach, is inside the box and the solution is that of the whole grid (as
        in :meth:`_displacement_controlled`); else the whole grid is solved, from
        the box's solution.  Returns p on the grid, approach, iterations, converged."""
        def scaled(q):              # a start carrying the force, or None
            if q is None or not q.max() > 0:
                return None
            return q * force / max(float(q.sum() * dA), 1e-300)

        scale = float(np.max(np.abs(h0)))
        box = bounding_box(h0 < FORCE_BOX * approach) if approach > 0 else None
        it0 = 0
        if box is not None:
            q0 = None if p0 is None else scaled(np.ascontiguousarray(p0[box]))
            q, app, it0, ok = polonsky_keer(normal_operator_block(*grid_key, *h0[box].shape),
                                            h0[box], dA, force=force, tol=self.tol,
                                            maxiter=self.maxiter, p0=q0, scale=scale,
                                            regions=_cut(regions, box[1]))
            p = np.zeros(h0.shape)
            p[box] = q
            if ok and app <= FORCE_BOX * approach:
                return p, app, it0, ok
            p0 = p if ok and p.max() > 0 else p0
        p, app, it, ok = polonsky_keer(normal_operator(*grid_key), h0, dA, force=force,
                                       tol=self.tol, maxiter=self.maxiter, p0=scaled(p0),
                                       scale=scale, regions=regions)
        return p, app, it0 + it, ok

    def _force_by_approach(self, grid_key, h0, dA, force, p0, regions=None):
        """Force-controlled solve with the pressure limit: the approach delta that
        carries ``force`` by Brent's method on displacement-controlled solves (each
        from the last solution), the force F(delta) being continuous and increasing.
        The bracket starts at the elastic approach, which carries less than the
        force once the pressure is capped.  Returns p, approach, iterations,
        converged."""
        from scipy.optimize import brentq

        limit = self.pressure_limit
        self.pressure_limit = math.inf
        try:
            p, app, it, ok = self._force_controlled(grid_key, h0, dA, force, p0, 0.0, regions)
        finally:
            self.pressure_limit = limit
        if not ok or p.max() <= limit:
            return p, app, it, ok                   # the elastic solution holds
        state = {"p": np.minimum(p, limit), "it": it, "ok": True}

        def excess(delta):
            q, k, good = self._displacement_controlled(grid_key, h0 - delta, dA, state["p"],
                                                       regions)
            state["it"] += k
            state["ok"] &= good
            if q.max() > 0:
                state["p"] = q
            return float(q.sum() * dA) / force - 1.0

        lo, hi = app, app * 1.25
        f_hi = excess(hi)
        while f_hi < 0.0:
            lo, hi = hi, hi * 1.5
            f_hi = excess(hi)
            if hi > 1e3 * app:
                return state["p"], hi, state["it"], False
        delta = brentq(excess, lo, hi, xtol=1e-10 * app, rtol=1e-12, maxiter=100)
        excess(delta)                      # the solution at the root (its pressure)
        return state["p"], delta, state["it"], state["ok"]

    def _plastic_extent(self, geometry, material, normal_force, ex, ey):
        """Half-extents of the potential area widened for a pressure limit below
        Hertz's peak: the contact then spreads to about force / limit (with its
        elastic rim), against Hertz's pi a b."""
        if normal_force is None or not math.isfinite(self.pressure_limit):
            return ex, ey
        A, B = geometry.curvatures
        hz = hertz_ellipse(A, B, material.contact_modulus, force=normal_force)
        if hz.p0 <= self.pressure_limit:
            return ex, ey
        k = math.sqrt(1.3 * normal_force / (self.pressure_limit * hz.area))
        return ex * max(k, 1.0), ey * max(k, 1.0)

    capabilities = frozenset({"force-control", "warm-start", "grid-reuse", "coupled"})

    def solve(self, geometry, material: Material = STEEL, normal_force: float | None = None,
              penetration: float | None = None, grid=None, element_size=None,
              warm_start: NormalSolution | None = None,
              extra_gap: np.ndarray | None = None,
              reuse_grid: NormalSolution | None = None) -> NormalSolution:
        """Solve for a given normal force [N] or approach [m] (see :meth:`_solve`).

        Where the contact reaches the edge of the potential contact area (the
        interpenetration region's extent, found on a coarse sampling of the gap,
        can miss parts of a rough or conformal patch of measured profiles), the
        area is enlarged by half its width on each side the contact reaches and the
        problem solved again, up to ``GROWTH_STEPS`` times; the warning of a
        truncated contact remains only where that does not suffice (or a kept grid,
        or ``extra_gap`` on it, fixes the area)."""
        t0 = time.perf_counter()
        box, sol = None, None
        for _ in range(GROWTH_STEPS + 1):
            new = self._solve(geometry, material, normal_force, penetration, grid,
                              element_size, warm_start, extra_gap, reuse_grid, box)
            if sol is not None and not _plausible_growth(sol, new, normal_force is None):
                # the enlarged area reached other parts of the surfaces (the tangent
                # plane's normals meet them far from the patch): keep the last one
                log.info("exact normal solver: an enlarged potential area changes the "
                         "solution implausibly; the area is kept")
                break
            sol = new
            sides = _edge_sides(sol.contact)
            if not any(sides) or extra_gap is not None or geometry.gap_function is None:
                break
            box = _grown_box(sol.x, sol.y, sides)
            reuse_grid = None
            warm_start = sol if sol.pressure.max() > 0 else warm_start
            log.info("exact normal solver: the contact reaches the edge of its potential area; "
                     "enlarged to %.2f x %.2f mm", 2e3 * box[1][0], 2e3 * box[1][1])
        sides = _edge_sides(sol.contact)
        if any(sides):
            log.warning("exact normal solver: contact reaches the edge of the potential contact "
                        "area; results may be truncated")
        sol.cpu_time = time.perf_counter() - t0
        return sol

    def _solve(self, geometry, material, normal_force, penetration, grid, element_size,
               warm_start, extra_gap, reuse_grid, box) -> NormalSolution:
        """Solve for a given normal force [N] or approach [m] on one potential area.

        ``extra_gap``: a displacement difference [m] added to the undeformed distance
        on the solution grid (the tangential tractions' share for dissimilar
        materials, :mod:`railcontact.coupling`).

        ``warm_start``: a previous solution whose pressure is the initial estimate: on
        the same grid (e.g. in the vertical-force iteration) as it is, on another grid
        (a neighbouring case of a sweep) interpolated.

        ``reuse_grid``: a solution of the same patch at a nearby approach (an earlier
        pass of the vertical-force iteration): its grid is kept where the potential
        contact area still lies in it and fills at least ``REUSE_FILL`` of it in
        each direction (with ``grid`` given or by default, not with
        ``element_size``), so that the pressure and the tangential solution of that
        pass are exact starts and the influence coefficients are reused.

        The undeformed distance is taken from ``geometry.gap`` (the exact gap of the
        geometry layer, shifted so that ``penetration`` is measured from the
        search position's approach), or from its curvatures for a bodies case.

        ``box``: centre and half-extents [m] of the potential contact area instead of
        the model's choice (:meth:`solve` enlarging it).
        """
        t0 = time.perf_counter()
        if (normal_force is None) == (penetration is None):
            raise InputError("give exactly one of normal force and penetration")
        if normal_force is not None and not (math.isfinite(normal_force) and normal_force >= 0):
            raise InputError(f"normal force {normal_force!r} N: expected a finite value >= 0")
        if penetration is not None and not (math.isfinite(penetration) and penetration >= 0):
            raise InputError(f"penetration {penetration!r} m: expected a finite value >= 0")
        h0 = None
        if reuse_grid is not None and element_size is None:
            h0 = self._kept_grid_gap(geometry, penetration, reuse_grid, grid)
        if h0 is not None:
            x, y = reuse_grid.x, reuse_grid.y
        else:
            (cx, cy), (ex, ey) = box or self._potential_area(geometry, material, normal_force,
                                                             penetration, continuous=True)
            if box is None and (geometry.gap_function is None or geometry.extent is None):
                ex, ey = self._plastic_extent(geometry, material, normal_force, ex, ey)
            if reuse_grid is not None and element_size is None and _fits(reuse_grid, cx, cy,
                                                                          ex, ey, grid):
                x, y = reuse_grid.x, reuse_grid.y
            else:
                x, y = make_grid(ex, ey, grid, element_size, center=(cx, cy))
            h0 = own_gap(geometry, x, y) + geometry.approach  # touching: min ~ 0
        dx, dy = x[1] - x[0], y[1] - y[0]
        if extra_gap is not None:
            if np.shape(extra_gap) != h0.shape:
                raise InputError(f"extra_gap of shape {np.shape(extra_gap)}: expected the "
                                 f"solution grid's {h0.shape}")
            h0 = h0 + extra_gap
        grid_key = (x.size, y.size, float(dx), float(dy), material.contact_modulus)
        dA = dx * dy
        regions = subregions(geometry, y)
        p0 = None
        if warm_start is not None and warm_start.pressure.max() > 0:
            if same_grid(warm_start.x, warm_start.y, x, y):
                p0 = warm_start.pressure
            elif warm_start.pressure_at is not None:
                # another grid (a neighbouring case of a sweep): its pressure there
                p0 = np.maximum(warm_start.pressure_at(x[:, None], y[None, :]), 0.0)
                if not p0.max() > 0:
                    p0 = None
        if normal_force is not None:
            if p0 is None and geometry.approach > 0:
                # Hertz's shape: with the rigid overlap approach - h0, the elastic
                # contact is where it exceeds half the approach, and p ~ its root there
                p0 = np.sqrt(np.maximum(0.5 * geometry.approach - h0, 0.0))
            if math.isfinite(self.pressure_limit):
                p, app, it, ok = self._force_by_approach(grid_key, h0, dA, normal_force, p0,
                                                         regions)
            else:
                p, app, it, ok = self._force_controlled(grid_key, h0, dA, normal_force, p0,
                                                        geometry.approach, regions)
        else:
            p, it, ok = self._displacement_controlled(grid_key, h0 - penetration, dA, p0,
                                                      regions)
            app = penetration
        status = SolverStatus(True, "", int(it)) if ok else SolverStatus.failed(
            f"exact normal solver: no convergence in {it} iterations", it)
        if not ok:
            log.warning("exact normal solver: no convergence in %d iterations", it)
        contact = p > 0
        edge = contact[0, :].any() or contact[-1, :].any() or contact[:, 0].any() or \
            contact[:, -1].any()
        if edge:
            status = status.with_warnings("the contact reaches the edge of the potential "
                                          "contact area (results may be truncated)")
        F = float(p.sum() * dA)
        x_lead, x_trail = _strip_edges(contact, np.ascontiguousarray(x, dtype=float))
        def pressure_at(xq, yq):
            return np.maximum(bilinear(x, y, p, xq, yq), 0.0)

        return NormalSolution(model="exact", x=x, y=y, pressure=p, contact=contact,
                              area=float(contact.sum() * dA), pmax=float(p.max()),
                              penetration=float(app), normal_force=F, semi_axes=None,
                              strips=(x_lead, x_trail), pressure_at=pressure_at, status=status,
                              cpu_time=time.perf_counter() - t0,
                              pressure_limit=self.pressure_limit)
