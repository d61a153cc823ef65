"""Frictional power per patch (issue 35): the exact model against CONTACT's
``FRIC.POWER``, and every other model against the exact one on the same patches.

1. CONTACT: every steady case of the inputs below that railcontact maps, solved
   with the models CONTACT used (``railcontact solve``), and the ``fric_power_W``
   column against the ``FRIC.POWER`` of the ``.ref_out`` (same sign convention,
   W).  The Manchester A-2.2 inputs (left, right: exact; kpec: KPEC and ANALYN
   with FASTSIM, then exact) and the steady inputs of the testbank.
2. Models against exact: the Manchester 10 kN sweep's geometry (S1002 on
   UIC60, right wheel) on the tread (y_ws = 0 and 3 mm) and on the flange
   (8 mm), at a small (0.1 %) and a large (0.6 %) longitudinal creepage with the
   geometric spin; each normal model with FASTSIM (and the strip models also with
   ``fastsim-strips``, FaStrip), the linear and Polach laws on Hertz, and the
   macroscopic power V (xi F_x + eta F_y + phi M_z) beside the local one.

Run alone (``python benchmarks/frictional_power.py``, writes
``benchmarks/frictional_power.md``) or from ``benchmarks/run_all.py``.
"""

from __future__ import annotations

import math
import os
import re
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SHARED = HERE.parent.parent / "shared"
REF = Path(os.environ.get("RAILCONTACT_REFERENCE", SHARED / "reference"))
BANK = Path(os.environ.get("RAILCONTACT_TESTBANK", SHARED / "contact_testbank"))

#: (folder, input, cases or None for all): the inputs compared with CONTACT
INPUTS = [("examples_basic", "mbench_a22_right", None),
          ("examples_basic", "mbench_a22_left", None),
          ("examples_basic", "mbench_a22_kpec", None),
          ("examples_trans", "force_site_b", None),
          ("examples_trans", "iestim_site_b", None),
          ("examples_trans", "t3_t1_force", [1]),
          ("examples_basic", "tractcurv", None),
          ("examples_basic", "fastsim", None),
          ("examples_basic", "carter2d", None),
          ("examples_basic", "spence35", None),
          ("examples_basic", "bentall", None),
          ("examples_basic", "mbench_a22_varfric", None),
          ("examples_basic", "veldep_fric", None),
          ("examples_trans", "m1_steady_roll", None),
          ("examples_trans", "m1_totforce", None),
          ("examples_trans", "t1_force_cp", None),
          ("examples_trans", "t1_merge_cp", None),
          ("examples_trans", "t1_split_cp", None),
          ("examples_trans", "t1_zws", None),
          ("examples_trans", "t1_npotmax", None)]

lines: list = []


def out(s=""):
    print(s, flush=True)
    lines.append(s)


def fric_power_ref(path) -> dict:
    """{case: [(YCP(TR) [mm] or None, FRIC.POWER [W]) of each patch]} from a CONTACT
    ``.ref_out`` (module 3 cases have no YCP(TR))."""
    text = Path(path).read_text()
    parts = re.split(r"\n Case +(\d+)\n", text)
    out_ = {}
    for num, body in zip(parts[1::2], parts[2::2]):
        pats = re.split(r"----- DATA FOR CONTACT PATCH", body)
        pats = pats[1:] if len(pats) > 1 else pats
        got = []
        for pb in pats:
            m = re.search(r"FRIC\.POWER\n(.*)\n", pb)
            if not m:
                continue
            y = re.search(r"XCP\(TR\).*\n\s*\S+\s+(\S+)", pb)
            got.append((float(y.group(1)) if y else None, float(m.group(1).split()[5])))
        out_[int(num)] = got
    return out_


def match_patches(mine, theirs):
    """Pairs (row, CONTACT's FRIC.POWER) by the nearest reference point (YCP(TR));
    rows without a CONTACT patch within 2 mm are left out (returned apart)."""
    pairs, left = [], []
    for r in mine:
        if theirs and theirs[0][0] is None:
            pairs.append((r, theirs[0][1]))
            continue
        best = min(theirs, key=lambda t: abs(t[0] - r["ycp_tr_mm"]), default=None)
        if best is not None and abs(best[0] - r["ycp_tr_mm"]) < 2.0:
            pairs.append((r, best[1]))
        else:
            left.append(r)
    return pairs, left


