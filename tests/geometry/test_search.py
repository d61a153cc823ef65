"""Contact search (railcontact.geometry.search): robustness of the patch geometry."""

import math

import numpy as np
import pytest

from railcontact.geometry import Track, Wheelset, find_contact
from railcontact.geometry.search import PatchRules, SearchStart
from railcontact.profiles import rail_profile, s1002


def test_patch_from_flange_root_to_flange_has_usable_curvatures():
    """S1002 on 60E1 1:40 at 6.44 mm with a deep right wheel: one interpenetration
    region runs from the flange root up the flange (contact angle 0.6 rad), and its
    deepest point projects beyond the rail profile's end in the patch's tangent plane.
    The patch still gets positive curvatures and a potential contact area of a few
    centimetres (it got A = 0 and an extent of +-464 m, and the exact solver a zero
    force there), and the exact normal solver carries load on it."""
    from railcontact.core.materials import STEEL
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
    from railcontact.core.errors import InputError
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    full = find_contact(ws, tr, lateral_shift=2e-3, vertical_force=6e4)
    one = find_contact(ws, tr, lateral_shift=2e-3, vertical_force=6e4,
                       start=SearchStart(load_iterations=1))
    for s in ("left", "right"):
        assert one.interpenetration[s] == pytest.approx(full.interpenetration[s], rel=0.05)
    d = dict(full.interpenetration)
    a = find_contact(ws, tr, lateral_shift=2e-3, interpenetration=d)
    b = find_contact(ws, tr, lateral_shift=2e-3, interpenetration=d,
                     start=SearchStart(full.pose.roll + 1e-4))
    assert b.pose.roll == pytest.approx(a.pose.roll, abs=1e-11)
    assert b.pose.vertical == pytest.approx(a.pose.vertical, abs=1e-11)
    with pytest.raises(InputError, match="load_iterations"):
        find_contact(ws, tr, vertical_force=6e4, start=SearchStart(load_iterations=0))
    with pytest.raises(InputError, match="roll_start"):
        find_contact(ws, tr, vertical_force=6e4, start=SearchStart(0.5))


@pytest.mark.parametrize("shift, candidates", [(1e-3, 1), (4.75e-3, 2), (5e-3, 2)])
def test_multi_hertzian_approach_carries_the_load(shift, candidates):
    """The multi-Hertzian estimate's interpenetration makes the candidates' Hertzian
    vertical forces, summed independently here, carry the load: on the tread (one
    candidate: the closed form) and where two tread minima lie within 0.05 mm of
    each other (4.75 mm: the second loaded, 5 mm: both)."""
    from railcontact.geometry.locus import compute_locus
    from railcontact.geometry.search import _approach_for_load, _candidates, _locus_curvatures
    from railcontact.core.materials import STEEL
    from railcontact.core.hertz_theory import hertz_ellipse
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


#: rules that send find_contact to the geometry layer's own search with the results of
#: one patch per region: a combine distance (1 nm) below the locus's sample spacing
OWN_SEARCH = PatchRules(combine_distance=1e-9)


