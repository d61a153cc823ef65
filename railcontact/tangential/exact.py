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

The whole iteration (Newton steps, GMRES, line search) runs compiled with Numba,
its FFT products by rocket-fft's ``numpy.fft`` support for Numba, on the bounding
box of the contact (outside it the tractions are zero and the slip is not needed),
with the grid's kernels cut to the box.
"""

from __future__ import annotations

import logging
import math
import time
from functools import lru_cache

import numpy as np
from numba import njit

from ..errors import InputError
from ..materials import Material, STEEL
from ..normal.base import bilinear, same_grid
from ..normal.influence import (TangentialOperator, block_size, bounding_box,
                                tangential_kernels)
from ..status import SolverStatus
from .base import TangentialSolution, check_inputs, register
from .fastsim import FastsimModel

log = logging.getLogger(__name__)


@njit(cache=True, nogil=True)
def _local_slip(rx, ry, dxx, dyy, g):
    """Local problem of one element: slip s = r + D p, D = diag(dxx, dyy).

    Stick: p = -D^-1 r if |p| <= g; else slip with p = -g s / |s|, where |s| = t
    solves sum_k (r_k / (1 + g d_k / t))^2 = t^2.  Returns px, py, ex, ey, stick
    (e the unit slip direction).
    """
    px = -rx / dxx
    py = -ry / dyy
    if px * px + py * py <= g * g:
        return px, py, 0.0, 0.0, True
    lo, hi = 0.0, math.sqrt(rx * rx + ry * ry)
    if g <= 0.0 or hi == 0.0:
        return 0.0, 0.0, 0.0, 0.0, False
    t = hi
    for _ in range(200):
        vx = rx / (1.0 + g * dxx / t)
        vy = ry / (1.0 + g * dyy / t)
        f = vx * vx + vy * vy - t * t
        if f > 0.0:
            lo = t
        else:
            hi = t
        dvx = rx * g * dxx / (t + g * dxx) ** 2
        dvy = ry * g * dyy / (t + g * dyy) ** 2
        fp = 2.0 * (vx * dvx + vy * dvy) - 2.0 * t
        tn = t - f / fp if fp != 0.0 else 0.5 * (lo + hi)
        if not (lo < tn < hi):
            tn = 0.5 * (lo + hi)
        if abs(tn - t) <= 1e-15 * (hi + t):
            t = tn
            break
        t = tn
    sx = rx / (1.0 + g * dxx / t)
    sy = ry / (1.0 + g * dyy / t)
    n = math.sqrt(sx * sx + sy * sy)
    return -g * sx / n, -g * sy / n, sx / n, sy / n, False


@njit(cache=True, nogil=True)
def _initial_march(wx, wy, contact, bound, dxx, dyy):
    """Initial tractions: every strip marched from the leading edge with only the
    element's own and upstream coupling (simplified theory with the exact element
    flexibility), solving the local friction problem element by element."""
    mx, my = wx.shape
    px = np.zeros((mx, my))
    py = np.zeros((mx, my))
    for j in range(my):
        ux = 0.0
        uy = 0.0
        for i in range(mx - 1, -1, -1):
            if not contact[i, j]:
                ux = 0.0
                uy = 0.0
                continue
            # s_I = w_I + D p_I - D p_I+
            rx = wx[i, j] - dxx * ux
            ry = wy[i, j] - dyy * uy
            qx, qy, _, _, _ = _local_slip(rx, ry, dxx, dyy, bound[i, j])
            px[i, j] = qx
            py[i, j] = qy
            ux = qx
            uy = qy
    return px, py


@njit(cache=True, nogil=True)
def _ssn_blocks(px, py, sx, sy, contact, bound, rho):
    """Residual F and the 2x2 blocks M of the generalised Jacobian.

    F = p - Proj(p - rho s).  Stick (|v| <= g, v = p - rho s): F = rho s, row
    rho C.  Slip: F = p - g v/|v|, row I - M (I - rho C), M = g/|v| (I - v v^T/|v|^2).
    Returned: F (mx, my, 2), M (mx, my, 2, 2) and the stick mask.
    """
    mx, my = px.shape
    F = np.zeros((mx, my, 2))
    M = np.zeros((mx, my, 2, 2))
    stick = np.zeros((mx, my), dtype=np.bool_)
    for i in range(mx):
        for j in range(my):
            if not contact[i, j]:
                F[i, j, 0] = px[i, j]
                F[i, j, 1] = py[i, j]
                continue
            vx = px[i, j] - rho * sx[i, j]
            vy = py[i, j] - rho * sy[i, j]
            nv = math.sqrt(vx * vx + vy * vy)
            g = bound[i, j]
            if nv <= g:
                stick[i, j] = True
                F[i, j, 0] = rho * sx[i, j]
                F[i, j, 1] = rho * sy[i, j]
            else:
                F[i, j, 0] = px[i, j] - g * vx / nv
                F[i, j, 1] = py[i, j] - g * vy / nv
                f = g / nv
                ex = vx / nv
                ey = vy / nv
                M[i, j, 0, 0] = f * (1.0 - ex * ex)
                M[i, j, 0, 1] = -f * ex * ey
                M[i, j, 1, 0] = -f * ex * ey
                M[i, j, 1, 1] = f * (1.0 - ey * ey)
    return F, M, stick


@njit(cache=True, nogil=True)
def _ssn_apply(zx, zy, cx, cy, contact, stick, M, rho):
    """J z from z and C z (both fields)."""
    mx, my = zx.shape
    ox = np.zeros((mx, my))
    oy = np.zeros((mx, my))
    for i in range(mx):
        for j in range(my):
            if not contact[i, j]:
                ox[i, j] = zx[i, j]
                oy[i, j] = zy[i, j]
            elif stick[i, j]:
                ox[i, j] = rho * cx[i, j]
                oy[i, j] = rho * cy[i, j]
            else:
                ax = zx[i, j] - rho * cx[i, j]
                ay = zy[i, j] - rho * cy[i, j]
                ox[i, j] = zx[i, j] - (M[i, j, 0, 0] * ax + M[i, j, 0, 1] * ay)
                oy[i, j] = zy[i, j] - (M[i, j, 1, 0] * ax + M[i, j, 1, 1] * ay)
    return ox, oy


@njit(cache=True, nogil=True)
def _ssn_precond(rx, ry, contact, stick, M, rho, dxx, dyy, upstream):
    """Solve P z = r, P the Jacobian with C replaced by its self and upstream part
    (C z)_I ~ D (z_I - z_I+): block lower-bidiagonal along each strip.  Without
    ``upstream`` (the shift problem) C is replaced by its self term D only."""
    mx, my = rx.shape
    zx = np.zeros((mx, my))
    zy = np.zeros((mx, my))
    for j in range(my):
        ux = 0.0
        uy = 0.0
        for i in range(mx - 1, -1, -1):
            if not contact[i, j]:
                zx[i, j] = rx[i, j]
                zy[i, j] = ry[i, j]
                ux = 0.0
                uy = 0.0
                continue
            if stick[i, j]:
                # rho D (z - u) = r
                zx[i, j] = rx[i, j] / (rho * dxx) + ux
                zy[i, j] = ry[i, j] / (rho * dyy) + uy
            else:
                # z - M (z - rho D (z - u)) = r  ->  (I - M + rho M D) z = r + rho M D u
                a00 = 1.0 - M[i, j, 0, 0] + rho * M[i, j, 0, 0] * dxx
                a01 = -M[i, j, 0, 1] + rho * M[i, j, 0, 1] * dyy
                a10 = -M[i, j, 1, 0] + rho * M[i, j, 1, 0] * dxx
                a11 = 1.0 - M[i, j, 1, 1] + rho * M[i, j, 1, 1] * dyy
                bx = rx[i, j] + rho * (M[i, j, 0, 0] * dxx * ux + M[i, j, 0, 1] * dyy * uy)
                by = ry[i, j] + rho * (M[i, j, 1, 0] * dxx * ux + M[i, j, 1, 1] * dyy * uy)
                det = a00 * a11 - a01 * a10
                zx[i, j] = (a11 * bx - a01 * by) / det
                zy[i, j] = (-a10 * bx + a00 * by) / det
            if upstream:
                ux = zx[i, j]
                uy = zy[i, j]
    return zx, zy


@njit(cache=True, nogil=True)
def _c_of(px, py, kxx, kxy, kyy, shape, bx, by, dx, shift):
    """The linear part of the slip, s - w, from tractions (px, py): rolling
    -(u_I+ - u_I)/dx, shift u_I (FFT products; bx, by the zero-padded work arrays)."""
    mx, my = px.shape
    bx[:mx, :my] = px
    by[:mx, :my] = py
    fx = np.fft.rfft2(bx)
    fy = np.fft.rfft2(by)
    # the kernel products in place, in one pass: fx <- kxx fx + kxy fy, fy <- ...
    for i in range(fx.shape[0]):
        for j in range(fx.shape[1]):
            a = fx[i, j]
            b = fy[i, j]
            c = kxy[i, j]
            fx[i, j] = kxx[i, j] * a + c * b
            fy[i, j] = c * a + kyy[i, j] * b
    ux = np.fft.irfft2(fx, s=shape)
    uy = np.fft.irfft2(fy, s=shape)
    cx = np.empty((mx, my))
    cy = np.empty((mx, my))
    for i in range(mx):
        for j in range(my):
            if shift:
                cx[i, j] = ux[i, j]
                cy[i, j] = uy[i, j]
            else:
                cx[i, j] = -(ux[i + 1, j] - ux[i, j]) / dx
                cy[i, j] = -(uy[i + 1, j] - uy[i, j]) / dx
    return cx, cy


@njit(cache=True, nogil=True)
def _unpack(v, cidx, mx, my):
    """Fields (z_x, z_y) on the grid from the stacked vector v of their values at the
    contact elements ``cidx`` (flat indices); zero elsewhere."""
    nc = cidx.size
    zx = np.zeros(mx * my)
    zy = np.zeros(mx * my)
    for k in range(nc):
        zx[cidx[k]] = v[k]
        zy[cidx[k]] = v[nc + k]
    return zx.reshape((mx, my)), zy.reshape((mx, my))


@njit(cache=True, nogil=True)
def _pack(ax, ay, cidx):
    """The stacked vector of two fields' values at the contact elements ``cidx``."""
    nc = cidx.size
    fx = ax.ravel()
    fy = ay.ravel()
    out = np.empty(2 * nc)
    for k in range(nc):
        out[k] = fx[cidx[k]]
        out[nc + k] = fy[cidx[k]]
    return out


