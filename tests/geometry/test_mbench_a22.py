"""Manchester contact benchmark A-2.2 against CONTACT's reference results.

Same profiles, loads (10 kN per wheel), shifts and yaw (2.4 mrad per mm), friction
0.3, G = 82 GPa, nu = 0.28, V = 2 m/s, and CONTACT's pitch velocity per case.
The rolling radius compared is the wheel radius at the contact point, r_Q of the
reference README (section 2.6), which accounts for contact ahead of the axle.
"""

import math

import numpy as np
import pytest

from railcontact import case_from_dict, solve
from railcontact.geometry import Track, Wheelset, find_contact
from railcontact.geometry.search import WheelsetMotion
from railcontact.profiles import read_profile
from tests.conftest import read_csv

SHIFTS = [0.5 * k for k in range(21)]
#: shifts where the tread contact jumps (conformal tread at 0.5 mm; tread plus
#: flange root at 5.0 mm): the Hertz-based approach of the search does not
#: reproduce CONTACT's weighted reference point there (see the issue note)
JUMPS = {0.5, 5.0}


def _ref(refdir):
    rows = read_csv(refdir / "mbench_a22" / "a22_patches.csv")
    extra = {(r["side"], r["case"]): r for r in read_csv(refdir / "mbench_a22" / "a22_patches_extra.csv")}
    out = {}
    for r in rows:
        x = float(extra[(r["side"], r["case"])]["xcp_w_mm"])
        rq = math.hypot(float(r["r_wheel_mm"]) + float(r["approach_mm"])
                        * math.cos(float(r["delta_tr_rad"])), x)
        out[(r["side"], float(r["y_ws_mm"]))] = {**r, "r_q_mm": rq}
    return out


def _raw(refdir, y, vpitch, builtin):
    prof = refdir / "profiles"
    return {"material": {"young_modulus": 2 * 82e9 * 1.28, "poisson_ratio": 0.28},
            "friction": {"coefficient": 0.3},
            "wheel": {"profile": "S1002" if builtin else str(prof / "MBench_S1002_v3.prw"),
                      "nominal_radius": 0.46},
            "rail": {"profile": "60E1" if builtin else str(prof / "MBench_UIC60_v3.prr"),
                     "inclination": math.atan(1 / 40) if builtin else 0.0},
            "wheelset": {"lateral_shift": y * 1e-3, "yaw": 2.4e-3 * y, "vertical_force": 1e4,
                         "velocity": 2.0, "pitch_velocity": vpitch},
            "solver": {"normal": "hertz", "tangential": "fastsim"}}


@pytest.fixture(scope="module", params=["files", "builtin"])
def a22(request, refdir):
    ref = _ref(refdir)
    res = {}
    for y in SHIFTS:
        vp = float(ref[("right", y)]["vpitch_rad_s"])
        res[y] = solve(case_from_dict(_raw(refdir, y, vp, request.param == "builtin")))
    return request.param, ref, res


def _dr(res):
    c = res.contact
    return (c.equivalent_point("right")["rolling_radius"]
            - c.equivalent_point("left")["rolling_radius"]) * 1e3


#: known misses against the 0.05 mm target, measured (reference points weighted as
#: CONTACT weights them, GAP_WEIGHT; elsewhere within 0.003 mm with the files): files
#: 5.0 mm +0.053; built-in profiles 4.5 mm -0.063, 5.0 mm -1.815 (the benchmark rail
#: file departs from the nominal 60E1 arcs by up to 0.04 mm near the gauge shoulder,
#: which moves the contact point of the built-in rail).  0.5 mm (-0.065 and -0.091
#: with the deepest point's curvature alone) meets it with the force curvature
#: (geometry.patch_curvature: -0.014 and -0.044 mm)
KNOWN_MISSES = {"files": JUMPS - {0.5}, "builtin": (JUMPS - {0.5}) | {4.5}}


@pytest.mark.parametrize("y", SHIFTS)
def test_rolling_radius_difference(a22, y, request):
    kind, ref, res = a22
    d = _dr(res[y]) - (ref[("right", y)]["r_q_mm"] - ref[("left", y)]["r_q_mm"])
    tol = 0.05 if y <= 6.0 else 0.5
    if y in KNOWN_MISSES[kind]:
        request.applymarker(pytest.mark.xfail(strict=True, reason=f"known miss {d:+.3f} mm"))
    assert abs(d) <= tol, f"{kind}: delta_r off by {d:+.4f} mm at {y} mm"


