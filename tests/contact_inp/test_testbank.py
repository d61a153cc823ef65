"""The wheel-rail inputs of CONTACT's testbank (examples_trans) against .ref_out.

Measured profiles ``site_b_hr.prr`` and ``worn_high_mileage.prw`` (North American
heavy haul), friction varying with the rail's inclination (0.2 on the gauge face,
0.35 on the head; V = 1), 0.4 mm elements, patches combined within 6 mm (D_SEP)
and turned up to 9 mm apart; force control (force_site_b, t3_*_force case 1) and
position control (iestim_site_b).  The transient ones (the conformal
t3_*_conformal too) are test_transient_m1.py's.  benchmarks/contact_inputs.py lists every case.
"""

import re
from pathlib import Path

import pytest

from railcontact.cases.case import case_from_dict

from railcontact.contact_inp import InpError, load_inp, solve_inp

_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


def ref_out(path) -> dict:
    """Per case of a CONTACT output file: total forces on the rail, z_ws and the
    patches' (y_tr, delta, F_n, F_x, F_s, p_max, mu)."""
    text = Path(path).read_text()
    parts = re.split(r"\n Case +(\d+)\n", text)
    out = {}
    for num, body in zip(parts[1::2], parts[2::2]):
        c = {"patches": []}
        m = re.search(r"TOTAL FORCES ON RAIL\n.*\n\s*" + r"\s+".join([f"({_NUM})"] * 3), body)
        if m:
            c["fx"], c["fy"], c["fz"] = (float(g) for g in m.groups())
        m = re.search(r"S_WS\s+Y_WS\s+Z_WS.*\n\s*" + r"\s+".join([f"({_NUM})"] * 3), body)
        if m:
            c["z_ws"] = float(m.group(3))
        for pb in body.split("----- DATA FOR CONTACT PATCH")[1:]:
            p = {}
            m = re.search(r"XCP\(TR\).*\n\s*" + r"\s+".join([f"({_NUM})"] * 4), pb)
            p["ycp_tr_mm"], p["delta_tr_rad"] = float(m.group(2)), float(m.group(4))
            m = re.search(r"\n\s*FSTAT\s+FKIN\s*\n\s*(" + _NUM + ")", pb)
            if m:                        # printed where a case sets the friction
                p["mu"] = float(m.group(1))
            # (a conformal patch's bar forces: BAR_FN, BAR_FX, BAR_FS)
            m = re.search(r"(?:BAR_)?FN\s+(?:BAR_)?FX\s+(?:BAR_)?FS\s+MN.*\n\s*"
                          + r"\s+".join([f"({_NUM})"] * 3), pb)
            p["fn_N"], p["fx_N"], p["fs_N"] = (float(g) for g in m.groups())
            m = re.search(r"FRIC\.POWER\s*\n\s*" + r"\s+".join([f"({_NUM})"] * 6), pb)
            p["fric_power_W"] = float(m.group(6))
            m = re.search(r"APPROACH\s+PMAX\s*\n\s*" + r"\s+".join([f"({_NUM})"] * 5), pb)
            p["pmax_MPa"] = float(m.group(5))
            c["patches"].append(p)
        out[int(num)] = c
    return out


