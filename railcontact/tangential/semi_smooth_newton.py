"""The compiled iteration of the exact tangential model: a semi-smooth Newton
method for Kalker's steady-rolling problem on a boundary-element grid.

The unknowns are the tractions p in the elements of the contact; the residual
F = p - Proj_g(p - rho s) vanishes where every element sticks (slip s = 0) or
slips on its bound g = mu p_n against its slip.  A Newton step (:func:`_newton_step`)
is solved by restarted GMRES with FFT products of the displacement-difference
operator (:func:`_c_of`) and a marching preconditioner, the self and upstream
coupling of each element inverted strip by strip from the leading edge
(:func:`_ssn_precond`); :func:`ssn_solve` runs the Newton steps with
Eisenstat-Walker forcing and a backtracking line search on |F|^2.  The local slip
of one element under its bound (:func:`_local_slip`) also gives the marching
first estimate (:func:`initial_march`).  The model around it (operators, grids,
warm starts) is :mod:`railcontact.tangential.exact`.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit


_NO_COLUMNS = np.zeros(0)

#: no oversolving: a Newton step after the first stops its linear solve once the
#: residual is under LINEAR_FLOOR * tol * g_max (2-norm; tol the iteration's tolerance
#: on the largest element's residual, g_max the largest traction bound), whatever the
#: Eisenstat-Walker forcing asks (the first step from a start near the solution keeps
#: a third of it: that step usually ends the iteration); the convergence test itself
#: is unchanged (docs/tuning.md, section "Tangential: exact")
LINEAR_FLOOR = 1.0


class SlipOperator(NamedTuple):
    """The operator p -> C p (:func:`_c_of`) on the padded grid of the contact's box."""

    #: spectra [m/Pa] of the influence kernels on the padded grid
    kxx: np.ndarray
    kxy: np.ndarray
    kyy: np.ndarray
    #: (nx, ny) the padded grid of the FFT
    shape: tuple
    #: element length [m] in the rolling direction
    dx: float
    #: a shift (True) or steady rolling (False: the slip has the upstream difference)
    shift: bool
    #: flexibility h3/G3 [m/Pa] of an interfacial layer (CONTACT's M = 4; 0: none),
    #: its displacement difference f p added to the bodies' B p
    layer: float = 0.0
    #: Blanco's conformal correction (:mod:`railcontact.normal.conformal_influence`):
    #: cos and sin of the inclination of each column of the box (empty: the
    #: half-space), the lateral displacement then
    #: u_s = c_I B_s(c p) + s_I B_s(s p)
    cos_col: np.ndarray = _NO_COLUMNS
    sin_col: np.ndarray = _NO_COLUMNS


class TractionBound(NamedTuple):
    """The bound on the tangential traction of each element: the friction bound g,
    or where an interfacial layer yields first, its yield limit, which may harden
    with the plastic flow of the step (CONTACT's M = 4; user guide, "Interfacial
    layer of contaminants"): per element

        bound(S) = min(g, max(0, tau + k S))   where tau < g,   g elsewhere,

    with S = |s| the element's slip (a plastic flow where the yield limit binds)."""

    #: friction bound mu p_n [Pa]
    g: np.ndarray
    #: the layer's yield limit before this step's plastic flow [Pa] (>= g: none)
    tau: np.ndarray
    #: the yield limit's rate with the element's slip [Pa per unit of slip]
    k: np.ndarray


class Jacobian(NamedTuple):
    """The Newton iteration's linearisation at an iterate (:func:`_ssn_blocks`):
    per contact element J z = z - M z + Q (C z)."""

    #: (mx, my) the contact elements
    contact: np.ndarray
    #: (mx, my) the elements in adhesion
    stick: np.ndarray
    #: (mx, my, 2, 2) the blocks M of the residual's derivative in the tractions
    M: np.ndarray
    #: (mx, my, 2, 2) the blocks Q of the residual's derivative in the slip
    Q: np.ndarray


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
def initial_march(wx, wy, contact, bound, dxx, dyy):
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
def bound_at(g, tau, k, S):
    """An element's traction bound at slip magnitude S (:class:`TractionBound`) and
    its slope in S."""
    if tau >= g:
        return g, 0.0
    val = tau + k * S
    if val >= g:
        return g, 0.0
    if val <= 0.0:
        return 0.0, 0.0
    return val, k


