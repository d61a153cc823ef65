"""railcontact.cases.bodies_setup: a case given by curvatures, parsed once."""

import dataclasses
import math

import pytest

from railcontact.cases.case import case_from_dict
from railcontact.core.errors import CaseFileError


def _bodies(radii, **extra):
    return case_from_dict({"bodies": {"radii": radii, "normal_force": 1e5, **extra.pop(
        "bodies", {})}, **extra}).bodies


def test_curvatures_and_values():
    b = _bodies({"wheel_rolling": 0.5, "rail_lateral": 0.3, "wheel_lateral": -0.6},
                bodies={"velocity": 20.0})
    A, B = b.curvatures
    assert A == pytest.approx(0.5 / 0.5) and B == pytest.approx(0.5 * (1 / 0.3 - 1 / 0.6))
    assert (b.normal_force, b.velocity, b.forces) == (1e5, 20.0, None)
    assert b.rolling_radius == 0.5
    assert b.smallest_radius("wheel_lateral", "rail_lateral") == pytest.approx(0.3)
    assert b.smallest_radius("rail_rolling") == math.inf         # flat: not given
    with pytest.raises(dataclasses.FrozenInstanceError):
        b.normal_force = 1.0


def test_prescribed_forces_and_defaults():
    b = _bodies({"wheel_rolling": 0.5, "rail_lateral": 0.3},
                force={"longitudinal": 3e3}, solver={"tangential": "fastsim"})
    assert b.forces == (3e3, 0.0) and b.velocity == 1.0
    assert math.isnan(_bodies({"rail_rolling": 0.5, "rail_lateral": 0.3}).rolling_radius)


@pytest.mark.parametrize("radii, extra, match", [
    ({"wheel_rolling": 0.0, "rail_lateral": 0.3}, {}, "bodies.radii.wheel_rolling = 0.0"),
    ({"wheel_rolling": 0.5, "rail_lateral": -0.3}, {},
     "relative curvatures A = 1, B = -1.667 1/m; expected both > 0"),
    ({"wheel_rolling": 0.5, "rail_lateral": 0.3}, {"force": {"lateral": 1e9}},
     "force.lateral = 1000000000.0: expected a value in \\[-1e\\+08, 1e\\+08\\] N"),
    ({"wheel_rolling": 0.5, "rail_lateral": 0.3}, {"bodies": {"velocity": -1.0}},
     "bodies.velocity = -1.0"),
])
def test_bad_bodies_named(radii, extra, match):
    with pytest.raises(CaseFileError, match=match):
        _bodies(radii, **extra)
