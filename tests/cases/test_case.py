"""railcontact.cases.case: case files parsed into a Case, their options and errors."""

import math
from pathlib import Path

import pytest

import railcontact as rc
from railcontact.core.errors import CaseFileError, UnknownModelError

EX = Path(__file__).resolve().parents[2] / "examples"


def test_api_errors():
    with pytest.raises(CaseFileError):
        rc.case_from_dict({"wheel": {"profile": "S1002"}})
    with pytest.raises(UnknownModelError):
        rc.solve(rc.load_case(EX / "bodies.toml"), normal="nope")


def test_per_wheel_loads():
    res = rc.solve(rc.case_from_dict({"wheel": {"profile": "S1002"}, "rail": {"profile": "60E1"},
                                      "wheelset": {"lateral_shift": 0.002,
                                                   "vertical_force": [50e3, 90e3]}}))
    for side, load in (("left", 50e3), ("right", 90e3)):
        fz = sum(p.normal.normal_force * math.cos(p.geometry.contact_angle)
                 - p.tangential.fy * math.sin(p.geometry.contact_angle)
                 for p in res.patches if p.geometry.side == side)
        assert fz == pytest.approx(load, rel=2e-4)
    with pytest.raises(CaseFileError, match="vertical_force"):
        rc.case_from_dict({"wheel": {"profile": "S1002"}, "rail": {"profile": "60E1"},
                           "wheelset": {"vertical_force": [1.0, 2.0, 3.0]}})


# ------------------------------------------------- CONTACT's options in case files
def _mbench_raw(refdir, **wheelset):
    prof = refdir / "profiles"
    return {"material": {"young_modulus": 2 * 82e9 * 1.28, "poisson_ratio": 0.28},
            "friction": {"coefficient": 0.3},
            "wheel": {"profile": str(prof / "MBench_S1002_v3.prw")},
            "rail": {"profile": str(prof / "MBench_UIC60_v3.prr"), "inclination": 0.0},
            "wheelset": {"vertical_force": 1e4, "velocity": 2.0, "side": "right", "roll": 0.0,
                         **wheelset},
            "solver": {"normal": "exact", "tangential": "exact",
                       "element_size": [2.5e-4, 2.5e-4]}}


def test_friction_varying_with_the_rail_inclination(refdir):
    """friction.variation (CONTACT's VARFRC = 1): each patch takes the coefficient
    at its rail surface's inclination, interpolated linearly, constant beyond."""
    from railcontact import case_from_dict, solve
    var = {"angle": [-0.5236, -0.3491], "coefficient": [0.2, 0.35]}
    for y, mu in ((2e-3, 0.35), (9e-3, 0.2)):       # tread, flange flank
        raw = _mbench_raw(refdir, lateral_shift=y)
        raw["friction"]["variation"] = var
        res = solve(case_from_dict(raw))
        (p,) = res.patches
        assert p.tangential.friction == mu
        assert abs(complex(p.tangential.fx, p.tangential.fy)) <= mu * p.normal.normal_force * 1.0001
    case = case_from_dict({**_mbench_raw(refdir), "friction": {"variation": var}})
    assert case.friction_at(-0.4363) == pytest.approx(0.275, abs=1e-3)
    for bad in ({"angle": [0.1, 0.0], "coefficient": [0.2, 0.3]},
                {"angle": [0.0], "coefficient": [0.2, 0.3]}, {"angles": [0.0]}):
        with pytest.raises(CaseFileError, match="friction.variation"):
            case_from_dict({**_mbench_raw(refdir), "friction": {"variation": bad}})


