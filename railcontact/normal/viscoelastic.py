"""Influence coefficients of viscoelastic bodies in steady rolling (CONTACT's M = 1).

Material: the standard linear solid (SLS) per body, given as CONTACT gives it (user
guide, "Viscoelastic materials"): the initial ("glassy") shear modulus G_g, Poisson's
ratio nu (constant in time), the spring ratio f_g = (E_g - E_r)/E_r (so that the final
modulus is G_r = G_g / (1 + f_g)) and the creep relaxation time tau_c of the creep
compliance

    C(t) = C_g [1 + f_g (1 - exp(-t / tau_c))].

Steady rolling towards +x at speed V: a material point at x passed the points x + s
(s >= 0) a time s / V earlier.  With nu constant the correspondence principle turns
every elastic displacement u_g (of the glassy modulus) into the hereditary integral
(Kalker 1990, appendix D; Wang & Knothe 1993)

    u(x) = u_g(x) + f_g / L * int_0^inf exp(-s / L) u_g(x + s) ds,   L = V tau_c,

the relaxation length L of the body.  The discrete influence coefficient of a
uniform load on an element at the offset X (observation minus source) is then

    C(X) = A(X) + f_g int_0^inf exp(-s / L) / L A(X + s) ds,

A the elastic element coefficient at any offset (closed form, Love 1929 /
Cerruti).  The matrix is still a convolution (block Toeplitz) but no longer
symmetric: it depends on the rolling direction.  Limits: L -> 0 (tau_c -> 0) gives
(1 + f_g) A, elastic with the final modulus G_r; L -> inf gives A plus a constant
(a rigid approach), elastic with G_g.

Evaluation: on the grid's offsets X = di dx the integral is split into element
lengths, ``C_f(di) = B(di) + q C_f(di + 1)``, q = exp(-dx / L), with
``B(m) = int_0^dx exp(-s/L)/L A(m dx + s) ds`` by Gauss-Legendre in
u = exp(-s/L) (exact weights for the exponential, the element edge at s = dx/2 a
panel boundary), and the part beyond the last row of offsets by composite
Gauss-Legendre on geometric panels (the kernel smooth there); the recursion runs
as a linear filter (:func:`scipy.signal.lfilter`).  Computed once per grid and
material (cached).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.signal import lfilter

from ..core.errors import InputError
from ..core.materials import Material
from .influence import Convolution, _log_sum

log = logging.getLogger(__name__)

#: Gauss-Legendre points per panel of the element integrals B(m) (two panels)
ELEMENT_POINTS = 16
#: Gauss-Legendre points per geometric panel of the tail beyond the grid
TAIL_POINTS = 12
#: the tail is integrated out to this many relaxation lengths
TAIL_LENGTHS = 60.0


@dataclass(frozen=True)
class ViscoelasticBody:
    """One body's standard linear solid (CONTACT's GG, POISS, FG, TC).

    Parameters
    ----------
    shear_modulus : float     initial (glassy) shear modulus G_g [Pa]
    poisson_ratio : float     nu [-], constant in time
    spring_ratio : float      f_g = C_v / C_g = (E_g - E_r) / E_r >= 0 [-]
    relaxation_time : float   creep relaxation time tau_c >= 0 [s]
    """

    shear_modulus: float
    poisson_ratio: float
    spring_ratio: float = 0.0
    relaxation_time: float = 0.0

    def __post_init__(self):
        G, nu, f, tc = (self.shear_modulus, self.poisson_ratio, self.spring_ratio,
                        self.relaxation_time)
        if not (isinstance(G, (int, float)) and math.isfinite(G) and G > 0):
            raise InputError(f"viscoelastic shear_modulus = {G!r} Pa: expected a value > 0")
        if not (isinstance(nu, (int, float)) and 0.0 <= nu < 0.5):
            raise InputError(f"viscoelastic poisson_ratio = {nu!r}: expected a value in [0, 0.5)")
        if not (isinstance(f, (int, float)) and math.isfinite(f) and f >= 0):
            raise InputError(f"viscoelastic spring_ratio (FG) = {f!r}: expected a value >= 0")
        if not (isinstance(tc, (int, float)) and math.isfinite(tc) and tc >= 0):
            raise InputError(f"viscoelastic relaxation_time (TC) = {tc!r} s: expected a "
                             "time >= 0")

    @property
    def final_shear_modulus(self) -> float:
        """G_r = G_g / (1 + f_g) [Pa], the modulus of very slow loading."""
        return self.shear_modulus / (1.0 + self.spring_ratio)


@dataclass(frozen=True)
class Viscoelastic:
    """The viscoelastic pair in steady rolling towards +x at ``velocity`` [m/s]
    (body 1 the rail, body 2 the wheel); hashable, so that kernels are cached."""

    body1: ViscoelasticBody
    body2: ViscoelasticBody
    velocity: float

    def __post_init__(self):
        v = self.velocity
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise InputError(f"viscoelastic rolling velocity = {v!r} m/s: expected a speed > 0 "
                             "(the relaxation length is velocity x relaxation time)")

    @property
    def bodies(self):
        return self.body1, self.body2

    @property
    def shear_modulus(self) -> float:
        """Combined initial shear modulus, 1/G = (1/G1 + 1/G2)/2 [Pa]."""
        return 2.0 / sum(1.0 / b.shear_modulus for b in self.bodies)

    @property
    def nu(self) -> float:
        """Combined Poisson's ratio, nu = G (nu1/G1 + nu2/G2)/2."""
        return 0.5 * self.shear_modulus * sum(b.poisson_ratio / b.shear_modulus
                                              for b in self.bodies)

    @property
    def contact_modulus(self) -> float:
        """Combined initial contact modulus E*, 1/E* = sum (1 - nu_a)/(2 G_a) [Pa]."""
        return 1.0 / sum((1 - b.poisson_ratio) / (2 * b.shear_modulus) for b in self.bodies)

    def relaxation_length(self, body) -> float:
        """L = V tau_c [m] of a body."""
        return self.velocity * body.relaxation_time


