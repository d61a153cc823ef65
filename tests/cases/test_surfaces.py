"""A wheel on rail surfaces against CONTACT's switch-and-crossing testbank
(../shared/contact_testbank/examples_s+c): an artificial nose rising 1:10, a wing
rail shifting 1:10, both together, and the S1002 wheel on the UK crossing of the
S&C benchmark (148 slices), where the load passes from the wing rail to the nose.

Tolerances (every patch): the number of patches; the reference point within
10 um (CONTACT prints 0.1 um; ours lie within 2 um on the patches that carry more
than 2 % of the load); F_n within 1 % and the area (elements in contact of the
same 0.2 x 0.05 or 0.2 x 0.2 mm grid) within 3 %; on patches that carry less
than 2 % of the load (a strip of 2 to 9 elements where the other rail is just
touched) F_n within 10 % of it or 1e-3 of the load, the position within 0.1 mm."""

import numpy as np
import pytest

import railcontact as rc
from railcontact.cases.case import case_from_dict
from railcontact.core.errors import CaseFileError
from tests.conftest import read_ref_out

#: CONTACT's material: G = 82 GPa, nu = 0.28
E = 2 * 82e9 * 1.28


def _case(testbank, slcs, s, y=0.0, z=None, fz=None, ds=0.05e-3, contact_angle="wheelset",
          solver=None):
    raw = {"material": {"young_modulus": E, "poisson_ratio": 0.28},
           "friction": {"coefficient": 0.3},
           "wheel": {"profile": "../profiles/MBench_S1002_v3.prw", "nominal_radius": 0.46},
           "rail": {"slices": f"../profiles/{slcs}", "lateral_position": 0.75,
                    "vertical_position": 0.0},
           "wheelset": {"side": "right", "position": s, "lateral_shift": y, "velocity": 2.0,
                        "pitch_velocity": -4.34811810, "flange_back_distance": 1.36,
                        "flange_back_position": -0.07},
           "solver": {"normal": "exact", "tangential": "exact", "element_size": [0.2e-3, ds],
                      "contact_angle": contact_angle, **(solver or {})}}
    if z is not None:
        raw["wheelset"]["vertical_position"] = z
    else:
        raw["wheelset"]["vertical_force"] = fz
    return case_from_dict(raw, testbank / "examples_s+c")


def _compare(res, ref, load, dA, angle_tol=1e-3):
    ours = res.patches
    assert len(ours) == len(ref["patches"])
    for p, q in zip(ours, ref["patches"]):
        g, n = p.geometry, p.normal
        big = q["fn"] > 0.02 * load
        tol = 0.01 if big else 0.1
        assert g.position * 1e3 == pytest.approx([q["xcp"], q["ycp"], q["zcp"]], abs=tol)
        if big:
            assert n.normal_force == pytest.approx(q["fn"], rel=0.01)
            assert n.area / dA == pytest.approx(q["ncon"], rel=0.03)
            assert g.contact_angle == pytest.approx(q["delta"], abs=angle_tol)
            assert n.penetration * 1e3 == pytest.approx(q["approach"], rel=0.015)
        else:
            assert abs(n.normal_force - q["fn"]) <= max(0.1 * q["fn"], 1e-3 * load)


@pytest.mark.parametrize("name,slcs,s,z", [
    ("cross_brute", "cross_nose.slcs", 0.0, -2.1275e-3),
    ("cross_locus", "cross_nose.slcs", 0.0, -2.1275e-3),
    ("wing_brute", "wing_rail.slcs", 0.1, 0.6589e-3),
    ("wing_locus", "wing_rail.slcs", 0.1, 0.6589e-3),
    ("cross+wing", "cross+wing.slcs", 0.1, 2.5212e-3)])
def test_artificial_nose_and_wing_rail(testbank, name, slcs, s, z):
    ref = read_ref_out(testbank / "examples_s+c" / f"{name}.ref_out")[0]
    res = rc.solve(_case(testbank, slcs, s, z=z))
    assert res.converged
    _compare(res, ref, 1e4, 0.2e-3 * 0.05e-3)
    # the creepages and tangential forces follow (forces on the rail in CONTACT)
    (p,) = res.patches
    (q,) = ref["patches"]
    assert p.creepage[0] == pytest.approx(q["cksi"], rel=0.01)
    assert p.tangential.fx == pytest.approx(-q["fx"], rel=0.01)


