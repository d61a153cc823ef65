"""Hertz against independent closed forms and numerical integration."""

import math

import numpy as np

import pytest
from scipy import integrate

from railcontact.core.errors import InputError
from railcontact.geometry import ContactGeometry
from railcontact.core.materials import Material
from railcontact.normal import get_normal_model, hertz_ellipse

MAT = Material(2.1e11, 0.28)
ES = MAT.contact_modulus


def _displacement(a, b, p0, x0, y0):
    """Surface approach at (x0, y0) under the Hertz pressure, by direct integration
    of the Boussinesq kernel in polar coordinates about the field point."""
    def ray(th):
        c, s = math.cos(th), math.sin(th)
        q = (c / a) ** 2 + (s / b) ** 2
        lin = 2 * (x0 * c / a ** 2 + y0 * s / b ** 2)
        c0 = 1 - (x0 / a) ** 2 - (y0 / b) ** 2
        rmax = (-lin + math.sqrt(lin * lin + 4 * q * c0)) / (2 * q)
        return integrate.quad(lambda r: math.sqrt(max(c0 - lin * r - q * r * r, 0.0)),
                              0, rmax, epsabs=0, epsrel=1e-11)[0]
    val = integrate.quad(ray, 0, 2 * math.pi, epsabs=0, epsrel=1e-10, limit=400)[0]
    return p0 * val / (math.pi * ES)


@pytest.mark.parametrize("ratio", [0.05, 0.2, 1.0, 3.0, 20.0])
def test_ellipse_against_boussinesq_integration(ratio):
    # pick curvatures; check a/b spans 0.05..20 and the surface displacement field
    A = 1.0
    from scipy.optimize import brentq
    B = brentq(lambda B: hertz_ellipse(A, B, ES, force=1e5).a / hertz_ellipse(A, B, ES, force=1e5).b
               - ratio, 1e-6, 1e7) if ratio != 1.0 else 1.0
    h = hertz_ellipse(A, B, ES, force=1e5)
    assert h.a / h.b == pytest.approx(ratio, rel=1e-9)
    d0 = _displacement(h.a, h.b, h.p0, 0.0, 0.0)
    assert d0 == pytest.approx(h.penetration, rel=1e-3)
    # inside the contact u = delta - A x^2 - B y^2
    ux = _displacement(h.a, h.b, h.p0, 0.5 * h.a, 0.0)
    uy = _displacement(h.a, h.b, h.p0, 0.0, 0.5 * h.b)
    assert (d0 - ux) / (0.5 * h.a) ** 2 == pytest.approx(A, rel=1e-3)
    assert (d0 - uy) / (0.5 * h.b) ** 2 == pytest.approx(B, rel=1e-3)
    # force = integral of the pressure
    assert 2 * math.pi * h.p0 * h.a * h.b / 3 == pytest.approx(1e5, rel=1e-12)


def test_force_and_penetration_inverse():
    h = hertz_ellipse(1.1, 25.0, ES, force=3e4)
    g = hertz_ellipse(1.1, 25.0, ES, penetration=h.penetration)
    assert g.force == pytest.approx(3e4, rel=1e-10)
    assert g.a == pytest.approx(h.a, rel=1e-10)


def test_concave_wheel_conformal_case():
    # wheel flange root concave (R = -15 mm) on a 13 mm gauge corner
    B = 0.5 * (1 / 0.013 - 1 / 0.015)
    A = 0.5 / 0.46
    h = hertz_ellipse(A, B, ES, force=4e4)
    assert h.a > h.b   # B = 5.1 1/m > A = 1.09 1/m: the lateral semi-axis is the short one
    assert _displacement(h.a, h.b, h.p0, 0, 0) == pytest.approx(h.penetration, rel=1e-3)
    with pytest.raises(InputError, match="curvature"):
        hertz_ellipse(A, 0.5 * (1 / 0.015 - 1 / 0.013), ES, force=4e4)


def test_model_grid_and_errors():
    g = ContactGeometry(curvatures=(1.0, 3.0))
    ns = get_normal_model("hertz").solve(g, MAT, normal_force=8e4, grid=(80, 80))
    dA = ns.dx * ns.dy
    assert ns.pressure.sum() * dA == pytest.approx(8e4, rel=2e-3)
    assert ns.contact.sum() * dA == pytest.approx(ns.area, rel=2e-2)
    assert ns.pmax == pytest.approx(3 * 8e4 / (2 * ns.area), rel=1e-12)
    ds = ns.to_xarray()
    assert ds["pressure"].attrs["units"] == "Pa"
    with pytest.raises(InputError, match="normal force"):
        get_normal_model("hertz").solve(g, MAT, normal_force=-1.0)
    with pytest.raises(InputError, match="exactly one"):
        get_normal_model("hertz").solve(g, MAT)
    from railcontact.core.errors import UnknownModelError
    with pytest.raises(UnknownModelError, match="unknown normal model 'hurtz'"):
        get_normal_model("hurtz")


