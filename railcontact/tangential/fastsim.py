"""FASTSIM: Kalker's simplified theory of rolling contact (``tangential="fastsim"``).

Kalker, J.J. (1982), "A fast algorithm for the simplified theory of rolling
contact", *Vehicle System Dynamics* 11, 1-13.

The surface displacement is taken proportional to the local traction, u = L p,
with one flexibility per creepage component (L1 for xi, L2 for eta, L3 for spin),
chosen so that the theory reproduces Kalker's linear theory (C11, C22, C23) at
small creepage.  Each strip of the patch (fixed lateral position y) is integrated
from its leading edge in the rolling direction: in adhesion the traction follows
dp/dx = u(x, y) / L with the rigid slip (xi - phi y, eta + phi x); where |p|
exceeds the traction bound mu p_n the traction is scaled back to the bound
(slip).  Tractions are evaluated at element mid-points, so that the linear
(adhesion) limit is integrated exactly.

The traction bound is the Hertzian (elliptic) pressure by default, as CONTACT's user
guide recommends; ``bound="parabolic"`` gives Kalker's original parabolic bound
p = 2 F_n / (pi a b) (1 - x^2/a^2 - y^2/b^2).
"""

from __future__ import annotations

import math
import time
from typing import NamedTuple

import numpy as np
from numba import njit

from ..core.errors import InputError
from ..core.hertz_theory import axes_at
from ..core.materials import Material, STEEL
from .base import TangentialSolution, check_inputs, register
from .friction import falling_friction
from .kalker import (Creepage, Flexibilities, coefficients_at, flexibilities,
                     flexibilities_array, kalker_coefficients, kalker_coefficients_array)


class Traction(NamedTuple):
    """Tangential fields of a march, on a strip's elements (1-D) or on the grid
    (mx, my; empty (0, my) where only the forces are wanted)."""

    #: tractions [Pa] on the rail
    px: np.ndarray
    py: np.ndarray
    #: slip (relative velocity over V) [-]
    sx: np.ndarray
    sy: np.ndarray
    #: adhesion (bool)
    stick: np.ndarray


class StripArrays(NamedTuple):
    """Many patches with semi-elliptic strip pressures (a
    :class:`~railcontact.normal.strip_batch.StripSolution`), arrays (patches, strips)
    unless said."""

    #: lateral position of each strip [m]
    y: np.ndarray
    #: (patches,) strip width [m]
    dy: np.ndarray
    #: centre x of each strip's contact [m]
    x_mid: np.ndarray
    #: half-length l_j of each strip's contact [m]
    half: np.ndarray
    #: peak pressure p_j of each strip [Pa]
    p_strip: np.ndarray

    @classmethod
    def of(cls, strips) -> "StripArrays":
        return cls(strips.y, strips.dy, strips.x_mid, strips.half, strips.p_strip)


@njit(cache=True, nogil=True, inline="always")
def _strip_to_grid(j, x_lead, x_trail, dx, xgrid, strip, grid):
    """Copy one strip's mid-point values ``strip`` (:class:`Traction`, element length
    dx from the leading edge) to column j of the regular grid ``grid``: tractions
    interpolated linearly, slip and stick from the nearest mid-point."""
    pxs, pys, sxs, sys_, sts = strip.px, strip.py, strip.sx, strip.sy, strip.stick
    px_out, py_out, sx_out, sy_out, stick_out = grid.px, grid.py, grid.sx, grid.sy, grid.stick
    nx = pxs.size
    for i in range(xgrid.size):
        xc = xgrid[i]
        if xc > x_lead or xc < x_trail:
            continue
        t = (x_lead - xc) / dx - 0.5
        k0 = int(math.floor(t))
        if k0 < 0:
            k0 = 0
            w = 0.0
        elif k0 >= nx - 1:
            k0 = nx - 1
            w = 0.0
        else:
            w = t - k0
        k1 = min(k0 + 1, nx - 1)
        px_out[i, j] = (1 - w) * pxs[k0] + w * pxs[k1]
        py_out[i, j] = (1 - w) * pys[k0] + w * pys[k1]
        kn = k0 if w < 0.5 else k1
        sx_out[i, j] = sxs[kn]
        sy_out[i, j] = sys_[kn]
        stick_out[i, j] = sts[kn]


