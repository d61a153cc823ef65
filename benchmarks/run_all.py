"""Timings and validations too long for the test suite (``make bench``).

Reports ratios measured in this run, and writes ``benchmarks/results.md``.
"""

from __future__ import annotations

import csv
import math
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

import railcontact as rc
from railcontact.geometry import ContactGeometry, Track, Wheelset, find_contact
from railcontact.normal import get_normal_model
from railcontact.profiles import rail_profile, s1002
from railcontact.tangential import get_tangential_model

HERE = Path(__file__).resolve().parent
REF = Path(os.environ.get("RAILCONTACT_REFERENCE", HERE.parent.parent / "shared" / "reference"))
lines = []


def out(s=""):
    print(s)
    lines.append(s)


def best_of(fn, repeat=5, number=1):
    ts = []
    for _ in range(repeat):
        t = time.perf_counter()
        for _ in range(number):
            fn()
        ts.append((time.perf_counter() - t) / number)
    return min(ts)


def mbench_case(prof, y_mm, vpitch, extra=None, solver=None):
    """Case dict of the Manchester 10 kN sweep (right wheel) at shift y_mm."""
    raw = {"material": {"young_modulus": 2 * 82e9 * 1.28, "poisson_ratio": 0.28},
           "friction": {"coefficient": 0.3},
           "wheel": {"profile": str(prof / "MBench_S1002_v3.prw")},
           "rail": {"profile": str(prof / "MBench_UIC60_v3.prr"), "inclination": 0.0},
           "wheelset": {"lateral_shift": y_mm * 1e-3, "vertical_force": 1e4, "velocity": 2.0,
                        "pitch_velocity": vpitch, "side": "right", **(extra or {})}}
    if solver:
        raw["solver"] = solver
    return rc.case_from_dict(raw)


def bench_hertz_fastsim():
    out("## Hertz + FASTSIM on one contact")
    mat = rc.Material()
    geom = ContactGeometry(curvatures=(1 / 0.92, 1 / 0.6))
    hz, fs = get_normal_model("hertz"), get_tangential_model("fastsim")

    def one(grid):
        ns = hz.solve(geom, mat, normal_force=1e5, grid=grid)
        fs.solve(ns, geom, mat, (1e-3, -5e-4, 0.2), 0.3, 30.0)
    one((20, 20))
    for grid in ((20, 20), (40, 40), (80, 80)):
        t = best_of(lambda: one(grid), 5, 20)
        out(f"* grid {grid[0]}x{grid[1]}: {t * 1e6:.0f} µs per Hertz+FASTSIM evaluation")
    return best_of(lambda: one((40, 40)), 5, 20)


def bench_contact_sweep(t_hf):
    out("\n## Wheel-rail cases: Manchester 10 kN sweep (right wheel, yaw 0, -2..10 mm)")
    if not (REF / "mbench_sweep_10kN.csv").is_file():
        out("reference data not found; skipped")
        return
    rows = list(csv.DictReader(open(REF / "mbench_sweep_10kN.csv")))
    prof = REF / "profiles"
    ours, theirs, dfn, dpm, darea = [], [], [], [], []
    for r in rows:
        y = float(r["y_ws_mm"])
        case = mbench_case(prof, y, float(r["vpitch_rad_s"]))
        rc.solve(case)
        t = best_of(lambda: rc.solve(case), 3)
        res = rc.solve(case)
        ours.append(t * 1e3)
        theirs.append(float(r["time_ms_mkl_1thread"]))
        fn = sum(p.normal.normal_force for p in res.patches)
        dfn.append(fn / float(r["fn_N"]) - 1)
        pm = max(p.normal.pmax for p in res.patches)
        dpm.append(pm / (float(r["pmax_MPa"]) * 1e6) - 1)
        ar = sum(p.normal.area for p in res.patches)
        darea.append(ar / (float(r["area_mm2"]) * 1e-6) - 1)
    ratio = [a / b for a, b in zip(ours, theirs)]
    out(f"* ours (Hertz+FASTSIM, geometry of both wheels, vertical-force iteration): median "
        f"{statistics.median(ours):.1f} ms per case")
    out(f"* CONTACT exact (one wheel, MKL, 1 thread, reference timing): median "
        f"{statistics.median(theirs):.1f} ms per case")
    out(f"* ratio ours / CONTACT: median {statistics.median(ratio):.2f} "
        f"(min {min(ratio):.2f}, max {max(ratio):.2f})")
    out(f"* Hertz+FASTSIM alone, 40x40 grid: {t_hf * 1e6:.0f} µs, i.e. "
        f"{statistics.median(ours) * 1e-3 / t_hf:.0f}x less than a whole case: the geometry dominates")
    out(f"* Hertz vs CONTACT exact, normal force: median |dFn| {100 * statistics.median(np.abs(dfn)):.2f} %,"
        f" max {100 * max(np.abs(dfn)):.2f} %")
    out(f"* Hertz vs CONTACT exact, pmax: median {100 * statistics.median(dpm):+.1f} %, "
        f"range [{100 * min(dpm):+.1f}, {100 * max(dpm):+.1f}] % (non-Hertzian patches)")
    out(f"* Hertz vs CONTACT exact, area: median {100 * statistics.median(darea):+.1f} %, "
        f"range [{100 * min(darea):+.1f}, {100 * max(darea):+.1f}] %")


def bench_exact_module3():
    out("\n## Exact solvers on CONTACT's 40x40 Hertzian timing problems")
    if not (REF / "contact_timing.csv").is_file():
        out("reference data not found; skipped")
        return
    rows = [r for r in csv.DictReader(open(REF / "contact_timing.csv"))
            if r["workload"] == "module3_hertz_40x40" and r["build"] == "mkl_fft"
            and r["omp_threads"] == "1" and r["eps"] == "1e-05"]
    mat = rc.Material.from_shear_modulus(82e9, 0.28)
    from railcontact.core.hertz_theory import hertz_ellipse
    problems = {"circ_partial_slip": (5e-3, 5e-3, (-1e-3, 2e-4, 0.1)),
                "circ_adhesion": (5e-3, 5e-3, (-1e-5, 0.0, 0.0)),
                "ellip_partial_slip": (3.5355e-3, 7.0711e-3, (-1e-3, 2e-4, 0.1))}
    nm = get_normal_model("exact", margin=0.1)
    tm = get_tangential_model("exact")
    hz, fs = get_normal_model("hertz", margin=0.1), get_tangential_model("fastsim")
    fn = 52360.0
    for r in rows:
        a, b, creep = problems[r["case"]]
        # curvatures of the Hertz ellipse with these semi-axes at this load
        A0 = 1.0
        from scipy.optimize import brentq
        B0 = 1.0 if a == b else brentq(
            lambda B: (lambda h: h.a / h.b)(hertz_ellipse(A0, B, mat.contact_modulus, force=fn))
            - a / b, 1e-3, 1e3)
        # the curvatures scaled to give semi-axis a (a ~ curvature^(-1/3) at a given force)
        k = (hertz_ellipse(A0, B0, mat.contact_modulus, force=fn).a / a) ** 3
        g = ContactGeometry(curvatures=(A0 * k, B0 * k))

        def exact():
            ns = nm.solve(g, mat, normal_force=fn, grid=(40, 40))
            return ns, tm.solve(ns, g, mat, creep, 0.3)

        def fast():
            ns = hz.solve(g, mat, normal_force=fn, grid=(40, 40))
            return fs.solve(ns, g, mat, creep, 0.3)
        exact()
        t_ex = best_of(exact, 5)
        t_fs = best_of(fast, 5, 10)
        ns, ts = exact()
        nslip = int((ts.contact & ~ts.stick).sum())
        out(f"* {r['case']}: exact {t_ex * 1e3:.1f} ms (ncon {int(ns.contact.sum())}, CONTACT "
            f"ncon {r['ncon']}; nslip {nslip}, CONTACT {r['nslip']}), CONTACT "
            f"{float(r['ms_per_case']):.1f} ms: ratio ours/CONTACT "
            f"{t_ex * 1e3 / float(r['ms_per_case']):.2f}; exact / (Hertz+FASTSIM) "
            f"{t_ex / t_fs:.0f}x")
    out("* contact and slip elements are CONTACT's in number on all three problems "
        "(tests/tangential/test_exact.py), as on its Kalker-coefficient runs with one "
        "creepage at a time")


#: CONTACT's rule for combining interpenetration regions into one patch
CONTACT_COMBINATION = {"combine_distance": 8e-3, "full_interaction_distance": 4e-3}


def _mbench_deviations(rows, element, offset=None, timed=False, wheelset=None):
    """Relative deviations of the exact solvers from CONTACT's rows (sums over the
    patches) and, where ``timed``, our time per case [ms]; ``offset``: the element
    lattice shifted by these fractions of an element (x, y), to show what its
    placement does; ``wheelset``: more wheelset keys of the cases."""
    import importlib
    exact = importlib.import_module("railcontact.normal.exact")
    real = exact.make_grid

    def shifted(ex, ey, grid=None, element_size=None, center=(0.0, 0.0), origin=(0.0, 0.0)):
        # the lattice through the solver's origin moved by the offset's fractions
        moved = (origin[0] + offset[0] * element, origin[1] + offset[1] * element)
        return real(ex, ey, grid, element_size, center, origin=moved)

    prof = REF / "profiles"
    out = {k: [] for k in ("Fn", "Fx", "Fy", "pmax", "area", "ms", "dy_ref", "angle",
                           "across")}
    try:
        if offset is not None:
            exact.make_grid = shifted
        for r in rows:
            case = mbench_case(prof, float(r["y_ws_mm"]), float(r["vpitch_rad_s"]),
                               {"roll": 0.0, **(wheelset or {})},
                               {"normal": "exact", "tangential": "exact",
                                               "element_size": [element, element]})
            P = rc.solve(case).patches                       # (also loads the kernels)
            out["ms"].append(best_of(lambda: rc.solve(case), 2) * 1e3 if timed else math.nan)
            out["Fn"].append(sum(p.normal.normal_force for p in P) / float(r["fn_mat_N"]) - 1)
            out["Fx"].append(sum(p.tangential.fx for p in P) / -float(r["fx_N"]) - 1)
            out["Fy"].append(sum(p.tangential.fy for p in P) / -float(r["fs_N"]) - 1)
            out["pmax"].append(max(p.normal.pmax for p in P)
                               / (float(r["pmax_mat_MPa"]) * 1e6) - 1)
            out["area"].append(sum(p.normal.area for p in P) / (float(r["area_mm2"]) * 1e-6) - 1)
            g = max(P, key=lambda p: p.normal.normal_force).geometry
            out["dy_ref"].append(abs(g.y_rail * 1e3 - float(r["ycp_r_mm"])))   # [mm]
            out["angle"].append(g.contact_angle / float(r["delta_tr_rad"]) - 1)
            big = max(P, key=lambda p: p.normal.normal_force).normal
            out["across"].append(int(big.contact.any(axis=0).sum()))
    finally:
        exact.make_grid = real
    return {k: np.asarray(v) for k, v in out.items()}


