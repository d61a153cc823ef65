"""Whole wheel-rail cases in the compiled pass (``railcontact.cases.compiled_case``)
against the per-patch path, on the 1000-case sweep, the Manchester 10 kN sweep and
through the command line, with the strip models in the pass (``make bench`` runs
it from ``run_all.py``; alone: ``python benchmarks/compiled_case.py [shifts]
[--strips]``, ``--strips``: the strip models' table alone, printed).

Every figure is measured in this run, as the CPU time of the process (user + system:
the shared machine's scheduling pauses out); the timings of the paths compared are
interleaved in blocks of 50 cases, so that a slower phase of the (shared) machine
falls on all of them alike, and each is also given in units of one real FFT
convolution of the exact solvers' padded 80 x 80 grid measured between the blocks.

The code before a change is timed from its commit, each tree in a process of its
own, alternating (no switch in the package keeps an old path alive for it):
``python benchmarks/before_after.py REF 2 compiled_sweep`` runs
:func:`bench_compiled_sweep` at ``REF`` and on this checkout (``compiled_strips``:
:func:`bench_strip_sweep`).
"""

from __future__ import annotations

import csv
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import railcontact as rc
from railcontact.cases.balance import BalanceOptions
from railcontact.cases.case import case_from_dict
from railcontact.cases.compiled_case import solve_case_forces
from run_all import sweep_raws

HERE = Path(__file__).resolve().parent
REF = Path(os.environ.get("RAILCONTACT_REFERENCE", HERE.parent.parent / "shared" / "reference"))


def _stats(t, ok):
    t = np.asarray(t)
    med = float(np.median(t))
    met = t[np.asarray(ok, bool)]
    tail_met = float(met.max() / np.median(met)) if met.size else math.nan
    return med, float(t.max() / med), int(np.count_nonzero(ok)), float(t.mean()), tail_met


def _warm_up(cases, rows, every=25):
    """Compile / load every kernel path the timed rows reach before timing them, as
    ``exact_case.py``'s workers do: each of ``rows`` (callables ``row(case, start)``
    returning its result, ``start`` a neighbour's result or None) on every
    ``every``-th case, cold and its next neighbour warm from it.  With an empty
    Numba cache (``make bench`` keys the cache by the sources' hash, so it is empty
    after every change) a path met first inside a timed row is compiled there: the
    geometry layer's start (``BalanceOptions(compiled_start=False)``) calls
    ``patch_curvature.force_curvature`` from Python with other argument types than
    the compiled pass, and its first case took 0.86 s of CPU, 213x that row's median
    (138x in the 0fa3ddc record)."""
    for i in range(0, len(cases) - 1, every):
        for row in rows:
            row(cases[i + 1], row(cases[i], None))


def _compiled_row(*models):
    """A :func:`_warm_up` row: the compiled pass (``solve_case_forces``) of
    ``models``, warm from a converged start."""
    def row(case, start):
        return solve_case_forces(case, *models,
                                 start=start if start is not None and start.converged else None)
    return row


def _solve_row(compiled_start):
    """A :func:`_warm_up` row: ``rc.solve`` Hertz + FASTSIM with or without the
    compiled start (it takes no warm start: the neighbour is solved cold)."""
    opts = BalanceOptions(compiled_start=compiled_start)
    return lambda case, start: rc.solve(case, "hertz", "fastsim", options=opts)


