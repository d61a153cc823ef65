"""railcontact.cases.surface_setup: which cases need rail surfaces, and their keys checked
before any file is read."""

import pytest

from railcontact.cases.case import case_from_dict
from railcontact.cases.surface_setup import check_surface_case, is_surface_case
from railcontact.core.errors import CaseFileError

WHEEL = {"profile": "S1002"}
SLICED = {"slices": "x.slcs", "lateral_position": 0.75}


def _check(raw):
    """The case checked: where case_from_dict checks it already, its error comes first."""
    check_surface_case(case_from_dict(raw))


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
    ({"rail": SLICED, "wheelset": {"roll": 0.5}}, "roll"),
])
def test_surface_key_errors(change, match):
    with pytest.raises(CaseFileError, match=match):
        _check({"wheel": WHEEL, **change})


def test_a_good_surface_case_passes():
    _check({"wheel": WHEEL, "rails": [dict(SLICED, lateral_range=[-0.02, 0.02])],
            "solver": {"rigid_slip": "surfaces", "tangential": "exact", "normal": "exact"},
            "wheelset": {"side": "left", "vertical_position": 1e-3}})