def _compare(rows, ref, cases, load_tol=0.01, patch_tol=0.01,
             keys=("fn_N", "fx_N", "fs_N", "pmax_MPa", "fric_power_W")):
    """Totals within ``load_tol`` of the vertical force; each patch carrying at least
    a tenth of it within ``patch_tol`` (F_n, F_x, F_s) and 3 % (p_max) (the
    Manchester comparisons' tolerances) and the frictional power within 2 % (issue
    35); every patch where CONTACT's is (0.05 mm),
    its contact angle within 0.01 rad and its friction coefficient CONTACT's.
    Returns the relative F_n deviations of the smaller patches."""
    small = []
    for case in cases:
        mine = [r for r in rows if r["case"] == case]
        c = ref[case]
        assert mine[0]["converged"], mine[0]["message"]
        fz = c["fz"]
        for k in ("fx", "fy", "fz"):
            assert abs(mine[0][f"{k}_tr_N"] - c[k]) <= load_tol * fz, (case, k)
        for p in c["patches"]:
            r = min(mine, key=lambda r: abs(r["ycp_tr_mm"] - p["ycp_tr_mm"]))
            assert abs(r["ycp_tr_mm"] - p["ycp_tr_mm"]) < 0.05
            assert r["delta_tr_rad"] == pytest.approx(p["delta_tr_rad"], abs=0.01)
            assert r["mu"] == pytest.approx(p["mu"], abs=1e-3)
            if p["fn_N"] < 0.1 * fz:
                small.append(r["fn_N"] / p["fn_N"] - 1)
                continue
            for k in keys:
                t = {"pmax_MPa": 0.03, "fric_power_W": 0.02}.get(k, patch_tol)
                assert r[k] == pytest.approx(p[k], rel=t), (case, k)
    return small


@pytest.fixture(scope="module")
def force_site_b(testbank):
    path = testbank / "examples_trans" / "force_site_b.inp"
    return solve_inp(path), ref_out(path.with_suffix(".ref_out"))


def test_force_control(force_site_b):
    """force_site_b: 3.7 to 128 kN, one to two patches (tread, gauge corner, flange
    flank).  Measured: totals within 0.15 % of F_z; patches above a tenth of the
    load within 0.6 % (F_n, F_x, F_s), p_max 1.2 %, frictional power 0.5 % of
    CONTACT's FRIC.POWER; z_ws within 1.2 um."""
    rows, ref = force_site_b
    _compare(rows, ref, [1, 2, 3, 4])
    for case in (1, 2, 3, 4):
        z = [r for r in rows if r["case"] == case][0]["z_ws_mm"]
        assert z == pytest.approx(ref[case]["z_ws"], abs=2e-3)


def test_force_control_small_flange_patch(force_site_b):
    """At 127.5 and 128 kN a flange-flank patch of 5 kN (4 % of the load, 70-85
    elements) forms beside the combined tread and gauge-corner patch.  Its force
    follows the approach of 13 um to the power 1.5.  Measured: F_n -0.42 % and
    -0.26 % with CONTACT's planar undeformed distance (the wheel linear between
    profile samples one DS apart) and gauge point, the .inp defaults; with the
    exact wheel surface and railcontact's gauge point +5.7 % and +4.9 % (the
    combined patch, 0.5 rad of contact angle across one tangent plane, sat about
    1 um deeper than CONTACT's)."""
    rows, ref = force_site_b
    small = _compare(rows, ref, [3, 4])
    assert small and max(abs(v) for v in small) <= 0.01


@pytest.fixture(scope="module")
def t3_t1_force(testbank):
    path = testbank / "examples_trans" / "t3_t1_force.inp"
    return solve_inp(path, cases=[1]), ref_out(path.with_suffix(".ref_out")), path


def test_steady_then_transient(t3_t1_force):
    """t3_t1_force: its first case (steady rolling, mu 0.9 on the head, 137 kN,
    three patches: tread, gauge corner, flange flank).  Measured: F_n of the tread
    and gauge-corner patches +0.01 and -0.02 % (with the exact wheel surface and
    railcontact's gauge point +0.2 and -0.7 %), the flange flank's +0.10 %.  Its
    second case (a transient shift, T = 1): test_transient_m1.py."""
    rows, ref, path = t3_t1_force
    _compare(rows, ref, [1], keys=("fn_N", "pmax_MPa"))


def test_steady_then_transient_creep_forces(t3_t1_force):
    """The tread and gauge-corner patches lie 6.5 mm apart, between D_SEP = 6 and
    D_TURN = 9 mm, and their contact angles are turned towards their mean
    (CONTACT measures the distance between the last samples inside the regions,
    railcontact between the interpolated ends, which move continuously with the
    wheelset height, so that the vertical balance converges).  Measured with
    CONTACT's wheel sampling and gauge point (the .inp defaults): the gauge-corner
    patch's angle 0.9 mrad off, F_n -0.02 %, F_x, F_s within 0.02 % of mu F_n;
    with the exact wheel surface and railcontact's gauge point the angle was 9 mrad
    off and F_s -1.1 %."""
    rows, ref, _ = t3_t1_force
    _compare(rows, ref, [1])


