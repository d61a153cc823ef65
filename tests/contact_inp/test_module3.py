"""CONTACT's module 3 on its own grid and its transient problems through ``.inp``:
Cattaneo's shift (``examples_basic/cattaneo.inp``), "from Cattaneo to Carter"
(``catt_to_cart.inp``: a shift, then transient rolling with contact-fixed (T = 2)
and material-fixed (T = 1) coordinates), and a 2-D Cattaneo-to-Carter sequence
against Carter's closed form."""

import math

import pytest

from railcontact.contact_inp import InpError, load_inp, read_inp, solve_inp
from railcontact.contact_inp.module3 import handles
from railcontact.contact_inp.outfile import read_out


def _check(rows, ref, cases, mu, force_tol=0.01, creep_tol=0.01, area_tol=0.03,
           pmax_tol=0.03):
    """Each case's F_n within ``force_tol``, F_x, F_y within ``force_tol`` of CONTACT's
    and of mu F_n, the creepage or shift (the second output block's X column where
    it is one) within ``creep_tol``, the contact elements within ``area_tol`` and
    p_max within ``pmax_tol``.  Returns the largest deviations."""
    worst = {}
    by_case = {r["case"]: r for r in rows}
    for c in cases:
        r, f = by_case[c], ref[c]
        assert r["converged"], (c, r["message"])
        dev = {"fn": r["fn_N"] / f["fn_N"] - 1,
               "fx": (r["fx_N"] - f["fx_N"]) / max(abs(f["fx_N"]), mu * f["fn_N"] * 1e-3),
               "fx_mu": (r["fx_N"] - f["fx_N"]) / (mu * f["fn_N"]),
               "fy_mu": (r["fs_N"] - f["fy_N"]) / (mu * f["fn_N"]),
               "pmax": r["pmax_MPa"] / f["pmax_MPa"] - 1}
        if f["x_label"] in ("SHIFT X", "CREEP X", "CKSI"):
            dev["cksi"] = r["cksi"] / f["x_value"] - 1 if f["x_value"] else r["cksi"]
        if "ncon" in f:
            dev["area"] = r["ncon"] / f["ncon"] - 1
        for k, v in dev.items():
            worst[k] = max(worst.get(k, 0.0), abs(v))
    tol = {"fn": force_tol, "fx": force_tol, "fx_mu": force_tol, "fy_mu": force_tol,
           "pmax": pmax_tol, "cksi": creep_tol, "area": area_tol}
    for k, v in worst.items():
        assert v <= tol[k], (k, v)
    return worst


def test_cattaneo(testbank):
    """cattaneo.inp: a Hertzian compression, then the shift at F_x = -0.875 mu F_n
    (F = 2) from the unloaded state on CONTACT's 19 x 19 grid.  Measured: the shift
    8.1549e-3 mm (CONTACT's 8.155e-3; Mindlin's 8.17e-3), F_x -3.21839 N, 45
    elements in adhesion and 132 in slip as in CONTACT, p_max 4.3930 MPa."""
    path = testbank / "examples_basic" / "cattaneo.inp"
    rows = solve_inp(path)
    ref = read_out(path.with_suffix(".ref_out"))
    worst = _check(rows, ref, [1, 2], mu=0.4)
    r = rows[1]
    assert (r["ncon"], r["nadh"], r["nslip"]) == (ref[2]["ncon"], ref[2]["nadh"],
                                                  ref[2]["nslip"])
    assert worst["cksi"] < 5e-4 and worst["fx"] < 2e-3
    # Mindlin: delta = 3 mu P (2 - nu) / (8 G a) [1 - (1 - Q/mu P)^(2/3)], a = 1 mm
    mindlin = 3 * 0.4 * 9.1954 * (2 - 0.42) / (8 * 200.0 * 1.0) * (1 - 0.125 ** (2 / 3))
    assert r["cksi"] == pytest.approx(mindlin, rel=0.005)
    # stick radius c/a = (1 - Q/mu P)^(1/3) = 0.5: 45 elements of 0.1333 mm squared
    c = math.sqrt(r["nadh"] * r["dx_mm"] * r["ds_mm"] / math.pi)
    assert c == pytest.approx(0.5, rel=0.05)


@pytest.fixture(scope="module")
def catt_to_cart(testbank):
    path = testbank / "examples_basic" / "catt_to_cart.inp"
    # the first and third sequences (the second, on a 90 x 33 grid, in
    # benchmarks/contact_testbank.py: the same figures)
    cases = list(range(1, 58)) + list(range(115, 172))
    return solve_inp(path, cases=cases), read_out(path.with_suffix(".ref_out")), cases


def test_catt_to_cart(catt_to_cart):
    """catt_to_cart.inp: three sequences of a Cattaneo shift at F_x = -0.657 mu F_n
    followed by 56 rolling steps of DQ = DX = 0.25 mm, on a contact-fixed grid
    (T = 2, cases 2-57), on a large world-fixed grid with the geometry moving
    (T = 1, 59-114) and on a grid moving with the contact by whole elements (T = 1,
    116-171; both with the approach prescribed).  Measured over all 171 cases:
    creepage or shift within 0.05 % of CONTACT's printed 4 digits, F_n, F_x within
    0.01 %, p_max 0.03 %, contact, adhesion and slip elements CONTACT's (here the
    first and third sequences)."""
    rows, ref, cases = catt_to_cart
    assert sorted(r["case"] for r in rows) == cases
    worst = _check(rows, ref, cases, mu=0.4013, force_tol=1e-3, creep_tol=1e-3,
                   pmax_tol=1e-3, area_tol=0.0)
    assert worst["cksi"] < 5e-4
    by_case = {r["case"]: r for r in rows}
    for c in cases:
        if "nadh" in ref[c]:
            assert (by_case[c]["nadh"], by_case[c]["nslip"]) == (ref[c]["nadh"],
                                                                ref[c]["nslip"]), c