# ---------------------------------------------------------------- element integrals
def _corner_sum(F, X, Y, hx, hy):
    return F(X + hx, Y + hy) - F(X - hx, Y + hy) - F(X + hx, Y - hy) + F(X - hx, Y - hy)


def _Lx(x, y):
    """x ln(y + r): antiderivative of y^2 / r^3 over a rectangle."""
    r = np.hypot(x, y)
    return np.where(x != 0, x * _log_sum(y, x, r), 0.0)


def _Ly(x, y):
    return _Lx(y, x)


def _R(x, y):
    return -np.hypot(x, y)


def _element_kernels(X, Y, dx, dy, body, normal):
    """The elastic element coefficients of one body [m/Pa] at offsets (X, Y) [m]
    (any, not only the grid's): the normal one, or the tangential (xx, xy, yy).
    One body's share: the two-body kernels of
    :mod:`railcontact.normal.influence` are the sum of both bodies' shares."""
    hx, hy = 0.5 * dx, 0.5 * dy
    G, nu = body.shear_modulus, body.poisson_ratio
    with np.errstate(divide="ignore", invalid="ignore"):
        lx = _corner_sum(_Lx, X, Y, hx, hy)
        ly = _corner_sum(_Ly, X, Y, hx, hy)
        if normal:
            # Boussinesq: (1 - nu) / (2 pi G) times the integral of 1/r
            return ((1 - nu) / (2 * np.pi * G) * (lx + ly),)
        rr = _corner_sum(_R, X, Y, hx, hy)
    c = 1.0 / (2 * np.pi * G)
    return (c * ((1 - nu) * (lx + ly) + nu * ly), c * nu * rr,
            c * ((1 - nu) * (lx + ly) + nu * lx))


def _gauss(n):
    t, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (t + 1.0), 0.5 * w                     # on [0, 1]


