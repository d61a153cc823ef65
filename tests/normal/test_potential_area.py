"""Helpers of the exact model's potential contact area
(railcontact.normal.potential_area) on small hand-made masks and grids."""

from types import SimpleNamespace

import numpy as np
import pytest

from railcontact.normal.potential_area import (AREA_SAMPLES, coarse_lines, crossings,
                                               edge_sides, fits, grown_box, plausible_growth,
                                               region_ends, strip_edges)


def test_strip_edges_of_a_mask():
    x = np.array([-2.0, -1.0, 0.0, 1.0, 2.0]) * 1e-3           # dx = 1 mm
    c = np.zeros((5, 3), bool)
    c[1:4, 0] = True            # elements -1..1 mm: edges -1.5 and 1.5 mm
    c[3, 2] = True              # one element at 1 mm
    lead, trail = strip_edges(c, x)
    assert lead == pytest.approx([1.5e-3, 0.0, 1.5e-3], abs=1e-15)
    assert trail == pytest.approx([-1.5e-3, 0.0, 0.5e-3], abs=1e-15)


def test_crossings_interpolate_the_zeros():
    s = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    g = np.array([1.0, -1.0, -2.0, -1.0, 3.0])                 # negative on 1..3
    lo, hi = crossings(s, g, 1, 3)
    assert lo == pytest.approx(0.5) and hi == pytest.approx(3.25)


def test_region_ends_are_the_crossings_of_the_minima():
    """region_ends (compiled, the minima on the four rows and columns it reads) gives
    bit for bit the crossings of h.min(axis=1) and h.min(axis=0): a paraboloid's
    negative region on uneven lines, plus noise, and a hand-made case (the ends
    at 0.5 and 3.25 along x, as test_crossings_interpolate_the_zeros)."""
    rng = np.random.default_rng(3)
    for _ in range(50):
        xs = np.linspace(-1.0, 1.0, 17) + rng.uniform(-0.04, 0.04, 17)
        ys = np.linspace(-1.0, 1.0, 13) + rng.uniform(-0.05, 0.05, 13)
        h = (xs[:, None] - 0.1) ** 2 + 2.0 * ys[None, :] ** 2 - 0.15 + 0.01 * rng.normal(
            size=(17, 13))
        i = np.flatnonzero((h < 0).any(axis=1))
        j = np.flatnonzero((h < 0).any(axis=0))
        i0, i1, j0, j1 = i[0], i[-1], j[0], j[-1]
        assert 0 < i0 and i1 < 16 and 0 < j0 and j1 < 12
        want = crossings(xs, h.min(axis=1), i0, i1) + crossings(ys, h.min(axis=0), j0, j1)
        assert region_ends(xs, ys, h, i0, i1, j0, j1) == want
    s = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    h = np.array([[5.0] * 5, [1.0, -1.0, -2.0, -1.0, 3.0], [5.0] * 5]).T
    assert region_ends(s, s[:3], h, 1, 3, 1, 1) == pytest.approx((0.5, 3.25, 5 / 7, 9 / 7))


def test_coarse_lines_are_numpys_linspace():
    """coarse_lines(c, half) is c + np.linspace(-2 half, 2 half, AREA_SAMPLES) bit
    for bit (the potential area's coarse sampling, compiled)."""
    rng = np.random.default_rng(4)
    for _ in range(200):
        c, half = rng.normal() * 10 ** rng.uniform(-6, -1), 10 ** rng.uniform(-4, -1)
        want = c + np.linspace(-2 * half, 2 * half, AREA_SAMPLES)
        assert np.array_equal(coarse_lines(c, half), want)


def test_edge_sides_and_grown_box():
    c = np.zeros((4, 6), bool)
    c[0, 2] = c[1, 5] = True
    assert edge_sides(c) == (True, False, False, True)
    x = np.linspace(0.5, 3.5, 4)                               # elements [0, 4] wide 1
    y = np.linspace(0.5, 5.5, 6)                               # [0, 6]
    (cx, cy), (ex, ey) = grown_box(x, y, (True, False, False, True))
    # x grows by half the width (2) at its low side: [-2, 4]; y at its high side: [0, 9]
    assert (cx, cy, ex, ey) == pytest.approx((1.0, 4.5, 3.0, 4.5))
    (cx, cy), (ex, ey) = grown_box(x, y, (False,) * 4)
    assert (cx, cy, ex, ey) == pytest.approx((2.0, 3.0, 2.0, 3.0))


def test_plausible_growth():
    s = lambda force, pen: SimpleNamespace(normal_force=force, penetration=pen)  # noqa: E731
    assert plausible_growth(s(1.0, 0), s(1.9, 0), displacement=True)
    assert not plausible_growth(s(1.0, 0), s(2.1, 0), displacement=True)
    assert plausible_growth(s(0, 1e-5), s(0, 0.5e-5), displacement=False)
    assert not plausible_growth(s(0, 1e-5), s(0, 0.1e-5), displacement=False)
    assert not plausible_growth(s(0, 1e-5), s(0, 1.1e-5), displacement=False)


def test_fits_needs_the_same_grid_and_a_box_inside():
    sol = SimpleNamespace(x=np.linspace(-4.5, 4.5, 10), y=np.linspace(-2.5, 2.5, 6))
    assert fits(sol, 0.0, 0.0, 4.0, 2.5, (10, 6))
    assert not fits(sol, 0.0, 0.0, 4.0, 2.5, (12, 6))             # other element counts
    assert not fits(sol, 3.0, 0.0, 4.0, 2.5, None)                # sticks out
    assert not fits(sol, 0.0, 0.0, 0.5, 0.5, None)                # fills too little
    assert not fits(SimpleNamespace(x=np.zeros(1), y=np.zeros(3)), 0, 0, 1, 1, None)


def test_compiled_edge_sides_and_overlap_bounds_against_numpy():
    """``edge_sides`` and ``inside_bounds`` (compiled) against their NumPy
    definitions on random masks and gaps, foreign columns included."""
    from railcontact.normal.potential_area import inside_bounds
    rng = np.random.default_rng(5)
    for shape in ((49, 49), (3, 8), (12, 2)):
        for _ in range(20):
            c = rng.random(shape) < 0.1
            assert edge_sides(c) == (c[0, :].any(), c[-1, :].any(), c[:, 0].any(),
                                     c[:, -1].any())
            h = rng.normal(0.3, 1.0, shape)
            foreign = rng.random(shape[1]) < 0.2
            inside = (h < 0) & ~foreign[None, :]
            ix, iy = np.flatnonzero(inside.any(axis=1)), np.flatnonzero(inside.any(axis=0))
            want = (-1,) * 4 if ix.size == 0 else (ix[0], ix[-1], iy[0], iy[-1])
            assert inside_bounds(h, foreign) == want
