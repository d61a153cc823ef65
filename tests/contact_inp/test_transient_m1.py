"""CONTACT's module 1 (wheel-rail) transient inputs (``examples_trans``: T = 1
shifts on the measured site_b profiles, T = 2 transient rolling after steady
rolling) against their ``.ref_out``, and the carrying of tractions from one
patch grid to another.

Tolerances (issue 34): F_x, F_s within 1 % of mu F_n, F_n within 1 %, the contact
area (elements in contact) within 3 %, p_max within 3 %, on every patch that
carries at least a tenth of the case's load (the smaller flange-flank patches:
``test_small_flange_patch``).  The normal problem is that of the steady cases
(test_testbank.py); where its F_n misses by more than 1 % on a position-
controlled case a test names it.
"""

import re
from pathlib import Path

import numpy as np
import pytest

from railcontact.contact_inp import InpError, load_inp, solve_inp
from railcontact.contact_inp.transient_m1 import (PatchState, carried_tractions, handles,
                                                  is_predecessor)

from .test_testbank import ref_out


def _ncon(path) -> dict:
    """NCON per case and patch of a CONTACT output file."""
    text = Path(path).read_text()
    parts = re.split(r"\n Case +(\d+)\n", text)
    out = {}
    for num, body in zip(parts[1::2], parts[2::2]):
        out[int(num)] = [int(m.group(1)) for m in re.finditer(
            r"NPOT\s+NCON\s+NADH\s+NSLIP.*\n\s*\d+\s+(\d+)", body)]
    return out


def _deviations(rows, path, cases):
    """Per patch of the given cases: (case, y_tr [mm], big, deviations), ``big`` where
    the patch carries at least a tenth of the case's vertical load; F_x, F_s
    relative to mu F_n."""
    ref = ref_out(path.with_suffix(".ref_out"))
    ncon = _ncon(path.with_suffix(".ref_out"))
    out = []
    for case in cases:
        mine = [r for r in rows if r["case"] == case]
        assert mine[0]["converged"], mine[0]["message"]
        c = ref[case]
        assert len(mine) == len(c["patches"]), case
        for p, n in zip(c["patches"], ncon[case]):
            r = min(mine, key=lambda r: abs(r["ycp_tr_mm"] - p["ycp_tr_mm"]))
            assert abs(r["ycp_tr_mm"] - p["ycp_tr_mm"]) < 0.05
            mu_fn = p["mu"] * p["fn_N"] if "mu" in p else r["mu"] * p["fn_N"]
            dev = {"fn": r["fn_N"] / p["fn_N"] - 1, "fx": (r["fx_N"] - p["fx_N"]) / mu_fn,
                   "fs": (r["fs_N"] - p["fs_N"]) / mu_fn,
                   "pmax": r["pmax_MPa"] / p["pmax_MPa"] - 1, "area": r["ncon"] / n - 1}
            out.append((case, p["ycp_tr_mm"], p["fn_N"] >= 0.1 * c["fz"], dev))
    return out


TOL = {"fn": 0.01, "fx": 0.01, "fs": 0.01, "pmax": 0.03, "area": 0.03}


def _assert_within(devs, keys=tuple(TOL), skip=()):
    """Every large patch's deviations within :data:`TOL` (``skip``: (case, y_tr)
    of patches left to another test)."""
    checked = 0
    for case, y, big, dev in devs:
        if not big or any(case == c and abs(y - yy) < 0.05 for c, yy in skip):
            continue
        for k in keys:
            assert abs(dev[k]) <= TOL[k], (case, y, k, dev[k])
        checked += 1
    assert checked


@pytest.fixture(scope="module")
def bank(testbank):
    return testbank / "examples_trans"


def test_handles():
    """Module 1 with T = 1 or 2 is solved here; steady (T = 3) module 1 is not."""
    from railcontact.contact_inp.reader import InpCase
    case = lambda m, t: InpCase(Path("x.inp"), 1, m, 1, {"T": t})   # noqa: E731
    assert handles(case(1, 1)) and handles(case(1, 2))
    assert not handles(case(1, 3)) and not handles(case(3, 1))


