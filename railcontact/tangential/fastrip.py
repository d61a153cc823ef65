"""FaStrip-type tangential model: strip theory for xi, eta and FASTSIM for spin
(``tangential="fastrip"``).

Sichani, Enblom & Berg (2016), "An alternative to FASTSIM for tangential solution
of the wheel-rail contact", *Vehicle System Dynamics* 54(6), 748-764, combine
Kalker's strip theory (longitudinal and lateral creepage) with a FASTSIM-type
treatment of spin.  The paper was not available to check its equations; this
module is our own formulation of that combination, from the facts below.

**Strip theory** (Haines & Ollerton; Kalker's extension to combined creepage).
Every strip (fixed y) is a 2-D rolling contact with a semi-elliptic pressure of
half-length l(y), centre x_c(y) and peak p0(y) (the strip's load is conserved).
Carter's solution holds per strip: the adhesion zone of half-length k l lies at the
leading edge, the traction is

    q = mu p0 [ sqrt(1 - ((x - x_c)/l)^2) - k sqrt(1 - ((x - x_s)/(k l))^2) ],

x_s = x_c + l - k l, with the second term only inside the adhesion zone, and
1 - k(y) = |w| / (mu p0(y)) (clipped to [0, 1]) with the weighted creepage
w = (2 G / pi^2) (C11 xi, C22 eta).  The factor 2 G C/pi^2 makes the small-creepage
force of an elliptic patch G a b (C11 xi, C22 eta), Kalker's linear theory; for a
slender ellipse (b >> a, C -> pi^2/(4 (1 - nu))) it is the 2-D E*/2 of Carter's
solution.  The traction direction is that of w in the linear range, blended
towards the creepage direction as the creepage grows (the weight min(1, f/3) of
``fastsim``'s blended flexibilities), so that full sliding follows the creepage.
The slip in the slip zone is Carter's, |s| = mu p0 / (K l) sqrt((x - x_s)^2 -
(k l)^2), K = |w| / |(xi, eta)|; beyond full slip (|w| > mu p0) the rigid excess
(|w| - mu p0)/K is added.  Slip starts at the lateral edges of the patch, where p0
is small (the lens-shaped adhesion area of strip theory).

**Spin** is added by FASTSIM's march (Kalker 1982) along every strip, with the
spin flexibility L3 of the equivalent ellipse.  From the leading edge, the trial
traction is the previous one plus the increment of the strip-theory traction (cell
means, so that the march integrates it exactly), plus, in the strip-theory slip
zone, the strip's slip times step / L3 (FASTSIM's rigid-slip increment), plus
FASTSIM's spin increment; where it exceeds mu p it is scaled back and the excess
is the slip.  Without spin this is strip theory exactly; a pure spin gives
FASTSIM's spin solution; with both, the slip direction weighs the translational
against the spin slip.

**CONTACT's Modified FaStrip** (its M = 5; Vollebregt 2025, "indicators" paper,
after Sichani, Enblom & Berg 2016) is a different combination:
:func:`contact_fastrip_rows` runs after CONTACT's modified-FASTSIM march on its
grid and replaces, per row, the tractions of the strip theory's adhesion zone
(Kalker's strip theory with spin in Sichani's non-dimensional creepages,
:func:`contact_strip_creepages`), leaving FASTSIM's slip behind it.  The ``.inp``
path takes it for M = 5 with B = 2, 3 (:mod:`railcontact.contact_inp.module3`);
``tangential="fastrip"`` (this module's model) remains railcontact's own
formulation above.

C11, C22 and L3 come from the patch's equivalent ellipse (as ``fastsim``).  The
strip quantities come from the normal solution: edges from ``normal.strips``,
p0 = 2 (integral of p dx) / (pi l).  Optional falling friction (same law as
``fastsim``) is applied per strip, from the mean slip velocity of the strip's
slipping elements.
"""

from __future__ import annotations

import math
import time
from typing import NamedTuple

import numpy as np
from numba import njit

from ..core.errors import InputError
from ..core.materials import Material, STEEL
from .base import TangentialSolution, check_inputs, register
from .fastsim import (StripArrays, Traction, _strip_to_grid, blend_weight, equivalent_ellipse,
                      semi_ellipse_weights, strip_pressures)