@njit(cache=True, nogil=True)
def _fastsim_strips(y, dy, x_lead, x_trail, bound, L, creepage, xgrid, grid):
    """March all strips; fill the grid fields ``grid`` (:class:`Traction`, traction
    on body 1 = rail) and return the forces and the frictional power per unit
    velocity [N]: the integral of p . s with FASTSIM's slip s = w_F + L dp/dx (w_F =
    (xi - phi y L1/L3, eta + phi x L2/L3), its rigid slip scaled by the
    flexibilities); as p vanishes at both ends of every strip, the integral of
    p . L dp/dx is zero and the power is the sum of p . w_F dx dy over the
    mid-points, the limit of the sum of p . s dx dy, which converges as slowly as
    the slip's onset is resolved (docs/frictional_power.md).

    ``y`` (my,) the strips' positions [m], ``dy`` their width [m], ``x_lead``,
    ``x_trail`` (my,) their edges [m], ``bound`` (my, nx) the traction bound [Pa] at
    the elements' mid-points, ``L``
    (:class:`~railcontact.tangential.kalker.Flexibilities`) and the spin of
    ``creepage`` (:class:`~railcontact.tangential.kalker.Creepage`) per strip
    (length my), ``xgrid`` the grid's x [m]."""
    L1, L2, L3 = L.L1, L.L2, L.L3
    xi, eta, phi = creepage.xi, creepage.eta, creepage.phi
    my = y.size
    nx = bound.shape[1]
    fx = 0.0
    fy = 0.0
    mz = 0.0
    pw = 0.0
    strip = Traction(np.empty(nx), np.empty(nx), np.empty(nx), np.empty(nx),
                     np.empty(nx, dtype=np.bool_))
    pxs, pys, sxs, sys_, sts = strip.px, strip.py, strip.sx, strip.sy, strip.stick
    for j in range(my):
        length = x_lead[j] - x_trail[j]
        if length <= 0.0:
            continue
        dx = length / nx
        px = 0.0
        py = 0.0
        prev = x_lead[j]
        for k in range(nx):
            xm = x_lead[j] - (k + 0.5) * dx
            step = prev - xm
            xmid = 0.5 * (prev + xm)
            ux = xi / L1[j] - phi[j] * y[j] / L3[j]
            uy = eta / L2[j] + phi[j] * xmid / L3[j]
            hx = px - step * ux
            hy = py - step * uy
            g = bound[j, k]
            mag = math.sqrt(hx * hx + hy * hy)
            if mag > g:
                sc = g / mag if mag > 0.0 else 0.0
                px = hx * sc
                py = hy * sc
                sxs[k] = L1[j] * (px - hx) / step
                sys_[k] = L2[j] * (py - hy) / step
                sts[k] = False
            else:
                px = hx
                py = hy
                sxs[k] = 0.0
                sys_[k] = 0.0
                sts[k] = True
            pxs[k] = px
            pys[k] = py
            fx += px * dx * dy
            fy += py * dx * dy
            mz += (xm * py - y[j] * px) * dx * dy
            pw += (px * L1[j] * ux + py * (eta + phi[j] * xm * L2[j] / L3[j])) * dx * dy
            prev = xm
        _strip_to_grid(j, x_lead[j], x_trail[j], dx, xgrid, strip, grid)
    return fx, fy, mz, pw


@njit(cache=True, nogil=True)
def fastsim_grid(x, y, bound, flex, creep, xofs, px, py, sx, sy, stick):
    """FASTSIM on a fixed grid of elements (CONTACT's M = 2, 3 on its own grid):
    every row of elements (fixed y) is marched from its leading element (largest
    x; rolling towards +x) to its trailing one, one element (dq = dx) per step,
    the displacement entering at zero: u_k = u_(k+1) - dx w_k, p_k = u_k / L,
    scaled back to the bound where it exceeds it (slip), with the rigid slip
    w = (xi - phi y, eta + phi (x + xofs)) per flexibility (the spin over L3).
    ``bound`` [Pa] is mu p_n per element (0 outside the contact: no traction,
    the march restarts from zero where contact resumes); ``flex`` = (L1, L2, L3)
    [m/Pa]; ``creep`` = (xi, eta, phi [1/m]); ``xofs`` [m] the offset of the
    spin's lever (CONTACT: dq/6 along the rolling direction).  Fills the
    tractions on body 1 (px, py [Pa]), the slip (sx, sy) [-] and the stick mask
    (all (mx, my)); returns nothing."""
    mx, my = bound.shape
    dx = x[1] - x[0]
    L1, L2, L3 = flex[0], flex[1], flex[2]
    xi, eta, phi = creep[0], creep[1], creep[2]
    for j in range(my):
        tx = 0.0
        ty = 0.0
        for k in range(mx - 1, -1, -1):
            g = bound[k, j]
            if g <= 0.0:
                tx = 0.0
                ty = 0.0
                px[k, j] = 0.0
                py[k, j] = 0.0
                sx[k, j] = 0.0
                sy[k, j] = 0.0
                stick[k, j] = False
                continue
            xmid = x[k] + xofs
            hx = tx - dx * (xi / L1 - phi * y[j] / L3)
            hy = ty - dx * (eta / L2 + phi * xmid / L3)
            mag = math.sqrt(hx * hx + hy * hy)
            if mag > g:
                sc = g / mag
                tx = hx * sc
                ty = hy * sc
                sx[k, j] = L1 * (tx - hx) / dx
                sy[k, j] = L2 * (ty - hy) / dx
                stick[k, j] = False
            else:
                tx = hx
                ty = hy
                sx[k, j] = 0.0
                sy[k, j] = 0.0
                stick[k, j] = True
            px[k, j] = tx
            py[k, j] = ty


