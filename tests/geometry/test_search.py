"""Contact search (railcontact.geometry.search): robustness of the patch geometry."""

import math

import numpy as np
import pytest

from railcontact.geometry import Track, Wheelset, find_contact
from railcontact.profiles import rail_profile, s1002


def test_patch_from_flange_root_to_flange_has_usable_curvatures():
    """S1002 on 60E1 1:40 at 6.44 mm with a deep right wheel: one interpenetration
    region runs from the flange root up the flange (contact angle 0.6 rad), and its
    deepest point projects beyond the rail profile's end in the patch's tangent plane.
    The patch still gets positive curvatures and a potential contact area of a few
    centimetres (it got A = 0 and an extent of +-464 m, and the exact solver a zero
    force there), and the exact normal solver carries load on it."""
    from railcontact.materials import STEEL
    from railcontact.normal import get_normal_model
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    y = -4e-3 + 200 * 13e-3 / 249
    c = find_contact(ws, tr, lateral_shift=y, interpenetration={"left": 7.6e-5, "right": 6.3e-4})
    right = [p for p in c.patches if p.side == "right" and p.approach > 0]
    assert right
    for p in right:
        A, B = p.curvatures
        assert 0 < A < 1e3 and 0 < B < 1e3
        x0, x1, y0, y1 = p.extent
        assert x1 - x0 < 0.1 and y1 - y0 < 0.1
        ns = get_normal_model("exact").solve(p, STEEL, penetration=p.approach, grid=(30, 30))
        assert ns.converged and ns.normal_force > 1e5
        assert np.all(np.isfinite(ns.pressure))


def test_load_iterations_and_roll_start():
    """One load iteration is a first estimate of the ten-iteration search; the start
    of the roll search changes the work, not the pose; bad values are refused."""
    import pytest
    from railcontact.errors import InputError
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    full = find_contact(ws, tr, lateral_shift=2e-3, vertical_force=6e4)
    one = find_contact(ws, tr, lateral_shift=2e-3, vertical_force=6e4, load_iterations=1)
    for s in ("left", "right"):
        assert one.interpenetration[s] == pytest.approx(full.interpenetration[s], rel=0.05)
    d = dict(full.interpenetration)
    a = find_contact(ws, tr, lateral_shift=2e-3, interpenetration=d)
    b = find_contact(ws, tr, lateral_shift=2e-3, interpenetration=d,
                     roll_start=full.pose.roll + 1e-4)
    assert b.pose.roll == pytest.approx(a.pose.roll, abs=1e-11)
    assert b.pose.vertical == pytest.approx(a.pose.vertical, abs=1e-11)
    with pytest.raises(InputError, match="load_iterations"):
        find_contact(ws, tr, vertical_force=6e4, load_iterations=0)
    with pytest.raises(InputError, match="roll_start"):
        find_contact(ws, tr, vertical_force=6e4, roll_start=0.5)


def test_gap_memo_is_kept_per_track():
    """The wheelset's memo of minimum gaps serves repeated searches on the same track
    (identical results) and never a different track at the same shift and yaw."""
    ws = Wheelset(s1002())
    rail = rail_profile("60E1", math.atan(1 / 40))
    narrow, wide = Track(rail, gauge=1.435), Track(rail, gauge=1.441)
    a = find_contact(ws, narrow, lateral_shift=3e-3, vertical_force=6e4)
    assert ws.gap_memo
    b = find_contact(ws, wide, lateral_shift=3e-3, vertical_force=6e4)
    c = find_contact(Wheelset(s1002()), wide, lateral_shift=3e-3, vertical_force=6e4)
    again = find_contact(ws, narrow, lateral_shift=3e-3, vertical_force=6e4)
    assert b.pose.roll == c.pose.roll and b.pose.vertical == c.pose.vertical
    assert again.pose.roll == a.pose.roll and again.pose.vertical == a.pose.vertical
    assert b.pose.vertical != a.pose.vertical