def test_nose_patch_ahead_of_the_axle(testbank):
    """The nose rising 1:10 touches the wheel 45.76 mm ahead of its axle (where the
    wheel's slope is 1:10), CONTACT's brute-force result to 0.1 um, with its
    approach, pressure and creepages."""
    ref = read_ref_out(testbank / "examples_s+c" / "cross_brute.ref_out")[0]["patches"][0]
    res = rc.solve(_case(testbank, "cross_nose.slcs", 0.0, z=-2.1275e-3, contact_angle="local"))
    (p,) = res.patches
    assert p.geometry.position[0] * 1e3 == pytest.approx(45.7571, abs=2e-4)
    assert p.normal.penetration * 1e3 == pytest.approx(ref["approach"], rel=1e-3)
    assert p.normal.pmax / 1e6 == pytest.approx(ref["pmax"], rel=2e-3)
    assert p.normal.area / (0.2e-3 * 0.05e-3) == pytest.approx(ref["ncon"], abs=1)
    assert p.geometry.s == pytest.approx(0.0457571, abs=1e-7)
    assert p.creepage == pytest.approx((ref["cksi"], ref["ceta"], ref["cphi"] * 1e3), rel=2e-3)
    assert (p.tangential.fx, p.tangential.fy) == pytest.approx((-ref["fx"], -ref["fs"]), rel=2e-3)
    d = res.to_dict()["patches"][0]
    assert d["rail"] == "cross_nose" and d["position"][0] == pytest.approx(0.0457571, abs=1e-7)


#: mbench_brute case 7: the nose patch is one element (0.2 mm) wide, so its count
#: of elements goes 19, 20, 22, 24 when the element lattice moves 0, 3, 5, 10 um
#: sideways (F_n within 0.3 %); our reference point lies 3 um from CONTACT's
MBENCH_ONE_COLUMN = pytest.mark.xfail(
    strict=True, reason="nose patch one element wide: 19 against CONTACT's 22 elements "
    "(-14 %) with F_n -0.27 %, p_max +0.09 %, approach -0.03 %")


@pytest.mark.parametrize("case", [pytest.param(c, marks=MBENCH_ONE_COLUMN) if c == 7 else c
                                  for c in range(1, 36)])
def test_uk_crossing_transfer_from_wing_rail_to_nose(testbank, case):
    """The S&C benchmark's UK crossing at s = 239 mm, the wheelset moving 0.81 to
    1.15 mm to the right under 10 kN (CONTACT's brute-force search), all 35 cases:
    the wing rail alone (1-4), a nose patch appearing 7.8 mm ahead of it (4.6 mm
    ahead of the axle, 5), both loaded (6-29), the wing rail's last touch (30), the
    nose alone (31-35)."""
    ref = read_ref_out(testbank / "examples_s+c" / "mbench_brute.ref_out")[case - 1]
    res = rc.solve(_case(testbank, "uk_crossing.slcs", ref["s"] * 1e-3, y=ref["y"] * 1e-3,
                         fz=1e4, ds=0.2e-3))
    assert res.converged
    assert res.pose.vertical * 1e3 == pytest.approx(ref["z"], abs=2e-4)
    _compare(res, ref, 1e4, 0.2e-3 * 0.2e-3)


@pytest.mark.parametrize("case", [10, 20])
def test_uk_crossing_against_contacts_locus_search(testbank, case):
    """The same inputs with CONTACT's contact locus (D = 2): over the 35 cases its
    reference points lie up to 68 um (x) and 38 um (y) from its brute-force ones
    (the tiny patches) and 12 um / 30 um on these; ours (one search, which meets
    the brute-force ones to 2 um) within 40 um of them, F_n within 1 %."""
    ref = read_ref_out(testbank / "examples_s+c" / "mbench_locus.ref_out")[case - 1]
    res = rc.solve(_case(testbank, "uk_crossing.slcs", ref["s"] * 1e-3, y=ref["y"] * 1e-3,
                         fz=1e4, ds=0.2e-3))
    for p, q in zip(res.patches, ref["patches"]):
        assert p.geometry.position * 1e3 == pytest.approx([q["xcp"], q["ycp"], q["zcp"]],
                                                          abs=0.04)
        assert p.normal.normal_force == pytest.approx(q["fn"], rel=0.01)


