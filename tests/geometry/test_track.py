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


def test_contact_gauge_point_on_a_straight_gauge_face():
    """CONTACT's gauge point (contact_gauge_point) where the gauge face is straight:
    the crossing of the gauge height is exact on any interpolation, so both rules
    give the closed form y = y_top - (h_g - z_0) / tan(alpha) of a face of
    inclination alpha."""
    from railcontact.geometry.track import _gauge_point, contact_gauge_point
    from railcontact.profiles import Profile
    a = math.radians(70.0)
    yh = np.linspace(-0.03, 0.03, 121)
    zh = 0.004 * (yh / 0.03) ** 2                     # head: top at y = 0, z = 0
    yf = -0.03 - np.arange(1, 41) * 0.5e-3 * math.cos(a)
    zf = 0.004 + np.arange(1, 41) * 0.5e-3 * math.sin(a)
    rail = Profile(np.concatenate((yf[::-1], yh)), np.concatenate((zf[::-1], zh)), "rail")
    expect = -0.03 - (0.014 - 0.004) / math.tan(a)
    assert contact_gauge_point(rail, 0.014) == pytest.approx(expect, abs=1e-12)
    assert _gauge_point(rail, 0.014) == pytest.approx(expect, abs=1e-9)


def test_contact_gauge_point_of_the_manchester_rail(refdir):
    """UIC60 1:40 of the Manchester benchmark (points some 0.2 mm apart on the
    gauge face): CONTACT's rule (the spline along the chord length) puts the gauge
    point 14 mm below the top at y = -43.03256 mm, railcontact's z(y) spline 0.32 um
    further out; that lateral offset was the 0.7 um in z_ws of the flange cases of
    the 10 kN sweep (tests/test_exact_wheel_rail.py)."""
    from railcontact.geometry.track import _gauge_point, contact_gauge_point
    from railcontact.profiles import get_profile
    rail = get_profile(str(refdir / "profiles" / "MBench_UIC60_v3.prr"), "rail")
    assert contact_gauge_point(rail, 0.014) == pytest.approx(-43.0325577e-3, abs=1e-10)
    assert (_gauge_point(rail, 0.014) - contact_gauge_point(rail, 0.014)) \
        == pytest.approx(-0.32e-6, abs=0.01e-6)


def test_a_track_refuses_a_change_after_it_is_built():
    """A Track is not changed after it is built (the compiled search keeps its pass
    profiles by the track's identity, so a changed gauge kept the old rails'
    places): assigning raises InputError naming the attribute and the way out,
    dataclasses.replace, whose track is placed and searched afresh (before: the
    assignment was taken, the offsets and the search's profiles stayed the old
    track's)."""
    import dataclasses
    from railcontact.geometry import find_contact
    rail = rail_profile("60E1", math.atan(1 / 40))
    tr = Track(rail)
    ws = Wheelset(s1002())
    d = {"left": 6e-5, "right": 9e-5}
    a = find_contact(ws, tr, 1e-3, 0.0, interpenetration=d)
    with pytest.raises(InputError, match=r"Track\.gauge = 1\.43.*dataclasses\.replace"):
        tr.gauge = 1.43
    with pytest.raises(InputError, match=r"Track\.rail_left"):
        tr.rail_left = rail
    with pytest.raises(InputError, match=r"del Track\.gauge"):
        del tr.gauge
    assert tr.gauge == 1.435 and tr.rail_offset("left") + tr.gauge_point(rail) == \
        pytest.approx(1.435 / 2, abs=1e-12)
    new = dataclasses.replace(tr, gauge=1.43)
    assert new.rail_offset("left") + new.gauge_point(rail) == pytest.approx(1.43 / 2, abs=1e-12)
    b = find_contact(ws, new, 1e-3, 0.0, interpenetration=d)
    c = find_contact(Wheelset(s1002()), Track(rail, gauge=1.43), 1e-3, 0.0, interpenetration=d)
    assert b.pose == c.pose and b.pose != a.pose
    assert [p.approach for p in b.patches] == [p.approach for p in c.patches]


def test_a_tracks_rail_offsets_are_read_only():
    """The rail offsets a Track is built with are placed when it is built, so the
    mapping it keeps refuses a change (before: ``track.rail_offsets["left"] = 0.8``
    was taken and ignored, the track kept 0.75), the caller's dict changed later
    leaves it as built, and a copy, deepcopy or pickle keeps both."""
    import copy
    import pickle
    rail = rail_profile("60E1", math.atan(1 / 40))
    given = {"left": 0.75, "right": 0.75}
    tr = Track(rail, rail_offsets=given)
    with pytest.raises(TypeError):
        tr.rail_offsets["left"] = 0.80
    given["left"] = 0.80
    assert tr.rail_offsets["left"] == 0.75 == tr.rail_offset("left")
    for other in (copy.deepcopy(tr), pickle.loads(pickle.dumps(tr)), copy.copy(tr)):
        assert other.rail_offsets["left"] == 0.75 == other.rail_offset("left")
        with pytest.raises(TypeError):
            other.rail_offsets["left"] = 0.80
        with pytest.raises(InputError):
            other.gauge = 1.43
