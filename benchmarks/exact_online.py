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

``--route-run``: one ``exact`` + ``exact`` run (``stand_in="both"``, this checkout)
over ``--duration`` s of the route from ``--start`` s (the issue's 100 s run, or the
part of it where the curve and the flange contact are), at ``--sample-rate``
samples per second (200 as the Hertz runs of ``dynamics_online.py``: the same rk4
step), in this process, with its progress (simulated time, CPU, evaluations, solves
and convolutions per evaluation, per chunk) logged to ``--log`` and its states saved
to ``--save`` (an ``.npz``, rewritten at each chunk: a run stopped early leaves the
part it made).  From ``--start`` > 0 the run starts from the state of the Hertz +
FASTSIM online run at that time (the same route from t = 0, compiled), handed over;
the exact run's step is that of its own Jacobian at the route's start (as a run from
t = 0 has it).  Then, in the same process: the Hertz + FASTSIM online run and the
table run over the same time (from t = 0) and the exact run's wheel forces Q, Y
against theirs at the same samples (rms, largest difference), max |Y/Q| of each, the
samples with a flange patch loaded.  ``--from-states FILE``: the comparison of a
saved (possibly partial) run's states instead of a run.  ``--initial FILE``: the run
starts from the first state of a saved run (its time), e.g. to time the same stretch
on two versions of the code, each in a checkout of its own (the wheel forces at the
samples are saved beside ``--save``, ``*.forces.npz``; the library keeps no switch
for a "before": the inner stages that solved every wheelset where one's patches had
moved were measured in 5cf8d1f with its ``--all-wheelsets``, since removed: the
figures are kept in ``benchmarks/dynamics_online.md``, and a checkout of 5cf8d1f
reruns them); ``--initial-time T``: from its state at T instead
(e.g. ``--initial runs/full.npz --initial-time 23.85 --duration 0.1 --no-refs``:
the stretch of the 100 s run where the wheel loads spiked, issue 30).
"""

from __future__ import annotations

import argparse
import json
import math
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
    ap.add_argument("--route-run", action="store_true",
                    help="one exact + exact run over --duration s from --start s, with "
                         "its progress logged, against the Hertz and table runs")
    ap.add_argument("--start", type=float, default=0.0,
                    help="--route-run: start time [s] (the Hertz run's state handed over)")
    ap.add_argument("--log", default=None, help="--route-run: progress log file")
    ap.add_argument("--save", default=None, help="--route-run: states (.npz)")
    ap.add_argument("--chunk", type=float, default=0.05,
                    help="--route-run: simulated seconds per progress line")
    ap.add_argument("--initial", default=None,
                    help="--route-run: start from the first state of a saved run (.npz of "
                         "--save) at its time, instead of --start's handover")
    ap.add_argument("--initial-time", type=float, default=None,
                    help="--route-run with --initial: the saved run's state at this time "
                         "[s] (its nearest sample) instead of its first, e.g. to restart "
                         "just before a stretch of it")
    ap.add_argument("--refs", default=None,
                    help="--route-run: the Hertz and table runs to compare with, kept in "
                         "REFS-hertz.nc and REFS-table.nc (run to max(100 s, the run's "
                         "end) where they are not there yet)")
    ap.add_argument("--refs-only", action="store_true",
                    help="--route-run: only make the --refs files")
    ap.add_argument("--no-refs", action="store_true",
                    help="--route-run: without the Hertz and table runs to compare with")
    ap.add_argument("--from-states", default=None,
                    help="--route-run: compare a saved run's states (.npz) instead")
    args = ap.parse_args(argv)
    if args.route_run:
        return route_run(args)
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
        from dynamics_online import write_report
        write_report(args.out, lines, append=True)
    return lines


# ----------------------------------------------------------------- --route-run
def _log(path, text):
    line = f"{time.strftime('%H:%M:%S', time.gmtime())} {text}"
    print(line, flush=True)
    if path:
        with open(path, "a") as f:
            f.write(line + "\n")


def _online_run(sysm, u, t0, duration, dt, every, sample_rate, chunk=None, note=None):
    """Rk4 of the online contact from (t0 [s], u) over ``duration`` [s], as
    :func:`railcontact.dynamics.simulation._run_rk4_online` steps it (the compiled
    loop with a compiled law, else the Python one), in chunks of ``chunk`` samples,
    ``note(k, t, steps)`` after each.  Returns the sample times, the states, the
    steps made, the loop's CPU time [s] and the status (completed, derailed,
    diverged)."""
    import railcontact.dynamics.simulation as S
    n = int(math.floor(duration * sample_rate + 1e-9))
    t = t0 + np.arange(n + 1) / sample_rate
    Y = np.empty((n + 1, u.size))
    Y[0] = u
    chunk = chunk or max(1, n // 100)
    cpu, steps, written, status = 0.0, 0, n, "completed"
    for k0 in range(0, n, chunk):
        k1 = min(k0 + chunk, n)
        c0 = time.process_time()
        if sysm.law >= 0:
            u, k, m = S.rk4_online(u, t[k0], dt, (k1 - k0) * every, every, sysm.system,
                                   sysm.online, sysm.fext_rows, sysm.out, Y[k0 + 1:k1 + 1])
        else:
            u, k, m = S._rk4_python(sysm, u, t[k0], dt, (k1 - k0) * every, every,
                                    Y[k0 + 1:k1 + 1])
        cpu += time.process_time() - c0
        steps += m
        if not np.all(np.isfinite(u)):
            written, status = k0, f"diverged before t = {t[k1]:.4g} s"
            break
        if m < (k1 - k0) * every:
            written, status = k0 + k, f"derailed at t = {t[k0] + m * dt:.4f} s"
            break
        if note is not None:
            note(k1, t[:k1 + 1], Y[:k1 + 1], steps, cpu)
    return t[:written + 1], Y[:written + 1], steps, cpu, status


def _wheel_forces(sysm, t, Y):
    """The dataset of a run's samples (the forces evaluated again at each)."""
    import railcontact.dynamics.simulation as S
    return S._dataset(sysm, t, Y.T, 0.0)