def test_uk_crossing_with_interrupted_slices(testbank):
    """mbench_intrup: 20 slices of the UK crossing (uk_interrupt_v2.slcs) whose
    first seven hold the wing rail only (the nose's features missing, CONTACT's
    'interruptions'); the nose's parts begin at the 8th slice, s = 118.94 mm.  The
    wheel at a prescribed position on the wing rail from s = 110 to 130 mm, 43
    cases, through the nose's beginning: every case one patch, F_n within 0.05 %
    and elements in contact within 0.5 % of CONTACT's (tolerances 1 % and 3 %),
    the reference point within 10 um (measured up to 8.7 um) but for the last two
    cases, where the wing rail's crown rises under the wheel (F_n +2.8 % from
    s = 128 to 130 mm) and the reference point moves by 40 um per mm of s: 31 and
    22 um (an expected failure below)."""
    refs = read_ref_out(testbank / "examples_s+c" / "mbench_intrup.ref_out")
    assert len(refs) == 43
    for ref in refs:
        res = rc.solve(_case(testbank, "uk_interrupt_v2.slcs", ref["s"] * 1e-3,
                             y=ref["y"] * 1e-3, z=ref["z"] * 1e-3, ds=0.2e-3))
        assert res.converged
        (p,) = res.patches
        (q,) = ref["patches"]
        g, n = p.geometry, p.normal
        if ref["case"] <= 41:                    # 42, 43: test_..._last_two_cases
            assert g.position * 1e3 == pytest.approx([q["xcp"], q["ycp"], q["zcp"]],
                                                      abs=0.01)
        assert n.normal_force == pytest.approx(q["fn"], rel=0.01)
        assert n.area / (0.2e-3 * 0.2e-3) == pytest.approx(q["ncon"], rel=0.03)
        assert g.contact_angle == pytest.approx(q["delta"], abs=1e-3)
        assert n.penetration * 1e3 == pytest.approx(q["approach"], rel=0.015)



@pytest.mark.xfail(strict=True, reason="mbench_intrup 42, 43: reference point 31 and 22 um "
                   "from CONTACT's (cause not found)")
@pytest.mark.parametrize("case", [42, 43])
def test_uk_crossing_with_interrupted_slices_last_two_cases(testbank, case):
    """The reference point of mbench_intrup's last two cases within 10 um."""
    ref = read_ref_out(testbank / "examples_s+c" / "mbench_intrup.ref_out")[case - 1]
    res = rc.solve(_case(testbank, "uk_interrupt_v2.slcs", ref["s"] * 1e-3,
                         y=ref["y"] * 1e-3, z=ref["z"] * 1e-3, ds=0.2e-3))
    (q,) = ref["patches"]
    assert res.patches[0].geometry.position * 1e3 == pytest.approx(
        [q["xcp"], q["ycp"], q["zcp"]], abs=0.01)

