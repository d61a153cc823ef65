"""Mapping CONTACT's input to a railcontact case in SI units
(railcontact.contact_inp.mapping), and the one-line errors for what is not supported."""

import pytest

from railcontact.cases.bodies import build_wheelset_track
from railcontact.cases.case import case_from_dict
from railcontact.cases.rules import CONTACT_RULES
from railcontact.contact_inp import InpError, load_inp
from tests.contact_inp.test_reader import CASE1, _write


@pytest.fixture
def files(tmp_path, refdir):
    import shutil
    for name in ("MBench_UIC60_v3.prr", "MBench_S1002_v3.prw"):
        shutil.copy(refdir / "profiles" / name,
                    tmp_path / ("rail.prr" if "UIC" in name else "wheel.prw"))
    return tmp_path


def test_mapping_to_a_case_in_si_units(files):
    (m1, m2) = load_inp(_write(files, CASE1))
    r = m1.raw
    assert r["material"]["young_modulus"] == pytest.approx(2 * 82e9 * 1.28)
    # CONTACT's rules, one preset: the exact model with CONTACT's planar undeformed
    # distance (the wheel linear between profile samples one DS apart)
    assert r["solver"] == {"normal": "exact", "tangential": "exact",
                           "element_size": [2e-4, 2.5e-4], "tangential_options": {},
                           "rules": "contact"}
    case = case_from_dict(r, files)
    assert case.rules == CONTACT_RULES
    assert case.normal_options == {"wheel_sampling": "contact"}
    ws = r["wheelset"]
    assert ws["side"] == "right" and ws["roll"] == 0.0001 and ws["yaw"] == 0.0024
    assert ws["lateral_shift"] == pytest.approx(1.5e-3) and ws["vertical_force"] == 1e4
    assert ws["velocity"] == 2.0 and ws["pitch_velocity"] == -4.348
    # CONTACT's patch rules: D_SEP, D_COMB and the default D_TURN = 2 D_SEP - D_COMB
    assert (ws["combine_distance"], ws["full_interaction_distance"],
            ws["turn_distance"]) == pytest.approx((8e-3, 4e-3, 12e-3))
    # CONTACT's contact locus (the wheel's normal perpendicular to x)
    ws_body, track = build_wheelset_track(case)
    assert ws_body.locus == "contact"
    # the rail placed by CONTACT's gauge point: 14 mm below the top on the spline
    # along the points' chord length, y = -43.0325577 mm (railcontact's own rule, on
    # z(y): -43.0328785 mm)
    assert r["track"] == {"gauge": pytest.approx(1.435), "gauge_height": pytest.approx(0.014)}
    assert track.rail_offset("right") == pytest.approx(0.7175 + 0.0430325577, abs=2e-10)
    own = build_wheelset_track(case.with_value("track.gauge_point", "profile"))[1]
    assert own.rail_offset("right") == pytest.approx(0.7175 + 0.0430328785, abs=2e-10)
    w = r["wheel"]
    assert w["mirror_y"] is True and w["mirror_z"] is False and w["nominal_radius"] == 0.46
    assert w["smoothing"] == {"method": "weighted", "length": pytest.approx(0.01)}
    assert w["kinks"]["width"] == pytest.approx(2e-3)
    assert r["rail"]["mirror_z"] == "auto" and "smoothing" not in r["rail"]
    assert m2.raw["wheelset"]["lateral_shift"] == pytest.approx(2.5e-3)


@pytest.mark.parametrize("old, new, match", [
    ("0022033    V-L-D-C-M-Z-E", "0032033    V-L-D-C-M-Z-E",
     r"DISCNS = 3 \(planar contact with rigid slip on the actual surfaces\)"),
    ("0022033    V-L-D-C-M-Z-E", "0023033    V-L-D-C-M-Z-E", r"INFLCF = 3 \(bilinear"),
    ("1203100    C-P-B-T-N-F-S   comment", "5203100    C-P-B-T-N-F-S   comment",
     r"GAUGHT = 14 mm with a roller rig \(a rail placed by its gauge face\)"),
    ("1435.0   0.000", "1435.0   0.025 1e-5", r"CURV = 1e-05 1/mm \(curved track\)"),
    ("     0.0    0.0   0.000          % DY", "     0.5    0.0   0.000   % DY",
     r"DYRAIL = 0.5 \(rail deviations\)"),
    ("1360.0  -70.0   460.0", "1360.0  -70.0   460.0  -10.0", r"YTAPE = -10 mm"),
])
def test_unsupported_options_stop_with_one_line(files, old, new, match):
    assert old in CASE1
    with pytest.raises(InpError, match=match) as err:
        load_inp(_write(files, CASE1.replace(old, new, 1)))
    assert "\n" not in str(err.value) and "is not supported" in str(err.value)