def test_catt_to_cart_reaches_the_steady_state(catt_to_cart, testbank, tmp_path):
    """The last step of each sequence is steady rolling: its creepage (T = 1: the
    shift over DQ) is that of a steady-state solve (T = 3) of the same force on the
    same grid, 3.101e-3 (CONTACT's last step: 3.101e-3; the shift 7.751e-4 mm over
    0.25 mm).  Measured: within 0.02 %."""
    rows, _, _ = catt_to_cart
    by_case = {r["case"]: r for r in rows}
    text = (testbank / "examples_basic" / "catt_to_cart.inp").read_text()
    head = text.split(" 3  MODULE")[1]
    # the first case, as steady rolling (T = 3) with CHI, DQ, VELOC
    steady = head.replace("201110      P-B-T-N-F-S", "203110      P-B-T-N-F-S", 1)
    steady = steady.replace("  0.280       0.280       1.000       1.000",
                            "  0.000       0.250        1000.\n"
                            "  0.280       0.280       1.000       1.000", 1)
    f = tmp_path / "steady.inp"
    f.write_text(" 3  MODULE" + steady + "\n 0  MODULE\n")
    (r,) = solve_inp(f)
    assert r["cksi"] == pytest.approx(3.101e-3, rel=5e-4)
    assert by_case[57]["cksi"] == pytest.approx(r["cksi"], rel=2e-4)
    for c in (171,):
        assert by_case[c]["cksi"] / 0.25 == pytest.approx(r["cksi"], rel=2e-4)


def _carter_2d_inp(q, steps, dx=0.04, mx=60):
    """A 2-D "Cattaneo to Carter" input: a cylinder pair (R = 500 mm, one strip of
    200 mm, G = 82 GPa, nu = 0.28, mu = 0.3, 35780 N: a = 1.0 mm) shifted to
    F_x = q mu F_n, then rolled ``steps`` steps of DQ = DX at that force (T = 2), then
    the same force in steady rolling (T = 3)."""
    xc1 = -0.5 * (mx - 1) * dx
    common = ("   100   100    30     1      1e-9        MAXGS, MAXIN, MAXNR, MAXOUT, EPS\n"
              f"  35780.   {q:.6f}   0.000   0.000       FN, FX, CETA, CPHI\n")
    first = (" 3  MODULE\n  201110  P-B-T-N-F-S\n  022020  L-D-C-M-Z-E\n 0000141  H-G-I-A-O-W-R\n"
             + common + "  0.300   0.300                     FSTAT, FKIN\n"
             "  0.280   0.280   82000.   82000.     POISS 1,2,  GG 1,2\n"
             "    3                                IPOTCN\n"
             f"   {mx}    1   {xc1:.6f}   0.000   {dx:.6f}   200.0   MX,MY,XC1,YC1,DX,DY\n"
             "    1    1                           IBASE, IPLAN\n"
             "  0.001   0.0   0.0   0.0   0.0   0.0   B1..B6\n")
    roll = (" 3  MODULE\n  002110  P-B-T-N-F-S\n  102000  L-D-C-M-Z-E\n 0000141  H-G-I-A-O-W-R\n"
            + common + f"  0.000   {dx:.6f}   1000.          CHI, DQ, VELOC\n"
            "  0.280   0.280   82000.   82000.     POISS 1,2,  GG 1,2\n")
    more = (" 3  MODULE\n  002110  P-B-T-N-F-S\n  100000  L-D-C-M-Z-E\n 0000141  H-G-I-A-O-W-R\n"
            + common)
    steady = (" 3  MODULE\n  203110  P-B-T-N-F-S\n  100000  L-D-C-M-Z-E\n 0000141  H-G-I-A-O-W-R\n"
              + common)
    return first + roll + more * (steps - 1) + steady + " 0  MODULE\n"


