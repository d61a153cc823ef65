"""Polach's method and falling friction."""

import math

import numpy as np
import pytest

from railcontact.core.errors import InputError
from railcontact.geometry import ContactGeometry
from railcontact.core.materials import Material
from railcontact.normal import get_normal_model
from railcontact.tangential import get_tangential_model, kalker_coefficients

MAT = Material(2.1e11, 0.28)
G = MAT.shear_modulus


@pytest.fixture(scope="module")
def ns():
    return get_normal_model("hertz").solve(ContactGeometry(curvatures=(1 / 0.92, 1 / 0.6)), MAT,
                                           normal_force=1e5)


def test_linear_theory(ns):
    a, b = ns.semi_axes
    c = math.sqrt(a * b)
    C11, C22, C23 = kalker_coefficients(a / b, MAT.poisson_ratio)
    p = get_tangential_model("polach")
    e = 1e-7
    assert p.solve(ns, None, MAT, (e, 0, 0), 0.3).fx == pytest.approx(G * c * c * C11 * e, rel=1e-4)
    assert p.solve(ns, None, MAT, (0, e, 0), 0.3).fy == pytest.approx(G * c * c * C22 * e, rel=1e-4)
    # spin: same sign as the lateral creepage term (Kalker: G c^3 C23 phi)
    assert p.solve(ns, None, MAT, (0, 0, e / c), 0.3).fy == pytest.approx(G * c * c * C23 * e,
                                                                          rel=1e-4)


def test_saturation_and_direction(ns):
    t = get_tangential_model("polach").solve(ns, None, MAT, (0.3, -0.4, 0.0), 0.3)
    assert math.hypot(t.fx, t.fy) == pytest.approx(0.3e5, rel=1e-3)
    assert t.fy / t.fx == pytest.approx(-4 / 3, rel=1e-9)
    assert t.options["local_fields"] is False


def test_dry_preset_falling_shape(ns):
    p = get_tangential_model("polach", preset="dry")
    s = np.array([0.001, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2])
    f = np.array([p.solve(ns, None, MAT, (x, 0, 0), 0.3, velocity=20).fx for x in s])
    i = int(np.argmax(f))
    assert 0 < i < len(s) - 1                      # maximum, then decrease
    assert np.all(np.diff(f[:i + 1]) > 0) and np.all(np.diff(f[i:]) < 0)
    assert f[-1] < 0.8 * f[i]


def test_fastsim_falling_friction(ns):
    f = get_tangential_model("fastsim", falling={"A": 0.38, "B": 0.7})
    f0 = get_tangential_model("fastsim")
    s = [0.001, 0.01, 0.03, 0.1]
    fx = [f.solve(ns, None, MAT, (x, 0, 0), 0.36, velocity=10).fx for x in s]
    fx0 = [f0.solve(ns, None, MAT, (x, 0, 0), 0.36, velocity=10).fx for x in s]
    assert fx[0] == pytest.approx(fx0[0], rel=0.01)          # little slip: Coulomb
    assert fx[-1] < fx[1]                                    # falling branch
    # full slip at w = 1 m/s: mu = 0.36 (0.62 exp(-0.7) + 0.38)
    t = f.solve(ns, None, MAT, (0.1, 0, 0), 0.36, velocity=10)
    assert t.fx / 1e5 < 0.36 * (0.62 * math.exp(-0.7) + 0.38) * 1.01


def test_bad_options():
    with pytest.raises(InputError):
        get_tangential_model("polach", kA=0.5, kS=0.8)
    with pytest.raises(InputError):
        get_tangential_model("polach", preset="icy")
    with pytest.raises(InputError):
        get_tangential_model("fastsim", falling={"A": 2.0, "B": 0.1})