def test_position_control(testbank):
    """iestim_site_b: z_ws prescribed from 1.13 to 1.23 mm.  The force follows the
    approach to the power 1.5, so that the few 0.1 um by which the geometries
    differ show most where the approach is smallest: measured F_z -2.4 % at 284 N
    (1.13 mm), within 0.5 % from 33 kN (1.17 mm) on."""
    path = testbank / "examples_trans" / "iestim_site_b.inp"
    rows = solve_inp(path, cases=[1, 8, 11])
    ref = ref_out(path.with_suffix(".ref_out"))
    _compare(rows, ref, [8, 11])
    light = [r for r in rows if r["case"] == 1][0]
    assert light["z_ws_mm"] == pytest.approx(1.13, abs=1e-9)
    assert light["fz_tr_N"] == pytest.approx(ref[1]["fz"], rel=0.03)


def test_patch_numbering(testbank):
    """CONTACT numbers a wheel's patches from the field side towards the gauge side:
    iestim_site_b cases 8 (three patches: flange flank at y_tr = 714 mm, gauge
    corner 723 mm, field-side tread 755 mm of the right rail) and 11 (two: 714 and
    746 mm).  The rows of the CSV and JSON outputs, and the patch dimension of a case
    file's NetCDF (``SolveResult.to_xarray``), come in CONTACT's order, each patch
    within 0.05 mm of CONTACT's patch of its number."""
    import json

    import numpy as np

    from railcontact import case_from_dict, solve
    from railcontact.contact_inp import to_csv, to_json

    path = testbank / "examples_trans" / "iestim_site_b.inp"
    rows = solve_inp(path, cases=[8, 11])
    ref = ref_out(path.with_suffix(".ref_out"))
    for case in (8, 11):
        mine = [r for r in rows if r["case"] == case]
        assert [r["patch"] for r in mine] == list(range(1, len(ref[case]["patches"]) + 1))
        for r, p in zip(mine, ref[case]["patches"]):
            assert abs(r["ycp_tr_mm"] - p["ycp_tr_mm"]) < 0.05, (case, r["patch"])
    table = json.loads(to_json(rows))["rows"]
    assert [(r["case"], r["patch"]) for r in table] == [(8, 1), (8, 2), (8, 3), (11, 1),
                                                        (11, 2)]
    csv_rows = to_csv(rows).splitlines()[1:]
    assert [float(line.split(",")[11]) for line in csv_rows] == pytest.approx(
        [r["ycp_tr_mm"] for r in rows])
    (m,) = load_inp(path, cases=[11])
    ds = solve(case_from_dict(m.raw)).to_xarray()
    # y_rail points to the field side: falling along the patch dimension
    assert ds.sizes["patch"] == 2 and np.all(np.diff(ds["y_rail"].values) < 0)


@pytest.mark.parametrize("name", ["mbench_a22_right", "mbench_a22_left"])
def test_frictional_power_a22(testbank, name):
    """The exact model's frictional power per patch (``fric_power_W``) against
    CONTACT's FRIC.POWER [W] in the Manchester A-2.2 cases, from near pure rolling
    (0.47 W) to full sliding on the flange (291 W): measured within 0.16 % (the
    printed 4 digits) on all 42 patches (benchmarks/frictional_power.py)."""
    path = testbank / "examples_basic" / f"{name}.inp"
    cases = [1, 2, 11, 21]
    rows = solve_inp(path, cases=cases)
    ref = ref_out(path.with_suffix(".ref_out"))
    for case in cases:
        (r,) = [r for r in rows if r["case"] == case]
        (p,) = ref[case]["patches"]
        assert r["fric_power_W"] < 0
        assert r["fric_power_W"] == pytest.approx(p["fric_power_W"], rel=0.02), case
        assert r["fric_power_W"] == pytest.approx(p["fric_power_W"], rel=2e-3), case


