"""CONTACT's rules as one record (railcontact.cases.rules): the preset, the
individual keys over it, what the models and bodies receive, and the errors."""

import pytest

from railcontact.cases.bodies import build_wheelset_track
from railcontact.cases.case import case_from_dict
from railcontact.cases.compiled_case import compiled_unsupported
from railcontact.cases.rules import CONTACT_RULES, ContactRules
from railcontact.core.errors import CaseFileError


def _raw(solver=None, **tables):
    raw = {"wheel": {"profile": "S1002"}, "rail": {"profile": "60E1"},
           "wheelset": {"lateral_shift": 0.003, "vertical_force": 7e4},
           "solver": {"normal": "hertz", "tangential": "fastsim", **(solver or {})}}
    raw.update(tables)
    return raw


def test_default_is_railcontacts_own():
    case = case_from_dict(_raw())
    assert case.rules == ContactRules() and case.rules.differing() == ()
    assert case.normal_options == {} and case.tangential_options == {}


def test_the_preset_sets_every_rule_and_the_models_options():
    """``solver.rules = "contact"``: each rule CONTACT's; the models receive the
    options of the rules that apply to them (FASTSIM's march and flexibility here;
    KPEC's rule and the exact model's wheel sampling with those models)."""
    case = case_from_dict(_raw({"rules": "contact"}))
    assert case.rules == CONTACT_RULES
    assert set(case.rules.differing()) == {
        "locus", "contact_angle", "reference_weights", "wheel_sampling", "kpec",
        "fastsim_march", "fastsim_flexibility", "thermal_scheme", "surface_slip",
        "gauge_point", "roller_turn"}
    assert case.tangential_options == {"march": "grid", "flexibility": "contact"}
    assert case.normal_options == {}
    kpec = case_from_dict(_raw({"rules": "contact", "normal": "kpec"}))
    assert kpec.normal_options == {"rule": "contact"}
    exact = case_from_dict(_raw({"rules": "contact", "normal": "exact", "tangential": "none"}))
    assert exact.normal_options == {"wheel_sampling": "contact"}
    # a bodies case has no wheel to sample
    bodies = case_from_dict({"bodies": {"radii": {"wheel_rolling": 0.46, "rail_lateral": 0.3},
                                        "normal_force": 1e4},
                             "solver": {"normal": "exact", "rules": "contact",
                                        "grid": [20, 20]}})
    assert bodies.normal_options == {} and bodies.rules.wheel_sampling == "contact"
    # the wheelset's locus and the track's gauge point follow the record
    ws, tr = build_wheelset_track(case)
    assert ws.locus == "contact" and tr.gauge_rule == "contact"


def test_individual_keys_win_over_the_preset():
    raw = _raw({"rules": "contact", "tangential_options": {"march": "strips"}},
               track={"gauge_point": "profile"})
    raw["wheelset"]["locus"] = "lowest"
    case = case_from_dict(raw)
    assert (case.rules.locus, case.rules.gauge_point, case.rules.fastsim_march) == \
        ("lowest", "profile", "strips")
    assert case.rules.fastsim_flexibility == "contact"
    assert case.tangential_options == {"march": "strips", "flexibility": "contact"}
    # one rule alone, without the preset
    one = case_from_dict(_raw(track={"gauge_point": "contact"}))
    assert one.rules.differing() == ("gauge_point",)


def test_thermal_scheme_from_the_rules():
    thermal = {"rail_temperature": 20.0}
    assert case_from_dict(_raw(thermal=thermal)).thermal[2] == "jaeger"
    assert case_from_dict(_raw({"rules": "contact"}, thermal=thermal)).thermal[2] == "contact"
    own = case_from_dict(_raw({"rules": "contact"}, thermal={**thermal, "scheme": "jaeger"}))
    assert own.thermal[2] == own.rules.thermal_scheme == "jaeger"