def _memory(di, dj, dx, dy, body, L, normal):
    """The hereditary part int_0^inf exp(-s/L)/L A(di dx + s, dj dy) ds of each
    kernel at the offsets di (ascending, consecutive) x dj: a list of arrays."""
    t, w = _gauss(ELEMENT_POINTS)
    q = math.exp(-dx / L)
    qh = math.exp(-0.5 * dx / L)
    wa, wb = -math.expm1(-0.5 * dx / L), qh * -math.expm1(-0.5 * dx / L)   # 1 - qh, qh - q
    # u = exp(-s/L) in [qh, 1] (s in [0, dx/2]) and [q, qh] (s in [dx/2, dx])
    u = np.concatenate([1.0 - wa * t, q + wb * t])
    wu = np.concatenate([wa * w, wb * w])
    s = -L * np.log(np.maximum(u, 1e-300))
    X = di[:, None, None] * dx + s[None, None, :] + 0.0 * dj[None, :, None]
    Y = np.broadcast_to((dj * dy)[None, :, None], X.shape)
    B = [np.einsum("ijk,k->ij", k, wu) for k in _element_kernels(X, Y, dx, dy, body, normal)]
    # the tail: s from (di_max + 1 - di) dx on, i.e. X from X0 = (di_max + 1) dx;
    # int_{X0}^inf exp(-(X - X0)/L)/L A(X) dX on geometric panels
    X0 = (di[-1] + 1) * dx
    s0 = min(dx, L) / 4.0
    edges = [0.0]
    e = s0
    while edges[-1] < TAIL_LENGTHS * L:
        edges.append(e)
        e *= 2.0
    edges = np.asarray(edges)
    tt, ww = _gauss(TAIL_POINTS)
    a, b = edges[:-1, None], edges[1:, None]
    sv = (a + (b - a) * tt[None, :]).ravel()
    wv = ((b - a) * ww[None, :]).ravel() * np.exp(-sv / L) / L
    Xt = np.broadcast_to(X0 + sv[None, :], (dj.size, sv.size))
    Yt = np.broadcast_to((dj * dy)[:, None], Xt.shape)
    T = [k @ wv for k in _element_kernels(Xt, Yt, dx, dy, body, normal)]
    out = []
    for Bk, Tk in zip(B, T):
        # C(di) = B(di) + q C(di + 1), C(di_max + 1) = T: a first-order filter run
        # from the last row backwards
        y, _ = lfilter([1.0], [1.0, -q], Bk[::-1], axis=0, zi=(q * Tk)[None, :])
        out.append(y[::-1])
    return out


def _viscoelastic(mx, my, dx, dy, visc, normal, extra_rows):
    di = np.arange(-(mx - 1), mx + extra_rows).astype(float)
    dj = np.arange(-(my - 1), my).astype(float)
    X, Y = di[:, None] * dx, dj[None, :] * dy
    total = None
    for body in visc.bodies:
        parts = list(_element_kernels(X, Y, dx, dy, body, normal))
        L = visc.relaxation_length(body)
        f = body.spring_ratio
        if f > 0 and L == 0.0:
            parts = [(1.0 + f) * k for k in parts]
        elif f > 0:
            parts = [k + f * m for k, m in zip(parts, _memory(di, dj, dx, dy, body, L,
                                                              normal))]
        total = parts if total is None else [a + b for a, b in zip(total, parts)]
    return tuple(np.ascontiguousarray(k) for k in total)


@lru_cache(maxsize=32)
def viscoelastic_normal_kernel(mx: int, my: int, dx: float, dy: float,
                               visc: Viscoelastic) -> np.ndarray:
    """Normal kernel C[di, dj] [m/Pa], offsets di in [-(mx-1), mx-1], dj in
    [-(my-1), my-1] (observation minus source), of the viscoelastic pair rolling
    towards +x; replaces :func:`railcontact.normal.influence.normal_kernel`."""
    return _viscoelastic(mx, my, float(dx), float(dy), visc, True, 0)[0]


@lru_cache(maxsize=32)
def viscoelastic_tangential_kernels(mx: int, my: int, dx: float, dy: float,
                                    visc: Viscoelastic, extra_rows: int = 0):
    """Tangential kernels (xx, xy, yy) [m/Pa] of the viscoelastic pair, offsets in x
    over [-(mx-1), mx-1+extra_rows]; replaces
    :func:`railcontact.normal.influence.tangential_kernels`."""
    if extra_rows not in (0, 1):
        raise ValueError(f"extra_rows = {extra_rows!r}: expected 0 or 1")
    return _viscoelastic(mx, my, float(dx), float(dy), visc, False, extra_rows)


@lru_cache(maxsize=32)
def viscoelastic_normal_operator(mx: int, my: int, dx: float, dy: float,
                                 visc: Viscoelastic) -> Convolution:
    """Cached convolution operator p -> C p of the viscoelastic pair (not symmetric)."""
    return Convolution(viscoelastic_normal_kernel(mx, my, dx, dy, visc), mx, my)