def test_nose_that_begins_between_slices(testbank):
    """cw_interrupt (cross+wing_extd.slcs: ten slices of a straight stock rail
    ahead of the artificial nose and wing rail, the nose's features missing
    there, so that the nose begins at s = 0 with a vertical face).

    Case 1 (10 kN, the wheelset 40 mm to the field side, on the wing rail 1.2 mm
    behind the kink where it leaves the straight line): F_n, vertical position,
    elements in contact (-1.1 %) as CONTACT's; the reference point 8 um from
    CONTACT's in y, 118 um in x (CONTACT ran this case with its contact locus,
    D = 2, whose reference points differ from the brute-force ones by up to
    68 um in x on the UK crossing).

    Case 2 (the wheel at s = 0 on the nose's crown, a prescribed position): the
    nose's front face cuts the patch at x = 0: contact only ahead of it, one
    patch, the elements in contact within 0.3 %, the approach within 0.1 %, the
    reference point 15 um (x) and 12 um (y) from CONTACT's.  The cut makes the
    reference point (the weighted mean over the interpenetration region) move by
    22 um per um of the region's depth, x and y alike: 0.7 um less depth (1.8 %)
    puts both within 1 um of CONTACT's.  F_n is 1.4 % below CONTACT's (short of
    the 1 % aimed at): the grid of elements lies on a lattice through the
    reference point, so its first row behind the cut, where the pressure is
    highest, starts 15 um further ahead than CONTACT's (one row more, the face
    0.1 mm earlier: +2.3 %); with the reference point moved onto CONTACT's, -1.1 %
    and 990 elements against 991, the rest from the patch's rear (x = 3.5-5 mm,
    1-3 elements fewer per row)."""
    refs = read_ref_out(testbank / "examples_s+c" / "cw_interrupt.ref_out")
    q = refs[0]["patches"][0]
    res = rc.solve(_case(testbank, "cross+wing_extd.slcs", 0.0, y=0.04, fz=1e4))
    assert res.converged
    (p,) = res.patches
    assert res.pose.vertical * 1e3 == pytest.approx(refs[0]["z"], abs=5e-4)
    assert p.normal.normal_force == pytest.approx(q["fn"], rel=0.01)
    assert p.normal.area / (0.2e-3 * 0.05e-3) == pytest.approx(q["ncon"], rel=0.03)
    assert p.geometry.position[1:] * 1e3 == pytest.approx([q["ycp"], q["zcp"]], abs=0.01)

    q = refs[1]["patches"][0]
    res = rc.solve(_case(testbank, "cross+wing_extd.slcs", 0.0, z=2.5287e-3))
    assert res.converged
    (p,) = res.patches
    g, n = p.geometry, p.normal
    x = g.position[0] + n.x[n.contact.any(axis=1)]
    assert x.min() > 0.0 and x.min() < 0.2e-3
    assert n.area / (0.2e-3 * 0.05e-3) == pytest.approx(q["ncon"], rel=0.01)
    assert n.penetration * 1e3 == pytest.approx(q["approach"], rel=0.002)


@pytest.mark.parametrize("case", [1, pytest.param(2, marks=pytest.mark.xfail(
    strict=True, reason="cw_interrupt 2 on CONTACT's gap mesh: F_n -0.87 % (within 1 %), "
    "the reference point 14 um (x) and 13 um (y) from CONTACT's: on CONTACT's own mesh "
    "nodes our gap is 0.12 to 0.55 um larger from x = 0.9 mm on, up to 1.9 um on the "
    "field-side edge lines (its rail interpolated between slices, its wheel between "
    "profile points), which the cut amplifies (22 um per um of depth)"))])
def test_nose_that_begins_between_slices_targets(testbank, case):
    """cw_interrupt at the issue's tolerances with CONTACT's rules of each case (the
    ``.inp``'s): case 1 (D = 2) with the contact locus's weights, its x within 2 um
    of CONTACT's (measured 1.0 um; with the 2-D weights 118 um); case 2 (D = 5) on
    CONTACT's gap mesh (x nodes 0.2995 mm apart through the wheel's lowest line,
    0.0375 mm laterally), its F_n within 1 % (measured -0.87 %; on the default
    fine grid -1.4 %) and its reference point within 10 um."""
    ref = read_ref_out(testbank / "examples_s+c" / "cw_interrupt.ref_out")[case - 1]
    q = ref["patches"][0]
    if case == 1:
        kw = dict(y=0.04, fz=1e4, solver={"reference_weights": "locus"})
    else:
        kw = dict(z=2.5287e-3, solver={"search_grid": "contact"})
    res = rc.solve(_case(testbank, "cross+wing_extd.slcs", 0.0, **kw))
    (p,) = res.patches
    if case == 1:
        assert p.geometry.position[0] * 1e3 == pytest.approx(q["xcp"], abs=0.002)
    else:
        assert p.normal.normal_force == pytest.approx(q["fn"], rel=0.01)
        assert p.geometry.position * 1e3 == pytest.approx([q["xcp"], q["ycp"], q["zcp"]],
                                                          abs=0.01)


