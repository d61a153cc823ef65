"""railcontact.cases.surface_setup: which cases need rail surfaces, and their keys checked
and parsed once, before any file is read."""

import pytest

from railcontact.cases.case import case_from_dict
from railcontact.cases.surface_setup import RailSpec, SurfaceCaseSetup, is_surface_case
from railcontact.core.errors import CaseFileError

WHEEL = {"profile": "S1002"}
SLICED = {"slices": "x.slcs", "lateral_position": 0.75}


def _check(raw):
    """The case read: its surface keys are parsed where it is read."""
    return case_from_dict(raw).surfaces


@pytest.mark.parametrize("raw, surface", [
    ({"wheel": WHEEL, "rail": {"profile": "60E1"}}, False),
    ({"wheel": WHEEL, "rail": {"profile": "60E1", "inclination": 0.0}}, False),
    ({"wheel": WHEEL, "rail": {"profile": "60E1", "lateral_position": 0.75}}, True),
    ({"wheel": WHEEL, "rails": [SLICED]}, True),
    ({"wheel": WHEEL, "rail": {"profile": "60E1"}, "roller": {"radius": 0.5}}, True),
    ({"wheel": WHEEL, "rail": {"profile": "60E1"}, "wheelset": {"position": 0.1}}, True),
])
def test_is_surface_case(raw, surface):
    assert is_surface_case(case_from_dict(raw)) == surface


@pytest.mark.parametrize("change, match", [
    ({"rails": [SLICED], "rail": SLICED}, "either as \\[\\[rails\\]\\] or as \\[rail\\]"),
    ({"rails": []}, "one or more tables"),
    ({"rail": dict(SLICED, colour="red")}, "unknown key rail.colour"),
    ({"rails": [dict(SLICED, lateral_range=[0.01, -0.01])]},
     "rails\\[0\\].lateral_range = \\[0.01, -0.01\\]: expected \\[y_min, y_max\\]"),
    ({"rails": [SLICED, SLICED], "roller": {"radius": 0.5}}, "give one rail"),
    ({"rail": SLICED, "roller": {"angular_velocity": 1.0}}, "expected radius"),
    ({"rail": SLICED, "solver": {"rigid_slip": "surfaces", "tangential": "fastsim"}},
     "needs solver.tangential = 'exact'"),
    ({"rail": SLICED, "solver": {"rigid_slip": "wheel"}}, "rigid_slip"),
    ({"rail": SLICED, "wheelset": {"roll": 0.6}}, "roll"),
])
def test_surface_key_errors(change, match):
    with pytest.raises(CaseFileError, match=match):
        _check({"wheel": WHEEL, **change})


def test_a_good_surface_case_passes():
    _check({"wheel": WHEEL, "rails": [dict(SLICED, lateral_range=[-0.02, 0.02])],
            "solver": {"rigid_slip": "surfaces", "tangential": "exact", "normal": "exact"},
            "wheelset": {"side": "left", "vertical_position": 1e-3}})


def test_parsed_once_into_typed_values():
    raw = {"wheel": WHEEL, "rails": [dict(SLICED, name="nose", vertical_position=-1e-3),
                                     {"profile": "60E1", "inclination": 0.0}],
           "wheelset": {"side": "left", "vertical_force": [5e4, 6e4], "yaw": 0.01,
                        "position": 0.2}, "solver": {"search_length": 0.05}}
    s = _check(raw)
    assert isinstance(s, SurfaceCaseSetup) and s.side == "left" and s.load == 5e4
    assert (s.position, s.yaw, s.search_length, s.vertical_position) == (0.2, 0.01, 0.05, None)
    nose, plain = s.rails
    assert isinstance(nose, RailSpec) and nose.slices == "x.slcs" and nose.name == "nose"
    assert (nose.lateral_position, nose.vertical_position) == (0.75, -1e-3)
    assert plain.lateral_position is None and plain.profile.inclination == 0.0
    assert s.roller is None and s.pitch_velocity is None
    # the search's rules are the case's record (railcontact's by default)
    assert case_from_dict(raw).rules.contact_angle == "local"
    # a prescribed height replaces the load; a roller's speed defaults to rolling
    r = _check({"wheel": WHEEL, "rail": {"profile": "60E1"}, "roller": {"radius": 0.5},
                "wheelset": {"vertical_position": 1e-3}})
    assert r.load is None and r.vertical_position == 1e-3
    # rolling towards -x on rail surfaces: a negative speed
    assert _check({"wheel": WHEEL, "rail": SLICED, "wheelset": {"velocity": -2.0}}).velocity \
        == -2.0
    assert (r.roller.radius, r.roller.angular_velocity, r.roller.position) == (0.5, None, 0.0)
    assert r.roller.profile_deviation is None
    d = _check({"wheel": WHEEL, "rail": {"profile": "60E1"},
                "roller": {"radius": 0.5, "profile_deviation": [5e-4, 0.1]}})
    assert d.roller.profile_deviation == (5e-4, 0.1)
    for bad in ([0.1, 0.0], [0.0, 0.6], [0.0], [0.0, "x"]):
        with pytest.raises(CaseFileError, match="roller.profile_deviation = .*expected"):
            _check({"wheel": WHEEL, "rail": {"profile": "60E1"},
                    "roller": {"radius": 0.5, "profile_deviation": bad}})


@pytest.mark.parametrize("change, match", [
    ({"rail": dict(SLICED, lateral_position=3.0)},
     "rail.lateral_position = 3.0: expected a value in \\[-2, 2\\] m"),
    ({"rail": dict(SLICED, slice_spacing=-1.0)}, "rail.slice_spacing = -1.0"),
    ({"rail": dict(SLICED, units="inch")}, "rail.units = 'inch'"),
    ({"rail": dict(SLICED, slices=3)}, "rail.slices = 3: expected a .slcs file"),
    ({"rail": SLICED, "roller": {"radius": 0.5}}, "roller's profile is a rail profile"),
    ({"rail": SLICED, "wheelset": {"yaw": 0.7}}, "wheelset.yaw = 0.7"),
    ({"rail": SLICED, "wheelset": {"velocity": 0.0}}, "wheelset.velocity = 0.0: expected a "
                                                      "speed of at least 0.001"),
    ({"rail": SLICED, "wheelset": {"velocity": -300.0}}, "wheelset.velocity = -300"),
])
def test_values_checked_once_where_read(change, match):
    with pytest.raises(CaseFileError, match=match):
        _check({"wheel": WHEEL, **change})


def test_wheel_deviation_key():
    """``wheelset.wheel_deviation = [dx, dy, dz, roll, yaw, pitch]`` (CONTACT's DXWHL ..
    DPITCHW in m and rad) makes a surface case and is parsed into a tuple; a list of
    another length, or a displacement or an angle out of range, is an error."""
    raw = {"wheel": WHEEL, "rail": {"profile": "60E1"},
           "wheelset": {"wheel_deviation": [0.0, 1e-3, 0.0, 0.1, 0.0, 0.0]}}
    assert is_surface_case(case_from_dict(raw))
    s = _check(raw)
    assert s.wheel_deviation == (0.0, 1e-3, 0.0, 0.1, 0.0, 0.0)
    assert _check({"wheel": WHEEL, "rail": SLICED}).wheel_deviation is None
    for bad in ([0.0] * 5, [0.1, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0.6, 0], [0, 0, 0, "x", 0, 0]):
        with pytest.raises(CaseFileError, match="wheelset.wheel_deviation = .*expected"):
            _check({"wheel": WHEEL, "rail": {"profile": "60E1"},
                    "wheelset": {"wheel_deviation": bad}})