def test_loci_of_given_interpenetrations_hold_the_same_patches(monkeypatch):
    """With the interpenetrations given, the loci cover only the wheel samples within
    the interpenetration plus REGION_MARGIN of the closest approach; the patches
    (tread, and flange root with flange on the deep right wheel) are those of loci
    over the whole LOCUS_WINDOW."""
    import railcontact.geometry.pose as pose
    from railcontact.geometry.locus import LOCUS_WINDOW
    tr = Track(rail_profile("60E1", math.atan(1 / 40)))
    runs = []
    for margin in (pose.REGION_MARGIN, LOCUS_WINDOW):
        monkeypatch.setattr(pose, "REGION_MARGIN", margin)
        out = []
        for y, d in ((1e-3, {"left": 7e-5, "right": 6.5e-5}),
                     (6.44e-3, {"left": 7.6e-5, "right": 6.3e-4})):
            c = find_contact(Wheelset(s1002()), tr, lateral_shift=y, interpenetration=d)
            out.append((c, [c.loci[s].y_wheel.size for s in ("left", "right")]))
        runs.append(out)
    for (small, n_small), (full, n_full) in zip(*runs):
        assert sum(n_small) < sum(n_full)
        assert len(small.patches) == len(full.patches)
        for p, q in zip(small.patches, full.patches):
            assert p.side == q.side
            assert p.approach == q.approach and p.contact_angle == q.contact_angle
            assert p.extent == q.extent and p.curvatures == q.curvatures


def test_gauge_point_per_rail_and_gauge_height():
    """The rail's gauge point (computed once per profile and gauge height) lies where
    the profile is gauge_height below its top on the gauge side; a deeper gauge
    height gives a point further to the gauge side; the offsets place the gauge
    faces the gauge apart."""
    rail = rail_profile("60E1", math.atan(1 / 40))
    top = float(np.min(rail.z))
    for h in (0.014, 0.010):
        tr = Track(rail, gauge_height=h)
        g = tr.gauge_point(rail)
        assert float(rail.z_at(g)) == pytest.approx(top + h, abs=1e-12)
        assert tr.rail_offset("left") + g == pytest.approx(1.435 / 2, abs=1e-12)
    assert Track(rail, gauge_height=0.014).gauge_point(rail) < \
        Track(rail, gauge_height=0.010).gauge_point(rail)


def _two_patch_contact():
    """S1002 on 60E1 1:40 at 5.40 mm shift: the right wheel touches with a flange
    root region (0.33 rad) and, a few mm to the field side, a shallow tread region
    (0.15 rad) just entering the contact."""
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    c = find_contact(ws, tr, lateral_shift=5.3976e-3, vertical_force=6e4,
                     interpenetration={"left": 74.069e-6, "right": 90.303e-6})
    return [p for p in c.patches if p.side == "right"]


def test_patch_bounds_lie_halfway_between_the_regions():
    """Each patch owns the band of its tangent plane up to halfway to the other
    region of its wheel: the two finite bounds meet at one rail position between
    the regions, the far bounds are open, and each region lies in its own band."""
    pats = _two_patch_contact()
    assert len(pats) == 2
    meet = []
    for p in pats:
        lo, hi = p.bounds
        assert math.isinf(lo) != math.isinf(hi)
        b = hi if math.isinf(lo) else lo
        meet.append(p.y_rail + b * math.cos(p.contact_angle))   # right wheel: y along t
        assert lo < p.extent[2] < p.extent[3] < hi
    assert meet[0] == pytest.approx(meet[1], abs=1e-9)
    ys = sorted(p.y_rail for p in pats)
    assert ys[0] < meet[0] < ys[1]


@pytest.mark.parametrize("shift, candidates", [(1e-3, 1), (4.75e-3, 2), (5e-3, 2)])
def test_multi_hertzian_approach_carries_the_load(shift, candidates):
    """The multi-Hertzian estimate's interpenetration makes the candidates' Hertzian
    vertical forces, summed independently here, carry the load: on the tread (one
    candidate: the closed form) and where two tread minima lie within 0.05 mm of
    each other (4.75 mm: the second loaded, 5 mm: both)."""
    from railcontact.geometry.locus import compute_locus
    from railcontact.geometry.search import _approach_for_load, _candidates, _locus_curvatures
    from railcontact.materials import STEEL
    from railcontact.hertz_theory import hertz_ellipse
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    rigid = find_contact(ws, tr, lateral_shift=shift)
    loc = compute_locus(ws, tr, "right", shift, rigid.pose.vertical, rigid.pose.roll, 0.0)
    d = _approach_for_load(loc, 6e4, ws.nominal_radius, STEEL)
    assert len(_candidates(loc)) == candidates
    total = 0.0
    for i in _candidates(loc):
        c = math.cos(math.atan(loc.slope[i]))
        pen = (d - (loc.gap[i] - loc.gap_min)) * c
        if pen > 0:
            A, B = _locus_curvatures(loc, i, ws.nominal_radius)
            total += hertz_ellipse(A, B, STEEL.contact_modulus, penetration=pen).force * c
    assert total == pytest.approx(6e4, rel=1e-9)
    assert 1e-5 < d < 1e-3