@pytest.mark.parametrize("locus", ["lowest", "contact"])
def test_prescribed_interpenetrations_search_in_the_compiled_pass(locus, monkeypatch):
    """Under prescribed interpenetrations find_contact runs the compiled pass's search
    (wheel_pass.search_patches): the same patches and loci as the geometry layer's own
    search to round-off (the same locus kernel), on tread, two-point and flange contact
    with yaw; with patch turning it searches itself.  The own search is the one every
    case that combines regions runs (every .inp case): a combine distance below the
    locus's sample spacing (OWN_SEARCH) combines none, so its patches are those of
    one patch per region."""
    from railcontact.geometry import search, wheel_pass
    ws, tr = Wheelset(s1002(), locus=locus), Track(rail_profile("60E1", math.atan(1 / 40)))
    calls = []
    monkeypatch.setattr(search, "search_patches",
                        lambda *a: calls.append(1) or wheel_pass.search_patches(*a))
    for shift, yaw, d in ((0.0, 0.0, (8e-5, 8e-5)), (5.5e-3, 2e-3, (6e-5, 9e-5)),
                          (8e-3, 6e-3, (6e-5, 1.2e-4))):
        d = {"left": d[0], "right": d[1]}
        a = find_contact(ws, tr, shift, yaw, vertical_force=7e4, interpenetration=d)
        b = find_contact(ws, tr, shift, yaw, vertical_force=7e4, interpenetration=d,
                         rules=OWN_SEARCH)
        assert abs(a.pose.roll - b.pose.roll) < 1e-12
        assert abs(a.pose.vertical - b.pose.vertical) < 1e-12
        assert len(a.patches) == len(b.patches) >= 2
        for p, q in zip(a.patches, b.patches):
            assert p.side == q.side
            assert np.allclose(p.position, q.position, rtol=0, atol=1e-12)
            assert p.approach == pytest.approx(q.approach, rel=1e-8, abs=1e-14)
            assert np.allclose(p.curvatures, q.curvatures, rtol=1e-7)
            assert p.contact_angle == pytest.approx(q.contact_angle, abs=1e-11)
            assert np.allclose(p.creepage, q.creepage, rtol=1e-8, atol=1e-12)
            assert np.allclose(p.bounds, q.bounds, rtol=1e-9, atol=1e-12)
        for s in ("left", "right"):
            la, lb = a.loci[s], b.loci[s]
            i0, i1 = max(la.samples[0], lb.samples[0]), min(la.samples[1], lb.samples[1])
            assert i1 - i0 > 10
            assert np.allclose(la.gap[i0 - la.samples[0]:i1 - la.samples[0]],
                               lb.gap[i0 - lb.samples[0]:i1 - lb.samples[0]], rtol=0, atol=1e-12)
    assert len(calls) == 3
    find_contact(ws, tr, 5.5e-3, 2e-3, vertical_force=7e4, interpenetration=d,
                 rules=PatchRules(turn_distance=0.02))
    assert len(calls) == 3


def test_compiled_search_computes_its_loci_where_read():
    """The compiled search's loci (SearchLoci, issue 30) are computed where read:
    those of compute_locus at the search's pose over the regions' window, exactly;
    the pass's profiles are made once per wheelset and track."""
    from railcontact.geometry import search
    from railcontact.geometry.locus import compute_locus
    from railcontact.geometry.pose import REGION_MARGIN
    from railcontact.geometry.search import SearchLoci
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    d = {"left": 6e-5, "right": 9e-5}
    c = find_contact(ws, tr, 5.5e-3, 2e-3, vertical_force=7e4, interpenetration=d)
    assert isinstance(c.loci, SearchLoci) and set(c.loci) == {"left", "right"}
    assert not c.loci._loci                       # nothing computed yet
    p = c.pose
    for s in ("left", "right"):
        ref = compute_locus(ws, tr, s, p.lateral_shift, p.vertical, p.roll, p.yaw,
                            window=d[s] + REGION_MARGIN)
        assert c.loci[s].samples == ref.samples
        assert np.array_equal(c.loci[s].gap, ref.gap)
        assert np.array_equal(c.loci[s].y_rail, ref.y_rail)
    with pytest.raises(KeyError):
        c.loci["middle"]
    prof = search._pass_profiles(ws, tr)
    assert search._pass_profiles(ws, tr) is prof
    assert search._pass_profiles(ws, Track(rail_profile("60E1", math.atan(1 / 40)))) \
        is not prof


