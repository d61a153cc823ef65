"""The wheel-rail keys of a case parsed once (railcontact.cases.wheel_rail_setup)."""

import dataclasses
import math
from pathlib import Path

import pytest

import railcontact as rc
from railcontact.cases.bodies import build_wheelset_track
from railcontact.core.errors import CaseFileError
from railcontact.profiles import s1002

EX = Path(__file__).resolve().parents[2] / "examples"


def test_example_parsed_into_typed_values():
    case = rc.load_case(EX / "wheel_rail.toml")
    s = case.wheel_rail
    assert (s.wheel.name, s.rail.name, s.rail.inclination) == ("S1002", "60E1", 0.025)
    assert (s.lateral_shift, s.yaw, s.roll, s.side) == (0.003, 0.0, None, "right")
    assert s.loads == {"left": 70e3, "right": 70e3}
    assert (s.gauge, s.gauge_height, s.flange_back_distance) == (1.435, 0.014, 1.360)
    assert s.separation_angle == pytest.approx(math.pi / 2)
    assert s.balanced_sides == ("left", "right")     # side only selects the reported patches
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.yaw = 0.1
    ws, tr = build_wheelset_track(case)
    assert ws.nominal_radius == 0.46 and tr.gauge == 1.435
    assert case.rules.locus == ws.locus == "lowest"
    assert build_wheelset_track(case.with_value("wheelset.locus", "contact"))[0].locus == \
        "contact"
    # a sweep's changed key is parsed again
    assert case.with_value("wheelset.yaw", 2e-3).wheel_rail.yaw == 2e-3


@pytest.mark.parametrize("key, value, match", [
    ("track.gauge", 1435.0, r"track.gauge = 1435.0: expected a value in \[0.1, 2\] m"),
    # the range the Track checks (before: 2.2 passed the case and failed building it)
    ("track.gauge", 2.2, r"track.gauge = 2.2: expected a value in \[0.1, 2\] m"),
    ("wheelset.flange_back_distance", 1360, "wheelset.flange_back_distance"),
    ("wheelset.lateral_shift", 3.0, "wheelset.lateral_shift"),
    ("wheelset.pitch_velocity", math.nan, "wheelset.pitch_velocity"),
    ("wheelset.side", "middle", "wheelset.side"),
    ("wheelset.locus", "highest", "wheelset.locus = 'highest': expected 'lowest'"),
])
def test_wrong_values_are_named(key, value, match):
    """Values in the wrong unit (mm for m) or out of range stop at reading."""
    case = rc.load_case(EX / "wheel_rail.toml")
    with pytest.raises(CaseFileError, match=match):
        case.with_value(key, value)


def test_profiles_given_as_objects():
    """A wear run hands its worn profiles to the case as Profile objects."""
    wheel = s1002()
    case = rc.case_from_dict({"wheel": {"profile": wheel}, "rail": {"profile": "60E1"}})
    assert case.wheel_rail.wheel.name is wheel
    ws, _ = build_wheelset_track(case)
    assert ws.wheel("right") is wheel


def test_bodies_case_has_no_wheelset():
    case = rc.load_case(EX / "bodies.toml")
    assert case.wheel_rail is None
    with pytest.raises(CaseFileError, match="no wheelset on a track"):
        build_wheelset_track(case)


def test_blanco_influence_keys():
    """``solver.influence = "blanco"`` with ``solver.influence_options`` (method,
    variant) on a conformal surface: Blanco's coefficients of the patches; the
    default is the half-space's; every wrong use is named."""
    from railcontact.geometry.conformal import ConformalInfluence
    case = rc.load_case(EX / "wheel_rail.toml")
    assert case.wheel_rail.influence is None
    conf = case.with_value("solver.contact_surface", "conformal")
    case = conf.with_value("solver.normal", "exact").with_value("solver.tangential", "exact")
    b = case.with_value("solver.influence", "blanco")
    assert b.wheel_rail.influence == ConformalInfluence("detailed", 3)
    fast = b.with_value("solver.influence_options", {"method": "fast", "variant": 3})
    assert fast.wheel_rail.influence == ConformalInfluence("fast", 3)
    for key, value, match in [
            ("solver.influence", "curved", r"solver.influence = 'curved': expected"),
            ("solver.influence_options", {"variant": 4},
             r"solver.influence_options: conformal influence variant 4: expected 3"),
            ("solver.influence_options", {"method": "slow"}, "method 'slow'"),
            ("solver.influence_options", {"order": 1}, r"keys \['order'\]")]:
        with pytest.raises(CaseFileError, match=match):
            (b if key != "solver.influence" else case).with_value(key, value)
    with pytest.raises(CaseFileError, match="expected solver.contact_surface = 'conformal'"):
        case.with_value("solver.contact_surface", "planar").with_value("solver.influence",
                                                                       "blanco")
    with pytest.raises(CaseFileError, match="with solver.influence = 'blanco'"):
        case.with_value("solver.influence_options", {"method": "fast"})
    with pytest.raises(CaseFileError, match="normal = 'exact', tangential = 'exact'"):
        b.with_value("solver.tangential", "fastsim")
