import math

import numpy as np
import pytest

from railcontact.core.errors import ProfileError
from railcontact.profiles import rail_profile, read_profile
from railcontact.profiles.rails import HEADS, head_points


@pytest.mark.parametrize("name, y1, z1, y2, z2, half14", [
    ("60E1", 10.228, 0.1744, 26.0265, 2.3025, 35.981),
    ("54E1", 10.012, 0.1671, 24.8635, 2.0649, 34.995),
    ("60E2", 11.889, 0.3537, 24.4565, 2.2582, 35.979),
])
def test_head_construction_derived_values(name, y1, z1, y2, z2, half14):
    p = rail_profile(name, inclination=0.0)
    assert p.z_at(y1 * 1e-3) * 1e3 == pytest.approx(z1, abs=2e-4)
    assert p.z_at(y2 * 1e-3) * 1e3 == pytest.approx(z2, abs=2e-4)
    # half-width 14 mm below the crown
    yy = np.linspace(0, p.y_max, 20000)
    i = np.flatnonzero(p.z_at(yy) <= 0.014)[-1]
    assert yy[i] * 1e3 == pytest.approx(half14, abs=0.01)


def test_60e2_flank_start():
    y, z = head_points(HEADS["60E2"], 0.01)
    # the flank starts at (35.9999, 14.3002) mm
    j = np.argmin(np.abs(z - 14.3002))
    assert y[j] == pytest.approx(35.9999, abs=2e-3)


def test_60e1_inclined_matches_manchester_file(refdir):
    rf = read_profile(refdir / "profiles" / "MBench_UIC60_v3.prr")
    r = rail_profile("60E1", math.atan(1 / 40))
    y = np.linspace(max(r.y_min, rf.y_min), min(r.y_max, rf.y_max), 20000)
    dn = (r.z_at(y) - rf.z_at(y)) / np.sqrt(1 + rf.slope(y) ** 2)
    crown = np.abs(y) <= 0.010
    assert np.nanmax(np.abs(dn[crown])) < 0.02e-3
    assert np.nanmax(np.abs(dn)) < 0.1e-3


def test_inclination_raises_field_side():
    up = rail_profile("60E1", 0.0)
    canted = rail_profile("60E1", math.atan(1 / 40))
    assert up.slope(0.0) == pytest.approx(0.0, abs=1e-9)
    assert canted.slope(0.0) == pytest.approx(0.0, abs=1e-9)   # origin at the top
    # the top moves towards the field side by about R300 * 1/40 = 7.5 mm
    assert canted.y_max - canted.y_min < up.y_max - up.y_min + 1e-3
    assert (up.y_max + up.y_min) / 2 - (canted.y_max + canted.y_min) / 2 > 5e-3


def test_inclination_1_in_20_gives_function():
    p = rail_profile("60E1", math.atan(1 / 20))
    assert np.all(np.diff(p.y) > 0)


def test_unknown_rail_and_bad_inclination():
    with pytest.raises(ProfileError, match="unknown"):
        rail_profile("XYZ")
    with pytest.raises(ProfileError, match="inclination"):
        rail_profile("60E1", 0.5)