def test_carter_2d_from_cattaneo(tmp_path):
    """2-D "from Cattaneo to Carter" at F_x = 0.6 mu F_n: the shift, then rolling at
    that force; after the material has passed the contact 2.5 times (2 a = 50
    steps of DX) the creepage is the steady one, and both are Carter's (1926; Johnson 1985,
    eq. 8.35) xi = -(mu a / R) (1 - sqrt(1 - F_x / mu F_n)) for a = 1.0 mm.
    Measured: the steady creepage 0.90 % below Carter's on 0.04 mm elements, 0.46 %
    on 0.02 mm (first order in DX, the rolling difference); the creepage of the
    rolling steps overshoots (+21 % at 25 steps) and settles: 2.4 % from the
    steady one at 50 steps, 0.04 % at 100, 0.003 % at 125."""
    q = 0.6
    f = tmp_path / "carter2d_trans.inp"
    steps = 125
    f.write_text(_carter_2d_inp(q, steps))
    rows = solve_inp(f)
    assert all(r["converged"] for r in rows)
    fn, mu, R, G, nu = 35780.0 / 200.0, 0.3, 500.0, 82000.0, 0.28
    a = math.sqrt(4 * fn * R * (1 - nu) / (math.pi * G))
    carter = -(mu * a / R) * (1 - math.sqrt(1 - q))
    shift, *rolling, steady = rows
    assert shift["fx_N"] == pytest.approx(q * mu * 35780.0, rel=1e-6)
    assert steady["cksi"] == pytest.approx(carter, rel=0.01)
    assert rolling[-1]["cksi"] == pytest.approx(steady["cksi"], rel=1e-4)
    # the creepage rises from the shift's onset to the steady value
    assert abs(rolling[0]["cksi"]) < abs(rolling[-1]["cksi"])
    # halving DX halves the deviation from Carter's
    f.write_text(_carter_2d_inp(q, 1, dx=0.02, mx=120))
    fine = solve_inp(f)[-1]
    e1, e2 = steady["cksi"] / carter - 1, fine["cksi"] / carter - 1
    assert e2 / e1 == pytest.approx(0.5, abs=0.05)


def test_state_rules(testbank):
    """Which cases take the module 3 path, and CONTACT's PVTIME rules: P = 3 repeats
    the last step from the same previous instance (the same result), P = 2 starts
    anew (the first case's result)."""
    path = testbank / "examples_basic" / "catt_to_cart.inp"
    cases = read_inp(path)
    assert [handles(c) for c in cases[:3]] == [True, True, True]
    ref_cases = load_inp(testbank / "examples_basic" / "cattaneo.inp")
    assert ref_cases[0].raw is not None and ref_cases[1].raw is None


def test_unsupported(tmp_path):
    """Options off this path stop with one line naming them."""
    text = _carter_2d_inp(0.5, 1).replace("  022020  L-D-C-M-Z-E", "  022120  L-D-C-M-Z-E", 1)
    f = tmp_path / "visc.inp"
    f.write_text(text)
    with pytest.raises(InpError) as err:
        load_inp(f)
    assert "\n" not in str(err.value)


def test_velocity_dependent_friction(testbank):
    """veldep_fric.inp: a 2-D wheel (IBASE = 2: R = 460 mm, 622 kN over 200 mm) in
    steady (T = 3) and transient rolling (T = 2) at CKSI = -1e-3 with the
    exponential falling friction law (L = 4: 0.18 + 0.12 exp(-ln2 s_a / 100 mm/s),
    no memory).  The friction coefficient is iterated to its fixed point
    mu = mu_s(s_a) (relaxed updates); INISLP picks the branch where there are
    several (> 0 from the static, < 0 from the kinetic coefficient).  Measured: the
    steady cases F_x 110896 N (CONTACT's 1.109e5) with CONTACT's 45 adhesion and 36
    slip elements, the first transient step from them 0.03 % below CONTACT's with
    its 77 and 4; all 53 cases within 0.05 % of CONTACT's F_x, through the
    periodic collapse and recovery of the adhesion area (the wiggles of falling
    friction, 106-110 kN)."""
    path = testbank / "examples_basic" / "veldep_fric.inp"
    rows = solve_inp(path)
    ref = read_out(path.with_suffix(".ref_out"))
    assert len(rows) == 53 and all(r["converged"] for r in rows)
    dev = {r["case"]: r["fx_N"] / ref[r["case"]]["fx_N"] - 1 for r in rows}
    assert max(abs(d) for d in dev.values()) < 1e-3
    r1, r2 = rows[0], rows[1]
    assert (r1["nadh"], r1["nslip"]) == (ref[1]["nadh"], ref[1]["nslip"]) == (45, 36)
    assert (r2["nadh"], r2["nslip"]) == (ref[2]["nadh"], ref[2]["nslip"]) == (77, 4)
    assert r1["fx_N"] == pytest.approx(1.109e5, rel=5e-4)
    assert all(abs(r["fn_N"] / ref[r["case"]]["fn_N"] - 1) < 1e-3 for r in rows)


@pytest.fixture(scope="module")
def ertz(testbank):
    path = testbank / "examples_basic" / "ertz_temperature.inp"
    return solve_inp(path), read_out(path.with_suffix(".ref_out"))


def test_temperature_forces_and_bulk_temperatures(ertz):
    """ertz_temperature.inp (Ertz & Knothe's case, rolling to the left, CHI = 180
    deg, solved mirrored): forces, adhesion and slip elements are CONTACT's in all
    four cases (F_x 29999.6 N against 3.000e4, 21823 against 21820); without
    sliding and with bulk temperatures 150 and 0 C (case 2) the contact is at
    CONTACT's 75.0 C; with partial slip (case 4, 0.2 %) the largest temperature
    90.85 C against CONTACT's 90.85."""
    rows, ref = ertz
    for r in rows:
        f = ref[r["case"]]
        assert r["converged"]
        assert r["fx_N"] == pytest.approx(f["fx_N"], rel=1e-3, abs=1.0)
        assert (r["nadh"], r["nslip"]) == (f["nadh"], f["nslip"])
    assert rows[1]["tmax_C"] == pytest.approx(75.0, abs=0.05)
    assert rows[3]["tmax_C"] == pytest.approx(ref[4]["tmax_C"], rel=0.03)