def test_shifts_from_rest(bank):
    """t1_zws: five shifts from the unloaded state (P = 2, contact formation:
    Cattaneo) at 23 to 555 kN, the wheelset's height given.  Measured: F_x, F_s
    within 0.01 % of mu F_n, F_n within 0.15 %, p_max within 0.34 %, on every
    patch above a tenth of the load."""
    path = bank / "t1_zws.inp"
    devs = _deviations(solve_inp(path, cases=[2, 3, 4, 5]), path, [2, 3, 4, 5])
    _assert_within(devs)


def test_shift_light_patch_normal_force(bank):
    """t1_zws case 2: the gauge-corner patch of 12 kN (of 23 kN) under a given
    wheelset height, on CONTACT's transient grid (its origin at the rail's s = 0,
    :class:`railcontact.contact_inp.transient_m1.SupergridNormal`) with the wheel
    samples counted from it: F_n +0.13 %, 133 elements in contact as CONTACT's,
    p_max +0.08 %.  With the grid through the reference point F_n was -2.3 %
    (CONTACT's samples fall elsewhere between its grid points), with the exact
    wheel surface -3.1 % and the area -3.8 %."""
    path = bank / "t1_zws.inp"
    devs = _deviations(solve_inp(path, cases=[2]), path, [2])
    _assert_within(devs, keys=("fn", "area"))


def test_shift_independent_of_earlier_cases(bank):
    """P = 2 starts a new sequence: a case solved alone equals the same case after
    others."""
    path = bank / "t1_zws.inp"
    alone = solve_inp(path, cases=[3])
    after = [r for r in solve_inp(path, cases=[2, 3]) if r["case"] == 3]
    assert [r["fx_N"] for r in alone] == pytest.approx([r["fx_N"] for r in after], rel=1e-9)


def test_merging_patches(bank):
    """t1_merge_cp: a shift from rest with three patches (tread 754 mm, gauge corner
    723 mm, flange flank 714 mm), then a continued shift (P = 0, S_WS + 0.4 mm,
    one element) in which tread and gauge corner merge into one patch: it starts
    from both patches' tractions.  Measured on the merged patch: F_x +0.02 %, F_s
    0.00 % of mu F_n, F_n +0.06 %, p_max 0.00 % (the grids on CONTACT's super-grid
    and the tractions carried by its lateral coordinate, the rail's s at the
    reference plus the distance in the plane; by the arc length of the rail point
    across the track F_x was -0.28 %); without the carried tractions its F_x
    would be a hundredth of CONTACT's."""
    path = bank / "t1_merge_cp.inp"
    rows = solve_inp(path)
    devs = _deviations(rows, path, [1, 2])
    _assert_within(devs)
    merged = [r for r in rows if r["case"] == 2 and abs(r["ycp_tr_mm"] - 745.65) < 0.05]
    assert merged and merged[0]["fx_N"] > 2.4e4          # the carried tractions


def test_merging_patches_gauge_corner_normal_force(bank):
    """t1_merge_cp (and t1_npotmax) case 1, gauge-corner patch of 48 kN: F_n +0.02 %
    on CONTACT's transient grid with its wheel samples (-1.5 % with the exact wheel
    surface); F_x, F_s within 0.03 % of mu F_n."""
    path = bank / "t1_merge_cp.inp"
    devs = _deviations(solve_inp(path, cases=[1]), path, [1])
    _assert_within(devs, keys=("fn",))


