"""Viscoelastic steady rolling (the standard linear solid, CONTACT's M = 1): the
hereditary influence coefficients against the elastic ones in their limits and
against direct quadrature, the active-set normal solver against Polonsky-Keer on a
symmetric problem, and the 2-D rolling cylinder against its closed forms: Hertz
with the final (rubbery) modulus G_r = G_g / (1 + f) for tau_c -> 0 and with the
initial (glassy) modulus for tau_c -> inf, and, for a short relaxation length
L = V tau_c << a, the pressure shifted towards the leading edge by
eps = f L / (1 + f) (the first-order term of the memory integral, u ~ (1 + f) u_g
+ f L du_g/dx, the small-relaxation limit of Hunter's (1961) cylinder): a rolling
resistance F_r / F_n = eps / R."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from railcontact.core.errors import InputError
from railcontact.normal.influence import _F, normal_kernel, normal_operator, tangential_kernels
from railcontact.normal.polonsky_keer import polonsky_keer
from railcontact.normal.viscoelastic import (Viscoelastic, ViscoelasticBody, active_set_normal,
                                             viscoelastic_normal_kernel,
                                             viscoelastic_normal_operator,
                                             viscoelastic_tangential_kernels)

G, NU = 1143e6, 0.4             # PA6 (CONTACT's visc_cylindr.inp): G_g, nu


def _pair(f, tc, velocity=1.0):
    b = ViscoelasticBody(G, NU, f, tc)
    return Viscoelastic(b, b, velocity)


def test_elastic_when_no_creep():
    """f = 0 or tau_c = 0: the elastic kernels (with G_g, or G_r = G_g / (1 + f)), to
    rounding (1e-9: the corner sums cancel digits)."""
    E = normal_kernel(30, 20, 1e-4, 2e-4, G / (1 - NU))
    assert np.allclose(viscoelastic_normal_kernel(30, 20, 1e-4, 2e-4, _pair(0.0, 0.3)), E,
                       rtol=1e-9, atol=0)
    assert np.allclose(viscoelastic_normal_kernel(30, 20, 1e-4, 2e-4, _pair(1.5, 0.0)),
                       2.5 * E, rtol=1e-9, atol=0)
    el = tangential_kernels(12, 10, 1e-4, 1e-4, G, NU, extra_rows=1)
    vi = viscoelastic_tangential_kernels(12, 10, 1e-4, 1e-4, _pair(0.0, 0.3), extra_rows=1)
    for a, b in zip(vi, el):
        assert np.allclose(a, b, rtol=1e-9, atol=1e-9 * np.abs(b).max())


def test_limits_of_the_relaxation_length():
    """L << dx: (1 + f) A within O(L / dx); L >> the grid: A plus a constant (a rigid
    approach), the variation of the difference below 1e-4 of A's peak."""
    E = normal_kernel(40, 1, 1.6e-4, 1.0, G / (1 - NU))
    short = viscoelastic_normal_kernel(40, 1, 1.6e-4, 1.0, _pair(1.0, 1.6e-10))   # L/dx 1e-6
    assert np.max(np.abs(short - 2 * E)) < 1e-5 * E.max()
    long = viscoelastic_normal_kernel(40, 1, 1.6e-4, 1.0, _pair(1.0, 1e4))
    d = long - E
    assert np.ptp(d) < 1e-4 * E.max() and d.min() > 0


def _element(x, y, dx, dy):
    """The elastic normal element coefficient of the pair at any offset [m/Pa]."""
    hx, hy = dx / 2, dy / 2
    return (1 - NU) / (math.pi * G) * (_F(x + hx, y + hy) - _F(x - hx, y + hy)
                                       - _F(x + hx, y - hy) + _F(x - hx, y - hy))


def test_kernel_against_direct_quadrature():
    """C(X) = A(X) + f int_0^inf exp(-s/L)/L A(X + s) ds at a few offsets, the
    integral by adaptive quadrature (breakpoints at the element edges): within 1e-6."""
    dx, dy, f, L = 1e-4, 1.5e-4, 1.0, 3e-4
    K = viscoelastic_normal_kernel(8, 5, dx, dy, _pair(f, L))
    for di, dj in [(0, 0), (-3, 0), (2, 1), (-7, 4), (5, -2)]:
        X, Y = di * dx, dj * dy
        pts = [p for p in (-dx / 2 - X, dx / 2 - X) if p > 0]
        g = lambda s: math.exp(-s / L) / L * float(_element(np.array(X + s), np.array(Y),  # noqa
                                                            dx, dy))
        mem = quad(g, 0, 60 * L, points=pts or None, limit=400, epsabs=0, epsrel=1e-11)[0]
        ref = float(_element(np.array(X), np.array(Y), dx, dy)) + f * mem
        assert K[7 + di, 4 + dj] == pytest.approx(ref, rel=1e-6)
    # not symmetric: the material behind a load (-x) passed it earlier and keeps
    # creeping, the displacement lags behind the load
    assert K[7 - 2, 4] > K[7 + 2, 4]