def _dense_block(kernel, idx, shape):
    """The influence matrix C[I, K] between the grid elements ``idx`` (flat indices
    into ``shape``) from the kernel (offsets centred at its middle)."""
    my = shape[1]
    ci, cj = (kernel.shape[0] - 1) // 2, (kernel.shape[1] - 1) // 2
    i, j = idx // my, idx % my
    return kernel[ci + i[:, None] - i[None, :], cj + j[:, None] - j[None, :]]


#: the active-set iteration solves its equations densely up to this many elements
#: (beyond, by GMRES with FFT products)
DENSE_LIMIT = 3000


def _closed_gap_dense(kernel, hf, idx, shape, dA, force):
    """p_S (and the approach, force given) closing the gap on the elements ``idx``:
    C_SS p_S - delta = -h_S with sum p_S dA = force (or delta = 0 with h less it)."""
    A = _dense_block(kernel, idx, shape)
    if force is None:
        return np.linalg.solve(A, -hf[idx]), 0.0
    n = idx.size
    M = np.zeros((n + 1, n + 1))
    M[:n, :n] = A
    M[:n, n] = -1.0
    M[n, :n] = dA
    sol = np.linalg.solve(M, np.concatenate([-hf[idx], [force]]))
    return sol[:n], float(sol[n])


def _closed_gap_iterative(op, hf, idx, shape, dA, force, start):
    """As :func:`_closed_gap_dense`, by GMRES on the same (bordered) system with the
    operator's FFT products (restricted to ``idx``); the force row scaled to the
    kernel's diagonal."""
    from scipy.sparse.linalg import LinearOperator, gmres

    n = idx.size
    full = np.zeros(int(np.prod(shape)))
    d0 = float(op.diag)
    k = 0 if force is None else 1
    w = d0 / dA / n                 # scales the force row to the others

    def matvec(v):
        full[:] = 0.0
        full[idx] = v[:n]
        u = op(full.reshape(shape)).ravel()[idx]
        if force is None:
            return u
        return np.concatenate([u - v[n], [w * dA * v[:n].sum()]])

    rhs = -hf[idx] if force is None else np.concatenate([-hf[idx], [w * force]])
    x0 = None
    if start is not None:
        x0 = np.concatenate([start, [0.0] * k]) if k else start
    M = LinearOperator((n + k, n + k), matvec=matvec, dtype=float)
    sol, info = gmres(M, rhs, x0=x0, rtol=1e-12, atol=0.0, restart=200, maxiter=50)
    if info != 0:
        log.info("viscoelastic active set: GMRES ended with info %d on %d elements", info, n)
    return (sol, 0.0) if force is None else (sol[:n], float(sol[n]))


def active_set_normal(op, h, dA, force=None, p0=None, maxiter=200):
    """The normal contact problem p >= 0, e = h + C p - delta >= 0, p e = 0 for an
    influence operator that need not be symmetric (viscoelastic rolling), by an
    active set: on the set S of loaded elements the gap is closed exactly
    (C_SS p_S = delta - h_S, with sum p_S dA = ``force`` where the force is given:
    delta the unknown approach; else ``h`` holds h - delta), then elements with
    p < 0 leave S and elements with an overlap (e < 0) join it, until S settles.

    Parameters
    ----------
    op : Convolution   the operator (its ``kernel``, offsets centred)
    h : ndarray        undeformed distance [m] (less the approach, force None)
    dA : float         element area [m^2]
    force : float      total force [N], or None (the approach given)
    p0 : ndarray       a start [Pa] (its loaded elements the first S)

    Returns p [Pa], approach [m] (force given; else 0), iterations, converged.
    The equations on S are solved densely up to ``DENSE_LIMIT`` elements, beyond by
    GMRES with the operator's FFT products."""
    h = np.asarray(h, dtype=float)
    shape = h.shape
    hf = h.ravel()
    S = (p0 > 0).ravel() if p0 is not None and np.any(p0 > 0) else hf <= np.min(hf) + \
        0.25 * (np.median(hf) - np.min(hf))
    p = np.zeros(hf.size)
    delta = 0.0
    seen = set()
    for it in range(1, maxiter + 1):
        idx = np.flatnonzero(S)
        if idx.size > DENSE_LIMIT:
            start = p[idx] if it > 1 else (None if p0 is None else np.ravel(p0)[idx])
            ps, delta = _closed_gap_iterative(op, hf, idx, shape, dA, force, start)
        else:
            ps, delta = _closed_gap_dense(op.kernel, hf, idx, shape, dA, force)
        p[:] = 0.0
        p[idx] = ps
        e = op(p.reshape(shape)).ravel() + hf - delta
        neg = S & (p < 0)
        over = ~S & (e < 0)
        if not neg.any() and not over.any():
            return p.reshape(shape), delta, it, True
        key = idx.tobytes()
        if key in seen:                     # a cycle: stop, flagged not converged
            break
        seen.add(key)
        S = (S & ~neg) | over
        if not S.any():
            return np.zeros(shape), delta, it, force is None
    return np.maximum(p, 0.0).reshape(shape), delta, it, False


