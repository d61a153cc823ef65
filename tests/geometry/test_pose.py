"""Wheelset pose (railcontact.geometry.pose): the memo of minimum gaps and the loci windows."""

import math

from railcontact.geometry import Track, Wheelset, find_contact
from railcontact.profiles import rail_profile, s1002


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
    from railcontact.geometry.search import PatchRules
    tr = Track(rail_profile("60E1", math.atan(1 / 40)))
    runs = []
    for margin in (pose.REGION_MARGIN, LOCUS_WINDOW):
        monkeypatch.setattr(pose, "REGION_MARGIN", margin)
        out = []
        for y, d in ((1e-3, {"left": 7e-5, "right": 6.5e-5}),
                     (6.44e-3, {"left": 7.6e-5, "right": 6.3e-4})):
            # the geometry layer's own search (solve_pose's windows), not the pass's:
            # the rules of a case that combines regions, none combined (1 nm)
            c = find_contact(Wheelset(s1002()), tr, lateral_shift=y, interpenetration=d,
                             rules=PatchRules(combine_distance=1e-9))
            out.append((c, [c.loci[s].y_wheel.size for s in ("left", "right")]))
        runs.append(out)
    for (small, n_small), (full, n_full) in zip(*runs):
        assert sum(n_small) < sum(n_full)
        assert len(small.patches) == len(full.patches)
        for p, q in zip(small.patches, full.patches):
            assert p.side == q.side
            assert p.approach == q.approach and p.contact_angle == q.contact_angle
            assert p.extent == q.extent and p.curvatures == q.curvatures


def test_the_memo_of_prescribed_rolls_is_bounded():
    """A wheelset searched at one shift and yaw under ever new prescribed rolls (a
    contact element's steps without lateral motion) keeps at most 257 rolls' memos
    (it kept every one: 300 of 300)."""
    from railcontact.geometry.pose import _memo
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    for k in range(300):
        find_contact(ws, tr, 1e-3, 0.0, roll=1e-3 * k / 300, side="right",
                     interpenetration={"right": 5e-5})
    assert 0 < len(_memo(ws, tr, 1e-3, 0.0).fixed_roll) <= 257
