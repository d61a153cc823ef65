"""Roller rigs: the rail replaced by a roller, against Hertz's closed form and
CONTACT's roller-rig tests (../shared/contact_testbank/examples_conformal/
test-rollers2 and test-rollers3)."""

import math

import numpy as np
import pytest

import railcontact as rc
from railcontact.cases.case import case_from_dict
from railcontact.core.materials import Material
from tests.conftest import read_ref_out

E = 2 * 82e9 * 1.28
MAT = Material(E, 0.28)


def _case(testbank, wheel, r0, rail, y0, fbd, fbp, z, roller=None, yaw=0.0, vs=0.1, vy=0.0,
          pv=-1.0, es=0.2e-3, normal="exact", tangential="exact"):
    raw = {"material": {"young_modulus": E, "poisson_ratio": 0.28},
           "friction": {"coefficient": 0.3},
           "wheel": {"profile": f"../profiles/{wheel}", "nominal_radius": r0},
           "rail": {"profile": f"../profiles/{rail}", "lateral_position": y0,
                    "inclination": 0.0},
           "wheelset": {"side": "right", "vertical_position": z, "yaw": yaw, "velocity": vs,
                        "lateral_velocity": vy, "pitch_velocity": pv,
                        "flange_back_distance": fbd, "flange_back_position": fbp},
           "solver": {"normal": normal, "tangential": tangential, "element_size": [es, es]}}
    if roller:
        raw["roller"] = roller
    return case_from_dict(raw, testbank / "examples_conformal")


#: test-rollers2/3 cases: 1a sphere R 100 mm on a plane (track), 1c the same yawed
#: -0.3 rad about a wheelset centre 200 mm away, 2a a cylinder R 133.3 mm on an
#: ellipsoidal roller (R 400 mm, lateral 100 mm), 2c the cylinder yawed -0.3 rad, 3a
#: the ellipsoid (133 x 100 mm) on a conical roller (taper 0.2 rad: spin)
CASES = {
    1: dict(wheel="circ_r100.prw", r0=0.1, rail="flat_plane.prr", y0=0.2, fbd=0.2, fbp=-0.1,
            z=0.16e-3),
    3: dict(wheel="circ_r100.prw", r0=0.1, rail="flat_plane.prr", y0=0.2, fbd=0.2, fbp=-0.1,
            z=0.16e-3, yaw=-0.3, vs=0.095533649, vy=-0.029552021),
    6: dict(wheel="flat_plane.prw", r0=0.13333333, rail="circ_r100.prr", y0=0.2, fbd=0.3,
            fbp=-0.05, z=0.16e-3, roller={"radius": 0.4, "angular_velocity": 0.25}, pv=-0.75),
    7: dict(wheel="flat_plane.prw", r0=0.13333333, rail="circ_r100.prr", y0=0.0, fbd=-0.1,
            fbp=-0.05, z=0.16e-3, roller={"radius": 0.4, "angular_velocity": 0.238834},
            yaw=-0.3, vy=-0.029552021, pv=-0.75),
    10: dict(wheel="circ_r100.prw", r0=0.13333333, rail="flat_ang200.prr", y0=0.2, fbd=0.2,
             fbp=-0.1, z=-1.87e-3, roller={"radius": 0.4, "angular_velocity": 0.24381},
             pv=-0.75),
}


