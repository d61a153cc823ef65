"""Built-in profiles by name and name-or-path resolution (railcontact.profiles.library)."""

import math

import numpy as np
import pytest

from railcontact.core.errors import ProfileError
from railcontact.profiles import rail_profile, s1002
from railcontact.profiles.library import builtin_names, get_profile


def test_builtin_names():
    names = builtin_names()
    assert names["wheel"] == ("S1002",)
    assert {"60E1", "54E1", "UIC60"} <= set(names["rail"])


def test_builtin_rails_are_canted_1_in_40_by_default():
    w = get_profile("s1002", "wheel")
    assert np.array_equal(w.y, s1002().y) and np.array_equal(w.z, s1002().z)
    r = get_profile("60e1", "rail")
    ref = rail_profile("60E1", math.atan(1 / 40))
    assert np.array_equal(r.y, ref.y) and np.array_equal(r.z, ref.z)
    flat = get_profile("60E1", "rail", inclination=0.0)
    assert not np.array_equal(flat.z, r.z)
    assert float(np.min(flat.z)) == pytest.approx(0.0, abs=1e-9)


def test_files_relative_to_the_case_and_checked_for_kind(refdir):
    w = get_profile("profiles/MBench_S1002_v3.prw", "wheel", base_dir=refdir)
    assert w.kind == "wheel" and w.y_min < -0.06 and w.y_max > 0.05
    again = get_profile(str(refdir / "profiles" / "MBench_S1002_v3.prw"), "wheel")
    assert again is w                                  # read once per file version
    r = get_profile("profiles/MBench_UIC60_v3.prr", "rail", base_dir=refdir, inclination=0.025)
    assert float(np.min(r.z)) == pytest.approx(0.0, abs=1e-9)    # origin at the top
    with pytest.raises(ProfileError, match="expected a rail profile"):
        get_profile(w, "rail")


def test_bad_names():
    with pytest.raises(ProfileError, match="neither a built-in name"):
        get_profile("S1003", "wheel")
    with pytest.raises(ProfileError, match="60E1"):
        get_profile("no_such_rail.prr", "rail")
    with pytest.raises(ProfileError, match="built in"):
        get_profile("60E1", "rail", options=object())


def test_builtin_profile_scaled_for_a_scaled_model():
    """A built-in profile takes the ``scale`` option alone (a 1:5 running gear on a
    roller rig): its coordinates times the scale; any other option is refused."""
    from railcontact.profiles.processing import ProfileOptions
    full = get_profile("60E1", "rail", inclination=0.025)
    small = get_profile("60E1", "rail", inclination=0.025, options=ProfileOptions(scale=0.2))
    assert small.y == pytest.approx(full.y * 0.2) and small.z == pytest.approx(full.z * 0.2)
    w = get_profile("S1002", "wheel", options=ProfileOptions(scale=0.2))
    assert w.y.min() == pytest.approx(0.2 * get_profile("S1002", "wheel").y.min())
    with pytest.raises(ProfileError, match="built in"):
        get_profile("S1002", "wheel", options=ProfileOptions(scale=0.2, mirror_y=True))