@njit(cache=True, nogil=True)
def _jacobian_times(v, cidx, mx, my, kxx, kxy, kyy, shape, bx, by, dx, shift, contact, stick,
                    M, rho):
    """J v for the stacked vector v of the unknowns at the contact elements (outside
    the contact J is the identity and the Newton steps are zero), and C v there (the
    linear part of the slip, which the Newton iteration accumulates)."""
    zx, zy = _unpack(v, cidx, mx, my)
    cx, cy = _c_of(zx, zy, kxx, kxy, kyy, shape, bx, by, dx, shift)
    ox, oy = _ssn_apply(zx, zy, cx, cy, contact, stick, M, rho)
    return _pack(ox, oy, cidx), _pack(cx, cy, cidx)


@njit(cache=True, nogil=True)
def _precond_times(v, cidx, mx, my, contact, stick, M, rho, dxx, dyy, shift):
    """P^-1 v for the stacked vector v of the unknowns at the contact elements."""
    zx, zy = _unpack(v, cidx, mx, my)
    ox, oy = _ssn_precond(zx, zy, contact, stick, M, rho, dxx, dyy, not shift)
    return _pack(ox, oy, cidx)


@njit(cache=True, nogil=True)
def _newton_step(b, rtol, restart, maxcycles, cidx, mx, my, kxx, kxy, kyy, shape, bx, by,
                 dx, shift, contact, stick, M, rho, dxx, dyy):
    """Solve J d = b to ||b - J d|| <= rtol ||b|| by restarted GMRES (Saad & Schultz
    1986) with right preconditioning by P (flexible form: the preconditioned
    directions are kept, Saad 1993); Givens rotations, Gram-Schmidt twice.
    Returns d, C d (from the products with the kept directions) and the number of
    products with J."""
    n = b.size
    x = np.zeros(n)
    cx = np.zeros(n)
    bnorm = np.sqrt(np.dot(b, b))
    nprod = 0
    if bnorm == 0.0:
        return x, cx, nprod
    V = np.empty((restart + 1, n))       # every row is written before it is read
    Z = np.empty((restart, n))
    CZ = np.empty((restart, n))          # C of the directions
    H = np.zeros((restart + 1, restart))
    cs = np.zeros(restart)
    sn = np.zeros(restart)
    gv = np.zeros(restart + 1)
    r = b.copy()
    for cycle in range(maxcycles):
        if cycle > 0:
            r = b - _jacobian_times(x, cidx, mx, my, kxx, kxy, kyy, shape, bx, by, dx,
                                    shift, contact, stick, M, rho)[0]
            nprod += 1
        beta = np.sqrt(np.dot(r, r))
        if beta <= rtol * bnorm:
            break
        V[0] = r / beta
        gv[:] = 0.0
        gv[0] = beta
        k_used = 0
        resid = beta
        for k in range(restart):
            Z[k] = _precond_times(V[k], cidx, mx, my, contact, stick, M, rho, dxx, dyy,
                                  shift)
            w, CZ[k] = _jacobian_times(Z[k], cidx, mx, my, kxx, kxy, kyy, shape, bx, by, dx,
                                       shift, contact, stick, M, rho)
            nprod += 1
            # classical Gram-Schmidt, done twice (as stable as the modified form, in
            # matrix-vector products)
            Vk = V[:k + 1]
            h1 = np.dot(Vk, w)
            w -= np.dot(h1, Vk)
            h2 = np.dot(Vk, w)
            w -= np.dot(h2, Vk)
            H[:k + 1, k] = h1 + h2
            hk = np.sqrt(np.dot(w, w))
            H[k + 1, k] = hk
            if hk > 0.0:
                V[k + 1] = w / hk
            for i in range(k):                       # earlier rotations
                a = H[i, k]
                c = H[i + 1, k]
                H[i, k] = cs[i] * a + sn[i] * c
                H[i + 1, k] = -sn[i] * a + cs[i] * c
            a = H[k, k]
            c = H[k + 1, k]
            den = np.sqrt(a * a + c * c)
            cs[k] = a / den if den > 0.0 else 1.0
            sn[k] = c / den if den > 0.0 else 0.0
            H[k, k] = den
            H[k + 1, k] = 0.0
            gv[k + 1] = -sn[k] * gv[k]
            gv[k] = cs[k] * gv[k]
            resid = abs(gv[k + 1])
            k_used = k + 1
            if resid <= rtol * bnorm or hk == 0.0:
                break
        y = np.zeros(k_used)
        for i in range(k_used - 1, -1, -1):
            s = gv[i]
            for j in range(i + 1, k_used):
                s -= H[i, j] * y[j]
            y[i] = s / H[i, i] if H[i, i] != 0.0 else 0.0
        for i in range(k_used):
            x += y[i] * Z[i]
            cx += y[i] * CZ[i]
        if resid <= rtol * bnorm:
            break
    return x, cx, nprod