@pytest.mark.parametrize("y", SHIFTS)
def test_contact_angles(a22, y, request):
    kind, ref, res = a22
    # measured: within 0.23 deg with the files (0.5 mm), 0.35 deg with the built-in
    # profiles except 5.0 mm (two-region patch, tread and flange root): 8.5 deg
    if kind == "builtin" and y == 5.0:
        request.applymarker(pytest.mark.xfail(strict=True, reason="contact jump"))
    for side in ("left", "right"):
        ours = res[y].contact.equivalent_point(side)["contact_angle"]
        assert math.degrees(abs(ours - float(ref[(side, y)]["delta_tr_rad"]))) <= 0.5, side


def test_normal_forces_and_approach(refdir):
    """Hertz + FASTSIM with the reference profile files: patch normal force within
    1.5 % and approach within 3 % of CONTACT's exact solution (tread and flange)."""
    ref = _ref(refdir)
    res = {y: solve(case_from_dict(_raw(refdir, y, float(ref[("right", y)]["vpitch_rad_s"]),
                                        False))) for y in SHIFTS if y not in JUMPS}
    for y in res:
        if y in JUMPS:
            continue
        right = [p for p in res[y].patches if p.geometry.side == "right"]
        fn = sum(p.normal.normal_force for p in right)
        assert fn == pytest.approx(float(ref[("right", y)]["fn_N"]), rel=0.015), y
        app = max(p.geometry.approach for p in right) * 1e3
        if y >= 1.0:
            assert app == pytest.approx(float(ref[("right", y)]["approach_mm"]), rel=0.03), y


def test_flange_contact_starts_between_6_and_6_5_mm(refdir):
    for builtin in (False, True):
        prof = refdir / "profiles"
        if builtin:
            from railcontact.profiles import rail_profile, s1002
            ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
        else:
            ws = Wheelset(read_profile(prof / "MBench_S1002_v3.prw"))
            tr = Track(read_profile(prof / "MBench_UIC60_v3.prr"))
        onset = None
        for y in np.arange(6.0, 6.55, 0.05):
            c = find_contact(ws, tr, y * 1e-3, 2.4e-3 * y, vertical_force=1e4)
            if min(p.contact_angle for p in c.side_patches("right")) < -0.8:
                onset = y
                break
        assert onset is not None and 6.0 < onset <= 6.5 + 1e-9, (builtin, onset)


def test_kinematic_creepages(refdir):
    ref = _ref(refdir)
    prof = refdir / "profiles"
    ws = Wheelset(read_profile(prof / "MBench_S1002_v3.prw"))
    tr = Track(read_profile(prof / "MBench_UIC60_v3.prr"))
    for y in (2.0, 3.0, 4.0, 8.0, 10.0):
        r = ref[("right", y)]
        c = find_contact(ws, tr, y * 1e-3, 2.4e-3 * y, vertical_force=1e4,
                         motion=WheelsetMotion(2.0, float(r["vpitch_rad_s"])))
        xi, eta, phi = c.side_patches("right")[0].creepage
        assert xi == pytest.approx(float(r["cksi"]), rel=0.02), y
        assert eta == pytest.approx(float(r["ceta"]), rel=0.02), y
        assert phi == pytest.approx(float(r["cphi_per_mm"]) * 1e3, rel=0.02), y


def test_symmetry_at_centre(refdir):
    prof = refdir / "profiles"
    ws = Wheelset(read_profile(prof / "MBench_S1002_v3.prw"))
    tr = Track(read_profile(prof / "MBench_UIC60_v3.prr"))
    c = find_contact(ws, tr, 0.0, 0.0, vertical_force=1e4)
    L, R = c.equivalent_point("left"), c.equivalent_point("right")
    assert L["rolling_radius"] == pytest.approx(R["rolling_radius"], abs=1e-9)
    assert L["contact_angle"] == pytest.approx(-R["contact_angle"], abs=1e-9)
    assert c.pose.roll == pytest.approx(0.0, abs=1e-12)
    # rail offset places the gauge point at gauge/2 (reference: profile origin at 760.533 mm)
    assert tr.rail_offset("right") * 1e3 == pytest.approx(760.533, abs=2e-3)