def bench_exact_wheel_rail():
    out("\n## Exact solvers on the Manchester 10 kN sweep (right wheel, roll 0)")
    if not (REF / "mbench_sweep_10kN.csv").is_file():
        out("reference data not found; skipped")
        return
    rows = list(csv.DictReader(open(REF / "mbench_sweep_10kN.csv")))
    ys = np.array([float(r["y_ws_mm"]) for r in rows])
    # where CONTACT's reference README says another contact search can legitimately
    # differ: near the jumps of the contact point
    jumps = ((ys >= 0.0) & (ys <= 1.0)) | ((ys >= 4.5) & (ys <= 7.0))
    dev = _mbench_deviations(rows, 0.25e-3, timed=True)
    # CONTACT's time per case (MKL build, 1 thread; contact_timing.csv, README section 3.6)
    timing = {float(r["y_ws_mm"]): float(r["ms_per_case"])
              for r in csv.DictReader(open(REF / "contact_timing.csv"))
              if r["workload"] == "mbench_sweep_10kN"}
    ratio = dev["ms"] / np.array([timing[float(r["y_ws_mm"])] for r in rows])
    tc, shape = conv_time()
    out(f"* time per case, ours / CONTACT's reference timing (contact_timing.csv): median "
        f"{statistics.median(ratio):.2f} (min {min(ratio):.2f}, max {max(ratio):.2f}; target "
        f"0.1); ours {statistics.median(dev['ms']):.2f} ms median = "
        f"{statistics.median(dev['ms']) * 1e-3 / tc:.0f} FFT convolutions of a {shape[0]} x "
        f"{shape[1]} padded grid, CONTACT's {statistics.median(timing.values()):.1f} ms "
        "(another machine and day: a ratio across runs, not interleaved); ours includes the "
        "contact search and the vertical balance (brentq, the roll given), as CONTACT's "
        "does")

    def table(dev, title):
        out(f"\n{title}\n")
        out("| | median abs | max abs (where) | max abs away from the contact jumps |")
        out("|---|---|---|---|")
        for k in ("Fn", "Fx", "Fy", "pmax", "area"):
            v = np.abs(dev[k]) * 100
            i = int(np.argmax(v))
            out(f"| {k} | {np.median(v):.2f} % | {v[i]:.2f} % ({ys[i]:g} mm) | "
                f"{v[~jumps].max():.2f} % ({ys[~jumps][int(np.argmax(v[~jumps]))]:g} mm) |")

    table(dev, "0.25 mm elements, against CONTACT on the same element size:")
    fine_file = REF / "mbench_sweep_10kN_dx0125.csv"
    if fine_file.is_file():
        fine = _mbench_deviations(list(csv.DictReader(open(fine_file))), 0.125e-3)
        table(fine, "0.125 mm elements, against CONTACT's run on that element size:")
    five = ys == 5.0
    out(f"\n* the patches' reference points lie within {dev['dy_ref'][~five].max() * 1e3:.1f} um "
        "of CONTACT's on the rail, except at 5 mm (weighted as CONTACT weights them, "
        "railcontact.geometry.regions.GAP_WEIGHT; weighted by the interpenetration itself "
        "they lay up to 1.1 mm away at 0-1 mm and 0.06-0.16 mm on the rail's crown)")
    out("* at 5 mm (a contact jump: 0-1 mm and 4.5-7 mm are where CONTACT's reference notes "
        "say another contact search can legitimately differ) CONTACT combines tread and "
        "flange root into one patch where ours are two by default, each with the creepage "
        f"of its own contact point (reference points {dev['dy_ref'][five][0]:.1f} mm apart)")
    comb = _mbench_deviations([rows[int(np.flatnonzero(five)[0])]], 0.25e-3,
                              wheelset=CONTACT_COMBINATION)
    same = _mbench_deviations([r for r, f in zip(rows, five) if not f], 0.25e-3,
                              wheelset=CONTACT_COMBINATION)
    fine_comb = None
    if fine_file.is_file():
        fine_comb = _mbench_deviations([r for r in csv.DictReader(open(fine_file))
                                        if float(r["y_ws_mm"]) == 5.0], 0.125e-3,
                                       wheelset=CONTACT_COMBINATION)
    moved = max(float(np.abs(same[q] - dev[q][~five]).max()) for q in ("Fn", "Fx", "Fy",
                                                                         "pmax", "area"))
    out("* with CONTACT's rule for combined patches (`wheelset.combine_distance` 8 mm, "
        "`wheelset.full_interaction_distance` 4 mm: one patch, its regions' mutual influence "
        "in the normal problem reduced, docs/case_files.md) the 5 mm case gives F_n "
        f"{comb['Fn'][0] * 100:+.2f} %, F_x {comb['Fx'][0] * 100:+.2f} %, F_y "
        f"{comb['Fy'][0] * 100:+.2f} %, p_max {comb['pmax'][0] * 100:+.2f} %, area "
        f"{comb['area'][0] * 100:+.2f} % (0.25 mm elements); the other 24 cases move by at "
        f"most {moved * 100:.2f} % (one region each)"
        + (f"; on 0.125 mm elements F_x {fine_comb['Fx'][0] * 100:+.2f} %, F_y "
           f"{fine_comb['Fy'][0] * 100:+.2f} %, area {fine_comb['area'][0] * 100:+.2f} %"
           if fine_comb else ""))
    k = int(np.argmax(np.abs(dev["Fx"]) * ~jumps))
    spread = {q: [] for q in ("area", "Fx")}
    for ox in (0.0, 0.5):
        for oy in (0.0, 0.25, 0.5, 0.75):
            d = _mbench_deviations([rows[k]], 0.25e-3, offset=(ox, oy))
            for q in spread:
                spread[q].append(d[q][0] * 100)
    text = (f"* at {ys[k]:g} mm ({dev['across'][k]:.0f} elements across the patch) the "
            "elements in contact move with the lattice's placement: shifting our lattice by "
            "quarter elements "
            f"gives area {min(spread['area']):+.1f} to {max(spread['area']):+.1f} % and F_x "
            f"{min(spread['Fx']):+.1f} to {max(spread['Fx']):+.1f} % from CONTACT's")
    if fine_file.is_file():
        coarse = {float(r["y_ws_mm"]): float(r["area_mm2"]) for r in rows}
        step = [coarse[float(r["y_ws_mm"])] / float(r["area_mm2"]) - 1
                for r in csv.DictReader(open(fine_file)) if float(r["y_ws_mm"]) >= 7.0]
        text += (f"; CONTACT's own area changes by {min(step) * 100:.1f}-{max(step) * 100:.1f} % "
                 "from 0.125 to 0.25 mm elements in flange contact (7-10 mm)")
    out(text)


def conv_time(m=40, n=40, repeat=7, number=400):
    """Time [s] of one real FFT convolution of an m x n grid, zero-padded as the exact
    solvers pad it (:class:`railcontact.normal.influence.Convolution`), through the
    solvers' own compiled path (rocket-fft's numpy.fft in Numba): the unit in which
    the exact timings are also reported, so that they carry across machines."""
    from railcontact.normal.polonsky_keer import _convolve
    from railcontact.normal.influence import normal_operator
    op = normal_operator(m, n, 1e-4, 1e-4, 2.3e11)
    p = np.random.default_rng(1).random((m, n))
    buf = np.zeros(op.shape)
    _convolve(p, op.khat, op.shape, buf)
    return best_of(lambda: _convolve(p, op.khat, op.shape, buf), repeat, number), op.shape


def bench_fft_unit(sizes=(20, 40, 60)):
    """The FFT convolution, the unit of every exact solve, in the forms available:
    the solvers' own (rocket-fft's numpy.fft in Numba, real transforms pruned to
    the rows that carry data, :func:`railcontact.normal.polonsky_keer._convolve`),
    the plain 2-D real transform of the padded grid in Numba, and scipy.fft's
    from Python; the padded size (scipy's ``next_fast_len``, real) against the
    exact 2 m - 1 and 2 m + 2.  The kernel's spectrum is computed once per grid
    and reused by every product of every solve on it
    (:class:`railcontact.normal.influence.Convolution`, cached per grid)."""
    from numba import njit
    from scipy import fft as sfft
    from railcontact.normal.influence import normal_operator
    from railcontact.normal.polonsky_keer import _convolve

    @njit(cache=True, nogil=True)
    def plain(p, khat, shape, buf):
        mx, my = p.shape
        buf[:mx, :my] = p
        f = np.fft.rfft2(buf)
        f *= khat
        return np.fft.irfft2(f, s=shape)[:mx, :my]

    out("\n## The FFT convolution (the unit of the exact solvers' timings)\n")
    out("| grid | padded | solvers' (pruned, Numba) | rfft2 (Numba) | scipy.fft (Python) "
        "| 2m-1 | 2m+2 |")
    out("|---|---|---|---|---|---|---|")
    for m in sizes:
        op = normal_operator(m, m, 1e-4, 1e-4, 2.3e11)
        p = np.random.default_rng(1).random((m, m))
        buf = np.zeros(op.shape)
        _convolve(p, op.khat, op.shape, buf)
        plain(p, op.khat, op.shape, buf)
        t_own = best_of(lambda: _convolve(p, op.khat, op.shape, buf), 5, 400)
        t_plain = best_of(lambda: plain(p, op.khat, op.shape, buf), 5, 400)
        t_py = best_of(lambda: op(p), 5, 400)
        other = []
        for n in (2 * m - 1, 2 * m + 2):
            b2 = np.zeros((n, n))
            kh = np.fft.rfft2(np.ones((n, n)))
            _convolve(p, kh, (n, n), b2)
            other.append(best_of(lambda: _convolve(p, kh, (n, n), b2), 5, 200))
        out(f"| {m} x {m} | {op.shape[0]} x {op.shape[1]} | {t_own * 1e6:.1f} µs | "
            f"{t_plain * 1e6:.1f} µs | {t_py * 1e6:.1f} µs | {other[0] * 1e6:.1f} µs | "
            f"{other[1] * 1e6:.1f} µs |")


def bench_force_controlled(step=10, block=(0, 120)):
    """Issue 30's force-controlled balance of the exact case
    (``BalanceOptions(force_control=True)``: one patch a side, each side's
    normal problem solved for its load, the exact tangential problem at the end)
    against the general balance on the interpenetrations, case by case
    interleaved: every ``step``-th case of the 1000-case sweep cold, and the cases
    ``block`` warm-started along the sweep; every time also in FFT convolutions."""
    from railcontact.cases.balance import BalanceOptions
    from railcontact.cases.case import case_from_dict
    raws = sweep_raws(load=7e4)
    tc = conv_time(repeat=3, number=100)[0]
    out("\n## The exact case: force-controlled balance against the general balance "
        "(1000-case sweep, 70 kN, 40 x 40)\n")
    out("| run | balance | mean | median | max / median | passes (searches) | load met |")
    out("|---|---|---|---|---|---|---|")
    runs = (("cold, every %d-th case" % step, raws[::step], False),
            ("warm, cases %d-%d" % block, raws[block[0]:block[1]], True))
    for label, rs, warm in runs:
        cases = [case_from_dict(r) for r in rs]
        t = {False: [], True: []}
        passes = {False: [], True: []}
        ok = {False: 0, True: 0}
        prev = {False: None, True: None}
        for c in cases:
            for fc in (False, True):
                t0 = time.perf_counter()
                res = rc.solve(c, "exact", "exact", warm_start=prev[fc] if warm else None,
                               options=BalanceOptions(force_control=fc))
                t[fc].append(time.perf_counter() - t0)
                prev[fc] = res
                passes[fc].append(res.balance.passes)
                ok[fc] += res.converged
        for fc in (False, True):
            v = np.asarray(t[fc])
            out(f"| {label} | {'force-controlled' if fc else 'general'} | "
                f"{v.mean() * 1e3:.2f} ms = {v.mean() / tc:.0f} conv. | "
                f"{np.median(v) * 1e3:.2f} ms = {np.median(v) / tc:.0f} conv. | "
                f"{v.max() / np.median(v):.1f} | {np.mean(passes[fc]):.2f} | "
                f"{ok[fc]} of {len(cases)} |")
    out(f"* the unit: one FFT convolution of the 80 x 80 padded grid, {tc * 1e6:.1f} µs in "
        "this run")