@pytest.mark.parametrize("locus", ["lowest", "contact"])
def test_prescribed_roll_searches_in_the_compiled_pass(locus, monkeypatch):
    """Under a prescribed roll (one wheel, CONTACT's single-wheel mode: every .inp
    wheel-rail case) find_contact's pose comes from the compiled pass's kernels
    (search._fixed_roll_pose: the side's minimum gap once per case and roll, the locus
    from the pass's memo of the case) and its patches are those of the geometry
    layer's own pose search (solve_pose, reached where the pass does not serve) to
    round-off: a sequence of interpenetrations as a balance makes them, on tread,
    two-point and flange contact with yaw, with CONTACT's rules of combining regions
    (8 mm) and turning them (12 mm), under a load and rigidly.  Where no region is
    combined or turned, under a load, the patches are the compiled pass's
    (search._pass_patches: wheel_pass.make_patch on the same locus)."""
    from railcontact.geometry import search
    rail = rail_profile("60E1", math.atan(1 / 40))
    rules = PatchRules(8e-3, 4e-3, 12e-3)
    calls, made = [], []
    real = search._fixed_roll_pose
    monkeypatch.setattr(search, "_fixed_roll_pose",
                        lambda *a: calls.append(1) or real(*a))
    real_patches = search._pass_patches
    monkeypatch.setattr(search, "_pass_patches",
                        lambda *a: made.append(1) or real_patches(*a))
    for shift, yaw, roll, side in ((0.0, 0.0, 0.0, "right"), (5.5e-3, 2e-3, 1e-3, "right"),
                                   (-6e-3, -4e-3, -1.5e-3, "left")):
        runs = []
        for own in (False, True):
            ws, tr = Wheelset(s1002(), locus=locus), Track(rail)   # fresh memos
            if own:
                monkeypatch.setattr(search, "pass_profiles", lambda *a: None)
            before = len(calls)
            out = [find_contact(ws, tr, shift, yaw, vertical_force=7e4, roll=roll, side=side,
                                rules=rules)]
            out += [find_contact(ws, tr, shift, yaw, roll=roll, side=side, rules=rules,
                                 interpenetration={side: d})
                    for d in (6e-5, 9e-5, 7.5e-5, 7.6e-5, 1.2e-4)]
            out.append(find_contact(ws, tr, shift, yaw, roll=roll, side=side, rules=rules))
            # every search in the pass (the estimate's iterations too), none in the own
            assert len(calls) - before >= len(out) if not own else len(calls) == before
            runs.append(out)
            monkeypatch.undo()
            monkeypatch.setattr(search, "_fixed_roll_pose",
                                lambda *a: calls.append(1) or real(*a))
            monkeypatch.setattr(search, "_pass_patches",
                                lambda *a: made.append(1) or real_patches(*a))
        for a, b in zip(*runs):
            assert a.pose.roll == b.pose.roll
            assert a.pose.vertical == pytest.approx(b.pose.vertical, abs=1e-13)
            assert len(a.patches) == len(b.patches) >= 1
            for p, q in zip(a.patches, b.patches):
                assert p.side == q.side == side
                assert np.allclose(p.position, q.position, rtol=0, atol=1e-12)
                assert p.approach == pytest.approx(q.approach, rel=1e-9, abs=1e-15)
                assert np.allclose(p.curvatures, q.curvatures, rtol=1e-8)
                assert p.contact_angle == pytest.approx(q.contact_angle, abs=1e-12)
                assert np.allclose(p.creepage, q.creepage, rtol=1e-9, atol=1e-13)
                assert len(p.interaction) == len(q.interaction)
                assert np.allclose(np.reshape(p.interaction, -1), np.reshape(q.interaction, -1),
                                   rtol=0, atol=1e-12)
    assert made                         # the compiled patches served