def test_surface_case_errors(testbank):
    base = _case(testbank, "cross_nose.slcs", 0.0, z=-2.1275e-3).raw
    bad = [({"rail": {"slices": "x.slcs"}}, "lateral_position"),
           ({"rail": {"slices": "x.slcs", "profile": "60E1", "lateral_position": 0.75}},
            "either profile or slices"),
           ({"rail": {"slices": "x.slcs", "lateral_position": 7.5}}, "lateral_position"),
           ({"wheelset": dict(base["wheelset"], side="both")}, "one wheel"),
           ({"roller": {"radius": 0.0}}, "roller"),
           ({"solver": dict(base["solver"], contact_angle="mean")}, "contact_angle"),
           ({"solver": dict(base["solver"], reference_weights="mean")}, "reference_weights"),
           ({"solver": dict(base["solver"], search_grid="coarse")}, "search_grid")]
    for change, match in bad:
        with pytest.raises(CaseFileError, match=match):
            raw = dict(base, **change)
            rc.solve(case_from_dict(raw, testbank / "examples_s+c"))
    raw = dict(base, rail=dict(base["rail"], slices="../profiles/none.slcs"))
    with pytest.raises(rc.ProfileError, match="does not exist"):
        rc.solve(case_from_dict(raw, testbank / "examples_s+c"))
    raw = dict(base, wheelset=dict(base["wheelset"], position=5.0))
    with pytest.raises(rc.ContactNotFoundError):
        rc.solve(case_from_dict(raw, testbank / "examples_s+c"))


def _uk_two_rails(testbank, s, element=0.4e-3):
    """The UK crossing's slices as two rails, the wing rail on the field side of
    the flangeway (rail-profile y > 0) and the nose on its gauge side."""
    raw = {"material": {"young_modulus": E, "poisson_ratio": 0.28},
           "friction": {"coefficient": 0.3},
           "wheel": {"profile": "../profiles/MBench_S1002_v3.prw", "nominal_radius": 0.46},
           "rails": [{"name": "wing rail", "slices": "../profiles/uk_crossing.slcs",
                      "lateral_position": 0.75, "lateral_range": [0.0, 0.2]},
                     {"name": "nose", "slices": "../profiles/uk_crossing.slcs",
                      "lateral_position": 0.75, "lateral_range": [-0.1, 0.0]}],
           "wheelset": {"side": "right", "position": s, "vertical_force": 1e4, "velocity": 2.0,
                        "pitch_velocity": -4.34811810},
           "solver": {"normal": "exact", "tangential": "exact",
                      "element_size": [element, element]}}
    return case_from_dict(raw, testbank / "examples_s+c")


def test_transfer_along_the_uk_crossing(testbank):
    """A quasi-static pass along s through the UK crossing, the wheelset centred,
    10 kN: the load moves from the wing rail (3.5 mm behind the axle) to the nose
    (5.0 mm ahead of it) within about 4 mm of travel, s = 250.4 to 254.0 mm, both
    carrying it in between; the wing rail's share falls and the nose's grows
    monotonically."""
    from railcontact.cases.crossing import sweep_along_track, transfer_range
    ds = sweep_along_track(_uk_two_rails(testbank, 0.25),
                           np.arange(0.2496, 0.2553, 0.0008), progress=False)
    assert list(ds["rail"].values) == ["wing rail", "nose"]
    assert bool(ds["converged"].all())
    assert np.allclose(ds["total_Fz"], 1e4, rtol=1e-4)
    fz = ds["Fz"].fillna(0.0)
    wing, nose = fz.sel(rail="wing rail").values, fz.sel(rail="nose").values
    assert wing[0] == pytest.approx(1e4, rel=1e-4) and nose[-1] == pytest.approx(1e4, rel=1e-4)
    assert np.all(np.diff(wing) <= 1.0) and np.all(np.diff(nose) >= -1.0)
    both = (ds["n_patches"] > 0).all("rail").values
    assert both.sum() >= 4
    lo, hi = transfer_range(ds, "wing rail", "nose")
    # measured on this 0.8 mm step: the nose above 2 % of the load from 251.2 mm, the
    # wing rail up to 253.6 mm (on a 0.4 mm step: 250.4 to 254.0 with any share)
    assert lo == pytest.approx(0.2512, abs=1e-6) and hi == pytest.approx(0.2536, abs=1e-6)
    x = ds["x"].where(ds["n_patches"] > 0)
    assert float(x.sel(rail="wing rail").max()) == pytest.approx(-3.5e-3, abs=0.2e-3)
    assert float(x.sel(rail="nose").min()) == pytest.approx(5.0e-3, abs=0.2e-3)