def fric_power(path) -> dict:
    """{case: [FRIC.POWER of each patch, W]} of a CONTACT output file (any module)."""
    parts = re.split(r"\n Case +(\d+)\n", Path(path).read_text())
    return {int(num): [float(m.split()[5]) for m in re.findall(r"FRIC\.POWER\n(.*)\n", body)]
            for num, body in zip(parts[1::2], parts[2::2])}


def test_frictional_power_traction_curve(testbank):
    """examples_basic/tractcurv (module 3, a Hertzian patch's traction curve from
    creepage 0 to full sliding): the exact model's frictional power against CONTACT's
    FRIC.POWER, measured within 0.04 % on the 29 cases above 0.05 W and -0.49 % at
    4e-5 W (benchmarks/frictional_power.md)."""
    path = testbank / "examples_basic" / "tractcurv.inp"
    cases = [1, 2, 10, 20, 30]
    rows = solve_inp(path, cases=cases)
    ref = fric_power(path.with_suffix(".ref_out"))
    for case in cases:
        (r,) = [r for r in rows if r["case"] == case]
        (c,) = ref[case]
        assert r["fric_power_W"] == pytest.approx(c, rel=0.02 if case > 1 else 0.01), case
        if case > 1:
            assert r["fric_power_W"] == pytest.approx(c, rel=1e-3), case


# ------------------------------------------------ switches and crossings (.slcs)
def _sc_compare(rows, ref, cases, dA):
    """Every patch (numbered as CONTACT's) within 1 % in F_n, F_x and F_s (the
    tangential ones also relative to mu F_n), 3 % in p_max and elements in contact,
    its reference point within 10 um, the contact angle within 1 mrad."""
    from tests.conftest import read_ref_out
    refs = read_ref_out(ref)
    for case in cases:
        mine = [r for r in rows if r["case"] == case]
        q = refs[case - 1]["patches"]
        assert [r["patch"] for r in mine] == list(range(1, len(q) + 1)), case
        for r, p in zip(mine, q):
            assert r["converged"], r["message"]
            assert [r["xcp_tr_mm"], r["ycp_tr_mm"], r["zcp_tr_mm"]] == pytest.approx(
                [p["xcp"], p["ycp"], p["zcp"]], abs=0.01)
            assert r["delta_tr_rad"] == pytest.approx(p["delta"], abs=1e-3)
            assert r["fn_N"] == pytest.approx(p["fn"], rel=0.01)
            for k, c in (("fx_N", "fx"), ("fs_N", "fs")):
                assert abs(r[k] - p[c]) <= 0.01 * max(abs(p[c]), 0.3 * p["fn"]), (case, k)
            assert r["pmax_MPa"] == pytest.approx(p["pmax"], rel=0.03)
            assert r["area_mm2"] / dA == pytest.approx(p["ncon"], rel=0.03)


@pytest.mark.parametrize("name", ["cross_brute", "cross_locus", "wing_brute", "wing_locus",
                                  "cross+wing"])
def test_switch_and_crossing_inputs(testbank, name):
    """CONTACT's S&C inputs (rail slices, D = 5 brute-force search and D = 2 contact
    locus) through `railcontact solve FILE.inp`: the artificial nose rising 1:10
    and the wing rail shifting 1:10 at a prescribed position, against .ref_out.
    Measured: F_n within 0.01 %, F_x, F_s within 0.15 % of mu F_n, p_max 0.03 %."""
    path = testbank / "examples_s+c" / f"{name}.inp"
    rows = solve_inp(path)
    _sc_compare(rows, path.with_suffix(".ref_out"), [1], 0.2 * 0.05)