@pytest.mark.parametrize("name", ["test-rollers2", "test-rollers3"])
@pytest.mark.parametrize("k", sorted(CASES))
def test_contact_roller_rig_tests(testbank, k, name):
    """Position, F_n (within 0.1 %), elements in contact (within 2 of 1273-1297),
    p_max (within 0.6 %) and the kinematic creepages (test-rollers2: CONTACT's
    planar rigid slip, which ours is; test-rollers3 evaluates the rigid slip on the
    actual surfaces, whose normal problem is the same)."""
    ref = read_ref_out(testbank / "examples_conformal" / f"{name}.ref_out")[k - 1]
    (q,) = ref["patches"]
    res = rc.solve(_case(testbank, **CASES[k]))
    (p,) = res.patches
    g, n = p.geometry, p.normal
    # within 1 um (2 um across the 0.2 rad cone of case 3a)
    assert g.position * 1e3 == pytest.approx([q["xcp"], q["ycp"], q["zcp"]],
                                             abs=3e-3 if k == 10 else 1e-3)
    assert n.normal_force == pytest.approx(q["fn"], rel=1e-3)
    assert abs(n.area / 0.04e-6 - q["ncon"]) <= 2
    assert n.pmax / 1e6 == pytest.approx(q["pmax"], rel=6e-3)
    # the sphere's profile file lies 0.05 um off its circle except at its centre;
    # on the cone (3a) 0.03 um apart
    assert n.penetration * 1e3 == pytest.approx(q["approach"], rel=3e-4 if k == 10 else 1e-4)
    if name == "test-rollers2" and k == 10:
        # on the cone: spin -2.004 1/m and F_s 14170 N (both as CONTACT's to 0.05 %);
        # xi -2.9e-5 against -3.4e-5 (a 0.5 um difference in the roller's radius
        # where its speed is taken)
        assert p.creepage[2] == pytest.approx(q["cphi"] * 1e3, rel=1e-3)
        assert p.creepage[0] == pytest.approx(q["cksi"], abs=1e-5)
        assert -p.tangential.fy == pytest.approx(q["fs"], rel=2e-3)
    elif name == "test-rollers2":
        # the sphere's 0.05 um glitch puts its wheel point 0.008 um deeper: 8e-8
        tol = 1e-7 if k in (1, 3) else 1e-9
        assert p.creepage[0] == pytest.approx(q["cksi"], abs=tol)
        assert p.creepage[1] == pytest.approx(q["ceta"], abs=tol)
        # forces on the rail in CONTACT; 8e-8 of creepage: 0.44 N
        assert abs(p.tangential.fx + q["fx"]) < (1.0 if k in (1, 3) else 0.01)


def test_contact_point_ahead_of_the_axle_with_yaw(testbank):
    """A sphere 200 mm from the wheelset centre, yawed by psi = -0.3 rad: its
    lowest point, the contact, lies at x = -200 sin(psi) = 59.104 mm ahead of the
    axle and y = 200 cos(psi); yawed the other way, behind it."""
    for yaw in (-0.3, 0.3):
        (p,) = rc.solve(_case(testbank, **dict(CASES[3], yaw=yaw, vy=0.1 * math.sin(yaw)))).patches
        assert p.geometry.position[0] == pytest.approx(-0.2 * math.sin(yaw), abs=1e-7)
        assert p.geometry.position[1] == pytest.approx(0.2 * math.cos(yaw), abs=1e-7)


def test_hertz_on_wheel_and_roller_is_the_closed_form(testbank):
    """A cylinder of 133.3 mm radius on a roller of 400 mm radius with a 100 mm
    lateral radius: the gap's curvatures are (1/R_w + 1/R_r)/2 and 1/(2 R_ry); Hertz
    on the patch equals the closed form (here a sphere of 100 mm: F = 4/3 E* sqrt(R)
    d^1.5); yawed by 0.3 rad the principal curvatures are those of the sum of the
    two rotated quadratic forms."""
    res = rc.solve(_case(testbank, **CASES[6], normal="hertz", tangential="none"))
    (p,) = res.patches
    A, B = p.geometry.curvatures
    assert A == pytest.approx(0.5 * (3 / 0.4 + 1 / 0.4), rel=1e-4)
    assert B == pytest.approx(0.5 / 0.1, rel=1e-6)
    d = p.geometry.approach
    assert d == pytest.approx(0.16e-3, rel=1e-9)
    F = 4 / 3 * MAT.contact_modulus * math.sqrt(0.1) * d ** 1.5
    assert p.normal.normal_force == pytest.approx(F, rel=2e-4)
    assert p.normal.pmax == pytest.approx(3 * F / (2 * math.pi * 0.1 * d), rel=2e-4)
    (q,) = rc.solve(_case(testbank, **CASES[7], normal="hertz", tangential="none")).patches
    c, s = math.cos(0.3), math.sin(0.3)
    M = 0.5 * np.array([[1 / 0.4 + 7.5 * c * c, 7.5 * s * c], [7.5 * s * c, 10 + 7.5 * s * s]])
    assert sorted(q.geometry.curvatures) == pytest.approx(np.linalg.eigvalsh(M), rel=1e-4)


