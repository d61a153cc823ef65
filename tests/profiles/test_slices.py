"""Rail slices (railcontact.profiles.slices): CONTACT's slices files, their errors,
writing them back, and the artificial crossing."""

import numpy as np
import pytest

from railcontact.core.errors import ProfileError
from railcontact.profiles.io import read_profile
from railcontact.profiles.slices import (RailSlices, artificial_crossing, read_slices,
                                         slices_from_list, write_slices)


def test_read_slices_files(testbank):
    prof = testbank / "profiles"
    nose = read_slices(prof / "cross_nose.slcs")
    assert len(nose) == 21 and nose.s[0] == pytest.approx(-0.1) and nose.s[-1] == pytest.approx(0.1)
    assert nose.features.shape == (21, 5)
    assert nose.features[0, 1] == pytest.approx(33.0541e-3)
    assert all(p.kind == "rail" for p in nose.profiles)
    uk = read_slices(prof / "uk_crossing.slcs")              # u in m, U_SCALE 1000 mm/m
    assert len(uk) == 148 and uk.features is None
    assert uk.s[0] == pytest.approx(-75.0) and uk.s[70] == pytest.approx(0.24836)
    # the profiles of the UK crossing are in metres, those of the nose in mm: both read
    assert 0.1 < uk.profiles[69].y_max - uk.profiles[69].y_min < 0.2
    assert 0.04 < nose.profiles[0].y_max - nose.profiles[0].y_min < 0.06


def test_slices_errors(tmp_path, testbank):
    with pytest.raises(ProfileError, match="does not exist"):
        read_slices(tmp_path / "none.slcs")
    f = tmp_path / "bad.slcs"
    f.write_text("0 1 U_OFFSET U_SCALE\n1 NSLC\n0 NFEAT\n1 U_INTPOL\n0 'a.prr'\n")
    with pytest.raises(ProfileError, match="NSLC = 1"):
        read_slices(f)
    f.write_text("0 1\n2\n0\n1 1 U_INTPOL PERTURB\n0 'a.prr'\n1 'b.prr'\n")
    with pytest.raises(ProfileError, match="perturbations"):
        read_slices(f)
    p = read_profile(testbank / "profiles" / "cross_nose" / "nose_1.prr")
    with pytest.raises(ProfileError, match="increase"):
        RailSlices(np.array([0.0, 0.0]), (p, p))
    with pytest.raises(ProfileError, match="slice 1 .* has no part"):
        RailSlices(np.array([0.0, 1.0]), (p, p), features=np.array([[0, -1, 0.05], [0, 0.01, 0.05]]))
    with pytest.raises(ProfileError, match="NaN"):
        RailSlices(np.array([0.0, 1.0]), (p, p), features=np.array([[0, np.nan], [0, 0.05]]))
    with pytest.raises(ProfileError, match="expected a list"):
        slices_from_list([{"s": 0.0, "profile": p}])
    with pytest.raises(ProfileError, match="position in m"):
        slices_from_list([{"s": "x", "profile": p}, {"s": 1.0, "profile": p}])


def test_artificial_crossing_geometry():
    """The nose's crown starts 6 mm below the running level at the tip and rises
    1:60 to 2 mm below it (reached at s = 0.24 m); its width grows at 1:9."""
    nose, wing = artificial_crossing(length=0.5, n=11)
    assert len(nose) == len(wing) == 11 and nose.s[0] == pytest.approx(-0.05)
    top = np.array([float(np.min(p.z)) for p in nose.profiles])
    drop = np.maximum(6e-3 - np.maximum(nose.s, 0.0) / 60, 2e-3)
    assert top == pytest.approx(drop, abs=1e-6)
    assert float(np.min(wing.profiles[0].z)) == pytest.approx(0.0, abs=1e-9)


def test_written_slices_read_back(tmp_path):
    nose, _ = artificial_crossing(length=0.2, n=5)
    path = write_slices(nose, tmp_path / "nose.slcs")
    back = read_slices(path)
    assert back.s == pytest.approx(nose.s, abs=1e-9)
    y = np.linspace(-0.03, -0.02, 7)
    for a, b in zip(nose.profiles, back.profiles):
        assert b.kind == "rail"
        assert b.z_at(y) == pytest.approx(a.z_at(y), abs=1e-6)