def test_switch_and_crossing_mapping(testbank):
    """A module 1 case with a .slcs rail becomes a case on rail surfaces: the
    slices' origin at RAILY0 (GAUGHT < 0), the wheelset at S_WS, CONTACT's contact
    angle rule (the rail's inclination at the wheelset: "wheelset"), D_SEP as the
    combining distance, SCALE = 1000 as slices in metres (wheel slices, .slcw:
    tests/contact_inp/test_wheel_slices.py)."""
    (m,) = load_inp(testbank / "examples_s+c" / "cross_brute.inp")
    r = m.raw
    assert r["rail"]["slices"].endswith("cross_nose.slcs")
    assert r["rail"]["lateral_position"] == pytest.approx(0.75) and r["rail"]["units"] == "mm"
    assert r["solver"]["rules"] == "contact"
    rules = case_from_dict(r, m.meta["inp"].path.parent).rules
    assert rules.contact_angle == "wheelset"
    # D = 5: CONTACT's 2-D gap mesh and its g^2 weights; D = 2: its contact locus
    assert (rules.reference_weights, rules.search_grid) == ("surface", "contact")
    (m2,) = load_inp(testbank / "examples_s+c" / "cross_locus.inp")
    rules2 = case_from_dict(m2.raw, testbank / "examples_s+c").rules
    assert (rules2.reference_weights, rules2.search_grid) == ("locus", "fine")
    assert "search_grid" not in m2.raw["solver"]
    ws = r["wheelset"]
    assert ws["position"] == 0.0 and ws["vertical_position"] == pytest.approx(-2.1275e-3)
    assert ws["combine_distance"] == pytest.approx(8e-3)
    m = load_inp(testbank / "examples_s+c" / "mbench_brute.inp", cases=[1])[0]
    assert m.raw["rail"]["units"] == "m" and "scale" not in m.raw["rail"]
    assert m.raw["wheelset"]["position"] == pytest.approx(0.239)
    assert m.raw["wheelset"]["vertical_force"] == 1e4


def test_uk_crossing_inputs(testbank):
    """mbench_brute (the S1002 wheel on the UK crossing under 10 kN, D = 5), case
    10: the wing rail and the nose both loaded, patch 1 the wing rail on the
    field side, patch 2 the nose, as CONTACT numbers them; 0.2 x 0.2 mm elements
    (every case: benchmarks/contact_testbank.py)."""
    path = testbank / "examples_s+c" / "mbench_brute.inp"
    rows = solve_inp(path, cases=[10])
    assert [r["npatch"] for r in rows] == [2, 2]
    _sc_compare(rows, path.with_suffix(".ref_out"), [10], 0.2 * 0.2)


def test_uk_crossing_small_wing_rail_patch(testbank):
    """mbench_locus (D = 2, CONTACT's contact locus) case 26: the wing-rail patch
    carries 12 % of the load on 45 elements.  Its reference point and angle are
    those of CONTACT's locus weights (each lateral line's lowest point along x,
    weighted with (-g)^2.5): x, y within 1 and 0.2 um of CONTACT's, and so are its
    elements in contact, 45 as CONTACT's (with the 2-D weights of the brute-force
    search, 7 um off in y: 50)."""
    path = testbank / "examples_s+c" / "mbench_locus.inp"
    rows = solve_inp(path, cases=[26])
    _sc_compare(rows, path.with_suffix(".ref_out"), [26], 0.2 * 0.2)
    assert rows[0]["ncon"] == 45