def bench_contact():
    from railcontact.contact_inp import InpError, load_inp, read_inp, solve_inp
    out("## 1. The exact model's frictional power against CONTACT's FRIC.POWER\n")
    out("Per patch: railcontact's `fric_power_W` against CONTACT's `FRIC.POWER` (W, both "
        "negative: the tractions on the rail against the rail's slip).  Deviation "
        "relative to CONTACT's value; patches below 0.05 W (near pure rolling) and "
        "below a tenth of the case's largest normal force are listed apart.\n")
    out("| input | models | cases | patches | max abs dev. | mean abs dev. | worst case |")
    out("|---|---|---|---|---|---|---|")
    detail = []
    for folder, name, cases in INPUTS:
        path = BANK / folder / f"{name}.inp"
        if not path.is_file():
            continue
        if cases is None:
            cases = []
            try:
                read = read_inp(path)
            except InpError as exc:
                out(f"| {name} | not read: {str(exc).split(': ', 1)[-1][:70]} | | | | | |")
                continue
            for c in read:
                try:
                    load_inp(path, cases=[c.number], profile_dirs=[REF / "profiles"])
                    cases.append(c.number)
                except InpError:
                    pass
        if not cases:
            out(f"| {name} | no steady case that railcontact maps | | | | | |")
            continue
        models = {}
        for m in load_inp(path, cases=cases, profile_dirs=[REF / "profiles"]):
            sol = (m.raw or {}).get("solver", {})
            models[m.number] = ("{} + {}".format(sol.get("normal", "hertz"),
                                                 sol.get("tangential", "fastsim"))
                                if m.raw else f"module {m.module} (2-D)")
        t = time.perf_counter()
        try:
            rows = solve_inp(path, cases=cases, profile_dirs=[REF / "profiles"])
        except Exception as exc:                  # noqa: BLE001 - reported
            out(f"| {name} | failed: {str(exc)[:80]} | | | | | |")
            continue
        t = time.perf_counter() - t
        ref = fric_power_ref(path.with_suffix(".ref_out"))
        groups: dict = {}
        for case in cases:
            mine = [r for r in rows if r["case"] == case and r.get("npatch")
                    and r.get("fric_power_W") is not None]
            theirs = ref.get(case, [])
            pairs, left = match_patches(mine, theirs)
            for r in left:
                detail.append(f"* {name} {case}.{r['patch']}: {r['fric_power_W']:.3g} W, "
                              f"F_n {float(r['fn_N']):.0f} N, no CONTACT patch there")
            if not pairs:
                continue
            fn_max = max(float(r["fn_N"]) for r, _ in pairs)
            for r, c in pairs:
                key = models[case]
                dev = r["fric_power_W"] / c - 1.0 if c else math.nan
                small = abs(c) < 0.05 or float(r["fn_N"]) < 0.1 * fn_max
                label = f"{name} {case}.{r['patch']}"
                detail.append(f"* {label}: {r['fric_power_W']:.4g} W (CONTACT {c:.4g} W), "
                              f"{100 * dev:+.2f} %" + (" (small patch)" if small else ""))
                if not small:
                    groups.setdefault(key, []).append((abs(dev), label))
        for key, devs in groups.items():
            worst = max(devs)
            out(f"| {name} | {key} | {len(cases)} ({t:.0f} s) | {len(devs)} | "
                f"{100 * worst[0]:.2f} % | {100 * sum(d for d, _ in devs) / len(devs):.2f} % "
                f"| {worst[1]} |")
    out("\nPer patch:\n")
    for d in detail:
        out(d)


def _sweep_row(y_mm):
    import csv
    rows = list(csv.DictReader(open(REF / "mbench_sweep_10kN.csv")))
    return min(rows, key=lambda r: abs(float(r["y_ws_mm"]) - y_mm))