@njit(cache=True, nogil=True)
def _ssn_state(px, py, wx, wy, cx, cy, contact, bound, rho):
    """Residual, Jacobian blocks, stick mask and merit |F|^2 at tractions (px, py)
    with C p = (cx, cy) (needed in the contact only)."""
    F, M, stick = _ssn_blocks(px, py, wx + cx, wy + cy, contact, bound, rho)
    return F, M, stick, np.sum(F * F)


@njit(cache=True, nogil=True)
def _ssn_solve(px, py, wx, wy, kxx, kxy, kyy, shape, dx, shift, contact, bound, rho, dxx,
               dyy, tol, maxiter):
    """Semi-smooth Newton iteration of :func:`steady_rolling`, compiled; (px, py) the
    initial tractions.  Returns px, py, the linear part of their slip C p (cx, cy;
    in the contact), the stick mask, Newton iterations, products with J,
    converged."""
    mx, my = px.shape
    cidx = np.flatnonzero(contact.ravel())    # the unknowns: tractions in the contact
    bx = np.zeros(shape)
    by = np.zeros(shape)
    gmax = max(np.max(bound), 1e-300)
    # C p by a product once; then it follows each step from the linear solve's
    # products (C d = sum of y_k C z_k), with no further product for the step and
    # its line search
    cx, cy = _c_of(px, py, kxx, kxy, kyy, shape, bx, by, dx, shift)
    cp = _pack(cx, cy, cidx)
    pp = _pack(px, py, cidx)                  # the unknowns, stacked
    F, M, stick, phi2 = _ssn_state(px, py, wx, wy, cx, cy, contact, bound, rho)
    converged = False
    forcing = 0.3
    phi_prev = phi2
    nprod = 0
    it = 0
    for it in range(1, maxiter + 1):
        if np.max(np.abs(F)) <= tol * gmax:
            converged = True
            break
        rhs = -_pack(F[:, :, 0].copy(), F[:, :, 1].copy(), cidx)
        # inexact Newton (Eisenstat-Walker): loose linear solves far from the solution,
        # the residual cut to at most 0.3 (docs/tuning.md, section "Tangential: exact")
        if it > 1:
            # no oversolving: the linear residual need not fall below what the
            # tolerance asks of the nonlinear one (a third of tol * gmax in 2-norm,
            # which bounds the largest element's)
            forcing = min(0.3, max(0.9 * phi2 / max(phi_prev, 1e-300), 1e-6,
                                   0.3 * tol * gmax / math.sqrt(phi2)))
        else:
            # a start close to the solution (an earlier pass's, residual under 1 % of
            # the bound) solves its first step to about the tolerance: that one
            # step then usually ends the iteration
            rmax = np.max(np.abs(F))
            if rmax < 1e-2 * gmax:
                forcing = min(0.3, max(0.3 * tol * gmax / rmax, 1e-3))
        phi_prev = phi2
        d, cd, k = _newton_step(rhs, forcing, 60, 10, cidx, mx, my, kxx, kxy, kyy, shape,
                                bx, by, dx, shift, contact, stick, M, rho, dxx, dyy)
        nprod += k
        # backtracking on the merit function |F|^2
        alpha = 1.0
        for _ in range(12):
            pt = pp + alpha * d
            ct = cp + alpha * cd
            tx, ty = _unpack(pt, cidx, mx, my)
            cx, cy = _unpack(ct, cidx, mx, my)
            Fn, Mn, sn, phin = _ssn_state(tx, ty, wx, wy, cx, cy, contact, bound, rho)
            if phin <= (1.0 - 1e-4 * alpha) * phi2:
                break
            alpha *= 0.5
        pp, px, py, cp, F, M, stick, phi2 = pt, tx, ty, ct, Fn, Mn, sn, phin
    cx, cy = _unpack(cp, cidx, mx, my)
    return px, py, cx, cy, stick, it, nprod, converged


