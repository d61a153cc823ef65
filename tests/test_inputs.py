"""railcontact.inputs: input files read into typed configurations where they enter."""

import dataclasses

import pytest

from railcontact.core.errors import CaseFileError
from railcontact.dynamics.scenario import DynamicsScenario
from railcontact.inputs import load_dynamics_scenario

SCENARIO = """
title = "short"
[wheel]
profile = "S1002"
[rail]
profile = "60E1"
[friction]
coefficient = 0.25
[vehicle]
model = "bogie"
[[route.segment]]
type = "tangent"
length = 50.0
[simulation]
velocity = 25.0
duration = 0.5
tangential = "polach"
fastsim_grid = [10, 8]
history_wheelset = 2
"""


def test_dynamics_scenario_typed_and_frozen(tmp_path):
    p = tmp_path / "s.toml"
    p.write_text(SCENARIO)
    sc = load_dynamics_scenario(p)
    assert isinstance(sc, DynamicsScenario)
    assert (sc.title, sc.velocity, sc.duration, sc.tangential) == ("short", 25.0, 0.5, "polach")
    assert sc.fastsim_grid == (10, 8) and sc.history_wheelset == 2 and sc.friction == 0.25
    assert len(sc.model.wheelsets) == 2 and sc.wheelset.wheel_right.name.upper() == "S1002"
    # the route covers the run and the vehicle's length; defaults are SI
    assert sc.route.length >= 25.0 * 0.5 and sc.table_step == 2e-4
    with pytest.raises(dataclasses.FrozenInstanceError):
        sc.velocity = 30.0


@pytest.mark.parametrize("edit, message", [
    (("velocity = 25.0", "velocity = 25.0\ncolour = 1"), "unknown key(s) simulation.['colour']"),
    (("history_wheelset = 2", "history_wheelset = 3"),
     "simulation.history_wheelset = 3: expected 1 to 2"),
    (('profile = "60E1"', 'profile = "60E1"\ninclination = "steep"'), "rail.inclination"),
    (("coefficient = 0.25", "coefficient = -1.0"), "friction.coefficient = -1.0"),
])
def test_bad_scenario_named(tmp_path, edit, message):
    p = tmp_path / "s.toml"
    p.write_text(SCENARIO.replace(*edit))
    with pytest.raises(CaseFileError) as err:
        load_dynamics_scenario(p)
    assert message in str(err.value)


def test_missing_file_named(tmp_path):
    with pytest.raises(CaseFileError, match="dynamics scenario .*nothere.toml' does not exist"):
        load_dynamics_scenario(tmp_path / "nothere.toml")