def contact_flexibilities(a: float, b: float, G: float, nu: float, creepage, mu: float,
                          fn: float, modification=(1.0, 1.0, 1.0)):
    """CONTACT's three flexibilities of modified FASTSIM (M = 3) for an ellipse with
    semi-axes a (rolling), b [m]: Kalker's L1 = 8a/(3 C11 G), L2 = 8a/(3 C22 G),
    L3 = pi a sqrt(a/b)/(4 C23 G), blended towards one combined flexibility
    L_c = (xi^2 + eta^2 + (phi f4/f3)^2) / (xi^2/L1 + eta^2/L2 + (phi f4/f3)^2/L3)
    (f3 = 8a/3, f4 = pi a^2/4) with the weight w = min(1, f/3), f = sqrt((xi^2 +
    eta^2) / (xi_c^2 + eta_c^2)), xi_c = mu F_n/(c^2 G C11), eta_c = mu F_n/(c^2 G
    C22), c^2 = a b (Vollebregt & Voltr 2023, VSD 61; CONTACT's user guide, "The
    flexibilities of the simplified theory"); then divided by Spiryagin's
    reduction factor k = k0 (alpha + (1 - alpha)/(1 + beta eps)), eps = G pi a b
    k0 C11 w_rel / (4 mu F_n), w_rel = |(xi, eta + phi a)| (``modification`` =
    (k0, alpha, beta): CONTACT's K0_MF, ALFAMF, BETAMF; (1, 1, 1): the original
    FASTSIM; Spiryagin et al. 2013, Wear 303).  Returns (L1, L2, L3) [m/Pa]."""
    xi, eta, phi = (float(v) for v in creepage)
    C11, C22, C23 = kalker_coefficients(a / b, nu)
    L = [8 * a / (3 * C11 * G), 8 * a / (3 * C22 * G),
         math.pi * a * math.sqrt(a / b) / (4 * C23 * G)]
    c2 = a * b
    xc, ec = mu * fn / (c2 * G * C11), mu * fn / (c2 * G * C22)
    f3, f4 = 8 * a / 3, math.pi * a * a / 4
    num = xi * xi + eta * eta + (phi * f4 / f3) ** 2
    den = xi * xi / L[0] + eta * eta / L[1] + (phi * f4 / f3) ** 2 / L[2]
    lc = num / max(den, 1e-14 * num / L[0]) if num > 0 else L[0]
    f = max(1e-10, math.sqrt((xi * xi + eta * eta) / (xc * xc + ec * ec)))
    w = min(1.0, f / 3.0)
    L = [(1 - w) * v + w * lc for v in L]
    k = modification_factor(modification, a, b, G, C11, creepage, mu, fn)
    return tuple(v / k for v in L)


def modification_factor(modification, a, b, G, C11, creepage, mu, fn) -> float:
    """Spiryagin's reduction factor k of modified FASTSIM (CONTACT's K0_MF, ALFAMF,
    BETAMF; :func:`contact_flexibilities`)."""
    k0, alpha, beta = (float(v) for v in modification)
    if not (0 < k0 <= 1 and 0 <= alpha <= 1 and beta >= 0):
        raise InputError(f"modified FASTSIM (K0_MF, ALFAMF, BETAMF) = {modification!r}: "
                         "expected 0 < k0 <= 1, 0 <= alpha <= 1, beta >= 0")
    xi, eta, phi = (float(v) for v in creepage)
    nu_phi = eta + phi * a
    if abs(nu_phi) < abs(eta):
        nu_phi = eta
    eps = G * math.pi * a * b * k0 * C11 * math.hypot(xi, nu_phi) / (4 * mu * fn) \
        if mu * fn > 0 else 0.0
    return k0 * (alpha + (1 - alpha) / (1 + beta * eps))


@njit(cache=True, nogil=True)
def fastsim_ellipse(a, b, fn, mu, G, C, creepage, nx, ny):
    """Forces only, for online use (vehicle dynamics): FASTSIM with blended
    flexibilities and the Hertzian traction bound on an ellipse with semi-axes a
    (rolling), b [m], normal force ``fn`` [N], friction ``mu``, shear modulus ``G``
    [Pa], Kalker's coefficients ``C``
    (:class:`~railcontact.tangential.kalker.KalkerCoefficients`) and the creepages
    (:class:`~railcontact.tangential.kalker.Creepage`), ``ny`` strips of ``nx``
    elements.

    Returns (F_x, F_y, M_z) on the wheel [N, N, N m], as :class:`FastsimModel`
    (same flexibilities and march, without grid fields).
    """
    C11, C22, C23 = C.C11, C.C22, C.C23
    xi, eta, phi = creepage.xi, creepage.eta, creepage.phi
    if fn <= 0.0 or a <= 0.0 or b <= 0.0:
        return 0.0, 0.0, 0.0
    L1 = 8.0 * a / (3.0 * C11 * G)
    L2 = 8.0 * a / (3.0 * C22 * G)
    L3 = math.pi * a * math.sqrt(a / b) / (4.0 * G * C23)
    if mu > 0.0:
        c2 = a * b
        f = math.hypot(xi * c2 * G * C11, eta * c2 * G * C22) / (mu * fn)
        w = min(1.0, f / 3.0)
        ps = phi * (math.pi * a * a / 4.0) / (8.0 * a / 3.0)
        den = xi * xi / L1 + eta * eta / L2 + ps * ps / L3
        Lc = (xi * xi + eta * eta + ps * ps) / den if den > 0.0 else L1
        L1, L2, L3 = (1 - w) * L1 + w * Lc, (1 - w) * L2 + w * Lc, (1 - w) * L3 + w * Lc
    p0 = 1.5 * fn / (math.pi * a * b)
    dy = 2.0 * b / ny
    fx = 0.0
    fy = 0.0
    mz = 0.0
    for j in range(ny):
        y = -b + (j + 0.5) * dy
        half = a * math.sqrt(max(0.0, 1.0 - (y / b) ** 2))
        if half <= 0.0:
            continue
        dx = 2.0 * half / nx
        ux = xi / L1 - phi * y / L3
        px = 0.0
        py = 0.0
        prev = half
        for k in range(nx):
            xm = half - (k + 0.5) * dx
            step = prev - xm
            hx = px - step * ux
            hy = py - step * (eta / L2 + phi * 0.5 * (prev + xm) / L3)
            g = mu * p0 * math.sqrt(max(0.0, 1.0 - (xm / a) ** 2 - (y / b) ** 2))
            mag = math.sqrt(hx * hx + hy * hy)
            if mag > g:
                sc = g / mag if mag > 0.0 else 0.0
                px = hx * sc
                py = hy * sc
            else:
                px = hx
                py = hy
            da = dx * dy
            fx += px * da
            fy += py * da
            mz += (xm * py - y * px) * da
            prev = xm
    # the tractions above are those on the rail; the wheel gets the opposite
    return -fx, -fy, -mz


