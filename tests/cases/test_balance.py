"""railcontact.cases.balance: the vertical balance of a wheel-rail case, and the
contact at a prescribed position."""

import numpy as np
import pytest

import railcontact as rc
from railcontact.cases.patches import case_models
from railcontact.cases.balance import WheelRailContact, solve_at_position, solve_wheel_rail


def _case(**wheelset):
    return rc.case_from_dict({"wheel": {"profile": "S1002"}, "rail": {"profile": "60E1"},
                              "wheelset": {"lateral_shift": 0.002, **wheelset}})


def test_the_evaluation_is_monotone_and_reused():
    case = _case(side="both", vertical_force=[50e3, 90e3])
    _, _, nmodel, tmodel, kw = case_models(case)
    evaluate = WheelRailContact(case, nmodel, tmodel, kw)
    d0 = evaluate.start()
    assert set(d0) == {"left", "right"} and all(v > 0 for v in d0.values())
    first = evaluate(d0)
    deeper = evaluate({s: 1.2 * v for s, v in d0.items()})
    assert all(deeper.forces[s] > first.forces[s] > 0 for s in d0)
    again = evaluate(dict(deeper.interpenetration))
    assert again.results is deeper.results                     # the same point: reused
    assert first.final and first.uncertainty is None           # FASTSIM solves every time


def test_solve_wheel_rail_meets_each_load_and_keeps_the_side():
    case = _case(side="right", vertical_force=[50e3, 90e3])
    _, _, nmodel, tmodel, kw = case_models(case)
    results, contact, balance = solve_wheel_rail(case, nmodel, tmodel, kw, rtol=1e-6)
    assert balance.converged and all(abs(r) <= 1e-6 for r in balance.residual.values())
    assert results and all(r.geometry.side == "right" for r in results)
    assert {p.side for p in contact.patches} == {"left", "right"}


def test_solve_at_position_deeper_is_heavier():
    base = _case(side="right", vertical_force=70e3)
    _, _, nmodel, tmodel, kw = case_models(base)
    z = rc.solve(base).pose.vertical
    forces = []
    for dz in (0.0, 2e-5):
        raw = {"wheel": {"profile": "S1002"}, "rail": {"profile": "60E1"},
               "wheelset": {"lateral_shift": 0.002, "side": "right", "roll": 0.0,
                            "vertical_position": z + dz}}
        results, contact = solve_at_position(rc.case_from_dict(raw), nmodel, tmodel, kw)
        assert results and all(r.geometry.side == "right" for r in results)
        forces.append(sum(r.normal.normal_force for r in results))
    assert forces[1] > forces[0] > 0


def _sweep_case(j):
    """Case j of the benchmark's 1000-case sweep (benchmarks/run_all.py sweep_raws:
    S1002/60E1 1:40, 70 kN, 40 x 40), built here as there."""
    import math
    k, iy = j % 250, j // 250
    y = -4e-3 + 13e-3 * k / 249
    return rc.case_from_dict({
        "wheel": {"profile": "S1002"}, "rail": {"profile": "60E1"},
        "wheelset": {"lateral_shift": y, "yaw": 2e-3 * iy, "vertical_force": 7e4,
                     "velocity": 30.0},
        "creepage": {"longitudinal": 1.5e-3 * math.sin(2 * math.pi * j / 97),
                     "lateral": 1e-3 * math.cos(2 * math.pi * j / 61),
                     "spin": 0.2 * math.sin(2 * math.pi * j / 43)},
        "solver": {"grid": [40, 40]}})