def test_the_compiled_pass_asks_the_record_once():
    """The compiled pass has railcontact's gauge point (and either locus, from the
    shared locus kernel): a case with CONTACT's gauge point is not run there (its
    reason names the rule), one whose only rules are the models' options is judged
    by those options."""
    case = case_from_dict(_raw())
    assert compiled_unsupported(case) is None
    why = compiled_unsupported(case_from_dict(_raw(track={"gauge_point": "contact"})))
    assert "gauge_point" in why
    contact = case_from_dict(_raw({"rules": "contact"}))
    assert compiled_unsupported(contact) == "tangential options given"
    why = compiled_unsupported(contact, tangential="fastsim")
    assert "gauge_point" in why and "locus" not in why


@pytest.mark.parametrize("solver, tables, match", [
    ({"rules": "CONTACT"}, {}, r"solver.rules = 'CONTACT': expected 'railcontact'"),
    ({}, {"track": {"gauge_point": "spline"}}, r"track.gauge_point = 'spline': expected "
                                              r"'profile'"),
    ({"surface_slip": "apex"}, {}, r"solver.surface_slip = 'apex': expected 'sections'"),
    ({"rules": ["contact"]}, {}, r"solver.rules = .*: expected 'railcontact'"),
    ({}, {"track": {"gauge_point": []}}, r"track.gauge_point = .*: expected 'profile'"),
    ({"rules": "contact"}, {"thermal": {"scheme": "grid"}}, "thermal.scheme"),
    ({}, {"roller": {"radius": 0.4, "turn": "axis"}}, r"roller.turn = 'axis': expected "
                                                      r"'profile'"),
    ({"rules": "contact", "tangential_options": {"march": "rows"}}, {}, "march"),
])
def test_wrong_rules_are_named(solver, tables, match):
    with pytest.raises(CaseFileError, match=match):
        case_from_dict(_raw(solver, **tables))


def test_a_sweep_changes_a_rule():
    case = case_from_dict(_raw())
    assert case.with_value("solver.rules", "contact").rules == CONTACT_RULES


def test_the_turned_roller_follows_the_record(testbank):
    """``roller_turn`` (``roller.turn``): a deviated roller's undeformed distance on
    its turned profile revolved (railcontact's, the default) or CONTACT's turned
    roller (the preset's); the surface built for the case carries it, and the
    search's surface is the same under both."""
    from railcontact.cases.surfaces import build_surface_case
    raw = {"wheel": {"profile": "../profiles/circ_r100.prw", "nominal_radius": 0.13333333},
           "rail": {"profile": "../profiles/flat_plane.prr", "lateral_position": 0.2},
           "roller": {"radius": 0.4, "profile_deviation": [0.0, 0.2]},
           "wheelset": {"vertical_position": -1.87e-3, "flange_back_distance": 0.2,
                        "flange_back_position": -0.1, "velocity": 0.1},
           "solver": {"normal": "exact", "tangential": "none"}}
    base = testbank / "examples_conformal"
    own = case_from_dict(raw, base)
    contact = case_from_dict({**raw, "solver": {**raw["solver"], "rules": "contact"}}, base)
    kept = case_from_dict({**raw, "solver": {**raw["solver"], "rules": "contact"},
                           "roller": {**raw["roller"], "turn": "profile"}}, base)
    assert (own.rules.roller_turn, contact.rules.roller_turn, kept.rules.roller_turn) == \
        ("profile", "surface", "profile")
    assert kept.rules.differing() == tuple(n for n in CONTACT_RULES.differing()
                                           if n != "roller_turn")
    surfs = [build_surface_case(c).rails[0].surface for c in (own, contact)]
    assert [(s.turn, s.tilted) for s in surfs] == [("profile", False), ("surface", True)]
    assert surfs[0].height(0.006, -0.02)[0] == surfs[1].height(0.006, -0.02)[0]
    assert surfs[1].gap_height(0.006, -0.02)[0] > surfs[0].gap_height(0.006, -0.02)[0]
