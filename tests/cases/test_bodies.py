"""railcontact.cases.bodies: a wheel-rail case's wheelset and track, and the contact search."""

from pathlib import Path

import pytest

import railcontact as rc
from railcontact.cases.bodies import build_wheelset_track, contact_search, wheel_rail_setup
from railcontact.core.errors import CaseFileError

EX = Path(__file__).resolve().parents[2] / "examples"


def _case(shift, **wheelset):
    return rc.case_from_dict({"wheel": {"profile": "S1002"}, "rail": {"profile": "60E1"},
                              "wheelset": {"lateral_shift": shift, **wheelset}})


def test_a_bodies_case_has_no_wheelset():
    with pytest.raises(CaseFileError, match="a bodies case has no wheelset on a track"):
        wheel_rail_setup(rc.load_case(EX / "bodies.toml"))


def test_wheelset_and_track_from_the_case():
    ws, tr = build_wheelset_track(rc.load_case(EX / "wheel_rail.toml"))
    assert ws.nominal_radius == 0.46 and ws.flange_back_distance == 1.360
    assert tr.gauge == 1.435 and tr.gauge_height == 0.014
    assert ws.wheel_right.kind == "wheel" and tr.rail_right.kind == "rail"


def test_centred_wheelset_is_symmetric():
    c = contact_search(_case(0.0))
    left, right = sorted(c.patches, key=lambda p: p.side)
    assert (left.side, right.side) == ("left", "right")
    assert c.pose.roll == pytest.approx(0.0, abs=1e-12)
    assert left.rolling_radius == pytest.approx(right.rolling_radius, rel=1e-12)
    assert left.contact_angle == pytest.approx(-right.contact_angle, rel=1e-12)
    assert left.y_rail == pytest.approx(right.y_rail, abs=1e-12)


def test_shifted_wheelset_rolls_on_unequal_radii():
    """A shift to the right puts the right wheel on a larger radius (conicity)."""
    c = contact_search(_case(0.004))
    r = {p.side: p.rolling_radius for p in c.patches}
    assert r["right"] > r["left"] and c.pose.roll != 0.0
    assert c.pose.lateral_shift == 0.004