def bench_compiled_sweep(out, conv_time, n_shift=250):
    """The 1000-case sweep: compiled pass cold and warm (each case from its
    neighbour) per online law, and the per-patch path with and without the compiled
    start."""
    raws = sweep_raws(n_shift)
    n = len(raws)
    out(f"\n## Whole wheel-rail cases in one compiled pass: {n}-case sweep (S1002 on 60E1 "
        "1:40, 70 kN per wheel, shift -4..9 mm, yaw 0..6 mrad, creepages varying, 40x40 "
        "FASTSIM grid; CPU time per case)")
    cases = [case_from_dict(r) for r in raws]
    laws = ("fastsim", "polach", "linear")
    _warm_up(cases, [_compiled_row("hertz", law) for law in laws]
             + [_solve_row(True), _solve_row(False)])
    keys = [f"cold_{law}" for law in laws] + ["best3_fastsim", "warm_fastsim", "solve_after",
                                              "solve_before"]
    t = {k: np.zeros(n) for k in keys}
    ok = {k: np.zeros(n, bool) for k in keys}
    passes = {k: np.zeros(n) for k in keys}
    # the compiled pass's pose steps and roll-search evaluations (both sides' minimum gaps)
    pose = {k: np.zeros(n) for k in keys}
    gaps = {k: np.zeros(n) for k in keys}
    dev_fn, dev_fy = [], []
    conv = []
    prev = None
    for b0 in range(0, n, 50):
        block = range(b0, min(b0 + 50, n))
        conv.append(conv_time(repeat=3, number=100)[0])
        cold = {}
        for law in laws:
            for i in block:
                t0 = time.process_time()
                r = solve_case_forces(cases[i], "hertz", law)
                t[f"cold_{law}"][i] = time.process_time() - t0
                ok[f"cold_{law}"][i], passes[f"cold_{law}"][i] = r.converged, r.passes
                pose[f"cold_{law}"][i], gaps[f"cold_{law}"][i] = r.pose_passes, r.gap_evaluations
                if law == "fastsim":
                    cold[i] = r
        for i in block:                 # the same, best of 3: the machine's hiccups out
            best = math.inf
            for _ in range(3):
                t0 = time.process_time()
                r = solve_case_forces(cases[i])
                best = min(best, time.process_time() - t0)
            t["best3_fastsim"][i], ok["best3_fastsim"][i] = best, r.converged
            passes["best3_fastsim"][i] = r.passes
        for i in block:
            t0 = time.process_time()
            r = solve_case_forces(cases[i], start=prev)
            t["warm_fastsim"][i] = time.process_time() - t0
            ok["warm_fastsim"][i], passes["warm_fastsim"][i] = r.converged, r.passes
            pose["warm_fastsim"][i], gaps["warm_fastsim"][i] = r.pose_passes, r.gap_evaluations
            prev = r if r.converged else None
        for key, flag in (("solve_after", True), ("solve_before", False)):
            opts = BalanceOptions(compiled_start=flag)
            for i in block:
                t0 = time.process_time()
                res = rc.solve(cases[i], "hertz", "fastsim", options=opts)
                t[key][i] = time.process_time() - t0
                ok[key][i] = res.converged
                passes[key][i] = res.balance.passes if res.balance else 0
                if flag and res.converged and cold[i].converged:
                    for s in ("left", "right"):
                        fa = sum(p.normal.normal_force for p in res.patches
                                 if p.geometry.side == s)
                        fb = sum(f for sd, f in zip(cold[i].side,
                                                    cold[i].patches["normal_force"])
                                 if sd == s)
                        ya = sum(p.tangential.fy for p in res.patches if p.geometry.side == s)
                        yb = sum(f for sd, f in zip(cold[i].side, cold[i].patches["fy"])
                                 if sd == s)
                        dev_fn.append(abs(fa - fb) / 7e4)
                        dev_fy.append(abs(ya - yb) / (0.3 * 7e4))
    unit = float(np.median(conv))
    out(f"* the unit: one real FFT convolution of the padded 80 x 80 grid took "
        f"{unit * 1e6:.1f} µs in this run (median of {len(conv)} measurements between the "
        "blocks)")
    out("\n| path | median per case | mean | in convolutions (median) | max / median | "
        "max / median of the cases that meet the load | load met | balance passes (mean) | "
        "pose steps (mean) | roll-search evaluations (mean / median) |")
    out("|---|---|---|---|---|---|---|---|---|---|")
    labels = {"cold_fastsim": "compiled Hertz + FASTSIM, cold (multi-Hertzian start)",
              "best3_fastsim": "the same, each case's best of 3 runs",
              "warm_fastsim": "compiled Hertz + FASTSIM, warm (from the previous case)",
              "cold_polach": "compiled Hertz + Polach, cold",
              "cold_linear": "compiled Hertz + linear, cold",
              "solve_after": "`rc.solve` Hertz + FASTSIM (full results), balance from the "
                             "compiled pass",
              "solve_before": "`rc.solve` Hertz + FASTSIM (full results), before: the "
                              "geometry layer's estimate"}
    figures = {}
    compiled = ("cold_fastsim", "best3_fastsim", "warm_fastsim", "cold_polach", "cold_linear")
    for k in compiled + ("solve_after", "solve_before"):
        med, ratio, met, mean, tail_met = _stats(t[k], ok[k])
        figures[k] = (med, ratio, met)
        counts = (f"{pose[k].mean():.2f} | {gaps[k].mean():.1f} / {np.median(gaps[k]):.0f}"
                  if k in compiled and k != "best3_fastsim" else "- | -")
        out(f"| {labels[k]} | {med * 1e3:.3f} ms | {mean * 1e3:.3f} ms | {med / unit:.1f} | "
            f"{ratio:.1f} | {tail_met:.1f} | {met} of {n} | {passes[k].mean():.2f} | {counts} |")
    for k in ("cold_fastsim", "warm_fastsim"):
        slow = np.argsort(t[k])[-5:][::-1]
        out(f"* slowest of {labels[k]} (the median case: {np.median(passes[k]):.0f} passes, "
            f"{np.median(pose[k]):.0f} pose steps, {np.median(gaps[k]):.0f} roll-search "
            "evaluations): "
            + ", ".join(f"{raws[i]['wheelset']['lateral_shift'] * 1e3:.2f} mm / "
                        f"{raws[i]['wheelset']['yaw'] * 1e3:.0f} mrad "
                        f"({t[k][i] / np.median(t[k]):.1f}x: {passes[k][i]:.0f} passes, "
                        f"{pose[k][i]:.0f} pose steps, {gaps[k][i]:.0f} evaluations)"
                        for i in slow))
    jumps = [i for i in range(n) if not ok["solve_before"][i]]
    out(f"\n* cases whose Hertzian force jumps across the load (the per-patch path before "
        f"the change reports `force_jump` there too): {len(jumps)}, at shifts "
        f"{sorted({round(raws[i]['wheelset']['lateral_shift'] * 1e3, 2) for i in jumps})} mm")
    both = ok["cold_fastsim"] == ok["solve_before"]
    out(f"* compiled and per-patch paths agree on which cases meet the load: "
        f"{int(np.count_nonzero(both))} of {n}")
    if dev_fn:
        out(f"* compiled against `rc.solve` (both balanced to 1e-4): sum F_n per wheel within "
            f"{max(dev_fn) * 100:.4f} % of Q (median {statistics.median(dev_fn) * 100:.5f} %), "
            f"sum F_y within {max(dev_fy) * 100:.4f} % of mu Q (FASTSIM on the ellipse against "
            "FASTSIM on Hertz's grid)")
    out(f"* speed-up of `rc.solve` from the compiled start: "
        f"{figures['solve_before'][0] / figures['solve_after'][0]:.1f}x (medians)")
    return figures, unit