@njit(cache=True, nogil=True)
def semi_ellipse_weights(nx):
    """sqrt(1 - s^2) at the mid-points of nx equal elements of [-1, 1], from the
    leading edge (s = 1)."""
    w = np.empty(nx)
    for i in range(nx):
        s = 1.0 - (2.0 * i + 1.0) / nx
        w[i] = math.sqrt(max(0.0, 1.0 - s * s))
    return w


@njit(cache=True, nogil=True)
def strip_pressures(x_mid, half, p_strip, w, scale, xl, xt, out):
    """Edges (``xl`` leading, ``xt`` trailing) of semi-elliptic strips and ``scale``
    times their pressure at the element mid-points (weights ``w``) into ``out``
    (strips, elements)."""
    for j in range(x_mid.size):
        xl[j] = x_mid[j] + half[j]
        xt[j] = x_mid[j] - half[j]
        for i in range(w.size):
            out[j, i] = scale * p_strip[j] * w[i]


@njit(cache=True, nogil=True)
def strip_patch_forces(st, L, mu, creepage, w, xl, xt, bound):
    """(F_x, F_y, M_z) on the wheel [N, N, N m] of one patch with semi-elliptic
    strip pressures: FASTSIM's strip march (:func:`_fastsim_strips`, ``w.size``
    elements per strip, weights :func:`semi_ellipse_weights`) with the bound
    mu p_j sqrt(1 - ((x - x_mid_j)/l_j)^2).  ``st`` (:class:`StripArrays` of the
    patch: arrays over its strips, ``dy`` its strip width), the flexibilities ``L``
    [m/Pa] and the spin ``creepage.phi`` [1/m] per strip, ``creepage.xi``,
    ``creepage.eta`` of the patch; ``xl``, ``xt`` (strips,) and ``bound`` (strips,
    elements) work arrays.  The batch path (:func:`fastsim_strip_patches`) and the
    compiled case (:mod:`railcontact.cases.strip_pass`) call it."""
    my = st.y.size
    xgrid = np.empty(0)
    none = np.empty((0, my))
    nogrid = Traction(none, none, none, none, np.empty((0, my), dtype=np.bool_))
    strip_pressures(st.x_mid, st.half, st.p_strip, w, mu, xl, xt, bound)
    fx, fy, mz, _ = _fastsim_strips(st.y, st.dy, xl, xt, bound, L, creepage, xgrid, nogrid)
    # the march gives the tractions on the rail; the wheel gets the opposite
    return -fx, -fy, -mz


@njit(cache=True, nogil=True)
def fastsim_strip_patches(strips, L, mu, creepage, nx, out):
    """Forces only, for many patches with semi-elliptic strip pressures (the strip
    models' batch solutions, :mod:`railcontact.normal.strip_batch`):
    :func:`strip_patch_forces` per patch.

    ``strips`` (:class:`StripArrays`) the patches' strips; arrays of shape (patches,
    strips): the flexibilities ``L`` [m/Pa]
    (:class:`~railcontact.tangential.kalker.Flexibilities`) and the spin
    ``creepage.phi`` [1/m] per strip (uniform for ``fastsim``, local for
    ``fastsim-strips``); per patch: ``mu``, ``creepage.xi``, ``creepage.eta``.
    Writes (F_x, F_y, M_z) on the wheel [N, N, N m] into ``out`` (patches, 3);
    patches with L1 <= 0 get zero.
    """
    y, dy, x_mid, half, p_strip = strips.y, strips.dy, strips.x_mid, strips.half, \
        strips.p_strip
    L1, L2, L3 = L.L1, L.L2, L.L3
    xi, eta, phi = creepage.xi, creepage.eta, creepage.phi
    my = y.shape[1]
    bound = np.empty((my, nx))
    xl = np.empty(my)
    xt = np.empty(my)
    w = semi_ellipse_weights(nx)
    for k in range(y.shape[0]):
        if not (L1[k, 0] > 0.0):
            out[k, 0] = 0.0
            out[k, 1] = 0.0
            out[k, 2] = 0.0
            continue
        out[k, 0], out[k, 1], out[k, 2] = strip_patch_forces(
            StripArrays(y[k], dy[k], x_mid[k], half[k], p_strip[k]),
            Flexibilities(L1[k], L2[k], L3[k]), mu[k], Creepage(xi[k], eta[k], phi[k]), w,
            xl, xt, bound)


class FlexMaterial(NamedTuple):
    """The material and tables of the compiled flexibilities
    (:func:`ellipse_flexibilities`)."""

    #: shear modulus G [Pa]
    G: float
    #: Poisson's ratio
    nu: float
    #: contact modulus E* [Pa]
    Es: float
    #: Kalker's tables (:mod:`railcontact.tangential.kalker`)
    kalker_ab: np.ndarray
    kalker_ba: np.ndarray
    #: the Hertz table (:func:`railcontact.core.hertz_theory._axes_table`)
    dt: float
    table: np.ndarray


