"""CONTACT's own input files run through ``railcontact solve``: every ``.inp`` of
``../shared/reference`` against its CSV, and the steady wheel-rail inputs of
``../shared/contact_testbank/examples_trans`` against their ``.ref_out``.

Run alone (``python benchmarks/contact_inputs.py``, writes
``benchmarks/contact_inputs.md``) or from ``benchmarks/run_all.py``.
"""

from __future__ import annotations

import csv
import math
import os
import re
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SHARED = HERE.parent.parent / "shared"
REF = Path(os.environ.get("RAILCONTACT_REFERENCE", SHARED / "reference"))
BANK = SHARED / "contact_testbank"

#: the tolerances of the hand-mapped tests (tests/test_exact_wheel_rail.py,
#: tests/normal/test_semi_hertzian.py): relative, per quantity
TOL_EXACT = {"fn_N": 0.01, "fx_N": 0.01, "fs_N": 0.01, "pmax_MPa": 0.03, "area_mm2": 0.02}
TOL_STRIP = {"fn_N": 0.01, "area_mm2": 0.03, "pmax_MPa": 0.03, "approach_mm": 0.03}

lines: list = []


def out(s=""):
    print(s, flush=True)
    lines.append(s)


def _rel(a, b):
    return a / b - 1.0 if b else math.nan


def _solve(path, **kw):
    from railcontact.contact_inp import solve_inp
    t = time.perf_counter()
    rows = solve_inp(path, profile_dirs=[REF / "profiles"], **kw)
    return rows, time.perf_counter() - t


def _report(name, pairs, tol, keys_abs=("ycp_r_mm", "delta_tr_rad")):
    """Deviation statistics of (ours, CONTACT's) row pairs."""
    worst = {}
    fails = []
    for ours, ref, label in pairs:
        bad = []
        # forces near zero (the centred case's F_x of 0.3 N) against a tenth
        # of the friction bound
        floor = 0.1 * float(ours.get("mu") or 0.3) * float(ref.get("fn_N") or 0.0)
        for k, t in tol.items():
            r = float(ref[k])
            scale = max(abs(r), floor) if k in ("fx_N", "fs_N") else abs(r)
            d = (float(ours[k]) - r) / scale if scale else math.nan
            if abs(d) > abs(worst.get(k, (0.0, ""))[0]):
                worst[k] = (d, label)
            if abs(d) > t:
                bad.append(f"{k} {100 * d:+.2f} %")
        for k in keys_abs:
            if k in ref and ref[k] not in ("", None):
                d = float(ours[k]) - float(ref[k])
                if abs(d) > abs(worst.get(k, (0.0, ""))[0]):
                    worst[k] = (d, label)
        if bad:
            fails.append(f"{label}: " + ", ".join(bad))
    out(f"* {name}: {len(pairs) - len(fails)} of {len(pairs)} rows within the hand-mapped "
        f"tests' tolerances ({', '.join(f'{k} {100 * t:g} %' for k, t in tol.items())}; "
        "F_x and F_s of at least a tenth of mu F_n)")
    for k, (d, label) in worst.items():
        unit = "" if k in tol else (" rad" if k.endswith("rad") else " mm")
        val = f"{100 * d:+.2f} %" if k in tol else f"{d:+.4f}{unit}"
        out(f"  * largest {k}: {val} ({label})")
    for f in fails:
        out(f"  * outside: {f}")
    return len(fails)