def test_active_set_equals_conjugate_gradients_when_symmetric():
    x = (np.arange(41) - 20) * 1e-4
    y = (np.arange(31) - 15) * 1e-4
    h = x[:, None] ** 2 / 0.2 + y[None, :] ** 2 / 0.6
    op = normal_operator(41, 31, 1e-4, 1e-4, 1.1e11)
    dA = 1e-8
    p1, d1, _, ok1 = polonsky_keer(op, h, dA, force=1e3, tol=1e-12, maxiter=5000)
    p2, d2, _, ok2 = active_set_normal(op, h, dA, 1e3, None)
    assert ok1 and ok2
    assert np.max(np.abs(p2 - p1)) < 1e-6 * p1.max() and d2 == pytest.approx(d1, rel=1e-7)
    p3, _, _, ok3 = active_set_normal(op, h - d1, dA, None, p1)     # approach given
    assert ok3 and np.max(np.abs(p3 - p1)) < 1e-6 * p1.max()


R, FN = 0.05, 6e5                # 2-D cylinder: R [m], F_n per length [N/m]


def _cylinder(f, tc, n=200, extent=2.6):
    """The 2-D cylinder (one strip 10 m long) rolling at 1 m/s: x, p, approach."""
    a_r = math.sqrt(4 * R * FN * (1 - NU) * (1 + f) / (math.pi * G))
    dx, dy = extent * a_r / n, 10.0
    x = (np.arange(n) - (n - 1) / 2) * dx
    op = viscoelastic_normal_operator(n, 1, dx, dy, _pair(f, tc))
    p, delta, _, ok = active_set_normal(op, (x ** 2 / (2 * R))[:, None], dx * dy, FN * dy)
    assert ok
    return x, p[:, 0], a_r


@pytest.mark.parametrize("tc, modulus", [(1e-9, G / 2), (1e5, G)])
def test_cylinder_limits_are_hertz(tc, modulus):
    """tau_c -> 0: Hertz with G_r = G_g / 2 (f = 1); tau_c -> inf: Hertz with G_g:
    p_0 = sqrt(F G / (pi R (1 - nu))), a = sqrt(4 R F (1 - nu) / (pi G)) (CONTACT's
    user guide, 2-D Hertz): p_max within 0.1 %, the contact width within one element."""
    x, p, _ = _cylinder(1.0, tc, n=160, extent=2.0 * math.sqrt(G / modulus / 2) * 1.3)
    p0 = math.sqrt(FN * modulus / (math.pi * R * (1 - NU)))
    a = math.sqrt(4 * R * FN * (1 - NU) / (math.pi * modulus))
    dx = x[1] - x[0]
    assert p.max() == pytest.approx(p0, rel=1e-3)
    assert abs(np.count_nonzero(p > 0) * dx - 2 * a) <= dx
    assert abs((x * p).sum() / p.sum()) < 1e-3 * dx          # no shift


def test_short_relaxation_shifts_the_pressure_forward():
    """L = 0.002 a: the pressure's centre eps = f L / (1 + f) ahead (towards +x, the
    leading edge), i.e. the rolling resistance F_r / F_n = eps / R; measured 0.996 eps
    on 400 elements (1 %), the peak that of Hertz with G_r (0.1 %)."""
    f = 1.0
    a_r = math.sqrt(4 * R * FN * (1 - NU) * (1 + f) / (math.pi * G))
    L = 0.002 * a_r
    x, p, _ = _cylinder(f, L, n=400)
    eps = f * L / (1 + f)
    assert (x * p).sum() / p.sum() == pytest.approx(eps, rel=0.01)
    assert p.max() == pytest.approx(math.sqrt(FN * G / 2 / (math.pi * R * (1 - NU))), rel=1e-3)


def test_intermediate_relaxation_is_stiffer_and_asymmetric():
    """A relaxation length of the order of the contact: p_max and the width between
    those of the two Hertz limits, the pressure's centre ahead of the middle."""
    x, p, a_r = _cylinder(1.0, 0.2 * math.sqrt(4 * R * FN * 0.6 * 2 / (math.pi * G)))
    p_r = math.sqrt(FN * G / 2 / (math.pi * R * (1 - NU)))
    p_g = math.sqrt(FN * G / (math.pi * R * (1 - NU)))
    assert p_r < p.max() < p_g
    assert (x * p).sum() / p.sum() > 0.01 * a_r


def test_inputs_checked():
    with pytest.raises(InputError, match="spring_ratio"):
        ViscoelasticBody(G, NU, -1.0, 0.1)
    with pytest.raises(InputError, match="relaxation_time"):
        ViscoelasticBody(G, NU, 1.0, -0.1)
    with pytest.raises(InputError, match="velocity"):
        _pair(1.0, 0.1, velocity=0.0)


def test_iterative_equations_match_dense(monkeypatch):
    """Beyond DENSE_LIMIT loaded elements the equations on the active set are solved
    by GMRES with FFT products: the same pressure (1e-8 of p_max) and approach."""
    import railcontact.normal.viscoelastic as ve

    x = (np.arange(36) - 17.5) * 1e-4
    y = (np.arange(30) - 14.5) * 1e-4
    h = x[:, None] ** 2 / 0.2 + y[None, :] ** 2 / 0.3
    op = viscoelastic_normal_operator(36, 30, 1e-4, 1e-4, _pair(1.0, 5e-4))
    p1, d1, _, ok1 = active_set_normal(op, h, 1e-8, 2e3)
    monkeypatch.setattr(ve, "DENSE_LIMIT", 50)
    p2, d2, _, ok2 = active_set_normal(op, h, 1e-8, 2e3)
    assert ok1 and ok2 and np.count_nonzero(p1 > 0) > 200
    assert np.max(np.abs(p2 - p1)) < 1e-8 * p1.max() and d2 == pytest.approx(d1, rel=1e-9)