def test_splitting_patch(bank):
    """t1_split_cp: one combined patch (745 mm) split into tread and gauge-corner
    patches in the continued shift.  The tread patch, which holds most of the
    combined patch's traction, continues it (all of its tractions, on its grid
    extended over them); the gauge-corner patch takes those on its own grid.
    Measured in case 2: tread F_x +0.03 %, F_s 0.00 %, gauge corner F_x -0.01 %,
    F_s -0.01 % of mu F_n (taking only the tractions on the tread's own grid gave
    F_x -2.6 %, taking all of them on the gauge corner's +7.1 %); F_n within
    0.02 % (as in t1_merge_cp case 1)."""
    path = bank / "t1_split_cp.inp"
    devs = _deviations(solve_inp(path), path, [1, 2])
    _assert_within(devs)


def test_force_control_shift(bank):
    """t1_force_cp: the vertical force prescribed (N = 1) in a shift from rest and
    its continuation: the balance takes the transient tangential forces'
    vertical share.  Measured on the 127 kN patch: F_n -0.08 %, F_x +0.08 %, F_s
    0.00 % of mu F_n, p_max -0.8 %."""
    path = bank / "t1_force_cp.inp"
    _assert_within(_deviations(solve_inp(path), path, [1, 2]))


def test_steady_then_shift(bank):
    """t3_t1_force: steady rolling (T = 3, 137 kN, mu 0.9 on the head), then a shift
    of 0.4 mm (T = 1, P = 0) from the steady tractions.  Measured in the shift: F_x,
    F_s within 0.6 % of mu F_n, F_n within 0.7 %, p_max 0.6 % on the tread and
    gauge-corner patches."""
    path = bank / "t3_t1_force.inp"
    _assert_within(_deviations(solve_inp(path), path, [2]))


def test_steady_then_transient_rolling(bank):
    """t3_t2_force: steady rolling, then transient rolling (T = 2, DQ = DX = 0.4 mm)
    from it: the state stays the steady one.  Measured (cases 2-6): F_x, F_s within
    0.61 % of mu F_n, F_n 0.63 %, p_max 0.58 %."""
    path = bank / "t3_t2_force.inp"
    _assert_within(_deviations(solve_inp(path, cases=[1, 2, 3]), path, [2, 3]))


def test_small_flange_patch(bank):
    """The flange-flank patch (714 mm, 3-4 % of the load) of t1_force_cp: F_n
    -0.31 % with CONTACT's wheel sampling and gauge point (the .inp defaults; +5.9 %
    with the exact wheel surface and railcontact's gauge point), F_x, F_s within
    0.24 % of mu F_n."""
    path = bank / "t1_force_cp.inp"
    devs = _deviations(solve_inp(path, cases=[1]), path, [1])
    for case, y, big, dev in devs:
        assert abs(dev["fn"]) <= 0.01, (case, y)


def test_transient_rolling_on_a_rail_at_railyo(bank):
    """m1_trans_dqrel: a flat wheel (R 100 mm) on a rail of 100 mm crown radius placed
    at RAILY0 (a case on rail surfaces), transient rolling from rest with DQ = 4 DX
    (T = 2, P = 2), then two steps at a tenth of the creepage.  Measured: F_n
    +0.01 %, p_max 0.00 %, elements in contact CONTACT's 1273; F_x: test below."""
    path = bank / "m1_trans_dqrel.inp"
    rows = solve_inp(path)
    devs = _deviations(rows, path, [1, 2, 3])
    _assert_within(devs, keys=("fn", "fs", "pmax", "area"))
    assert [r["cksi"] for r in rows] == pytest.approx([-4.082e-2, -4.008e-3, -4.008e-3],
                                                      rel=1e-3)


def test_cattaneo_to_carter_on_a_rolled_wheel(bank):
    """m1_trans_roll: a flat wheel rolled by DROLLW = 5 deg on a circular rail,
    shifted from rest (T = 1) case after case until Carter's steady state; all 81
    cases within the issue's tolerances of CONTACT's .ref_out (the wheel's roll
    deviation and the carried tractions together)."""
    path = bank / "m1_trans_roll.inp"
    rows = solve_inp(path)
    cases = sorted({r["case"] for r in rows})
    assert len(cases) == 81
    _assert_within(_deviations(rows, path, cases))