def flex_material(material) -> FlexMaterial:
    """The :class:`FlexMaterial` of a :class:`~railcontact.core.materials.Material`."""
    from ..core.hertz_theory import _axes_table
    from .kalker import _TAB_AB, _TAB_BA
    dt, tab = _axes_table()
    return FlexMaterial(float(material.shear_modulus), float(material.nu),
                        float(material.contact_modulus), _TAB_AB, _TAB_BA, dt, tab)


@njit(cache=True, nogil=True)
def ellipse_flexibilities(a, b, fn, creepage, mu, mat):
    """FASTSIM's flexibilities (L1, L2, L3) [m/Pa] of an ellipse (a, b) [m] with
    normal force ``fn`` [N], blended towards the combined flexibility as the
    creepage ``creepage`` (xi, eta, phi) grows (:func:`blended_flexibilities`,
    friction ``mu``; ``mat`` a :class:`FlexMaterial`); unblended where fn <= 0."""
    xi, eta, phi = creepage
    c11, c22, c23 = coefficients_at(a / b, mat.nu, mat.kalker_ab, mat.kalker_ba)
    G = mat.G
    L1 = 8.0 * a / (3.0 * c11 * G)
    L2 = 8.0 * a / (3.0 * c22 * G)
    L3 = math.pi * a * math.sqrt(a / b) / (4.0 * G * c23)
    if not fn > 0.0:
        return L1, L2, L3
    c2 = a * b
    w = min(1.0, math.hypot(xi * c2 * G * c11, eta * c2 * G * c22) / (mu * fn) / 3.0)
    ps = phi * (math.pi * a * a / 4.0) / (8.0 * a / 3.0)
    num = xi * xi + eta * eta + ps * ps
    den = xi * xi / L1 + eta * eta / L2 + ps * ps / L3
    Lc = num / den if den > 0.0 else L1
    return (1.0 - w) * L1 + w * Lc, (1.0 - w) * L2 + w * Lc, (1.0 - w) * L3 + w * Lc


@njit(cache=True, nogil=True)
def strip_flexibilities(half, A, B, pen, ellipse, creepage, mu, mat, local, L):
    """Flexibilities per strip of one strip-model patch into ``L`` (3, strips):
    those of its equivalent ellipse (``ellipse``: a, b [m] and the normal force F_n
    [N]; :func:`ellipse_flexibilities`) on every strip, or with ``local``
    (``fastsim-strips``) on each loaded strip those of its local ellipse, the
    Hertz ellipse of the gap's curvatures ``A``, ``B`` [1/m] at the strip for the
    approach ``pen`` [m] (Ayasse & Chollet 2005), blended with the patch's F_n;
    zero where the patch carries no load.  The batch path and the compiled case
    call it."""
    a, b, fn = ellipse
    if not (fn > 0.0 and a > 0.0 and b > 0.0):
        L[:] = 0.0
        return
    L1, L2, L3 = ellipse_flexibilities(a, b, fn, creepage, mu, mat)
    for j in range(half.size):
        L[0, j], L[1, j], L[2, j] = L1, L2, L3
        if local and pen > 0.0 and half[j] > 0.0:
            la, lb, _ = axes_at(A[j], B[j], pen, mat.Es, mat.dt, mat.table)
            L[0, j], L[1, j], L[2, j] = ellipse_flexibilities(la, lb, fn, creepage, mu, mat)


@njit(cache=True, nogil=True)
def _strip_flexibilities_kernel(half, A, B, pen, ellipses, creep, mu, mat, local, L):
    for k in range(half.shape[0]):
        strip_flexibilities(half[k], A[k], B[k], pen[k],
                            (ellipses[0, k], ellipses[1, k], ellipses[2, k]),
                            (creep[0, k], creep[1, k], creep[2, k]), mu, mat, local, L[:, k])


def batch_flexibilities(strips, a, b, ok, creepage, material, friction, local):
    """Flexibilities (3, patches, strips) of many strip-model patches
    (:func:`strip_flexibilities` per patch; ``ok``: the patches that carry load)."""
    F = np.where(ok, strips.normal_force, 0.0)
    n, my = strips.y.shape
    L = np.zeros((3, n, my))
    pen = np.ascontiguousarray(np.broadcast_to(np.asarray(strips.penetration, float), (n,)))
    _strip_flexibilities_kernel(np.ascontiguousarray(strips.half),
                                np.ascontiguousarray(strips.A), np.ascontiguousarray(strips.B),
                                pen, np.array([a, b, F], dtype=float),
                                np.array(creepage, dtype=float), float(friction),
                                flex_material(material), bool(local), L)
    return L


def equivalent_ellipse(normal) -> tuple:
    """Semi-axes (a, b) [m] of the ellipse equivalent to a patch.

    Uses the model's own ellipse when it has one; otherwise the Kik-Piotrowski rule
    a = sqrt(A/pi) sqrt(L/W), b = sqrt(A/pi) sqrt(W/L) from the area A and the
    extents L (rolling) and W (lateral) of the contact.
    """
    if normal.semi_axes is not None:
        return normal.semi_axes
    mask = normal.contact
    if not mask.any():
        return (0.0, 0.0)
    xs, ys = normal.x[mask.any(axis=1)], normal.y[mask.any(axis=0)]
    L = xs.max() - xs.min() + normal.dx
    W = ys.max() - ys.min() + normal.dy
    r = math.sqrt(normal.area / math.pi)
    return r * math.sqrt(L / W), r * math.sqrt(W / L)


