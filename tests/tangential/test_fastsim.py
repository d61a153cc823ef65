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


def test_frictional_power_is_the_limit_of_the_slip_integral():
    """FASTSIM's power, the integral of p . s with its slip s = w_F + L dp/dx, is summed
    as p . w_F (docs/frictional_power.md): with one flexibility (full sliding, the
    blended L1 = L2 = L3) it is V (xi F_x + eta F_y + phi M_z) (rel. 1e-9); with three
    it is the limit of the sum of p . s over the grid fields, which converges slowly:
    measured -5.0 % at 80, -0.8 % at 640 and -0.2 % at 2000 elements per strip for a
    partial-slip case with spin, while the power moves by 0.14 % from 80 to 640."""
    ns = hertz_patch(1.3)
    V = 20.0
    t = get_tangential_model("fastsim").solve(ns, None, MAT, (0.03, -0.04, 0.5), 0.3, V)
    macro = V * (0.03 * t.fx - 0.04 * t.fy + 0.5 * t.mz)
    assert t.frictional_power == pytest.approx(macro, rel=1e-9)
    sums = []
    for n in (80, 640):
        t = get_tangential_model("fastsim", elements=n).solve(ns, None, MAT,
                                                              (1e-3, 2e-4, 0.3), 0.3, V)
        dA = (t.x[1] - t.x[0]) * (t.y[1] - t.y[0])
        sums.append((t.frictional_power, t.power_density.sum() * dA))
    (p80, s80), (p640, s640) = sums
    assert p640 == pytest.approx(p80, rel=2e-3)                 # converged
    assert 0.93 < s80 / p80 < 0.97 and 0.99 < s640 / p640 < 1.0  # the sum approaches it


@pytest.mark.parametrize("ab", [0.5, 2.0])
def test_grid_march_linear_theory_and_saturation(ab):
    """``march="grid"`` (CONTACT's element march on the normal solution's grid): in
    the linear range Kalker's C11, C22 within 1.5 % on 120 x 120 elements (the first
    full step per row, u = dx w at the leading element, adds about 1/n per row of n
    elements: +2.0 % at 60 x 60, +0.9 % measured at 120 x 120), at large creepage
    the force mu F_n along the creepage (0.5 %), and the same forces as the strip
    march within 2 % of mu F_n in partial slip with spin."""
    ns = hertz_patch(ab, grid=(120, 120))
    a, b = ns.semi_axes
    c2 = a * b
    G = MAT.shear_modulus
    C11, C22, _ = kalker_coefficients(a / b, MAT.poisson_ratio)
    fs = get_tangential_model("fastsim", march="grid")
    e = 1e-6
    tx = fs.solve(ns, None, MAT, (e, 0, 0), 0.3)
    ty = fs.solve(ns, None, MAT, (0, e, 0), 0.3)
    assert tx.fx / (G * c2 * e) == pytest.approx(C11, rel=0.015)
    assert ty.fy / (G * c2 * e) == pytest.approx(C22, rel=0.015)
    t = fs.solve(ns, None, MAT, (0.03, -0.04, 0.0), 0.3)
    assert math.hypot(t.fx, t.fy) == pytest.approx(0.3 * FN, rel=5e-3)
    assert t.fy / t.fx == pytest.approx(-0.04 / 0.03, rel=1e-3)
    cr = (5e-4, -8e-4, 0.5)
    g, s = fs.solve(ns, None, MAT, cr, 0.3), get_tangential_model("fastsim").solve(
        ns, None, MAT, cr, 0.3)
    assert abs(g.fx - s.fx) < 0.02 * 0.3 * FN and abs(g.fy - s.fy) < 0.02 * 0.3 * FN
    with pytest.raises(InputError, match="march"):
        get_tangential_model("fastsim", march="diagonal")
    with pytest.raises(InputError, match="grid"):
        get_tangential_model("fastsim", march="grid", bound="parabolic")


def test_contact_blending_weight():
    """``flexibility="contact"``: CONTACT's blending weight (simpflex; Vollebregt &
    Voltr 2023), f = sqrt((xi^2 + eta^2)/(xi_c^2 + eta_c^2)): the blended
    flexibilities of :func:`contact_flexibilities` (1e-12) and CONTACT's printed
    FLX1-3 of mbench_a22_kpec.inp case 2 (4 digits) from its equivalent ellipse
    (31 x 71 elements of 0.2 mm, 939 in contact) and creepages; the default
    ``"blended"`` weight |(xi/xi_c, eta/eta_c)| gives L3 4.6 % larger there; both
    are Kalker's in the linear range."""
    from railcontact.tangential.fastsim import contact_flexibilities, FastsimModel
    G, nu = 8.2e10, 0.28
    r = math.sqrt(939 * 0.04e-6 / math.pi)
    a, b = r * math.sqrt(31 / 71), r * math.sqrt(71 / 31)
    cr, fn = (4.780e-4, 1.202e-3, 0.1221), 9890.0
    got = FastsimModel(flexibility="contact")._flexibilities(a, b, G, nu, cr, 0.3, fn)
    want = contact_flexibilities(a, b, G, nu, cr, 0.3, fn)
    np.testing.assert_allclose(got, want, rtol=1e-12)
    np.testing.assert_allclose(np.array(got) * 1e9, [0.2157e-4, 0.2497e-4, 0.1907e-4],
                               rtol=0, atol=0.00006e-4)
    own = FastsimModel()._flexibilities(a, b, G, nu, cr, 0.3, fn)
    assert own[2] / got[2] - 1 == pytest.approx(0.046, abs=0.002)
    # the two weights agree on a pure creepage along one axis when scaled alike:
    # in the linear range (w = 0) both are Kalker's
    tiny = (1e-9, 0.0, 0.0)
    np.testing.assert_allclose(FastsimModel()._flexibilities(a, b, G, nu, tiny, 0.3, fn),
                               FastsimModel(flexibility="contact")._flexibilities(
                                   a, b, G, nu, tiny, 0.3, fn), rtol=1e-5)