def test_transient_rolling_from_rest_force(bank):
    """m1_trans_dqrel's first step from rest (a rolling step DQ = 4 DX, P = 2) and
    the two following steps, with CONTACT's leading-edge correction (material that
    entered the contact during the step takes its fraction of the rigid shift):
    F_x 51.71, 53.14, 54.03 N as CONTACT's .ref_out (within 0.005 % of mu F_n;
    without the correction the first step was 53.72 N, +2.1 %), adhesion elements
    696, 892, 859 as CONTACT's."""
    path = bank / "m1_trans_dqrel.inp"
    rows = solve_inp(path)
    _assert_within(_deviations(rows, path, [1, 2, 3]), keys=("fx",))
    assert [r["nadh"] for r in rows] == [696, 892, 859]


@pytest.fixture(scope="module")
def conformal_shift(bank):
    path = bank / "t3_t1_conformal.inp"
    return solve_inp(path, cases=[1, 2, 3, 4]), path


def test_conformal_shift(conformal_shift):
    """t3_t1_conformal: steady rolling on the conformal patch (D = 4), then shifts
    of 0.4 mm (T = 1, the conformal contact kept by D = 1): the exact solver's
    transient step with the conformal patch's extra slip (times 1 s) on its
    developed grid, its bar forces.  Measured on the large patch (44 mm along its
    curve, 127 kN), cases 2-4: F_n -0.12 %, F_x -0.38 %, F_s -0.41 % of mu F_n,
    p_max -0.05 %, 1530 elements in contact (CONTACT 1528)."""
    rows, path = conformal_shift
    devs = _deviations(rows, path, [2, 3, 4])
    _assert_within(devs)
    assert sum(big for *_, big, _ in devs) == 3


@pytest.mark.xfail(strict=True, reason="t3_t1_conformal flange patch in the shifts: 99 to 101 "
                   "elements in contact against CONTACT's 103 to 104 (-3.9 to -4.8 %); "
                   "F_n +0.54 to +0.56 %, F_x -0.57 % of mu F_n, p_max -0.72 % (CONTACT's "
                   "loses 0.9 % of F_n and 4 % of p_max from the steady case, on 456 "
                   "potential elements instead of 494)")
def test_conformal_shift_flange_patch(conformal_shift):
    """The flange patch (6.3 kN, -72.8 deg), steady in case 1 within 0.07 % of
    CONTACT's F_n (tests/cases/test_conformal.py); in the shifts, on CONTACT's
    super-grid (columns at multiples of DS of the rail's s, the wheel samples
    counted from the grid's origin), its F_n and p_max follow CONTACT's drop (6335
    to 6319 N, 732.3 to 704.3 MPa; CONTACT 6339 to 6284 N, 739.9 to 709.4 MPa),
    its area drops further than CONTACT's (107 to 99 elements; CONTACT 106 to 104)."""
    rows, path = conformal_shift
    for case, y, big, dev in _deviations(rows, path, [2, 3, 4]):
        for k in TOL:
            assert abs(dev[k]) <= TOL[k], (case, y, k, dev[k])


@pytest.fixture(scope="module")
def conformal_rolling(bank):
    path = bank / "t3_t2_conformal.inp"
    return solve_inp(path), path


def test_conformal_transient_rolling(conformal_rolling):
    """t3_t2_conformal: steady rolling, then transient rolling (T = 2, DQ = DX) on
    the conformal patch with F_z 137, 117, 127, 137, 137 kN.  Measured on the large
    patch of cases 2, 4, 5, 6: F_n within 0.06 %, F_x 0.80 %, F_s 0.48 % of mu F_n,
    p_max 0.06 %, elements in contact 0.14 % (case 3: the test below); the flange
    patch (under a tenth of the load) F_n +0.57 to +1.18 %."""
    rows, path = conformal_rolling
    devs = _deviations(rows, path, [2, 4, 5, 6])
    _assert_within(devs)
    assert sum(big for *_, big, _ in devs) == 4


