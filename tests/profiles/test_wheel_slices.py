"""CONTACT's wheel slices (``.slcw``): the wheel flat of ``wheelflat.inp``
(``S1002_flat.slcw``, 258 slices) read, and its radial deviation from an intact
slice against the user guide's description (the flat in theta_wc = [0.486,
0.812] rad, centred at 0.649 rad)."""

import math

import numpy as np
import pytest

from railcontact.core.errors import ProfileError
from railcontact.profiles.wheel_slices import WheelSlices, read_wheel_slices


@pytest.fixture(scope="module")
def flat(testbank):
    return read_wheel_slices(testbank / "examples_basic" / "S1002_flat.slcw", units="mm")


def test_read(flat):
    assert len(flat) == 258
    assert flat.theta[0] == pytest.approx(-3.0995) and flat.theta[-1] == pytest.approx(3.1224)
    assert all(p.kind == "wheel" for p in flat.profiles)


def test_the_flat_where_the_user_guide_puts_it(flat):
    """Slices deviating by more than 20 um from the slice at theta = 0 lie in
    [0.4898, 0.8122] rad (the guide: [0.486, 0.812]); the deepest, 1.40 mm, at
    0.6469 rad (the guide's centre 0.649); nowhere above the intact profile by
    more than 0.05 mm."""
    ref = flat.profiles[int(np.argmin(np.abs(flat.theta)))]
    y = np.linspace(-0.03, 0.04, 141)
    dev = flat.heights(y) - ref.z_at(y)[None, :]
    low = np.nanmin(dev, axis=1)
    k = np.flatnonzero(low < -2e-5)
    assert flat.theta[k[0]] >= 0.486 and flat.theta[k[-1]] <= 0.8125
    assert flat.theta[np.argmin(low)] == pytest.approx(0.649, abs=0.005)
    assert low.min() == pytest.approx(-1.40e-3, abs=0.01e-3)
    assert np.nanmax(dev) < 5e-5


def test_radial_deviation_rules(flat):
    """Linear between slices, periodic in 2 pi, constant beyond the slices."""
    ref = flat.profiles[int(np.argmin(np.abs(flat.theta)))]
    k = int(np.argmin(np.abs(flat.theta - 0.649)))
    t0, t1 = flat.theta[k], flat.theta[k + 1]
    y = np.full(3, 0.005)
    d = flat.radial_deviation(np.array([t0, t1, 0.5 * (t0 + t1)]), y, ref)
    assert d[2] == pytest.approx(0.5 * (d[0] + d[1]), rel=1e-12)
    assert flat.radial_deviation(t0 + 2 * math.pi, 0.005, ref) == pytest.approx(d[0], rel=1e-12)
    # beyond the last slice (3.1224 rad) up to pi: the last slice's profile
    last = flat.radial_deviation(3.14, 0.005, ref)
    assert last == pytest.approx(float(flat.profiles[-1].z_at(0.005) - ref.z_at(0.005)),
                                 abs=1e-15)


def test_bad_slices(flat, tmp_path):
    with pytest.raises(ProfileError, match="increase"):
        WheelSlices(np.array([0.1, 0.0]), flat.profiles[:2])
    f = tmp_path / "w.slcw"
    f.write_text("0 1\n2\n2 0 0\n1\n0.0 'a.txt'\n0.1 'b.txt'\n")
    with pytest.raises(ProfileError, match="NFEAT"):
        read_wheel_slices(f)