# ------------------------------------------------------------------ roller rigs
def test_roller_rig_inputs(testbank):
    """CONTACT's roller-rig tests from .inp (test-rollers2: D = 2): a sphere on a
    plane at RAILY0 = 200 mm (case 1), a cylinder on an ellipsoidal roller (C = 5,
    NOMRAD_R 400 mm, VPITCH_ROL; case 6) and an ellipsoid on a conical roller
    (case 10, spin): F_n within 0.1 %, p_max within 0.6 %, the elements in contact
    CONTACT's, the reference point within 3 um, F_x, F_s within 1 % of mu F_n
    (case 10's F_s 14175 against 14170 N).  The wheel's deviations by flexibility
    (E = 4): the sphere yawed by DYAWW = -0.3 rad about its profile origin (case 2,
    its geometry unchanged) and rolled by DROLLW = 0.1 rad and lifted by DZWHL
    (case 5: the contact 9.98 mm aside, at y = 209.983 mm as CONTACT's).  The
    roller's deviations (Z = 3): its profile turned by DROLLR and lowered by
    DZRAIL about the roller's fixed axis (case 9: the ellipsoidal roller's profile
    turned by 0.1 rad, the contact at y = 190.0167 mm and the profile point
    (-9.9833, 0.4996) mm as CONTACT's; case 11: the cylindrical roller turned by
    0.2 rad, its undeformed distance CONTACT's turned roller, a tilted cylinder,
    ``roller.turn = "surface"`` of the ``.inp``'s rules: F_n +0.026 %, F_s 14026
    against 14020 N, 0.02 % of mu F_n, p_max 2904 MPa and the 1281 elements as
    CONTACT's; before the rule, on the cone, F_n +0.22 %, F_s 0.53 %, 1287
    elements)."""
    from tests.conftest import read_ref_out
    path = testbank / "examples_conformal" / "test-rollers2.inp"
    rows = {r["case"]: r for r in solve_inp(path, cases=[1, 2, 5, 6, 9, 10, 11])}
    refs = read_ref_out(path.with_suffix(".ref_out"))
    for case, r in rows.items():
        (q,) = refs[case - 1]["patches"]
        assert r["converged"], r["message"]
        assert r["fn_N"] == pytest.approx(q["fn"], rel=1e-3)
        assert r["pmax_MPa"] == pytest.approx(q["pmax"], rel=6e-3)
        assert r["ncon"] == q["ncon"]
        assert [r["xcp_tr_mm"], r["ycp_tr_mm"], r["zcp_tr_mm"]] == pytest.approx(
            [q["xcp"], q["ycp"], q["zcp"]], abs=3e-3)
        for k, c in (("fx_N", "fx"), ("fs_N", "fs")):
            assert abs(r[k] - q[c]) <= 0.01 * 0.3 * q["fn"], (case, k)
    assert rows[10]["fs_N"] == pytest.approx(refs[9]["patches"][0]["fs"], rel=1e-3)
    assert rows[5]["ycp_w_mm"] == pytest.approx(9.983, abs=1e-3)
    assert [rows[9]["ycp_r_mm"], rows[9]["zcp_r_mm"]] == pytest.approx([-9.9833, 0.4996],
                                                                       abs=2e-4)
    assert rows[11]["ycp_r_mm"] == pytest.approx(-20.2588, abs=3e-3)


def test_rolling_towards_minus_x_on_a_test_rig(testbank):
    """test-rollers2 case 4 (the sphere yawed by -0.3 rad rolling backwards, VS =
    -95.5 mm/s, on the plane at RAILY0 = 200 mm): the steady problem mirrored in x.
    Measured: F_n +0.065 % (97224 against 97160 N), p_max -0.43 %, the elements in
    contact CONTACT's 1273, F_x, F_s under 0.5 N (CONTACT 0.005, 0.017 N: pure
    rolling); test-rollers3 case 4 (D = 3, the same backwards): F_x, F_s the
    negatives of its case 3, as CONTACT's are of its case 3 (991.1, -745.2 N, with
    CONTACT's rule of the rigid slip on the surfaces:
    :func:`test_yawed_sphere_with_contacts_rigid_slip_rule`)."""
    from tests.conftest import read_ref_out
    path = testbank / "examples_conformal" / "test-rollers2.inp"
    (r,) = solve_inp(path, cases=[4])
    (q,) = read_ref_out(path.with_suffix(".ref_out"))[3]["patches"]
    assert r["converged"], r["message"]
    assert r["fn_N"] == pytest.approx(q["fn"], rel=1e-3)
    assert r["pmax_MPa"] == pytest.approx(q["pmax"], rel=6e-3)
    assert r["ncon"] == q["ncon"]
    for k, c in (("fx_N", "fx"), ("fs_N", "fs")):
        assert abs(r[k] - q[c]) <= 0.01 * 0.3 * q["fn"], k
    path = testbank / "examples_conformal" / "test-rollers3.inp"
    r3, r4 = solve_inp(path, cases=[3, 4])
    assert (r4["fx_N"], r4["fs_N"]) == pytest.approx((-r3["fx_N"], -r3["fs_N"]), rel=1e-5)


