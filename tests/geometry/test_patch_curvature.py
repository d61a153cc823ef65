"""railcontact.geometry.patch_curvature: the region's curvature of a Hertzian gap
(closed forms) and the force curvature's continuity where the deepest point jumps."""

import math

import numpy as np
import pytest


def _loc(y, gap, theta=0.0):
    """A locus tuple (the fields the curvature rules read: yr, gap, slope)."""
    return (0, y.size, None, None, y, gap, np.full(y.size, math.tan(theta)))


def test_moment_curvature_of_a_hertzian_gap():
    """For the gap g = -d + B y² sampled every 25 um (the locus's step), the depth
    and the trapezoidal moment of the interpenetration squared give B cos³(θ)
    (closed form: I = 16/15 d^2.5 / sqrt(B); the trapezoid's error below 0.5 %
    with 200 samples across)."""
    from railcontact.geometry.patch_curvature import moment_curvature
    d, B, theta = 8e-5, 3.5, 0.05
    y = np.arange(-0.01, 0.01 + 1e-9, 2.5e-5) + 7e-6
    gap = -d + B * y * y
    neg = np.flatnonzero(gap < 0)
    got = moment_curvature(_loc(y, gap, theta), int(neg[0]), int(neg[-1]))
    assert got == pytest.approx(B * math.cos(theta) ** 3, rel=5e-3)


def _twin(tilt):
    """Two minima 12 mm apart, 1 um below the barrier between them (S1002 on 60E1's
    tread), the right one wider (its curvature half the left's) and deeper by
    ``tilt`` [m]; the deepest point's curvature B at that minimum."""
    y = np.arange(-0.02, 0.03 + 1e-9, 2.5e-5)
    u = np.where(y > 0, y / math.sqrt(2), y)
    c = 1e-6 / 0.005 ** 4
    gap = -6e-5 + c * (u * u - 0.005 ** 2) ** 2 - tilt * u / 0.005
    neg = np.flatnonzero(gap < 0)
    im = int(np.argmin(gap))
    Bm = 0.5 * (gap[im + 1] + gap[im - 1] - 2 * gap[im]) / 2.5e-5 ** 2
    return _loc(y, gap), int(neg[0]), int(neg[-1]), im, Bm


def test_force_curvature_is_continuous_where_the_deepest_point_jumps():
    """As the deeper of two equal minima changes sides, the deepest point's
    curvature jumps (the two minima's differ by a factor > 1.5 here); the force's
    curvature is the region's on both sides and moves by less than 0.1 %."""
    from railcontact.geometry.patch_curvature import force_curvature, moment_curvature
    loc_a, a0, a1, ia, Ba = _twin(-1e-8)
    loc_b, b0, b1, ib, Bb = _twin(1e-8)
    assert loc_a[4][ia] < 0.0 < loc_b[4][ib]
    assert max(Ba, Bb) / min(Ba, Bb) > 1.5
    fa = force_curvature(loc_a, a0, a1, ia, Ba)
    fb = force_curvature(loc_b, b0, b1, ib, Bb)
    assert fa == pytest.approx(moment_curvature(loc_a, a0, a1), rel=1e-12)
    assert fb == pytest.approx(fa, rel=1e-3)


def test_force_curvature_keeps_a_hertzian_patchs():
    """On a Hertzian gap (one minimum, B within 25 % of the region's) the force's
    curvature is the deepest point's, unchanged."""
    from railcontact.geometry.patch_curvature import force_curvature
    y = np.arange(-0.01, 0.01 + 1e-9, 2.5e-5)
    gap = -8e-5 + 3.5 * y * y
    neg = np.flatnonzero(gap < 0)
    im = int(np.argmin(gap))
    assert force_curvature(_loc(y, gap), int(neg[0]), int(neg[-1]), im, 3.6) == 3.6


def test_region_depth():
    """The region's deepest sample (the first of two equal ones) and its depth;
    samples outside the region do not count."""
    from railcontact.geometry.patch_curvature import region_depth
    gap = np.array([-9.0, 1.0, -2.0, -3.0, 0.5, -3.0, -9.0]) * 1e-6
    im, d = region_depth(gap, 1, 5)
    assert im == 3 and d == 3e-6
    assert region_depth(np.array([1e-6, 2e-6]), 0, 1) == (0, -1e-6)


