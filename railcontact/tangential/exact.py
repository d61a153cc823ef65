"""Exact steady-state rolling: Kalker's theory on a boundary-element grid
(``tangential="exact"``).

Kalker (1990), *Three-Dimensional Elastic Bodies in Rolling Contact*, ch. 2 and 5;
discretisation as in CONTACT.  On the grid of the normal solution, with piecewise
constant tractions p (on body 1, the rail) and the displacement difference u = B p
(Cerruti's influence coefficients of uniform tractions on rectangles,
:func:`railcontact.normal.influence.tangential_kernels`), the relative slip of
element I in steady rolling is

    s_I = w_I - (u_{I+} - u_I) / dx,        w = (xi - phi y, eta + phi x),

with I+ the element upstream (towards the leading edge, +x).  In contact
|p_I| <= g_I = mu p_n; stick elements have s_I = 0, slip elements |p_I| = g_I with
p_I = -g_I s_I / |s_I|; outside the contact p = 0.  For identical materials the
tangential problem is independent of the normal one.

Solver: a semi-smooth Newton method on the complementarity residual
F = p - Proj_g(p - rho s) (zero exactly when every element sticks with s = 0 or
slips on the bound against its slip).  Each Newton step is solved inexactly
(Eisenstat-Walker forcing) by restarted GMRES with FFT matrix-vector products and a
marching preconditioner (the self and upstream coupling of each element, i.e. the
operator of simplified theory, inverted strip by strip from the leading edge);
a backtracking line search on |F|^2 globalises it (why not Gauss-Seidel sweeps:
docs/tuning.md, section "Tangential: exact").  A result that does not converge is
flagged.

The whole iteration (Newton steps, GMRES, line search) runs compiled with Numba
(:mod:`railcontact.tangential.semi_smooth_newton`),
its FFT products by rocket-fft's ``numpy.fft`` support for Numba, on the bounding
box of the contact (outside it the tractions are zero and the slip is not needed),
with the grid's kernels cut to the box.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass
from functools import lru_cache
from typing import NamedTuple

import numpy as np
from numba import njit
from scipy import fft

from ..core.errors import InputError
from ..core.materials import InterfaceLayer, Material, STEEL
from ..normal.base import bilinear_at, same_grid
from ..normal.influence import (TangentialOperator, block_size, box_bounds, rect_integrals,
                                tangential_coefficients, tangential_kernels)
from ..normal.viscoelastic import (Viscoelastic, ViscoelasticOption,
                                   viscoelastic_tangential_kernels)
from ..core.status import SolverStatus
from ..geometry.conformal import influence_angles
from .base import TangentialSolution, check_inputs, register
from .fastsim import FastsimModel
from .semi_smooth_newton import SlipOperator, TractionBound, initial_march, ssn_solve

log = logging.getLogger(__name__)

#: in steady rolling the lateral rigid slip of spin, eta + phi x, is taken at
#: x + SPIN_OFFSET dx (towards the leading edge), as CONTACT does (the factor FACPHI of
#: its rolling step, default 1/6, Vollebregt's CONTACT user guide): an O(dx) choice of
#: the discretisation, with the same continuum limit [element lengths dx]
#: (docs/tuning.md, section "Tangential: exact")
SPIN_OFFSET = 1.0 / 6.0

#: rolling with a hardening or softening interfacial layer: the yield limits of
#: the elements are iterated until none changes by more than this (relative to the
#: largest friction bound), at most LAYER_ITERATIONS times
LAYER_TOL = 1e-9
LAYER_ITERATIONS = 200


@lru_cache(maxsize=32)
def _self_terms(mx, my, dx, dy, G, nu):
    kxx, _, kyy = tangential_kernels(1, 1, dx, dy, G, nu)
    return float(kxx[0, 0]), float(kyy[0, 0])


@lru_cache(maxsize=32)
def _kernels(mx, my, dx, dy, G, nu):
    """Tangential kernels of an mx x my grid (offsets in x up to mx: one extra row
    for the rolling difference) and the self terms (dxx, dyy) of the operator.
    ``G`` a :class:`~railcontact.normal.viscoelastic.Viscoelastic` pair: its
    steady-rolling kernels (``nu`` unused)."""
    if isinstance(G, Viscoelastic):
        kxx, kxy, kyy = viscoelastic_tangential_kernels(mx, my, dx, dy, G, extra_rows=1)
    else:
        kxx, kxy, kyy = tangential_kernels(mx, my, dx, dy, G, nu, extra_rows=1)
    ox, oy = mx - 1, my - 1
    dxx = (kxx[ox, oy] - kxx[ox + 1, oy]) / dx
    dyy = (kyy[ox, oy] - kyy[ox + 1, oy]) / dx
    return (kxx, kxy, kyy), (dxx, dyy)


def _sub_operator(mx, my, dx, dy, G, nu, ms, ns):
    """FFT operator for an ms x ns block of the mx x my grid (the contact's bounding
    box: outside the contact the tractions are zero and the slip is not needed),
    from the grid's kernels cut to the block's offsets; cached per FFT size (it
    serves the block and every smaller one, :func:`block_size`)."""
    if not isinstance(G, Viscoelastic):
        return _elastic_block(mx, my, dx, dy, G, nu,
                              *block_size(ms, ns, mx, my, extra_rows=1))[0]
    return _block_operator(mx, my, dx, dy, G, nu, *block_size(ms, ns, mx, my, extra_rows=1))


class _SpectraOperator(TangentialOperator):
    """A :class:`~railcontact.normal.influence.TangentialOperator` from its kernels'
    spectra (``spectra`` (xx, xy, yy) on the padded grid ``shape``) for an mx x my
    block with one extra row."""

    def __init__(self, spectra, shape, mx: int, my: int):
        self.kxx, self.kxy, self.kyy = spectra
        self.shape, self.mx, self.my, self.rows = shape, mx, my, 1


@lru_cache(maxsize=64)
def _elastic_block(mx, my, dx, dy, G, nu, ms, ns):
    """The FFT operator of an ms x ns block of the mx x my grid (elastic bodies of
    shear modulus G [Pa] and Poisson's ratio nu) and the grid's self terms (dxx,
    dyy) [m/Pa] of the rolling difference: :func:`_block_operator` and
    :func:`_kernels` in one compiled pass over the block's offsets alone, from the
    grid's element integrals (:func:`railcontact.normal.influence.rect_integrals`,
    cached per grid and shared with the normal solve): the same values, without the
    whole grid's kernels (issue 30: a new grid's set-up)."""
    rect = rect_integrals(mx, my, float(dx), float(dy))
    shape = (fft.next_fast_len(2 * ms, real=True), fft.next_fast_len(2 * ns - 1, real=True))
    c = 1.0 / (np.pi * G)
    spectra, dxx, dyy = _block_spectra(rect, (c, float(nu), float(dx)), (mx, my, ms, ns), shape)
    return _SpectraOperator(spectra, shape, ms, ns), (dxx, dyy)


@njit(cache=True, nogil=True)
def _block_spectra(rect, consts, sizes, shape):
    """Spectra (xx, xy, yy) on the padded grid ``shape`` of the tangential kernels
    of an ms x ns block with one extra row, and the self terms (dxx, dyy) of the
    rolling difference, from the mx x my grid's element integrals ``rect`` (Lx, Ly,
    R: :func:`~railcontact.normal.influence.tangential_coefficients` element by
    element, as :func:`~railcontact.normal.influence.tangential_kernels`); ``consts``
    (1/(pi G), nu, dx), ``sizes`` (mx, my, ms, ns)."""
    Lx, Ly, Rr = rect
    c, nu, dx = consts
    mx, my, ms, ns = sizes
    N1, N2 = shape
    k = np.zeros((3, N1, N2))
    for a in range(2 * ms):
        ga = mx - ms + a                  # the grid kernel's row
        i = (a - (ms - 1)) % N1
        for b in range(2 * ns - 1):
            gb = my - ns + b
            j = (b - (ns - 1)) % N2
            k[0, i, j], k[1, i, j], k[2, i, j] = tangential_coefficients(
                Lx[ga, gb], Ly[ga, gb], Rr[ga, gb], c, nu)
    ox, oy = mx - 1, my - 1
    xx0, _, yy0 = tangential_coefficients(Lx[ox, oy], Ly[ox, oy], Rr[ox, oy], c, nu)
    xx1, _, yy1 = tangential_coefficients(Lx[ox + 1, oy], Ly[ox + 1, oy], Rr[ox + 1, oy], c, nu)
    dxx, dyy = (xx0 - xx1) / dx, (yy0 - yy1) / dx
    return (np.fft.rfft2(k[0]), np.fft.rfft2(k[1]), np.fft.rfft2(k[2])), dxx, dyy


@lru_cache(maxsize=64)
def _block_operator(mx, my, dx, dy, G, nu, ms, ns):
    kernels, _ = _kernels(mx, my, dx, dy, G, nu)
    cut = (slice(mx - ms, mx + ms), slice(my - ns, my - 1 + ns))
    return TangentialOperator(tuple(k[cut] for k in kernels), ms, ns, rows=1)


class LayerBound(NamedTuple):
    """The traction bound of :func:`steady_rolling` with an interfacial layer
    (:class:`~railcontact.core.materials.InterfaceLayer`, CONTACT's M = 4): in
    place of the friction bound's array.

    Slip then is the frictional slip plus the layer's plastic flow, both against
    the traction; the flow takes over where the yield limit lies under the
    friction bound, and the yield limit grows (k > 0) or falls (k < 0) with it.
    Rolling: ``tau`` the yield limit of the material entering the contact
    (tau_c0), the plastic displacement accumulated along each strip towards the
    trailing edge; shift and transient steps: ``tau`` the yield limit each
    element has before the step (tau_c0 + k u*_pl of the previous instance)."""

    #: friction bound mu p_n [Pa] per element
    g: np.ndarray
    #: yield limit [Pa] per element (inf: none)
    tau: np.ndarray
    #: hardening rate k_tau [Pa/m] of the yield limit with the plastic displacement
    k: float
    #: the layer's flexibility h3/G3 [m/Pa]
    flexibility: float
    #: the lowest yield limit [Pa] a softening layer keeps from element to element
    #: (the element's own flow may take its traction bound lower, as in CONTACT)
    floor: float = 0.0


def layer_bound(layer: InterfaceLayer | None, g, ustar=None) -> LayerBound:
    """The :class:`LayerBound` of ``layer`` for the friction bound g [Pa] (array),
    with the yield limit tau_c0 + k_tau u* where the material has accumulated the
    plastic displacement ``ustar`` [m] (None: fresh material)."""
    g = np.ascontiguousarray(g, dtype=float)
    floor = 0.0
    if layer is None or not layer.plastic:
        tau = np.full(g.shape, np.inf)
    else:
        floor = layer.yield_floor
        tau = np.full(g.shape, float(layer.yield_stress))
        if ustar is not None:
            tau = np.maximum(tau + layer.hardening * np.asarray(ustar, dtype=float), floor)
    return LayerBound(g, tau, 0.0 if layer is None else float(layer.hardening),
                      0.0 if layer is None else layer.flexibility, floor)


def _bound_at(g, tau, k, S):
    """The traction bound of each element at slip magnitude S (NumPy;
    :class:`~railcontact.tangential.semi_smooth_newton.TractionBound`)."""
    return np.where(tau >= g, g, np.clip(tau + k * S, 0.0, g))


def _plastic_part(g, tau, k, S):
    """The part of each element's slip magnitude S that is plastic flow of the layer
    (the rest slides): all of it where the yield limit lies under the friction bound,
    up to the slip at which a hardening limit reaches that bound."""
    with np.errstate(invalid="ignore", divide="ignore"):
        cap = np.where(k > 0, (g - tau) / np.where(k > 0, k, 1.0), np.inf)
    return np.where(tau < g, np.minimum(S, cap), 0.0)


def plastic_flow(bound: LayerBound, sx, sy, dx, rolling):
    """The layer's plastic flow of a solution of :func:`steady_rolling` with a
    :class:`LayerBound`: (increment [m] per element over the step or, rolling,
    while the material passes the element; accumulated displacement u*_pl [m]
    after the element, rolling: summed from the leading edge, else the increment;
    the mask of the elements in plastic flow, CONTACT's "plasticity area").
    ``sx, sy`` the solution's slip, ``dx`` [m] the element length."""
    S = np.hypot(sx, sy)
    if not rolling:
        d = _plastic_part(bound.g, bound.tau, bound.k, S)
        return d, d, (S > 0) & (bound.tau < bound.g)
    d, acc, tau = _rolling_flow(bound, S, dx)
    return d, acc, (S > 0) & (tau < bound.g)


def _rolling_flow(bound, S, dx):
    """Rolling: the plastic increments d [m] of each element, the displacement
    accumulated after it and the yield limit each element starts from, with the
    material entering at the leading edge (+x, the highest index) at ``bound.tau``."""
    tau0 = bound.tau
    # marched towards the trailing edge: an element's yield limit follows the flow
    # upstream of it
    mx = S.shape[0]
    d = np.zeros(S.shape)
    acc = np.zeros(S.shape)
    tau = np.array(tau0, dtype=float, copy=True)
    u = np.zeros(S.shape[1:])
    for i in range(mx - 1, -1, -1):
        tau[i] = np.maximum(tau0[i] + bound.k * u, bound.floor)
        d[i] = _plastic_part(bound.g[i], tau[i], bound.k * dx, S[i]) * dx
        u = u + d[i]
        acc[i] = u
    return d, acc, tau


def _operators(mx, my, dx, dy, G, nu):
    """FFT operator of the whole mx x my grid and the self terms (dxx, dyy)."""
    return _sub_operator(mx, my, dx, dy, G, nu, mx, my), _kernels(mx, my, dx, dy, G, nu)[1]


class TurnedElastic(NamedTuple):
    """Elastic bodies of one material on a conformal patch with Blanco's corrected
    influence coefficients (variant 3, :mod:`railcontact.normal.conformal_influence`),
    in place of the shear modulus of :func:`steady_rolling`."""

    #: combined shear modulus [Pa]
    G: float
    #: inclination [rad] of each grid column (the curve's angle)
    angles: np.ndarray


def steady_rolling(x, y, contact, bound, creepage, G, nu, tol=1e-7, maxiter=60, p0=None,
                   mode="rolling", w_extra=None):
    """Solve the discrete steady-rolling (or shift) problem by a semi-smooth Newton method.

    ``mode="rolling"``: s = w - (u_I+ - u_I)/dx with w from the creepages,
    w = (xi - phi y, eta + phi (x + SPIN_OFFSET dx)).
    ``mode="shift"``: Cattaneo's transient shift from an unloaded state,
    s = w + u (slip displacement [m]), with ``creepage`` = (shift_x, shift_y, rotation)
    the rigid shift [m, m] and rotation about n [rad] of body 1.

    ``w_extra``: an additional rigid slip (s_x, s_y) per element (the pressure's
    share for dissimilar materials).

    ``G`` a :class:`TurnedElastic`: the shear modulus with the inclination [rad]
    of each grid column of a conformal patch with Blanco's corrected influence
    coefficients (variant 3, :mod:`railcontact.normal.conformal_influence`): the
    lateral displacement difference turned between the columns' frames.

    ``bound``: the friction bound mu p_n [Pa] per element, or a
    :class:`LayerBound`: an interfacial layer's flexibility and yield limit
    (CONTACT's M = 4).  Rolling with a hardening or softening layer, the yield
    limit of each element follows from the plastic flow upstream of it: the
    problem is solved again with the limits of the last solution until they
    settle (:data:`LAYER_TOL`).

    With viscoelastic bodies, ``G`` is a
    :class:`~railcontact.normal.viscoelastic.Viscoelastic` pair instead of the combined
    shear modulus [Pa] (steady rolling towards +x, CONTACT's M = 1; ``mode="rolling"``
    only).

    Returns p (on body 1), slip, stick mask, Newton iterations and a convergence
    flag.  Convergence: max |F| <= tol * max bound, with F the complementarity
    residual p - Proj(p - rho s).
    """
    mx, my = x.size, y.size
    dx, dy = float(x[1] - x[0]), float(y[1] - y[0])
    angles = None
    if isinstance(G, TurnedElastic):
        G, angles = float(G.G), np.asarray(G.angles, dtype=float)
        if angles.shape != (my,):
            raise InputError(f"{angles.size} column inclinations: expected one per grid "
                             f"column ({my})")
    if isinstance(G, Viscoelastic) and mode != "rolling":
        raise InputError(f"viscoelastic materials with mode {mode!r}: expected steady "
                         "rolling ('rolling')")
    # the problem lives on the contact's bounding box: tractions are zero outside the
    # contact and the slip is needed only inside it, so the FFT products run on the
    # box's (smaller) padded grid, with the same arithmetic
    i0, i1, j0, j1 = _contact_box(contact)
    box = (slice(i0, i1), slice(j0, j1))
    ms, ns = i1 - i0, j1 - j0
    if isinstance(G, Viscoelastic):
        op = _sub_operator(mx, my, dx, dy, G, nu, ms, ns)
        _, (dxx, dyy) = _kernels(mx, my, dx, dy, G, nu)
    else:
        op, (dxx, dyy) = _elastic_block(mx, my, dx, dy, G, nu,
                                        *block_size(ms, ns, mx, my, extra_rows=1))
    if mode == "shift":
        kx, ky = _self_terms(mx, my, dx, dy, G, nu)
        dxx, dyy = kx, ky
    layer = bound if isinstance(bound, LayerBound) else None
    flex = 0.0
    if layer is not None:
        bound = np.ascontiguousarray(layer.g)
        flex = float(layer.flexibility)
        # the layer's own displacement f p: rolling, -(f p_I+ - f p_I)/dx
        dxx, dyy = dxx + (flex if mode == "shift" else flex / dx), \
            dyy + (flex if mode == "shift" else flex / dx)
    xi, eta, phi = creepage
    rho = 1.0 / (0.5 * (dxx + dyy))
    shift = mode == "shift"
    if p0 is not None and w_extra is None:
        # a warm start (the sweep's and the balance's solves): the box's fields in
        # one compiled pass, the same arithmetic as the whole grid's below
        cb, gb, *q = _box_fields(contact, np.ascontiguousarray(bound, dtype=float),
                                 (np.ascontiguousarray(p0[0], dtype=float),
                                  np.ascontiguousarray(p0[1], dtype=float)),
                                 (float(xi), float(eta), float(phi), SPIN_OFFSET * dx),
                                 (np.asarray(x, dtype=float), np.asarray(y, dtype=float)),
                                 (i0, i1, j0, j1, not shift))
    else:
        wx = np.ascontiguousarray(np.where(contact, xi - phi * y[None, :], 0.0))
        x_spin = x + SPIN_OFFSET * dx if mode == "rolling" else x
        wy = np.ascontiguousarray(np.where(contact, eta + phi * x_spin[:, None], 0.0))
        if w_extra is not None:
            wx = np.ascontiguousarray(wx + np.where(contact, w_extra[0], 0.0))
            wy = np.ascontiguousarray(wy + np.where(contact, w_extra[1], 0.0))
        if p0 is not None:
            px, py = p0[0].copy(), p0[1].copy()
        elif mode == "shift":
            px, py = np.zeros((mx, my)), np.zeros((mx, my))
        else:
            g0 = bound if layer is None else np.ascontiguousarray(np.minimum(bound, layer.tau))
            px, py = initial_march(wx, wy, contact, g0, dxx, dyy)
        cb, gb, *q = (np.ascontiguousarray(a[box]) for a in (contact, bound, px, py, wx, wy))
    if angles is None:
        sop = SlipOperator(op.kxx, op.kxy, op.kyy, op.shape, dx, shift, flex)
    else:
        a = angles[box[1]]
        sop = SlipOperator(op.kxx, op.kxy, op.kyy, op.shape, dx, shift, flex,
                           np.ascontiguousarray(np.cos(a)), np.ascontiguousarray(np.sin(a)))
    if layer is None:
        tb = TractionBound(gb, gb, np.zeros_like(gb))
    else:
        tb = TractionBound(gb, np.ascontiguousarray(layer.tau[box]),
                           np.full(gb.shape, layer.k * (1.0 if shift else dx)))
    # the iteration returns the slip's linear part and the stick mask of its last
    # iterate (C p accumulated from its products, no product more)
    qx, qy, cx, cy, sb, it, nprod, converged = ssn_solve(
        *q, sop, cb, tb, rho, (dxx, dyy), float(tol), int(maxiter))
    if layer is not None and not shift and layer.k != 0.0 and np.isfinite(layer.tau).any():
        # rolling with a hardening (softening) layer: each element's yield limit from
        # the flow upstream of it, the problem solved again until the limits settle
        sub = LayerBound(gb, np.ascontiguousarray(layer.tau[box]), layer.k, flex, layer.floor)
        gmax = max(float(gb.max()), 1e-300)
        # the update relaxed by omega, halved where it turns against the last one (an
        # oscillation: a stiff hardening) and grown by half (up to 1) where it does not
        omega, last = 1.0, None
        for _ in range(LAYER_ITERATIONS):
            S = np.hypot(q[2] + cx, q[3] + cy) * ~sb
            tau = _rolling_flow(sub, S, dx)[2]
            step = (np.minimum(tau, gb) - np.minimum(tb.tau, gb)) * cb
            change = float(np.max(np.abs(step))) / gmax
            log.debug("layer's yield limits: change %.3e (omega %.3f)", change, omega)
            if change <= LAYER_TOL:
                break
            if last is not None:
                omega = 0.5 * omega if float(np.sum(step * last)) < 0 else min(1.0, 1.5 * omega)
            if omega < 1e-4:
                # stalled (a very stiff hardening, k_tau dx of several times the
                # element's stiffness): flagged not converged
                converged = False
                break
            last = step
            tau = np.where(np.isfinite(tb.tau), tb.tau + omega * (tau - tb.tau), tau)
            tb = TractionBound(gb, np.ascontiguousarray(tau), tb.k)
            qx, qy, cx, cy, sb, it2, nprod, converged = ssn_solve(
                qx, qy, q[2], q[3], sop, cb, tb, rho, (dxx, dyy), float(tol), int(maxiter))
            it += it2
        else:
            converged = False
    log.debug("semi-smooth Newton: %d iterations, %d products with the Jacobian", it, nprod)
    sbx, sby = q[2] + cx, q[3] + cy
    if layer is not None:
        # the bound at the slip found (a hardening or softening yield limit)
        sx, sy = np.zeros((mx, my)), np.zeros((mx, my))
        sx[box], sy[box] = sbx, sby
        tau = np.full((mx, my), np.inf)
        tau[box] = tb.tau
        kk = np.zeros((mx, my))
        kk[box] = tb.k
        bound = _bound_at(bound, tau, kk, np.hypot(sx, sy))
    # the box's fields on the grid; in slip elements the traction on the bound exactly
    px, py, sx, sy, stick = _grid_fields((qx, qy, sbx, sby), sb, (box[0].start, box[1].start),
                                         contact, np.ascontiguousarray(bound, dtype=float))
    return px, py, sx, sy, stick, it, converged


@njit(cache=True, nogil=True)
def _contact_box(contact):
    """(i0, i1, j0, j1): the rows i0..i1-1 and columns j0..j1-1 of the smallest block
    holding every element of ``contact`` (:func:`~railcontact.normal.influence.bounding_box`,
    compiled; (0, 1, 0, 1) where there is none)."""
    i0, i1, j0, j1 = box_bounds(contact)
    if i1 < 0:
        return 0, 1, 0, 1
    return i0, i1 + 1, j0, j1 + 1


@njit(cache=True, nogil=True)
def _box_fields(contact, bound, p, creep, lines, box):
    """The fields of :func:`steady_rolling` on the contact's box ``box`` (i0, i1,
    j0, j1, rolling): contact, bound [Pa], the start's tractions ``p`` (px, py)
    [Pa] and the rigid slip w = (xi - phi y, eta + phi (x + x_off)) in the contact
    (zero outside; ``creep`` (xi, eta, phi, x_off), x_off added in rolling only),
    ``lines`` the grid's centres (x, y) [m]: the NumPy expressions' arithmetic
    element by element, the box alone (issue 30: the set-up of a warm-started
    solve)."""
    px, py = p
    xi, eta, phi, xoff = creep
    x, y = lines
    i0, i1, j0, j1, rolling = box
    ms, ns = i1 - i0, j1 - j0
    cb = np.empty((ms, ns), dtype=np.bool_)
    gb, qx, qy = np.empty((ms, ns)), np.empty((ms, ns)), np.empty((ms, ns))
    wx, wy = np.zeros((ms, ns)), np.zeros((ms, ns))
    for a in range(ms):
        i = i0 + a
        xs = x[i] + xoff if rolling else x[i]
        for b in range(ns):
            j = j0 + b
            c = contact[i, j]
            cb[a, b] = c
            gb[a, b] = bound[i, j]
            qx[a, b] = px[i, j]
            qy[a, b] = py[i, j]
            if c:
                wx[a, b] = xi - phi * y[j]
                wy[a, b] = eta + phi * xs
    return cb, gb, qx, qy, wx, wy


@njit(cache=True, nogil=True)
def _grid_fields(box_fields, stick_box, corner, contact, bound):
    """The tractions px, py [Pa], slip sx, sy and stick mask on the whole grid
    (``contact``'s shape) from those of its contact's bounding box (``box_fields``
    = (px, py, sx, sy) and ``stick_box`` there, its first element at ``corner``):
    zero outside the box, the slip zero outside the slip area (contact less stick),
    the stick mask within the contact, and in slip elements the traction scaled
    onto the bound ``bound`` [Pa] exactly (where it is not zero).  The arithmetic of
    the NumPy expressions it replaced, in one compiled loop (issue 30: the
    tangential solve's set-up around its iteration)."""
    qx, qy, qsx, qsy = box_fields
    mx, my = contact.shape
    px, py = np.zeros((mx, my)), np.zeros((mx, my))
    sx, sy = np.zeros((mx, my)), np.zeros((mx, my))
    stick = np.zeros((mx, my), dtype=np.bool_)
    i0, j0 = corner
    for a in range(qx.shape[0]):
        for b in range(qx.shape[1]):
            i, j = i0 + a, j0 + b
            tx, ty = qx[a, b], qy[a, b]
            st = stick_box[a, b]
            if contact[i, j] and not st:
                mag = np.hypot(tx, ty)
                if mag > 0:
                    scale = bound[i, j] / mag
                    tx, ty = tx * scale, ty * scale
                sx[i, j], sy[i, j] = qsx[a, b], qsy[a, b]
            px[i, j], py[i, j] = tx, ty
            stick[i, j] = st and contact[i, j]
    return px, py, sx, sy, stick


def grid_offset(origin_from, origin_to, element_size, shift=(0.0, 0.0)):
    """Index offset (di, dj) of a grid whose first element centre is ``origin_to``
    (moved by ``shift`` [m]) in a grid of the same element size whose first centre is
    ``origin_from``: element (i, j) of the first lies at element (i + di, j + dj) of
    the second.  The offset must be whole elements (CONTACT's transient cases: a
    grid moved by whole elements, a rolling step DQ of whole elements); InputError
    otherwise."""
    dx, dy = element_size
    fx = (origin_to[0] + shift[0] - origin_from[0]) / dx
    fy = (origin_to[1] + shift[1] - origin_from[1]) / dy
    di, dj = round(fx), round(fy)
    if abs(fx - di) > 1e-6 or abs(fy - dj) > 1e-6:
        raise InputError(f"transient step: the grid moved by {fx:.4f} x {fy:.4f} elements "
                         "relative to the previous step's material points; expected whole "
                         "elements")
    return int(di), int(dj)


def previous_displacement(px, py, offset, shape, dx, dy, G, nu):
    """Displacement difference u' = B p' [m] that the previous time step's tractions
    (px, py) [Pa] (body 1, on their own mx' x my' grid) cause at the elements of
    the current grid (``shape`` (mx, my)), whose element (i, j) lies at element
    (i + di, j + dj) of the previous grid (``offset``, :func:`grid_offset`).

    The influence coefficients are those of the steady solver (Cerruti, uniform
    tractions on rectangles); evaluated once per time step by FFT convolution on the
    union of both grids."""
    from scipy.signal import fftconvolve

    di, dj = offset
    m0, n0 = px.shape
    mx, my = shape
    lo_i, lo_j = min(0, di), min(0, dj)
    Mu, Nu = max(m0, di + mx) - lo_i, max(n0, dj + my) - lo_j
    kxx, kxy, kyy = tangential_kernels(Mu, Nu, dx, dy, G, nu)
    qx, qy = np.zeros((Mu, Nu)), np.zeros((Mu, Nu))
    qx[-lo_i:m0 - lo_i, -lo_j:n0 - lo_j] = px
    qy[-lo_i:m0 - lo_i, -lo_j:n0 - lo_j] = py
    # u[i] = sum_k K[i - k] q[k]: the full convolution's rows Mu-1 .. 2Mu-2
    conv = lambda k, q: fftconvolve(q, k, mode="full")[Mu - 1:2 * Mu - 1, Nu - 1:2 * Nu - 1]  # noqa: E731
    ux = conv(kxx, qx) + conv(kxy, qy)
    uy = conv(kxy, qx) + conv(kyy, qy)
    cut = (slice(di - lo_i, di - lo_i + mx), slice(dj - lo_j, dj - lo_j + my))
    return np.ascontiguousarray(ux[cut]), np.ascontiguousarray(uy[cut])


def leading_edge(contact, dx, step):
    """CONTACT's leading-edge correction of a transient rolling step (T = 2, rolling
    towards +x over ``step`` [m] per time step; Vollebregt, CONTACT user guide and
    its m_leadedge module): material within one step of the leading edge entered
    the contact during the step.

    In each grid row the leading edge lies one element beyond every element in
    contact whose neighbour ahead (+x) is not in contact (or that ends the grid),
    at x_b = x_0 + dx.  An element in contact at x behind it has been in the contact
    for the fraction f = min(1, (x_b - x) / step) of the step; where f < 1 its
    rigid shift is f W and its previous displacement is that at the leading edge
    (the previous tractions' displacement at the element x_0 + dx, on the current
    grid) instead of the one at its own place one step before.  Elements in the
    last two columns keep f = 1 (no room for the edge).

    Parameters
    ----------
    contact : ndarray of bool, shape (mx, my)
        Elements in contact (x along the first axis).
    dx : float
        Element size along x [m].
    step : float
        Rolling distance per time step [m]: > 0 rolling towards +x, < 0 towards -x
        (CHI = 180 deg: the leading edge on the -x side, the rule mirrored).

    Returns
    -------
    facdt : ndarray, shape (mx, my)
        The fraction f (1 outside the contact and away from the leading edge).
    edge : ndarray of int, shape (mx, my)
        Index along x of the element x_0 + dx at which the boundary displacement
        is taken where f < 1; -1 where f = 1; -2 where x_0 + dx lies in the last
        column or beyond it (the boundary displacement is then taken as zero).
    """
    contact = np.asarray(contact, bool)
    mx = contact.shape[0]
    if step < 0:
        facdt, edge = leading_edge(contact[::-1], dx, -step)
        return facdt[::-1].copy(), np.where(edge >= 0, mx - 1 - edge, edge)[::-1].copy()
    ahead = np.zeros_like(contact)
    ahead[:-1] = contact[1:]
    last = contact & ~ahead                                   # x_0 of each edge
    idx = np.arange(mx)[:, None]
    big = np.where(last, idx, mx + 10)
    x0 = np.minimum.accumulate(big[::-1], axis=0)[::-1]      # next edge ahead (or at) i
    frac = np.minimum(1.0, (x0 - idx + 1) * dx / step)
    near = contact & (frac < 0.9999) & (idx < mx - 2) & (x0 < mx)
    facdt = np.where(near, frac, 1.0)
    edge = np.where(near, np.where(x0 >= mx - 2, -2, x0 + 1), -1)
    return facdt, edge


def leading_edge_slip(contact, dx, step, w, u, u_here=None):
    """The rigid shift ``w`` (w_x, w_y) [m] and previous displacement ``u`` (u'_x,
    u'_y) [m] of a rolling step (``step`` [m], :func:`leading_edge`) with CONTACT's
    leading-edge correction: where the material entered the contact during the
    step, f w and the previous displacement at the leading edge, taken from
    ``u_here`` (the previous tractions' displacement where they acted, on the
    current grid; None: no previous tractions, zero)."""
    facdt, edge = leading_edge(contact, dx, step)
    near = edge != -1
    if not near.any():
        return w, u
    w = (w[0] * facdt, w[1] * facdt)
    ubx, uby = np.zeros(contact.shape), np.zeros(contact.shape)
    if u_here is not None:
        cols = np.broadcast_to(np.arange(contact.shape[1])[None, :], contact.shape)
        at = near & (edge >= 0)
        ubx[at] = u_here[0][edge[at], cols[at]]
        uby[at] = u_here[1][edge[at], cols[at]]
    return w, (np.where(near, ubx, u[0]), np.where(near, uby, u[1]))


def shifted_tractions(px, py, offset, shape):
    """The previous tractions on the current grid (element (i, j) from element
    (i + di, j + dj) of the previous grid; zero where it has none)."""
    di, dj = offset
    m0, n0 = px.shape
    mx, my = shape
    qx, qy = np.zeros(shape), np.zeros(shape)
    i0, i1 = max(0, -di), min(mx, m0 - di)
    j0, j1 = max(0, -dj), min(my, n0 - dj)
    if i0 < i1 and j0 < j1:
        qx[i0:i1, j0:j1] = px[i0 + di:i1 + di, j0 + dj:j1 + dj]
        qy[i0:i1, j0:j1] = py[i0 + di:i1 + di, j0 + dj:j1 + dj]
    return qx, qy


def transient_step(x, y, contact, bound, rigid_shift, u_prev, G, nu, tol=1e-7, maxiter=60,
                   p0=None):
    """One time step of a transient problem (CONTACT's T = 1, shift or rolling with
    material-fixed coordinates, and T = 2, rolling with contact-fixed coordinates):
    the slip over the step of element I,

        s_I = W_I + u_I - u'_I,        u = B p,

    with W the rigid shift [m] of body 1 over the step (per element: (W_x, W_y)),
    u the displacement difference of the current tractions and u' that of the
    previous step's tractions at the same material points (:func:`previous_displacement`;
    for rolling, at the position the material had one step DQ before).  Kalker
    (1990), sec. 2.2 and 5.2; Cattaneo's shift from the unloaded state is u' = 0.
    It is the shift mode of :func:`steady_rolling` (the same semi-smooth Newton
    iteration and influence coefficients), with the rigid shift and -u' as its
    extra slip.

    ``bound``: as in :func:`steady_rolling` (an array, or a :class:`LayerBound`,
    whose layer's own displacement f p' the caller includes in ``u_prev``).

    Returns px, py [Pa] (body 1), slip sx, sy [m] per step, stick mask, Newton
    iterations, converged.
    """
    wx = np.asarray(rigid_shift[0], dtype=float) - u_prev[0]
    wy = np.asarray(rigid_shift[1], dtype=float) - u_prev[1]
    if p0 is not None:
        g = np.minimum(bound.g, bound.tau) if isinstance(bound, LayerBound) else bound
        mag = np.hypot(p0[0], p0[1])
        with np.errstate(invalid="ignore", divide="ignore"):
            scale = np.where(mag > g, g / np.where(mag > 0, mag, 1.0), 1.0)
        p0 = (np.ascontiguousarray(np.where(contact, p0[0] * scale, 0.0)),
              np.ascontiguousarray(np.where(contact, p0[1] * scale, 0.0)))
    return steady_rolling(x, y, contact, bound, (0.0, 0.0, 0.0), G, nu, tol, maxiter, p0=p0,
                          mode="shift", w_extra=(np.broadcast_to(wx, contact.shape),
                                                 np.broadcast_to(wy, contact.shape)))


def _initial_tractions(warm, x, y, contact, bound):
    """Tractions on the rail (body 1) from a previous solution ``warm``: on the same
    grid as they are, on another grid interpolated (linear, zero outside); inside
    the contact and within the traction bound."""
    bound = np.ascontiguousarray(bound, dtype=float)
    if same_grid(warm.x, warm.y, x, y):
        return _bounded_start(np.ascontiguousarray(-warm.traction_x, dtype=float),
                              np.ascontiguousarray(-warm.traction_y, dtype=float), contact,
                              bound)
    # bilinear (:func:`~railcontact.normal.base.bilinear`'s arithmetic) at this grid's
    # centres, the fractional indices of its lines in the warm start's grid
    wx, wy = warm.x, warm.y
    u = np.ascontiguousarray((x - wx[0]) / (wx[1] - wx[0]), dtype=float)
    v = np.ascontiguousarray((y - wy[0]) / (wy[1] - wy[0]), dtype=float)
    return _interpolated_start((np.ascontiguousarray(warm.traction_x, dtype=float),
                                np.ascontiguousarray(warm.traction_y, dtype=float)),
                               (u, v), contact, bound)


@njit(cache=True, nogil=True)
def _interpolated_start(fields, lines, contact, bound):
    """The tractions on body 1 [Pa] of a warm start's ``fields`` (traction_x,
    traction_y on body 2, on their own grid) bilinear at the fractional indices
    ``lines`` (u, v) of this grid's centres (zero outside its centres), inside the
    contact (zero outside) and scaled onto ``bound`` [Pa] where they exceed it: the
    interpolation over the contact's elements, then :func:`_bounded_start`
    (issue 30: a new grid's warm start)."""
    fx, fy = fields
    u, v = lines
    tx, ty = np.zeros(contact.shape), np.zeros(contact.shape)
    for i in range(contact.shape[0]):
        for j in range(contact.shape[1]):
            if contact[i, j]:
                tx[i, j] = -bilinear_at(fx, u[i], v[j])
                ty[i, j] = -bilinear_at(fy, u[i], v[j])
    return _bounded_start(tx, ty, contact, bound)


@njit(cache=True, nogil=True)
def _bounded_start(tx, ty, contact, bound):
    """The tractions (tx, ty) [Pa] inside the contact (zero outside) and scaled onto
    the bound ``bound`` [Pa] where they exceed it (one compiled loop, issue 30)."""
    ox, oy = np.zeros(tx.shape), np.zeros(tx.shape)
    for i in range(tx.shape[0]):
        for j in range(tx.shape[1]):
            if contact[i, j]:
                a, b = tx[i, j], ty[i, j]
                mag = np.hypot(a, b)
                if mag > bound[i, j]:
                    s = bound[i, j] / mag
                    a, b = a * s, b * s
                ox[i, j], oy[i, j] = a, b
    return ox, oy


@dataclass(frozen=True)
class _Iteration:
    """How the exact tangential solver ended."""

    #: Newton iterations (or time steps' iterations, transient)
    iterations: int
    converged: bool
    #: whether it restarted from zero traction
    fallback: bool


@register("exact")
class ExactTangentialModel:
    """Kalker's exact theory of steady-state rolling (identical materials).

    Parameters
    ----------
    tol : float      convergence: largest complementarity residual
                     |p - Proj(p - rho s)| / largest bound (default 1e-5; what it
                     costs in accuracy: docs/tuning.md, section "Tangential: exact")
    maxiter : int    limit of Newton iterations
    mode : {"rolling", "shift", "transient"}
        ``"rolling"``: steady-state rolling with creepages (xi, eta, phi).
        ``"shift"``: transient shift from the unloaded state (Cattaneo-Mindlin); the
        "creepage" argument is then the rigid shift (dx [m], dy [m], rotation [rad])
        of the rail relative to the wheel, and the slip a displacement [m].
        ``"transient"``: one time step of a transient problem from the previous
        step's solution (``solve(..., previous=...)``; :func:`transient_step`):
        with ``step = 0`` a shift (CONTACT's T = 1; "creepage" the rigid shift of
        the step as in ``"shift"``), with ``step > 0`` rolling over that distance
        [m] on a contact-fixed grid (T = 2; "creepage" the creepages, the rigid
        shift step times them).  Without ``previous`` the step starts from the
        unloaded state.
    step : float
        Rolling distance [m] per time step of the ``"transient"`` mode (0: a
        shift); a whole number of elements.
    layer : InterfaceLayer or dict, optional
        An interfacial (third-body) layer between the bodies with a plastic yield
        limit (CONTACT's M = 4, :class:`~railcontact.core.materials.InterfaceLayer`;
        a dict of its fields ``thickness`` [m], ``shear_modulus`` [Pa],
        ``yield_stress`` [Pa], ``hardening`` [Pa/m]): its flexibility adds to each
        element's own, and the traction is bounded by the yield limit where that
        lies under the friction bound (:class:`LayerBound`).  In the
        ``"transient"`` mode the plastic displacement accumulated so far comes
        with ``previous`` (its ``options["plastic_displacement"]``).
    viscoelastic : dict or ViscoelasticOption, optional
        Steady rolling (``"rolling"``) of viscoelastic bodies (the standard linear
        solid, CONTACT's M = 1): ``spring_ratio``, ``relaxation_time`` [s] and
        ``velocity`` [m/s] (:class:`~railcontact.normal.viscoelastic.ViscoelasticOption`;
        the material's moduli the initial ones): the hereditary influence
        coefficients of :mod:`railcontact.normal.viscoelastic` replace the elastic ones.
    """

    capabilities = frozenset({"warm-start", "coupled", "lazy", "friction-field", "extra-slip"})

    def __init__(self, tol: float = 1e-5, maxiter: int = 60, mode: str = "rolling",
                 step: float = 0.0, layer: InterfaceLayer | dict | None = None,
                 viscoelastic=None):
        if not 0 < tol < 1e-2:
            raise InputError(f"exact tangential tol {tol!r}: expected a value in (0, 0.01)")
        if mode not in ("rolling", "shift", "transient"):
            raise InputError(f"exact tangential mode {mode!r}: expected 'rolling' (steady "
                             "rolling), 'shift' (transient shift, Cattaneo) or 'transient' "
                             "(a time step from the previous one)")
        if not (isinstance(step, (int, float)) and math.isfinite(step) and step >= 0):
            raise InputError(f"exact tangential step {step!r} m: expected a rolling distance "
                             ">= 0 (0: a shift)")
        self.tol, self.maxiter, self.mode, self.step = tol, int(maxiter), mode, float(step)
        if isinstance(layer, dict):
            known = {"thickness", "shear_modulus", "yield_stress", "hardening"}
            if set(layer) - known:
                raise InputError(f"exact tangential layer keys {sorted(set(layer) - known)}: "
                                 f"expected some of {sorted(known)}")
            layer = InterfaceLayer(**{k: float(v) if isinstance(v, int) and
                                      not isinstance(v, bool) else v
                                      for k, v in layer.items()})
        elif layer is not None and not isinstance(layer, InterfaceLayer):
            raise InputError(f"exact tangential layer {layer!r}: expected an InterfaceLayer or "
                             "a dict of its fields")
        self.layer = layer
        self.viscoelastic = ViscoelasticOption.from_value(viscoelastic)
        if self.viscoelastic is not None and mode != "rolling":
            raise InputError(f"exact tangential mode {mode!r} with viscoelastic materials: "
                             "expected steady rolling ('rolling'), as CONTACT solves them")
        if self.viscoelastic is not None and self.layer is not None:
            raise InputError("exact tangential model with both an interfacial layer and "
                             "viscoelastic materials: expected one of them (CONTACT's M = 4 "
                             "or M = 1)")

    def _transient(self, x, y, contact, bound, creepage, material, previous, extra_slip=None):
        """One step of the ``"transient"`` mode: (px, py, sx, sy, stick, it, ok) and
        the options it adds to the solution (an interfacial layer's plastic
        displacement).  ``extra_slip`` (w_x, w_y) per element adds to the creepages'
        rigid slip as they do: times the step for rolling, a shift [m] for a shift."""
        xi, eta, phi = creepage
        dx, dy = float(x[1] - x[0]), float(y[1] - y[0])
        X, Y = x[:, None], y[None, :]
        h = self.step
        ex, ey = (0.0, 0.0) if extra_slip is None else extra_slip
        if h > 0:
            w = (h * (xi - phi * Y + ex), h * (eta + phi * (X + h / 6.0) + ey))
        else:
            w = (xi - phi * Y + ex, eta + phi * X + ey)
        w = tuple(np.broadcast_to(c, contact.shape) for c in w)
        G, nu = material.shear_modulus, material.nu
        zero = np.zeros(contact.shape)
        u, p0, ustar = (zero, zero), None, None
        if previous is not None:
            if previous.x.size < 2 or previous.y.size < 2 or \
                    abs(float(previous.x[1] - previous.x[0]) - dx) > 1e-9 * dx or \
                    abs(float(previous.y[1] - previous.y[0]) - dy) > 1e-9 * dy:
                raise InputError("transient step: the previous solution's element size "
                                 "differs; expected the same grid spacing")
            off = grid_offset((float(previous.x[0]), float(previous.y[0])),
                              (float(x[0]), float(y[0])), (dx, dy), (h, 0.0))
            qx, qy = -previous.traction_x, -previous.traction_y       # on the rail
            u = previous_displacement(qx, qy, off, contact.shape, dx, dy, G, nu)
            p0 = shifted_tractions(qx, qy, off, contact.shape)
            if self.layer is not None:
                f = self.layer.flexibility
                u = (u[0] + f * p0[0], u[1] + f * p0[1])
                prev_u = previous.options.get("plastic_displacement")
                if prev_u is not None:
                    ustar = shifted_tractions(np.asarray(prev_u), zero, off, contact.shape)[0]
        if h > 0:
            w, u = self._leading_edge((x, y, contact), w, u, previous, material)
        if self.layer is not None:
            bound = layer_bound(self.layer, bound, ustar)
        out = transient_step(x, y, contact, bound, w, u, G, nu, self.tol, self.maxiter, p0=p0)
        extra = {}
        if self.layer is not None:
            # the plastic displacement the material has accumulated [m], for the next step
            inc = plastic_flow(bound, out[2], out[3], dx, False)[0]
            extra["plastic_displacement"] = inc if ustar is None else ustar + inc
        return out, extra

    def _leading_edge(self, grid, w, u, previous, material):
        """A rolling step's rigid shift ``w`` and previous displacement ``u`` with
        CONTACT's leading-edge correction (:func:`leading_edge_slip`) on ``grid``
        (x, y, contact)."""
        x, y, contact = grid
        dx, dy = float(x[1] - x[0]), float(y[1] - y[0])
        here = None
        if previous is not None and (leading_edge(contact, dx, self.step)[1] != -1).any():
            # the previous tractions' displacement where they acted (no shift)
            off = grid_offset((float(previous.x[0]), float(previous.y[0])),
                              (float(x[0]), float(y[0])), (dx, dy))
            qx, qy = -previous.traction_x, -previous.traction_y
            here = previous_displacement(qx, qy, off, contact.shape, dx, dy,
                                         material.shear_modulus, material.nu)
            if self.layer is not None:
                px, py = shifted_tractions(qx, qy, off, contact.shape)
                f = self.layer.flexibility
                here = (here[0] + f * px, here[1] + f * py)
        return leading_edge_slip(contact, dx, self.step, w, u, here)

    def solve(self, normal, geometry=None, material: Material = STEEL, creepage=(0.0, 0.0, 0.0),
              friction: float = 0.3, velocity: float = 1.0,
              warm_start: TangentialSolution | None = None,
              extra_slip=None, previous: TangentialSolution | None = None,
              friction_scale=None) -> TangentialSolution:
        """Creep forces for creepages (xi [-], eta [-], phi [1/m]) on the normal
        solution's grid.  ``warm_start``: a previous solution (e.g. of a neighbouring
        case, on this grid or interpolated from its own) used as the initial
        estimate; without it, FASTSIM's solution is.  ``previous``: the last time
        step's solution (``"transient"`` mode), whose tractions enter the slip at
        the same material points.  ``friction_scale``: friction varying across the
        patch, each element's coefficient ``friction`` times this array's value
        (broadcast to the normal solution's grid, e.g. one value per column;
        CONTACT's friction along the track, a conformal patch's coefficients by the
        local angle); ``friction`` stays the patch's reported coefficient.
        ``extra_slip``: a rigid slip (w_x, w_y) per element beside the creepages' (a
        conformal patch's, dissimilar materials'); in the ``"transient"`` mode it
        is read as the creepages are (times ``step`` in rolling, a shift [m] in a
        shift)."""
        t0 = time.perf_counter()
        xi, eta, phi = check_inputs(creepage, friction)
        x, y = normal.x, normal.y
        if x.size < 2 or y.size < 2:
            raise InputError("exact tangential solver needs a grid of at least 2 x 2 elements")
        contact = np.ascontiguousarray(normal.contact & (normal.pressure > 0))
        mu = friction
        if friction_scale is not None:
            scale = np.asarray(friction_scale, float)
            try:
                scale = np.broadcast_to(scale, contact.shape)
            except ValueError:
                scale = None
            if scale is None or not np.all(np.isfinite(scale)) or np.any(scale < 0):
                raise InputError(f"friction_scale of shape {np.shape(friction_scale)}: expected "
                                 f"finite values >= 0 on (or broadcast to) the normal "
                                 f"solution's grid {contact.shape}")
            mu = friction * scale
        bound = np.ascontiguousarray(mu * np.where(contact, normal.pressure, 0.0))
        if previous is not None and self.mode != "transient":
            raise InputError(f"a previous time step's solution is used by the 'transient' "
                             f"mode; this model's mode is {self.mode!r}")
        # Blanco's coefficients (steady rolling or a shift of elastic bodies without
        # a layer: the case parser rejects the others)
        angles = None if geometry is None else influence_angles(geometry, y)
        if self.mode == "transient":
            if extra_slip is not None:
                extra_slip = tuple(np.broadcast_to(np.asarray(e, float), contact.shape)
                                   for e in extra_slip)
            (px, py, sx, sy, stick, it, ok), extra = self._transient(
                x, y, contact, bound, (xi, eta, phi), material, previous, extra_slip)
            return self._solution(x, y, (px, py, sx, sy, stick), contact,
                                  _Iteration(it, ok, False), velocity, (xi, eta, phi),
                                  friction, t0, extra)
        p0 = None
        if warm_start is None and self.mode == "rolling" and normal.strips is not None \
                and normal.pressure_at is not None:
            # initial estimate from simplified theory (seed 000: an initial estimate of the
            # contact area "significantly accelerates the convergence"): FASTSIM has the
            # right global stiffness, so Newton starts close to the solution
            try:
                warm_start = FastsimModel().solve(normal, geometry, material, (xi, eta, phi),
                                                  friction, velocity)
            except Exception as exc:                      # pragma: no cover - fallback
                log.debug("no FASTSIM initial estimate: %s", exc)
        if self.layer is not None:
            bound = layer_bound(self.layer, bound)
        g0 = bound if self.layer is None else np.minimum(bound.g, bound.tau)
        if warm_start is not None:
            p0 = _initial_tractions(warm_start, x, y, contact, g0)
        G = material.shear_modulus
        if self.viscoelastic is not None:
            if extra_slip is not None:
                raise InputError("viscoelastic materials with dissimilar elastic constants: "
                                 "expected quasi-identical bodies")
            G = self.viscoelastic.pair(material)     # its steady-rolling kernels
        if angles is not None:
            G = TurnedElastic(G, angles)
        args = (x, y, contact, bound, (xi, eta, phi), G, material.nu, self.tol)
        px, py, sx, sy, stick, it, ok = steady_rolling(*args, self.maxiter, p0=p0, mode=self.mode,
                                                       w_extra=extra_slip)
        fallback = False
        if not ok:
            # fall back: restart from zero traction with damped steps and more iterations
            log.info("exact tangential solver: no convergence in %d iterations; restarting "
                     "from zero traction with %d iterations", it, 4 * self.maxiter)
            q = steady_rolling(*args, 4 * self.maxiter, p0=(np.zeros_like(g0),
                                                               np.zeros_like(g0)),
                               mode=self.mode, w_extra=extra_slip)
            fallback = True
            if q[-1] or not ok:
                px, py, sx, sy, stick, it, ok = q
        return self._solution(x, y, (px, py, sx, sy, stick), contact,
                              _Iteration(it, ok, fallback), velocity, (xi, eta, phi), friction,
                              t0)

    def _solution(self, x, y, fields, contact, iteration, velocity, creepage, friction,
                  t0, extra=None) -> TangentialSolution:
        """The TangentialSolution of tractions (px, py) on the rail: ``fields`` (px,
        py [Pa], sx, sy [-], stick) on the grid (x, y) [m], ``iteration`` how the
        solver ended (:class:`_Iteration`), ``t0`` its start (``time.perf_counter``),
        ``extra`` further entries of its options."""
        px, py, sx, sy, stick = fields
        it, ok, fallback = iteration.iterations, iteration.converged, iteration.fallback
        if not ok:
            log.info("exact tangential solver: not converged (flagged in the result)")
        status = SolverStatus(True, "", int(it)) if ok else SolverStatus.failed(
            f"exact tangential solver: no convergence in {it} Newton iterations"
            + (" (also restarted from zero traction)" if fallback else ""), it)
        dA = (x[1] - x[0]) * (y[1] - y[0])
        fx, fy = float(px.sum() * dA), float(py.sum() * dA)
        mz = float(((x[:, None] * py) - (y[None, :] * px)).sum() * dA)
        options = {"iterations": it, "fallback": fallback, "mode": self.mode}
        if self.mode == "transient":
            options["step"] = self.step
        options.update(extra or {})
        return TangentialSolution("exact", x, y, -px, -py, sx, sy, stick, contact, -fx, -fy,
                                  -mz, velocity, creepage, friction,
                                  time.perf_counter() - t0, options, status)