#: the parts of a wheel-rail case whose time :func:`time_split` reports: (label,
#: module, attribute); nested parts are reported inside their parent
SPLIT = [("contact search", "railcontact.cases.balance", "contact_search"),
         ("exact normal solves", "railcontact.normal.exact", "ExactNormalModel.solve"),
         ("  of which Polonsky-Keer iterations", "railcontact.normal.polonsky_keer", "_pk_kernel"),
         ("exact tangential solves", "railcontact.tangential.exact", "ExactTangentialModel.solve"),
         ("  of which semi-smooth Newton-GMRES", "railcontact.tangential.exact", "ssn_solve"),
         ("FASTSIM stand-ins", "railcontact.tangential.fastsim", "FastsimModel.solve")]


def time_split(cases, warm=False):
    """Wall time per case [s] of whole exact cases and of their parts (:data:`SPLIT`),
    and the calls per case, measured by wrapping the parts with timers."""
    import functools
    import importlib
    spent = {label: [0.0, 0] for label, _, _ in SPLIT}
    saved = []
    for label, mod, attr in SPLIT:
        owner = importlib.import_module(mod)
        *path, name = attr.split(".")
        for p in path:
            owner = getattr(owner, p)
        real = getattr(owner, name)

        def timed(*a, _real=real, _label=label, **k):
            t0 = time.perf_counter()
            try:
                return _real(*a, **k)
            finally:
                spent[_label][0] += time.perf_counter() - t0
                spent[_label][1] += 1
        saved.append((owner, name, real))
        setattr(owner, name, functools.wraps(real)(timed))
    try:
        prev = None
        t0 = time.perf_counter()
        for c in cases:
            prev = rc.solve(c, "exact", "exact", warm_start=prev if warm else None)
        total = time.perf_counter() - t0
    finally:
        for owner, name, real in saved:
            setattr(owner, name, real)
    n = len(cases)
    return total / n, {k: (v[0] / n, v[1] / n) for k, v in spent.items()}


def sweep_raws(n_shift=250, yaws=(0.0, 2e-3, 4e-3, 6e-3), load=7e4):
    """The 1000-case sweep: S1002 on 60E1 1:40, shift -4..9 mm, yaw 0..6 mrad,
    creepages varying along the sweep, ``load`` per wheel, 40 x 40 grid."""
    raws = []
    for iy, yaw in enumerate(yaws):
        for k, y in enumerate(np.linspace(-4e-3, 9e-3, n_shift)):
            j = iy * n_shift + k
            raws.append({"wheel": {"profile": "S1002"}, "rail": {"profile": "60E1"},
                         "wheelset": {"lateral_shift": float(y), "yaw": yaw,
                                      "vertical_force": load, "velocity": 30.0},
                         "creepage": {"longitudinal": 1.5e-3 * math.sin(2 * math.pi * j / 97),
                                      "lateral": 1e-3 * math.cos(2 * math.pi * j / 61),
                                      "spin": 0.2 * math.sin(2 * math.pi * j / 43)},
                         "solver": {"grid": [40, 40]}})
    return raws


def bench_exact_sweep(n_shift=250, yaws=(0.0, 2e-3, 4e-3, 6e-3)):
    """Exact normal + exact steady rolling on a 40x40 grid against Hertz + FASTSIM,
    cold and warm-started, on ~1000 wheel-rail cases with the vertical force given;
    every timing also in units of one real FFT convolution of the padded grid."""
    n = n_shift * len(yaws)
    out(f"\n## Exact solvers on a {n}-case sweep (S1002 on 60E1 1:40, shift -4..9 mm, "
        "yaw 0..6 mrad, creepages varying along the sweep, 60 kN per wheel, 40x40 grid)")
    raws = sweep_raws(n_shift, yaws, 6e4)
    from railcontact.cases.case import case_from_dict
    from railcontact.cases.bodies import contact_search
    cases = [case_from_dict(r) for r in raws]
    shifts = np.array([r["wheelset"]["lateral_shift"] for r in raws])
    loose = []
    for r in raws:
        r = {k: (dict(v) if isinstance(v, dict) else v) for k, v in r.items()}
        r["solver"]["force_tolerance"] = 1e-3
        loose.append(case_from_dict(r))
    rc.solve(cases[0], "exact", "exact")                       # compile / load
    rc.solve(cases[0], "hertz", "fastsim")
    # the runs interleaved in blocks of 50 cases, so that a slower phase of the
    # machine falls on all of them alike; every case timed on its own
    keys = ("geom", "hf", "cold", "warm", "loose", "alone_warm", "alone_cold")
    t = {k: np.zeros(n) for k in keys}
    cpu = {k: np.zeros(n) for k in keys}      # CPU time: the tail without the machine's pauses
    conv = []
    ok = {"cold": 0, "warm": 0}
    stick, cold, warm_fx, passes, resid, loose_fx, ok_loose = [], [], [], [], [], [], 0
    cold_fn, warm_fn, warm_resid, warm_passes = [], [], [], []
    prev = last = None

    def timed(key, i, fn):
        t0, c0 = time.perf_counter(), time.process_time()
        res = fn()
        t[key][i] = time.perf_counter() - t0
        cpu[key][i] = time.process_time() - c0
        return res

    for b0 in range(0, n, 50):
        block = range(b0, min(b0 + 50, n))
        conv.append(conv_time(repeat=3, number=100)[0])
        for i in block:                                   # as the solve's first search
            timed("geom", i, lambda: contact_search(cases[i], load_iterations=1))
        for i in block:
            timed("hf", i, lambda: rc.solve(cases[i], "hertz", "fastsim"))
        cold_res = [timed("cold", i, lambda: rc.solve(cases[i], "exact", "exact"))
                    for i in block]
        warm_res = []
        for i in block:
            prev = timed("warm", i, lambda: rc.solve(cases[i], "exact", "exact",
                                                     warm_start=prev))
            warm_res.append(prev)
        loose_res = [timed("loose", i, lambda: rc.solve(loose[i], "exact", "exact"))
                     for i in block]
        # the exact solves alone: each patch of the warm results once more on its final
        # geometry, from the previous case's solutions and cold
        for mode in ("alone_warm", "alone_cold"):
            for k, i in enumerate(block):
                nb = (warm_res[k - 1] if k else last) if mode == "alone_warm" else None
                timed(mode, i, lambda: _solves_alone(cases[i], warm_res[k], nb))
        last = warm_res[-1]
        for res in cold_res:
            ok["cold"] += res.converged
            passes.append(res.balance.passes)
            resid.append(max(abs(v) for v in res.vertical_residual.values()))
            stick.extend(p.tangential.stick_fraction for p in res.patches)
            cold.append(sum(p.tangential.fx for p in res.patches))
            cold_fn.append(sum(p.normal.normal_force for p in res.patches))
        for res in warm_res:
            ok["warm"] += res.converged
            warm_fx.append(sum(p.tangential.fx for p in res.patches))
            warm_fn.append(sum(p.normal.normal_force for p in res.patches))
            warm_passes.append(res.balance.passes)
            warm_resid.append(max(abs(v) for v in res.vertical_residual.values()))
        for res in loose_res:
            ok_loose += res.converged
            loose_fx.append(sum(p.tangential.fx for p in res.patches))
    tc = float(np.median(conv))
    _, shape = conv_time()
    mean = {k: float(v.mean()) for k, v in t.items()}
    cold = np.asarray(cold)
    dev_warm = np.abs(np.asarray(warm_fx) - cold) / (0.3 * 1.2e5)
    dev_loose = np.abs(np.asarray(loose_fx) - cold) / (0.3 * 1.2e5)
    st = np.asarray(stick)

    def both(s):
        return f"{s * 1e3:.2f} ms = {s / tc:.0f} convolutions"

    out(f"* the unit: one real FFT convolution of the padded grid ({shape[0]} x {shape[1]} "
        f"for 40 x 40 elements; rocket-fft in Numba, as the solvers' products) took "
        f"{tc * 1e6:.1f} µs in this run (median of {len(conv)} measurements between the "
        "blocks)")
    out(f"* patches in partial slip (stick fraction 5-95 %): "
        f"{np.mean((st > 0.05) & (st < 0.95)) * 100:.0f} %, in full slip "
        f"{np.mean(st <= 0.05) * 100:.0f} %")
    out(f"* (a) Hertz + FASTSIM, whole case (geometry, vertical balance): "
        f"{both(mean['hf'])} per case (target 1 ms)")
    for mode, ok_n, target in (("cold", ok["cold"], 5e-3), ("warm", ok["warm"], 2e-3)):
        v = t[mode]
        out(f"* (b) exact + exact, {mode}: {both(mean[mode])} per case (target "
            f"{target * 1e3:.0f} ms), (b)/(a) = {mean[mode] / mean['hf']:.1f}; median "
            f"{np.median(v) * 1e3:.2f} ms, slowest {v.max() * 1e3:.1f} ms = "
            f"{v.max() / np.median(v):.1f} x the median (case {int(np.argmax(v))}, "
            f"{shifts[int(np.argmax(v))] * 1e3:.2f} mm); {ok_n} of {n} meet the load; "
            f"in CPU time (the shared machine's pauses out) median "
            f"{np.median(cpu[mode]) * 1e3:.2f} ms, slowest {cpu[mode].max() * 1e3:.1f} ms = "
            f"{cpu[mode].max() / np.median(cpu[mode]):.1f} x the median (case "
            f"{int(np.argmax(cpu[mode]))}, {shifts[int(np.argmax(cpu[mode]))] * 1e3:.2f} mm), "
            f"{int(np.sum(cpu[mode] > 3 * np.median(cpu[mode])))} cases over 3 x")
    resid = np.asarray(resid)
    miss = resid > 1e-4
    if miss.any():
        out(f"* vertical load met to 1e-4 in {n - miss.sum()} of {n} cases (cold); the "
            f"others: {', '.join(f'{r * 100:.2g} %' for r in np.sort(resid[miss])[::-1])}, "
            f"at {_span(shifts[miss] * 1e3)} mm shift")
    else:
        out(f"* vertical load met to 1e-4 in all {n} cases, cold and "
            f"{'warm' if max(warm_resid) <= 1e-4 else 'not all warm'}-started")
    out(f"* passes of the vertical balance (each a contact search and the normal problems, "
        f"or the tangential problems at the last interpenetrations): {np.mean(passes):.2f} "
        f"per case cold (max {max(passes)}), {np.mean(warm_passes):.2f} warm-started "
        f"(max {max(warm_passes)}); the slowest cases are flange contact at 6.2-7 mm where "
        "a second region joins the flange patch near the load")
    both_met = ~miss & (np.asarray(warm_resid) <= 1e-4)
    tread = both_met & (shifts < 6.2e-3)
    flange = both_met & (shifts >= 6.2e-3)
    dfn = np.abs(np.asarray(warm_fn) - np.asarray(cold_fn)) / 1.2e5
    out(f"* warm / cold: {mean['warm'] / mean['cold']:.2f}: a warm-started case starts "
        "from a contact search at its neighbour's interpenetrations and Jacobian, and its "
        "pressures and tractions")
    out(f"* warm against cold, where both met the load: sum F_x differs by "
        f"{np.median(dev_warm[both_met]) * 100:.3f} % of mu Q (median), "
        f"{np.percentile(dev_warm[both_met], 95) * 100:.2f} % (95th percentile); up to "
        f"{dev_warm[tread].max() * 100:.2f} % below 6.2 mm shift, where the 40x40 grid's "
        "extent follows the iteration's path (docs/case_files.md); up to "
        f"{dev_warm[flange].max() * 100:.2f} % in flange contact (6.2-9 mm), where the "
        "vertical balance grows by only about a quarter of F_n per F_n, so that the grids' "
        "small difference in F_y/F_n moves F_n four times as much (sum F_n up to "
        f"{dfn[flange].max() * 100:.1f} % of Q apart; {dfn[tread].max() * 100:.3f} % below "
        "6.2 mm; on CONTACT's lattice of elements warm and cold agree, "
        "tests/test_warm_start.py)")
    out(f"* (b) exact + exact, cold, vertical load to 1e-3 (`solver.force_tolerance`): "
        f"{both(mean['loose'])} per case, (b)/(a) = {mean['loose'] / mean['hf']:.1f}; "
        f"{ok_loose} of {n} converged; sum F_x within {dev_loose[~miss].max() * 100:.3f} % "
        "of mu Q of the 1e-4 run")
    out(f"* one contact search under the load (both wheels, one multi-Hertzian iteration): "
        f"{both(mean['geom'])}")
    out(f"* the exact solves alone, once per patch on the warm result's final geometry "
        f"(normal problem at its approach, then the tangential one; no contact search, no "
        f"vertical balance): {both(mean['alone_warm'])} per case from the previous case's "
        f"solutions, {both(mean['alone_cold'])} cold")
    out("* the timings above were taken interleaved, in blocks of 50 cases")
    # where the time goes: the parts of a case, timed on every fifth case
    sub = cases[::5]
    for mode in ("cold", "warm"):
        total, parts = time_split(sub if mode == "cold" else cases[:len(sub)], mode == "warm")
        out(f"\nWhere an exact case's time goes ({mode}, {len(sub)} cases, "
            f"{both(total)} per case):\n")
        out("| part | ms per case | share | calls per case |")
        out("|---|---|---|---|")
        for label, (s, calls) in parts.items():
            out(f"| {label.strip()}{' (within the above)' if label.startswith(' ') else ''} "
                f"| {s * 1e3:.2f} | {s / total * 100:.0f} % | {calls:.1f} |")
        rest = total - sum(s for label, (s, _) in parts.items() if not label.startswith(" "))
        out(f"| the rest (balance, creepages, grids, results) | {rest * 1e3:.2f} | "
            f"{rest / total * 100:.0f} % | |")