def _middle_patch(rows, path):
    """t3_t2_conformal case 3's middle patch (723.38 mm): (CONTACT's row, ours, mu F_n)."""
    ref = ref_out(path.with_suffix(".ref_out"))[3]["patches"]
    p = min(ref, key=lambda p: abs(p["ycp_tr_mm"] - 723.38))
    r = min((r for r in rows if r["case"] == 3), key=lambda r: abs(r["ycp_tr_mm"] - 723.38))
    assert abs(r["ycp_tr_mm"] - p["ycp_tr_mm"]) < 0.05
    return p, r, r["mu"] * p["fn_N"]


def test_conformal_transient_rolling_three_patches(conformal_rolling):
    """At 117 kN the patch splits in three, as CONTACT's, and both parts of the large
    patch start from all of its previous tractions (CONTACT's grid of a connected
    patch extended over the previous contact area, :func:`carried_tractions`).
    Measured: the large patch (72.6 kN) F_n +0.02 %, F_x -0.49 %, F_s -0.07 % of
    mu F_n; the middle patch (44.2 kN, full slip, the friction 0.2 at -30 deg to
    0.9 at -20 deg) F_n +0.00 %, F_x +0.15 % of mu F_n, p_max -0.27 %, 338
    elements in contact against 340.  Its bar F_s (-2107.5 against CONTACT's
    -2011 N) in CONTACT's patch frame, the bar forces turned by the difference of
    the reference angles (-0.52716 against -0.5252 rad), is -2020.9 N: 0.10 % of
    mu F_n (mu 0.2, at the reference angle).  Before, with the lesser part of a
    split taking only the tractions on its own grid: +255 N, 18 %."""
    rows, path = conformal_rolling
    _assert_within(_deviations(rows, path, [3]), skip=[(3, 723.3827)])
    p, r, mu_fn = _middle_patch(rows, path)
    assert abs(r["fn_N"] / p["fn_N"] - 1) <= TOL["fn"]
    assert abs(r["pmax_MPa"] / p["pmax_MPa"] - 1) <= TOL["pmax"]
    assert abs(r["fx_N"] - p["fx_N"]) <= TOL["fx"] * mu_fn
    d = p["delta_tr_rad"] - r["delta_tr_rad"]
    fs_turned = r["fs_N"] * np.cos(d) + r["fn_N"] * np.sin(d)
    assert abs(fs_turned - p["fs_N"]) <= TOL["fs"] * mu_fn, (fs_turned, p["fs_N"])


@pytest.mark.xfail(strict=True, reason="t3_t2_conformal case 3, middle patch: bar F_s -2107.5 "
                   "against CONTACT's -2011 N, 1.09 % of mu F_n (mu 0.2 at the reference "
                   "angle).  Not a balance tolerance: CONTACT's z_ws stays 1.2081357 mm "
                   "and F_s -2011 N with EPS 1e-6 to 1e-10, railcontact's z_ws moves "
                   "0.3 nm between force tolerances 1e-4 and 1e-8.  Half of it (47 N) is "
                   "z_ws 15.9 nm below CONTACT's (F_z(z_ws) 0.044 % above CONTACT's at "
                   "its root, under its printed digits 1.2081 mm and 1.170E+05 N; F_s "
                   "moves 3 N per nm), half (50 N) lies at the same z_ws (the reference "
                   "angle 0.9 mrad below CONTACT's).  CONTACT's F_z(z_ws) has three roots "
                   "at 117 kN (F_s -2011, -1644, -1351 N), ours one: "
                   "docs/contact_users.md, 'What CONTACT's printed digits decide'")
def test_conformal_transient_rolling_middle_patch_bar_fs(conformal_rolling):
    """The middle patch's bar F_s as printed, against CONTACT's, 1 % of mu F_n."""
    rows, path = conformal_rolling
    p, r, mu_fn = _middle_patch(rows, path)
    assert abs(r["fs_N"] - p["fs_N"]) <= TOL["fs"] * mu_fn