def test_force_controlled_balance_meets_the_load_as_the_general_one():
    """The force-controlled balance (one patch a side, exact models; off by default,
    BalanceOptions.force_control) meets each load to 1e-4 with the exact F_y, its patches
    are its last search's (whose approaches carry the load by the contact
    stiffness), and it agrees with the general balance: F_n to 1e-4 (measured
    <= 3.5e-5 on these tread cases), F_x and F_y within 0.6 % of mu Q (measured
    <= 0.1 %; the general balance's own cold/warm spread below 6.2 mm is 0.57 %,
    the 40 x 40 grid's extent following the path: benchmarks/results.md)."""
    import railcontact.cases.balance as B
    from railcontact.cases.results import vertical_force_on_rail
    from railcontact.normal import get_normal_model
    mu_q = 0.3 * 7e4
    for j in (20, 150):
        case = _sweep_case(j)
        ref = rc.solve(case, "exact", "exact")
        res = rc.solve(case, "exact", "exact", options=B.BalanceOptions(force_control=True))
        assert res.converged and ref.converged
        assert res.balance.passes <= B.FORCE_CONTROL_SEARCHES
        for side in ("left", "right"):
            assert vertical_force_on_rail(res.patches, side) == pytest.approx(7e4, rel=1e-4)
        ids = {id(g) for g in res.contact.patches}
        assert all(id(p.geometry) in ids for p in res.patches)
        assert len(res.patches) == len(ref.patches) == 2
        for a, b in zip(ref.patches, res.patches):
            assert b.geometry.side == a.geometry.side
            assert b.normal.normal_force == pytest.approx(a.normal.normal_force, rel=1e-4)
            assert abs(b.tangential.fx - a.tangential.fx) <= 6e-3 * mu_q
            assert abs(b.tangential.fy - a.tangential.fy) <= 6e-3 * mu_q
            # the search's approach carries the load: within 1e-4 by the stiffness
            slope = B._log_stiffness(get_normal_model("exact"), case, b)
            assert abs(slope * (b.geometry.approach / b.normal.penetration - 1)) <= 1e-4
        # its Jacobian for a neighbour: K delta / F_n, Hertz's 1.5 on the tread
        assert np.all(np.abs(np.diag(res.balance.jacobian) - 1.5) < 0.1)


def test_balance_options_are_checked_where_they_enter():
    """BalanceOptions and rc.solve's ``options`` say which input is wrong."""
    import railcontact.cases.balance as B
    from railcontact.core.errors import InputError
    assert B.BalanceOptions() == B.DEFAULT_OPTIONS
    assert B.DEFAULT_OPTIONS.extrapolate_ratio == B.EXTRAPOLATE_RATIO
    with pytest.raises(InputError, match="extrapolate_ratio"):
        B.BalanceOptions(extrapolate_ratio=0.5)
    with pytest.raises(InputError, match="compiled_start"):
        B.BalanceOptions(compiled_start=1)
    with pytest.raises(InputError, match="options"):
        rc.solve(_sweep_case(20), "hertz", "fastsim", options={"force_control": True})


def _warm_start_case(j):
    """Case j of the 1000-case sweep at 60 kN (tests/test_warm_start.py's), exact
    models, 40 x 40 grid."""
    from tests.test_warm_start import _sweep_raw
    return rc.case_from_dict(_sweep_raw(j, grid=[40, 40]))


def test_a_warm_flange_case_restarts_from_the_hertz_estimate(monkeypatch):
    """Sweep case 198 (6.34 mm, flange contact joining on the right wheel) started
    from case 197: the extrapolated start lands on the other branch of the flange's
    S-shaped force (its first evaluation 0.3 of the load off in ln F: beyond
    RESTART_MISS), and the balance restarts from the compiled Hertz + FASTSIM
    balance: 8 passes (the first evaluation counted) against 13, the same forces
    within the grids' path (measured 99 N of sum F_n = 191 kN, 2 N of F_x; 6 against
    11 passes before a patch's deepest point became the locus's minimum between
    its samples, geometry.patch_curvature.deepest_fraction).  The balance without
    the restart: RESTART_MISS = 0 (no restart), set here alone."""
    from railcontact.cases import balance as B
    assert B.RESTART_MISS == 0.5
    prev = rc.solve(_warm_start_case(197))
    after = rc.solve(_warm_start_case(198), warm_start=prev)
    monkeypatch.setattr(B, "RESTART_MISS", 0.0)
    before = rc.solve(_warm_start_case(198), warm_start=prev)
    for res in (before, after):
        assert res.converged and max(abs(v) for v in res.vertical_residual.values()) <= 1e-4
    assert after.balance.passes <= 8 and after.balance.passes + 4 <= before.balance.passes
    fn = [sum(p.normal.normal_force for p in r.patches) for r in (before, after)]
    fx = [sum(p.tangential.fx for p in r.patches) for r in (before, after)]
    assert abs(fn[1] - fn[0]) < 1e-3 * 1.2e5 and abs(fx[1] - fx[0]) < 5e-3 * 0.3 * 6e4


