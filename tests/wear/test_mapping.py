"""From local wear to profile depth and the worn profile (railcontact.wear.mapping),
on hand-made grids and profiles."""

from types import SimpleNamespace

import numpy as np
import pytest

from railcontact.profiles.profile import Profile
from railcontact.wear.mapping import profile_depth, removed_area, strip_depth, wear_profile


def flat(kind, slope=0.0):
    y = np.linspace(-0.03, 0.03, 601)
    return Profile(y, slope * y, kind=kind, name=f"flat {kind}")


def test_strip_depth_sums_along_the_rolling_direction():
    rate = np.array([[1.0, 2.0], [3.0, 4.0], [0.0, 1.0]]) * 1e-9
    normal = SimpleNamespace(dx=2e-4)
    assert strip_depth(rate, normal) == pytest.approx([8e-13, 1.4e-12], rel=1e-12)


@pytest.mark.parametrize("side, sgn", [("right", 1.0), ("left", -1.0)])
def test_profile_depth_conserves_the_strip_integral(side, sgn):
    dy = 1e-4
    y = (np.arange(40) - 19.5) * dy
    d = 1e-6 * (1.0 + np.linspace(0.0, 1.0, 40))                # sloping strip depths
    normal = SimpleNamespace(y=y, dy=dy)
    prof = flat("rail")
    s_ref = float(prof.arc_length(0.005))
    geo = SimpleNamespace(y_rail=0.005, y_wheel=0.0, side=side)
    s = np.linspace(s_ref - 0.01, s_ref + 0.01, 1001)
    out = profile_depth(geo, normal, d, prof, "rail", s)
    assert np.trapezoid(out, s) == pytest.approx(d.sum() * dy, rel=1e-12)
    # the deeper end of the strips lies at s_ref + sgn y
    deep = s[np.argmax(out)]
    assert sgn * (deep - s_ref) == pytest.approx(y[-1], abs=2 * (s[1] - s[0]))
    assert out[np.abs(s - s_ref) > 2.5e-3].max() == 0.0


@pytest.mark.parametrize("body, dz", [("rail", 1.0), ("wheel", -1.0)])
def test_uniform_depth_on_a_flat_profile(body, dz):
    prof = flat(body)
    s = prof.arc_length(prof.y)
    depth = np.where(np.abs(prof.y) <= 0.01, 1e-4, 0.0)
    worn = wear_profile(prof, s, depth, body)
    # material is removed into the rail (z down) and towards the axle on the wheel
    assert float(worn.z_at(0.0)) == pytest.approx(dz * 1e-4, abs=1e-12)
    assert float(worn.z_at(0.02)) == pytest.approx(0.0, abs=1e-12)
    assert removed_area(prof, worn, body) == pytest.approx(2e-6, rel=5e-3)   # 20 mm x 0.1 mm


def test_depth_along_the_normal_of_an_inclined_profile():
    """On a face of slope 1 a depth w moves a point by w/sqrt(2) in y and z: the
    vertical cut loses w sqrt(2)."""
    prof = flat("rail", slope=1.0)
    s = prof.arc_length(prof.y)
    worn = wear_profile(prof, s, np.full(s.size, 1e-4), "rail")
    assert float(worn.z_at(0.0) - prof.z_at(0.0)) == pytest.approx(1e-4 * np.sqrt(2), rel=1e-6)
