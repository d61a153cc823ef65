"""railcontact.cases.keys: a case's keys read by dotted name, checked once."""

import math

import pytest

from railcontact.cases.keys import CaseKeys
from railcontact.core.errors import CaseFileError


def test_get_by_dotted_key_and_default():
    keys = CaseKeys({"wheelset": {"yaw": 0.002, "side": "left"}})
    assert keys.get("wheelset.yaw") == 0.002
    assert keys.get("wheelset.roll", 0.5) == 0.5
    assert keys.get("wheelset.side.more") is None       # through a non-table


@pytest.mark.parametrize("value, message", [
    ("3 mm", "wheelset.lateral_shift = '3 mm': expected a number in m"),
    (math.nan, "wheelset.lateral_shift = nan: expected a number in m"),
    (True, "wheelset.lateral_shift = True: expected a number in m"),
    (0.2, "wheelset.lateral_shift = 0.2: expected a value in [-0.05, 0.05] m"),
])
def test_number_names_key_value_and_range(value, message):
    keys = CaseKeys({"wheelset": {"lateral_shift": value}})
    with pytest.raises(CaseFileError) as err:
        keys.number("wheelset.lateral_shift", 0.0, -0.05, 0.05, "m")
    assert str(err.value) == message


def test_number_default_and_missing():
    keys = CaseKeys({})
    assert keys.number("wheel.nominal_radius", 0.46, 0.1, 1.5, "m") == 0.46
    with pytest.raises(CaseFileError, match="bodies.normal_force: missing; expected a number in N"):
        keys.number("bodies.normal_force", None, 0.0, 1e8, "N")


def test_wheel_loads_one_or_per_side():
    assert CaseKeys({"wheelset": {"vertical_force": 5e4}}).wheel_loads() == {
        "left": 5e4, "right": 5e4}
    assert CaseKeys({"wheelset": {"vertical_force": [4e4, 6e4]}}).wheel_loads() == {
        "left": 4e4, "right": 6e4}
    assert CaseKeys({}).wheel_loads() == {"left": 70e3, "right": 70e3}
    for bad in ([1e4], -5.0, [1e4, "x"]):
        with pytest.raises(CaseFileError, match="wheelset.vertical_force"):
            CaseKeys({"wheelset": {"vertical_force": bad}}).wheel_loads()


def test_profile_options_and_units():
    assert CaseKeys({"wheel": {"profile": "S1002"}}).profile_options("wheel") == (None, "auto")
    options, units = CaseKeys({"rail": {"mirror_y": True, "units": "mm"}}).profile_options("rail")
    assert units == "mm" and options is not None
    with pytest.raises(CaseFileError, match="rail.units = 'inch': expected 'auto', 'mm' or 'm'"):
        CaseKeys({"rail": {"units": "inch"}}).profile_options("rail")