#: in steady rolling the lateral rigid slip of spin, eta + phi x, is taken at
#: x + SPIN_OFFSET dx (towards the leading edge), as CONTACT does (the factor FACPHI of
#: its rolling step, default 1/6, Vollebregt's CONTACT user guide): an O(dx) choice of
#: the discretisation, with the same continuum limit [element lengths dx]
#: (docs/tuning.md, section "Tangential: exact")
SPIN_OFFSET = 1.0 / 6.0


@lru_cache(maxsize=32)
def _self_terms(mx, my, dx, dy, G, nu):
    kxx, _, kyy = tangential_kernels(1, 1, dx, dy, G, nu)
    return float(kxx[0, 0]), float(kyy[0, 0])


@lru_cache(maxsize=32)
def _kernels(mx, my, dx, dy, G, nu):
    """Tangential kernels of an mx x my grid (offsets in x up to mx: one extra row
    for the rolling difference) and the self terms (dxx, dyy) of the operator."""
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
    return _block_operator(mx, my, dx, dy, G, nu, *block_size(ms, ns, mx, my, extra_rows=1))


@lru_cache(maxsize=64)
def _block_operator(mx, my, dx, dy, G, nu, ms, ns):
    kernels, _ = _kernels(mx, my, dx, dy, G, nu)
    cut = (slice(mx - ms, mx + ms), slice(my - ns, my - 1 + ns))
    return TangentialOperator(tuple(k[cut] for k in kernels), ms, ns, rows=1)