from .friction import falling_friction
from .kalker import (flexibilities, flexibilities_array, kalker_coefficients,
                     kalker_coefficients_array)


@njit(cache=True, nogil=True)
def _march(y, dy, x_lead, x_trail, bound, dqx, dqy, L3, phi, xgrid, grid):
    """March every strip from its leading edge: the trial traction (on the rail) is
    the previous one plus the strip-theory increment (dqx, dqy) [Pa] and FASTSIM's
    spin increment (flexibility ``L3`` [m/Pa], spin ``phi`` [1/m]); where it exceeds
    the bound [Pa] it is scaled back, and the excess over the bound is the slip
    (times L3 / step, as in FASTSIM).  ``y`` (my,) the strips' positions [m], ``dy``
    their width [m], ``x_lead``, ``x_trail`` their edges [m], ``xgrid`` the grid's x
    [m].  Returns the forces on the rail (mid-point rule) and the frictional power
    per unit velocity, sum |p| |s| dx dy over the slipping mid-points [N], and fills
    the grid fields ``grid`` (:class:`~railcontact.tangential.fastsim.Traction`)."""
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
            hx = px + dqx[j, k] + step * phi * y[j] / L3
            hy = py + dqy[j, k] - step * phi * xmid / L3
            g = bound[j, k]
            mag = math.sqrt(hx * hx + hy * hy)
            slip = 0.0
            if mag > g * (1.0 + 1e-9):
                sc = g / mag
                px = hx * sc
                py = hy * sc
                slip = L3 * (mag - g) / step
            else:
                if mag > g:
                    sc = g / mag
                    hx *= sc
                    hy *= sc
                px = hx
                py = hy
            pm = math.sqrt(px * px + py * py)
            if slip > 0.0 and pm > 0.0:
                sxs[k] = -slip * px / pm          # along the traction on the wheel
                sys_[k] = -slip * py / pm
                sts[k] = False
                pw += slip * pm * dx * dy
            else:
                sxs[k] = 0.0
                sys_[k] = 0.0
                sts[k] = True
            pxs[k] = px
            pys[k] = py
            fx += px * dx * dy
            fy += py * dx * dy
            mz += (xm * py - y[j] * px) * dx * dy
            prev = xm
        _strip_to_grid(j, x_lead[j], x_trail[j], dx, xgrid, strip, grid)
    return fx, fy, mz, pw


@njit(cache=True, nogil=True)
def _ellipse_area(u):
    """Integral of sqrt(1 - t^2) from 0 to u, for u clipped to [-1, 1]."""
    if u >= 1.0:
        return 0.25 * math.pi
    if u <= -1.0:
        return -0.25 * math.pi
    return 0.5 * (u * math.sqrt(1.0 - u * u) + math.asin(u))


@njit(cache=True, nogil=True)
def _strip_increments(x_lead, x_trail, p0, pn, mu, wn, K, L3, dq, bound):
    """Strip theory on every strip of one patch, for the spin march (:func:`_march`).

    Strip j (edges ``x_lead``, ``x_trail``, peak pressure ``p0``, friction ``mu``)
    has Carter's adhesion zone of half-length k l at the leading edge,
    1 - k = wn / (mu p0).  Per element (``nx`` = pn.shape[1] from the leading edge):
    ``dq`` the increment of the cell-mean strip traction (exact cell integrals of
    both semi-ellipses of Carter's traction), plus in the slip zone Carter's slip
    (and the rigid excess of full sliding) times step / L3; ``bound``
    mu max(pn, q / mu) with ``pn`` the pressure at the mid-points.
    """
    my, nx = pn.shape
    for j in range(my):
        length = x_lead[j] - x_trail[j]
        if not length > 0.0:
            dq[j, :] = 0.0
            bound[j, :] = 0.0
            continue
        half = 0.5 * length
        xc = x_lead[j] - half
        ex = length / nx
        mp = mu[j] * p0[j]
        k = min(max(1.0 - wn / mp, 0.0), 1.0) if mp > 0.0 else 0.0
        ka = k * half
        xs = xc + half - ka
        excess = max(wn - mp, 0.0) / K
        prev = 0.0
        e1 = 0.25 * math.pi                 # integrals to the cell's leading edge
        e2 = 0.25 * math.pi
        for i in range(nx):
            xm = x_lead[j] - (i + 0.5) * ex
            x1 = xm - 0.5 * ex              # trailing edge of the cell
            f1 = _ellipse_area((x1 - xc) / half)
            q = half * (e1 - f1)
            e1 = f1
            if ka > 0.0 and e2 > -0.25 * math.pi:       # the adhesion zone's ellipse
                f2 = _ellipse_area((x1 - xs) / ka)
                q -= k * ka * (e2 - f2)
                e2 = f2
            q *= mp / ex
            d = q - prev
            prev = q
            if xm < xs - ka and abs(xm - xc) < half:       # strip-theory slip zone
                fac = math.sqrt(max((xm - xs) ** 2 - ka * ka, 0.0))
                step = 0.5 * ex if i == 0 else ex
                d += step * (mp / (K * half) * fac + excess) / L3
            dq[j, i] = d
            bound[j, i] = max(mu[j] * pn[j, i], q)