#: the strip models' pairs of the compiled pass timed against Hertz + FASTSIM
STRIP_PAIRS = (("kik-piotrowski", "fastsim-strips"), ("analyn", "fastsim-strips"),
               ("kpec", "fastsim-strips"))


def bench_strip_sweep(out, conv_time, n_shift=250):
    """The 1000-case sweep with the strip models in the compiled pass
    (``railcontact.cases.strip_pass``): KP, ANALYN and KPEC + ``fastsim-strips``,
    cold and warm (each case from its neighbour), interleaved in blocks of 50 with
    Hertz + FASTSIM cold and warm, CPU time per case."""
    raws = sweep_raws(n_shift)
    n = len(raws)
    cases = [case_from_dict(r) for r in raws]
    pairs = (("hertz", "fastsim"),) + STRIP_PAIRS
    _warm_up(cases, [_compiled_row(*p) for p in pairs])
    keys = [(p, w) for p in pairs for w in ("cold", "warm")]
    t = {k: np.zeros(n) for k in keys}
    ok = {k: np.zeros(n, bool) for k in keys}
    passes = {k: np.zeros(n) for k in keys}
    prev = {p: None for p in pairs}
    conv = []
    for b0 in range(0, n, 50):
        block = range(b0, min(b0 + 50, n))
        conv.append(conv_time(repeat=3, number=100)[0])
        for p in pairs:
            for i in block:
                t0 = time.process_time()
                r = solve_case_forces(cases[i], *p)
                t[(p, "cold")][i] = time.process_time() - t0
                ok[(p, "cold")][i], passes[(p, "cold")][i] = r.converged, r.passes
            for i in block:
                t0 = time.process_time()
                r = solve_case_forces(cases[i], *p, start=prev[p])
                t[(p, "warm")][i] = time.process_time() - t0
                ok[(p, "warm")][i], passes[(p, "warm")][i] = r.converged, r.passes
                prev[p] = r if r.converged else None
    unit = float(np.median(conv))
    out(f"\n## Strip models in the compiled pass: {n}-case sweep (as above; strips = the "
        "grid's 40 columns, 40 elements per strip; CPU time per case, every row interleaved "
        "in blocks of 50 in one run)")
    out(f"* the unit: one real FFT convolution of the padded 80 x 80 grid took "
        f"{unit * 1e6:.1f} µs in this run (median of {len(conv)} measurements between the "
        "blocks)")
    out("\n| models | start | median per case | mean | in convolutions (median) | "
        "max / median | max / median of the cases that meet the load | load met | "
        "balance passes (mean) |")
    out("|---|---|---|---|---|---|---|---|---|")
    figures = {}
    for k in keys:
        med, ratio, met, mean, tail_met = _stats(t[k], ok[k])
        figures[k] = (med, ratio, met)
        start = "cold (multi-Hertzian)" if k[1] == "cold" else "warm (from the previous case)"
        out(f"| {k[0][0]} + {k[0][1]} | {start} | {med * 1e3:.3f} ms | {mean * 1e3:.3f} ms | "
            f"{med / unit:.1f} | {ratio:.1f} | {tail_met:.1f} | {met} of {n} | "
            f"{passes[k].mean():.2f} |")
    for k in keys:
        slow = np.argsort(t[k])[-5:][::-1]
        out(f"* slowest of {k[0][0]} + {k[0][1]}, {k[1]}: "
            + ", ".join(f"{raws[i]['wheelset']['lateral_shift'] * 1e3:.2f} mm / "
                        f"{raws[i]['wheelset']['yaw'] * 1e3:.0f} mrad "
                        f"({t[k][i] / np.median(t[k]):.1f}x, {passes[k][i]:.0f} passes)"
                        for i in slow))
    return figures, unit