def test_exact_model_converges_to_hertz_on_the_roller(testbank):
    """The exact model on the wheel-roller patch with 0.8, 0.4, 0.2 and 0.1 mm
    elements at the same approach: p_max approaches Hertz's as h^2 (measured 3.6e-3,
    8.0e-4, 2.1e-4, 6.9e-5), the area (an element count) as h (13, 3.5, 1.3,
    0.6 %), the force is within 3e-4 on every grid."""
    (h,) = rc.solve(_case(testbank, **CASES[6], normal="hertz", tangential="none")).patches
    ep, ea = [], []
    for es in (0.8e-3, 0.4e-3, 0.2e-3, 0.1e-3):
        (p,) = rc.solve(_case(testbank, **CASES[6], es=es, tangential="none")).patches
        ep.append(abs(p.normal.pmax / h.normal.pmax - 1))
        ea.append(abs(p.normal.area / h.normal.area - 1))
        assert p.normal.normal_force == pytest.approx(h.normal.normal_force, rel=3e-4)
    assert ep[0] > ep[1] > ep[2] > ep[3] and ep[3] < 1e-4
    assert ea[0] > ea[1] > ea[2] > ea[3] and ea[3] < 0.01


def test_creepage_from_the_rollers_surface_speed(testbank):
    """Pure rolling when the roller's surface speed equals the wheel's
    (0.25 rad/s x 400 mm = 0.75 rad/s x 133.3 mm); a roller 1 % faster gives a
    longitudinal creepage of -1 %: the wheel turns slower than the ground under
    it, as a braked wheel on track."""
    base = CASES[6]
    (p,) = rc.solve(_case(testbank, **base, tangential="none")).patches
    assert abs(p.creepage[0]) < 3e-8 and p.geometry.velocity == pytest.approx(0.1, rel=1e-3)
    fast = dict(base, roller={"radius": 0.4, "angular_velocity": 0.2525})
    (q,) = rc.solve(_case(testbank, **fast, tangential="none")).patches
    assert q.creepage[0] == pytest.approx(-0.01 / 1.005, rel=1e-3)
    # the default angular velocity rolls purely with the wheel
    dflt = dict(base, roller={"radius": 0.4})
    (r,) = rc.solve(_case(testbank, **dflt, tangential="none")).patches
    assert abs(r.creepage[0]) < 1e-7


def test_yawed_wheel_leaves_the_rollers_apex():
    """A yawed wheel touches a straight rail at x = -d tan(psi) (d its lateral
    distance from the yaw axis); on a roller of radius R_r the contact lies where
    both circles are tangent, at R_r / (R_r + R_w) of that: the DLR rig's 'the
    wheels leave the apexes of the rollers and slightly run downhill'.  The scaled
    rig of examples/roller_rig_scaled.py at yaw 0.84 mrad: -0.123 mm on the rail,
    -0.082 mm on the 0.18 m roller under the 92 mm wheel."""
    import runpy
    from pathlib import Path
    ex = runpy.run_path(str(Path(__file__).resolve().parents[1] / "examples" /
                            "roller_rig_scaled.py"))
    for psi in (0.838e-3, -2e-3):
        (p,) = rc.solve(ex["case"](0.0, psi)).patches
        (q,) = rc.solve(ex["case"](0.0, psi, roller=False)).patches
        d = q.geometry.position[1]                       # the yaw axis lies at y = 0
        # (the tread's cone adds r tan(delta) ~ 2.7 mm to d's 150 mm: 1.8 %)
        assert q.geometry.position[0] == pytest.approx(-d * math.tan(psi), rel=0.025)
        rw, rr = p.geometry.rolling_radius, p.geometry.rail_rolling_radius
        assert p.geometry.position[0] == pytest.approx(
            q.geometry.position[0] * rr / (rr + rw), rel=5e-3)
        # the roller's curvature along the track shortens the patch (Hertz)
        assert p.normal.semi_axes[0] < 0.85 * q.normal.semi_axes[0]