def strip_parameters(a, b, fn, xi, eta, c11, c22, G, mu):
    """Per-patch constants of the strip theory (scalars or arrays): the weighted
    creepage magnitude wn [Pa], the traction direction (ex, ey) and K = wn / |(xi,
    eta)| [Pa] (module notes)."""
    wx = 2 * G * c11 * xi / math.pi ** 2
    wy = 2 * G * c22 * eta / math.pi ** 2
    wn = np.hypot(wx, wy)
    cn = np.hypot(xi, eta)
    with np.errstate(divide="ignore", invalid="ignore"):
        ex, ey = np.where(wn > 0, wx / wn, 0.0), np.where(wn > 0, wy / wn, 0.0)
        K = np.where(cn > 0, wn / cn, 1.0)
        # the direction of w in the linear range, blended towards the creepage
        # direction as the creepage grows (as fastsim's flexibilities)
        wb = blend_weight(a, b, c11, c22, G, xi, eta, mu, fn)
        dx = (1 - wb) * ex + wb * np.where(cn > 0, xi / cn, 0.0)
        dy = (1 - wb) * ey + wb * np.where(cn > 0, eta / cn, 0.0)
        dn = np.hypot(dx, dy)
        ex, ey = np.where(dn > 0, dx / dn, 0.0), np.where(dn > 0, dy / dn, 0.0)
    return wn, ex, ey, K


@njit(cache=True, nogil=True)
def fastrip_strip_patches(strips, mu, wn, ex, ey, K, L3, phi, nx, out):
    """Forces only, for many patches with semi-elliptic strip pressures (the strip
    models' batch solutions, :mod:`railcontact.normal.strip_batch`): the strip theory
    (:func:`_strip_increments`) and the spin march (:func:`_march`, ``nx`` elements
    per strip) of :class:`FastripModel`.

    ``strips`` (:class:`~railcontact.tangential.fastsim.StripArrays`) the patches'
    strips; per patch: ``mu``, ``wn``, ``ex``, ``ey``, ``K`` (:func:`strip_parameters`),
    ``L3`` [m/Pa] of the equivalent ellipse and the spin ``phi`` [1/m].  Writes
    (F_x, F_y, M_z) on the wheel into ``out`` (patches, 3); patches with L3 <= 0 get
    zero.
    """
    y, dy, x_mid, half, p_strip = strips.y, strips.dy, strips.x_mid, strips.half, \
        strips.p_strip
    my = y.shape[1]
    xl = np.empty(my)
    xt = np.empty(my)
    mus = np.empty(my)
    pn = np.empty((my, nx))
    dq = np.empty((my, nx))
    bound = np.empty((my, nx))
    dqx = np.empty((my, nx))
    dqy = np.empty((my, nx))
    xgrid = np.empty(0)
    none = np.empty((0, my))
    nogrid = Traction(none, none, none, none, np.empty((0, my), dtype=np.bool_))
    w = semi_ellipse_weights(nx)
    for k in range(y.shape[0]):
        if not (L3[k] > 0.0 and mu[k] > 0.0):
            out[k, 0] = 0.0
            out[k, 1] = 0.0
            out[k, 2] = 0.0
            continue
        strip_pressures(x_mid[k], half[k], p_strip[k], w, 1.0, xl, xt, pn)
        mus[:] = mu[k]
        _strip_increments(xl, xt, p_strip[k], pn, mus, wn[k], K[k], L3[k], dq, bound)
        for j in range(my):
            for i in range(nx):
                dqx[j, i] = -ex[k] * dq[j, i]      # rail tractions: opposite to the wheel's
                dqy[j, i] = -ey[k] * dq[j, i]
        fx, fy, mz, _ = _march(y[k], dy[k], xl, xt, bound, dqx, dqy, L3[k], phi[k], xgrid,
                               nogrid)
        out[k, 0] = -fx
        out[k, 1] = -fy
        out[k, 2] = -mz