def test_unsupported_material_after_its_inputs(files):
    text = CASE1.replace("0022033    V-L-D-C-M-Z-E", "0022133    V-L-D-C-M-Z-E", 1).replace(
        "82000.  82000.                POISS 1,2,  GG 1,2",
        "82000.  82000.                POISS 1,2,  GG 1,2\n  1e3 1e3 0.1 0.1  FG, VT", 1)
    with pytest.raises(InpError, match=r"MATER = 1 \(viscoelastic material\) is not supported"):
        load_inp(_write(files, text))


def test_missing_profile_names_where_it_looked(tmp_path):
    with pytest.raises(InpError, match="profile file 'wheel.prw' not found.*--profiles"):
        load_inp(_write(tmp_path, CASE1))
    with pytest.raises(InpError, match="no case 7"):
        load_inp(_write(tmp_path, CASE1), cases=[7])


def test_module3_hertzian_case(refdir):
    (m,) = load_inp(refdir / "kalker_example.inp")
    r = m.raw
    assert m.module == 3 and r["solver"]["grid"] == [80, 80]
    assert r["solver"]["normal_options"] == {"margin": pytest.approx(0.1)}
    assert r["bodies"]["normal_force"] == pytest.approx(52359.8776)
    assert r["creepage"] == {"longitudinal": 1e-5, "lateral": 0.0, "spin": 0.0}
    # the curvatures of the 5 mm circle at that load
    from railcontact import Material
    from railcontact.core.hertz_theory import hertz_ellipse
    rad = r["bodies"]["radii"]
    h = hertz_ellipse(0.5 / rad["wheel_rolling"], 0.5 / rad["wheel_lateral"],
                      Material(**r["material"]).contact_modulus, force=52359.8776)
    assert (h.a, h.b) == pytest.approx((5e-3, 5e-3), rel=1e-9)


def test_deviations_by_flexibility(testbank, tmp_path):
    """CONTACT's deviations by flexibility on a roller rig or a test rig: the wheel's
    (E = 4, 5: DXWHL .. DPITCHW, mm and rad) become ``wheelset.wheel_deviation`` in m
    and rad; a rail's DYRAIL, DZRAIL (Z = 2, 3) its placement; a roller's DZRAIL,
    DROLLR its profile's deviation about its fixed axis; a rail's roll and the
    deviations' velocities stop with one line."""
    path = testbank / "examples_conformal" / "test-rollers3.inp"
    two, five = load_inp(path, cases=[2, 5])
    assert two.raw["wheelset"]["wheel_deviation"] == [0.0, 0.0, 0.0, 0.0, -0.3, 0.0]
    assert five.raw["wheelset"]["wheel_deviation"] == pytest.approx(
        [0.0, 0.0, -0.4996e-3, 0.1, 0.0, 0.0])
    (one,) = load_inp(path, cases=[1])
    assert "wheel_deviation" not in one.raw["wheelset"]
    text = path.read_text().replace("     0.0    0.0   0.000   0.0    0.0   0.000    DY, DZ, "
                                    "ROLL, VY, VZ, VROLL",
                                    "     1.5   -0.2   0.000   0.0    0.0   0.000    DY, DZ, "
                                    "ROLL, VY, VZ, VROLL", 1)
    moved = tmp_path / "moved_rail.inp"
    moved.write_text(text)
    (m,) = load_inp(moved, cases=[1], profile_dirs=[testbank / "profiles"])
    assert m.raw["rail"]["lateral_position"] == pytest.approx(0.2015)
    assert m.raw["rail"]["vertical_position"] == pytest.approx(-0.2e-3)
    (nine,) = load_inp(path, cases=[9])
    assert nine.raw["roller"]["profile_deviation"] == pytest.approx([0.4996e-3, 0.1])
    assert nine.raw["rail"]["vertical_position"] == 0.0
    rolled = tmp_path / "rolled_rail.inp"
    rolled.write_text(text.replace("     1.5   -0.2   0.000   0.0    0.0   0.000    DY, DZ, ",
                                   "     1.5   -0.2   0.100   0.0    0.0   0.000    DY, DZ, ", 1))
    with pytest.raises(InpError, match=r"case 1 .*DROLLR = 0.1 with a rail at RAILY0 is not "
                                       r"supported; expected 0 \(the wheel's deviations"):
        load_inp(rolled, cases=[1], profile_dirs=[testbank / "profiles"])


