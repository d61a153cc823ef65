"""railcontact.geometry.wheel_pass: the compiled contact search gives the geometry
layer's patches (railcontact.geometry.find_contact) under the same
interpenetrations."""

import math

import numpy as np
import pytest

from railcontact.geometry import Track, Wheelset, find_contact
from railcontact.geometry.wheel_pass import (NPF, P_A, P_APPROACH, P_B, P_CONTACT_ANGLE, P_ETA,
                                             P_PHI, P_ROLLING_RADIUS, P_SIDE, P_WEIGHT, P_XI,
                                             P_Y_RAIL, MAX_PATCHES, PassPose, locus_regions,
                                             new_memo, pass_profiles, search_patches)
from railcontact.profiles import rail_profile, s1002


@pytest.fixture(scope="module")
def bodies():
    return Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))


def _pose(ws, tr, shift, yaw, combine=0.0):
    return PassPose(shift, yaw, tr.rail_offset("left"), tr.rail_offset("right"),
                    ws.wheel_offset, ws.nominal_radius, 30.0, -30.0 / ws.nominal_radius, 0.0,
                    0.0, combine)


# tread contact, tread with yaw, and flange contact on the right wheel
@pytest.mark.parametrize("shift, yaw, d", [(0.0, 0.0, (8e-5, 8e-5)),
                                           (3e-3, 4e-3, (7e-5, 9e-5)),
                                           (7.5e-3, 2e-3, (6e-5, 1.2e-4))])
def test_patches_are_the_geometry_layers(bodies, shift, yaw, d):
    ws, tr = bodies
    prof = pass_profiles(ws, tr)
    out = np.zeros((2 * MAX_PATCHES, NPF))
    m, z, roll = search_patches(prof, _pose(ws, tr, shift, yaw), np.array(d), new_memo(), out)
    ref = find_contact(ws, tr, shift, yaw, vertical_force=7e4,
                       interpenetration={"left": d[0], "right": d[1]})
    # the pose: roll to the searches' tolerance (1e-12 rad), z to 1e-12 m
    assert abs(roll - ref.pose.roll) < 1e-10 and abs(z - ref.pose.vertical) < 1e-11
    assert m == len(ref.patches)
    # the rows run along each side's locus from the gauge side; the geometry layer
    # numbers a wheel's patches from the field side
    rows = [r for s in (0, 1) for r in reversed([r for r in out[:m] if r[P_SIDE] == s])]
    for row, p in zip(rows, ref.patches):
        assert ("left", "right")[int(row[P_SIDE])] == p.side
        assert row[P_Y_RAIL] == pytest.approx(p.y_rail, abs=1e-10)
        assert row[P_CONTACT_ANGLE] == pytest.approx(p.contact_angle, abs=1e-9)
        assert row[P_APPROACH] == pytest.approx(p.approach, rel=1e-6, abs=1e-12)
        assert row[P_A] == pytest.approx(p.curvatures[0], rel=1e-5)
        assert row[P_B] == pytest.approx(p.curvatures[1], rel=1e-5)
        assert row[P_ROLLING_RADIUS] == pytest.approx(p.rolling_radius, abs=1e-10)
        assert row[P_WEIGHT] == pytest.approx(p.weight, rel=1e-9)
        for k, c in zip((P_XI, P_ETA, P_PHI), p.creepage):
            assert row[k] == pytest.approx(c, rel=1e-6, abs=1e-9)


def test_a_second_search_reuses_the_memo_and_agrees(bodies):
    ws, tr = bodies
    prof, pose = pass_profiles(ws, tr), _pose(ws, tr, 2e-3, 3e-3)
    memo = new_memo()
    out = np.zeros((2 * MAX_PATCHES, NPF))
    search_patches(prof, pose, np.array([6e-5, 8e-5]), memo, out)
    assert np.isfinite(memo[[6, 7, 12, 13]]).all()            # the minima's windows kept
    m, z, roll = search_patches(prof, pose, np.array([7e-5, 9e-5]), memo, out)
    fresh = np.zeros_like(out)
    m2, z2, roll2 = search_patches(prof, pose, np.array([7e-5, 9e-5]), new_memo(), fresh)
    assert m == m2 and abs(roll - roll2) < 1e-10 and abs(z - z2) < 1e-11
    assert np.allclose(out[:m, P_APPROACH], fresh[:m, P_APPROACH], rtol=1e-6)


def test_regions_combine_within_the_distance():
    # two interpenetration runs 4 samples apart (25 um each) on a flat rail surface
    gap = np.array([1.0, -1e-6, -2e-6, 1e-6, 1e-6, 1e-6, 1e-6, -1e-6, -1e-6, 1.0]) * 1e-3
    P = np.zeros((3, gap.size))
    yr = np.arange(gap.size) * 2.5e-5
    apart = locus_regions(gap, P, yr, 0.0)
    assert apart.tolist() == [[1, 2], [7, 8]]
    assert locus_regions(gap, P, yr, 1e-3).tolist() == [[1, 8]]


def test_rows_become_the_geometry_layers_patches(bodies):
    from railcontact.geometry.track import WheelsetPose
    from railcontact.geometry.wheel_pass import rows_contact
    ws, tr = bodies
    shift, yaw, d = 6.0e-3, 2e-3, (7e-5, 1.1e-4)
    prof = pass_profiles(ws, tr)
    out = np.zeros((2 * MAX_PATCHES, NPF))
    m, z, roll = search_patches(prof, _pose(ws, tr, shift, yaw), np.array(d), new_memo(), out)
    loads = {"left": 7e4, "right": 7e4}
    targets = {"left": d[0], "right": d[1]}
    got = rows_contact(out[:m], ws, tr, WheelsetPose(shift, z, roll, yaw), loads, targets)
    ref = find_contact(ws, tr, shift, yaw, vertical_force=7e4, interpenetration=targets)
    assert len(got.patches) == len(ref.patches)
    x = np.linspace(-4e-3, 4e-3, 5)[:, None]
    y = np.linspace(-3e-3, 3e-3, 7)[None, :]
    for a, b in zip(got.patches, ref.patches):
        assert a.side == b.side
        assert np.allclose(a.extent, b.extent, rtol=1e-5, atol=1e-9)
        assert np.allclose(a.bounds, b.bounds, rtol=1e-9, atol=1e-12)
        assert np.allclose(a.position, b.position, atol=1e-10)
        # the undeformed distance on a grid of the tangent plane: the same surfaces
        assert np.allclose(a.gap(x, y), b.gap(x, y), atol=1e-10)


def _loc(y, gap, theta=0.0):
    """A locus tuple (the fields the curvature rules read: yr, gap, slope)."""
    return (0, y.size, None, None, y, gap, np.full(y.size, math.tan(theta)))


def test_moment_curvature_of_a_hertzian_gap():
    """For the gap g = -d + B y² sampled every 25 um (the locus's step), the depth
    and the trapezoidal moment of the interpenetration squared give B cos³(θ)
    (closed form: I = 16/15 d^2.5 / sqrt(B); the trapezoid's error below 0.5 %
    with 200 samples across)."""
    from railcontact.geometry.wheel_pass import moment_curvature
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
    from railcontact.geometry.wheel_pass import force_curvature, moment_curvature
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
    from railcontact.geometry.wheel_pass import force_curvature
    y = np.arange(-0.01, 0.01 + 1e-9, 2.5e-5)
    gap = -8e-5 + 3.5 * y * y
    neg = np.flatnonzero(gap < 0)
    im = int(np.argmin(gap))
    assert force_curvature(_loc(y, gap), int(neg[0]), int(neg[-1]), im, 3.6) == 3.6