def test_temperature_full_sliding(ertz):
    """Cases 1 and 3 (full sliding at 1 m/s): with CONTACT's weight of each
    element's own heat input (scheme "contact") the largest temperature is
    CONTACT's: measured 166.82 and 241.82 C against its 166.8 and 241.8 (before:
    152.3 and 227.3 with the element integral to the centre, -8.7 % and -6.0 %;
    Jaeger's closed form gives 150.3), and the partial slip case 90.85 against
    90.85."""
    rows, ref = ertz
    for c in (1, 3, 4):
        assert rows[c - 1]["tmax_C"] == pytest.approx(ref[c]["tmax_C"], rel=1e-3)


def _ertz_l6(testbank, tmp_path, fref_line):
    """Ertz & Knothe's first case (full sliding at 1 m/s) with temperature dependent
    friction (L = 6) and the given FREF, TREF, DFHEAT, DTHEAT line."""
    src = (testbank / "examples_basic" / "ertz_temperature.inp").read_text()
    first = src.split("% Second case")[0]
    first = first.replace("  022020     L-D-C-M-Z-E", "  622020     L-D-C-M-Z-E")
    first = first.replace("   0.300    0.300                              FSTAT, FKIN",
                          fref_line + "\n   0.0   0.0     MEMDST, MEM_S0")
    path = tmp_path / "ertz_l6.inp"
    path.write_text(first + "\n 0  MODULE\n")
    (case,) = read_inp(path)
    from railcontact.contact_inp.module3 import Sequence
    seq = Sequence()
    return seq.run(case), seq.last


def test_temperature_dependent_friction_limits(testbank, tmp_path):
    """FRCLAW = 6 (CONTACT's piecewise linear mu(T_1)): with T_ref above every
    temperature reached the case is Coulomb friction at FREF, CONTACT's case 1
    (F_x 3.000e4 N, MAX(T1,T2) 166.8 C); with mu falling linearly from 0.3 at 0 C by
    0.1 per 300 K the friction and the flash temperature settle at a fixed point:
    at every contact element mu = mu(T_1) of the final solution's own surface
    temperature (to 1e-6), |p_t| = mu p in full sliding, F_x and T both below the
    Coulomb case's (measured F_x 26921 N, 144.2 C against 30000 N, 166.8 C)."""
    row, _ = _ertz_l6(testbank, tmp_path, "   0.300   1000.0  -0.1   100.0   FREF, TREF, "
                                          "DFHEAT, DTHEAT")
    assert row["converged"]
    assert row["fx_N"] == pytest.approx(3.0e4, rel=1e-4)
    assert row["tmax_C"] == pytest.approx(166.8, rel=1e-3)
    row, res = _ertz_l6(testbank, tmp_path, "   0.300   0.0  -0.1   300.0   FREF, TREF, "
                                            "DFHEAT, DTHEAT")
    assert row["converged"], row["message"]
    c = res.pressure > 0
    law = lambda t: 0.3 - 0.1 * min(max(t, 0.0), 300.0) / 300.0        # noqa: E731
    t1 = res.temperature[0]
    mu = res.mu[:c.shape[0], :c.shape[1]]
    expect = [law(t) for t in t1[c]]
    assert mu[c] == pytest.approx(expect, abs=1e-6)
    import numpy as np
    # full sliding: the traction is at the bound mu p everywhere
    assert np.hypot(res.px, res.py)[c] == pytest.approx((mu * res.pressure)[c], rel=1e-6)
    assert 0.2 * 1e5 < row["fx_N"] < 0.29 * 1e5
    assert 75.0 < row["tmax_C"] < 160.0
    assert np.all(mu[c] <= 0.3) and np.all(mu[c] >= 0.2)


def test_temperature_dependent_friction_needs_temperatures(testbank, tmp_path):
    """L = 6 without the H digit: the case names what it needs."""
    src = (testbank / "examples_basic" / "ertz_temperature.inp").read_text()
    first = src.split("% Second case")[0]
    first = first.replace(" 3002241   H-G-I", " 0002241   H-G-I").replace(
        "  022020     L-D-C-M-Z-E", "  622020     L-D-C-M-Z-E").replace(
        "   0.300    0.300                              FSTAT, FKIN",
        "  0.3  0.0  -0.1  300.0  FREF, TREF, DFHEAT, DTHEAT\n  0.0  0.0  MEMDST, MEM_S0")
    lines = [ln for ln in first.splitlines() if "BKTEMP" not in ln]
    path = tmp_path / "l6_no_heat.inp"
    path.write_text("\n".join(lines) + "\n 0  MODULE\n")
    (case,) = read_inp(path)
    from railcontact.contact_inp.module3 import check
    with pytest.raises(InpError, match="FRCLAW = 6.*HEAT = 0"):
        check(case)


def test_frictional_power_on_contacts_grid(testbank):
    """carter2d (Carter's 2-D rolling on CONTACT's own grid, module 3 path): the
    frictional power of the steady rolling solution V sum p . s dA against CONTACT's
    FRIC.POWER [W], measured within 0.01 %."""
    import re
    from pathlib import Path
    path = testbank / "examples_basic" / "carter2d.inp"
    (r,) = solve_inp(path)
    text = Path(path.with_suffix(".ref_out")).read_text()
    (line,) = re.findall(r"FRIC\.POWER\n(.*)\n", text)
    c = float(line.split()[5])
    assert c < 0 and r["fric_power_W"] == pytest.approx(c, rel=2e-3)