def bench_manchester(out, unit):
    """The Manchester 10 kN sweep (right wheel reported, S1002/UIC60 files) against
    CONTACT's reference timing."""
    f = REF / "mbench_sweep_10kN.csv"
    if not f.is_file():
        out("\nManchester reference data not found; skipped")
        return
    rows = list(csv.DictReader(open(f)))
    prof = REF / "profiles"
    cases = []
    for r in rows:
        raw = {"material": {"young_modulus": 2 * 82e9 * 1.28, "poisson_ratio": 0.28},
               "friction": {"coefficient": 0.3},
               "wheel": {"profile": str(prof / "MBench_S1002_v3.prw")},
               "rail": {"profile": str(prof / "MBench_UIC60_v3.prr"), "inclination": 0.0},
               "wheelset": {"lateral_shift": float(r["y_ws_mm"]) * 1e-3, "vertical_force": 1e4,
                            "velocity": 2.0, "pitch_velocity": float(r["vpitch_rad_s"]),
                            "side": "right"}}
        cases.append(rc.case_from_dict(raw))
    theirs = [float(r["time_ms_mkl_1thread"]) * 1e-3 for r in rows]
    t = {"compiled": [], "after": [], "before": []}
    _warm_up(cases, [_compiled_row(), _solve_row(True), _solve_row(False)], every=5)
    for c in cases:
        for _ in range(1):
            best = {k: math.inf for k in t}
            for _rep in range(3):                       # interleaved, best of 3
                t0 = time.process_time()
                solve_case_forces(c)
                best["compiled"] = min(best["compiled"], time.process_time() - t0)
                t0 = time.process_time()
                rc.solve(c, "hertz", "fastsim")
                best["after"] = min(best["after"], time.process_time() - t0)
                t0 = time.process_time()
                rc.solve(c, "hertz", "fastsim", options=BalanceOptions(compiled_start=False))
                best["before"] = min(best["before"], time.process_time() - t0)
            for k in t:
                t[k].append(best[k])
    out(f"\n## Manchester 10 kN sweep ({len(cases)} cases, right wheel; CONTACT's reference "
        "timing: exact, one wheel, MKL, 1 thread, another machine)")
    out("\n| path | median per case | in convolutions | median ratio to CONTACT (target 0.1) "
        "| max ratio |")
    out("|---|---|---|---|---|")
    names = {"compiled": "compiled Hertz + FASTSIM (both wheels balanced)",
             "after": "`rc.solve` Hertz + FASTSIM, balance from the compiled pass",
             "before": "`rc.solve` Hertz + FASTSIM, before"}
    for k, v in t.items():
        ratio = [a / b for a, b in zip(v, theirs)]
        out(f"| {names[k]} | {statistics.median(v) * 1e3:.3f} ms | "
            f"{statistics.median(v) / unit:.1f} | {statistics.median(ratio):.3f} | "
            f"{max(ratio):.3f} |")
    out("* the exact solvers' case (the target's subject in issue 30) is unchanged by this "
        "pass: see the exact-solver sections")