@register("fastrip")
class FastripModel:
    """Strip theory for longitudinal and lateral creepage, FASTSIM for spin.

    Parameters
    ----------
    elements : int, optional
        Elements per strip for the spin march (default: the grid's mx).
    falling : dict, optional
        {"A": mu_inf/mu0, "B": s/m}: slip-velocity dependent friction (Polach 2005),
        one coefficient per strip from the mean slip velocity of its slip zone.
    """

    capabilities = frozenset({"strip-march"})

    def __init__(self, elements: int | None = None, falling=None):
        if elements is not None and not (isinstance(elements, int) and 2 <= elements <= 5000):
            raise InputError(f"fastrip elements {elements!r}: expected an integer in [2, 5000]")
        self.elements = elements
        self.falling = falling_friction(falling)

    @staticmethod
    def strip_forces(strips, patches, a, b, ok, creepage, material, friction, elements, out):
        """Forces of many strip-model patches at once (:mod:`railcontact.cases.batch`;
        arguments as :meth:`railcontact.tangential.fastsim.FastsimModel.strip_forces`):
        FaStrip's strip theory on each patch's equivalent ellipse and its spin march
        over the strips."""
        xi, eta, phi = creepage
        G, nu = material.shear_modulus, material.nu
        n = xi.size
        c11, c22, L3 = np.ones(n), np.ones(n), np.zeros(n)
        if ok.any():
            c11[ok], c22[ok], _ = kalker_coefficients_array(a[ok] / b[ok], nu)
            L3[ok] = flexibilities_array(a[ok], b[ok], G, nu)[2]
        with np.errstate(divide="ignore", invalid="ignore"):
            wn, ex, ey, K = strip_parameters(a, b, strips.normal_force, xi, eta, c11, c22, G,
                                             friction)
        fastrip_strip_patches(StripArrays.of(strips), np.full(n, float(friction)), wn, ex, ey, K, L3, phi,
                              int(elements), out)

    def solve(self, normal, geometry=None, material: Material = STEEL, creepage=(0.0, 0.0, 0.0),
              friction: float = 0.3, velocity: float = 1.0) -> TangentialSolution:
        """Creep forces for creepages (xi [-], eta [-], phi [1/m]); see the module notes."""
        t0 = time.perf_counter()
        xi, eta, phi = check_inputs(creepage, friction)
        x, y = normal.x, normal.y
        mx, my = x.size, y.size
        a, b = equivalent_ellipse(normal)
        zeros = np.zeros((mx, my))
        if a <= 0 or b <= 0 or normal.normal_force <= 0 or friction <= 0:
            return TangentialSolution(self.name, x, y, zeros, zeros.copy(), zeros.copy(),
                                      zeros.copy(), np.zeros((mx, my), bool), normal.contact,
                                      0.0, 0.0, 0.0, velocity, (xi, eta, phi), friction)
        G, nu = material.shear_modulus, material.nu
        c11, c22, _ = kalker_coefficients(a / b, nu)
        wn, ex, ey, K = (float(v) for v in strip_parameters(a, b, normal.normal_force, xi,
                                                            eta, c11, c22, G, friction))
        # strips: edges and peak pressure (load conserving)
        x_lead, x_trail = (np.ascontiguousarray(v, dtype=float) for v in normal.strips)
        half = 0.5 * np.maximum(x_lead - x_trail, 0.0)
        load = normal.pressure.sum(axis=0) * normal.dx
        with np.errstate(divide="ignore", invalid="ignore"):
            p0 = np.where(half > 0, 2 * load / (math.pi * half), 0.0)
        # FASTSIM spin march: mid-points of nx elements per strip
        nx = self.elements or mx
        frac = (np.arange(nx) + 0.5) / nx
        xm = x_lead[:, None] - frac[None, :] * (x_lead - x_trail)[:, None]
        ym = np.broadcast_to(y[:, None], xm.shape)
        pn = np.ascontiguousarray(normal.pressure_at(xm, ym), dtype=float)
        L3 = flexibilities(a, b, G, nu)[2]
        mu = np.full(my, float(friction))
        dq, bound = np.empty((my, nx)), np.empty((my, nx))
        iters = 0
        for iters in range(1, 61 if self.falling is not None else 2):
            _strip_increments(x_lead, x_trail, p0, pn, mu, wn, K, L3, dq, bound)
            px, py, sx, sy = (np.zeros((mx, my)) for _ in range(4))
            stick = np.zeros((mx, my), dtype=bool)
            # rail tractions: opposite to the wheel's (direction e)
            fxr, fyr, mzr, pw = _march(np.ascontiguousarray(y), normal.dy, x_lead, x_trail,
                                       bound, -ex * dq, -ey * dq, L3, phi,
                                       np.ascontiguousarray(x), Traction(px, py, sx, sy, stick))
            if self.falling is None:
                break
            w = np.hypot(sx, sy) * velocity
            nslip = np.maximum((w > 0).sum(axis=0), 1)
            new = self.falling(friction, w.sum(axis=0) / nslip)
            change = float(np.max(np.abs(new - mu)))
            mu = 0.5 * mu + 0.5 * new
            if change < 1e-5 * friction:
                break
        tx, ty = -px, -py
        stick &= normal.contact
        fx, fy, mz = -fxr, -fyr, -mzr
        return TangentialSolution(self.name, x, y, tx, ty, sx, sy, stick, normal.contact,
                                  float(fx), float(fy), float(mz), velocity, (xi, eta, phi),
                                  friction,
                                  time.perf_counter() - t0,
                                  {"friction_iterations": iters,
                                   "creep_coefficients": (c11, c22), "L3": L3},
                                  power=float(pw) * velocity)