def test_the_deepest_fraction_is_the_parabolas_vertex_and_continuous():
    """On a parabola sampled every 25 um the vertex is recovered exactly (closed
    form), and where the deepest sample passes to its neighbour (their gaps equal)
    both give the point half-way between them: the interpolated point does not jump."""
    from railcontact.geometry.patch_curvature import (at_fraction, deepest_fraction,
                                                      deepest_slope)
    y = np.arange(0.0, 5e-4, 2.5e-5)
    for y0 in (1.51e-4, 1.62e-4, 1.6249e-4):
        gap = -1e-4 + 3.0 * (y - y0) ** 2
        im = int(np.argmin(gap))
        f = deepest_fraction(gap, im)
        assert -0.5 <= f <= 0.5
        assert at_fraction(y, im, f) == pytest.approx(y0, abs=1e-12)
        # a linear slope along the samples is interpolated exactly
        assert deepest_slope(gap, 0.2 + 40.0 * y, im) == pytest.approx(0.2 + 40.0 * y0,
                                                                       abs=1e-9)
    # the switch: samples 6 and 7 equally deep, an asymmetric gap about them
    gap = -1e-4 + 3.0 * (y - 1.625e-4) ** 2 + 50.0 * (y - 1.625e-4) ** 3
    gap[7] = gap[6]
    assert deepest_fraction(gap, 6) == pytest.approx(0.5)
    assert deepest_fraction(gap, 7) == pytest.approx(-0.5)
    assert at_fraction(y, 6, 0.5) == pytest.approx(at_fraction(y, 7, -0.5), abs=1e-15)
    # the locus's ends and samples without a gap: the deepest sample itself
    assert deepest_fraction(gap, 0) == 0.0
    gap[5] = np.inf
    assert deepest_fraction(gap, 6) == 0.0


def test_the_deepest_gap_is_continuous_where_the_deepest_sample_passes_on():
    """The gap at the locus's minimum between the samples (deepest_gap): a cubic
    gap's own value at the parabola's vertex (closed form, the four samples' cubic
    exact), the sample's gap where the vertex is the sample, and where the deepest
    sample passes to its neighbour (their gaps equal) the same value from either
    side, where the parabola's vertex alone jumps by (gap[5] - gap[8]) / 8."""
    from railcontact.geometry.patch_curvature import deepest_fraction, deepest_gap
    y = np.arange(0.0, 5e-4, 2.5e-5)
    h = 2.5e-5
    for y0 in (1.51e-4, 1.62e-4, 1.6249e-4, 1.5e-4):
        gap = -1e-4 + 3.0 * (y - y0) ** 2 + 4e3 * (y - y0) ** 3
        im = int(np.argmin(gap))
        f = deepest_fraction(gap, im)
        yv = y[im] + f * h
        assert deepest_gap(gap, im) == pytest.approx(
            -1e-4 + 3.0 * (yv - y0) ** 2 + 4e3 * (yv - y0) ** 3, rel=0, abs=1e-18)
    gap = -1e-4 + 3.0 * (y - 1.5e-4) ** 2
    assert deepest_gap(gap, 6) == gap[6]
    # the switch: samples 6 and 7 equally deep, an asymmetric gap about them
    gap = -1e-4 + 3.0 * (y - 1.625e-4) ** 2 + 4e3 * (y - 1.625e-4) ** 3
    gap[7] = gap[6]
    assert deepest_gap(gap, 6) == pytest.approx(deepest_gap(gap, 7), rel=0, abs=1e-18)
    vertex = [gap[i] - (gap[i - 1] - gap[i + 1]) ** 2
              / (8 * (gap[i - 1] - 2 * gap[i] + gap[i + 1])) for i in (6, 7)]
    assert abs(vertex[0] - vertex[1]) == pytest.approx(abs(gap[5] - gap[8]) / 8, rel=1e-9)
    assert abs(vertex[0] - vertex[1]) > 1e-11
    # without a fourth sample (the locus's end): the parabola's vertex
    assert deepest_gap(gap[:8], 6) == pytest.approx(vertex[0], rel=0, abs=1e-18)