@pytest.fixture(scope="module")
def varfric_case6(testbank):
    from railcontact.contact_inp import solve_inp
    path = testbank / "examples_basic" / "mbench_a22_varfric.inp"
    (r,) = solve_inp(path, cases=[6])
    return path, r


def test_friction_along_the_track(varfric_case6):
    """mbench_a22_varfric.inp, VARFRC = 2 (0.2 at SVF = 0, 0.3 at 100 mm): CONTACT
    interpolates the coefficient at the wheelset's position S_WS, one for all of
    the case's elements (its m_wr_solvecp; a CONTACT run of these cases with V = 0
    and that coefficient prints the same digits).  Case 6 (S_WS = 60 mm, planar):
    0.26, F_x against CONTACT's 19.71 N within 1 % of mu F_n, F_s against -249.5 N,
    1291 elements in contact as CONTACT's.  Case 7 (S_WS = 70 mm, conformal, the
    patch 7.4 mm behind the axle): 0.27 as CONTACT prints (with each element's
    coefficient at its place, 0.2626 at the reference point and F_s +2.5 %)."""
    path, r = varfric_case6
    (m,) = load_inp(path, cases=[6])
    assert "variation" not in m.raw["friction"]
    assert m.raw["friction"]["coefficient"] == pytest.approx(0.26)
    assert r["mu"] == pytest.approx(0.26)
    mu_fn = 0.26 * 9997.0
    assert abs(r["fx_N"] - 19.71) <= 0.01 * mu_fn
    assert abs(r["fs_N"] + 249.5) <= 0.01 * mu_fn
    assert r["fn_N"] == pytest.approx(9997.0, rel=1e-3) and r["ncon"] == 1291
    (m,) = load_inp(path, cases=[7])
    assert m.raw["friction"]["coefficient"] == pytest.approx(0.27)


def test_interfacial_layer_maps_to_the_exact_models_layer(testbank):
    """MATER = 4 in module 1 (examples_plast/mbench_a22_left.inp): the exact
    tangential model with the layer in SI (GG3 820 N/mm^2, LAYTHK 0.02 mm, TAU_C0
    60 N/mm^2, K_TAU 1000 N/mm^3); TAU_C0 <= 0 is a layer without yield."""
    import math
    path = testbank / "examples_plast" / "mbench_a22_left.inp"
    (m,) = load_inp(path, profile_dirs=[testbank / "profiles"])
    s = m.raw["solver"]
    assert s["tangential"] == "exact"
    layer = s["tangential_options"]["layer"]
    assert layer == pytest.approx({"thickness": 2e-5, "shear_modulus": 8.2e8,
                                   "yield_stress": 6e7, "hardening": 1e12})
    from railcontact.contact_inp.mapping import layer_options
    from railcontact.contact_inp import read_inp
    (case,) = read_inp(path)
    case.values["TAU_C0"] = 0.0
    assert layer_options(case)["yield_stress"] == math.inf


def _a22_with_heat(testbank, tmp_path, b1, b2, heatcp2=450.0):
    """Manchester A-2.2's first case (right wheel, exact model) at 12 mrad yaw with
    HEAT = 3 and the bulk temperatures ``b1`` (rail), ``b2`` (wheel)."""
    src = (testbank / "examples_basic" / "mbench_a22_right.inp").read_text()
    t = src.split("%  2: Lateral")[0]
    t = t.replace(" 0000321    H-G-I-A-O-W-R", " 3000321    H-G-I-A-O-W-R")
    t = t.replace("82000.  82000.                POISS 1,2,  GG 1,2",
                  "82000.  82000.                POISS 1,2,  GG 1,2\n"
                  f"  {b1}  450.0  50e-3  7.85e-6   BKTEMP, HEATCP1, LAMBDA1, DENS1\n"
                  f"  {b2}  {heatcp2}  50e-3  7.85e-6   BKTEMP, HEATCP2, LAMBDA2, DENS2")
    t = t.replace("10000.  0.00000000 0.0000  0.0", "10000.  0.00000000 0.0120  0.0")
    path = tmp_path / f"a22_heat_{b2}.inp"
    path.write_text(t + "\n 0 MODULE\n")
    return path


