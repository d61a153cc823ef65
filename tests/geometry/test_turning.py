"""CONTACT's rule for the reference angles of nearby separate patches."""

import numpy as np
import pytest

from railcontact.geometry.turning import default_turn_distance, turned_angles


def test_turning_blends_from_combined_to_separate():
    a, w = [-0.6, -0.05], [1.0, 3.0]
    comb = (1.0 * -0.6 + 3.0 * -0.05) / 4.0
    # at d_sep both take the combined patch's weighted angle, at d_turn their own
    for d, f in ((8e-3, 1.0), (10e-3, 0.5), (12e-3, 0.0), (12.5e-3, 0.0), (7e-3, 0.0)):
        out = turned_angles(a, w, [d], 8e-3, 12e-3)
        expected = np.array(a) + f * (comb - np.array(a))
        np.testing.assert_allclose(out, expected, atol=1e-15)
    assert default_turn_distance(8e-3, 4e-3) == pytest.approx(12e-3)
    # no turning where d_turn does not exceed d_sep, nor beyond a_sep
    np.testing.assert_array_equal(turned_angles(a, w, [9e-3], 8e-3, 8e-3), a)
    np.testing.assert_array_equal(turned_angles(a, w, [9e-3], 8e-3, 12e-3, max_angle=0.5), a)


def test_a_middle_patch_is_turned_by_both_neighbours():
    a, w = [-1.0, -0.5, 0.0], [1.0, 1.0, 1.0]
    out = turned_angles(a, w, [10e-3, 10e-3], 8e-3, 12e-3)
    # each pair blends half way to its mean, from the a-priori angles
    assert out[0] == pytest.approx(-1.0 + 0.5 * 0.25)
    assert out[1] == pytest.approx(-0.5 + 0.5 * -0.25 + 0.5 * 0.25)
    assert out[2] == pytest.approx(0.0 - 0.5 * 0.25)


def test_turning_in_the_search(refdir):
    """Tread and flange root of S1002/UIC60 near 5 mm lateral shift (right wheel,
    10 kN): two regions about 6 mm apart.  With regions combined within 4 mm and
    turned up to 8 mm, their contact angles move towards each other (towards
    their weighted mean), never past it."""
    from railcontact.geometry import Track, Wheelset, find_contact
    from railcontact.geometry.search import PatchRules
    from railcontact.profiles import read_profile
    ws = Wheelset(read_profile(refdir / "profiles" / "MBench_S1002_v3.prw"))
    tr = Track(read_profile(refdir / "profiles" / "MBench_UIC60_v3.prr"))
    turned_pairs = 0
    for y in (4.9, 5.0, 5.1):
        kw = dict(vertical_force=1e4, roll=0.0, side="right")
        rules = dict(combine_distance=4e-3, full_interaction_distance=2e-3)
        plain = find_contact(ws, tr, y * 1e-3, 0.0, rules=PatchRules(**rules),
                             **kw).side_patches("right")
        turned = find_contact(ws, tr, y * 1e-3, 0.0,
                              rules=PatchRules(turn_distance=8e-3, **rules),
                              **kw).side_patches("right")
        assert len(plain) == len(turned) == 2
        (a0, b0), (a1, b1) = ([p.contact_angle for p in ps] for ps in (plain, turned))
        w = np.array([p.weight for p in plain])
        mean = (w[0] * a0 + w[1] * b0) / w.sum()
        for before, after in ((a0, a1), (b0, b1)):
            assert min(before, mean) - 1e-12 <= after <= max(before, mean) + 1e-12
        turned_pairs += abs(a1 - b1) < abs(a0 - b0) - 1e-3
        # the reference points stay; only the tangent planes turn
        assert [p.y_rail for p in turned] == pytest.approx([p.y_rail for p in plain], abs=1e-12)
    assert turned_pairs == 3
