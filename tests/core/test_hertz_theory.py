"""railcontact.core.hertz_theory against the closed forms of Hertz's theory
(Johnson, Contact Mechanics, 1985, sections 4.2 and 3.4)."""

import math

import numpy as np
import pytest
from scipy.special import ellipe, ellipk

from railcontact.core.errors import InputError
from railcontact.core.hertz_theory import (eccentricity_from_ratio, hertz_curvatures, hertz_ellipse,
                                      hertz_ellipses, hertz_ellipses_table)

ES = 1.15e11                     # E* of steel on steel [Pa]


def test_equal_curvatures_give_a_circle():
    """A = B = 1/(2R): a^3 = 3 F R / (4 E*), delta = a^2 / R, p0 = 3 F / (2 pi a^2)."""
    R, F = 0.3, 5e4
    h = hertz_ellipse(1 / (2 * R), 1 / (2 * R), ES, force=F)
    a = (3 * F * R / (4 * ES)) ** (1 / 3)
    assert h.a == pytest.approx(a, rel=1e-12) and h.b == pytest.approx(a, rel=1e-12)
    assert h.penetration == pytest.approx(a * a / R, rel=1e-12)
    assert h.p0 == pytest.approx(3 * F / (2 * math.pi * a * a), rel=1e-12)
    assert h.area == pytest.approx(math.pi * a * a, rel=1e-12)
    assert eccentricity_from_ratio(1.0) == 0.0


def _curvatures_of(a_major, b_minor, F):
    """Johnson's (4.39): the curvatures of the ellipse with the given semi-axes."""
    m = 1 - (b_minor / a_major) ** 2
    K, E = ellipk(m), ellipe(m)
    c = 3 * F / (2 * math.pi * a_major * b_minor) * b_minor / (ES * a_major ** 2 * m)
    return c * (K - E), c * (a_major ** 2 / b_minor ** 2 * E - K), K


@pytest.mark.parametrize("a, b", [(8e-3, 5e-3), (3e-3, 9e-3), (20e-3, 2e-3)])
def test_ellipse_against_the_elliptic_integrals(a, b):
    """The ellipse with semi-axes (a, b) has the curvatures of Johnson's (4.39);
    solved from those, by force and by penetration, it comes back."""
    F = 8e4
    big, small = max(a, b), min(a, b)
    A_small, A_large, K = _curvatures_of(big, small, F)
    A, B = (A_small, A_large) if a >= b else (A_large, A_small)
    p0 = 3 * F / (2 * math.pi * a * b)
    delta = p0 * small * K / ES
    h = hertz_ellipse(A, B, ES, force=F)
    assert (h.a, h.b) == pytest.approx((a, b), rel=1e-10)
    assert h.p0 == pytest.approx(p0, rel=1e-10) and h.penetration == pytest.approx(delta, rel=1e-10)
    g = hertz_ellipse(A, B, ES, penetration=delta)
    assert (g.a, g.b, g.force) == pytest.approx((a, b, F), rel=1e-10)
    assert hertz_curvatures(a, b, ES, F) == pytest.approx((A, B), rel=1e-10)


def test_scaling_with_the_force():
    """a, b grow as F^(1/3), p0 and the approach as F^(1/3) and F^(2/3)."""
    h1, h8 = (hertz_ellipse(2.0, 5.0, ES, force=F) for F in (1e4, 8e4))
    assert h8.a / h1.a == pytest.approx(2, rel=1e-12) and h8.b / h1.b == pytest.approx(2, rel=1e-12)
    assert h8.p0 / h1.p0 == pytest.approx(2, rel=1e-12)
    assert h8.penetration / h1.penetration == pytest.approx(4, rel=1e-12)


def test_vectorised_forms_agree_with_the_scalar_one():
    A = np.array([1.0, 2.0, 5.0, 0.5])
    B = np.array([1.0, 0.7, 50.0, 3.0])
    d = np.array([1e-4, 5e-5, 2e-5, 0.0])
    a, b, F = hertz_ellipses(A, B, ES, d)
    at, bt, Ft = hertz_ellipses_table(A, B, ES, d)
    for i in range(3):
        h = hertz_ellipse(A[i], B[i], ES, penetration=d[i])
        assert (a[i], b[i], F[i]) == pytest.approx((h.a, h.b, h.force), rel=1e-9)
        assert (at[i], bt[i], Ft[i]) == pytest.approx((h.a, h.b, h.force), rel=1e-6)
    assert a[3] == b[3] == F[3] == 0.0 and at[3] == bt[3] == Ft[3] == 0.0


@pytest.mark.parametrize("kw", [dict(A=-1.0, B=1.0, force=1.0),
                                dict(A=1.0, B=float("nan"), force=1.0),
                                dict(A=1.0, B=1.0), dict(A=1.0, B=1.0, force=1.0, penetration=1e-5),
                                dict(A=1.0, B=1.0, force=-1.0)])
def test_bad_input(kw):
    with pytest.raises(InputError):
        hertz_ellipse(contact_modulus=ES, **kw)