def test_modified_fastsim_on_contacts_grid(testbank):
    """fastsim.inp: modified FASTSIM (M = 3) with the parabolic (B = 3) and the
    elliptical (B = 2) traction bound on CONTACT's grids of 44 x 44 and 220 x 220
    elements, rolling along +x and (case 8) along -x with the spin reversed:
    F_y within 0.02 % of CONTACT's (its 4 printed digits; the coarse grid's
    F_y lies 3.8 % from the fine one's, which our grid reproduces), F_x 0, the
    elements in contact and in adhesion CONTACT's, p_max its (at the element
    centres).  Cases 4 and 7 (Modified FaStrip, M = 5):
    :func:`test_modified_fastrip_on_contacts_grid`."""
    path = testbank / "examples_basic" / "fastsim.inp"
    rows = {r["case"]: r for r in solve_inp(path, cases=[2, 3, 5, 6, 8])}
    ref = read_out(path.with_suffix(".ref_out"))
    for case, r in rows.items():
        q = ref[case]
        assert r["converged"]
        assert r["fs_N"] == pytest.approx(q["fy_N"], rel=2e-4), case
        assert abs(r["fx_N"]) <= 1e-6 * q["fn_N"]
        assert (r["ncon"], r["nadh"], r["nslip"]) == (q["ncon"], q["nadh"], q["nslip"]), case
        assert r["pmax_MPa"] == pytest.approx(q["pmax_MPa"], abs=0.5)
    assert rows[8]["fs_N"] == pytest.approx(rows[5]["fs_N"], rel=1e-12)


def test_modified_fastrip_on_contacts_grid(testbank):
    """fastsim.inp cases 4 and 7: CONTACT's Modified FaStrip (M = 5, B = 2) on
    its grids of 44 x 44 and 220 x 220 elements: F_y and M_z within half a unit of
    CONTACT's 4 printed digits (5 N of 15830 N: 0.03 %; 5 N m m of 48160), F_x 0,
    the elements in contact (the elliptical bound's, case 3's) and in adhesion
    CONTACT's.  Before (hertz + railcontact's own FaStrip): F_y -13871 N, 12.4 %
    off, 1388 elements in contact."""
    path = testbank / "examples_basic" / "fastsim.inp"
    rows = {r["case"]: r for r in solve_inp(path, cases=[4, 7])}
    ref = read_out(path.with_suffix(".ref_out"))
    mz = {4: -4.816e4, 7: -4.757e4}
    for case, r in rows.items():
        q = ref[case]
        assert r["converged"]
        assert r["fs_N"] == pytest.approx(q["fy_N"], abs=5.0), case
        assert r["mn_Nmm"] == pytest.approx(mz[case], abs=5.0), case
        assert abs(r["fx_N"]) <= 1e-6 * q["fn_N"]
        assert (r["ncon"], r["nadh"], r["nslip"]) == (q["ncon"], q["nadh"], q["nslip"]), case


def test_modified_fastsim_options(tmp_path, testbank):
    """M = 2 (one flexibility FLX) and Spiryagin's slope reduction K0_MF < 1: in
    the linear range (tiny creepage, full adhesion) FASTSIM reproduces
    F_y = -(8 a^2 b / (3 L)) eta on a fine grid (440 x 440 elements: within
    0.5 %, the march's first full step per row adding 0.65 % at 220 x 220;
    tractions on body 1), and K0_MF = 0.5 with ALFAMF = 1 halves it (the flexibility doubled)."""
    text = (testbank / "examples_basic" / "fastsim.inp").read_text()
    start = text.index("% fifth case")
    case5 = text[start:text.index("% sixth case")]
    a, b, L, eta = 8e-3, 4e-3, 2e-4, -1e-7                    # L in mm^3/N
    c = (case5.replace("122320", "022220").replace("220  220", "440  440")
         .replace("-0.000625   0.000625        FN, CKSI, CETA, CPHI",
                  f"{eta}   0.0   FN, CKSI, CETA, CPHI\n   0.3  0.3   FSTAT, FKIN")
         .replace("1.000      1.000      1.000", f"{L}  1.000  1.000  1.000"))
    assert c.count(f"{L}  1.000") == 1 and c.count("022220") == 1 and "FKIN" in c
    half = c.replace(f"{L}  1.000  1.000  1.000", f"{L}  0.5  1.000  1.000")
    p = tmp_path / "m2.inp"
    p.write_text(c + half + "\n 0 MODULE\n")
    one, two = solve_inp(p)
    assert one["converged"] and two["converged"], (one["message"], two["message"])
    want = -(8 * a * a * b / (3 * L * 1e-9)) * eta
    assert one["fs_N"] == pytest.approx(want, rel=5e-3)
    assert one["nadh"] == one["ncon"]
    assert two["fs_N"] == pytest.approx(0.5 * one["fs_N"], rel=1e-9)