@njit(cache=True, nogil=True)
def _ssn_blocks(px, py, sx, sy, contact, bound, rho):
    """Residual F and the 2x2 blocks M, Q of the generalised Jacobian.

    F = p - Proj(p - rho s) on the bound b(|s|) (:class:`TractionBound`).  Stick
    (|v| <= b, v = p - rho s): F = rho s, row rho C (M = I, Q = rho I).  Slip:
    F = p - b v/|v|, row I - M + Q C with M = b/|v| (I - e e^T), e = v/|v|, and
    Q = rho M - b' e s^T/|s| (b' the bound's slope in |s|: a hardening or softening
    yield limit; rho + b' in place of rho where the limit hardens).
    Returned: F (mx, my, 2), M and Q (mx, my, 2, 2), the stick mask.
    """
    mx, my = px.shape
    F = np.zeros((mx, my, 2))
    M = np.zeros((mx, my, 2, 2))
    Q = np.zeros((mx, my, 2, 2))
    stick = np.zeros((mx, my), dtype=np.bool_)
    for i in range(mx):
        for j in range(my):
            if not contact[i, j]:
                F[i, j, 0] = px[i, j]
                F[i, j, 1] = py[i, j]
                continue
            # a hardening yield limit (slope k in the slip): the element's scaling
            # rho + k, which makes the stick and flow branches of F meet with the same
            # slope in one element's own problem (a stiff hardening otherwise cycles
            # between them); any rho > 0 has the same solutions
            r = rho
            if bound.tau[i, j] < bound.g[i, j] and bound.k[i, j] > 0.0:
                r = rho + bound.k[i, j]
            vx = px[i, j] - r * sx[i, j]
            vy = py[i, j] - r * sy[i, j]
            nv = math.sqrt(vx * vx + vy * vy)
            ns = math.sqrt(sx[i, j] * sx[i, j] + sy[i, j] * sy[i, j])
            g, slope = bound_at(bound.g[i, j], bound.tau[i, j], bound.k[i, j], ns)
            if nv <= g:
                stick[i, j] = True
                F[i, j, 0] = r * sx[i, j]
                F[i, j, 1] = r * sy[i, j]
                M[i, j, 0, 0] = 1.0
                M[i, j, 1, 1] = 1.0
                Q[i, j, 0, 0] = r
                Q[i, j, 1, 1] = r
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
                for a in range(2):
                    for b in range(2):
                        Q[i, j, a, b] = r * M[i, j, a, b]
                if slope != 0.0 and ns > 0.0:
                    tx = sx[i, j] / ns
                    ty = sy[i, j] / ns
                    Q[i, j, 0, 0] -= slope * ex * tx
                    Q[i, j, 0, 1] -= slope * ex * ty
                    Q[i, j, 1, 0] -= slope * ey * tx
                    Q[i, j, 1, 1] -= slope * ey * ty
    return F, M, Q, stick


@njit(cache=True, nogil=True)
def _ssn_apply(zx, zy, cx, cy, contact, M, Q):
    """J z from z and C z (both fields): z - M z + Q C z in the contact, z outside."""
    mx, my = zx.shape
    ox = np.zeros((mx, my))
    oy = np.zeros((mx, my))
    for i in range(mx):
        for j in range(my):
            if not contact[i, j]:
                ox[i, j] = zx[i, j]
                oy[i, j] = zy[i, j]
            else:
                ox[i, j] = zx[i, j] - (M[i, j, 0, 0] * zx[i, j] + M[i, j, 0, 1] * zy[i, j]) \
                    + Q[i, j, 0, 0] * cx[i, j] + Q[i, j, 0, 1] * cy[i, j]
                oy[i, j] = zy[i, j] - (M[i, j, 1, 0] * zx[i, j] + M[i, j, 1, 1] * zy[i, j]) \
                    + Q[i, j, 1, 0] * cx[i, j] + Q[i, j, 1, 1] * cy[i, j]
    return ox, oy


@njit(cache=True, nogil=True)
def _ssn_precond(rx, ry, contact, M, Q, dxx, dyy, upstream):
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
            # z - M z + Q D (z - u) = r  ->  (I - M + Q D) z = r + Q D u
            a00 = 1.0 - M[i, j, 0, 0] + Q[i, j, 0, 0] * dxx
            a01 = -M[i, j, 0, 1] + Q[i, j, 0, 1] * dyy
            a10 = -M[i, j, 1, 0] + Q[i, j, 1, 0] * dxx
            a11 = 1.0 - M[i, j, 1, 1] + Q[i, j, 1, 1] * dyy
            bx = rx[i, j] + Q[i, j, 0, 0] * dxx * ux + Q[i, j, 0, 1] * dyy * uy
            by = ry[i, j] + Q[i, j, 1, 0] * dxx * ux + Q[i, j, 1, 1] * dyy * uy
            det = a00 * a11 - a01 * a10
            if det == 0.0:
                zx[i, j] = rx[i, j]
                zy[i, j] = ry[i, j]
            else:
                zx[i, j] = (a11 * bx - a01 * by) / det
                zy[i, j] = (-a10 * bx + a00 * by) / det
            if upstream:
                ux = zx[i, j]
                uy = zy[i, j]
    return zx, zy