@pytest.mark.parametrize("k", [1, 6])
def test_rigid_slip_on_the_actual_surfaces(testbank, k):
    """``solver.rigid_slip = "surfaces"``: the rigid slip from each body's radius
    across the patch (CONTACT's D = 3, test-rollers3): the sphere rolling purely at
    its centre brakes by -y^2/(2 R^2) across the patch, F_x 1091 N on the rail in
    CONTACT (ours -1091.0 on the wheel); the cylinder on the ellipsoidal roller
    -284.2 N (ours +284.2).  (On the yawed cases 1c and 2c CONTACT's rule gives
    lateral forces of 745 and 244 N where railcontact's default gives 321 and 7 N:
    :func:`test_rigid_slip_of_a_yawed_sphere_is_the_rotated_one`; CONTACT's rule,
    ``solver.surface_slip = "midplane"``: :func:`test_contacts_midplane_rule`.)"""
    ref = read_ref_out(testbank / "examples_conformal" / "test-rollers3.ref_out")[k - 1]
    (q,) = ref["patches"]
    c = _case(testbank, **CASES[k])
    raw = dict(c.raw, solver=dict(c.raw["solver"], rigid_slip="surfaces"))
    (p,) = rc.solve(case_from_dict(raw, c.base_dir)).patches
    assert p.tangential.fx == pytest.approx(-q["fx"], rel=2e-3)
    assert abs(p.tangential.fy) < 1e-3 * abs(q["fx"])
    with pytest.raises(rc.CaseFileError, match="rigid_slip"):
        case_from_dict(dict(raw, solver=dict(raw["solver"], rigid_slip="actual")), c.base_dir)


def _slip_fields(testbank, k, *rules):
    """test-rollers3 case ``k`` (CASES) with the rigid slip on the surfaces, solved:
    the mean over its contact of each rule's slip field (s_x, s_y), the fields on
    the normal solution's grid, and the contact mask."""
    from railcontact.cases.surfaces import build_surface_case
    c = _case(testbank, **CASES[k])
    case = case_from_dict(dict(c.raw, solver=dict(c.raw["solver"], rigid_slip="surfaces")),
                          c.base_dir)
    (p,) = rc.solve(case).patches
    setup = build_surface_case(case)
    n = p.normal
    X, Y = np.meshgrid(n.x, n.y, indexing="ij")
    fields = [rule(p.geometry, setup.wheel, setup.rails[0], setup.motion, X, Y)
              for rule in rules]
    return ([np.array([a[n.contact].mean() for a in f]) for f in fields], fields, n.contact)