class StripTheoryRows(NamedTuple):
    """Inputs of :func:`contact_fastrip_rows` (CONTACT's "Modified FaStrip", M = 5):
    ``x`` (mx,), ``y`` (my,) the element centres [m] of the grid in the march's frame
    (rolling towards +x), ``dx`` the element length [m], ``pressure`` (mx, my) [Pa]
    and ``contact`` (mx, my) the elements in contact, ``mu`` the friction coefficient,
    ``pmax`` [Pa] and ``a`` [m] of the equivalent ellipse, ``creep`` the strip
    theory's non-dimensional creepages (xi', eta', phi') (:func:`contact_strip_creepages`)
    and ``nu`` Poisson's ratio."""
    x: np.ndarray
    y: np.ndarray
    dx: float
    pressure: np.ndarray
    contact: np.ndarray
    mu: float
    pmax: float
    a: float
    creep: np.ndarray
    nu: float


def contact_strip_creepages(a, b, G, nu, mu, fn, creepage):
    """Non-dimensional creepages of CONTACT's Modified FaStrip (M = 5) on the
    equivalent ellipse (a, b) [m]: with p_max = 3 F_n / (2 pi a b) and Kalker's
    C11, C22, C23 of a/b,

        xi'  = -G 4 (1 - nu) C11 xi  / (2 pi^2 mu p_max),
        eta' = -G 4 (1 - nu) C22 eta / (2 pi^2 mu p_max),
        phi' = -G 3 sqrt(a b) C23 phi / (2 pi mu p_max),

    (Kalker's strip theory in the notation of Sichani, Enblom & Berg 2016, as
    CONTACT's Modified FaStrip scales them; ``creepage`` = (xi, eta, phi [1/m])).
    Returns (array of the three, p_max [Pa])."""
    xi, eta, phi = (float(v) for v in creepage)
    pmax = 1.5 * fn / (math.pi * a * b)
    c11, c22, c23 = kalker_coefficients(a / b, nu)
    den = 2.0 * mu * pmax
    cr = np.array([-G * 4 * (1 - nu) * c11 * xi / (den * math.pi ** 2),
                   -G * 4 * (1 - nu) * c22 * eta / (den * math.pi ** 2),
                   -G * 3 * math.sqrt(a * b) * c23 * phi / (den * math.pi)])
    return cr, pmax


