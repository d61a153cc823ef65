"""railcontact.cases.balance: the vertical balance of a wheel-rail case, and the
contact at a prescribed position."""

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