def bench_reference_inputs():
    out("## CONTACT's inputs of ../shared/reference through `railcontact solve`")
    out("Profiles from `--profiles ../shared/reference/profiles` (the A-2.2 inputs name them "
        "without a folder).\n")
    # both sides
    a22 = {(r["side"], int(r["case"])): r
           for r in csv.DictReader(open(REF / "mbench_a22" / "a22_patches.csv"))}
    for side in ("left", "right"):
        rows, t = _solve(REF / "mbench_a22" / f"mbench_a22_{side}.inp")
        pairs = [(r, a22[(side, r["case"])], f"{side} {a22[(side, r['case'])]['y_ws_mm']} mm")
                 for r in rows if r["npatch"]]
        _report(f"mbench_a22_{side}.inp ({len(rows)} rows, {t:.1f} s)", pairs, TOL_EXACT)
    for name in ("mbench_sweep_10kN", "mbench_sweep_10kN_dx0125"):
        ref = {int(i): r for i, r in enumerate(csv.DictReader(open(REF / f"{name}.csv")), 1)}
        rows, t = _solve(REF / f"{name}.inp")
        pairs = []
        for r in rows:
            x = dict(ref[r["case"]])
            x["fn_N"], x["pmax_MPa"] = x["fn_mat_N"], x["pmax_mat_MPa"]
            pairs.append((r, x, f"{x['y_ws_mm']} mm"))
        _report(f"{name}.inp ({len(rows)} rows, {t:.1f} s)", pairs, TOL_EXACT)
    kpec = {i: r for i, r in enumerate(csv.DictReader(open(REF / "mbench_a22" / "a22_kpec.csv")),
                                       1)}
    rows, t = _solve(REF / "mbench_a22" / "mbench_a22_kpec.inp")
    strip = [(r, kpec[r["case"]], f"{kpec[r['case']]['method']} {kpec[r['case']]['y_ws_mm']} mm")
             for r in rows if kpec[r["case"]]["method"] != "contact"]
    full = [(r, kpec[r["case"]], f"contact {kpec[r['case']]['y_ws_mm']} mm")
            for r in rows if kpec[r["case"]]["method"] == "contact"]
    _report(f"mbench_a22_kpec.inp, KPEC and ANALYN + FASTSIM ({t:.1f} s for all 9)", strip,
            TOL_STRIP)
    _report("mbench_a22_kpec.inp, exact", full, TOL_EXACT)
    # module 3
    kal = [r for r in csv.DictReader(open(REF / "kalker_coefficients_contact.csv"))
           if r["nu"] == "0.28" and r["a_over_b"] == "1.0" and r["mx"] == "80"
           and r["creepage"] == "1e-05" and r["mu"] == "0.3"]
    rows, t = _solve(REF / "kalker_example.inp")
    (r,) = rows
    out(f"* kalker_example.inp ({t:.2f} s): F_x {r['fx_N']:.2f} N against CONTACT's "
        f"{float(kal[0]['fx_xi_N']):.2f} N ({100 * _rel(r['fx_N'], float(kal[0]['fx_xi_N'])):+.2f}"
        f" %), contact elements {r['ncon']} ({kal[0]['ncon']}), slipping {r['nslip']} "
        f"({kal[0]['nslip_xi']})")
    tim = [x for x in csv.DictReader(open(REF / "contact_timing.csv"))
           if x["case"] == "circ_partial_slip" and x["eps"] == "1e-06"][0]
    rows, t = _solve(REF / "timing_m3_40x40_example.inp")
    (r,) = rows
    out(f"* timing_m3_40x40_example.inp ({t:.2f} s): contact elements {r['ncon']} "
        f"({tim['ncon']}), slipping {r['nslip']} ({tim['nslip']})")


# ------------------------------------------------------------------ testbank
_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


def parse_ref_out(path) -> dict:
    """CONTACT's per-case totals and per-patch values from a ``.ref_out`` file:
    {case: {"totals": {...}, "z_ws": ..., "patches": [{...}]}}."""
    text = Path(path).read_text()
    cases = {}
    parts = re.split(r"\n Case +(\d+)\n", text)
    for num, body in zip(parts[1::2], parts[2::2]):
        c = {"patches": []}
        m = re.search(r"TOTAL FORCES ON RAIL\n.*\n\s*(" + _NUM + r")\s+(" + _NUM + r")\s+(" + _NUM
                      + r")", body)
        if m:
            c["totals"] = {"fx_tr_N": float(m.group(1)), "fy_tr_N": float(m.group(2)),
                           "fz_tr_N": float(m.group(3))}
        m = re.search(r"S_WS\s+Y_WS\s+Z_WS.*\n\s*(" + _NUM + r")\s+(" + _NUM + r")\s+(" + _NUM
                      + ")", body)
        if m:
            c["z_ws_mm"] = float(m.group(3))
        for pb in re.split(r"----- DATA FOR CONTACT PATCH", body)[1:]:
            p = {}
            m = re.search(r"XCP\(TR\).*\n\s*" + r"\s+".join([f"({_NUM})"] * 6), pb)
            if m:
                for k, g in zip(("xcp_tr_mm", "ycp_tr_mm", "zcp_tr_mm", "delta_tr_rad",
                                 "ycp_r_mm", "zcp_r_mm"), m.groups()):
                    p[k] = float(g)
            # (friction varying across a conformal patch: a table "IY FSTAT FKIN" whose
            # first column is the row number; mu is then the largest printed FSTAT)
            m = re.search(r"IY\s+FSTAT\s+FKIN\s*\n((?:.*\S.*\n)+)", pb)
            if m:
                rows = [ln.split() for ln in m.group(1).splitlines()]
                p["mu"] = max(float(r[1]) for r in rows if len(r) >= 3 and r[0].isdigit())
            else:
                m = re.search(r"FSTAT\s+FKIN\s*\n\s*(" + _NUM + ")", pb)
                if m:
                    p["mu"] = float(m.group(1))
            m = re.search(r"CKSI\s+CETA\s+CPHI\s*\n\s*" + r"\s+".join([f"({_NUM})"] * 6), pb)
            if m:
                p["cksi"], p["ceta"], p["cphi_per_mm"] = (float(g) for g in m.groups()[3:])
            # (a conformal patch: CONTACT's bar forces BAR_FN, BAR_FX, BAR_FS)
            m = re.search(r"(?:BAR_)?FN\s+(?:BAR_)?FX\s+(?:BAR_)?FS\s+MN.*\n\s*"
                          + r"\s+".join([f"({_NUM})"] * 4), pb)
            if m:
                for k, g in zip(("fn_N", "fx_N", "fs_N", "mn_Nmm"), m.groups()):
                    p[k] = float(g)
            m = re.search(r"APPROACH\s+PMAX\s*\n\s*" + r"\s+".join([f"({_NUM})"] * 5), pb)
            if m:
                p["approach_mm"], p["pmax_MPa"] = float(m.group(4)), float(m.group(5))
            m = re.search(r"NPOT\s+NCON\s+NADH\s+NSLIP.*\n\s*(\d+)\s+(\d+)\s+(\d+)\s+(\d+)", pb)
            if m:
                p["ncon"], p["nadh"], p["nslip"] = (int(m.group(i)) for i in (2, 3, 4))
            c["patches"].append(p)
        cases[int(num)] = c
    return cases