def test_yawed_sphere_with_contacts_rigid_slip_rule(testbank):
    """test-rollers3 cases 3, 4 (the sphere yawed by -0.3 rad rolling along its
    heading, forwards and backwards, D = 3): with CONTACT's rule of the rigid slip on
    the surfaces (``solver.surface_slip = "midplane"``, part of ``solver.rules =
    "contact"`` that every ``.inp`` case has) F_x, F_s as CONTACT's .ref_out within
    0.05 % of mu F_n (measured: F_x 987.7 against 991.1 N, F_s -744.3 against
    -745.2 N, 0.01 and 0.003 %), F_n within 0.1 % (+0.07 %).  railcontact's own rule
    (the case-file default, ``"sections"``) gives the exact answer instead, case 1's
    forces turned by the yaw: F_s -320.6 N against the exact -322.4 N (CONTACT's
    rule 1.45 % of mu F_n from it)."""
    from tests.conftest import read_ref_out
    path = testbank / "examples_conformal" / "test-rollers3.inp"
    (m,) = load_inp(path, cases=[3])
    assert case_from_dict(m.raw, path.parent).rules.surface_slip == "midplane"
    refs = read_ref_out(path.with_suffix(".ref_out"))
    for r in solve_inp(path, cases=[3, 4]):
        (q,) = refs[r["case"] - 1]["patches"]
        assert r["converged"], r["message"]
        assert r["fn_N"] == pytest.approx(q["fn"], rel=1e-3)
        for k, c in (("fx_N", "fx"), ("fs_N", "fs")):
            assert abs(r[k] - q[c]) <= 5e-4 * 0.3 * q["fn"], (r["case"], k, r[k], q[c])
    # the case-file default: the exact answer, far from CONTACT's
    m.raw["solver"]["surface_slip"] = "sections"
    from railcontact.cases.solve import solve
    (p,) = solve(case_from_dict(m.raw, path.parent)).patches
    (q,) = refs[2]["patches"]
    assert abs(abs(p.tangential.fy) - abs(q["fs"])) > 0.01 * 0.3 * q["fn"]


def test_wheel_deviation_on_a_track(testbank):
    """m1_steady_roll.inp: a cylindrical wheel rolled by DROLLW = 5 deg about its
    profile origin (E = 5) on a circular rail at the track centre.  The contact
    moves to where the rail is inclined by 5 deg (y = 8.710 mm, z = 0.380 mm); the
    wheel turns about the design axle, so that the tilted contact gives the spin
    CONTACT gives (-8.66e-4 /mm).  F_n, F_x, F_s within 0.1 % of CONTACT's (F_n
    -0.015 %: 239.96 against 240.0 N; F_x -37.65, F_s -23.54 N as CONTACT), the
    reference point within 1 um, the creepages within 0.5 %."""
    from tests.conftest import read_ref_out
    path = testbank / "examples_trans" / "m1_steady_roll.inp"
    (r,) = solve_inp(path)
    (q,) = read_ref_out(path.with_suffix(".ref_out"))[0]["patches"]
    assert r["converged"], r["message"]
    assert r["fn_N"] == pytest.approx(q["fn"], rel=1e-3)
    assert r["fx_N"] == pytest.approx(q["fx"], rel=1e-3)
    assert r["fs_N"] == pytest.approx(q["fs"], rel=1e-3)
    assert r["pmax_MPa"] == pytest.approx(q["pmax"], rel=3e-3)
    assert [r["xcp_tr_mm"], r["ycp_tr_mm"], r["zcp_tr_mm"]] == pytest.approx(
        [q["xcp"], q["ycp"], q["zcp"]], abs=1e-3)
    assert r["delta_tr_rad"] == pytest.approx(0.0872, abs=1e-4)
    assert r["cphi_per_mm"] == pytest.approx(-8.662e-4, rel=5e-3)
    assert (r["cksi"], r["ceta"]) == pytest.approx((3.564e-3, 4.022e-3), rel=5e-3)