def test_dissimilar_materials_bentall(testbank):
    """bentall.inp: an aluminium roller on a steel one (K != 0), 2-D, rolling
    along -x, the normal and tangential problems coupled on CONTACT's grid:
    Bufler's no-slip free rolling (case 3), tractive rolling at FX = +-0.75 mu F_n
    (cases 5, 6).  The creepage met within half a unit of CONTACT's 4 printed
    digits, p_max within its printed 0.1 MPa, the elements in contact, adhesion
    and slip CONTACT's."""
    path = testbank / "examples_basic" / "bentall.inp"
    rows = {r["case"]: r for r in solve_inp(path, cases=[3, 5, 6])}
    creep = {3: 3.591e-4, 5: 2.108e-4, 6: 5.392e-4}
    ref = read_out(path.with_suffix(".ref_out"))
    for case, r in rows.items():
        q = ref[case]
        assert r["converged"], r["message"]
        assert r["cksi"] == pytest.approx(creep[case], abs=6e-8)
        assert r["fx_N"] == pytest.approx(q["fx_N"], abs=0.06)
        assert r["pmax_MPa"] == pytest.approx(q["pmax_MPa"], abs=0.06)
        assert (r["ncon"], r["nadh"], r["nslip"]) == (q["ncon"], q["nadh"], q["nslip"])


def test_modified_fastsim_traction_curve(testbank):
    """tractcurv.inp cases 92-120: modified FASTSIM with Spiryagin's slope reduction
    (K0_MF 0.54, ALFAMF 0.02, BETAMF 0.62), the parabolic bound and exponential
    falling friction (L = 4, kept from case 91): the friction coefficient the
    law's steady value at the patch's slip velocity VELOC |(CKSI, CETA)|.  F_x
    within 0.15 % of CONTACT's over the curve (measured 0.11 %: its rise, peak at
    32460 N and fall); the cases where CONTACT's coefficient is kept from a
    stopped case (91: MATER = 4) run on their own (`--case`)."""
    path = testbank / "examples_basic" / "tractcurv.inp"
    cases = [92, 97, 106, 113, 120]
    rows = {r["case"]: r for r in solve_inp(path, cases=cases)}
    ref = read_out(path.with_suffix(".ref_out"))
    for case in cases:
        r, q = rows[case], ref[case]
        assert r["fx_N"] == pytest.approx(q["fx_N"], rel=1.5e-3), case
        assert r["pmax_MPa"] == pytest.approx(q["pmax_MPa"], rel=2e-3)
    assert rows[106]["fx_N"] < rows[97]["fx_N"] and rows[120]["fx_N"] > rows[106]["fx_N"]


def test_spence_compression_dissimilar_shift(testbank):
    """spence35.inp: Spence's compression of dissimilar bodies (G1 = 0.5, nu1 = 0
    on a rigid body, K = 0.5), F_n = (k/45)^3 in stages k, each a shift (T = 1)
    from the last stage's tractions (P = 0) with the normal and tangential problems
    coupled (the pressure's tangential displacements of the step as a rigid shift,
    the tractions' normal ones as a gap).  The first 15 stages (the whole sequence
    and its subsurface stresses: tests/contact_inp/test_subsurface.py): approach
    and p_max within 0.1 % of CONTACT's 4 printed digits (measured 0.03 %, 0.02 %);
    F_x, F_y (zero but for round-off) within 1 % of mu F_n of CONTACT's."""
    path = testbank / "examples_basic" / "spence35.inp"
    rows = {r["case"]: r for r in solve_inp(path, cases=range(1, 16))}
    ref = read_out(path.with_suffix(".ref_out"))
    for case, r in rows.items():
        q = ref[case]
        assert r["converged"], r["message"]
        assert r["approach_mm"] == pytest.approx(q["approach_mm"], rel=1e-3)
        assert r["pmax_MPa"] == pytest.approx(q["pmax_MPa"], rel=1e-3)
        assert abs(r["fx_N"] - q["fx_N"]) <= 0.01 * 0.2986 * q["fn_N"]
        assert abs(r["fs_N"] - q["fy_N"]) <= 0.01 * 0.2986 * q["fn_N"]
    # the elements in contact and adhesion where CONTACT prints them (case 6)
    assert (rows[6]["ncon"], rows[6]["nadh"]) == (ref[6]["ncon"], ref[6]["nadh"])


def test_one_column_steady_rolling(testbank):
    """subsurf.inp, case 2: steady rolling on CONTACT's one element (MX = MY = 1) with
    FX = 0.999 FSTAT FN prescribed; the solver's grid gets an empty column ahead.
    CONTACT's CREEP X -0.6430 and approach 0.807984 mm."""
    path = testbank / "examples_basic" / "subsurf.inp"
    rows = solve_inp(path)
    assert rows[1]["cksi"] == pytest.approx(-0.6430, abs=6e-5)
    assert rows[1]["fx_N"] == pytest.approx(0.999, rel=1e-6)
    assert rows[1]["approach_mm"] == pytest.approx(0.807984, abs=1e-6)
    assert (rows[1]["mx"], rows[1]["my"], rows[1]["ncon"], rows[1]["nadh"]) == (1, 1, 1, 1)


# ------------------------------------------ interfacial layer, plasticity (M = 4)
def _plast(testbank, name, cases=None, folder="examples_plast"):
    path = testbank / folder / f"{name}.inp"
    return solve_inp(path, cases=cases), read_out(path.with_suffix(".ref_out"))


