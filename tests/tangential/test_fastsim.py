"""FASTSIM against Kalker's linear theory and the Coulomb limit."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from railcontact.core.errors import InputError
from railcontact.geometry import ContactGeometry
from railcontact.core.materials import Material
from railcontact.normal import get_normal_model, hertz_ellipse
from railcontact.tangential import get_tangential_model, kalker_coefficients

MAT = Material(2.1e11, 0.28)
FN = 5e4


def hertz_patch(ab, grid=(60, 60)):
    Es = MAT.contact_modulus
    A = 1.0
    B = 1.0 if ab == 1 else brentq(
        lambda B: (lambda h: h.a / h.b)(hertz_ellipse(A, B, Es, force=FN)) - ab, 1e-4, 1e5)
    return get_normal_model("hertz", margin=0.0).solve(ContactGeometry(curvatures=(A, B)), MAT,
                                                       normal_force=FN, grid=grid)


@pytest.mark.parametrize("ab", [0.5, 1.0, 2.0])
def test_linear_theory(ab):
    ns = hertz_patch(ab)
    a, b = ns.semi_axes
    c = math.sqrt(a * b)
    G = MAT.shear_modulus
    C11, C22, C23 = kalker_coefficients(a / b, MAT.poisson_ratio)
    fs = get_tangential_model("fastsim")
    e = 1e-6
    tx = fs.solve(ns, None, MAT, (e, 0, 0), 0.3)
    ty = fs.solve(ns, None, MAT, (0, e, 0), 0.3)
    tp = fs.solve(ns, None, MAT, (0, 0, e / c), 0.3)
    # forces on the wheel: F = +G c^2 C xi (creepage of the rail relative to the wheel)
    assert tx.fx / (G * c * c * e) == pytest.approx(C11, rel=0.02)
    assert ty.fy / (G * c * c * e) == pytest.approx(C22, rel=0.02)
    assert tp.fy / (G * c ** 3 * e / c) == pytest.approx(C23, rel=0.02)
    assert abs(tx.fy) < 1e-9 * abs(tx.fx)
    assert tx.stick_fraction > 0.95


@pytest.mark.parametrize("bound", ["elliptic", "parabolic"])
def test_saturation(bound):
    ns = hertz_patch(1.3)
    fs = get_tangential_model("fastsim", bound=bound)
    t = fs.solve(ns, None, MAT, (0.03, -0.04, 0.0), 0.3)
    F = math.hypot(t.fx, t.fy)
    assert F == pytest.approx(0.3 * FN, rel=5e-3)
    # force along the creepage, full slip
    assert t.fy / t.fx == pytest.approx(-0.04 / 0.03, rel=1e-3)
    assert t.stick_fraction < 0.02
    assert t.frictional_power > 0


def test_creep_curve_monotone_and_partial_slip():
    ns = hertz_patch(1.0)
    fs = get_tangential_model("fastsim")
    xis = np.linspace(0, 5e-3, 21)
    fx = [fs.solve(ns, None, MAT, (x, 0, 0), 0.3).fx for x in xis]
    assert np.all(np.diff(fx) > 0)
    assert fx[-1] < 0.3 * FN
    mid = fs.solve(ns, None, MAT, (1e-3, 0, 0), 0.3)
    assert 0.1 < mid.stick_fraction < 0.9
    # the stick zone is at the leading edge (x > 0)
    xs = np.broadcast_to(ns.x[:, None], mid.stick.shape)
    assert xs[mid.stick].mean() > xs[ns.contact & ~mid.stick].mean()


def test_parabolic_bound_differs_from_elliptic():
    # the parabolic bound is 4/3 higher at the centre and lower near the edges
    ns = hertz_patch(1.0)
    e = (1.5e-3, 0, 0)
    te = get_tangential_model("fastsim").solve(ns, None, MAT, e, 0.3)
    tp = get_tangential_model("fastsim", bound="parabolic").solve(ns, None, MAT, e, 0.3)
    assert abs(tp.fx - te.fx) > 1e-3 * abs(te.fx)
    assert np.max(np.abs(tp.traction_x)) > np.max(np.abs(te.traction_x))


def test_three_flexibilities_distort_direction_at_full_slip():
    ns = hertz_patch(1.3)
    t = get_tangential_model("fastsim", flexibility="three").solve(ns, None, MAT,
                                                                    (0.03, -0.04, 0.0), 0.3)
    assert abs(t.fy / t.fx + 0.04 / 0.03) > 0.05


def test_bad_options():
    with pytest.raises(InputError):
        get_tangential_model("fastsim", bound="square")
    ns = hertz_patch(1.0)
    with pytest.raises(InputError, match="friction"):
        get_tangential_model("fastsim").solve(ns, None, MAT, (0, 0, 0), -0.1)
    with pytest.raises(InputError, match="creepage"):
        get_tangential_model("fastsim").solve(ns, None, MAT, (math.nan, 0, 0), 0.3)