def _span(v):
    """'a-b' of the smallest and largest of v, or 'a' where they are one."""
    lo, hi = f"{min(v):.2f}", f"{max(v):.2f}"
    return lo if lo == hi else f"{lo}-{hi}"


def _solves_alone(case, res, neighbour):
    """The exact normal (approach given) and tangential problems of every patch of
    ``res`` solved once on its geometry, warm-started from the nearest patch of
    ``neighbour`` (a result) or cold."""
    from railcontact.normal import get_normal_model
    from railcontact.cases.patches import nearest_patch as _nearest
    from railcontact.tangential import get_tangential_model
    nm, tm = get_normal_model("exact"), get_tangential_model("exact")
    for p in res.patches:
        g = p.geometry
        q = _nearest(neighbour.patches, g) if neighbour is not None else None
        ns = nm.solve(g, case.material, penetration=g.approach, grid=case.grid,
                      warm_start=q.normal if q else None)
        tm.solve(ns, g, case.material, p.creepage, case.friction, g.velocity,
                 warm_start=q.tangential if q else None)


def bench_sweep_parallel():
    out("\n## Parallel sweep (Dask)")
    case = rc.load_case(HERE.parent / "examples" / "wheel_rail.toml")
    vary = {"wheelset.lateral_shift": [round(0.0005 * i, 6) for i in range(16)]}
    rc.sweep(case, vary, scheduler="sync", progress=False)
    t_sync = best_of(lambda: rc.sweep(case, vary, scheduler="sync", progress=False), 2)
    t_thr = best_of(lambda: rc.sweep(case, vary, scheduler="threads", progress=False), 2)
    t_proc = best_of(lambda: rc.sweep(case, vary, scheduler="processes", progress=False), 2)
    out(f"* 16 wheel-rail cases: sync {t_sync:.2f} s, threads {t_thr:.2f} s, processes "
        f"{t_proc:.2f} s (speed-up {t_sync / t_proc:.2f} on {os.cpu_count()} cores, worker "
        "start-up included)")
    vary = {"wheelset.lateral_shift": [round(0.0001 * i, 6) for i in range(128)]}
    t_sync = best_of(lambda: rc.sweep(case, vary, scheduler="sync", progress=False), 1)
    t_proc = best_of(lambda: rc.sweep(case, vary, scheduler="processes", progress=False), 1)
    out(f"* 128 wheel-rail cases: sync {t_sync:.2f} s, processes {t_proc:.2f} s "
        f"(speed-up {t_sync / t_proc:.2f})")
    vary = {"wheelset.lateral_shift": [round(0.00004 * i, 7) for i in range(256)]}
    t_sync = best_of(lambda: rc.sweep(case, vary, "exact", "exact", scheduler="sync",
                                      progress=False), 1)
    t_proc = best_of(lambda: rc.sweep(case, vary, "exact", "exact", scheduler="processes",
                                      progress=False), 1)
    out(f"* 256 exact wheel-rail cases: sync {t_sync:.2f} s, processes {t_proc:.2f} s "
        f"(speed-up {t_sync / t_proc:.2f}); `scheduler=\"auto\"` starts processes where a "
        "sweep is expected to take over 8 s in one process (from 400 exact or 1600 "
        "Hertz + FASTSIM cases)")


FAST_MODELS = [("hertz", "fastsim"), ("kik-piotrowski", "fastsim"), ("kpec", "fastsim"),
               ("stripes", "fastsim"), ("analyn", "fastsim"), ("analyn", "fastsim-strips"),
               ("analyn", "fastrip"), ("hertz", "fastrip"), ("hertz", "polach")]


def bench_fast_models(n_shift=250, yaws=(0.0, 2e-3, 4e-3, 6e-3)):
    """Every fast model on the same 1000 wheel-rail cases (S1002 on 60E1 1:40)."""
    n = n_shift * len(yaws)
    out(f"\n## Fast models on a {n}-case sweep (S1002 on 60E1 1:40, shift -4..9 mm, "
        f"yaw 0..6 mrad, 60 kN per wheel)")
    mat = rc.Material()
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    t0 = time.perf_counter()
    patches = []
    for yaw in yaws:
        for y in np.linspace(-4e-3, 9e-3, n_shift):
            c = find_contact(ws, tr, lateral_shift=float(y), yaw=yaw, vertical_force=6e4,
                             material=mat)
            patches.extend(p for p in c.patches if p.approach > 0)
    t_geom = time.perf_counter() - t0
    out(f"* geometry (contact search, both wheels): {1e3 * t_geom / n:.1f} ms per case; "
        f"{len(patches)} loaded patches")
    times = {}
    for nname, tname in FAST_MODELS:
        nm, tm = get_normal_model(nname), get_tangential_model(tname)
        nm.solve(patches[0], mat, penetration=patches[0].approach)      # compile/warm caches
        t0 = time.perf_counter()
        for g in patches:
            ns = nm.solve(g, mat, penetration=g.approach)
            tm.solve(ns, g, mat, g.creepage, 0.3, g.velocity)
        times[(nname, tname)] = (time.perf_counter() - t0) / n
    ref = times[FAST_MODELS[0]]
    from railcontact.cases.batch import solve_patches
    batch = {}
    pairs = [("hertz", law) for law in ("fastsim", "polach", "fastrip")] + [
        (nname, law) for nname in ("kik-piotrowski", "kpec", "stripes", "analyn")
        for law in ("fastsim", "polach", "fastsim-strips", "fastrip")]
    for nname, law in pairs:
        solve_patches(patches[:4], nname, law)                          # compile / load
        batch[(nname, law)] = best_of(lambda: solve_patches(patches, nname, law),
                                      repeat=5) / n
    ref_b = batch[("hertz", "fastsim")]
    out("\nPer-patch models (the registered models: grids, pressure interpolators and "
        "result objects for every patch):\n")
    out("| normal | tangential | time per case (both wheels) | ratio to per-patch Hertz+FASTSIM |")
    out("|---|---|---|---|")
    for (nname, tname), t in times.items():
        out(f"| {nname} | {tname} | {t * 1e3:.2f} ms | {t / ref:.1f} |")
    out("\nCompiled batch path `railcontact.cases.batch.solve_patches` (all patches of the "
        "sweep in one call, forces, area and p_max only): Hertz vectorised with FASTSIM "
        "20x20 per ellipse (FaStrip: the ellipse in 20 strips of 20 elements); the strip "
        "models on 40 strips per patch, FASTSIM (equivalent ellipse), FASTSIM with local "
        "ellipses and spin per strip, and FaStrip marching their strip pressures (20 "
        "elements per strip); Polach on the (equivalent) ellipse.\n")
    out("| normal | tangential | time per case (both wheels) | ratio to batch Hertz+FASTSIM |")
    out("|---|---|---|---|")
    for (nname, law), t in batch.items():
        out(f"| {nname} | {law} | {t * 1e6:.1f} µs | {t / ref_b:.1f} |")
    worst_pair = max((k for k in batch if k != ("hertz", "fastsim")), key=batch.get)
    worst = batch[worst_pair] / ref_b
    out(f"\nBatch Hertz+FASTSIM: {ref_b * 1e6:.1f} µs per case (target 50 µs); the slowest "
        f"batch model pair ({' + '.join(worst_pair)}) is {worst:.1f}x Hertz+FASTSIM "
        f"(target 10x).  "
        f"The per-patch Hertz+FASTSIM costs {ref / ref_b:.0f}x its batch form.")
    out(f"\nThe contact search itself costs {1e3 * t_geom / n:.1f} ms per case, "
        f"{t_geom / n / ref_b:.0f}x batch Hertz+FASTSIM.")


def bench_strips_accuracy():
    """Equivalent ellipse vs local ellipses against the exact solver, quartic gap."""
    out("\n## FASTSIM on a non-Hertzian gap h = x^2 + 2.5 y^2 + 4e5 y^4 [m], 50 kN, "
        "ANALYN pressure, vs the exact solver")
    mat = rc.Material(2.1e11, 0.28)
    g = ContactGeometry(curvatures=(1.0, 2.5),
                        gap_function=lambda x, y: x * x + 2.5 * y * y + 4e5 * y ** 4)
    ns = get_normal_model("analyn").solve(g, mat, normal_force=5e4, grid=(50, 50))
    ne = get_normal_model("exact").solve(g, mat, normal_force=5e4, grid=(50, 50))
    out("\n| creepage | exact | fastsim (equivalent ellipse) | fastsim-strips (local ellipses) |")
    out("|---|---|---|---|")
    for label, creep, comp in (("xi = 1e-4", (1e-4, 0, 0), "fx"), ("eta = 1e-4", (0, 1e-4, 0), "fy"),
                               ("phi = 0.05 1/m", (0, 0, 0.05), "fy")):
        ref = getattr(get_tangential_model("exact").solve(ne, g, mat, creep, 0.3), comp)
        cells = []
        for name in ("fastsim", "fastsim-strips"):
            v = getattr(get_tangential_model(name, flexibility="three").solve(ns, g, mat, creep, 0.3),
                        comp)
            cells.append(f"{v:.1f} N ({100 * (v / ref - 1):+.1f} %)")
        out(f"| {label} | {comp} {ref:.1f} N | {cells[0]} | {cells[1]} |")


