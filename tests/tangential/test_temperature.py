"""Flash temperatures (railcontact.tangential.temperature) against Jaeger's moving
heat source."""

import math

import numpy as np
import pytest

from railcontact.core.errors import InputError
from railcontact.tangential.temperature import ThermalProperties, flash_temperatures

STEEL = dict(heat_capacity=450.0, conductivity=50.0, density=7850.0)


def test_uniform_band_source():
    """A uniform flux q over a band of length L, equal bodies at the same bulk
    temperature: each takes q/2, and the surface temperature rises as Jaeger's
    (Carslaw & Jaeger 1959, sec. 2.9) T0 + (q/2) 2 sqrt(x - x_in) / sqrt(pi lambda rho c V)
    along the band; behind it both bodies cool alike.  Exact at the element
    centres: the exact element integrals of a constant flux telescope."""
    V, L, m, q = 30.0, 0.01, 200, 2e8
    dx = L / m * 2
    contact = np.zeros((m, 1), bool)
    contact[: m // 2] = True
    flux = np.where(contact, q, 0.0)
    b = ThermalProperties(20.0, **STEEL)
    t1, t2, q1 = flash_temperatures(flux, contact, dx, V, b, b)
    assert np.allclose(q1[contact], q / 2, rtol=1e-10)
    assert np.allclose(t1, t2)
    x = (np.arange(m) + 0.5) * dx
    k = b.jaeger_factor(V)
    jaeger = 20.0 + k * (q / 2) * 2 * np.sqrt(x[: m // 2])
    assert t1[: m // 2, 0] == pytest.approx(jaeger, rel=1e-9)
    # behind the band: the band's integral, 2 (sqrt(x) - sqrt(x - L))
    behind = 20.0 + k * (q / 2) * 2 * (np.sqrt(x[m // 2:]) - np.sqrt(x[m // 2:] - L))
    assert t1[m // 2:, 0] == pytest.approx(behind, rel=1e-9)


def test_hertzian_sliding_and_different_bulk_temperatures():
    """Full sliding on a Hertzian strip (q = mu p V_s): the largest rise is Jaeger's
    0.5 K mu V_s p0 sqrt(a) max_u int_-1^u sqrt(1 - t^2)/sqrt(u - t) dt, the integral
    2.1883 (Ertz & Knothe's case: a = 5.88 mm, p0 = 770.6 MPa, V = 30 m/s, 1 m/s
    sliding: 150.3 C).  Without heat and with bulk temperatures 150 and 0 C the
    contact is at 75 C in both bodies, the hot one giving heat to the cold one.
    Measured on 0.2 mm elements: 150.31 C against 150.33 (-0.02 %)."""
    a, p0, mu, V, vs = 5.88e-3, 770.6e6, 0.3, 30.0, 1.0
    dx = 0.2e-3
    x = np.arange(-a - 5 * dx, a + 40 * dx, dx) + dx / 2
    p = p0 * np.sqrt(np.clip(1 - (x / a) ** 2, 0, None))
    contact = (p > 0)[:, None]
    b = ThermalProperties(0.0, **STEEL)
    t1, t2, _ = flash_temperatures((mu * p * vs)[:, None], contact, dx, V, b, b)
    closed = 0.5 * b.jaeger_factor(V) * mu * vs * p0 * math.sqrt(a) * 2.1883
    assert closed == pytest.approx(150.3, abs=0.1)
    assert t1.max() == pytest.approx(closed, rel=0.01)
    hot = ThermalProperties(150.0, **STEEL)
    t1, t2, q1 = flash_temperatures(np.zeros_like(contact, float), contact, dx, V, hot, b)
    assert t1[contact] == pytest.approx(75.0, abs=1e-9)
    assert t2[contact] == pytest.approx(75.0, abs=1e-9)
    assert np.all(q1[contact] < 0)                     # out of the hot body
    assert t1[0, 0] == 150.0 and t2[0, 0] == 0.0       # ahead of the contact


def test_contact_scheme_and_the_dense_solve():
    """CONTACT's scheme counts the own element twice as strongly: on a uniform band
    its rise exceeds Jaeger's by exactly (q/2) 2 sqrt(dx/2) k at every element
    in the band.  The compiled forward substitution equals a dense solve of the
    equal-temperature conditions, also for unequal bodies and a gap in the strip
    (to 1e-9)."""
    from railcontact.tangential.temperature import _abel_matrix
    V, m, q, dx = 30.0, 60, 2e8, 1e-4
    contact = np.zeros((m, 2), bool)
    contact[5:40, 0] = True
    contact[5:20, 1] = contact[25:45, 1] = True
    flux = np.where(contact, q, 0.0)
    b = ThermalProperties(20.0, **STEEL)
    tj, _, _ = flash_temperatures(flux, contact, dx, V, b, b)
    tc, _, _ = flash_temperatures(flux, contact, dx, V, b, b, scheme="contact")
    extra = b.jaeger_factor(V) * (q / 2) * 2 * math.sqrt(dx / 2)
    assert (tc - tj)[contact] == pytest.approx(extra, rel=1e-9)
    assert np.allclose(tc[~contact], tj[~contact])
    hot = ThermalProperties(150.0, heat_capacity=500.0, conductivity=30.0, density=7000.0)
    for scheme in ("jaeger", "contact"):
        t1, t2, q1 = flash_temperatures(flux * np.linspace(0.5, 1.5, m)[:, None], contact,
                                        dx, V, hot, b, scheme=scheme)
        assert np.allclose(t1[contact], t2[contact], rtol=0, atol=1e-9)
        A = _abel_matrix(m, dx, scheme)
        k1, k2 = hot.jaeger_factor(V), b.jaeger_factor(V)
        for j in range(2):
            idx = np.flatnonzero(contact[:, j])
            sub = A[np.ix_(idx, idx)]
            qq = (flux * np.linspace(0.5, 1.5, m)[:, None])[idx, j]
            dense = np.linalg.solve((k1 + k2) * sub, -130.0 + k2 * (sub @ qq))
            assert q1[idx, j] == pytest.approx(dense, rel=1e-9)


def test_inputs():
    with pytest.raises(InputError, match="conductivity"):
        ThermalProperties(0.0, 450.0, -1.0, 7850.0)
    b = ThermalProperties(0.0, **STEEL)
    with pytest.raises(InputError, match="equal 2-D grids"):
        flash_temperatures(np.zeros((3, 2)), np.zeros((3, 3), bool), 1e-4, 1.0, b, b)
    with pytest.raises(InputError, match="scheme"):
        flash_temperatures(np.zeros((3, 2)), np.zeros((3, 2), bool), 1e-4, 1.0, b, b,
                           scheme="upwind")


def test_patch_temperatures_of_a_tangential_solution():
    """patch_temperatures reads the flux |p_t| |s| V off a TangentialSolution and
    runs the material from the leading edge (+x) backwards: a uniform flux band
    gives Jaeger's rise from the band's +x end (to 1e-9); no grid along x: None."""
    from railcontact.tangential.base import TangentialSolution
    from railcontact.tangential.temperature import STEEL, patch_temperatures
    m, dx, V = 80, 1e-4, 30.0
    x = (np.arange(m) - m / 2 + 0.5) * dx
    contact = np.zeros((m, 1), bool)
    contact[40:70] = True
    tx = np.where(contact, 3e8, 0.0)
    sx = np.where(contact, 0.02, 0.0)
    z = np.zeros((m, 1))
    sol = TangentialSolution("test", x, np.zeros(1), tx, z, sx, z, ~contact, contact,
                             0.0, 0.0, 0.0, V)
    t_rail, t_wheel = patch_temperatures(sol)
    q = 3e8 * 0.02 * V
    dist = (69 - np.arange(40, 70) + 0.5) * dx            # from the band's +x end
    jaeger = 20.0 + STEEL.jaeger_factor(V) * (q / 2) * 2 * np.sqrt(dist)
    assert t_rail[40:70, 0] == pytest.approx(jaeger, rel=1e-9)
    assert np.all(t_rail[70:, 0] == 20.0)                 # ahead of the patch
    one = TangentialSolution("test", x[:1], np.zeros(1), tx[:1], z[:1], sx[:1], z[:1],
                             ~contact[:1], contact[:1], 0.0, 0.0, 0.0, V)
    assert patch_temperatures(one) is None


def test_contact_scheme_converges_to_jaeger_as_sqrt_dx():
    """Ertz & Knothe's sliding strip (Jaeger's closed form 150.33 C): the exact
    element integral ("jaeger") is within 0.07 % from 0.4 mm elements on; CONTACT's
    own-element weight lies above by an excess that halves when dx falls by four
    (sqrt(dx)): measured +20.1, +9.87, +4.88 K at dx = 0.4, 0.1, 0.025 mm (+9.4 %
    at CONTACT's 0.2 mm)."""
    a, p0, mu, V, vs = 5.88e-3, 770.6e6, 0.3, 30.0, 1.0
    b = ThermalProperties(0.0, **STEEL)
    closed = 0.5 * b.jaeger_factor(V) * mu * vs * p0 * math.sqrt(a) * 2.1883
    excess = []
    for dx in (0.4e-3, 0.1e-3, 0.025e-3):
        x = np.arange(-a - 5 * dx, a + 40 * dx, dx) + dx / 2
        p = p0 * np.sqrt(np.clip(1 - (x / a) ** 2, 0, None))
        c = (p > 0)[:, None]
        tj = flash_temperatures((mu * p * vs)[:, None], c, dx, V, b, b)[0].max()
        tc = flash_temperatures((mu * p * vs)[:, None], c, dx, V, b, b, scheme="contact")[0].max()
        assert tj == pytest.approx(closed, rel=7e-4)
        excess.append(tc - closed)
    assert excess[0] / excess[1] == pytest.approx(2.0, rel=0.05)
    assert excess[1] / excess[2] == pytest.approx(2.0, rel=0.05)