def blend_weight(a, b, c11, c22, G, xi, eta, mu, fn, contact: bool = False):
    """How far the creepage is from the linear range: min(1, f/3) with
    f = |(xi/xi_c, eta/eta_c)| = |(xi c^2 G C11, eta c^2 G C22)| / (mu F_n), or with
    ``contact`` CONTACT's f = sqrt((xi^2 + eta^2) / (xi_c^2 + eta_c^2)) (its
    ``simpflex``, :func:`contact_flexibilities`; Vollebregt & Voltr 2023);
    xi_c = mu F_n/(c^2 G C11), eta_c = mu F_n/(c^2 G C22), c^2 = a b (0 where
    F_n <= 0).  The two agree where C11 = C22."""
    c2 = a * b
    with np.errstate(divide="ignore", invalid="ignore"):
        if contact:
            f = (np.hypot(xi, eta) * c2 * G / (mu * fn)
                 / np.hypot(1.0 / np.asarray(c11, dtype=float),
                            1.0 / np.asarray(c22, dtype=float)))
        else:
            f = np.hypot(xi * c2 * G * c11, eta * c2 * G * c22) / (mu * fn)
    return np.where(np.asarray(fn) > 0, np.minimum(1.0, f / 3.0), 0.0)


def blended_flexibilities(a, b, L, G, nu, creepage, mu, fn, coefficients=None,
                          contact: bool = False):
    """Flexibilities blended towards a combined value as the creepage grows
    (scalars, or arrays of semi-axes and flexibilities, elementwise).

    ``a``, ``b`` the semi-axes [m], ``L`` the flexibilities (L1, L2, L3) [m/Pa], ``G``
    [Pa] and ``nu`` the material, ``creepage`` (xi, eta, phi), ``mu`` the friction and
    ``fn`` the normal force [N]; ``coefficients``: Kalker's (C11, C22) of the
    ellipses, where already known; ``contact``: CONTACT's blending weight
    (:func:`blend_weight`).  Returns (L1, L2, L3)."""
    L1, L2, L3 = L
    xi, eta, phi = creepage
    if np.ndim(fn) == 0 and (mu <= 0 or fn <= 0):
        return L1, L2, L3
    if coefficients is not None:
        c11, c22 = coefficients
    elif np.ndim(a) == 0:
        c11, c22, _ = kalker_coefficients(a / b, nu)          # cached scalar path
    else:
        a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        c11, c22, _ = kalker_coefficients_array(a / b, nu)
    w = blend_weight(a, b, c11, c22, G, xi, eta, mu, fn, contact)
    ps = phi * (math.pi * a * a / 4) / (8 * a / 3)
    num = xi * xi + eta * eta + ps * ps
    den = np.float64(xi * xi / L1 + eta * eta / L2 + ps * ps / L3)
    with np.errstate(divide="ignore", invalid="ignore"):
        Lc = np.where(den > 0, num / den, L1)
    out = ((1 - w) * L1 + w * Lc, (1 - w) * L2 + w * Lc, (1 - w) * L3 + w * Lc)
    if np.ndim(out[0]) == 0:
        return tuple(float(v) for v in out)
    return out