def bench_tangential_accuracy():
    """FASTSIM and FaStrip against the exact solver on Hertzian patches."""
    out("\n## FASTSIM and FaStrip vs the exact solver, Hertz patches (100 kN, mu 0.3, 60x60)")
    mat = rc.Material(2 * 82e9 * 1.28, 0.28)
    out("\n| A:B | creepage (xi, eta, phi [1/m]) | exact Fx, Fy [N] | fastsim | fastrip |")
    out("|---|---|---|---|---|")
    for AB in ((1.0, 1.0), (1.0, 4.0), (4.0, 1.0)):
        g = ContactGeometry(curvatures=AB)
        ns = get_normal_model("hertz").solve(g, mat, normal_force=1e5, grid=(60, 60))
        for creep in ((1e-3, 0, 0), (2e-3, 1e-3, 0), (0, 0, 0.3), (1e-3, 0, 0.5),
                      (-0.01, 0, 0.5)):
            ex = get_tangential_model("exact").solve(ns, g, mat, creep, 0.3)
            cells = []
            for name in ("fastsim", "fastrip"):
                t = get_tangential_model(name).solve(ns, g, mat, creep, 0.3)
                cells.append(f"{100 * (t.fx - ex.fx) / 3e4:+.1f} / {100 * (t.fy - ex.fy) / 3e4:+.1f} %")
            out(f"| {AB[0]:g}:{AB[1]:g} | {creep} | {ex.fx:.0f}, {ex.fy:.0f} | {cells[0]} | "
                f"{cells[1]} |")
    out("\nDifferences in % of mu Fn (Fx / Fy).")


def bench_dynamics(duration=100.0, velocity=50.0, exact_duration=0.01):
    """Issue 6: the benchmark vehicle on a curved, irregular track, against real time."""
    from railcontact.dynamics import (Integration, Route, VehicleModel, WheelRailTable,
                                      simulate_vehicle)
    from railcontact.dynamics.route import Irregularities
    from railcontact.dynamics.vehicle import G_ACC
    out("## Vehicle dynamics: Manchester vehicle, 50 m/s, curved irregular track\n")
    model = VehicleModel.vehicle()
    t0 = time.perf_counter()
    table = WheelRailTable.build(Wheelset(s1002()),
                                 Track(rail_profile("60E1", math.atan(1 / 40))),
                                 model.wheelsets[0][1] * G_ACC / 2)
    t_table = time.perf_counter() - t0
    length = velocity * duration + 40.0
    route = Route.from_segments(
        [{"type": "tangent", "length": 300.0}, {"type": "transition", "length": 200.0},
         {"type": "curve", "radius": 2500.0, "cant": 0.12, "length": length - 500.0}],
        Irregularities.from_psd(length, "ERRI-low", seed=7))
    phi = math.asin(0.12 / 1.5)
    au = velocity ** 2 / 2500.0 * math.cos(phi) - G_ACC * math.sin(phi)
    simulate_vehicle(model, route, table, velocity, 0.5)        # compile / load the cache
    simulate_vehicle(model, route, table, velocity, 0.5, integration=Integration("lsoda"))
    rows = []
    ds = simulate_vehicle(model, route, table, velocity, duration, "fastsim")
    rows.append(("Hertz table + FASTSIM (compiled, 12x12), rk4", duration, ds))
    ds_l = simulate_vehicle(model, route, table, velocity, duration, "fastsim",
                            integration=Integration("lsoda"))
    rows.append(("Hertz table + FASTSIM (compiled, 12x12), LSODA rtol 1e-6", duration, ds_l))
    ds_p = simulate_vehicle(model, route, table, velocity, duration, "polach")
    rows.append(("Hertz table + Polach (compiled), rk4", duration, ds_p))
    ds_e = simulate_vehicle(model, route, table, velocity, exact_duration, "exact")
    rows.append(("Hertz table + exact tangential (Python, 20x20), LSODA", exact_duration, ds_e))
    out(f"Contact table (121 shifts, multi-Hertzian search): {t_table:.1f} s, once per "
        "profile pair.  One core; LSODA with the compiled right-hand side.\n")
    out("| tangential law | simulated [s] | wall [s] | wall / simulated | RHS calls | "
        "µs per RHS call |")
    out("|---|---|---|---|---|---|")
    for name, dur, d in rows:
        w = d.attrs["wall_time_s"]
        out(f"| {name} | {dur:g} | {w:.2f} | {w / dur:.3g} | {d.attrs['rhs_calls']} | "
            f"{1e6 * w / d.attrs['rhs_calls']:.0f} |")
    dy = float(abs(ds["lateral_displacement"] - ds_l["lateral_displacement"]).max())
    dY = float(abs(ds["Y"] - ds_l["Y"]).max())
    out(f"\nrk4 (step {ds.attrs['step_s'] * 1e3:.2f} ms) against LSODA over the 100 s: "
        f"wheelset displacements differ by at most {dy * 1e6:.1f} µm, wheel forces Y by "
        f"{dY:.0f} N (max |Y| {float(abs(ds_l['Y']).max()) / 1e3:.1f} kN).")
    curve = ds.where(ds["curvature"] > 0.99 / 2500.0, drop=True)
    ysum = curve["Y"].sum(("wheelset", "side"))
    out(f"\nIn the curve (FASTSIM run): mean ΣY = {float(ysum.mean()) / 1e3:.2f} kN against "
        f"M a_u = {model.total_mass * au / 1e3:.2f} kN (irregular track, so the balance "
        f"holds on average only); max |Y/Q| = {float(abs(ds['Y_over_Q']).max()):.2f}; "
        f"wheelset 1 mean lateral displacement "
        f"{float(curve['lateral_displacement'].sel(wheelset=1).mean()) * 1e3:.2f} mm.\n")


def _wear_runs(sc):
    """Step-1 tables and dynamics runs of a closed-loop scenario (the same for every
    local model): (simulation, tables per route, datasets per route, grids)."""
    from railcontact.dynamics.simulation import Integration, simulate_vehicle
    from railcontact.wear.closed_loop import ClosedLoopWear
    from railcontact.wear.mapping import arc_length_grid
    from railcontact.wear.route_tasks import build_table
    sim = ClosedLoopWear(sc, None, progress=False)
    table = build_table(*sim.wheels[0], *sim.rails[0], sim.rail_offsets, sim.settings)
    tables = [table] * sim.nw
    d = sc.dynamics
    runs = [simulate_vehicle(sc.model, r.route, tables, r.speed, r.duration, d["tangential"],
                             r.friction, sc.case.material, d["initial_lateral_shift"],
                             d["tangential_options"], d["fastsim_grid"],
                             Integration(d["integrator"], d["sample_rate"], d["rtol"],
                                         step=d["step"]))
            for r in sc.routes]
    grid = arc_length_grid(sim.wheels[0][0], sc.grid_step)
    rgrid = arc_length_grid(sim.rails[0][0], sc.grid_step)
    return sim, tables, runs, grid, rgrid


def _wear_post(sc, sim, tables, runs, grid, rgrid, model, sample_distance=None,
               reuse=None, warm=True):
    """Post-process the runs with one model: (vehicle-averaged wheel wear per metre
    of the route mix, smoothed as the loop does; PostProcessStats per route)."""
    from railcontact.wear import get_wear_law
    from railcontact.wear.mapping import smooth_depth
    from railcontact.wear.postprocess import PatchPostProcessor
    n, t = model.split("+")
    pp = PatchPostProcessor(n, t, get_wear_law(sc.law, **sc.parameters), sc.case.material,
                            sc.case.grid, sc.case.element_size,
                            reuse_tolerance=sc.reuse_tolerance if reuse is None else reuse,
                            warm=warm)
    total = np.zeros_like(grid)
    stats = []
    for w, item, ds in zip(sim.weights, sc.routes, runs):
        stride = max(1, int(round((sample_distance or sc.sample_distance)
                                  * sc.dynamics["sample_rate"] / item.speed)))
        res = pp.run(ds, tables, sim.wheels, sim.rails[0], [[grid, grid]] * sim.nw,
                     [rgrid, rgrid], item.friction, stride)
        total += w * sum(d for pair in res["wheel"] for d in pair) / (2 * sim.nw)
        stats.append(res["stats"])
    return smooth_depth(total, sc.grid_step, sc.smoothing), stats