def test_plastic_3bl_rheometer(testbank):
    """plastic_3bl.inp (the user guide's "Shearing of interfacial layers"): one
    element of 1 mm^2 under 900 N shifted (T = 1) through four layers of Hou et al.
    (magnetite, clay, sand, MoS2: elastic, then yielding, hardening, softening and
    unloading).  All 57 cases: F_x within 0.05 % of CONTACT's (its 4 printed
    digits; measured 0.016 %), the element in adhesion or flow as CONTACT has it."""
    rows, ref = _plast(testbank, "plastic_3bl", folder="examples_basic")
    assert len(rows) == 57
    worst = _check(rows, ref, range(1, 58), mu=0.5, force_tol=5e-4)
    assert worst["fx"] < 2e-4
    assert [r["nadh"] for r in rows] == [ref[r["case"]]["nadh"] for r in rows]


def test_plastic_one_shift(testbank):
    """plastic_one_shift.inp: one element shifted back and forth and sideways (T = 1,
    k_tau > 0, the plastic displacement carried from case to case): F_x, F_y within
    0.05 % of CONTACT's (its 4 printed digits; measured 0.017 %)."""
    rows, ref = _plast(testbank, "plastic_one_shift")
    _check(rows, ref, range(1, 28), mu=0.5, force_tol=5e-4)


def test_plastic_cattaneo_to_carter(testbank):
    """catt2d_plast.inp: a 2-D shift at F_x = 0.6 mu F_n (F = 1) from the unloaded
    state, then 49 steps of transient rolling (T = 2, DQ = DX) into Carter's steady
    state, with a hardening layer (tau_c0 = 35 N/mm^2, k_tau = 123000 N/mm^3) whose
    plastic displacement travels with the material.  Every case within 0.05 % of
    CONTACT's F_x (its 4 printed digits; measured 0.044 %, p_max 0.023 %), its
    adhesion elements CONTACT's."""
    rows, ref = _plast(testbank, "catt2d_plast")
    _check(rows, ref, range(1, 51), mu=0.5, force_tol=5e-4)
    assert [r["nadh"] for r in rows] == [ref[r["case"]]["nadh"] for r in rows]


def test_plastic_3d_sequence(testbank):
    """catt3d_plast.inp: a 3-D steady state, shift and transient rolling sequence
    with the layer: every case within 0.05 % of CONTACT (measured F_x 0.036 %,
    p_max 0.027 %)."""
    rows, ref = _plast(testbank, "catt3d_plast")
    _check(rows, ref, [r["case"] for r in rows if r["case"] in ref], mu=0.5,
           force_tol=5e-4)


def test_plastic_carter_steady_rolling(testbank):
    """carter_plast.inp, 2-D steady rolling at CKSI = -4e-4 on 30 elements with
    k_tau = 123000, 0 and -20500 N/mm^3 (work-hardening, perfectly plastic,
    softening): F_x within 0.05 % of CONTACT's (measured 0.034 %), the elements in
    adhesion and slip CONTACT's."""
    rows, ref = _plast(testbank, "carter_plast", cases=[2, 3, 4])
    _check(rows, ref, [2, 3, 4], mu=0.5, force_tol=5e-4)
    for r in rows:
        assert (r["nadh"], r["nslip"]) == (ref[r["case"]]["nadh"], ref[r["case"]]["nslip"])
    # more flow, less force: hardening > perfectly plastic > softening
    assert rows[0]["fx_N"] > rows[1]["fx_N"] > rows[2]["fx_N"] and \
        rows[0]["nplast"] < rows[1]["nplast"] < rows[2]["nplast"]


def test_plastic_traction_curve_softening(testbank):
    """tractcurve_plast.inp, the softening layer (k_tau = -81.9 N/mm^3) at CKSI = 2 %
    to 25 % on a 44 x 44 Hertzian grid: F_x within 0.05 % of CONTACT's (measured
    0.009 %), with CONTACT's slip elements; beyond 20 % creepage the yield limit
    carried on stops at a tenth of tau_c0 (CONTACT's floor; without it F_x is 0.9 %
    off at 25 %)."""
    rows, ref = _plast(testbank, "tractcurve_plast", cases=[236, 238, 240])
    _check(rows, ref, [236, 238, 240], mu=0.33, force_tol=5e-4)
    for r in rows:
        assert r["nslip"] == ref[r["case"]]["nslip"]


def test_layer_with_falling_friction_and_memory(testbank):
    """tractcurv.inp cases 31-60 (the user guide's "reduced initial slope and
    falling friction"): an elastic layer (GG3 8200 N/mm^2, LAYTHK 1.25 mm, no
    yield) and exponential falling friction with memory (MEMDST 3 um, MEM_S0 1
    mm/s) on a 44 x 44 Hertzian grid.  F_x within 0.05 % of CONTACT's along the
    curve (its rise, peak at 33260 N and fall; measured 0.014 % over the 30 cases)
    and its elements in adhesion.  Without the memory (the instantaneous law) F_x
    is 0.2 % under CONTACT's at the peak (case 47: -33198 N against -33260 N),
    outside this test's 0.05 %."""
    path = testbank / "examples_basic" / "tractcurv.inp"
    cases = [31, 36, 41, 47, 53, 60]
    rows = solve_inp(path, cases=cases)
    ref = read_out(path.with_suffix(".ref_out"))
    _check(rows, ref, cases, mu=0.33, force_tol=5e-4)
    for r in rows:
        assert r["nadh"] == ref[r["case"]]["nadh"], r["case"]