def test_two_rails_of_one_slices_file_equal_the_one_rail(testbank):
    """Naming the wing rail and the nose of one slices file as two rails (each its
    lateral range) changes nothing but the names (mbench case 18: both loaded)."""
    ref = read_ref_out(testbank / "examples_s+c" / "mbench_brute.ref_out")[17]
    one = rc.solve(_case(testbank, "uk_crossing.slcs", ref["s"] * 1e-3, y=ref["y"] * 1e-3,
                         fz=1e4, ds=0.2e-3, contact_angle="local"))
    case = _uk_two_rails(testbank, ref["s"] * 1e-3, element=0.2e-3)
    raw = dict(case.raw, wheelset=dict(case.raw["wheelset"], lateral_shift=ref["y"] * 1e-3))
    two = rc.solve(case_from_dict(raw, testbank / "examples_s+c"))
    assert [p.geometry.rail for p in two.patches] == ["wing rail", "nose"]
    for a, b in zip(one.patches, two.patches):
        assert b.geometry.position == pytest.approx(a.geometry.position, abs=1e-9)
        assert b.normal.normal_force == pytest.approx(a.normal.normal_force, rel=1e-6)
    forces = two.rail_forces()
    assert forces["wing rail"] + forces["nose"] == pytest.approx(1e4, rel=1e-4)


def test_slices_written_and_read_back(tmp_path):
    from railcontact.geometry.sliced_surface import SlicedSurface
    from railcontact.profiles.slices import artificial_crossing, read_slices, write_slices
    nose, wing = artificial_crossing(n=9)
    p = write_slices(nose, tmp_path / "nose.slcs")
    back = read_slices(p)
    assert np.allclose(back.s, nose.s, atol=1e-9)
    s = np.array([0.031, 0.2])
    y = np.array([-0.018, -0.012])
    assert np.allclose(SlicedSurface(back).height(s, y)[0], SlicedSurface(nose).height(s, y)[0],
                       atol=1e-9)


def test_left_wheel_is_the_mirrored_right_wheel(testbank):
    """A left wheel on the same rails (placed in its side frame, y to its field
    side) at the mirrored pose: positions and contact angles mirrored, the
    longitudinal creepage and force equal, the lateral and spin ones negated."""
    def run(side, y, yaw):
        case = _case(testbank, "cross_nose.slcs", 0.0, y=y, fz=1e4)
        raw = dict(case.raw, wheelset=dict(case.raw["wheelset"], side=side, yaw=yaw))
        return rc.solve(case_from_dict(raw, testbank / "examples_s+c")).patches[0]
    r = run("right", 1e-3, 2e-3)
    left = run("left", -1e-3, -2e-3)
    assert left.geometry.side == "left"
    # (to the vertical iteration's tolerance: the two solves take other paths)
    assert left.geometry.position == pytest.approx(r.geometry.position * [1, -1, 1], abs=1e-8)
    assert left.geometry.contact_angle == pytest.approx(-r.geometry.contact_angle, abs=1e-8)
    assert left.creepage == pytest.approx(np.array(r.creepage) * [1, -1, -1], rel=1e-6,
                                          abs=1e-10)
    assert left.normal.normal_force == pytest.approx(r.normal.normal_force, rel=1e-5)
    assert left.tangential.fx == pytest.approx(r.tangential.fx, rel=1e-4)
    assert left.tangential.fy == pytest.approx(-r.tangential.fy, rel=1e-4)


def test_profile_options_reach_the_surfaces(testbank):
    """A surface case reads its wheel as profile cases do: with the [wheel] units and
    CONTACT's processing (here a 1.05 scale), not the raw file (ignored before)."""
    from railcontact.profiles import ProfileOptions
    from railcontact.profiles.library import get_profile
    from railcontact.cases.surfaces import build_surface_case
    raw = {"wheel": {"profile": "../profiles/MBench_S1002_v3.prw", "nominal_radius": 0.46},
           "rail": {"profile": "../profiles/MBench_UIC60_v3.prr", "lateral_position": 0.75,
                    "vertical_position": 0.0, "units": "mm"},
           "wheelset": {"side": "right", "vertical_force": 1e4}}
    plain = build_surface_case(case_from_dict(raw, testbank / "examples_s+c")).wheel.profile
    raw["wheel"]["scale"] = 1.05
    got = build_surface_case(case_from_dict(raw, testbank / "examples_s+c")).wheel.profile
    want = get_profile(testbank / "profiles" / "MBench_S1002_v3.prw", "wheel",
                       options=ProfileOptions.from_table({"scale": 1.05}, "wheel"))
    np.testing.assert_allclose(got.z_at(want.y[5:-5]), want.z[5:-5], atol=1e-12)
    assert np.ptp(got.y) == pytest.approx(1.05 * np.ptp(plain.y), rel=1e-9)


