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