def _patch(y_mm, normal, tangential, cksi):
    """One Manchester sweep case (right wheel, CONTACT's roll 0) solved with
    (normal, tangential) at the longitudinal creepage cksi (VPITCH scaled from the
    sweep's -0.1 %)."""
    import railcontact as rc
    r = _sweep_row(y_mm)
    prof = REF / "profiles"
    # VPITCH of the sweep (CKSI = -0.1 %) scaled to the creepage cksi
    vpitch = float(r["vpitch_rad_s"]) * (1.0 + cksi) / (1.0 + float(r["cksi"]))
    raw = {"material": {"young_modulus": 2 * 82e9 * 1.28, "poisson_ratio": 0.28},
           "friction": {"coefficient": 0.3},
           "wheel": {"profile": str(prof / "MBench_S1002_v3.prw")},
           "rail": {"profile": str(prof / "MBench_UIC60_v3.prr"), "inclination": 0.0},
           "wheelset": {"lateral_shift": y_mm * 1e-3, "vertical_force": 1e4, "velocity": 2.0,
                        "pitch_velocity": vpitch, "side": "right", "roll": 0.0},
           "solver": {"element_size": [0.25e-3, 0.25e-3]}}
    return rc.solve(rc.case_from_dict(raw), normal, tangential)


def bench_models():
    out("\n## 2. Every model's frictional power against the exact model's\n")
    t0 = time.perf_counter()
    out("Manchester 10 kN sweep geometry (S1002/UIC60, right wheel, F_z = 10 kN, mu = 0.3, "
        "V = 2 m/s, 0.25 mm elements), one patch per case.  `P` is the model's frictional "
        "power (its local slip field: `TangentialSolution.frictional_power`), `P_macro` "
        "= V (xi F_x + eta F_y + phi M_z); both against the exact model's `P` on the same "
        "case.\n")
    pairs = [("hertz", "fastsim"), ("kik-piotrowski", "fastsim"), ("kpec", "fastsim"),
             ("stripes", "fastsim"), ("stripes", "fastsim-strips"), ("stripes", "fastrip"),
             ("analyn", "fastsim"), ("analyn", "fastsim-strips"), ("hertz", "linear"),
             ("hertz", "polach")]
    cases = [("tread", 0.0), ("tread", 3.0), ("flange", 8.0)]
    for label, y in cases:
        for cksi in (-0.001, -0.006):
            try:
                ex = _patch(y, "exact", "exact", cksi)
            except Exception as exc:              # noqa: BLE001 - reported
                out(f"* {label} y_ws = {y} mm, cksi {cksi}: exact failed ({exc})")
                continue
            pe = sum(p.tangential.frictional_power for p in ex.patches)
            p0 = max(ex.patches, key=lambda p: p.normal.normal_force)
            xi, eta, phi = p0.creepage
            out(f"\n### {label}, y_ws = {y:g} mm, creepage ({xi:.2e}, {eta:.1e}, "
                f"{phi:.3g} 1/m); exact: P = {pe:.3f} W, "
                f"stick {100 * p0.tangential.stick_fraction:.0f} %, {len(ex.patches)} patch(es), "
                f"delta = {p0.geometry.contact_angle:.3f} rad\n")
            out("| normal + tangential | P [W] | P / P_exact | P_macro / P_exact | "
                "F_x / F_x,exact |")
            out("|---|---|---|---|---|")
            fxe = sum(p.tangential.fx for p in ex.patches)
            for nm, tg in pairs:
                try:
                    res = _patch(y, nm, tg, cksi)
                except Exception as exc:          # noqa: BLE001 - reported
                    out(f"| {nm} + {tg} | failed: {str(exc)[:60]} | | | |")
                    continue
                ts = [p.tangential for p in res.patches]
                pw = sum(t.frictional_power for t in ts)
                pm = sum(abs(t.velocity * (t.creepage[0] * t.fx + t.creepage[1] * t.fy
                                           + t.creepage[2] * t.mz)) for t in ts)
                fx = sum(t.fx for t in ts)
                out(f"| {nm} + {tg} | {pw:.3f} | {pw / pe:.3f} | {pm / pe:.3f} | "
                    f"{fx / fxe:.3f} |")
    out(f"\n({time.perf_counter() - t0:.0f} s)")


def main():
    out(f"# Frictional power per patch ({time.strftime('%Y-%m-%d')}, {os.cpu_count()} cores, "
        f"Python {sys.version.split()[0]})\n")
    bench_contact()
    bench_models()
    (HERE / "frictional_power.md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
