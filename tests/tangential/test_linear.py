"""Kalker's linear theory (railcontact.tangential.linear) against Kalker's table."""

import math

import pytest

from railcontact.core.errors import InputError
from railcontact.geometry import ContactGeometry
from railcontact.core.materials import Material
from railcontact.normal import get_normal_model
from railcontact.tangential import get_tangential_model

MAT = Material(2.1e11, 0.25)
G = MAT.shear_modulus


@pytest.fixture(scope="module")
def circle():
    """A circular Hertz patch (equal curvatures): a/b = 1."""
    return get_normal_model("hertz").solve(ContactGeometry(curvatures=(1 / 0.5, 1 / 0.5)), MAT,
                                           normal_force=1e5)


def test_circle_forces_with_kalkers_table_values(circle):
    # Kalker's table, a/b = 1, nu = 0.25: C11 = 4.12, C22 = 3.67, C23 = 1.47
    a, b = circle.semi_axes
    assert a == pytest.approx(b, rel=1e-9)
    c = math.sqrt(a * b)
    lin = get_tangential_model("linear")
    t = lin.solve(circle, None, MAT, (1e-3, 0.0, 0.0), 0.3)
    assert t.fx == pytest.approx(G * c * c * 4.12 * 1e-3, rel=1e-3)
    assert t.fy == 0.0
    t = lin.solve(circle, None, MAT, (0.0, -2e-3, 0.0), 0.3)
    assert t.fy == pytest.approx(-G * c * c * 3.67 * 2e-3, rel=1e-3)
    t = lin.solve(circle, None, MAT, (0.0, 0.0, 0.5), 0.3)
    assert t.fy == pytest.approx(G * c ** 3 * 1.47 * 0.5, rel=1e-3)
    assert t.fx == 0.0


def test_linear_is_unbounded_and_superposes(circle):
    lin = get_tangential_model("linear")
    big = lin.solve(circle, None, MAT, (0.05, 0.0, 0.0), 0.3)
    assert big.fx > 5 * 0.3 * 1e5                 # no Coulomb bound
    both = lin.solve(circle, None, MAT, (0.0, 1e-3, 0.2), 0.3)
    eta = lin.solve(circle, None, MAT, (0.0, 1e-3, 0.0), 0.3)
    phi = lin.solve(circle, None, MAT, (0.0, 0.0, 0.2), 0.3)
    assert both.fy == pytest.approx(eta.fy + phi.fy, rel=1e-12)
    assert big.options["local_fields"] is False
    assert not big.traction_x.any() and not big.slip_x.any()


def test_bad_friction(circle):
    with pytest.raises(InputError):
        get_tangential_model("linear").solve(circle, None, MAT, (1e-3, 0.0, 0.0), -0.3)