def bench_wear_closed_loop(full: bool = True):
    """Issue 24: closed-loop wear of examples/wear_vehicle.toml (one core): (a) exact +
    exact against Hertz + FASTSIM, (b) the per-patch cost of every model and, unless
    ``full`` is False, (c) the sample stride, (d) repeated states, (e) the step size."""
    from railcontact.inputs import load_wear_scenario
    from railcontact.wear.closed_loop import ClosedLoopWear
    out("## Closed-loop wear: examples/wear_vehicle.toml (Manchester vehicle, tangent + "
        "R1200 + R300, 4 steps of 0.1 mm, USFD), one core (scheduler sync)\n")
    sc = load_wear_scenario(HERE.parent / "examples" / "wear_vehicle.toml")
    sc.scheduler = "sync"
    # (a) the example with Hertz + FASTSIM and with exact + exact, interleaved by step
    models = {"hertz+fastsim": sc, "exact+exact": sc.with_models("exact", "exact")}
    sims = {m: ClosedLoopWear(s, None, progress=False) for m, s in models.items()}
    wall = dict.fromkeys(models, 0.0)
    cpu = dict.fromkeys(models, 0.0)
    for _ in range(sc.steps + 1):
        for m, sim in sims.items():
            t0, c0 = time.perf_counter(), time.process_time()
            if sim.step < sc.steps:
                sim.run_step()
            else:
                ds = sim.run(resume=False)        # the final state's measures
                sims[m] = ds
            wall[m] += time.perf_counter() - t0
            cpu[m] += time.process_time() - c0
    hf, ex = sims["hertz+fastsim"], sims["exact+exact"]
    out("| local model | wall [s] | CPU [s] | tables [s] | dynamics [s] | post-processing "
        "[s] | solves [s] | patches | solved | reused | ms per solved patch |")
    out("|---|---|---|---|---|---|---|---|---|---|---|")
    for m, ds in sims.items():
        solved = float(ds["patches_solved"].sum())
        out(f"| {m} | {wall[m]:.1f} | {cpu[m]:.1f} | {float(ds['table_time'].sum()):.1f} | "
            f"{float(ds['dynamics_time'].sum()):.1f} | "
            f"{float(ds['postprocess_time'].sum()):.1f} | {float(ds['solve_time'].sum()):.1f} "
            f"| {int(ds['patches'].sum())} | {int(solved)} | {int(ds['patches_reused'].sum())} "
            f"| {1e3 * float(ds['solve_time'].sum()) / solved:.2f} |")
    out(f"\n* exact + exact / Hertz + FASTSIM, whole run: wall {wall['exact+exact'] / wall['hertz+fastsim']:.2f}, "
        f"CPU {cpu['exact+exact'] / cpu['hertz+fastsim']:.2f} (target <= 5); Hertz + FASTSIM "
        f"run {wall['hertz+fastsim']:.0f} s (target < 120 s); the two runs interleaved step "
        "by step")
    for m, ds in sims.items():
        law, rem = ds["law_area_wheel"].values, ds["removed_area_wheel"].values
        s = ds.sel(route="R300", wheelset=1)
        out(f"* {m}: {ds.attrs['total_distance_m'] / 1e3:.0f} km; removed area / law's total "
            f"- 1: max {np.max(np.abs(rem / law - 1)) * 100:.3f} %; equivalent conicity "
            f"{' -> '.join(f'{g:.4f}' for g in ds['equivalent_conicity'].sel(route='tangent', wheelset=1).values)}; "
            f"R300 wheelset 1 mean lateral position "
            f"{float(s['lateral_position'].isel(step=0)) * 1e3:.3f} -> "
            f"{float(s['lateral_position'].isel(step=-1)) * 1e3:.3f} mm, outer flange contact on "
            f"the wheel {float(s['contact_y_wheel'].sel(side='left', patch='flange').isel(step=0)) * 1e3:.2f}"
            f" -> {float(s['contact_y_wheel'].sel(side='left', patch='flange').isel(step=-1)) * 1e3:.2f} mm")

    # (b) per-patch post-processing cost of every model, on the same step-1 runs
    sim, tables, runs, grid, rgrid = _wear_runs(sc)
    out("\nPer-patch cost of the post-processing, every model on the same step-1 dynamics "
        f"({sc.case.grid[0]}x{sc.case.grid[1]} grids, samples every 2 m, no reuse; models "
        "interleaved; 'all' includes the wear law and the mapping onto the profiles):\n")
    out("| local model | patches | ms per patch (solves) | ms per patch (all) | / Hertz + FASTSIM |")
    out("|---|---|---|---|---|")
    rows = []
    for m, warm in (("hertz+fastsim", True), ("kik-piotrowski+fastsim", True),
                    ("kpec+fastsim", True), ("stripes+fastsim", True),
                    ("analyn+fastsim", True), ("hertz+exact", True), ("exact+exact", True),
                    ("exact+exact", False)):
        c0 = time.process_time()
        _, st = _wear_post(sc, sim, tables, runs, grid, rgrid, m, sample_distance=2.0,
                           reuse=0.0, warm=warm)
        c = time.process_time() - c0
        n = sum(x.solved for x in st)
        rows.append((m + ("" if warm else " (cold: no warm starts)"), n,
                     1e3 * sum(x.solve_time for x in st) / n, 1e3 * c / n))
    for name, n, solve, allt in rows:
        out(f"| {name} | {n} | {solve:.3f} | {allt:.3f} | {allt / rows[0][3]:.1f} |")

    if not full:
        return
    # (c) the stride: samples every 0.25 .. 4 m against every dynamics sample
    out("\nSample stride (step-1 runs, dynamics sampled at 400 Hz: one sample per 0.1, "
        "0.09, 0.05 m on the three routes): the route mix's wheel wear per metre "
        "(vehicle-averaged, smoothed) against every sample's, max |difference| / max:\n")
    sc4 = load_wear_scenario(HERE.parent / "examples" / "wear_vehicle.toml")
    sc4.dynamics["sample_rate"] = 400.0
    sim4, tables4, runs4, grid4, rgrid4 = _wear_runs(sc4)
    out("| local model | 0.25 m | 0.5 m | 1 m (default) | 2 m | 4 m |")
    out("|---|---|---|---|---|---|")
    for m in ("hertz+fastsim", "exact+exact"):
        ref, _ = _wear_post(sc4, sim4, tables4, runs4, grid4, rgrid4, m,
                            sample_distance=1e-3)
        cells = []
        for dist in (0.25, 0.5, 1.0, 2.0, 4.0):
            w, _ = _wear_post(sc4, sim4, tables4, runs4, grid4, rgrid4, m,
                              sample_distance=dist)
            cells.append(f"{np.max(np.abs(w - ref)) / ref.max() * 100:.2f} %")
        out(f"| {m} | " + " | ".join(cells) + " |")

    # (d) repeated states: the reuse tolerance
    out("\nRepeated states (step-1 runs, samples every 1 m): the wear per metre against "
        "solving every patch, and the share of patches reused:\n")
    out("| local model | tolerance | reused | max difference / max | post-processing CPU / "
        "without reuse |")
    out("|---|---|---|---|---|")
    for m in ("hertz+fastsim", "exact+exact"):
        c0 = time.process_time()
        ref, _ = _wear_post(sc, sim, tables, runs, grid, rgrid, m, reuse=0.0)
        c_ref = time.process_time() - c0
        for tol in (1e-3, 1e-2):
            c0 = time.process_time()
            w, st = _wear_post(sc, sim, tables, runs, grid, rgrid, m, reuse=tol)
            c = time.process_time() - c0
            share = sum(x.reused for x in st) / sum(x.patches for x in st)
            out(f"| {m} | {tol:g} | {share * 100:.0f} % | "
                f"{np.max(np.abs(w - ref)) / ref.max() * 100:.3f} % | {c / c_ref:.2f} |")

    # (e) step size: K steps against 2K of half the distance
    out(f"\nStep size (Hertz + FASTSIM): the final wheel profiles of K steps against 2K "
        "steps of half the distance, max |difference| / the maximum wear depth, over the "
        "whole profile and away from the contact jumps (the wheel positions the contact "
        "skips between neighbouring table shifts of the new and the final profiles, "
        "widened by 2 mm; target < 5 %):\n")
    out("| steps | distance [km] | max depth [mm] | whole profile | at y [mm] | away from "
        "jumps | at y [mm] | excluded [mm] | conicity at the end (K, 2K) |")
    out("|---|---|---|---|---|---|---|---|---|")
    total = float(hf.attrs["total_distance_m"])
    d = [float(v) for v in hf["distance"].values]
    runs = {}
    for label, dists in (("2 (step control) / 4", [d[0], d[1]]),
                         ("4 / 8", [total / 4] * 4), ("8 / 16", [total / 8] * 8)):
        pair = []
        for ds_ in (dists, [x / 2 for x in dists for _ in (0, 1)]):
            key = tuple(ds_)
            if key not in runs:
                s2 = load_wear_scenario(HERE.parent / "examples" / "wear_vehicle.toml")
                s2.scheduler, s2.steps, s2.distances = "sync", len(ds_), list(ds_)
                sim2 = ClosedLoopWear(s2, None, progress=False)
                runs[key] = (sim2.run(resume=False), sim2)
            pair.append(runs[key])
        out("| " + label + " | " + _halving_row(*pair[0], *pair[1]) + " |")


def _halving_row(coarse, _, fine, sim):
    """A row of the step-size table: the final wheel profiles of a run and of its
    run of halved steps (wheelset 1, right; the example wears all wheels alike)."""
    from railcontact.wear.route_tasks import away_from_contact_jumps, build_table
    sel = {"wheelset": 1, "side": "right"}
    y = coarse["y_wheel"].values
    diff = np.abs(coarse["profile_z_wheel"].sel(**sel).isel(state=-1).values
                  - fine["profile_z_wheel"].sel(**sel).isel(state=-1).values)
    depth = fine["wear_depth_wheel"].sel(**sel).sum("step").values.max()
    ok = np.isfinite(diff)
    w0 = sim.initial_wheels[1]
    tabs = [build_table(w0, w0, *sim.rails[0], sim.rail_offsets, sim.settings),
            build_table(*sim.wheels[0], *sim.rails[0], sim.rail_offsets, sim.settings)]
    away = ok & away_from_contact_jumps(tabs, y)
    i = int(np.nanargmax(np.where(ok, diff, np.nan)))
    j = int(np.nanargmax(np.where(away, diff, np.nan)))
    g = [float(r["equivalent_conicity"].sel(route="tangent", wheelset=1).values[-1])
         for r in (coarse, fine)]
    return (f"{float(fine.attrs['total_distance_m']) / 1e3:.0f} | {depth * 1e3:.3f} | "
            f"{diff[i] / depth * 100:.1f} % | {y[i] * 1e3:.1f} | {diff[j] / depth * 100:.1f} % | "
            f"{y[j] * 1e3:.1f} | {np.count_nonzero(~away & ok) * (y[1] - y[0]) * 1e3:.0f} | "
            f"{g[0]:.4f}, {g[1]:.4f}")


def bench_subsurface():
    """Subsurface stresses of a 40 x 40 patch (Hertz + FASTSIM, 1e5 N): the cost per
    depth in FFT convolutions of the padded grid (issue 31 asks for at most 10), with
    the kernel spectra of the grid and depth cached (patches on one grid, repeated
    calls) and built afresh (a new grid; in reused arrays, and in new memory); and
    the accuracy against Johnson's Hertz
    axis and CONTACT's subsurf.ref_subs."""
    from railcontact.subsurface import kernels
    from railcontact.subsurface.stresses import subsurface_stresses
    from railcontact.normal.influence import normal_operator
    out("\n## Subsurface stresses (40 x 40 patch)")
    mat = rc.Material()
    geom = ContactGeometry(curvatures=(1 / 0.92, 1 / 0.6))
    ns = get_normal_model("hertz").solve(geom, mat, normal_force=1e5, grid=(40, 40))
    ts = get_tangential_model("fastsim").solve(ns, geom, mat, (1e-3, -5e-4, 0.2), 0.3, 30.0)
    depths = np.linspace(0.0, 2.0 * ns.semi_axes[1], 21)
    from railcontact.normal.polonsky_keer import _convolve
    op = normal_operator(40, 40, ns.dx, ns.dy, mat.contact_modulus)
    shape = op.shape
    buf = np.zeros(shape)

    def cold():
        kernels.clear_cache()           # the arrays kept for reuse, as in a long run
        subsurface_stresses(ns, ts, depths=depths, material=mat)

    def fresh():
        kernels.clear_cache(release=True)       # new memory from the system
        subsurface_stresses(ns, ts, depths=depths, material=mat)
    # CPU time, the five timed in turn (best of 9 rounds): the ratios hold on a
    # loaded machine, where wall-clock timings taken minutes apart do not
    jobs = {"conv": (lambda: _convolve(ns.pressure, op.khat, shape, buf), 400),
            "scipy": (lambda: op(ns.pressure), 400),
            "warm": (lambda: subsurface_stresses(ns, ts, depths=depths, material=mat), 20),
            "cold": (cold, 5), "fresh": (fresh, 5)}
    for f, _ in jobs.values():
        f()
    t = {k: math.inf for k in jobs}
    for _ in range(9):
        for k, (f, n) in jobs.items():
            t0 = time.process_time()
            for _ in range(n):
                f()
            t[k] = min(t[k], (time.process_time() - t0) / n)
    tc, t_scipy, warm, t_cold, t_fresh = t["conv"], t["scipy"], t["warm"], t["cold"], t["fresh"]
    nz = depths.size
    out(f"* unit: one FFT convolution of the padded {shape[0]}x{shape[1]} grid, {tc * 1e6:.1f} µs "
        f"compiled (the exact solvers' unit), {t_scipy * 1e6:.1f} µs through scipy.fft")
    out(f"* kernel spectra cached (same grid and depths): {warm / nz * 1e6:.0f} µs per depth = "
        f"{warm / nz / tc:.1f} compiled convolutions ({warm / nz / t_scipy:.1f} scipy ones)")
    out(f"* kernel spectra built (a new grid): {t_cold / nz * 1e6:.0f} µs per depth = "
        f"{t_cold / nz / tc:.1f} compiled convolutions ({t_cold / nz / t_scipy:.1f} scipy ones)")
    out(f"* the same in memory new from the system (the cache's arrays released): "
        f"{t_fresh / nz * 1e6:.0f} µs per depth = {t_fresh / nz / tc:.1f} compiled convolutions "
        f"({t_fresh / nz / t_scipy:.1f} scipy ones)")
    ss = subsurface_stresses(ns, ts, depths=depths, material=mat)
    m = ss.maximum("von_mises")
    out(f"* this patch: max von Mises {m['value'] * 1e-6:.0f} MPa at depth {m['depth'] * 1e3:.2f} mm "
        f"(p0 {ns.pmax * 1e-6:.0f} MPa)")
    # Hertz's circular contact on the axis (Johnson 1985, eq. 3.45)
    sph = ContactGeometry(curvatures=(2.0, 2.0))
    nu = mat.poisson_ratio
    for grid in ((41, 41), (81, 81)):
        h = get_normal_model("hertz").solve(sph, mat, normal_force=1e5, grid=grid)
        a, p0 = h.semi_axes[0], h.pmax
        zr = np.array([0.1, 0.25, 0.5, 0.75, 1.0, 2.0])
        s = subsurface_stresses(h, depths=zr * a, material=mat)
        i, j = int(np.argmin(abs(h.x))), int(np.argmin(abs(h.y)))
        sz = -p0 / (1 + zr ** 2)
        sr = p0 * (-(1 + nu) * (1 - zr * np.arctan(1 / zr)) + 0.5 / (1 + zr ** 2))
        e = max(np.abs(s.sigma[0, i, j] / sr - 1).max(), np.abs(s.sigma[2, i, j] / sz - 1).max())
        out(f"* Hertz axis, {grid[0]}x{grid[1]} grid, z/a 0.1..2: largest deviation of sigma_r, "
            f"sigma_z from Johnson {100 * e:.2f} %")