def test_conformal_undeformed_distance_and_extra_slip(testbank):
    """examples_basic/conformal.inp (a strongly conformal flange root, R_ry = 10.0,
    R_wy = -10.2 mm, 51 x 39 elements of 0.4 mm): case 1, the Hertzian quadratic gap
    (F_n 100007 N, CONTACT 1.000e5; F_x 9143.8, F_y 25918 N, p_max 912.82 MPa, 1027
    elements, as CONTACT's), case 2, the true undeformed
    distance given per element (IBASE = 9), and case 4, with the conformal rigid
    slip given per element (EXRHS, E = 9) and CKSI = CETA = CPHI = 0.  Measured:
    F_n 91835.7 N (CONTACT 9.184e4), F_x 8958.5 / 10502.8 N (8959 / 1.050e4), F_y
    24173 / 22514 N (2.417e4 / 2.251e4), p_max 1012.31 MPa (1012), 871 elements in
    contact as CONTACT.  Cases 3 and 5 read numerical influence coefficients from a
    file not shipped (INFLCF = 9): their rows are errors naming it, the others run."""
    path = testbank / "examples_basic" / "conformal.inp"
    rows = solve_inp(path, cases=[1, 2, 3, 4])
    ref = read_out(path.with_suffix(".ref_out"))
    worst = _check([r for r in rows if r["case"] != 3], ref, [1, 2, 4], mu=0.3)
    assert worst["fn"] < 2e-4 and worst["fx_mu"] < 1e-3 and worst["fy_mu"] < 1e-3
    assert worst["pmax"] < 1e-3 and worst["area"] == 0.0
    (err,) = [r for r in rows if r["case"] == 3]
    assert not err["converged"] and "inflcf_r10_mx51.txt" in err["message"]
    assert "not found" in err["message"]


def _ibase_inp(ibase9: bool, exrhs=None, cksi=-0.0004, ceta=-0.0002):
    """A small steady-rolling module 3 case (21 x 17 elements of 0.4 mm, a Hertzian
    gap 0.00077 x^2 + 0.00098 y^2 at the approach 0.01 mm) with the gap given by
    IBASE = 1 or per element (IBASE = 9), and an optional extra rigid slip (EXRHS
    (x, y), the same for every element, E = 9)."""
    mx, my, dx = 21, 17, 0.4
    xl, yl = -0.5 * mx * dx, -0.5 * my * dx
    b1, b3 = 0.00076859, 0.00098039
    e = "9" if exrhs is not None else "0"
    text = (" 3 MODULE\n  203000  P-B-T-N-F-S\n  02202" + e + "  L-D-C-M-Z-E\n"
            " 0001341  H-G-I-A-O-W-R\n   80   200    5    1   1e-9   MAXGS\n"
            f"   0.01   {cksi}   {ceta}   0.0   PEN, CKSI, CETA, CPHI\n"
            "   0.300   0.300   FSTAT, FKIN\n   0.000   0.400   30000.   CHI, DQ, VELOC\n"
            "   0.280   0.280   82000.   82000.   POISS, GG\n    1   IPOTCN\n"
            f"   {mx}   {my}   {xl}   {yl}   {dx}   {dx}   MX,MY,XL,YL,DX,DY\n")
    if ibase9:
        text += "    9    1   IBASE, IPLAN\n"
        for j in range(my):
            y = yl + (j + 0.5) * dx
            for i in range(mx):
                x = xl + (i + 0.5) * dx
                text += f" {b1 * x * x + b3 * y * y:.12f}\n"
    else:
        text += f"    1    1   IBASE, IPLAN\n  {b1}  0.0  {b3}  0.0  0.0  0.0\n"
    if exrhs is not None:
        text += f" {exrhs[0]}  {exrhs[1]}\n" * (mx * my)
    return text + " 0 MODULE\n"


def test_undeformed_distance_per_element_and_extra_slip(tmp_path):
    """IBASE = 9 with the values of an IBASE = 1 quadratic gives the same solution
    (to the solver's tolerance), and a uniform extra rigid slip EXRHS = (a, b) is
    the creepages (CKSI + a, CETA + b): the rigid slip of every element is
    W = (CKSI - CPHI y + EXRHS_x, CETA + CPHI x + EXRHS_y) (user guide, E3 = 9)."""
    out = {}
    for name, text in {"quad": _ibase_inp(False), "table": _ibase_inp(True),
                       "creep": _ibase_inp(False, cksi=-0.0003, ceta=-0.00015),
                       "extra": _ibase_inp(True, exrhs=(0.0001, 0.00005))}.items():
        f = tmp_path / f"{name}.inp"
        f.write_text(text)
        (out[name],) = solve_inp(f)
        assert out[name]["converged"], out[name]["message"]
    q, t = out["quad"], out["table"]
    assert q["ncon"] == t["ncon"] > 50 and q["ncon"] < 0.7 * 21 * 17
    for k in ("fn_N", "fx_N", "fs_N", "pmax_MPa"):
        assert t[k] == pytest.approx(q[k], rel=1e-6), k
    c, e = out["creep"], out["extra"]
    assert 0 < c["nadh"] < c["ncon"]                  # partial slip: not trivial
    for k in ("fn_N", "fx_N", "fs_N"):
        assert e[k] == pytest.approx(c[k], rel=1e-6), k
    assert e["nadh"] == c["nadh"]