@njit(cache=True, nogil=True)
def _turned_lateral(px, py, op, bx, by):
    """The lateral displacement difference of Blanco's coefficients (variant 3) on
    the padded grid: u_s = c_I [B_sx (c p_x) + B_ss (c p_s)] + s_I [B_sx (s p_x)
    + B_ss (s p_s)], c, s the cos and sin of each column's inclination
    (``op.cos_col``, ``op.sin_col``; ``bx``, ``by`` the zero-padded work arrays)."""
    mx, my = px.shape
    kxy, kyy, shape = op.kxy, op.kyy, op.shape
    out = np.zeros(shape)
    for m in range(2):
        w = op.cos_col if m == 0 else op.sin_col
        for i in range(mx):
            for j in range(my):
                bx[i, j] = w[j] * px[i, j]
                by[i, j] = w[j] * py[i, j]
        fx = np.fft.rfft2(bx)
        fy = np.fft.rfft2(by)
        for i in range(fx.shape[0]):
            for j in range(fx.shape[1]):
                fy[i, j] = kxy[i, j] * fx[i, j] + kyy[i, j] * fy[i, j]
        u = np.fft.irfft2(fy, s=shape)
        for i in range(shape[0]):
            for j in range(my):
                out[i, j] += w[j] * u[i, j]
    return out


@njit(cache=True, nogil=True)
def _c_of(px, py, op, bx, by):
    """The linear part of the slip, s - w, from tractions (px, py): rolling
    -(u_I+ - u_I)/dx, shift u_I, with u = B p + f p (FFT products of the
    :class:`SlipOperator` ``op``, f its layer's flexibility; bx, by the zero-padded
    work arrays)."""
    kxx, kxy, kyy, shape, dx, shift, f = op.kxx, op.kxy, op.kyy, op.shape, op.dx, \
        op.shift, op.layer
    mx, my = px.shape
    bx[:mx, :my] = px
    by[:mx, :my] = py
    fx = np.fft.rfft2(bx)
    fy = np.fft.rfft2(by)
    # the kernel products in place, in one pass: fx <- kxx fx + kxy fy, fy <- ...
    # (fy only on the half-space: Blanco's lateral displacement is turned per column)
    turned = op.cos_col.size > 0
    for i in range(fx.shape[0]):
        for j in range(fx.shape[1]):
            a = fx[i, j]
            b = fy[i, j]
            c = kxy[i, j]
            fx[i, j] = kxx[i, j] * a + c * b
            if not turned:
                fy[i, j] = c * a + kyy[i, j] * b
    ux = np.fft.irfft2(fx, s=shape)
    if turned:
        uy = _turned_lateral(px, py, op, bx, by)
    else:
        uy = np.fft.irfft2(fy, s=shape)
    cx = np.empty((mx, my))
    cy = np.empty((mx, my))
    if f != 0.0:
        for i in range(mx):
            for j in range(my):
                ux[i, j] += f * px[i, j]
                uy[i, j] += f * py[i, j]
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
def _jacobian_times(v, cidx, mx, my, op, buffers, jac):
    """J v for the stacked vector v of the unknowns at the contact elements ``cidx``
    (flat indices on the (mx, my) grid; outside the contact J is the identity and the
    Newton steps are zero), and C v there (the linear part of the slip, which the
    Newton iteration accumulates).  ``op`` the :class:`SlipOperator`, ``buffers`` its
    two padded work arrays, ``jac`` the :class:`Jacobian`."""
    zx, zy = _unpack(v, cidx, mx, my)
    cx, cy = _c_of(zx, zy, op, buffers[0], buffers[1])
    ox, oy = _ssn_apply(zx, zy, cx, cy, jac.contact, jac.M, jac.Q)
    return _pack(ox, oy, cidx), _pack(cx, cy, cidx)


@njit(cache=True, nogil=True)
def _precond_times(v, cidx, mx, my, jac, self_terms, shift):
    """P^-1 v for the stacked vector v of the unknowns at the contact elements;
    ``self_terms`` (dxx, dyy) [m/Pa] the elements' own influence."""
    zx, zy = _unpack(v, cidx, mx, my)
    ox, oy = _ssn_precond(zx, zy, jac.contact, jac.M, jac.Q, self_terms[0], self_terms[1],
                          not shift)
    return _pack(ox, oy, cidx)


