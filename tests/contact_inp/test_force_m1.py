"""CONTACT's module 1 with the total longitudinal force FX_WS prescribed (F = 1):
the pitch velocity found (railcontact.contact_inp.force_m1), on groove_li.inp (a
wheel of 10 mm cross-section radius in a grooved rail, Li 2002; conformal contact,
D = 4; the rail at RAILY0 = 0 on a test rig, solved as the same case translated
onto a track's rail) against its .ref_out.

Tolerances (issue 34): F_n within 1 %, F_x, F_s within 1 % of mu F_n, p_max and the
elements in contact within 3 %."""

import re

import pytest

from railcontact.contact_inp import solve_inp
from railcontact.contact_inp.force_m1 import wheelset_fx

from ..cases.test_conformal import _ref


@pytest.fixture(scope="module")
def groove(testbank):
    path = testbank / "examples_conformal" / "groove_li.inp"
    return solve_inp(path, cases=[1, 4]), path


def test_free_rolling_in_a_groove(groove):
    """groove_li cases 1-4 (groove radii 10.25, 10.10, 10.05, 10.02 mm, F_z 10 kN,
    FX_WS = 0; measured on all four, tested on 1 and 4): the pitch velocity found
    within 2.7e-6 of CONTACT's (cases 1-4 2.0 to 2.7e-6 with CONTACT's sampled wheel
    on the conformal surface; case 4 1.6e-6), F_n within 0.01 %, p_max within 0.06 %,
    the elements in contact within 0.22 % (case 4: 2265 as CONTACT's), F_x and F_s under 0.02 N
    (CONTACT's up to 0.019 N), the reference point at the groove's bottom (y_tr
    0).  FX_WS = 0 is met to a tenth of CONTACT's own residual, 0.019 N (measured
    1.5e-3 N: the pitch velocity's tolerance 1e-10 times dF_x/d(omega))."""
    rows, path = groove
    text = path.with_suffix(".ref_out").read_text()
    vpitch = [float(v) for v in re.findall(
        r"VPITCH_WS\n\s+" + r"\S+\s+" * 5 + r"(\S+)", text)]
    assert len(rows) == 2
    for r in rows:
        c = r["case"]
        (p,) = _ref(path.with_suffix(".ref_out"), c)["patches"]
        assert r["converged"], r["message"]
        assert abs(wheelset_fx([r])) < 1.9e-3
        assert r["vpitch_rad_s"] == pytest.approx(vpitch[c - 1], rel=5e-6)
        assert r["fn_N"] == pytest.approx(p["fn"], rel=0.01)
        assert abs(r["fx_N"] - p["fx"]) <= 0.01 * 0.3 * p["fn"]
        assert abs(r["fs_N"] - p["fs"]) <= 0.01 * 0.3 * p["fn"]
        assert r["pmax_MPa"] == pytest.approx(p["pmax"], rel=0.03)
        assert r["ncon"] == pytest.approx(p["ncon"], rel=0.03)
        assert r["ycp_tr_mm"] == pytest.approx(0.0, abs=1e-3)
    # the found pitch velocity differs from the nominal -VS/NOMRAD = -1
    assert rows[1]["vpitch_rad_s"] == pytest.approx(-1.0009761, rel=5e-6)


@pytest.mark.xfail(strict=True, reason="groove_li case 4's pitch velocity -1.0009745 against "
                   "CONTACT's -1.0009761 (1.6e-6; 3e-7 before the conformal gap took CONTACT's "
                   "sampled wheel, which brought its elements to CONTACT's 2265 and p_max "
                   "closer: shifting the samples by DS/2 moves it by 1.5e-5)")
def test_free_rolling_in_a_groove_case4_pitch(groove):
    """groove_li case 4: the pitch velocity found within 1e-6 of CONTACT's."""
    rows, _ = groove
    assert rows[1]["vpitch_rad_s"] == pytest.approx(-1.0009761, rel=1e-6)


def test_prescribed_force_meets_it(testbank, tmp_path):
    """FX_WS = 600 N (a fifth of mu F_z) in groove_li's first case: the pitch
    velocity found gives it within 1e-4 (measured 599.965 N: the solves' own
    tolerances)."""
    path = testbank / "examples_conformal" / "groove_li.inp"
    src = path.read_text()
    bad = src.replace(" 420.0 0.0    0.0   0.0        0.0    0.0       VS,VY,VZ, VROLL,VYAW,FX_WS",
                      " 420.0 0.0    0.0   0.0        0.0  600.0       VS,VY,VZ, VROLL,VYAW,FX_WS",
                      1)
    assert bad != src
    f = tmp_path / "groove_fx.inp"
    f.write_text(bad.replace("'../profiles/", f"'{testbank / 'profiles'}/"))
    (r,) = solve_inp(f, cases=[1])
    assert r["converged"], r["message"]
    assert wheelset_fx([r]) == pytest.approx(600.0, rel=1e-4)
    assert r["fx_N"] == pytest.approx(600.0, rel=1e-4)
    assert r["vpitch_rad_s"] > -1.0002276
