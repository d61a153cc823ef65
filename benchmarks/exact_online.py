"""Issue 30, ``exact`` + ``exact`` online in the vehicle dynamics: where an
evaluation of the right-hand side spends its time, before and after, interleaved.

The scenario of ``benchmarks/dynamics_online.py`` (Manchester vehicle, 4
wheelsets, 50 m/s, the curved irregular route from its start: the first
``--duration`` s lie on its tangent with ERRI-low irregularities; rk4 at the
step of the run's Jacobian, which divides the interval of ``--sample-rate``
samples per second: 1000 as that benchmark's exact row had it, 0.5 ms), run by
each variant in a process of its own, the variants alternating for ``--rounds``
rounds:

* ``before``: the code of ``--before`` (a git ref, default :data:`BEFORE`; extracted
  into the temporary folder with a Numba cache of its own): the normal and
  tangential problems solved per patch at every evaluation, each warm-started from
  the same wheel's patch of the last evaluation interpolated to a new grid;
* ``none``, ``tangential``, ``both``: this checkout with
  ``OnlineWheelRail(stand_in=...)``: the normal solves warm-started on the
  patch's kept grid, and the compiled stand-ins corrected at the inner stages of
  each rk4 step (none; FASTSIM for the tangential problems; FASTSIM and Hertz's
  spring for both).

Per run, in the rk4 loop alone (the start, the static equilibrium and the step's
Jacobian, apart): CPU time of the process, evaluations, ms per evaluation,
multiples of real time (CPU / simulated), exact normal and tangential solves per
evaluation, FFT convolutions per evaluation (counted as ``exact_case.py`` counts
them: Polonsky-Keer it + ceil(it / 10), semi-smooth Newton 2 (1 + products)),
and the CPU of the compiled solvers' iterations, the compiled search and the
rest (Python: grids, gaps, set-up, results, the loop).  The unit, one FFT
convolution of the 40 x 40 grid's 80 x 80 padding, measured in each process
after its run.  The wheel forces Q and Y of every wheel at the samples against
the ``before`` run's: rms and largest difference.

``python benchmarks/exact_online.py [--duration 0.5] [--rounds 2] [--before REF]
[--variants before,none,tangential,both] [--sample-rate 1000] [--out FILE]``
(prints a Markdown section; ``--out`` appends it to a file).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
VARIANTS = ("before", "none", "tangential", "both")
#: the code before the stand-ins and the kept grids (issue 30's main, 2026-11-27)
BEFORE = "ff7965a"


def _child(variant: str, duration: float, npz: str, sample_rate: float) -> dict:
    """One run in this process (the package on ``sys.path``): the measurements."""
    sys.path.insert(0, str(Path.cwd() / "benchmarks"))
    from dynamics_online import _setup
    from exact_case import Counter, _pk, _ssn, unit_cpu
    import railcontact.dynamics.simulation as S
    from railcontact.dynamics import Integration, simulate_vehicle
    from railcontact.dynamics.online_contact import OnlineWheelRail
    from railcontact.dynamics.vehicle import G_ACC
    model, ws, tr, _, route = _setup(100.0, 50.0)
    kw = {} if variant == "before" else {"stand_in": variant}
    online = OnlineWheelRail(ws, tr, damping=6e5, normal="exact", **kw)
    integ = Integration(method="rk4", sample_rate=sample_rate)
    simulate_vehicle(model, route, online, 50.0, max(2.0 / sample_rate, 2e-3), "exact",
                     integration=integ)                     # the caches loaded
    c = Counter()
    stages = (("railcontact.dynamics.simulation", "rhs_online", "search", None),
              ("railcontact.geometry.wheel_pass", "patch_geometry", "geometry", None),
              ("railcontact.normal.exact", "ExactNormalModel.solve", "normal", None),
              ("railcontact.normal.exact", "polonsky_keer", "pk", _pk),
              ("railcontact.tangential.exact", "ExactTangentialModel.solve", "tangential",
               None),
              ("railcontact.tangential.exact", "ssn_solve", "ssn", _ssn))
    for mod, attr, label, count in stages:
        c.wrap(mod, attr, label, count)
    real, loop = S._rk4_python, {"cpu": 0.0, "first": True}

    def timed(*a, **k):                # the rk4 loop's chunks, the counters from its first
        if loop["first"]:
            for d in (c.calls, c.cpu, c.iters, c.conv):
                d.clear()
            loop["first"] = False
        t0 = time.process_time()
        r = real(*a, **k)
        loop["cpu"] += time.process_time() - t0
        loop["counts"] = {k: dict(v) for k, v in (("calls", c.calls), ("cpu", c.cpu),
                                                  ("iters", c.iters), ("conv", c.conv))}
        return r
    S._rk4_python = timed
    c0 = time.process_time()
    ds = simulate_vehicle(model, route, online, 50.0, duration, "exact", integration=integ)
    total = time.process_time() - c0
    S._rk4_python = real
    c.restore()
    np.savez(npz, Q=ds["Q"].values, Y=ds["Y"].values, t=ds["time"].values)
    return {"variant": variant, "loop_cpu": loop["cpu"], "total_cpu": total,
            "evaluations": int(ds.attrs["rhs_calls"]), "step_s": float(ds.attrs["step_s"]),
            "duration": duration, "status": ds.attrs["status"], "counts": loop["counts"],
            "unit": unit_cpu(), "q0": model.wheelsets[0][1] * G_ACC / 2}


def _before_tree(ref: str) -> Path:
    """The package at ``ref`` extracted into a folder of the temporary directory
    (kept, with its Numba cache, for the next run)."""
    sha = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", ref], check=True,
                         capture_output=True, text=True).stdout.strip()
    tree = Path(tempfile.gettempdir()) / f"railcontact-exact-online-{sha}"
    if not (tree / "railcontact").is_dir():
        tree.mkdir(parents=True, exist_ok=True)
        subprocess.run(f"git -C {ROOT} archive {sha} railcontact benchmarks | tar -x -C {tree}",
                       shell=True, check=True)
    return tree


def _run(variant: str, duration: float, before: Path, npz: str, sample_rate: float) -> dict:
    tree = before if variant == "before" else ROOT
    env = dict(os.environ, PYTHONPATH=str(tree),
               NUMBA_CACHE_DIR=str(tree / ".numba-exact-online") if variant == "before"
               else os.environ.get("NUMBA_CACHE_DIR", str(ROOT / ".venv" / "numba-cache")))
    p = subprocess.run([sys.executable, str(HERE / "exact_online.py"), "--child", variant,
                        "--duration", str(duration), "--npz", npz, "--sample-rate",
                        str(sample_rate)], cwd=tree, env=env,
                       capture_output=True, text=True)
    if p.returncode:
        raise RuntimeError(f"{variant}: {p.stderr.strip()[-2000:]}")
    return json.loads(p.stdout.strip().splitlines()[-1])


def _row(r: dict) -> str:
    n = r["evaluations"]
    cnt = r["counts"]
    calls, cpu, conv = cnt["calls"], cnt["cpu"], cnt["conv"]
    unit = r["unit"]
    per = r["loop_cpu"] / n
    kern = cpu.get("pk", 0.0) + cpu.get("ssn", 0.0)
    convs = (conv.get("pk", 0) + conv.get("ssn", 0)) / n
    return (f"| {r['variant']} | {r['duration']:g} | {r['loop_cpu']:.2f} | "
            f"{r['loop_cpu'] / r['duration']:.1f} | {n} | {per * 1e3:.2f} | {per / unit:.0f} | "
            f"{calls.get('normal', 0) / n:.2f} | {calls.get('tangential', 0) / n:.2f} | "
            f"{convs:.0f} | {100 * kern / r['loop_cpu']:.0f} % | "
            f"{100 * cpu.get('search', 0.0) / r['loop_cpu']:.0f} % | "
            f"{100 * (1 - (kern + cpu.get('search', 0.0)) / r['loop_cpu']):.0f} % | "
            f"{unit * 1e6:.1f} |")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--duration", type=float, default=0.5)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--before", default=BEFORE)
    ap.add_argument("--sample-rate", type=float, default=1000.0,
                    help="samples per second (the rk4 step divides their interval)")
    ap.add_argument("--variants", default=",".join(VARIANTS))
    ap.add_argument("--out", default=None)
    ap.add_argument("--child", default=None)
    ap.add_argument("--npz", default=None)
    args = ap.parse_args(argv)
    if args.child:
        print(json.dumps(_child(args.child, args.duration, args.npz, args.sample_rate)))
        return None
    variants = args.variants.split(",")
    before = _before_tree(args.before) if "before" in variants else ROOT
    load0 = os.getloadavg()
    results = {v: [] for v in variants}
    with tempfile.TemporaryDirectory() as tmp:
        forces = {}
        for k in range(args.rounds):
            for v in variants:
                npz = str(Path(tmp) / f"{v}.npz")
                r = _run(v, args.duration, before, npz, args.sample_rate)
                results[v].append(r)
                forces[v] = dict(np.load(npz))
                print(_row(r), flush=True)
    load1 = os.getloadavg()
    lines = [f"Exact + exact online, {args.duration:g} s of the route (tangent, ERRI-low), "
             f"{args.sample_rate:g} samples per second, rk4 step "
             f"{results[variants[0]][0]['step_s'] * 1e3:.3g} ms, {args.rounds} rounds "
             f"interleaved (the best round of each variant shown), each run in a process of "
             f"its own; CPU time of the rk4 loop; load average "
             f"{load0[0]:.1f} at the start, {load1[0]:.1f} at the end (2 cores):", "",
             "| variant | simulated [s] | loop CPU [s] | x real time | evaluations | "
             "ms per evaluation | = FFT convolutions | normal solves per evaluation | "
             "tangential solves per evaluation | FFT convolutions per evaluation (counted) | "
             "compiled solver iterations | compiled search and forces | Python and the rest | "
             "unit [µs] |", "|" + "---|" * 14]
    for v in variants:
        lines.append(_row(min(results[v], key=lambda r: r["loop_cpu"])))
    if "before" in forces:
        ref = forces["before"]
        q0 = results["before"][0]["q0"]
        lines += ["", "Wheel forces of every wheel at the samples against ``before``:", "",
                  "| variant | samples | Q rms diff. [N] | Q max diff. [N] | Y rms diff. [N] | "
                  "Y max diff. [N] | Q max / Q0 | Y max / Q0 |", "|" + "---|" * 8]
        for v in variants:
            if v == "before":
                continue
            n = min(ref["Q"].shape[0], forces[v]["Q"].shape[0])
            dq = forces[v]["Q"][:n] - ref["Q"][:n]
            dy = forces[v]["Y"][:n] - ref["Y"][:n]
            lines.append(f"| {v} | {n} | {np.sqrt(np.mean(dq ** 2)):.1f} | "
                         f"{np.max(np.abs(dq)):.1f} | {np.sqrt(np.mean(dy ** 2)):.1f} | "
                         f"{np.max(np.abs(dy)):.1f} | {100 * np.max(np.abs(dq)) / q0:.3f} % | "
                         f"{100 * np.max(np.abs(dy)) / q0:.3f} % |")
    text = "\n".join(lines)
    print(text)
    if args.out:
        with open(args.out, "a") as f:
            f.write("\n" + text + "\n")
    return lines


if __name__ == "__main__":
    main()