def _child_cpu() -> float:
    """CPU time [s] (user + system) of the finished child processes so far."""
    import resource
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def bench_cli_overhead(out, n=1000, small=3, repeat=3):
    """``railcontact sweep case --vary ... --json`` against the library's sweep
    (``railcontact.cases.sweep.sweep``, results to JSON) on the same cases, each in a
    fresh process (sync scheduler both): the time per case is the difference between
    a run of ``n`` and one of ``small`` cases (the start-up, imports and Numba's cache
    once per process, cancel); each the best of ``repeat``, the two interleaved run by
    run, after a first run.  CPU time (user + system) of the processes: the shared
    machine's scheduling pauses out.  The overhead itself: both on the same ``n``
    cases in this process (:func:`_in_process_cli`, :func:`_in_process_lib`), start-up
    apart, whose noise in the small runs (+-0.2 s) moves the slopes' ratio by +-10 %."""
    with tempfile.TemporaryDirectory() as tmp:
        case = Path(tmp) / "case.toml"
        case.write_text('[wheel]\nprofile = "S1002"\n[rail]\nprofile = "60E1"\n'
                        '[wheelset]\nvertical_force = 70000.0\nvelocity = 30.0\n'
                        '[solver]\ngrid = [40, 40]\n')

        def vary_of(m):
            step = 13e-3 / (n - 1)
            return f"wheelset.lateral_shift=-0.004:{-0.004 + (m - 1) * step:.9f}:{step:.9f}"

        def cli(m):
            # (exit status 1 where a case does not meet its load: a force that jumps)
            t0 = _child_cpu()
            proc = subprocess.run([sys.executable, "-m", "railcontact.cli", "sweep", str(case),
                                   "--vary", vary_of(m), "--json", "--scheduler", "sync"],
                                  capture_output=True, text=True)
            dt = _child_cpu() - t0
            return dt, len(json.loads(proc.stdout[proc.stdout.index("{"):])["cases"])

        def lib(m):
            code = ("import json, sys; import railcontact as rc; "
                    "from railcontact.cases.sweep import parse_vary, sweep; "
                    f"k, v = parse_vary({vary_of(m)!r}); "
                    f"r = sweep(rc.load_case({str(case)!r}), {{k: v}}, scheduler='sync', "
                    "progress=False); s = json.dumps(r); print(len(r['cases']))")
            t0 = _child_cpu()
            proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
            dt = _child_cpu() - t0
            return dt, int(proc.stdout.split()[-1])
        cli(small)                      # Numba's cache filled for the command's kernels
        runs = {name: {small: [], n: []} for name in ("cli", "lib")}
        for _ in range(repeat):         # interleaved: the machine's drift falls on both
            for m in (small, n):
                for name, f in (("cli", cli), ("lib", lib)):
                    runs[name][m].append(f(m))
        res = {name: (min(r[small]), min(r[n])) for name, r in runs.items()}
        # the CLI's own overhead per case, start-up apart: its command
        # (railcontact.cli.main, output captured) and the library's sweep + json.dumps
        # on the same n cases in this process, interleaved, best of ``repeat`` each
        t = {"cli": [], "lib": []}
        for _ in range(repeat + 1):                 # (the first round loads, not counted)
            t["cli"].append(_in_process_cli(case, vary_of(n)))
            t["lib"].append(_in_process_lib(case, vary_of(n)))
        best = {k: min(v[1:]) for k, v in t.items()}
    per = {k: (v[1][0] - v[0][0]) / (v[1][1] - v[0][1]) for k, v in res.items()}
    out(f"\n## The command-line sweep's own overhead ({res['cli'][1][1]} cases, Hertz + "
        "FASTSIM, sync, each in a fresh process, CPU time)")
    for k, label in (("cli", "`railcontact sweep ... --json`"),
                     ("lib", "`railcontact.cases.sweep.sweep` and `json.dumps`")):
        (ts, ms), (tf, mf) = res[k]
        out(f"* {label}: {tf:.2f} s for {mf} cases, {ts:.2f} s for {ms}: "
            f"{per[k] * 1e3:.2f} ms per further case")
    out(f"* the slopes' ratio (fresh processes; the {small}-case runs' start-up noise, "
        f"+-0.2 s of 1.4-1.6 s, is +-10 % of a slope): "
        f"{100 * (per['cli'] / per['lib'] - 1):+.1f} %")
    out(f"* in one process ({n} cases, best of {repeat}, interleaved): the command "
        f"{best['cli']:.2f} s, the library {best['lib']:.2f} s")
    out(f"* the CLI's own overhead per case: {100 * (best['cli'] / best['lib'] - 1):+.1f} % "
        "(target < 10 %)")


