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


# CONTACT's locus (each wheel section's point whose normal is perpendicular to x):
# the pass takes it from the same kernel (the wheel slopes in PassProfiles.ws)
@pytest.mark.parametrize("shift, yaw, d", [(3e-3, 4e-3, (7e-5, 9e-5)),
                                           (7.5e-3, 6e-3, (6e-5, 1.2e-4))])
def test_contact_locus_patches_are_the_geometry_layers(bodies, shift, yaw, d):
    ws = Wheelset(s1002(), locus="contact")
    tr = bodies[1]
    assert pass_profiles(ws, tr).ws.size == pass_profiles(ws, tr).eta.size
    test_patches_are_the_geometry_layers((ws, tr), shift, yaw, d)
    # and the locus is CONTACT's, not the lowest points: here the two loci's patches
    # lie 8 to 63 nm apart laterally, far beyond the agreement above (0.1 nm)
    lowest, contact = (find_contact(w, tr, shift, yaw, vertical_force=7e4,
                                    interpenetration={"left": d[0], "right": d[1]})
                       for w in (bodies[0], ws))
    assert max(abs(a.y_rail - b.y_rail) for a, b in zip(lowest.patches, contact.patches)) > 5e-9


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