def test_roller_rig_rigid_slip_on_the_surfaces(testbank):
    """test-rollers3 (D = 3, kept by the later cases' D = 1): the rigid slip on the
    actual surfaces brakes the sphere rolling on the plane (F_x 1091 N on the rail,
    case 1; rolled by a deviation, case 5: 1092 N) and the cylinder on the
    ellipsoidal roller (-284.2 N, case 6), as CONTACT's within 0.2 %.  (Its yawed
    cases 3, 4, 7, 8 within 0.01 % of mu F_n with CONTACT's rule of the rigid slip
    on the surfaces, :func:`test_yawed_sphere_with_contacts_rigid_slip_rule`; the conical
    roller, case 10: tests/geometry/test_surface_search.py.)  Case 9, the roller's
    profile turned by DROLLR = 0.1 rad and lowered by DZRAIL: -284.4 N as CONTACT's
    -284.2."""
    from tests.conftest import read_ref_out
    path = testbank / "examples_conformal" / "test-rollers3.inp"
    (m,) = load_inp(path, cases=[6])
    assert m.raw["solver"]["rigid_slip"] == "surfaces" and m.raw["roller"]["radius"] == 0.4
    rows = {r["case"]: r for r in solve_inp(path, cases=[1, 5, 6, 9])}
    refs = read_ref_out(path.with_suffix(".ref_out"))
    for case, r in rows.items():
        (q,) = refs[case - 1]["patches"]
        assert r["fx_N"] == pytest.approx(q["fx"], rel=2e-3)
        assert abs(r["fs_N"]) < 1e-3 * abs(q["fx"])


def test_roller_turned_by_its_deviation_rigid_slip_on_the_surfaces(testbank):
    """test-rollers3 case 11 (the cylindrical roller turned by DROLLR = 0.2 rad, D =
    3): CONTACT's undeformed distance of the turned roller is the roller as read
    turned as a whole, a tilted cylinder (``roller.turn = "surface"``, on for every
    ``.inp`` case), where its search and the roller's rotation take the turned
    profile revolved, the cone of case 10.  The issue's tolerances: F_n, F_x, F_s
    within 1 % (of mu F_n), p_max and the elements in contact within 3 %.  Measured:
    F_n 97886 against 97860 N (+0.026 %), F_x 204.0 against 204.1 N, F_s 14028
    against 13780 N (0.85 % of mu F_n, as case 10's 0.84 %: CONTACT's 0.2 mm grid,
    0.41 % at 0.1 mm, 0.22 % at 0.05 mm), p_max 2904 MPa and the 1281 elements as
    CONTACT's.  Case 10 - case 11 as CONTACT's: F_n 185 against 190 N, F_s 148
    against 150 N (railcontact's own rule, the cone: 0 and 0; before the rule case
    11 was 1.35 % of mu F_n off)."""
    from tests.conftest import read_ref_out
    path = testbank / "examples_conformal" / "test-rollers3.inp"
    r10, r11 = solve_inp(path, cases=[10, 11])
    refs = read_ref_out(path.with_suffix(".ref_out"))
    (q10,), (q,) = refs[9]["patches"], refs[10]["patches"]
    assert r11["converged"], r11["message"]
    assert r11["fn_N"] == pytest.approx(q["fn"], rel=1e-2)
    for k, c in (("fx_N", "fx"), ("fs_N", "fs")):
        assert abs(r11[k] - q[c]) <= 0.01 * 0.3 * q["fn"], k
    assert r11["pmax_MPa"] == pytest.approx(q["pmax"], rel=3e-2)
    assert r11["ncon"] == pytest.approx(q["ncon"], rel=3e-2)
    # the rule itself: case 10 - case 11 (CONTACT's printed to 4 digits: +-10 N)
    assert r10["fn_N"] - r11["fn_N"] == pytest.approx(q10["fn"] - q["fn"], abs=15.0)
    assert r10["fs_N"] - r11["fs_N"] == pytest.approx(q10["fs"] - q["fs"], abs=15.0)
    assert r10["fn_N"] - r11["fn_N"] > 150.0