def test_a_changed_wheelset_is_searched_afresh():
    """A wheelset changed after a search (its flange-back distance) is searched as a
    new one with those values: its memo (the compiled search's profiles) emptied
    (before: the old profiles' samples, z 2.38e-4 against 8.02e-5 m)."""
    tr = Track(rail_profile("60E1", math.atan(1 / 40)))
    d = {"left": 6e-5, "right": 9e-5}
    ws = Wheelset(s1002())
    find_contact(ws, tr, 1e-3, 0.0, interpenetration=d)
    find_contact(ws, tr, 1e-3, 0.0, roll=1e-3, side="right", interpenetration=d)
    ws.flange_back_distance = 1.365
    for kw in ({}, {"roll": 1e-3, "side": "right"}):
        a = find_contact(ws, tr, 1e-3, 0.0, interpenetration=d, **kw)
        b = find_contact(Wheelset(s1002(), flange_back_distance=1.365), tr, 1e-3, 0.0,
                         interpenetration=d, **kw)
        assert a.pose == b.pose
        assert [p.approach for p in a.patches] == [p.approach for p in b.patches]


def test_a_cases_searches_share_one_memo():
    """A case's compiled searches under prescribed interpenetrations (one wheelset,
    track, shift and yaw) share one memo (search_memo: the last loci's wheel samples
    and the roll search's secant slope, issue 30): a balance's sequence of searches
    finds the pose and patches of searches from a fresh memo each (a new wheelset)
    to the roll search's tolerance, on tread, two-point and flange contact."""
    from railcontact.geometry.search import search_memo
    tr = Track(rail_profile("60E1", math.atan(1 / 40)))
    for shift, yaw, d0 in ((0.0, 0.0, 8e-5), (5.5e-3, 2e-3, 7e-5), (8e-3, 6e-3, 9e-5)):
        ws = Wheelset(s1002())
        roll = 0.0
        for f in (1.0, 1.3, 0.9, 1.02, 1.001):
            d = {"left": d0 * f, "right": d0 * f * 1.1}
            a = find_contact(ws, tr, shift, yaw, vertical_force=7e4, interpenetration=d,
                             start=SearchStart(roll))
            b = find_contact(Wheelset(s1002()), tr, shift, yaw, vertical_force=7e4,
                             interpenetration=d, start=SearchStart(roll))
            assert abs(a.pose.roll - b.pose.roll) < 1e-11
            assert abs(a.pose.vertical - b.pose.vertical) < 1e-11
            assert len(a.patches) == len(b.patches) >= 2
            for p, q in zip(a.patches, b.patches):
                assert np.allclose(p.position, q.position, rtol=0, atol=1e-11)
                assert p.approach == pytest.approx(q.approach, rel=1e-6, abs=1e-13)
                assert np.allclose(p.curvatures, q.curvatures, rtol=1e-6)
                assert np.allclose(p.creepage, q.creepage, rtol=1e-6, atol=1e-11)
            roll = a.pose.roll
        assert search_memo(ws, tr, shift, yaw) is not None


def test_a_prescribed_roll_locus_does_not_depend_on_earlier_searches():
    """A prescribed-roll locus (search._fixed_roll_pose) spans its samples within the
    window and one on either side, whatever the case searched before (before: the
    memo's span of the last locus, e.g. a deeper search's: 162 of 384 combinations
    measured spanned other samples, their patches within 2.8e-13 relative), its
    patches the same."""
    tr = Track(rail_profile("60E1", math.atan(1 / 40)))
    for y, roll, side in ((-2e-3, 0.0, "right"), (-2e-3, 1e-3, "left")):
        cold = find_contact(Wheelset(s1002()), tr, y, 0.0, roll=roll, side=side,
                            interpenetration={side: 1e-5})
        ws = Wheelset(s1002())
        for d in (3e-4, 1e-5):          # a deeper search first (before: 2200-3697
            # against 2392-3569 on the right)
            after = find_contact(ws, tr, y, 0.0, roll=roll, side=side,
                                 interpenetration={side: d})
        lc, la = cold.loci[side], after.loci[side]
        assert la.samples == lc.samples and la.gap.size == lc.samples[1] - lc.samples[0]
        assert np.array_equal(la.gap, lc.gap)
        assert [p.approach for p in after.patches] == [p.approach for p in cold.patches]