def _operators(mx, my, dx, dy, G, nu):
    """FFT operator of the whole mx x my grid and the self terms (dxx, dyy)."""
    return _sub_operator(mx, my, dx, dy, G, nu, mx, my), _kernels(mx, my, dx, dy, G, nu)[1]


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

    Returns p (on body 1), slip, stick mask, Newton iterations and a convergence
    flag.  Convergence: max |F| <= tol * max bound, with F the complementarity
    residual p - Proj(p - rho s).
    """
    mx, my = x.size, y.size
    dx, dy = float(x[1] - x[0]), float(y[1] - y[0])
    _, (dxx, dyy) = _kernels(mx, my, dx, dy, G, nu)
    if mode == "shift":
        kx, ky = _self_terms(mx, my, dx, dy, G, nu)
        dxx, dyy = kx, ky
    xi, eta, phi = creepage
    wx = np.ascontiguousarray(np.where(contact, xi - phi * y[None, :], 0.0))
    x_spin = x + SPIN_OFFSET * dx if mode == "rolling" else x
    wy = np.ascontiguousarray(np.where(contact, eta + phi * x_spin[:, None], 0.0))
    if w_extra is not None:
        wx = np.ascontiguousarray(wx + np.where(contact, w_extra[0], 0.0))
        wy = np.ascontiguousarray(wy + np.where(contact, w_extra[1], 0.0))
    rho = 1.0 / (0.5 * (dxx + dyy))

    if p0 is not None:
        px, py = p0[0].copy(), p0[1].copy()
    elif mode == "shift":
        px, py = np.zeros((mx, my)), np.zeros((mx, my))
    else:
        px, py = _initial_march(wx, wy, contact, bound, dxx, dyy)
    shift = mode == "shift"
    # the problem lives on the contact's bounding box: tractions are zero outside the
    # contact and the slip is needed only inside it, so the FFT products run on the
    # box's (smaller) padded grid, with the same arithmetic
    box = bounding_box(contact) or (slice(0, 1), slice(0, 1))
    ms, ns = contact[box].shape
    op = _sub_operator(mx, my, dx, dy, G, nu, ms, ns)
    cb, gb, *q = (np.ascontiguousarray(a[box]) for a in (contact, bound, px, py, wx, wy))
    # the iteration returns the slip's linear part and the stick mask of its last
    # iterate (C p accumulated from its products, no product more)
    qx, qy, cx, cy, sb, it, nprod, converged = _ssn_solve(
        *q, op.kxx, op.kxy, op.kyy, op.shape, dx, shift, cb, gb, rho, dxx, dyy, float(tol),
        int(maxiter))
    log.debug("semi-smooth Newton: %d iterations, %d products with the Jacobian", it, nprod)
    sbx, sby = q[2] + cx, q[3] + cy
    px, py, sx, sy = (np.zeros((mx, my)) for _ in range(4))
    stick = np.zeros((mx, my), dtype=bool)
    px[box], py[box], stick[box], sx[box], sy[box] = qx, qy, sb, sbx, sby
    slip = contact & ~stick
    # in slip elements the traction lies on the bound: report it there exactly
    mag = np.hypot(px, py)
    with np.errstate(invalid="ignore", divide="ignore"):
        scale = np.where(slip & (mag > 0), bound / np.where(mag > 0, mag, 1.0), 1.0)
    px, py = px * scale, py * scale
    sx = np.where(slip, sx, 0.0)
    sy = np.where(slip, sy, 0.0)
    return px, py, sx, sy, stick & contact, it, converged


def _initial_tractions(warm, x, y, contact, bound):
    """Tractions on the rail (body 1) from a previous solution ``warm``: on the same
    grid as they are, on another grid interpolated (linear, zero outside); inside
    the contact and within the traction bound."""
    if same_grid(warm.x, warm.y, x, y):
        tx, ty = -warm.traction_x, -warm.traction_y
    else:
        X, Y = np.broadcast_arrays(x[:, None], y[None, :])
        tx = -bilinear(warm.x, warm.y, warm.traction_x, X, Y)
        ty = -bilinear(warm.x, warm.y, warm.traction_y, X, Y)
    mag = np.hypot(tx, ty)
    with np.errstate(invalid="ignore", divide="ignore"):
        scale = np.where(mag > bound, bound / np.where(mag > 0, mag, 1.0), 1.0)
    return (np.ascontiguousarray(np.where(contact, tx * scale, 0.0)),
            np.ascontiguousarray(np.where(contact, ty * scale, 0.0)))


@register("exact")
class ExactTangentialModel:
    """Kalker's exact theory of steady-state rolling (identical materials).

    Parameters
    ----------
    tol : float      convergence: largest complementarity residual
                     |p - Proj(p - rho s)| / largest bound (default 1e-5; what it
                     costs in accuracy: docs/tuning.md, section "Tangential: exact")
    maxiter : int    limit of Newton iterations
    mode : {"rolling", "shift"}
        ``"rolling"``: steady-state rolling with creepages (xi, eta, phi).
        ``"shift"``: transient shift from the unloaded state (Cattaneo-Mindlin); the
        "creepage" argument is then the rigid shift (dx [m], dy [m], rotation [rad])
        of the rail relative to the wheel, and the slip a displacement [m].
    """

    capabilities = frozenset({"warm-start", "coupled", "lazy"})

    def __init__(self, tol: float = 1e-5, maxiter: int = 60, mode: str = "rolling"):
        if not 0 < tol < 1e-2:
            raise InputError(f"exact tangential tol {tol!r}: expected a value in (0, 0.01)")
        if mode not in ("rolling", "shift"):
            raise InputError(f"exact tangential mode {mode!r}: expected 'rolling' (steady "
                             "rolling) or 'shift' (transient shift, Cattaneo)")
        self.tol, self.maxiter, self.mode = tol, int(maxiter), mode

    def solve(self, normal, geometry=None, material: Material = STEEL, creepage=(0.0, 0.0, 0.0),
              friction: float = 0.3, velocity: float = 1.0,
              warm_start: TangentialSolution | None = None,
              extra_slip=None) -> TangentialSolution:
        """Creep forces for creepages (xi [-], eta [-], phi [1/m]) on the normal
        solution's grid.  ``warm_start``: a previous solution (e.g. of a neighbouring
        case, on this grid or interpolated from its own) used as the initial
        estimate; without it, FASTSIM's solution is."""
        t0 = time.perf_counter()
        xi, eta, phi = check_inputs(creepage, friction)
        x, y = normal.x, normal.y
        if x.size < 2 or y.size < 2:
            raise InputError("exact tangential solver needs a grid of at least 2 x 2 elements")
        contact = np.ascontiguousarray(normal.contact & (normal.pressure > 0))
        bound = np.ascontiguousarray(friction * np.where(contact, normal.pressure, 0.0))
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
        if warm_start is not None:
            p0 = _initial_tractions(warm_start, x, y, contact, bound)
        args = (x, y, contact, bound, (xi, eta, phi), material.shear_modulus,
                material.nu, self.tol)
        px, py, sx, sy, stick, it, ok = steady_rolling(*args, self.maxiter, p0=p0, mode=self.mode,
                                                       w_extra=extra_slip)
        fallback = False
        if not ok:
            # fall back: restart from zero traction with damped steps and more iterations
            log.info("exact tangential solver: no convergence in %d iterations; restarting "
                     "from zero traction with %d iterations", it, 4 * self.maxiter)
            q = steady_rolling(*args, 4 * self.maxiter, p0=(np.zeros_like(bound),
                                                               np.zeros_like(bound)),
                               mode=self.mode, w_extra=extra_slip)
            fallback = True
            if q[-1] or not ok:
                px, py, sx, sy, stick, it, ok = q
        if not ok:
            log.warning("exact tangential solver: not converged (flagged in the result)")
        status = SolverStatus(True, "", int(it)) if ok else SolverStatus.failed(
            f"exact tangential solver: no convergence in {it} Newton iterations"
            + (" (also restarted from zero traction)" if fallback else ""), it)
        dA = (x[1] - x[0]) * (y[1] - y[0])
        fx, fy = float(px.sum() * dA), float(py.sum() * dA)
        mz = float(((x[:, None] * py) - (y[None, :] * px)).sum() * dA)
        return TangentialSolution("exact", x, y, -px, -py, sx, sy, stick, contact, -fx, -fy,
                                  -mz, velocity, (xi, eta, phi), friction,
                                  time.perf_counter() - t0,
                                  {"iterations": it, "fallback": fallback, "mode": self.mode},
                                  status)