def test_transient_options_stop_with_one_line(bank, tmp_path):
    """What the transient path does not support stops before any work, naming the
    option: dissimilar materials, rail slices."""
    src = (bank / "t1_zws.inp").read_text()
    bad = src.replace("0.8200E+05  0.8200E+05", "0.8200E+05  0.9000E+05", 1)
    assert bad != src
    f = tmp_path / "t1_zws_dissimilar.inp"
    f.write_text(bad.replace("'../profiles/", f"'{bank.parent / 'profiles'}/"))
    with pytest.raises(InpError, match=r"case 1 \(line 4\): TANG = 1 with dissimilar "
                                        r"materials is not supported") as err:
        load_inp(f)
    assert "\n" not in str(err.value)
    src = (bank.parent / "examples_s+c" / "cross_brute.inp").read_text()
    digits = re.search(r"\n *(\d)(\d)(\d)(\d)(\d{3}) +C-P-B-T-N-F-S", src)
    assert digits and digits.group(4) == "3"
    bad = src[:digits.start(4)] + "1" + src[digits.end(4):]
    f = bank.parent / "examples_s+c" / "cross_brute.inp"
    g = tmp_path / "cross_brute_t1.inp"
    g.write_text(bad.replace("'../", f"'{f.parent.parent}/"))
    with pytest.raises(InpError, match=r"TANG = 1 with rail slices or a roller rig is not "
                                       r"supported") as err:
        load_inp(g)
    assert "\n" not in str(err.value)


def test_carried_tractions_exact_on_coinciding_grids():
    """Tractions carried to a grid whose elements coincide with the old ones (moved
    by whole elements) arrive unchanged; on a grid offset by part of an element the
    total force and its first moment are kept."""
    dx = 1e-3
    x = (np.arange(6) - 2.5) * dx
    y = (np.arange(5) - 2.0) * dx
    rng = np.random.default_rng(1)
    px, py = rng.normal(size=(6, 5)), rng.normal(size=(6, 5))
    state = PatchState(0.0, y.copy(), x, y, px, py)
    m_of = lambda q: np.asarray(q, dtype=float)                    # noqa: E731
    # the new patch's reference point 2 elements ahead: its element i is old i + 2
    xe, ye, qx, qy = carried_tractions([state], 2 * dx, m_of, x, y)
    i = int(round((x[0] - xe[0]) / dx))
    assert np.allclose(qx[i:i + 4, :5], px[2:, :]) and np.allclose(qy[i:i + 4, :5], py[2:, :])
    assert qx.sum() == pytest.approx(px.sum())
    # a third of an element across: force and moment kept
    xe, ye, qx, qy = carried_tractions([state], dx / 3, m_of, x, y + 0.25 * dx)
    assert qx.sum() == pytest.approx(px.sum())
    X = xe[:, None] + dx / 3
    assert (qx * X).sum() == pytest.approx((px * x[:, None]).sum(), abs=1e-12)
    # T = 2: the material moved back by one element
    xe, ye, qx, _ = carried_tractions([state], 0.0, m_of, x, y, back=dx)
    i = int(round((x[0] - xe[0]) / dx))
    assert np.allclose(qx[i:i + 5, :5], px[1:, :])


