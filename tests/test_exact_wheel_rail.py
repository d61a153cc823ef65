"""Exact normal + exact tangential on Manchester wheel-rail cases vs CONTACT.

Same profiles and element size as the reference (0.2 mm for A-2.2, 0.25 mm for the
10 kN sweep, which CONTACT computed for the right wheel alone with zero roll).
"""

import pytest

import railcontact as rc
from tests.conftest import read_csv


def _raw(refdir, y, yaw, vpitch, element, extra=None):
    prof = refdir / "profiles"
    raw = {"material": {"young_modulus": 2 * 82e9 * 1.28, "poisson_ratio": 0.28},
           "friction": {"coefficient": 0.3},
           "wheel": {"profile": str(prof / "MBench_S1002_v3.prw")},
           "rail": {"profile": str(prof / "MBench_UIC60_v3.prr"), "inclination": 0.0},
           "wheelset": {"lateral_shift": y * 1e-3, "yaw": yaw, "vertical_force": 1e4,
                        "velocity": 2.0, "pitch_velocity": vpitch},
           "solver": {"normal": "exact", "tangential": "exact",
                      "element_size": [element, element]}}
    raw["wheelset"].update(extra or {})
    return raw


@pytest.mark.parametrize("y", [2.0, 4.0, 8.0, 10.0])
def test_a22_both_wheels(refdir, y):
    ref = {(r["side"], float(r["y_ws_mm"])): r
           for r in read_csv(refdir / "mbench_a22" / "a22_patches.csv")}
    res = rc.solve(rc.case_from_dict(_raw(refdir, y, 2.4e-3 * y,
                                          float(ref[("right", y)]["vpitch_rad_s"]), 0.2e-3)))
    for side in ("left", "right"):
        (p,) = [q for q in res.patches if q.geometry.side == side]
        r = ref[(side, y)]
        assert p.normal.normal_force == pytest.approx(float(r["fn_N"]), rel=0.01)
        # forces on the wheel are the negatives of CONTACT's forces on the rail
        assert p.tangential.fx == pytest.approx(-float(r["fx_N"]), rel=0.01)
        assert p.tangential.fy == pytest.approx(-float(r["fs_N"]), rel=0.01)
        assert p.normal.pmax == pytest.approx(float(r["pmax_MPa"]) * 1e6, rel=0.03)
        tol = 0.02 if abs(p.geometry.contact_angle) < 0.5 else 0.04   # measured 3.4 % flange
        assert p.normal.area == pytest.approx(float(r["area_mm2"]) * 1e-6, rel=tol)


@pytest.mark.parametrize("y", [-2.0, 3.0, 9.0])
def test_sweep_10kN_single_wheel(refdir, y):
    rows = {float(r["y_ws_mm"]): r for r in read_csv(refdir / "mbench_sweep_10kN.csv")}
    r = rows[y]
    res = rc.solve(rc.case_from_dict(_raw(refdir, y, 0.0, float(r["vpitch_rad_s"]), 0.25e-3,
                                          {"side": "right", "roll": 0.0})))
    (p,) = res.patches
    assert p.normal.normal_force == pytest.approx(float(r["fn_mat_N"]), rel=0.01)
    assert p.normal.pmax == pytest.approx(float(r["pmax_mat_MPa"]) * 1e6, rel=0.03)
    assert p.normal.area == pytest.approx(float(r["area_mm2"]) * 1e-6, rel=0.04)
    # tread: Fx within 1 %; flange: 3 % (the kinematic creepage at our contact point is
    # -1.03e-3 where CONTACT tuned it to -1.00e-3)
    tol = 0.01 if y < 5 else 0.03
    assert p.tangential.fx == pytest.approx(-float(r["fx_N"]), rel=tol)
    assert p.tangential.fy == pytest.approx(-float(r["fs_N"]), rel=0.05)
