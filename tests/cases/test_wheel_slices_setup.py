"""``wheel.slices`` and ``wheelset.pitch`` of a wheel-rail case: the out-of-round
wheel built with the wheel's profile options, bad values named."""

import pytest

from railcontact.cases.case import case_from_dict
from railcontact.cases.wheel_rail_setup import ProfileSource
from railcontact.cases.wheel_slices_setup import out_of_round_wheel
from railcontact.core.errors import CaseFileError
from railcontact.profiles import get_profile


def test_out_of_round_wheel(testbank):
    ref = get_profile("S1002", "wheel")
    src = ProfileSource("S1002", units="mm")
    w = out_of_round_wheel(src, "S1002_flat.slcw", -0.6, ref, testbank / "examples_basic")
    assert len(w.slices) == 258 and w.pitch == -0.6 and w.reference is ref
    assert out_of_round_wheel(src, None, 0.0, ref, None) is None
    with pytest.raises(CaseFileError, match="wheel.slices"):
        out_of_round_wheel(src, "missing.slcw", 0.0, ref, testbank)


def test_keys_checked():
    raw = {"wheel": {"profile": "S1002", "slices": "flat.slcs"}, "rail": {"profile": "60E1"},
           "wheelset": {"pitch": 0.5}}
    with pytest.raises(CaseFileError, match=r"wheel.slices = .*\.slcw"):
        case_from_dict(raw)
    raw = {"wheel": {"profile": "S1002", "slices": "flat.slcw"}, "rail": {"profile": "60E1"},
           "wheelset": {"pitch": "a"}}
    with pytest.raises(CaseFileError, match="wheelset.pitch"):
        case_from_dict(raw)