@dataclass(frozen=True)
class ViscoelasticOption:
    """The viscoelastic option of the exact models (``viscoelastic=`` of
    :class:`~railcontact.normal.exact.ExactNormalModel` and
    :class:`~railcontact.tangential.exact.ExactTangentialModel`): the standard
    linear solid's creep beside the elastic ``Material``, whose moduli are the
    initial (glassy) ones.

    Parameters
    ----------
    spring_ratio : (float, float)      f_g of the rail and the wheel (CONTACT's FG)
    relaxation_time : (float, float)   tau_c [s] of the rail and the wheel (TC)
    velocity : float                   rolling speed V [m/s] (towards +x)
    """

    spring_ratio: tuple
    relaxation_time: tuple
    velocity: float = 1.0

    @classmethod
    def from_value(cls, value) -> "ViscoelasticOption | None":
        """From an option value: None, an instance, or a table with ``spring_ratio``,
        ``relaxation_time`` (a number for both bodies, or [rail, wheel]) and
        ``velocity`` [m/s]."""
        if value is None or isinstance(value, cls):
            return value
        if not isinstance(value, dict) or set(value) - {"spring_ratio", "relaxation_time",
                                                        "velocity"} \
                or not {"spring_ratio", "relaxation_time"} <= set(value):
            raise InputError(f"viscoelastic = {value!r}: expected a table with spring_ratio, "
                             "relaxation_time [s] (a number, or [rail, wheel]) and velocity "
                             "[m/s]")

        def pair(v, name):
            v = [v, v] if isinstance(v, (int, float)) and not isinstance(v, bool) else v
            if not (isinstance(v, (list, tuple)) and len(v) == 2
                    and all(isinstance(a, (int, float)) and not isinstance(a, bool)
                            for a in v)):
                raise InputError(f"viscoelastic.{name} = {v!r}: expected a number or two "
                                 "[rail, wheel]")
            return (float(v[0]), float(v[1]))

        return cls(pair(value["spring_ratio"], "spring_ratio"),
                   pair(value["relaxation_time"], "relaxation_time"),
                   float(value.get("velocity", 1.0)))

    def pair(self, material) -> Viscoelastic:
        """The viscoelastic pair of an elastic ``Material`` (its moduli the initial
        ones; quasi-identical bodies only: the kernels do not couple the normal and
        tangential problems)."""
        if material.is_dissimilar:
            raise InputError("viscoelastic materials with dissimilar elastic constants "
                             "(K != 0): expected quasi-identical bodies ((1 - 2 nu)/G equal)")
        bodies = [ViscoelasticBody(E / (2.0 * (1.0 + nu)), nu, f, t)
                  for (E, nu), f, t in zip(material.bodies, self.spring_ratio,
                                           self.relaxation_time)]
        return Viscoelastic(bodies[0], bodies[1], self.velocity)


def final_material(visc: Viscoelastic):
    """The elastic ``Material`` of the pair's final (relaxed) moduli G_r = G_g / (1 + f)
    (the softest response: the largest contact, the potential area's estimate)."""
    (b1, b2) = visc.bodies
    E1 = 2.0 * b1.final_shear_modulus * (1.0 + b1.poisson_ratio)
    E2 = 2.0 * b2.final_shear_modulus * (1.0 + b2.poisson_ratio)
    return Material(E1, b1.poisson_ratio, E2, b2.poisson_ratio)