def test_module1_surface_temperatures(testbank, tmp_path):
    """HEAT = 3 in module 1: every patch's tmax_C (CONTACT's MAX(T1,T2), its scheme)
    from the wheel-rail solution's slip and tractions.  Equal steels make the
    problem linear in the bulk temperatures: with the wheel at 150 C and the rail
    at 0 C the largest temperature is the cold case's plus their mean, 75 C (to
    1e-9; measured 4.80 C of frictional heating at 12 mrad yaw).  Different heat
    constants of the two bodies stop with one line."""
    from railcontact.contact_inp import solve_inp
    dirs = [testbank / "examples_basic"]
    (cold,) = solve_inp(_a22_with_heat(testbank, tmp_path, 0.0, 0.0), profile_dirs=dirs)
    (hot,) = solve_inp(_a22_with_heat(testbank, tmp_path, 0.0, 150.0), profile_dirs=dirs)
    assert cold["converged"] and hot["converged"]
    assert cold["tmax_C"] > 1.0 and cold["nslip"] > 0
    assert hot["tmax_C"] == pytest.approx(cold["tmax_C"] + 75.0, abs=1e-9)
    with pytest.raises(InpError, match="HEATCP, LAMBDA or DENS of the two bodies"):
        solve_inp(_a22_with_heat(testbank, tmp_path, 0.0, 1.0, heatcp2=500.0),
                  profile_dirs=dirs)


def test_conformal_groove_on_a_test_rig_is_translated_onto_a_track(testbank):
    """groove_li case 1: a rail at RAILY0 = 0 (GAUGHT < 0), conformal (D = 4), no
    roll or yaw: the track's case with the rail 0.75 m from the centre and the
    wheel moved with it (FBDIST 0 -> 1.5 m), y_tr moved back in the rows; FX_WS
    prescribed (F = 1) from the nominal pitch velocity -VS/NOMRAD."""
    (m,) = load_inp(testbank / "examples_conformal" / "groove_li.inp", cases=[1])
    assert m.raw["track"]["rail_offset"] == pytest.approx(0.75)
    assert m.raw["wheelset"]["flange_back_distance"] == pytest.approx(1.5)
    assert m.raw["solver"]["contact_surface"] == "conformal"
    assert m.meta["translation"] == pytest.approx(0.75) and m.meta["fx_ws"] == 0.0
    assert m.raw["wheelset"]["pitch_velocity"] == pytest.approx(-1.0)


@pytest.mark.parametrize("cases", [(1, 2, 3), (4, 5, 6)])
def test_kpec_and_analyn_with_modified_fastsim(testbank, cases):
    """mbench_a22_kpec.inp: KPEC (B = 5, cases 1-3) and ANALYN (B = 6, cases 4-6)
    with modified FASTSIM (M = 3) on A-2.2 at y_ws = 0, 0.5, 5 mm, mapped to
    CONTACT's conventions (KPEC on the grid's elements, ``rule="contact"``; the
    FASTSIM march over the grid's elements, ``march="grid"``, with CONTACT's
    blended flexibilities), against its .ref_out with issue 34's tolerances: F_n
    within 1 % (CONTACT's own case 1 stops 0.2 % short of FZ = 10 kN), F_x and F_s
    within 1 % of mu F_n (measured <= 0.15 %; before: 6.8 % in case 1, 2.3 % in
    cases 2 and 5), p_max within 3 % (<= 0.6 %; before: -21.7 % in case 1) and
    the elements in contact within 3 % (<= 1.8 %, case 3; before: +4.9 %), and
    the frictional power within 2 % of CONTACT's FRIC.POWER (measured <= 1.9 %,
    case 1 near pure rolling; before: up to 72 %)."""
    from railcontact.contact_inp import solve_inp
    from tests.conftest import read_ref_out
    path = testbank / "examples_basic" / "mbench_a22_kpec.inp"
    ref = {c["case"]: c["patches"] for c in read_ref_out(path.with_suffix(".ref_out"))}
    rows = solve_inp(path, cases=list(cases))
    assert sorted(r["case"] for r in rows) == list(cases)
    # CONTACT's FRIC.POWER [W], printed in the forces' table
    power = {1: -0.7617, 2: -6.592, 3: -76.92, 4: -0.3397, 5: -6.644, 6: -76.63}
    for r in rows:
        (q,) = ref[r["case"]]
        assert r["converged"] and r["npatch"] == 1, r["message"]
        mfn = 0.3 * q["fn"]
        assert r["fn_N"] == pytest.approx(q["fn"], rel=0.01), r["case"]
        assert abs(r["fx_N"] - q["fx"]) < 0.01 * mfn, r["case"]
        assert abs(r["fs_N"] - q["fs"]) < 0.01 * mfn, r["case"]
        assert r["pmax_MPa"] == pytest.approx(q["pmax"], rel=0.03), r["case"]
        assert r["ncon"] == pytest.approx(q["ncon"], rel=0.03), r["case"]
        assert r["fric_power_W"] == pytest.approx(power[r["case"]], rel=0.02), r["case"]


