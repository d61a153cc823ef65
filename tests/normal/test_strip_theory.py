"""The strip models' equations (railcontact.normal.strip_theory) on hand-made strip
quantities: the parabolic minimum, STRIPES' corrected gap, and the strip pressures
of a Hertzian gap against Hertz."""

import math

import numpy as np
import pytest

from railcontact.core.errors import InputError
from railcontact.core.hertz_theory import hertz_ellipse
from railcontact.core.materials import STEEL
from railcontact.normal.strip_theory import corrected_gap, parabolic_minima, strip_pressures

Es = STEEL.contact_modulus


def test_parabolic_minimum_of_three_samples():
    h = lambda t: 2.0 + 3.0 * (t - 0.1) ** 2                            # noqa: E731
    d = 0.5
    t, c1, c2, g = parabolic_minima(h(-d), h(0.0), h(d), d, 1.0)
    assert (t, c2, g) == pytest.approx((0.1, 3.0, 2.0), rel=1e-12)
    assert c1 == pytest.approx(-0.6, rel=1e-12)
    t, _, _, g = parabolic_minima(h(-d), h(0.0), h(d), d, 0.05)        # clipped
    assert t == pytest.approx(0.05) and g == pytest.approx(h(0.05), rel=1e-12)
    t, _, _, g = parabolic_minima(np.array([1.0]), np.array([2.0]), np.array([1.5]), d, 1.0)
    assert t[0] == 0.0 and g[0] == 2.0                                  # not convex


def test_corrected_gap_with_a_constant_beta():
    y = np.linspace(-1.0, 1.0, 11)
    g = np.vstack([y ** 2, 0.5 * (y - 0.3) ** 2 + 0.1 * y ** 3])
    beta = np.vstack([np.full(11, 0.7), np.full(11, 1.3)])
    j0 = np.array([5, 7])
    out = corrected_gap(g, beta, j0)
    for r in range(2):
        k = j0[r]
        assert out[r] == pytest.approx(beta[r] * (g[r] - g[r, k]) + g[r, k], abs=1e-13)


@pytest.mark.parametrize("A, B", [(1 / 0.92, 1 / 0.6), (3.0, 1.0)])
def test_hertz_strips_on_a_hertzian_gap(A, B):
    """ANALYN and STRIPES cut every strip from the Hertz solution: l_j = a sqrt(1 -
    (y/b)^2), p_j = p0 sqrt(1 - (y/b)^2); KPEC's peak within 2 % of p0."""
    d = 1e-4
    hz = hertz_ellipse(A, B, Es, penetration=d)
    y = np.linspace(-1.3 * hz.b, 1.3 * hz.b, 121)[None, :]
    dy = np.array([y[0, 1] - y[0, 0]])
    hstar = B * y ** 2 - d
    full = lambda v: np.full(y.shape, v)                                 # noqa: E731
    inside = np.abs(y[0]) < hz.b
    root = np.sqrt(np.maximum(1.0 - (y[0] / hz.b) ** 2, 0.0))
    for model in ("analyn", "stripes"):
        half, peak = strip_pressures(model, y, dy, full(0.0), hstar, full(A), full(B), Es)
        # squared, 1 - (y/b)^2: the Hertz table's 1e-7 in b is not amplified at the edge
        assert (half[0] / hz.a) ** 2 == pytest.approx(root ** 2, abs=1e-6), model
        assert (peak[0] / hz.p0) ** 2 == pytest.approx(root ** 2, abs=1e-6), model
        assert not half[0, ~inside].any()
    half, peak = strip_pressures("kpec", y, dy, full(0.0), hstar, full(A), full(B), Es)
    assert peak.max() == pytest.approx(hz.p0, rel=0.02)
    with pytest.raises(InputError, match="strip model"):
        strip_pressures("hertz", y, dy, full(0.0), hstar, full(A), full(B), Es)
