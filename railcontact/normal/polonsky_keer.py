"""The constrained conjugate-gradient method of Polonsky & Keer (Wear 231, 1999)
for the normal contact problem on a grid: p >= 0, e = h + A p - delta >= 0, p e = 0.

Force-controlled (the mean gap over the contact area is the unknown approach) or
displacement-controlled (approach given).  The products A p are FFT convolutions
of the padded grid (compiled with Numba and rocket-fft), so an iteration costs
O(N log N); within a combined patch the regions interact through a reduced
influence (:class:`~railcontact.geometry.contact.ContactGeometry.interaction`), and
near the few elements that change between iterations the product is corrected by
direct sums.  The model around it (grid, potential area, warm starts) is
:mod:`railcontact.normal.exact`.
"""

from __future__ import annotations

import logging
import math
from typing import NamedTuple

import numpy as np
from numba import njit

from ..core.errors import InputError

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
    scale : float      gap scale [m] of the iteration's test (default
                       :func:`gap_scale`: max |h| where both surfaces were found)
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

    ``converged``: the iteration's test passed (the root mean square of the gap over
    the loaded elements below ``tol * scale`` and the pressure settled) and the final
    pressure is a solution: on its displacements A p (a fresh product) no element
    violates the contact conditions (a gap on a loaded element, an overlap on an
    unloaded one, a gap at the pressure limit) by more than ``KKT_FACTOR * tol``
    times the largest displacement (:func:`_violation`).

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
    if math.isfinite(plimit):
        p = np.minimum(p, plimit)
    p = np.ascontiguousarray(p)
    scale = gap_scale(h) if scale is None else float(scale)
    if regions is None:
        cols, fm = np.zeros(h.shape[1], dtype=np.int64), np.ones((1, 1))
    else:
        cols = np.ascontiguousarray(regions[0], dtype=np.int64)
        fm = np.ascontiguousarray(regions[1], dtype=float)
        if cols.shape != (h.shape[1],) or fm.shape != (fm.shape[0], fm.shape[0]) \
                or cols.min() < 0 or cols.max() >= fm.shape[0]:
            raise InputError(f"regions: expected one sub-region index per grid column "
                             f"({h.shape[1]}) and a square factor matrix covering them")
    influence = Influence(op.khat, op.shape, op.kernel, cols, fm, _modulation(op, h.shape[1]))
    gbar, it, converged = _pk_kernel(influence, h, float(dA),
                                     0.0 if force is None else float(force), force is not None,
                                     p, scale, plimit, float(tol), int(maxiter))
    # the result is a solution only where the contact conditions hold: checked on the
    # displacements of the final pressure (a fresh product), whatever the
    # iteration's own test said
    residual, umax = _check(p, influence, h, force is not None, plimit)
    allowed = KKT_FACTOR * float(tol) * umax
    if converged and residual > allowed:
        log.warning("Polonsky-Keer on %d x %d: the iteration's test passed after %d "
                    "iterations, but the pressure violates the contact conditions by "
                    "%.3g m (allowed %.3g m): not converged", *h.shape, it, residual, allowed)
        converged = False
    approach = gbar if force is not None else 0.0
    return p, approach, int(it), bool(converged)


def gap_scale(h) -> float:
    """The gap scale [m] of the convergence test for the undeformed distance ``h``:
    its largest magnitude over the points where both surfaces were found (a missed
    surface is marked by a gap of ``MISSED_GAP`` or more: 1 m, which would make the
    test hundreds of times looser than the patch's gaps of some millimetres)."""
    return float(_gap_scale(np.ascontiguousarray(h, dtype=float)))


@njit(cache=True, nogil=True)
def _gap_scale(h):
    """:func:`gap_scale`, compiled (for a 2-D ``h``, or of any shape, flattened)."""
    found = -1.0
    every = 0.0
    for v in h.ravel():
        a = abs(v)
        every = max(every, a)
        if v < MISSED_GAP:
            found = max(found, a)
    return found if found >= 0.0 else every