def route_run(args):
    """``--route-run``: see the module's docstring."""
    sys.path.insert(0, str(HERE))
    from dynamics_online import _setup
    from exact_case import Counter, _pk, _ssn, unit_cpu
    import railcontact.dynamics.simulation as S
    from railcontact.dynamics import Integration, simulate_vehicle
    from railcontact.dynamics.online_contact import OnlineWheelRail
    from railcontact.dynamics.vehicle import G_ACC
    V, T0, T, rate = 50.0, args.start, args.duration, args.sample_rate
    log = args.log
    model, ws, tr, table, route = _setup(max(100.0, T0 + T), V)
    q0 = model.wheelsets[0][1] * G_ACC / 2
    load0 = os.getloadavg()
    head = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                          capture_output=True, text=True).stdout.strip()
    _log(log, f"route run: exact + exact (stand-ins both), {T:g} s from t = {T0:g} s, "
              f"{rate:g} samples/s, commit {head}, load average {load0[0]:.1f}")
    hertz = OnlineWheelRail(ws, tr, damping=6e5)
    exact = OnlineWheelRail(ws, tr, damping=6e5, normal="exact")
    integ = Integration(method="rk4", sample_rate=rate)
    if args.refs_only:
        return _references(args, model, route, table, hertz, integ, max(100.0, T0 + T))
    for c, law in ((hertz, "fastsim"), (exact, "exact")):       # the caches loaded
        simulate_vehicle(model, route, c, V, 2.0 / rate, law, integration=integ)
    # the exact run's system, its static equilibrium and its step (as simulate_vehicle)
    sx = S._System(model, route, exact, V, "exact")
    u = S.static_contact(sx, np.zeros(sx.n_states))
    dt, every = S.online_step(sx, u, rate)
    _log(log, f"exact: rk4 step {dt * 1e3:.4g} ms ({every} per sample)")
    if args.from_states:            # a saved (possibly partial) run's states
        z = np.load(args.from_states)
        t, Y = z["t"], z["Y"]
        k = int(np.max(np.nonzero(np.all(np.isfinite(Y), axis=1))[0]))
        t, Y = t[:k + 1], Y[:k + 1]
        n = max(int(z["evaluations"]), 1)
        dx = _wheel_forces(sx, t, Y)
        return _route_report(args, dict(
            head=head, T0=float(z["start"]), T=float(t[-1] - z["start"]), rate=rate,
            dt=float(z["dt"]), status=f"saved states to t = {t[-1]:.3f} s", cpu=float(z["cpu"]),
            wall=math.nan, evals=n, steps=int(z["steps"]), conv=int(z["conv"]),
            unit=unit_cpu(), counts={"calls": {"normal": int(z["normal"]),
                                               "tangential": int(z["tangential"])}},
            load0=load0, load1=os.getloadavg(), q0=q0), dx, model, route, table, hertz, integ)
    if args.initial:                # a saved run's first state
        z = np.load(args.initial)
        k0 = 0 if args.initial_time is None else int(np.argmin(np.abs(z["t"] -
                                                                      args.initial_time)))
        T0, u = float(z["t"][k0]), z["Y"][k0].copy()
        _log(log, f"the first state of {args.initial} (t = {T0:g} s) handed over")
    elif T0 > 0:                    # the Hertz + FASTSIM online run's state at T0
        sh = S._System(model, route, hertz, V, "fastsim")
        uh = S.static_contact(sh, np.zeros(sh.n_states))
        dth, eh = S.online_step(sh, uh, rate)
        th, Yh, _, cpu_h, st = _online_run(sh, uh, 0.0, T0, dth, eh, rate)
        if st != "completed":
            raise RuntimeError(f"the Hertz run to t = {T0:g} s: {st}")
        u = Yh[-1].copy()
        _log(log, f"the Hertz + FASTSIM online state at t = {th[-1]:g} s handed over "
                  f"(its step {dth * 1e3:.4g} ms, {cpu_h:.1f} s CPU)")
    c = Counter()
    for mod, attr, label, count in (
            ("railcontact.dynamics.simulation", "rhs_online", "search", None),
            ("railcontact.normal.exact", "ExactNormalModel.solve", "normal", None),
            ("railcontact.normal.exact", "polonsky_keer", "pk", _pk),
            ("railcontact.tangential.exact", "ExactTangentialModel.solve", "tangential", None),
            ("railcontact.tangential.exact", "ssn_solve", "ssn", _ssn)):
        c.wrap(mod, attr, label, count)
    sx.calls = 0
    last = {"calls": 0, "cpu": 0.0, "normal": 0, "tangential": 0, "conv": 0,
            "wall": time.perf_counter(), "saved": time.perf_counter()}
    per = max(1, int(round(args.chunk * rate)))

    def note(k, t, Y, steps, cpu):
        ev = sx.calls - last["calls"]
        conv = c.conv.get("pk", 0) + c.conv.get("ssn", 0)
        d_cpu = cpu - last["cpu"]
        _log(log, f"t = {t[-1]:.3f} s: CPU {cpu:.1f} s ({d_cpu / (args.chunk):.1f} x real time "
                  f"in this chunk), wall {time.perf_counter() - last['wall']:.1f} s, "
                  f"evaluations {sx.calls} (+{ev}, {1e3 * d_cpu / max(ev, 1):.2f} ms each), "
                  f"normal/tangential solves per evaluation "
                  f"{(c.calls.get('normal', 0) - last['normal']) / max(ev, 1):.2f}/"
                  f"{(c.calls.get('tangential', 0) - last['tangential']) / max(ev, 1):.2f}, "
                  f"convolutions per evaluation {(conv - last['conv']) / max(ev, 1):.0f}, "
                  f"rows {int(sx.online.count.sum())}, load {os.getloadavg()[0]:.1f}")
        last.update(calls=sx.calls, cpu=cpu, normal=c.calls.get("normal", 0),
                    tangential=c.calls.get("tangential", 0), conv=conv)
        if args.save and (time.perf_counter() - last["saved"] > 60 or k == n_all):
            np.savez(args.save, t=t, Y=Y, steps=steps, cpu=cpu, evaluations=sx.calls,
                     dt=dt, start=T0, conv=conv, normal=c.calls.get("normal", 0),
                     tangential=c.calls.get("tangential", 0))
            last["saved"] = time.perf_counter()

    n_all = int(math.floor(T * rate + 1e-9))
    w0 = time.perf_counter()
    t, Y, steps, cpu, status = _online_run(sx, u, T0, T, dt, every, rate, per, note)
    wall = time.perf_counter() - w0
    evals = sx.calls
    counts = {k: dict(v) for k, v in (("calls", c.calls), ("cpu", c.cpu), ("conv", c.conv))}
    c.restore()
    if args.save:
        np.savez(args.save, t=t, Y=Y, steps=steps, cpu=cpu, evaluations=evals, dt=dt,
                 start=T0, conv=counts["conv"].get("pk", 0) + counts["conv"].get("ssn", 0),
                 normal=counts["calls"].get("normal", 0),
                 tangential=counts["calls"].get("tangential", 0))
    _log(log, f"exact run: {status}, {t[-1] - T0:g} s simulated, loop CPU {cpu:.1f} s, "
              f"wall {wall:.1f} s, {evals} evaluations, {steps} steps")
    c0 = time.process_time()
    dx = _wheel_forces(sx, t, Y)
    _log(log, f"the exact run's samples evaluated again: {time.process_time() - c0:.1f} s CPU")
    if args.save:
        np.savez(args.save[:-4] + ".forces.npz", t=t, Q=dx["Q"].values, Y=dx["Y"].values)
    unit = unit_cpu()
    conv = counts["conv"].get("pk", 0) + counts["conv"].get("ssn", 0)
    load1 = os.getloadavg()
    return _route_report(args, dict(
        head=head, T0=T0, T=t[-1] - T0, rate=rate, dt=dt, status=status, cpu=cpu,
        wall=wall, evals=evals, steps=steps, conv=conv, unit=unit, counts=counts,
        load0=load0, load1=load1, q0=q0), dx, model, route, table, hertz, integ)


