"""Wheelset and track placement (railcontact.geometry.track)."""

import math

import numpy as np
import pytest

from railcontact.core.errors import InputError, ProfileError
from railcontact.geometry import Track, Wheelset
from railcontact.geometry.track import rotation
from railcontact.profiles import rail_profile, s1002


def test_gauge_point_per_rail_and_gauge_height():
    """The rail's gauge point (computed once per profile and gauge height) lies where
    the profile is gauge_height below its top on the gauge side; a deeper gauge
    height gives a point further to the gauge side; the offsets place the gauge
    faces the gauge apart."""
    rail = rail_profile("60E1", math.atan(1 / 40))
    top = float(np.min(rail.z))
    for h in (0.014, 0.010):
        tr = Track(rail, gauge_height=h)
        g = tr.gauge_point(rail)
        assert float(rail.z_at(g)) == pytest.approx(top + h, abs=1e-12)
        assert tr.rail_offset("left") + g == pytest.approx(1.435 / 2, abs=1e-12)
    assert Track(rail, gauge_height=0.014).gauge_point(rail) < \
        Track(rail, gauge_height=0.010).gauge_point(rail)


def test_wheel_offset_and_rail_offsets_given():
    """S1002: the tape circle 1.360/2 + 0.070 = 0.750 m from the wheelset centre
    (docs/conventions.md); rails placed by given offsets stay there whatever the
    gauge."""
    assert Wheelset(s1002()).wheel_offset == pytest.approx(0.750, abs=1e-15)
    assert Wheelset(s1002(), flange_back_distance=1.353).wheel_offset == \
        pytest.approx(0.7465, abs=1e-15)
    rail = rail_profile("60E1", math.atan(1 / 40))
    tr = Track(rail, gauge=1.440, rail_offsets={"left": 0.75, "right": 0.752})
    assert (tr.rail_offset("left"), tr.rail_offset("right")) == (0.75, 0.752)
    wide = Track(rail, gauge=1.441)
    assert wide.rail_offset("right") - Track(rail).rail_offset("right") == \
        pytest.approx(0.003, abs=1e-12)


def test_rotation_follows_the_sign_conventions():
    """Positive yaw turns the front (+x) to the right (+y); positive roll turns the
    axle (+y) down (+z) on the right (docs/conventions.md); orthonormal."""
    Rm = rotation(0.1, -0.05)
    assert Rm @ Rm.T == pytest.approx(np.eye(3), abs=1e-15)
    assert np.linalg.det(Rm) == pytest.approx(1.0, abs=1e-15)
    assert rotation(0.1, 0.0)[:, 0] == pytest.approx([math.cos(0.1), math.sin(0.1), 0.0])
    assert rotation(0.0, 0.05)[:, 1] == pytest.approx([0.0, math.cos(0.05), math.sin(0.05)])


def test_bad_track_and_wheelset():
    rail = rail_profile("60E1")
    with pytest.raises(InputError, match="track.gauge"):
        Track(rail, gauge=14.35)
    with pytest.raises(InputError, match="gauge_height"):
        Track(rail, gauge_height=-0.01)
    with pytest.raises(InputError, match="rail_offsets"):
        Track(rail, rail_offsets={"left": 0.75})
    with pytest.raises(ProfileError, match="wheel profile"):
        Track(s1002())
    with pytest.raises(ProfileError, match="rail profile"):
        Wheelset(rail)
    with pytest.raises(InputError, match="nominal_radius"):
        Wheelset(s1002(), nominal_radius=460.0)