@njit(cache=True, nogil=True)
def _convolve(p, khat, shape, buf):
    """A p by a zero-padded real FFT (``buf``: the padded work array, zero outside
    the grid of p), pruned to the rows that carry data: the real transforms along
    the second axis run on the mx rows of p only (the padding rows are zero), the
    complex ones along the first axis on the whole padded length, and the inverse
    real transforms on the mx output rows kept.  The same product as
    ``irfft2(rfft2(buf) * khat)[:mx, :my]`` to rounding, in 0.89 of its time on
    the 40 x 40 grid's 80 x 80 padding (best of 5 x 2000 products on a quiet
    machine; under load the two are within its noise: ``benchmarks/run_all.py``,
    ``bench_fft_unit``)."""
    mx, my = p.shape
    n1, n2 = shape
    buf[:mx, :my] = p
    full = np.zeros((n1, n2 // 2 + 1), dtype=np.complex128)
    full[:mx] = np.fft.rfft(buf[:mx], axis=1)
    f = np.fft.fft(full, axis=0)
    f *= khat
    g = np.fft.ifft(f, axis=0)
    return np.fft.irfft(g[:mx], n=n2, axis=1)[:, :my]



def _modulation(op, my):
    """The column modulation of an operator (``op.modulation``, (m, my): the
    product is sum_m w_m * A (w_m * p), Blanco's conformal correction,
    :mod:`railcontact.normal.conformal_influence`), or an empty (0, my) array for
    the half-space's :class:`~railcontact.normal.influence.Convolution`."""
    if op.modulation is None:
        return np.zeros((0, my))
    return op.modulation


@njit(cache=True, nogil=True)
def _apply(p, khat, shape, buf, cols, fm, mod):
    """A p; with a column modulation ``mod`` (m, my) the product
    sum_m mod[m] * A (mod[m] * p) (each weight per grid column), else A p itself
    (:func:`_apply_plain`)."""
    nm = mod.shape[0]
    if nm == 0:
        return _apply_plain(p, khat, shape, buf, cols, fm)
    mx, my = p.shape
    u = np.zeros((mx, my))
    q = np.empty((mx, my))
    for m in range(nm):
        for i in range(mx):
            for j in range(my):
                q[i, j] = mod[m, j] * p[i, j]
        um = _apply_plain(q, khat, shape, buf, cols, fm)
        for i in range(mx):
            for j in range(my):
                u[i, j] += mod[m, j] * um[i, j]
    return u


@njit(cache=True, nogil=True)
def _apply_plain(p, khat, shape, buf, cols, fm):
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
def _add_direct(u, f, idx, dq, kernel, cols, fm, mod):
    """u += f A dq for dq nonzero only at the flat indices ``idx`` (values ``dq``):
    each element's displacements summed directly from the kernel (offsets centred
    at (kernel rows - 1) / 2), scaled between sub-regions as in :func:`_apply`
    and by the column modulation ``mod`` (sum_m mod[m, j0] mod[m, j])."""
    mx, my = u.shape
    ci = (kernel.shape[0] - 1) // 2
    cj = (kernel.shape[1] - 1) // 2
    one = fm.shape[0] == 1
    nm = mod.shape[0]
    for k in range(idx.size):
        i0 = idx[k] // my
        j0 = idx[k] % my
        a = f * dq[k]
        if nm > 0:
            for j in range(my):
                w = 0.0
                for m in range(nm):
                    w += mod[m, j0] * mod[m, j]
                w *= a * fm[cols[j0], cols[j]]
                for i in range(mx):
                    u[i, j] += w * kernel[ci + i - i0, cj + j - j0]
        elif one:
            for i in range(mx):
                row = ci + i - i0
                for j in range(my):
                    u[i, j] += a * kernel[row, cj + j - j0]
        else:
            for i in range(mx):
                row = ci + i - i0
                for j in range(my):
                    u[i, j] += a * fm[cols[j0], cols[j]] * kernel[row, cj + j - j0]



#: a converged solution meets the contact conditions at every element to this factor
#: on ``tol`` times its largest displacement (a gap at most that on a loaded element,
#: an overlap at most that on an unloaded one): a bound on the solution itself,
#: whatever gap scale the iteration's own test (the root mean square of the gap over
#: the loaded elements) was given (the converged solves of tests/normal,
#: tests/contact_inp, tests/cases and tests/test_exact_wheel_rail.py, 3557 of them,
#: meet it to 1.6 times ``tol``)
KKT_FACTOR = 100.0

#: an undeformed distance [m] at or above this marks a point where a surface was
#: missed (the geometry layer gives 1 m there): left out of the gap scale
MISSED_GAP = 0.5

#: Polonsky-Keer updates the displacements of a step directly (from the kernel) where
#: at most this fraction of the elements were clipped or loaded, else by an FFT
DIRECT_FRACTION = 0.02



class Influence(NamedTuple):
    """The influence operator p -> A p of :func:`_pk_kernel`: the spectrum of a
    :class:`~railcontact.normal.influence.Convolution` and its kernel, with the
    sub-regions of a combined patch."""

    #: spectrum [m/Pa] of the influence kernel on the padded grid
    khat: np.ndarray
    #: (nx, ny) the padded grid of the FFT
    shape: tuple
    #: the influence kernel [m/Pa], offsets centred at (rows - 1) / 2, (columns - 1) / 2
    kernel: np.ndarray
    #: (my,) the sub-region of each grid column
    cols: np.ndarray
    #: (k, k) interaction factors [-] between the sub-regions (:func:`_apply`)
    factors: np.ndarray
    #: (m, my) column weights of a modulated product (:func:`_apply`; Blanco's
    #: conformal correction), (0, my) for the plain one
    modulation: np.ndarray


@njit(cache=True, nogil=True)
def _free_set(p, u, h, g, S, Sp, plimit):
    """The gap g = A p + h and the set S of the elements free to move: loaded below
    the limit, or at the limit with an opening gap (it may unload).  Returns the
    size of S and whether an element at the limit joined it (the directions
    restart)."""
    mx, my = h.shape
    nS = 0
    rejoined = False
    for i in range(mx):
        for j in range(my):
            g[i, j] = u[i, j] + h[i, j]
            at = p[i, j] >= plimit
            S[i, j] = (0.0 < p[i, j] and not at) or (at and g[i, j] > 0.0)
            if at and S[i, j] and not Sp[i, j]:
                rejoined = True
            nS += S[i, j]
    return nS, rejoined


@njit(cache=True, nogil=True)
def _no_free_element(p, g, S, plimit):
    """With S empty: whether the pressure already is the solution (no element at
    zero overlaps, none at the limit has a gap); else S becomes the elements below
    the limit at the deepest overlap.  Returns (solved, the size of S)."""
    mx, my = g.shape
    gmin = np.inf
    kkt = True
    for i in range(mx):
        for j in range(my):
            if p[i, j] < plimit:
                gmin = min(gmin, g[i, j])
                kkt = kkt and g[i, j] >= 0.0
            else:
                kkt = kkt and g[i, j] <= 0.0
    nS = 0
    for i in range(mx):
        for j in range(my):
            S[i, j] = p[i, j] < plimit and g[i, j] <= gmin + 1e-15
            nS += S[i, j]
    return kkt, nS


@njit(cache=True, nogil=True)
def _direction(g, S, t, restart, G_old):
    """Conjugate gradients: the new direction t on S from the gap g (steepest descent
    where the directions restart).  Returns G = |g|² on S."""
    mx, my = g.shape
    G = 0.0
    for i in range(mx):
        for j in range(my):
            if S[i, j]:
                G += g[i, j] * g[i, j]
    beta = 0.0 if restart else G / G_old
    for i in range(mx):
        for j in range(my):
            t[i, j] = g[i, j] + beta * t[i, j] if S[i, j] else 0.0
    return G


@njit(cache=True, nogil=True)
def _step_length(g, r, t, S):
    """Conjugate gradients: the step tau = (g, t) / (A t, t) on S (0 / 0: nothing
    left to do; returned as the pair (num, den))."""
    mx, my = g.shape
    den = 0.0
    num = 0.0
    for i in range(mx):
        for j in range(my):
            if S[i, j]:
                den += r[i, j] * t[i, j]
                num += g[i, j] * t[i, j]
    return num, den


@njit(cache=True, nogil=True)
def _project(p, t, g, tau, plimit, pn, idx, dq):
    """The step p - tau t projected on the bounds 0 <= p <= ``plimit`` (the plastic
    cap), into ``pn``; an unloaded element with an overlap is loaded.  The elements
    changed by the projection go to ``idx`` (flat index) and ``dq`` (their change),
    as many as fit.  Returns (sum of pn, number of elements changed, whether an
    element was loaded: the directions restart)."""
    mx, my = p.shape
    limit = idx.size - 1
    loaded = False
    total = 0.0
    nd = 0
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
                loaded = True
            if q != q0:
                if nd < limit:
                    idx[nd] = i * my + j
                    dq[nd] = q - q0
                nd += 1
            total += q
            pn[i, j] = q
    return total, nd, loaded


@njit(cache=True, nogil=True)
def _accept(p, pn, f):
    """p = f pn; returns the relative change sum |p_new - p| / sum p_new."""
    mx, my = p.shape
    diff = 0.0
    ref = 0.0
    for i in range(mx):
        for j in range(my):
            q = pn[i, j] * f
            diff += abs(q - p[i, j])
            ref += q
            p[i, j] = q
    return diff / max(ref, 1e-300)


@njit(cache=True, nogil=True)
def _update_displacements(u, f, tau, r, rbar, changed, influence):
    """A p after a step without a convolution: p changed by -tau t (then scaled by
    f) and by ``changed`` = (idx, dq) on the few elements the projection moved, so
    A p = f (A p_old - tau A t) plus the direct sum of those elements'
    displacements (:func:`_add_direct`); ``r + rbar`` is A t."""
    mx, my = u.shape
    for i in range(mx):
        for j in range(my):
            u[i, j] = f * (u[i, j] - tau * (r[i, j] + rbar))
    _add_direct(u, f, changed[0], changed[1], influence.kernel, influence.cols,
                influence.factors, influence.modulation)


@njit(cache=True, nogil=True)
def _pk_kernel(influence, h, dA, force, controlled, p, scale, plimit, tol, maxiter):
    """Constrained conjugate gradients of Polonsky & Keer on the pressure ``p``
    (the initial estimate, overwritten with the solution).

    Parameters
    ----------
    influence : Influence
        The operator p -> A p [m/Pa], with the sub-regions of a combined patch.
    h : ndarray (mx, my)
        Undeformed distance [m] (less the approach where it is given).
    dA : float
        Element area [m²].
    force : float
        Total force [N] with ``controlled``.
    controlled : bool
        Force-controlled (the approach is the unknown) or not.
    p : ndarray (mx, my)
        Pressure [Pa]: the start, overwritten with the solution.
    scale : float
        Gap scale [m] of the convergence test.
    plimit : float
        Upper bound of the pressure [Pa] (inf: elastic).
    tol : float
        Relative tolerance.
    maxiter : int
        Iterations at most.

    Conjugate directions on the set S of loaded elements (:func:`_free_set`,
    :func:`_direction`, :func:`_step_length`); an element whose pressure would turn
    negative is set to zero, an unloaded element with a negative gap (an overlap)
    is loaded and the directions restart (:func:`_project`).  Force-controlled:
    the approach is the mean gap over S and the pressure is scaled to the force.
    After a step A p = f (A p_old - tau A t + A d), with f the force scaling (1
    displacement-controlled) and d the changes of the clipped and loaded elements:
    A d summed directly where they are few (``DIRECT_FRACTION`` of the elements;
    :func:`_update_displacements`), else A p by a convolution; refreshed by a
    convolution every 10 steps.
    ``plimit``: an element that reaches the limit is clipped to it (it may overlap:
    plastic flow) and leaves the directions; an element at the limit whose gap
    opens joins them again (it may unload; the directions restart), so that at the
    solution p = 0 with a gap, 0 < p < limit without one, or p = limit with an
    overlap.  Only with the approach given (``controlled`` False).
    Returns the approach (mean gap, force-controlled), iterations, whether the
    iteration's test passed (:func:`polonsky_keer` reports convergence only where,
    besides, the final pressure meets the contact conditions: :func:`_violation`).
    """
    khat, shape, cols, fm = influence.khat, influence.shape, influence.cols, \
        influence.factors
    mod = influence.modulation
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
            u[:, :] = _apply(p, khat, shape, buf, cols, fm, mod)
            fresh = 0
        nS, rejoined = _free_set(p, u, h, g, S, Sp, plimit)
        restart = restart or rejoined
        if nS == 0:
            solved, nS = _no_free_element(p, g, S, plimit)
            if not controlled and solved:
                converged = True             # e.g. no overlap anywhere: p = 0
                break
        if controlled:
            gbar = _mean_on(g, S)
            g -= gbar
        Sp[:, :] = S
        G = _direction(g, S, t, restart, G_old)
        G_old = G
        r = _apply(t, khat, shape, buf, cols, fm, mod)
        rbar = 0.0
        if controlled:
            rbar = _mean_on(r, S)
            r -= rbar
        num, den = _step_length(g, r, t, S)
        if den == 0.0:
            converged = True
            break
        tau = num / den
        total, nd, restart = _project(p, t, g, tau, plimit, pn, idx, dq)
        f = force / (total * dA) if controlled and total > 0.0 else 1.0
        change = _accept(p, pn, f)
        if nd <= limit:
            _update_displacements(u, f, tau, r, rbar, (idx[:nd], dq[:nd]), influence)
            fresh += 1
            valid = True
        else:
            valid = False
        if change < tol and G <= (tol * scale) ** 2 * max(nS, 1):
            converged = True
            break
    return gbar, it, converged


@njit(cache=True, nogil=True)
def _check(p, influence, h, controlled, plimit):
    """The final pressure's test (:func:`polonsky_keer`): its displacements A p by
    a fresh product, the largest violation [m] of the contact conditions
    (:func:`_violation`) and the largest displacement [m]."""
    u = _apply(p, influence.khat, influence.shape, np.zeros(influence.shape),
               influence.cols, influence.factors, influence.modulation)
    return _violation(p, u, h, controlled, plimit), np.max(u)


@njit(cache=True, nogil=True)
def _violation(p, u, h, controlled, plimit):
    """The largest violation [m] of the contact conditions by the pressure ``p``
    with displacements ``u`` = A p: a gap g = u + h (less the approach, the mean
    gap over the loaded elements, where the force is given) on an element loaded
    below the limit, an overlap -g on an unloaded one, a gap on one at the limit."""
    mx, my = p.shape
    gbar = 0.0
    if controlled:
        n = 0
        for i in range(mx):
            for j in range(my):
                if 0.0 < p[i, j] < plimit:
                    gbar += u[i, j] + h[i, j]
                    n += 1
        gbar = gbar / n if n > 0 else 0.0
    worst = 0.0
    for i in range(mx):
        for j in range(my):
            g = u[i, j] + h[i, j] - gbar
            if p[i, j] <= 0.0:
                v = -g
            elif p[i, j] >= plimit:
                v = g
            else:
                v = abs(g)
            worst = max(worst, v)
    return worst



def flat_punch_stiffness(op, contact, dA, regions=None, tol=1e-8, maxiter=500):
    """The stiffness [N/m] of a rigid flat punch on the elements ``contact`` (bool,
    on the grid of ``op`` or a block of it): the total load of the pressures q
    with A q = 1 on the set and q = 0 elsewhere, K = dA sum q.

    The derivative dF_n/d(delta) of a converged normal solution whose contact is
    that set: where the contact area does not change, F_n is linear in the
    approach, p(delta + e) = p(delta) + e q; where it grows, the elements that join
    carry no pressure at their edge, so the derivative is the same (the
    incremental stiffness of an elastic contact is that of the flat punch of its
    contact area; Barber, Elasticity, the incremental-stiffness theorem; Hertz:
    dF/d(delta) = 2 E* a = 3/2 F/delta).  Solved by conjugate gradients on the set
    (A is symmetric positive definite there), the products by the same FFT
    convolutions as :func:`polonsky_keer`.

    Returns K [N/m], iterations, converged.
    """
    mask = np.ascontiguousarray(contact, dtype=np.bool_)
    if not mask.any():
        return 0.0, 0, True
    if regions is None:
        cols, fm = np.zeros(mask.shape[1], dtype=np.int64), np.ones((1, 1))
    else:
        cols = np.ascontiguousarray(regions[0], dtype=np.int64)
        fm = np.ascontiguousarray(regions[1], dtype=float)
    influence = Influence(op.khat, op.shape, op.kernel, cols, fm,
                          _modulation(op, mask.shape[1]))
    total, it, ok = _punch_kernel(influence, mask, float(tol), int(maxiter))
    return float(total * dA), int(it), bool(ok)



@njit(cache=True, nogil=True)
def _punch_kernel(influence, mask, tol, maxiter):
    """Conjugate gradients for A q = 1 on the elements of ``mask`` (q = 0 off it),
    from q = 1 / A_ii; returns sum q, iterations, converged (the residual's norm
    below ``tol`` times the right-hand side's)."""
    khat, shape, cols, fm = influence.khat, influence.shape, influence.cols, \
        influence.factors
    mod = influence.modulation
    mx, my = mask.shape
    buf = np.zeros(shape)
    ci = (influence.kernel.shape[0] - 1) // 2
    cj = (influence.kernel.shape[1] - 1) // 2
    diag = influence.kernel[ci, cj]
    q = np.zeros((mx, my))
    n = 0
    for i in range(mx):
        for j in range(my):
            if mask[i, j]:
                q[i, j] = 1.0 / diag
                n += 1
    u = _apply(q, khat, shape, buf, cols, fm, mod)
    r = np.zeros((mx, my))
    for i in range(mx):
        for j in range(my):
            if mask[i, j]:
                r[i, j] = 1.0 - u[i, j]
    d = r.copy()
    rr = np.sum(r * r)
    limit = tol * tol * n
    it = 0
    converged = rr <= limit
    while not converged and it < maxiter:
        it += 1
        ad = _apply(d, khat, shape, buf, cols, fm, mod)
        dad = 0.0
        for i in range(mx):
            for j in range(my):
                if mask[i, j]:
                    dad += d[i, j] * ad[i, j]
        alpha = rr / dad
        rr_new = 0.0
        for i in range(mx):
            for j in range(my):
                if mask[i, j]:
                    q[i, j] += alpha * d[i, j]
                    r[i, j] -= alpha * ad[i, j]
                    rr_new += r[i, j] * r[i, j]
        beta = rr_new / rr
        rr = rr_new
        for i in range(mx):
            for j in range(my):
                d[i, j] = r[i, j] + beta * d[i, j] if mask[i, j] else 0.0
        converged = rr <= limit
    return np.sum(q), it, converged