def bench_rcf_cost():
    """The RCF damage measures beside wear (railcontact.wear.rcf): their CPU time per
    patch against the wear post-processing's, one closed-loop step of
    examples/wear_vehicle.toml, without (FI_surf, WLRM) and with FI_sub (a
    subsurface stress field per solved patch)."""
    import dataclasses
    from railcontact.inputs import load_wear_scenario
    from railcontact.wear.closed_loop import ClosedLoopWear
    out("\n## RCF damage measures beside wear (examples/wear_vehicle.toml, one step)")
    for sub in (False, True):
        sc = load_wear_scenario(HERE.parent / "examples" / "wear_vehicle.toml")
        sc.steps = 1
        sc.scheduler = "sync"
        sc.rcf = dataclasses.replace(sc.rcf, subsurface=sub)
        ds = ClosedLoopWear(sc, None, progress=False).run(resume=False)
        rcf = float(ds["rcf_time"].sum())
        post = float(ds["postprocess_time"].sum())
        solved = float(ds["patches_solved"].sum())
        label = "with FI_sub" if sub else "FI_surf + WLRM (no subsurface field)"
        out(f"* {label}: {rcf / solved * 1e3:.2f} ms per solved patch, "
            f"{100 * rcf / (post - rcf):.1f} % of the rest of the post-processing "
            f"({(post - rcf) / solved * 1e3:.2f} ms per solved patch; {solved:.0f} solved)")


def bench_fmu(n_steps=400, dt=1e-3):
    """The contact element's FMU (railcontact fmu) stepped by FMPy's FMI 3.0 API
    through a hunting-like history, against the Python API's evaluation alone."""
    out("\n## Contact element FMU (FMI 3.0 co-simulation, FMPy), cost per step")
    try:
        from fmpy import extract, read_model_description
        from fmpy.fmi3 import FMU3Slave
        from railcontact.fmu import build_fmu
    except ImportError as exc:
        out(f"fmpy/pythonfmu3 not installed ({exc}); skipped")
        return
    import tempfile
    from railcontact.dynamics.contact_element import WheelsetState
    from railcontact.inputs import contact_element
    with tempfile.TemporaryDirectory() as tmp:
        path = build_fmu(Path(tmp) / "element.fmu")
        md = read_model_description(str(path))
        vr = {v.name: v.valueReference for v in md.modelVariables}
        unzipdir = extract(str(path))
        t = np.arange(n_steps) * dt
        w = 2 * np.pi * 5.0
        y, yaw = 3e-3 * np.sin(w * t), 1e-3 * np.cos(w * t)
        ins = [vr[k] for k in ("lateral_shift", "yaw", "vertical_position")]
        outs = [vr[f"force_{c}"] for c in "xyz"] + [vr[f"torque_{c}"] for c in "xyz"]
        fmu = FMU3Slave(guid=md.guid, unzipDirectory=unzipdir,
                        modelIdentifier=md.coSimulation.modelIdentifier, instanceName="bench")
        fmu.instantiate()
        fmu.enterInitializationMode()
        fmu.setFloat64(ins, [y[0], yaw[0], 3e-4])
        fmu.exitInitializationMode()
        got = np.empty((n_steps, 6))
        ts = np.empty(n_steps)
        for k in range(n_steps):
            t0 = time.perf_counter()
            fmu.setFloat64(ins, [y[k], yaw[k], 3e-4])
            fmu.doStep(currentCommunicationPoint=t[k], communicationStepSize=dt)
            got[k] = fmu.getFloat64(outs)
            ts[k] = time.perf_counter() - t0
        t_fmu = float(np.median(ts))
        fmu.terminate()
        fmu.freeInstance()
    el = contact_element()
    want = np.empty((n_steps, 6))
    for k in range(n_steps):
        t0 = time.perf_counter()
        r = el.evaluate(WheelsetState(lateral_shift=y[k], yaw=yaw[k], vertical_position=3e-4))
        want[k, :3], want[k, 3:] = r.force, r.torque
        ts[k] = time.perf_counter() - t0
    t_api = float(np.median(ts))
    dev = np.abs(got - want).max() / np.abs(want).max()
    out(f"* {n_steps} steps of {dt * 1e3:g} ms (y = 3 mm sin, yaw = 1 mrad cos at 5 Hz; S1002 on "
        f"60E1, Hertz + FASTSIM, position mode), medians: {t_fmu * 1e3:.2f} ms per FMU step "
        f"(set inputs, doStep, get 6 outputs), {t_api * 1e3:.2f} ms per API evaluation: "
        f"FMI overhead {(t_fmu - t_api) * 1e3:.3f} ms per step")
    out(f"* largest deviation of the FMU's forces and torques from the API's: {dev:.1e} "
        "(relative to the largest)")
    _fmu_c_host(el)


def _fmu_c_host(element):
    """The FMU run by a host in C (benchmarks/fmu_c_host.c) in a process of its own,
    with the environment of docs/multibody.md; its forces against the API's."""
    import shutil
    import subprocess
    import sysconfig
    import tempfile
    import zipfile
    from railcontact.dynamics.contact_element import WheelsetState
    from railcontact.inputs import contact_element
    from railcontact.fmu import build_fmu
    import pythonfmu3
    if shutil.which("gcc") is None:
        out("* C host: no gcc; skipped")
        return
    fmi = Path(pythonfmu3.__file__).parent / "pythonfmu-export" / "src" / "fmi"
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        subprocess.run(["gcc", "-O1", "-o", str(tmp / "host"), str(HERE / "fmu_c_host.c"),
                        f"-I{fmi}", "-ldl"], check=True)
        with zipfile.ZipFile(build_fmu(tmp / "e.fmu")) as z:
            z.extractall(tmp / "fmu")
        xml = (tmp / "fmu" / "modelDescription.xml").read_text()
        token = xml.split('instantiationToken="')[1].split('"')[0]
        import site
        env = dict(os.environ,
                   LD_PRELOAD=os.path.join(sysconfig.get_config_var("LIBDIR"),
                                           sysconfig.get_config_var("LDLIBRARY")),
                   PYTHONHOME=sys.base_prefix,
                   PYTHONPATH=os.pathsep.join(site.getsitepackages() + [str(HERE.parent)]))
        t0 = time.perf_counter()
        run = subprocess.run([str(tmp / "host"),
                              str(tmp / "fmu" / "binaries" / "x86_64-linux" /
                                  "RailContactElement.so"), str(tmp / "fmu" / "resources"),
                              token, "0.003", "1.8e-4"], env=env, capture_output=True, text=True)
        wall = time.perf_counter() - t0
    if run.returncode != 0:
        out(f"* C host: FAILED (exit status {run.returncode}): {run.stderr.strip()[-300:]}")
        return
    got = np.array([float(v) for v in run.stdout.split()])
    r = element.evaluate(WheelsetState(lateral_shift=0.003, vertical_position=1.8e-4))
    want = np.r_[r.force, r.torque]
    out(f"* a host in C (benchmarks/fmu_c_host.c, libpython preloaded): one step in a fresh "
        f"process in {wall:.1f} s (start of Python, imports, Numba cache); forces and torques "
        f"against the API's: largest relative deviation "
        f"{np.abs(got - want).max() / np.abs(want).max():.1e}")


def bench_quasi_elastic(alphas=(1e-5, 2e-5, 3e-5, 5e-5)):
    """Arnold's quasi-elastic contact against the multi-Hertzian elastic one on
    S1002/60E1 1:40 at 70 kN: the normal force across the rigid contact jumps, the
    penetration, the equivalent conicity, the linear critical speed."""
    out("\n## Arnold's quasi-elastic contact vs multi-Hertzian, S1002/60E1 1:40, 70 kN")
    from railcontact.dynamics import VehicleModel, WheelRailTable, critical_speed
    from railcontact.dynamics.contact_element import WheelsetState
    from railcontact.inputs import contact_element
    from railcontact.geometry import contact_table, equivalent_conicity
    from railcontact.geometry.quasi_elastic import quasi_elastic_contact, quasi_elastic_table
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", inclination=math.atan(1 / 40)))
    element = contact_element(tangential="none", mode="load")

    def jump_at(lo, hi, size):
        a = lambda y: quasi_elastic_contact(ws, tr, y, alpha=1e-8).points["right"].contact_angle
        alo = a(lo)
        while hi - lo > 1e-7:
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if abs(a(mid) - alo) < size else (lo, mid)
        return 0.5 * (lo + hi)

    for lo, hi, size in ((4.9e-3, 5.1e-3, 0.05), (6.2e-3, 6.3e-3, 0.3)):
        yj = jump_at(lo, hi, size)
        row = []
        for h in (4e-6, 1e-6):
            ys = np.arange(yj - 2e-5, yj + 2e-5 + h / 2, h)
            steps = {}
            for a in (1e-8, 3e-5):
                d = np.array([quasi_elastic_contact(ws, tr, y, alpha=a).points["right"]
                              .contact_angle for y in ys])
                steps[a] = np.abs(np.diff(70e3 / np.cos(d))).max()
            fn = np.array([element.evaluate(WheelsetState(lateral_shift=y, loads=(70e3, 70e3)))
                           .normal_force["right"] for y in ys])
            steps["mh"] = np.abs(np.diff(fn)).max()
            row.append(f"h = {h * 1e6:g} um: rigid {steps[1e-8] / 1e3:.2f} kN, quasi-elastic "
                       f"(alpha 3e-5) {steps[3e-5] / 1e3:.3f} kN, multi-Hertzian {steps['mh'] / 1e3:.2f} kN")
        out(f"* jump of the rigid contact point at y = {yj * 1e3:.3f} mm, largest step of the "
            f"right wheel's normal force within +-20 um: " + "; ".join(row))
    ys = np.arange(-4e-3, 4.01e-3, 1e-3)
    el = [find_contact(ws, tr, y, 0.0, vertical_force=70e3).interpenetration for y in ys]
    for a in alphas:
        r = np.array([[quasi_elastic_contact(ws, tr, y, alpha=a).points[s].penetration / e[s]
                       for s in ("left", "right")] for y, e in zip(ys, el)])
        out(f"* alpha = {a:g} m: quasi-elastic / multi-Hertzian vertical penetration over shifts "
            f"-4..4 mm: {r.min():.2f} .. {r.max():.2f} (mean {r.mean():.3f})")
    ysc = np.arange(-8e-3, 8.01e-3, 2.5e-4)
    amps = (1e-3, 2e-3, 3e-3, 4e-3, 6e-3)
    tabs = {"multi-Hertzian (70 kN)": contact_table(ws, tr, ysc, vertical_force=70e3),
            "rigid": quasi_elastic_table(ws, tr, ysc, alpha=1e-8)}
    for a in alphas:
        tabs[f"quasi-elastic alpha {a:g}"] = quasi_elastic_table(ws, tr, ysc, alpha=a)
    out("* equivalent conicity (EN 15302 wavelength method) at amplitudes "
        + ", ".join(f"{x * 1e3:g}" for x in amps) + " mm:")
    for name, tb in tabs.items():
        out(f"  * {name}: " + ", ".join(f"{equivalent_conicity(tb, x):.3f}" for x in amps))
    mh = WheelRailTable.build(ws, tr, 60e3, shift_range=0.01, step=2.5e-4)
    qe = WheelRailTable.quasi_elastic(ws, tr, 60e3, 3e-5, shift_range=0.01, step=2.5e-4)
    for m in ("bogie", "vehicle"):
        model = VehicleModel.from_parameters(m, {})
        out(f"* Manchester {m}, linear critical speed: multi-Hertzian table "
            f"{critical_speed(model, mh):.1f} m/s, quasi-elastic (alpha 3e-5) "
            f"{critical_speed(model, qe):.1f} m/s")