def test_vertical_position_prescribed(refdir):
    """wheelset.vertical_position (CONTACT's NORM = 0): at the height the force
    control found, the same patch and force (to the force tolerance)."""
    from railcontact import case_from_dict, solve
    force = solve(case_from_dict(_mbench_raw(refdir, lateral_shift=3e-3)))
    raw = _mbench_raw(refdir, lateral_shift=3e-3, vertical_position=force.pose.vertical)
    del raw["wheelset"]["vertical_force"]
    pos = solve(case_from_dict(raw))
    assert pos.balance is None and pos.pose.vertical == force.pose.vertical
    assert pos.patches[0].normal.normal_force == pytest.approx(
        force.patches[0].normal.normal_force, rel=2e-4)
    # raised by 1 mm the wheel does not reach the rail: no patch, no error
    raw["wheelset"]["vertical_position"] = force.pose.vertical - 1e-3
    assert solve(case_from_dict(raw)).patches == []
    raw["wheelset"]["vertical_force"] = 1e4
    with pytest.raises(CaseFileError, match="either vertical_force or vertical_position"):
        rc.case_from_dict(raw)
    del raw["wheelset"]["roll"], raw["wheelset"]["vertical_force"]
    with pytest.raises(CaseFileError, match="give wheelset.roll"):
        rc.case_from_dict(raw)


@pytest.mark.parametrize("key", ["normal_options", "tangential_options"])
@pytest.mark.parametrize("value", [0, "0", [1, 2]])
def test_solver_options_must_be_a_table(key, value):
    """Found by the property tests with random seeds: a model's options that are not
    a table were a raw TypeError/ValueError."""
    raw = {"wheel": {"profile": "S1002"}, "rail": {"profile": "60E1"}, "solver": {key: value}}
    with pytest.raises(CaseFileError, match=f"solver.{key} = .*expected a table"):
        rc.case_from_dict(raw)


def test_friction_along_the_track_keys(refdir):
    """friction.variation = {x, coefficient} (CONTACT's VARFRC = 2): coefficients at x
    [m] from the wheelset centre, parsed once; it needs the exact tangential model
    and a wheel-rail case on a track."""
    from railcontact import case_from_dict
    var = {"x": [-0.06, 0.04], "coefficient": [0.2, 0.3]}
    raw = _mbench_raw(refdir)
    raw["friction"]["variation"] = var
    case = case_from_dict(raw)
    assert case.friction_along_track == ((-0.06, 0.04), (0.2, 0.3))
    assert case.friction_variation is None
    with pytest.raises(CaseFileError, match="needs solver.tangential = 'exact'"):
        case_from_dict({**raw, "solver": {"tangential": "fastsim"}})
    with pytest.raises(CaseFileError, match="friction.variation.x = .*increasing"):
        case_from_dict({**raw, "friction": {"variation": {"x": [0.1, 0.0],
                                                           "coefficient": [0.2, 0.3]}}})
    roller = {**raw, "roller": {"radius": 0.5}}
    with pytest.raises(CaseFileError, match="applies to a wheel-rail case on a track"):
        case_from_dict(roller)


def test_blanco_incompatibilities_are_named_where_the_case_enters():
    """``solver.influence = "blanco"`` with an interfacial layer or the transient
    mode: one CaseFileError naming the keys when the case is read (before any
    contact search or solve); ``[viscoelastic]`` is refused for any wheel-rail case."""
    case = rc.load_case(EX / "wheel_rail.toml").with_values(
        {"solver.contact_surface": "conformal", "solver.normal": "exact",
         "solver.tangential": "exact"})
    b = case.with_value("solver.influence", "blanco")
    layer = {"thickness": 2e-5, "shear_modulus": 8.2e8, "yield_stress": 6e7, "hardening": 1e12}
    for values, keys in [
            ({"solver.tangential_options": {"layer": layer}},
             "solver.tangential_options.layer"),
            ({"solver.tangential_options": {"mode": "transient"}},
             "solver.tangential_options.mode = 'transient'"),
            ({"solver.tangential_options": {"mode": "transient", "layer": layer}},
             "layer and solver.tangential_options.mode = 'transient'")]:
        case.with_values(values)                      # the half-space's: accepted
        with pytest.raises(CaseFileError, match=r"solver.influence = 'blanco' with .*" + keys):
            b.with_values(values)
    with pytest.raises(CaseFileError, match=r"\[viscoelastic\] needs a \[bodies\] case"):
        b.with_value("viscoelastic", {"spring_ratio": 1.0, "relaxation_time": 0.003})