@njit(cache=True, nogil=True)
def _newton_step(b, rtol, restart, maxcycles, cidx, mx, my, op, buffers, jac, self_terms):
    """Solve J d = b to ||b - J d|| <= rtol ||b|| by restarted GMRES (Saad & Schultz
    1986; ``restart`` directions, ``maxcycles`` cycles at most) with right
    preconditioning by P (flexible form: the preconditioned directions are kept,
    Saad 1993); Givens rotations, Gram-Schmidt twice.  The unknowns, operator and
    linearisation as in :func:`_jacobian_times`, ``self_terms`` as in
    :func:`_precond_times`.  Returns d, C d (from the products with the kept
    directions) and the number of products with J."""
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
            r = b - _jacobian_times(x, cidx, mx, my, op, buffers, jac)[0]
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
            Z[k] = _precond_times(V[k], cidx, mx, my, jac, self_terms, op.shift)
            w, CZ[k] = _jacobian_times(Z[k], cidx, mx, my, op, buffers, jac)
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
    F, M, Q, stick = _ssn_blocks(px, py, wx + cx, wy + cy, contact, bound, rho)
    return F, M, Q, stick, np.sum(F * F)


@njit(cache=True, nogil=True)
def ssn_solve(px, py, wx, wy, op, contact, bound, rho, self_terms, tol, maxiter):
    """Semi-smooth Newton iteration of :func:`steady_rolling`, compiled.

    (px, py) the initial tractions [Pa], (wx, wy) the rigid slip [-] in the
    ``contact``, ``op`` the :class:`SlipOperator`, ``bound`` the traction bound
    (:class:`TractionBound`),
    ``rho`` the scaling of the tractions in the residual [m/Pa], ``self_terms`` (dxx,
    dyy) [m/Pa] the elements' own influence (the preconditioner), ``tol`` relative to
    the largest bound and ``maxiter`` Newton iterations at most.
    Returns px, py, the linear part of their slip C p (cx, cy; in the contact), the
    stick mask, Newton iterations, products with J, converged."""
    shape = op.shape
    mx, my = px.shape
    cidx = np.flatnonzero(contact.ravel())    # the unknowns: tractions in the contact
    bx = np.zeros(shape)
    by = np.zeros(shape)
    gmax = max(np.max(bound.g), 1e-300)
    # C p by a product once; then it follows each step from the linear solve's
    # products (C d = sum of y_k C z_k), with no further product for the step and
    # its line search
    cx, cy = _c_of(px, py, op, bx, by)
    cp = _pack(cx, cy, cidx)
    pp = _pack(px, py, cidx)                  # the unknowns, stacked
    F, M, Q, stick, phi2 = _ssn_state(px, py, wx, wy, cx, cy, contact, bound, rho)
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
            # tolerance asks of the nonlinear one (LINEAR_FLOOR * tol * gmax in
            # 2-norm, which bounds the largest element's)
            forcing = min(0.3, max(0.9 * phi2 / max(phi_prev, 1e-300), 1e-6,
                                   LINEAR_FLOOR * tol * gmax / math.sqrt(phi2)))
        else:
            # a start close to the solution (an earlier pass's, residual under 1 % of
            # the bound) solves its first step to about the tolerance: that one
            # step then usually ends the iteration
            rmax = np.max(np.abs(F))
            if rmax < 1e-2 * gmax:
                forcing = min(0.3, max(0.3 * tol * gmax / rmax, 1e-3))
        phi_prev = phi2
        d, cd, k = _newton_step(rhs, forcing, 60, 10, cidx, mx, my, op, (bx, by),
                                Jacobian(contact, stick, M, Q), self_terms)
        nprod += k
        # backtracking on the merit function |F|^2
        alpha = 1.0
        for _ in range(12):
            pt = pp + alpha * d
            ct = cp + alpha * cd
            tx, ty = _unpack(pt, cidx, mx, my)
            cx, cy = _unpack(ct, cidx, mx, my)
            Fn, Mn, Qn, sn, phin = _ssn_state(tx, ty, wx, wy, cx, cy, contact, bound, rho)
            if phin <= (1.0 - 1e-4 * alpha) * phi2:
                break
            alpha *= 0.5
        pp, px, py, cp, F, M, Q, stick, phi2 = pt, tx, ty, ct, Fn, Mn, Qn, sn, phin
    cx, cy = _unpack(cp, cidx, mx, my)
    return px, py, cx, cy, stick, it, nprod, converged