@register("fastsim")
class FastsimModel:
    """Kalker's FASTSIM with three flexibilities.

    Parameters
    ----------
    bound : {"elliptic", "parabolic"}
        Traction bound: Hertzian pressure (default) or Kalker's parabolic one.
    elements : int, optional
        Elements per strip in the rolling direction (default: the grid's mx).
    falling : dict, optional
        {"A": mu_inf/mu0, "B": s/m}: slip-velocity dependent friction
        mu = mu0 ((1 - A) exp(-B w) + A) (Polach 2005), with w the local slip velocity
        |s| V, solved by a damped fixed-point iteration on the local coefficients.
    flexibility : {"blended", "contact", "three", "single"}
        ``"three"``: Kalker's L1, L2, L3 (exact in the linear range, but at large
        creepage the force direction is distorted when L1 != L2).
        ``"blended"`` (default): the three flexibilities are blended towards one
        combined flexibility as the creepage grows (after Vollebregt & Voltr, VSD 61,
        2023; CONTACT's weight differs where C11 != C22, ``"contact"``): weight
        w = min(1, f/3), f = |(xi/xi_c, eta/eta_c)| with xi_c = mu F_n/(c^2 G C11),
        eta_c = mu F_n/(c^2 G C22); combined L = (xi^2 + eta^2 + (phi f4/f3)^2) /
        (xi^2/L1 + eta^2/L2 + (phi f4/f3)^2/L3), f3 = 8a/3, f4 = pi a^2/4.
        ``"contact"``: blended as CONTACT blends them (its M = 3; the ``.inp``
        path's choice): the weight's f = sqrt((xi^2 + eta^2)/(xi_c^2 +
        eta_c^2)) (:func:`contact_flexibilities`); on mbench_a22_kpec.inp case 2
        L1, L3 4.6 % apart from ``"blended"``'s, F_s 0.4 % of mu F_n.
        ``"single"``: Kalker's single weighted flexibility.
    march : {"strips", "grid"}
        ``"strips"`` (default): every strip marched over ``elements`` elements between
        its own edges (``normal.strips``), the pressure interpolated to their
        mid-points.  ``"grid"``: CONTACT's march (modified FASTSIM, M = 3, on its
        grid): every row of the normal solution's grid marched element by element
        from its leading element, one element (dq = dx) per step, the bound mu p at
        the element centres, the spin's lever taken dq/6 ahead
        (:func:`fastsim_grid`); the ``.inp`` path's choice.  Not with ``falling``
        or the parabolic bound.
    """

    capabilities = frozenset({"online", "strip-march"})
    #: code of the compiled law (:mod:`railcontact.tangential.online`)
    online_law = 1

    def __init__(self, bound: str = "elliptic", elements: int | None = None,
                 flexibility: str = "blended", falling=None, march: str = "strips"):
        if bound not in ("elliptic", "parabolic"):
            raise InputError(f"fastsim bound {bound!r}: expected 'elliptic' or 'parabolic'")
        if flexibility not in ("blended", "contact", "three", "single"):
            raise InputError(f"fastsim flexibility {flexibility!r}: expected 'blended', "
                             "'contact', 'three' or 'single'")
        if elements is not None and not (isinstance(elements, int) and 2 <= elements <= 5000):
            raise InputError(f"fastsim elements {elements!r}: expected an integer in [2, 5000]")
        if march not in ("strips", "grid"):
            raise InputError(f"fastsim march {march!r}: expected 'strips' or 'grid'")
        if march == "grid" and (falling is not None or bound != "elliptic"):
            raise InputError("fastsim march 'grid': expected the elliptic bound (the normal "
                             "solution's pressure) and no falling friction")
        self.march = march
        self.bound = bound
        self.elements = elements
        self.flexibility = flexibility
        self.falling = falling_friction(falling)

    def _strip_parameters(self, normal, geometry, material, a, b, creepage, friction):
        """Flexibilities L1, L2, L3 [m/Pa] and spin [1/m] per strip (arrays over y)."""
        xi, eta, phi = creepage
        G, nu = material.shear_modulus, material.nu
        L = self._flexibilities(a, b, G, nu, creepage, friction, normal.normal_force)
        my = normal.y.size
        return (*(np.full(my, v) for v in L), np.full(my, phi))

    @classmethod
    def strip_forces(cls, strips, patches, a, b, ok, creepage, material, friction,
                     elements, out):
        """Forces of many strip-model patches at once (:mod:`railcontact.cases.batch`).

        ``strips`` is a :class:`~railcontact.normal.strip_batch.StripSolution`,
        (a, b) [m] the patches' equivalent ellipses (``ok`` where they carry load),
        ``creepage`` the arrays (xi, eta, phi); FASTSIM marches every strip's
        semi-elliptic pressure with ``elements`` elements and writes
        (F_x, F_y, M_z) [N, N, N m] into ``out`` (patches, 3).
        """
        L, spin = cls._batch_flexibilities(strips, patches, a, b, ok, creepage, material,
                                           friction)
        xi, eta, _ = creepage
        fastsim_strip_patches(StripArrays.of(strips),
                              Flexibilities(*(np.ascontiguousarray(v) for v in L)),
                              np.full(xi.size, float(friction)), Creepage(xi, eta, spin),
                              int(elements), out)

    @staticmethod
    def _batch_flexibilities(strips, patches, a, b, ok, creepage, material, friction):
        """Blended flexibilities of each patch's equivalent ellipse on all its strips,
        and the patch's spin: arrays (3, patches, strips) and (patches, strips)."""
        L = batch_flexibilities(strips, a, b, ok, creepage, material, friction, False)
        return L, np.repeat(np.asarray(creepage[2], float)[:, None], strips.y.shape[1], axis=1)

    def _reported_flexibilities(self, L1, L2, L3):
        """Flexibilities for the solution's options: one value each (uniform)."""
        return (float(L1[0]), float(L2[0]), float(L3[0]))

    def _flexibilities(self, a, b, G, nu, creepage, friction, fn):
        """The three flexibilities of an ellipse (a, b) with this model's option."""
        xi, eta, phi = creepage
        if np.ndim(a):
            L1, L2, L3 = flexibilities_array(a, b, G, nu)
        else:
            L1, L2, L3 = flexibilities(a, b, G, nu)
        if self.flexibility in ("blended", "contact"):
            L1, L2, L3 = blended_flexibilities(a, b, (L1, L2, L3), G, nu, creepage, friction,
                                               fn, contact=self.flexibility == "contact")
        elif self.flexibility == "single":
            c = np.sqrt(a * b)
            den = np.sqrt(xi * xi + (c * phi) ** 2 + eta * eta)
            if np.all(den > 0):
                L = (abs(xi) * L1 + abs(eta) * L2 + c * abs(phi) * L3) / den
                L1 = L2 = L3 = L
        return L1, L2, L3

    def solve(self, normal, geometry=None, material: Material = STEEL, creepage=(0.0, 0.0, 0.0),
              friction: float = 0.3, velocity: float = 1.0) -> TangentialSolution:
        """Creep forces for creepages (xi [-], eta [-], phi [1/m]).

        Parameters
        ----------
        normal : NormalSolution
        creepage : (xi, eta, phi)
            Rigid slip of the rail relative to the wheel / V (CONTACT's convention).
        friction : float
            Coulomb friction coefficient mu.
        velocity : float
            Rolling velocity V [m/s] (scales slip velocities and frictional power).
        """
        t0 = time.perf_counter()
        xi, eta, phi = check_inputs(creepage, friction)
        a, b = equivalent_ellipse(normal)
        mx, my = normal.x.size, normal.y.size
        zeros = np.zeros((mx, my))
        if a <= 0 or b <= 0 or normal.normal_force <= 0:
            return TangentialSolution(self.name, normal.x, normal.y, zeros, zeros.copy(),
                                      zeros.copy(), zeros.copy(), np.zeros((mx, my), bool),
                                      normal.contact, 0.0, 0.0, 0.0, velocity, (xi, eta, phi),
                                      friction)
        if getattr(self, "march", "strips") == "grid":
            return self._solve_grid(normal, material, a, b, (xi, eta, phi), friction,
                                    velocity, t0)
        L1, L2, L3, phis = self._strip_parameters(normal, geometry, material, a, b,
                                                  (xi, eta, phi), friction)
        x_lead, x_trail = normal.strips
        nx = self.elements or mx
        frac = (np.arange(nx) + 0.5) / nx
        xm = x_lead[:, None] - frac[None, :] * (x_lead - x_trail)[:, None]
        ym = np.broadcast_to(normal.y[:, None], xm.shape)
        if self.bound == "elliptic":
            pn = normal.pressure_at(xm, ym)
        else:
            pn = (2 * normal.normal_force / (math.pi * a * b)
                  * np.clip(1 - (xm / a) ** 2 - (ym / b) ** 2, 0.0, None))
        pn = np.ascontiguousarray(pn, dtype=float)
        mu_mid = np.full(pn.shape, float(friction))
        if self.falling is not None:      # grid cell of each mid-point
            ix = np.clip(np.searchsorted(normal.x, xm), 0, mx - 1)
            iy = np.broadcast_to(np.arange(my)[:, None], xm.shape)
        iters = 0
        for iters in range(1, 61 if self.falling is not None else 2):
            bound = np.ascontiguousarray(mu_mid * pn)
            px, py, sx, sy = (np.zeros((mx, my)) for _ in range(4))
            stick = np.zeros((mx, my), dtype=bool)
            fx1, fy1, mz1, pw = _fastsim_strips(np.ascontiguousarray(normal.y), normal.dy,
                                                np.ascontiguousarray(x_lead, dtype=float),
                                                np.ascontiguousarray(x_trail, dtype=float),
                                                bound, Flexibilities(L1, L2, L3),
                                                Creepage(xi, eta, phis),
                                                np.ascontiguousarray(normal.x),
                                                Traction(px, py, sx, sy, stick))
            if self.falling is None:
                break
            w = np.hypot(sx, sy)[ix, iy] * velocity
            new = self.falling(friction, w)
            change = float(np.max(np.abs(new - mu_mid)))
            mu_mid = 0.5 * mu_mid + 0.5 * new
            if change < 1e-5 * friction:
                break
        contact = normal.contact
        stick &= contact
        # body 1 is the rail: the tractions on the wheel are the opposite
        flex = self._reported_flexibilities(L1, L2, L3)
        return TangentialSolution(self.name, normal.x, normal.y, -px, -py, sx, sy, stick,
                                  contact, -fx1, -fy1, -mz1, velocity, (xi, eta, phi), friction,
                                  time.perf_counter() - t0,
                                  {"bound": self.bound, "flexibilities": flex,
                                   "friction_iterations": iters},
                                  power=abs(float(pw)) * velocity)

    def _solve_grid(self, normal, material, a, b, creepage, friction, velocity, t0):
        """CONTACT's element march on the normal solution's grid (``march="grid"``,
        :func:`fastsim_grid`), with this model's flexibilities of the equivalent
        ellipse (a, b) [m]."""
        xi, eta, phi = creepage
        L = self._flexibilities(a, b, material.shear_modulus, material.nu, creepage,
                                friction, normal.normal_force)
        x, y = np.ascontiguousarray(normal.x), np.ascontiguousarray(normal.y)
        mx, my = x.size, y.size
        bound = np.ascontiguousarray(np.where(normal.contact, friction * normal.pressure, 0.0))
        px, py, sx, sy = (np.zeros((mx, my)) for _ in range(4))
        stick = np.zeros((mx, my), dtype=np.bool_)
        fastsim_grid(x, y, bound, np.array([float(v) for v in L]),
                     np.array([xi, eta, phi], dtype=float), normal.dx / 6.0, px, py, sx, sy,
                     stick)
        dA = normal.dx * normal.dy
        fx, fy = float(px.sum() * dA), float(py.sum() * dA)
        mz = float((x[:, None] * py - y[None, :] * px).sum() * dA)
        # frictional power per unit velocity: |p| |s| over the slipping elements
        pw = float((np.hypot(px, py) * np.hypot(sx, sy)).sum() * dA)
        flex = tuple(float(v) for v in L)
        # body 1 is the rail: the tractions on the wheel are the opposite
        return TangentialSolution(self.name, normal.x, normal.y, -px, -py, sx, sy,
                                  stick & normal.contact, normal.contact, -fx, -fy, -mz,
                                  velocity, creepage, friction, time.perf_counter() - t0,
                                  {"bound": self.bound, "flexibilities": flex,
                                   "friction_iterations": 1, "march": "grid"},
                                  power=pw * velocity)