def test_a_cold_exact_case_starts_from_the_compiled_patches(monkeypatch):
    """A cold exact case starts at the compiled pass's balance with its patches (no
    first contact search), the multi-Hertzian estimate's search otherwise (here
    where hertz_estimate is made to return None, as where the pass does not meet
    the loads); both meet the loads with the same forces on the tread (sweep case
    100, 1.2 mm)."""
    from railcontact.cases import balance as B
    searches = []
    real = B.contact_search
    monkeypatch.setattr(B, "contact_search", lambda *a, **k: searches.append(1) or real(*a, **k))
    out = {}
    for flag in (True, False):
        searches.clear()
        if not flag:
            monkeypatch.setattr(B, "hertz_estimate", lambda *a, **k: None)
        res = rc.solve(_warm_start_case(100))
        assert res.converged
        out[flag] = (len(searches), res.balance.passes,
                     sum(p.normal.normal_force for p in res.patches),
                     sum(p.tangential.fx for p in res.patches))
    assert out[True][0] < out[True][1] and out[False][0] == out[False][1]
    assert out[True][2] == pytest.approx(out[False][2], rel=2e-4)
    assert out[True][3] == pytest.approx(out[False][3], abs=5e-3 * 0.3 * 6e4)


def test_a_warm_case_searches_from_its_neighbours_memo(monkeypatch):
    """A case's compiled searches start from the memo of its neighbour's last search
    (VerticalBalance.search) where the two poses are within MEMO_SHIFT and MEMO_YAW,
    else afresh (sweep cases 100, 101: 1.2 mm, 52 um apart; issue 30); its forces are
    those of a fresh memo's to the roll search's tolerance (measured 7e-9 of the
    load; on the 1000-case sweep 0.0013 % of Q at most warm, 1.6e-7 % cold:
    docs/tuning.md)."""
    from railcontact.cases import balance as B
    from railcontact.cases.compiled_case import MEMO_SHIFT
    prev = rc.solve(_warm_start_case(100), "exact", "exact")
    shift, yaw, memo = prev.balance.search
    assert shift == _warm_start_case(100).wheel_rail.lateral_shift and memo.shape == (15,)
    seeded = []
    real = B.search_memo
    monkeypatch.setattr(B, "search_memo",
                        lambda *a: seeded.append(len(a) == 5) or real(*a))
    case = _warm_start_case(101)
    assert abs(case.wheel_rail.lateral_shift - shift) <= MEMO_SHIFT
    warm = rc.solve(case, "exact", "exact", warm_start=prev)
    assert seeded[0]                    # the neighbour's memo held first
    prev.balance.search = None
    seeded.clear()
    fresh = rc.solve(case, "exact", "exact", warm_start=prev)
    assert not seeded[0]
    for res in (warm, fresh):
        assert res.converged
    q = sum(case.wheel_rail.loads.values())
    fn = [sum(p.normal.normal_force for p in r.patches) for r in (warm, fresh)]
    fy = [sum(p.tangential.fy for p in r.patches) for r in (warm, fresh)]
    assert abs(fn[0] - fn[1]) <= 1e-6 * q and abs(fy[0] - fy[1]) <= 1e-6 * 0.3 * q