def test_blanco_coefficients_map_and_match_contact(testbank, tmp_path):
    """INFLCF = 4 (groove_li cases 5-8: IF_METH 1, VARIANT 3) maps to Blanco's
    conformal influence coefficients (``solver.influence = "blanco"``), kept by
    the cases after it (C = 1).  Case 5 (a 10 mm wheel section in a 10.25 mm
    groove, 10 kN, FX_WS = 0) against its .ref_out: F_n, F_x, F_s within 1 % (of
    mu F_n for the tangential ones; measured under 0.01 N), p_max and the elements
    in contact within the issue's 3 % and within 0.5 % asserted (measured 520.3
    against 520.6 N/mm^2, -0.05 %, and 1207 against 1207 elements; the
    half-space's coefficients of case 1 give 530.0 and 1187, +1.8 % and -1.7 % off
    case 5's), the pitch velocity within 5e-6 (-1.0002343 against -1.0002366
    rad/s).  Cases 6-8 (benchmarks/contact_testbank.py): p_max -0.07 to -0.10 %,
    elements in contact as CONTACT's."""
    import re

    from railcontact.contact_inp import solve_inp
    from railcontact.contact_inp.force_m1 import wheelset_fx

    from ..cases.test_conformal import _ref
    path = testbank / "examples_conformal" / "groove_li.inp"
    m = load_inp(path, cases=[5, 6])
    for c in m:
        assert c.raw["solver"]["contact_surface"] == "conformal"
        assert c.raw["solver"]["influence"] == "blanco"
        assert c.raw["solver"]["influence_options"] == {"method": "detailed", "variant": 3}
    assert "influence" not in load_inp(path, cases=[1])[0].raw["solver"]
    (r,) = solve_inp(path, cases=[5])
    (p,) = _ref(path.with_suffix(".ref_out"), 5)["patches"]
    text = path.with_suffix(".ref_out").read_text()
    vpitch = [float(v) for v in re.findall(r"VPITCH_WS\n\s+" + r"\S+\s+" * 5 + r"(\S+)", text)]
    assert r["converged"], r["message"]
    assert abs(wheelset_fx([r])) < 1.9e-3
    assert r["fn_N"] == pytest.approx(p["fn"], rel=0.01)
    assert abs(r["fx_N"] - p["fx"]) <= 0.01 * 0.3 * p["fn"]
    assert abs(r["fs_N"] - p["fs"]) <= 0.01 * 0.3 * p["fn"]
    assert r["pmax_MPa"] == pytest.approx(p["pmax"], rel=0.005)
    assert r["ncon"] == pytest.approx(p["ncon"], rel=0.005)
    assert r["vpitch_rad_s"] == pytest.approx(vpitch[4], abs=5e-6)


@pytest.mark.parametrize("edits, match", [
    ([("      1       3                                 IF_METH, IF_VAR",
       "      1       4                                 IF_METH, IF_VAR")],
     r"case 5 .*VARIANT = 4 of Blanco's coefficients is not supported; expected 3"),
    ([("1203110    C-P-B-T-N-F-S   CONFIG, PVTIME, BOUND, TANG, NORM, FORCE, STRESS\n"
       "  044033", "1203100    C-P-B-T-N-F-S   CONFIG, PVTIME, BOUND, TANG, NORM, FORCE, "
       "STRESS\n  024033")],
     r"case 5 .*INFLCF = 4 .*on a planar patch is not supported; expected DISCNS = 4"),
])
def test_blanco_options_not_supported_stop(testbank, tmp_path, edits, match):
    """Blanco's variants 1, 2, 4 and INFLCF = 4 on a planar patch stop with one line
    naming them."""
    path = testbank / "examples_conformal" / "groove_li.inp"
    src = path.read_text()
    for old, new in edits:
        assert src.count(old) == 1
        src = src.replace(old, new)
    f = tmp_path / "groove.inp"
    f.write_text(src.replace("'../profiles/", f"'{testbank / 'profiles'}/"))
    with pytest.raises(InpError, match=match) as err:
        load_inp(f, cases=[5])
    assert "\n" not in str(err.value)
