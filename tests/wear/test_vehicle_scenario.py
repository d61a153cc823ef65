"""Validation helpers of the closed-loop wear scenario
(railcontact.wear.vehicle_scenario); the whole scenario is exercised in
test_closed_loop.py."""

from types import SimpleNamespace

import pytest

from railcontact.core.errors import CaseFileError, InputError
from railcontact.wear.vehicle_scenario import apply_wear_settings, is_vehicle_scenario, number


def test_number_checks_type_and_range():
    assert number({"steps": 3}, "wear", "steps", None, 1, 10) == 3.0
    assert number({}, "wear", "steps", 5, 1, 10) == 5.0
    for bad in (0, 11, True, "3", None):
        with pytest.raises(CaseFileError, match=r"wear.steps = .*expected a value in \[1, 10\]"):
            number({"steps": bad}, "wear", "steps", None, 1, 10)


def target():
    return SimpleNamespace(law="frictional-power", parameters={}, body="wheel",
                           scheduler="sync", steps=1, max_depth_per_step=1e-4)


def test_wear_settings_applied_and_checked():
    t = target()
    apply_wear_settings(t, {"law": "archard", "parameters": {"hardness": 3e9}, "body": "both",
                            "steps": 12.0, "max_depth_per_step": 5e-5})
    assert (t.law, t.body, t.steps, t.max_depth_per_step) == ("archard", "both", 12, 5e-5)
    assert isinstance(t.steps, int) and t.parameters == {"hardness": 3e9}
    with pytest.raises(CaseFileError, match="wear.body"):
        apply_wear_settings(target(), {"body": "axle"})
    with pytest.raises(CaseFileError, match="wear.max_depth_per_step"):
        apply_wear_settings(target(), {"max_depth_per_step": 0.1})
    with pytest.raises(InputError, match="archard hardness"):
        apply_wear_settings(target(), {"law": "archard", "parameters": {"hardness": -1.0}})


def test_closed_loop_scenarios_are_recognised():
    assert is_vehicle_scenario({"vehicle": {}, "wear": {}})
    assert is_vehicle_scenario({"route": [{}]})
    assert not is_vehicle_scenario({"wheel": {}, "condition": [{}]})


def test_seed001_study_example_holds_the_papers_cases():
    """examples/seed001_study.toml: Table 3 of Tao et al. (CM2015) -- tangent at 90 km/h,
    R400/R600/R1000 with 120/120/76 mm of cant at 60/80/80 km/h -- on AAR class 6
    irregularities, friction 0.3, r0 = 420 mm, back-to-back 1353 mm, USFD wear."""
    import math
    from pathlib import Path

    from railcontact.inputs import load_wear_scenario
    sc = load_wear_scenario(Path(__file__).resolve().parents[2] / "examples" /
                            "seed001_study.toml")
    table3 = {"tangent": (math.inf, 0.0, 90.0), "R400": (400.0, 0.120, 60.0),
              "R600": (600.0, 0.120, 80.0), "R1000": (1000.0, 0.076, 80.0)}
    assert [r.name for r in sc.routes] == list(table3)
    for r in sc.routes:
        radius, cant, kmh = table3[r.name]
        assert r.speed * 3.6 == pytest.approx(kmh, rel=1e-4)
        assert float(r.route.curvature.max()) == pytest.approx(1 / radius, abs=1e-12)
        assert float(r.route.cant.max()) == pytest.approx(math.asin(cant / 1.5), abs=1e-12)
        assert r.route.irregularities.source.startswith("AAR-6")
        assert r.friction == 0.3
    assert sc.case.wheel_rail.flange_back_distance == pytest.approx(1.353)