def test_wheel_beyond_the_last_slice(testbank):
    """A wheel beyond the last slice of a rail (cross_nose.slcs covers s = -0.1 to
    0.1 m) is named: a warning in the result's status where the search still
    reaches back into the slices (s = 0.12 m, the wheel lowered onto the nose's
    end: the patch lies at s <= 0.1 m), the
    error's message where nothing is left under the wheel (s = 0.3 m)."""
    from railcontact.core.errors import ContactNotFoundError
    res = rc.solve(_case(testbank, "cross_nose.slcs", 0.12, z=-9.3e-3))
    assert any("beyond the last slice of the rail 'cross_nose'" in w
               for w in res.status.warnings)
    assert all(p.geometry.s <= 0.1 + 1e-9 for p in res.patches)
    ok = rc.solve(_case(testbank, "cross_nose.slcs", 0.0, z=-2.1275e-3))
    assert not any("beyond" in w for w in ok.status.warnings)
    with pytest.raises(ContactNotFoundError, match=r"s = 0\.3 m lies beyond the last slice "
                                                   r"of the rail 'cross_nose'"):
        rc.solve(_case(testbank, "cross_nose.slcs", 0.3, fz=1e4))


def test_patch_separation_distance_on_rail_surfaces(testbank):
    """wheelset.combine_distance (CONTACT's D_SEP) on rail surfaces: mbench_brute's
    case 10 has a wing-rail patch and a nose patch 67 mm apart laterally (two
    patches at D_SEP = 8 mm, CONTACT's); at 80 mm they are one patch, which
    carries what the two carried together (the same interpenetration, 1 %)."""
    ref = read_ref_out(testbank / "examples_s+c" / "mbench_brute.ref_out")[9]
    case = _case(testbank, "uk_crossing.slcs", ref["s"] * 1e-3, y=ref["y"] * 1e-3,
                 z=ref["z"] * 1e-3, ds=0.2e-3)
    two = rc.solve(case_from_dict(dict(case.raw, wheelset=dict(
        case.raw["wheelset"], combine_distance=8e-3)), testbank / "examples_s+c"))
    one = rc.solve(case_from_dict(dict(case.raw, wheelset=dict(
        case.raw["wheelset"], combine_distance=80e-3)), testbank / "examples_s+c"))
    assert len(two.patches) == 2 and len(one.patches) == 1
    # numbered from the field side: the wing rail's patch first
    assert two.patches[0].geometry.position[1] > two.patches[1].geometry.position[1]
    assert sum(p.normal.normal_force for p in two.patches) == pytest.approx(
        sum(q["fn"] for q in ref["patches"]), rel=0.01)


def test_profile_processing_of_slices(testbank):
    """CONTACT's profile processing keys on a rail given by slices reach every
    slice: a scale of 1.05 widens each slice's lateral extent by 5 %."""
    from railcontact.cases.surfaces import build_surface_case
    base = _case(testbank, "cross_nose.slcs", 0.0, z=-2.1275e-3).raw
    plain = build_surface_case(case_from_dict(base, testbank / "examples_s+c"))
    raw = dict(base, rail=dict(base["rail"], scale=1.05))
    scaled = build_surface_case(case_from_dict(raw, testbank / "examples_s+c"))
    a = plain.rails[0].surface.slices.profiles[3]
    b = scaled.rails[0].surface.slices.profiles[3]
    assert np.ptp(b.y) == pytest.approx(1.05 * np.ptp(a.y), rel=1e-9)
    with pytest.raises(CaseFileError, match="unknown key rail.smooth"):
        case_from_dict(dict(base, rail=dict(base["rail"], smooth=1.0)),
                       testbank / "examples_s+c")
