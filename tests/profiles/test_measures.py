"""Standard wheel measures (railcontact.profiles.measures): flange height, flange
thickness and qR of S1002 against the nominal values (REFERENCES.md: 28 mm,
32.5 mm, 10.79 mm)."""

import numpy as np
import pytest

from railcontact.core.errors import ProfileError
from railcontact.profiles import rail_profile, s1002, wheel_measures
from railcontact.profiles.profile import Profile


def test_s1002_nominal_measures():
    m = wheel_measures(s1002())
    assert m["flange_height"] == pytest.approx(28.0e-3, abs=2e-6)
    assert m["flange_thickness"] == pytest.approx(32.5e-3, abs=5e-6)
    assert m["qR"] == pytest.approx(10.8e-3, abs=0.02e-3)
    assert m["flange_tip_y"] == pytest.approx(-55e-3, abs=0.01e-3)


def test_flange_back_and_qr_by_definition():
    m = wheel_measures(s1002(), flange_back=-60e-3)
    # Sd from a flange back 10 mm further out is 10 mm smaller
    assert m["flange_thickness"] == pytest.approx(22.5e-3, abs=5e-6)
    # qR between F = 10 mm (S = -37.50) and F = 26 mm (S = -48.29), REFERENCES.md
    assert m["qR"] == pytest.approx(48.29e-3 - 37.50e-3, abs=0.01e-3)


def test_measures_refuse_rails_and_flangeless_wheels():
    with pytest.raises(ProfileError, match="rail profile"):
        wheel_measures(rail_profile("60E1"))
    y = np.linspace(-0.07, 0.06, 131)
    flat = Profile(y, 0.005 * np.abs(y), kind="wheel", name="flat")
    with pytest.raises(ProfileError, match="no flange"):
        wheel_measures(flat)