def test_rigid_slip_of_a_yawed_sphere_is_the_rotated_one(testbank):
    """The sphere of test-rollers3 1c, yawed by psi = -0.3 rad and moving along its
    heading, is the unyawed case 1a turned by psi: its rigid slip on the actual
    surfaces, averaged over the contact, is 1a's turned by psi, over cos(psi)
    (the creepages are relative to the rolling speed along the track, V cos psi):
    (-2.022e-4, 0) becomes (-2.022e-4, 6.255e-5), to 0.1 %.  CONTACT's D = 3
    prints mean creepages (-3.991e-4, 0) for 1a and (-3.615e-4, 2.473e-4) for 1c:
    turned by 34.38 deg = 2 |psi| and scaled by 1.0975 (1 / cos^2 psi = 1.0957),
    one turn by psi more than the bodies' motion gives; its lateral force of
    745 N (ours 321 N) follows from that: CONTACT's rule, a case option
    (``solver.surface_slip = "midplane"``, on for ``.inp`` inputs), in
    :func:`test_contacts_midplane_rule`."""
    from railcontact.geometry.surface_search import surface_slip
    mean = [_slip_fields(testbank, k, surface_slip)[0][0] for k in (1, 3)]
    psi = CASES[3]["yaw"]
    turned = np.array([[math.cos(psi), -math.sin(psi)], [math.sin(psi), math.cos(psi)]]) \
        @ mean[0] / math.cos(psi)
    assert mean[0][0] == pytest.approx(-2.022e-4, rel=1e-3) and mean[0][1] == 0.0
    assert mean[1] == pytest.approx(turned, rel=1e-3)


def test_half_space_ratio_counts_the_rollers_radius(testbank):
    """A patch on a roller reports its size against the smallest radii it touches,
    the roller's rolling radius among them: a 4 mm circle between a 133 mm
    cylinder and a roller of 400 mm (100 mm across) has max(b / 100, a / 133) = 0.04;
    on a 20 mm roller a / 20 = 0.2 (here evaluated with the Hertz ellipse)."""
    (p,) = rc.solve(_case(testbank, **CASES[6], normal="hertz", tangential="none")).patches
    a, b = p.normal.semi_axes
    # (the file's 100 mm circle: its smallest radius under the patch is 97.9 mm)
    assert p.halfspace_ratio == pytest.approx(max(b / 0.1, a / (0.4 / 3)), rel=0.03)
    small = dict(CASES[6], roller={"radius": 0.02, "angular_velocity": 5.0})
    (q,) = rc.solve(_case(testbank, **small, normal="hertz", tangential="none")).patches
    assert q.geometry.rail_rolling_radius == pytest.approx(0.02)
    assert q.halfspace_ratio == pytest.approx(
        max(q.normal.semi_axes[1] / 0.1, q.normal.semi_axes[0] / 0.02), rel=0.03)


def test_contacts_midplane_rule(testbank):
    """CONTACT's rigid slip on the surfaces (``solver.surface_slip = "midplane"``,
    :func:`railcontact.geometry.surface_search.midplane_slip`): each body's velocity
    at its surface point, turned onto the mid-plane in the (x, n) plane only.  On
    the unyawed sphere (case 1a) it is railcontact's own rule to 1e-7 (both remove
    the slip of the curvature along x); on the sphere yawed by psi = -0.3 rad (1c)
    the turn in the (x, n) plane leaves a lateral slip: its mean over the contact
    (-1.828e-4, 1.2525e-4) against the turned (-2.022e-4, 6.255e-5), in the
    direction of CONTACT's printed creepages (-3.615e-4, 2.473e-4), to 0.2 %."""
    from railcontact.geometry.surface_search import midplane_slip, surface_slip
    _, (own, mid), contact = _slip_fields(testbank, 1, surface_slip, midplane_slip)
    assert np.abs(mid[0] - own[0])[contact].max() < 1e-7
    assert np.abs(mid[1])[contact].max() < 1e-12
    (own3, mid3), _, _ = _slip_fields(testbank, 3, surface_slip, midplane_slip)
    assert own3 == pytest.approx([-2.022e-4, 6.255e-5], rel=2e-3)
    assert mid3 == pytest.approx([-1.828e-4, 1.2525e-4], rel=2e-3)
    # CONTACT's printed mean creepages (over its interpenetration, a larger region,
    # so larger in size: -3.991e-4 unyawed against our -2.022e-4) point the same way
    assert mid3[1] / mid3[0] == pytest.approx(2.473e-4 / -3.615e-4, rel=3e-3)