def bench_testbank():
    from railcontact.contact_inp import InpError, load_inp
    out("\n## Steady wheel-rail inputs of ../shared/contact_testbank/examples_trans")
    out("Measured profiles `site_b_hr.prr` / `worn_high_mileage.prw`, friction varying with the "
        "rail inclination (V = 1), patches combined within D_SEP = 6 mm and turned up to 9 mm.\n")
    folder = BANK / "examples_trans"
    for name in sorted(p.stem for p in folder.glob("*.inp")):
        path = folder / f"{name}.inp"
        try:
            load_inp(path)
            steady = None
        except InpError as exc:
            steady = str(exc)
        if steady is not None:
            # the steady cases before the first unsupported one
            try:
                from railcontact.contact_inp import read_inp
                ok = []
                for c in read_inp(path):
                    try:
                        load_inp(path, cases=[c.number])
                        ok.append(c.number)
                    except InpError:
                        break
            except InpError:
                ok = []
            out(f"* {name}.inp: rejected with `{steady.split(': ', 1)[1]}`"
                + (f"; its steady cases {ok} run" if ok else ""))
            if not ok:
                continue
        else:
            ok = None
        rows, t = _solve(path, cases=ok)
        ref = parse_ref_out(folder / f"{name}.ref_out")
        dev = {k: [] for k in ("fz_tr_N", "fy_tr_N", "fx_tr_N")}
        case_lines = []
        for case in sorted({r["case"] for r in rows}):
            mine = [r for r in rows if r["case"] == case]
            theirs = ref.get(case, {})
            tot = theirs.get("totals")
            if not tot:
                continue
            r0 = mine[0]
            np_ours, np_ref = r0["npatch"], len(theirs["patches"])
            fz = r0.get("fz_tr_N", 0.0)
            msg = (f"  * case {case}: patches {np_ours} ({np_ref}); F_tr on rail x/y/z "
                   f"{r0.get('fx_tr_N', 0.0):.0f} / {r0.get('fy_tr_N', 0.0):.0f} / {fz:.0f} N "
                   f"({tot['fx_tr_N']:.0f} / {tot['fy_tr_N']:.0f} / {tot['fz_tr_N']:.0f})")
            if "z_ws_mm" in theirs and r0.get("z_ws_mm") is not None:
                msg += f"; z_ws {r0['z_ws_mm']:.4f} mm ({theirs['z_ws_mm']:.4f})"
            case_lines.append(msg)
            for k in dev:
                dev[k].append((r0.get(k, 0.0) - tot[k]) / max(abs(tot["fz_tr_N"]), 1.0))
        if any(dev.values()):
            out(f"* {name}.inp ({len({r['case'] for r in rows})} cases, {t:.1f} s): track "
                "forces against CONTACT's, relative to its vertical force: "
                + ", ".join(f"{k[:2]} max {100 * max(abs(v) for v in d):.2f} %"
                            for k, d in dev.items() if d) + " (CONTACT's in brackets):")
        for msg in case_lines:
            out(msg)


def main():
    out(f"# CONTACT input files through railcontact ({time.strftime('%Y-%m-%d')}, "
        f"{os.cpu_count()} cores, Python {sys.version.split()[0]})\n")
    bench_reference_inputs()
    bench_testbank()
    (HERE / "contact_inputs.md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
