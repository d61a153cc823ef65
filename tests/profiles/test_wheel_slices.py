"""CONTACT's wheel slices (``.slcw``): the wheel flat of ``wheelflat.inp``
(``S1002_flat.slcw``, 258 slices) read, and its radial deviation from an intact
slice against the user guide's description (the flat in theta_wc = [0.486,
0.812] rad, centred at 0.649 rad)."""

import math

import numpy as np
import pytest

from scipy.interpolate import BSpline

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
    """TH_INTPOL = 2: CONTACT's approximating spline along theta (the cubic B-spline
    with knots at the slices and their heights its control points, the end ones
    doubled); periodic in 2 pi, the end slices' profiles beyond them; linear
    between slices otherwise."""
    assert flat.approximating
    ref = flat.profiles[int(np.argmin(np.abs(flat.theta)))]
    k = int(np.argmin(np.abs(flat.theta - 0.649)))
    y = 0.005
    zs = np.array([float(p.z_at(y) - ref.z_at(y)) for p in flat.profiles])
    th = flat.theta
    spline = BSpline(np.r_[[th[0]] * 4, th[1:-1], [th[-1]] * 4], np.r_[zs[0], zs, zs[-1]], 3)
    t = np.linspace(th[k - 3], th[k + 3], 13)
    assert flat.radial_deviation(t, np.full(t.size, y), ref) == pytest.approx(spline(t),
                                                                             abs=1e-12)
    d = float(flat.radial_deviation(th[k], y, ref))
    z = zs[k - 1:k + 2]
    assert min(z) - 1e-9 <= d <= max(z) + 1e-9           # a smoothing, not an overshoot
    assert float(flat.radial_deviation(flat.theta[k] + 2 * math.pi, y, ref)) == \
        pytest.approx(d, rel=1e-12)
    last = float(flat.radial_deviation(3.14, y, ref))
    assert last == pytest.approx(float(flat.profiles[-1].z_at(y) - ref.z_at(y)), abs=1e-12)
    lin = WheelSlices(flat.theta, flat.profiles, "linear", approximating=False)
    t0, t1 = flat.theta[k], flat.theta[k + 1]
    d3 = lin.radial_deviation(np.array([t0, t1, 0.5 * (t0 + t1)]), np.full(3, y), ref)
    assert d3[0] == pytest.approx(z[1], rel=1e-12)
    assert d3[2] == pytest.approx(0.5 * (d3[0] + d3[1]), rel=1e-12)


def test_bad_slices(flat, tmp_path):
    with pytest.raises(ProfileError, match="increase"):
        WheelSlices(np.array([0.1, 0.0]), flat.profiles[:2])
    f = tmp_path / "w.slcw"
    f.write_text("0 1\n2\n2 0 0\n1\n0.0 'a.txt'\n0.1 'b.txt'\n")
    with pytest.raises(ProfileError, match="NFEAT"):
        read_wheel_slices(f)