def bench_wear_grid_reuse(repeat: int = 5):
    """Issue 29: grid reuse in the wear post-processing (the exact normal solver's
    declared "grid-reuse"): a bogie on a 40 m R300 curve, every sample post-processed
    with exact + exact and no repeated states, with and without the kept grid,
    interleaved ``repeat`` times (medians)."""
    from railcontact.dynamics.simulation import Integration, simulate_vehicle
    from railcontact.inputs import wear_scenario_from_dict
    from railcontact.wear import get_wear_law
    from railcontact.wear.postprocess import PatchPostProcessor
    from railcontact.wear.route_tasks import build_table
    sc = wear_scenario_from_dict({
        "wheel": {"profile": "S1002"}, "rail": {"profile": "60E1", "inclination": 0.025},
        "solver": {"normal": "hertz", "tangential": "fastsim", "grid": [20, 20]},
        "vehicle": {"model": "bogie"}, "dynamics": {"table_range": 0.010, "table_step": 5e-4},
        "wear": {"law": "usfd", "steps": 1},
        "route": [{"name": "R300", "radius": 300.0, "cant": 0.1, "speed": 20.0,
                   "length": 40.0, "lead": 5.0}]})
    sim = sc.driver(progress=False)
    table = build_table(*sim.wheels[0], *sim.rails[0], sim.rail_offsets, sim.settings)
    item = sc.routes[0]
    ds = simulate_vehicle(sc.model, item.route, table, item.speed, item.duration,
                          friction=item.friction, integration=Integration(sample_rate=100.0))
    grid = np.arange(0.0, 0.2, 1e-4)
    args = (ds, [table, table], [list(sim.wheels[0])] * 2, sim.rails[0], [[grid, grid]] * 2,
            [grid, grid], item.friction, 1)
    pps = {}
    for keep in (False, True):
        pp = PatchPostProcessor("exact", "exact", get_wear_law("usfd"), sc.case.material,
                                (20, 20), reuse_tolerance=0.0)
        pp.regrid = keep and pp.regrid
        pp.run(*args)                                          # compiled, warm
        pps[keep] = pp
    wall, solve, res = {False: [], True: []}, {False: [], True: []}, {}
    for _ in range(repeat):
        for keep, pp in pps.items():
            t0 = time.perf_counter()
            res[keep] = pp.run(*args)
            wall[keep].append(time.perf_counter() - t0)
            solve[keep].append(res[keep]["stats"].solve_time)
    same = all(np.array_equal(np.array(res[True][k]), np.array(res[False][k]))
               for k in ("wheel", "rail")) and res[True]["energy"] == res[False]["energy"]
    out("## Wear post-processing: grid reuse (exact + exact, bogie on R300, "
        f"{res[True]['stats'].solved} solves, medians of {repeat} interleaved runs)\n")
    out("| kept grid | post-processing [s] | solves [s] |")
    out("|---|---|---|")
    for keep in (False, True):
        out(f"| {'yes' if keep else 'no'} | {statistics.median(wall[keep]):.3f} | "
            f"{statistics.median(solve[keep]):.3f} |")
    out(f"\n* wear depths and energy with and without it bit-identical: {same}\n")


def bench_roller_rig(yaw_stiffness=(2e4, 5e4, 1e5, 2e5), lateral_stiffness=(1.55e5, 1.55e6)):
    """The 1:5 wheelset of examples/roller_rig_dynamics.toml on rollers of 0.18 m and
    on tangent track: the linear critical speeds over the primary stiffnesses, and
    which roller-rig terms move it (the roller's curvature in the Hertz patch alone;
    the kinematics alone: the leaning normal, the roller's spin, its radius in xi);
    the contact's x against the 3-D roller search; the cost of the example."""
    import copy
    import dataclasses
    import runpy
    out("\n## Roller rig (1:5 S1002/60E1, rollers of 0.18 m): rig against tangent track")
    from railcontact.dynamics.roller_rig import (O_XC, RigSystem, RollerRig, critical_speed,
                                                 rig_tables, run_rig_scenario)
    from railcontact.inputs import load_dynamics_scenario
    sc = load_dynamics_scenario(HERE.parent / "examples" / "roller_rig_dynamics.toml")
    t0 = time.perf_counter()
    rig_tab, track_tab = rig_tables(sc)
    out(f"* contact table, {rig_tab.shift.size} shifts: {time.perf_counter() - t0:.2f} s")
    out("| k_y [N/m] | k_psi [N m/rad] | track [m/s] | rig [m/s] | rig/track | Hertz only "
        "| kinematics only |")
    out("|---|---|---|---|---|---|---|")
    for ky in lateral_stiffness:
        for kp in yaw_stiffness:
            w = dataclasses.replace(sc.vehicle, k_y=ky, k_yaw=kp)

            def vc(rig, tab):
                try:
                    return critical_speed(w, rig, tab)
                except (rc.InputError, ValueError) as exc:
                    return str(exc).split(": ")[-1]
            hertz = copy.copy(rig_tab)
            hertz.radius = None
            kin = copy.copy(track_tab)
            kin.radius = sc.rig.radius
            vt, vr = vc(sc.rig.on_track(), track_tab), vc(sc.rig, rig_tab)
            vh, vk = vc(sc.rig.on_track(), hertz), vc(sc.rig, kin)
            f = lambda v: f"{v:.1f}" if isinstance(v, float) else v
            ratio = f"{vr / vt:.3f}" if isinstance(vr, float) and isinstance(vt, float) else "-"
            out(f"| {ky:.3g} | {kp:.3g} | {f(vt)} | {f(vr)} | {ratio} | {f(vh)} | {f(vk)} |")
    ex = runpy.run_path(str(HERE.parent / "examples" / "roller_rig_scaled.py"))
    system = RigSystem(sc.vehicle, sc.rig, rig_tab)
    for y, psi in ((0.0, 0.838e-3), (0.0, -2e-3), (4e-4, 1e-3), (-6e-4, -1.5e-3)):
        xc = system.forces([[y, psi, 0.0, 0.0]])[0, 0, 1, 0, O_XC]
        (p,) = rc.solve(ex["case"](y, psi)).patches
        out(f"* y {y * 1e3:.1f} mm, yaw {psi * 1e3:.3f} mrad: contact x {xc * 1e3:.4f} mm, "
            f"3-D roller search {p.geometry.position[0] * 1e3:.4f} mm "
            f"({xc / p.geometry.position[0] - 1:+.2%})")
    for name in ("roller_rig_dynamics.toml", "roller_rig_bogie.toml"):
        t0 = time.perf_counter()
        ds = run_rig_scenario(load_dynamics_scenario(HERE.parent / "examples" / name),
                              progress=False)
        out(f"* examples/{name}: {time.perf_counter() - t0:.2f} s (4 s of hunting at "
            f"200 Hz, table and both critical speeds); linear critical speed on the rig "
            f"{ds.attrs['critical_speed_m_s']:.1f} m/s, on track "
            f"{ds.attrs['track_critical_speed_m_s']:.1f} m/s")


def main():
    out(f"# railcontact benchmarks ({time.strftime('%Y-%m-%d')}, {os.cpu_count()} cores, "
        f"Python {sys.version.split()[0]})\n")
    t = bench_hertz_fastsim()
    bench_contact_sweep(t)
    bench_exact_module3()
    bench_exact_wheel_rail()
    bench_fft_unit()
    bench_exact_sweep()
    bench_force_controlled()
    bench_tangential_accuracy()
    bench_sweep_parallel()
    bench_fast_models()
    import compiled_case                # whole cases in one compiled pass
    (HERE / "compiled_case.md").write_text("\n".join(compiled_case.main()) + "\n")
    import exact_case                   # issue 30, the exact case: benchmarks/exact_case.md
    out("\n## The exact case's stages, before and after the extrapolated start "
        "(benchmarks/exact_case.md)\n")
    for s in exact_case.main([]):
        out(s)
    import exact_normal                 # issue 30, the exact normal solve: benchmarks/exact_normal.md
    exact_normal.main([])
    bench_strips_accuracy()
    bench_dynamics()
    bench_fmu()
    bench_quasi_elastic()
    bench_roller_rig()
    bench_wear_closed_loop()
    bench_wear_grid_reuse()
    bench_subsurface()
    bench_rcf_cost()
    (HERE / "results.md").write_text("\n".join(lines) + "\n")
    import contact_inputs          # CONTACT's input files: benchmarks/contact_inputs.md
    contact_inputs.main()
    import contact_testbank        # every testbank input: benchmarks/contact_testbank.md
    contact_testbank.main([])
    import contact_variants        # variants run by CONTACT: benchmarks/contact_variants.md
    contact_variants.main([])
    import frictional_power        # issue 35: benchmarks/frictional_power.md
    frictional_power.main()
    import seed001_tables          # seed 001's Tables 1-2: benchmarks/seed001_tables.md
    seed001_tables.main()
    import dynamics_online         # issue 30, contact online: benchmarks/dynamics_online.md
    dynamics_online.main([])
    import exact_online            # issue 30, exact + exact online (appended to the same)
    exact_online.main(["--out", str(HERE / "dynamics_online.md")])
    import gauge_corner_sampling   # issue 34: CONTACT's wheel sampling (prints)
    gauge_corner_sampling.main()
    import t3_t2_conformal_balance  # issue 34: case 3's vertical balance (prints)
    t3_t2_conformal_balance.main()
    import seed003_plastic         # issue 31: benchmarks/seed003_plastic.md
    seed003_plastic.main()


if __name__ == "__main__":
    main()