def _references(args, model, route, table, hertz, integ, T1):
    """The Hertz + FASTSIM online run and the table run from t = 0 to ``T1`` [s]
    (their wheel forces), from ``--refs``'s files where they reach ``T1``, else run
    (and kept there)."""
    import xarray as xr
    from railcontact.dynamics import simulate_vehicle
    refs = {}
    for name, c, tag in (("Hertz + FASTSIM online", hertz, "hertz"), ("table", table, "table")):
        path = f"{args.refs}-{tag}.nc" if args.refs else None
        if path and Path(path).exists():
            ds = xr.load_dataset(path)
            if float(ds["time"].values[-1]) >= T1 - 1e-9:
                refs[name] = ds
                continue
        c0 = time.process_time()
        ds = simulate_vehicle(model, route, c, 50.0, T1, "fastsim", integration=integ)
        _log(args.log, f"{name} run to t = {T1:g} s: {time.process_time() - c0:.1f} s CPU, "
                       f"status {ds.attrs['status']}")
        ds = ds[["Q", "Y", "Y_over_Q", "patch_normal_force"]]
        if path:
            ds.to_netcdf(path, engine="h5netcdf")
        refs[name] = ds
    return refs


def _route_report(args, r, dx, model, route, table, hertz, integ):
    """The Markdown section of a route run and its comparison with the Hertz +
    FASTSIM online and the table runs (from t = 0, :func:`_references`)."""
    T0, T1 = r["T0"], r["T0"] + r["T"]
    refs = {} if args.no_refs else _references(args, model, route, table, hertz, integ, T1)
    n, per = r["evals"], r["cpu"] / max(r["evals"], 1)
    calls = r["counts"]["calls"]
    lines = [f"Exact + exact online (`stand_in=\"both\"`), {r['T']:g} s of the route from "
             f"t = {T0:g} s ({'the Hertz + FASTSIM online state handed over' if T0 > 0 else 'static equilibrium'}), "
             f"{r['rate']:g} samples per second, rk4 step {r['dt'] * 1e3:.4g} ms; commit "
             f"{r['head']}; load average {r['load0'][0]:.1f} at the start, "
             f"{r['load1'][0]:.1f} at the end (2 cores); status {r['status']}.", "",
             "| simulated [s] | loop CPU [s] | loop wall [s] | x real time (CPU) | evaluations "
             "| ms per evaluation | = FFT convolutions | normal / tangential solves per "
             "evaluation | FFT convolutions per evaluation (counted) | unit [µs] |",
             "|" + "---|" * 10,
             f"| {r['T']:g} | {r['cpu']:.1f} | {r['wall']:.1f} | {r['cpu'] / r['T']:.1f} | {n} | "
             f"{per * 1e3:.2f} | {per / r['unit']:.0f} | "
             f"{calls.get('normal', 0) / n:.2f} / {calls.get('tangential', 0) / n:.2f} | "
             f"{r['conv'] / n:.0f} | {r['unit'] * 1e6:.1f} |", ""]
    sel_t = lambda ds: (ds["time"].values >= T0 - 1e-9) & (ds["time"].values <= T1 + 1e-9)
    xs = dx.isel(time=sel_t(dx))
    flange = (xs["patch_normal_force"].values[..., 1] > 0).any(axis=(1, 2))
    lines += ["Wheel forces of every wheel (4 wheelsets x 2) at the samples, the exact run "
              "against each: rms and largest difference [N] (/ Q0 = "
              f"{r['q0'] / 1e3:.1f} kN); all samples, and those with a flange patch loaded "
              f"in the exact run ({int(flange.sum())} of {flange.size}):", "",
              "| against | samples | Q rms | Q max | Y rms | Y max | flange samples: Q rms | "
              "Q max | Y rms | Y max |", "|" + "---|" * 10]
    yq = {"exact + exact": xs}
    for name, ds in refs.items():
        rs = ds.isel(time=sel_t(ds))
        m = min(rs.sizes["time"], xs.sizes["time"])
        yq[name] = rs.isel(time=slice(0, m))
        cells = []
        for sel in (np.ones(m, bool), flange[:m]):
            for v in ("Q", "Y"):
                d = (xs[v].values[:m] - rs[v].values[:m])[sel]
                cells += ([f"{np.sqrt(np.mean(d ** 2)):.0f} ({100 * np.sqrt(np.mean(d ** 2)) / r['q0']:.2f} %)",
                           f"{np.max(np.abs(d)):.0f} ({100 * np.max(np.abs(d)) / r['q0']:.2f} %)"]
                          if d.size else ["", ""])
        lines.append(f"| {name} | {m} | " + " | ".join(cells) + " |")
    lines += ["", "| run | max \\|Y/Q\\| | at t [s] | wheelset, wheel | Y [kN] | Q [kN] | "
              "99.9th percentile \\|Y/Q\\| | Q min, max [kN] |", "|---|---|---|---|---|---|---|---|"]
    for name, ds in yq.items():
        a = np.abs(ds["Y_over_Q"].values)
        k = np.unravel_index(int(np.nanargmax(a)), a.shape)
        lines.append(f"| {name} | {a[k]:.2f} | {float(ds['time'].values[k[0]]):.3f} | "
                     f"{k[1] + 1}, {('left', 'right')[k[2]]} | "
                     f"{float(ds['Y'].values[k]) / 1e3:.1f} | {float(ds['Q'].values[k]) / 1e3:.1f} | "
                     f"{float(np.nanpercentile(a, 99.9)):.2f} | "
                     f"{float(np.min(ds['Q'].values)) / 1e3:.1f}, "
                     f"{float(np.max(ds['Q'].values)) / 1e3:.1f} |")
    text = "\n".join(lines)
    _log(args.log, "report:\n" + text)
    if args.out:
        from dynamics_online import write_report
        write_report(args.out, lines, append=True)
    return lines


if __name__ == "__main__":
    main()