def test_carried_tractions_split():
    """A previous patch split in two (CONTACT's rule, ``merge_prev_potcon``): each
    new patch takes the predecessor's tractions on its grid extended over the
    predecessor's kept contact area.  With that area kept (after a steady or a
    continued step) both take all of them; with none kept (a contact formed in a
    P = 2 step) the grid reaches only to the old grid's first element: each part
    takes what lies from there up to its own grid's end (t1_split_cp)."""
    dx = 1e-3
    x = (np.arange(4) - 1.5) * dx
    y_old = (np.arange(10) - 4.5) * dx
    px = np.ones((4, 10))
    m_of = lambda q: np.asarray(q, dtype=float)                    # noqa: E731
    area = (float(x[0]), float(x[-1]), float(y_old[0]), float(y_old[-1]))
    y_big = (np.arange(4) - 1.5) * dx + 2.0 * dx    # old columns 5-8, band y >= -2 mm
    y_small = (np.arange(3) - 1.0) * dx - 3.5 * dx  # old columns 0-2, band y < -2 mm
    total = px.sum() * dx * dx
    for kept in (area, None):
        state = PatchState(0.0, y_old.copy(), x, y_old, px, np.zeros((4, 10)), area, kept)
        xe, ye, qx, _ = carried_tractions([state], 0.0, m_of, x, y_big,
                                          bounds=(-2.0 * dx, np.inf))
        assert ye[0] == pytest.approx(y_old[0])
        if kept is None:
            # from the old grid's first element to its own grid's end: columns 0-8
            assert qx.sum() == pytest.approx(4 * 9)
        else:
            assert qx.sum() * dx * dx == pytest.approx(total) and ye[-1] >= y_old[-1]
        xe, ye, qx, _ = carried_tractions([state], 0.0, m_of, x, y_small,
                                          bounds=(-np.inf, -2.0 * dx))
        if kept is None:
            # up to its own grid's end (old columns 0-3 of 0.5 mm beyond: 0-2)
            assert ye.size == 3 and qx.sum() == pytest.approx(4 * 3)
        else:
            assert qx.sum() * dx * dx == pytest.approx(total)
            assert ye[-1] >= y_old[-1]
    # tractions outside the rectangle of the new grid and the kept area are lost
    kept = (float(x[0]), float(x[-1]), float(y_old[5]), float(y_old[-1]))
    state = PatchState(0.0, y_old.copy(), x, y_old, px, np.zeros((4, 10)), area, kept)
    xe, ye, qx, _ = carried_tractions([state], 0.0, m_of, x, y_big,
                                      bounds=(-2.0 * dx, np.inf))
    assert qx.sum() == pytest.approx(4 * 5)
    # no loaded element on the new grid within its band: not a predecessor
    assert not is_predecessor(state, 0.0, m_of, x, y_big + 20 * dx)
    xe, ye, qx, _ = carried_tractions([state], 0.0, m_of, x, y_big + 20 * dx)
    assert ye.size == 4 and not qx.any()


def test_rail_chord_length_from_the_rail_files_origin():
    """CONTACT's s of a rail point (rail_chord_length): the chord length along the
    points from where the file's y = 0.  On points every 1 mm of a circle of
    radius 0.3 m (y increasing strictly, so that s = 0 at y = 0): at y = 10.5 mm,
    ten chords and half of the next (to 1e-9 m); with the file's origin shifted
    1.25 mm across the track (``origin_shift``) s starts there instead, its s
    interpolated linearly between the points (CONTACT's ``grid_make_arclength``)."""
    from railcontact.contact_inp.transient_m1 import rail_chord_length
    from railcontact.profiles import Profile
    R, dt = 0.3, 1e-3 / 0.3
    t = np.arange(-30, 31) * dt
    rail = Profile(R * np.sin(t), R * (1 - np.cos(t)), "rail")
    chord = 2 * R * np.sin(dt / 2)
    y = R * np.sin(10.5 * dt)
    meta = {"cant": 0.0, "origin_shift": (0.0, 0.0)}
    assert rail_chord_length(rail, y, meta) == pytest.approx(10.5 * chord, abs=1e-9)
    shifted = {"cant": 0.0, "origin_shift": (1.25e-3, 0.0)}
    s0 = np.interp(-1.25e-3, R * np.sin(t), chord * np.arange(-30, 31))
    assert rail_chord_length(rail, y, shifted) == pytest.approx(10.5 * chord - s0, abs=1e-9)