def test_vectorised_hertz_equals_scalar():
    from railcontact.core.hertz_theory import hertz_ellipses
    rng = np.random.default_rng(7)
    A = 10 ** rng.uniform(-1, 3, 300)
    B = 10 ** rng.uniform(-1, 3, 300)
    B[:5] = A[:5]                      # circles
    B[5:10] = A[5:10] * (1 + 1e-6)     # nearly circles
    B[10:15] = A[10:15] * 1e4          # slender ellipses
    d = 10 ** rng.uniform(-6, -4, 300)
    Es = 1.15e11
    a, b, f = hertz_ellipses(A, B, Es, d)
    for i in range(300):
        h = hertz_ellipse(A[i], B[i], Es, penetration=d[i])
        assert (a[i], b[i], f[i]) == pytest.approx((h.a, h.b, h.force), rel=1e-10)
    a0, b0, f0 = hertz_ellipses(1.0, 2.0, Es, [0.0, -1e-6])
    assert np.all(a0 == 0) and np.all(f0 == 0)


def test_table_hertz_equals_scalar():
    """The tabulated Hertz solution for the strip models: within 1e-7 of the exact
    one, also for circles, nearly circles and slender ellipses (a/b up to 1e-2),
    zero at zero or negative approach, and bad curvatures rejected."""
    from railcontact.core.hertz_theory import hertz_ellipses_table
    rng = np.random.default_rng(8)
    A = 10 ** rng.uniform(-1, 3, 300)
    B = 10 ** rng.uniform(-1, 3, 300)
    B[:5] = A[:5]
    B[5:10] = A[5:10] * (1 + 1e-6)
    B[10:15] = A[10:15] * 1e4
    A[15:20] = B[15:20] * 1e4
    d = 10 ** rng.uniform(-6, -4, 300)
    Es = 1.15e11
    a, b, f = hertz_ellipses_table(A.reshape(20, 15), B.reshape(20, 15), Es, d.reshape(20, 15))
    assert a.shape == (20, 15)
    for i in range(300):
        h = hertz_ellipse(A[i], B[i], Es, penetration=d[i])
        assert (a.flat[i], b.flat[i], f.flat[i]) == pytest.approx((h.a, h.b, h.force), rel=1e-7)
    a0, b0, f0 = hertz_ellipses_table(1.0, 2.0, Es, [0.0, -1e-6])
    assert np.all(a0 == 0) and np.all(b0 == 0) and np.all(f0 == 0)
    with pytest.raises(InputError, match="curvatures"):
        hertz_ellipses_table([1.0, -1.0], 1.0, Es, 1e-5)


def test_ratio_is_continuous_where_the_series_takes_over():
    from railcontact.core.hertz_theory import SERIES_M, _ratio
    # series below SERIES_M, elliptic integrals above: both must agree there
    lo, hi = _ratio(SERIES_M * (1 - 1e-9)) - 1, _ratio(SERIES_M * (1 + 1e-9)) - 1
    assert lo == pytest.approx(hi, rel=1e-8)
    assert _ratio(1e-6) - 1 == pytest.approx(0.75e-6, rel=1e-5)
    # monotone through the switch, so that the inversion has one root
    m = np.linspace(0.5 * SERIES_M, 2 * SERIES_M, 2001)
    assert np.all(np.diff([_ratio(v) for v in m]) > 0)


def test_force_curvature_sets_the_force_and_the_curvatures_the_ellipse():
    """A patch whose force curvature differs from its B
    (geometry.wheel_pass.force_curvature): at a penetration, the force is Hertz's
    with (A, B_force), the ellipse Hertz's with (A, B) at that force; under a force,
    the penetration is (A, B_force)'s.  Closed forms of core.hertz_theory, 1e-12."""
    A, B, Bf, d = 1.1, 3.95, 0.9, 6e-5
    g = ContactGeometry(curvatures=(A, B), force_curvature=Bf)
    Es = MAT.contact_modulus
    hz = get_normal_model("hertz")
    sol = hz.solve(g, MAT, penetration=d)
    F = hertz_ellipse(A, Bf, Es, penetration=d).force
    ref = hertz_ellipse(A, B, Es, force=F)
    assert sol.normal_force == pytest.approx(F, rel=1e-12)
    assert sol.semi_axes[0] == pytest.approx(ref.a, rel=1e-12)
    assert sol.semi_axes[1] == pytest.approx(ref.b, rel=1e-12)
    assert sol.penetration == pytest.approx(d, rel=1e-12)
    back = hz.solve(g, MAT, normal_force=F)
    assert back.penetration == pytest.approx(d, rel=1e-9)
    assert back.semi_axes[0] == pytest.approx(ref.a, rel=1e-12)
