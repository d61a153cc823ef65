"""railcontact.cases.solve: one case solved, cold or warm-started from a neighbour."""

import dataclasses
import math

import pytest

import railcontact as rc
import railcontact.cases.solve as case_solve
from railcontact.cases.results import vertical_force_on_rail


def _case(shift):
    return rc.case_from_dict({"wheel": {"profile": "S1002"}, "rail": {"profile": "60E1"},
                              "wheelset": {"lateral_shift": shift, "side": "both",
                                           "vertical_force": [50e3, 90e3]}})


@pytest.fixture(scope="module")
def neighbour():
    return case_solve.solve(_case(0.002))


def test_warm_start_gives_the_cold_result(neighbour):
    case = _case(0.0025)
    warm = case_solve.solve(case, warm_start=neighbour)
    cold = case_solve.solve(case)
    assert warm.converged and cold.converged
    for res in (warm, cold):
        for side, load in (("left", 50e3), ("right", 90e3)):
            fz = sum(p.normal.normal_force * math.cos(p.geometry.contact_angle)
                     - p.tangential.fy * math.sin(p.geometry.contact_angle)
                     for p in res.patches if p.geometry.side == side)
            assert fz == pytest.approx(load, rel=case.force_tolerance)
    # both meet the balance to the force tolerance, so they agree to twice that
    for w, c in zip(warm.patches, cold.patches):
        assert w.geometry.side == c.geometry.side
        assert w.normal.normal_force == pytest.approx(c.normal.normal_force,
                                                      rel=2 * case.force_tolerance)
    assert warm.pose.lateral_shift == cold.pose.lateral_shift == 0.0025


def test_an_unconverged_warm_start_is_solved_again_cold(neighbour, monkeypatch):
    calls = []
    real = case_solve._solve

    def spy(case, normal, tangential, warm_start, options=None):
        calls.append(warm_start is not None)
        res = real(case, normal, tangential, warm_start, options)
        if warm_start is not None:            # as if the warm-started balance had failed
            res.balance = dataclasses.replace(res.balance, converged=False)
        return res

    monkeypatch.setattr(case_solve, "_solve", spy)
    res = case_solve.solve(_case(0.0025), warm_start=neighbour)
    assert calls == [True, False] and res.converged and res.cpu_time > 0


def test_vertical_force_on_rail_matches_the_load(neighbour):
    for side, load in (("left", 50e3), ("right", 90e3)):
        assert vertical_force_on_rail(neighbour.patches, side) == pytest.approx(load, rel=2e-4)