def _in_process_cli(case, vary) -> float:
    """CPU time [s] of ``railcontact sweep CASE --vary VARY --json --scheduler sync``
    run as :func:`railcontact.cli.main` in this process (its output captured)."""
    import contextlib
    import io
    from railcontact import cli
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        t0 = time.process_time()
        try:
            cli.main(["sweep", str(case), "--vary", vary, "--json", "--scheduler", "sync"])
        except SystemExit:              # (status 1 where a case misses its load)
            pass
        return time.process_time() - t0


def _in_process_lib(case, vary) -> float:
    """CPU time [s] of the library's sweep of the same cases and ``json.dumps``."""
    from railcontact.cases.sweep import parse_vary, sweep
    t0 = time.process_time()
    k, v = parse_vary(vary)
    json.dumps(sweep(rc.load_case(case), {k: v}, scheduler="sync", progress=False))
    return time.process_time() - t0


def main(n_shift=250, strips_only=False):
    sys.path.insert(0, str(HERE))
    from run_all import conv_time
    lines = []

    def out(s=""):
        print(s, flush=True)
        lines.append(s)
    if strips_only:
        bench_strip_sweep(out, conv_time, n_shift)
        return lines
    figures, unit = bench_compiled_sweep(out, conv_time, n_shift)
    bench_strip_sweep(out, conv_time, n_shift)
    bench_manchester(out, unit)
    bench_cli_overhead(out)
    return lines


if __name__ == "__main__":
    import argparse
    ap = argparse.ArgumentParser(description="Whole wheel-rail cases in the compiled "
                                 "pass; run without arguments it writes compiled_case.md")
    ap.add_argument("shifts", nargs="?", type=int, default=250,
                    help="lateral shifts of the sweep per yaw (250: the 1000-case sweep)")
    ap.add_argument("--strips", action="store_true",
                    help="the strip models' table alone, printed")
    args = ap.parse_args()
    load0 = os.getloadavg()[1]
    report = main(args.shifts, args.strips)
    if len(sys.argv) <= 1:
        (HERE / "compiled_case.md").write_text(
            f"# Whole cases in one compiled pass ({time.strftime('%Y-%m-%d')}, "
            f"{os.cpu_count()} cores, Python {sys.version.split()[0]}; the machine's load "
            f"average (5 min) {load0:.1f} at the start, {os.getloadavg()[1]:.1f} at the end: "
            "CPU times, interleaved, stand; wall times would not)\n"
            + "\n".join(report) + "\n")