@njit(cache=True, nogil=True)
def contact_fastrip_rows(rows, px, py, stick):
    """CONTACT's Modified FaStrip (M = 5; Vollebregt 2025, after Sichani, Enblom &
    Berg 2016) on top of a modified-FASTSIM march on CONTACT's grid: in every row
    (fixed y_j) of the grid ``rows`` (:class:`StripTheoryRows`) the strip theory's
    adhesion zone [-a_j + 2 d_j, a_j] replaces FASTSIM's tractions (``px``, ``py``
    [Pa], on body 1, filled by the march) and marks the elements adhesion
    (``stick``); the elements of the row behind it slip, FASTSIM's traction scaled to
    the bound mu p.  a_j is half the row's contact length (whole elements), d_j
    the length of the slip zone,

        d_j = (sqrt(eta'^2 + (1 - phi'^2) (xi' - phi' y_j/a)^2) + eta' phi')
              / (1 - phi'^2) a / (1 - nu)

    (full slip where it is negative or undefined, or phi' = 1), the strip traction

        q = mu p_max [(kappa, lambda) sqrt(a_j^2 - x^2)/a
                      - (kappa, lambda - phi') sqrt((a_j - d_j)^2 - (x - d_j)^2)/a],

    (kappa, lambda) the unit vector of (xi' - phi' y_j/a, eta' + phi' d_j/a).  A row
    whose strip traction would exceed mu p_max anywhere in its adhesion zone keeps
    FASTSIM's solution (CONTACT's check of the traction bound).  Rows are
    independent; nothing is returned."""
    x, y, dx, pn, contact = rows.x, rows.y, rows.dx, rows.pressure, rows.contact
    mu, pmax, a, nu = rows.mu, rows.pmax, rows.a, rows.nu
    xi_p, eta_p, phi_p = rows.creep[0], rows.creep[1], rows.creep[2]
    mx, my = pn.shape
    for j in range(my):
        xsta = 1e300
        xend = -1e300
        for i in range(mx):
            if contact[i, j]:
                xsta = min(xsta, x[i] - 0.5 * dx)
                xend = max(xend, x[i] + 0.5 * dx)
        aj = max(1e-13, 0.5 * (xend - xsta))
        full = aj + 1e-3                    # a slip zone longer than the strip
        sx_j = xi_p - phi_p * y[j] / a
        if abs(phi_p - 1.0) <= 1e-6:
            d = full
        else:
            disc = eta_p * eta_p + (1.0 - phi_p * phi_p) * sx_j * sx_j
            if disc >= 0.0:
                d = (math.sqrt(disc) + eta_p * phi_p) / (1.0 - phi_p * phi_p) * a / (1.0 - nu)
                if d < 0.0:
                    d = full
            else:
                d = full
        sy_j = eta_p + phi_p * d / a
        nrm = math.sqrt(max(1e-20, sx_j * sx_j + sy_j * sy_j))
        kappa = sx_j / nrm
        lam = sy_j / nrm
        lam_p = lam - phi_p
        xint = -aj + 2.0 * d
        ftmax = 0.0
        for i in range(mx):
            if contact[i, j] and x[i] > xint:
                sc = math.sqrt(max(0.0, aj * aj - x[i] * x[i])) / a
                sa = math.sqrt(max(0.0, (aj - d) ** 2 - (x[i] - d) ** 2)) / a
                fx = kappa * (sc - sa)
                fy = lam * sc - lam_p * sa
                ftmax = max(ftmax, fx * fx + fy * fy)
        if ftmax > 1.0:
            continue
        for i in range(mx):
            if not contact[i, j]:
                continue
            if x[i] > xint:
                sc = math.sqrt(max(0.0, aj * aj - x[i] * x[i])) / a
                sa = math.sqrt(max(0.0, (aj - d) ** 2 - (x[i] - d) ** 2)) / a
                px[i, j] = mu * pmax * kappa * (sc - sa)
                py[i, j] = mu * pmax * (lam * sc - lam_p * sa)
                stick[i, j] = True
            else:
                pt = max(1e-10, math.sqrt(px[i, j] ** 2 + py[i, j] ** 2))
                g = mu * pn[i, j]
                px[i, j] *= g / pt
                py[i, j] *= g / pt
                stick[i, j] = False
