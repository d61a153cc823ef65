"""Issue 30, "contact online in the dynamics": the Manchester vehicle at 50 m/s on
the curved irregular route of ``run_all.bench_dynamics`` (300 m tangent, 200 m
transition, R 2500 m with 120 mm cant, ERRI-low seed 7), with the contact
searched online at every evaluation of the right-hand side
(:mod:`railcontact.dynamics.online_contact`) against the contact table.

Measured in one run, interleaved (table, online, table, online: the best of each
pair counts), wall and CPU time (the machine is shared: CPU time is the process's
own), as multiples of real time (wall / simulated):

* Hertz + FASTSIM (compiled) and Hertz + Polach (compiled), online, over
  ``--duration`` s (100 s for the issue's figure);
* the strip models ANALYN (over ``--strip-duration``, default ``--duration``) and
  Kik-Piotrowski (``--kp-duration``) + ``fastsim-strips``, compiled in the rk4
  loop (:mod:`railcontact.cases.strip_pass` per patch), as the compiled laws;
* ``exact`` + ``exact`` (per patch in Python, warm-started on kept grids, the
  compiled stand-ins at the rk4 steps' inner stages:
  ``OnlineWheelRail(stand_in="both")``; ``benchmarks/exact_online.py`` has its
  breakdown) online over a short stretch (``--exact-duration``), as multiples of
  real time of the rk4 loop's wall time and of the whole call's CPU time (with the
  start: static equilibrium and the step's Jacobian);
* the difference in wheel forces between the online and the table run on the
  tangent track (the first 300 m, after the first 0.5 s): rms of Q, Y, Fx, Fy per
  wheel, as a fraction of the static wheel load and of the table run's own rms;
  the same with the cross level set to zero (like for like: the table path has no
  wheelset roll or vertical freedom); and on smooth tangent track (no irregularities, every wheelset let go 3 mm off
  centre, ``--smooth-duration`` s), where neither path has a dynamic wheel load.

Run alone (``python benchmarks/dynamics_online.py [--duration 100]``, writes
``benchmarks/dynamics_online.md``) or from ``benchmarks/run_all.py``.

``--strip-compare T`` runs only the strip model online (``--strip-normal``, ANALYN
by default, + ``fastsim-strips``) over T s as before and after the warm-started
strips and the strip springs' stiffness, interleaved in one process
(``--strip-repeats`` pairs; CPU time): before = each evaluation's strips laid
afresh (``warm_strips=False``) and the step bounded to 0.5 ms (the former
``simulation.STRIP_ONLINE_STEP``), after = the defaults; with the rms difference
of the wheel forces between the two (writes ``--out``, by default
``benchmarks/dynamics_online_strips.md``).
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
lines: list = []


def out(s=""):
    print(s, flush=True)
    lines.append(s)


#: the line from which ``dynamics_online.md`` holds the records of earlier runs (the
#: 100 s exact + exact route, branches' measurements), kept when the script rewrites
#: the part above it
RECORDS = "<!-- records of earlier runs: kept by benchmarks/dynamics_online.py -->"


def write_report(path, lines, append=False) -> None:
    """Write ``lines`` to the report ``path``, keeping its records of earlier runs
    (from :data:`RECORDS` on) below them; ``append``: after the part above the
    records instead of replacing it (``exact_online.py --out``)."""
    path = Path(path)
    old = path.read_text() if path.is_file() else ""
    head, mark, records = old.partition(RECORDS)
    text = "\n".join(lines) + "\n"
    if append:
        text = head.rstrip("\n") + "\n\n" + text
    path.write_text(text + ("\n" + mark + records if mark else ""))


def _setup(duration, velocity):
    from railcontact.dynamics import Route, VehicleModel, WheelRailTable
    from railcontact.dynamics.route import Irregularities
    from railcontact.dynamics.vehicle import G_ACC
    from railcontact.geometry import Track, Wheelset
    from railcontact.profiles import rail_profile, s1002
    model = VehicleModel.vehicle()
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    table = WheelRailTable.build(ws, tr, model.wheelsets[0][1] * G_ACC / 2)
    length = velocity * duration + 60.0
    route = Route.from_segments(
        [{"type": "tangent", "length": 300.0}, {"type": "transition", "length": 200.0},
         {"type": "curve", "radius": 2500.0, "cant": 0.12, "length": max(length - 500.0, 50)}],
        Irregularities.from_psd(max(length, 560.0), "ERRI-low", seed=7))
    return model, ws, tr, table, route


def _run(model, route, contact, velocity, duration, law, sample_rate=200.0):
    from railcontact.dynamics import Integration, simulate_vehicle
    w0, c0 = time.perf_counter(), time.process_time()
    ds = simulate_vehicle(model, route, contact, velocity, duration, law,
                          integration=Integration(sample_rate=sample_rate))
    return ds, time.perf_counter() - w0, time.process_time() - c0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--duration", type=float, default=100.0)
    ap.add_argument("--strip-duration", type=float, default=None,
                    help="ANALYN + fastsim-strips, compiled [s] (default: --duration)")
    ap.add_argument("--kp-duration", type=float, default=10.0,
                    help="Kik-Piotrowski + fastsim-strips, compiled [s]")
    ap.add_argument("--exact-duration", type=float, default=0.2)
    ap.add_argument("--velocity", type=float, default=50.0)
    ap.add_argument("--damping", type=float, default=6e5)
    ap.add_argument("--smooth-duration", type=float, default=10.0)
    ap.add_argument("--strips-only", action="store_true",
                    help="only the online runs of Hertz + FASTSIM and the strip models")
    ap.add_argument("--strip-compare", type=float, default=None,
                    help="only the strip model online, before/after, over this many s")
    ap.add_argument("--strip-normal", default="analyn")
    ap.add_argument("--strip-repeats", type=int, default=1)
    ap.add_argument("--out", default=None)
    args = ap.parse_args(argv)
    lines.clear()
    if args.strip_compare is not None:
        return strip_compare(args)
    args.out = args.out or str(HERE / "dynamics_online.md")
    from railcontact.dynamics.online_contact import OnlineWheelRail
    from railcontact.dynamics.vehicle import G_ACC
    V, T = args.velocity, args.duration
    model, ws, tr, table, route = _setup(T, V)
    online = OnlineWheelRail(ws, tr, damping=args.damping)
    online_an = OnlineWheelRail(ws, tr, damping=args.damping, normal="analyn")
    online_kp = OnlineWheelRail(ws, tr, damping=args.damping, normal="kik-piotrowski")
    online_ex = OnlineWheelRail(ws, tr, damping=args.damping, normal="exact")
    for c in (table, online):                       # compile / load the caches
        _run(model, route, c, V, 0.05, "fastsim")
        if not args.strips_only:
            _run(model, route, c, V, 0.05, "polach")
    for c in (online_an, online_kp):
        _run(model, route, c, V, 0.05, "fastsim-strips")
    strip_T = T if args.strip_duration is None else args.strip_duration
    out("# Contact online in the dynamics (issue 30)\n")
    out(f"Manchester vehicle (4 wheelsets), {V:g} m/s, curved irregular route "
        f"(300 m tangent, 200 m transition, R 2500 m, cant 120 mm, ERRI-low seed 7); "
        f"online contact damping {args.damping:g} N s/m per patch.  Times in one run, "
        "table and online interleaved; wall and this process's CPU time (the machine "
        "is shared by other sessions).\n")
    out("| contact | law | simulated [s] | wall [s] | CPU [s] | wall / real time | "
        "CPU / real time | rk4 step [ms] | RHS calls | µs CPU per RHS call |")
    out("|---|---|---|---|---|---|---|---|---|---|")
    res = {}
    runs = [(name, c, law, T, f"Hertz + {law} (compiled)") for law in ("fastsim", "polach")
            for name, c in (("table", table), ("online", online))]
    if args.strips_only:
        runs = [("online", online, "fastsim", T, "Hertz + fastsim (compiled)")]
    runs += [("online", online_an, "fastsim-strips", strip_T,
              "analyn + fastsim-strips (compiled strips, cases.strip_pass)"),
             ("online", online_kp, "fastsim-strips", args.kp_duration,
              "kik-piotrowski + fastsim-strips (compiled strips, cases.strip_pass)")]
    for name, c, law, dur, label in runs:
        ds, wall, cpu = _run(model, route, c, V, dur, law)
        res[(name, law, getattr(c, "normal", "hertz"))] = ds
        calls = ds.attrs["rhs_calls"]
        out(f"| {name} | {label} | {dur:g} | {wall:.1f} | {cpu:.1f} | "
            f"{wall / dur:.3g} | {cpu / dur:.3g} | {ds.attrs['step_s'] * 1e3:.3f} | {calls} | "
            f"{1e6 * cpu / max(calls, 1):.0f} |")
        if ds.attrs.get("status") != "completed":
            out(f"\n{label}: status {ds.attrs.get('status')}: {ds.attrs.get('derailment', '')}\n")
    if args.strips_only:
        write_report(args.out, lines)
        return lines
    for name, c, law, dur in (("online", online_ex, "exact", args.exact_duration),):
        from railcontact.dynamics import Integration, simulate_vehicle
        w0, c0 = time.perf_counter(), time.process_time()
        ds = simulate_vehicle(model, route, c, V, dur, law,
                              integration=Integration(method="rk4", sample_rate=1000.0))
        wall, cpu = time.perf_counter() - w0, time.process_time() - c0
        loop = ds.attrs["wall_time_s"]
        calls = ds.attrs["rhs_calls"]
        how = f"Python per patch, kept grids, stand-ins {c.stand_in}"
        out(f"| {name} | {c.normal} + {law} ({how}) | {dur:g} | {wall:.1f} "
            f"(loop {loop:.1f}) | {cpu:.1f} | {loop / dur:.3g} (loop) | {cpu / dur:.3g} "
            f"(incl. start) | {ds.attrs['step_s'] * 1e3:.3f} | {calls} | "
            f"{1e6 * loop / max(calls, 1):.0f} (wall) |")
    # online against table on the tangent track
    t_ds, o_ds = res[("table", "fastsim", "hertz")], res[("online", "fastsim", "hertz")]
    q0 = model.wheelsets[0][1] * G_ACC / 2
    dist = t_ds["distance"].values
    tangent = (t_ds["time"].values >= 0.5) & (dist <= 300.0)
    if tangent.sum() > 10 and o_ds.sizes["time"] == t_ds.sizes["time"]:
        out("\nOnline against table, Hertz + FASTSIM, on the tangent track "
            f"({int(tangent.sum())} samples, t >= 0.5 s, wheelset 1 within the first "
            "300 m), every wheel of the four wheelsets:\n")
        out("| force | rms difference [N] | / static wheel load Q0 | / rms of the table run |")
        out("|---|---|---|---|")
        for v, label in (("Q", "Q (vertical)"), ("Y", "Y (lateral, track plane)"),
                         ("longitudinal_force", "Fx (creep)"),
                         ("lateral_creep_force", "Fy (creep)")):
            a = t_ds[v].values[tangent]
            b = o_ds[v].values[tangent]
            d = float(np.sqrt(np.mean((a - b) ** 2)))
            r = float(np.sqrt(np.mean(a ** 2)))
            out(f"| {label} | {d:.0f} | {100 * d / q0:.2f} % | {100 * d / r:.1f} % |")
        y_a = t_ds["lateral_displacement"].values[tangent]
        y_b = o_ds["lateral_displacement"].values[tangent]
        out(f"\nLateral displacement of the wheelsets: rms difference "
            f"{1e6 * float(np.sqrt(np.mean((y_a - y_b) ** 2))):.0f} µm against an rms of "
            f"{1e6 * float(np.sqrt(np.mean(y_a ** 2))):.0f} µm.  Static wheel load Q0 = "
            f"{q0 / 1e3:.1f} kN.")
    # like for like: the same tangent without the cross level (the table path has no
    # wheelset roll or vertical freedom: the online wheelset's roll inertia and its
    # contact springs answer the cross level's short waves, the table's loads do not)
    from railcontact.dynamics import Route
    from railcontact.dynamics.route import Irregularities
    ir = Irregularities.from_psd(max(V * T + 60.0, 560.0), "ERRI-low", seed=7)
    flat = Irregularities(ir.s, ir.alignment, np.zeros_like(ir.cross_level), "alignment only")
    T6 = 6.5
    pair = [_run(model, Route.from_segments([{"type": "tangent", "length": 400.0}], flat), c,
                 V, T6, "fastsim")[0] for c in (table, online)]
    sel = (pair[0]["time"].values >= 0.5) & (pair[0]["distance"].values <= 300.0)
    out("\nThe same tangent track (the first 300 m, t >= 0.5 s) with the cross level set to "
        "zero, the alignment kept (like for like: the table path has no wheelset roll or "
        f"vertical freedom), {int(sel.sum())} samples:\n")
    out("| force | rms difference [N] | / static wheel load Q0 | / rms of the table run |")
    out("|---|---|---|---|")
    for v, label in (("Q", "Q (vertical)"), ("Y", "Y (lateral, track plane)"),
                     ("longitudinal_force", "Fx (creep)"), ("lateral_creep_force", "Fy (creep)")):
        a, b = pair[0][v].values[sel], pair[1][v].values[sel]
        d = float(np.sqrt(np.mean((a - b) ** 2)))
        r = float(np.sqrt(np.mean(a ** 2)))
        out(f"| {label} | {d:.0f} | {100 * d / q0:.2f} % | {100 * d / r:.1f} % |")
    # smooth tangent track: both paths quasi-static in the vertical and roll
    smooth = Route.tangent(V * args.smooth_duration + 60.0)
    from railcontact.dynamics import Integration, simulate_vehicle
    runs = [simulate_vehicle(model, smooth, c, V, args.smooth_duration, "fastsim", 0.3,
                             initial_lateral_shift=0.003,
                             integration=Integration(sample_rate=200.0)) for c in (table, online)]
    out(f"\nOnline against table on smooth tangent track (no irregularities), every wheelset "
        f"let go 3 mm off centre, {args.smooth_duration:g} s, all samples:\n")
    out("| force | rms difference [N] | / static wheel load Q0 | / rms of the table run |")
    out("|---|---|---|---|")
    for v, label in (("Q", "Q"), ("Y", "Y"), ("longitudinal_force", "Fx"),
                     ("lateral_creep_force", "Fy")):
        a, b = runs[0][v].values, runs[1][v].values
        d = float(np.sqrt(np.mean((a - b) ** 2)))
        r = float(np.sqrt(np.mean(a ** 2)))
        out(f"| {label} | {d:.0f} | {100 * d / q0:.2f} % | {100 * d / r:.1f} % |")
    curve = o_ds.where(o_ds["curvature"] > 0.99 / 2500.0, drop=True)
    if curve.sizes["time"]:
        yq = np.abs(curve["Y_over_Q"].values)
        k = np.unravel_index(int(np.nanargmax(yq)), yq.shape)
        lim = o_ds.attrs["nadal_limit"]
        above = yq[:, k[1], k[2]] > lim
        run = longest = 0
        for x in above:
            run = run + 1 if x else 0
            longest = max(longest, run)
        out(f"\nIn the curve (online, FASTSIM): max |Y/Q| {yq[k]:.2f} (Nadal's limit "
            f"{lim:.2f}) at t = {float(curve['time'].values[k[0]]):.2f} s, wheelset "
            f"{k[1] + 1}, {('left', 'right')[k[2]]} wheel, Y = "
            f"{float(curve['Y'].values[k]) / 1e3:.1f} kN, Q = "
            f"{float(curve['Q'].values[k]) / 1e3:.1f} kN; that wheel above Nadal's limit in "
            f"{int(above.sum())} samples of {above.size} ({1e3 * longest / 200.0:.0f} ms at "
            f"most in a row at 200 Hz); 99.9th percentile of |Y/Q| over all wheels "
            f"{float(np.nanpercentile(yq, 99.9)):.2f}; status {o_ds.attrs['status']}.")
    write_report(args.out, lines)
    return lines


def strip_compare(args):
    """``--strip-compare``: the strip model online before and after, interleaved."""
    from railcontact.dynamics import Integration, simulate_vehicle
    from railcontact.dynamics.online_contact import OnlineWheelRail
    from railcontact.dynamics.vehicle import G_ACC
    V, T, normal = args.velocity, args.strip_compare, args.strip_normal
    model, ws, tr, table, route = _setup(max(T, args.duration), V)   # the route
    q0 = model.wheelsets[0][1] * G_ACC / 2
    runs = {"before": (False, 5e-4), "after": (True, None)}

    def one(name, duration):
        warm, step = runs[name]
        c = OnlineWheelRail(ws, tr, damping=args.damping, normal=normal, warm_strips=warm)
        w0, c0 = time.perf_counter(), time.process_time()
        ds = simulate_vehicle(model, route, c, V, duration, "fastsim-strips",
                              integration=Integration(sample_rate=200.0, step=step))
        return ds, time.perf_counter() - w0, time.process_time() - c0

    for name in runs:                                 # compile / load the caches
        one(name, 0.02)
    out(f"# {normal} + fastsim-strips online: before and after (branch striponline)\n")
    out(f"Manchester vehicle, {V:g} m/s, the curved irregular route of "
        "`dynamics_online.py`, "
        f"{T:g} s; before: each evaluation's strips laid afresh, the rk4 step bounded to "
        "0.5 ms; after: the strips laid from the last evaluation's run ends "
        "(`warm_strips`), the strip springs' stiffness dividing the Jacobian's step.  "
        "Interleaved in one process, CPU time of the process (shared machine).\n")
    out("| run | CPU [s] | CPU / real time | wall [s] | rk4 step [ms] | steps (divided) "
        "| RHS calls | µs CPU per RHS call | status |")
    out("|---|---|---|---|---|---|---|---|---|")
    res = {}
    for _ in range(max(args.strip_repeats, 1)):
        for name in runs:
            ds, wall, cpu = one(name, T)
            res[name] = ds
            calls = ds.attrs["rhs_calls"]
            out(f"| {name} | {cpu:.1f} | {cpu / T:.3f} | {wall:.0f} | "
                f"{ds.attrs['step_s'] * 1e3:.3f} | {ds.attrs['rk4_steps']} "
                f"({ds.attrs['rk4_substepped']}) | {calls} | {1e6 * cpu / calls:.0f} | "
                f"{ds.attrs['status']} |")
    a, b = res["before"], res["after"]
    n = min(a.sizes["time"], b.sizes["time"])
    a, b = a.isel(time=slice(0, n)), b.isel(time=slice(0, n))
    t, dist = a["time"].values, a["distance"].values
    parts = [("all samples", np.ones(n, bool)),
             ("tangent (t >= 0.5 s, the first 300 m)", (t >= 0.5) & (dist <= 300.0)),
             ("curve (R 2500 m)", a["curvature"].values > 0.99 / 2500.0)]
    out("\nAfter against before, every wheel of the four wheelsets: rms difference [N] "
        "(/ static wheel load Q0; / rms of the before run):\n")
    out("| samples | n | Q | Y | Fx | Fy |")
    out("|---|---|---|---|---|---|")
    for label, sel in parts:
        if sel.sum() < 10:
            continue
        cells = []
        for v in ("Q", "Y", "longitudinal_force", "lateral_creep_force"):
            x, y = a[v].values[sel], b[v].values[sel]
            d = float(np.sqrt(np.nanmean((x - y) ** 2)))
            r = float(np.sqrt(np.nanmean(x ** 2)))
            cells.append(f"{d:.0f} ({100 * d / q0:.2f} %; {100 * d / r:.1f} %)")
        out(f"| {label} | {int(sel.sum())} | " + " | ".join(cells) + " |")
    for name, ds in res.items():
        yq = np.abs(ds["Y_over_Q"].values)
        out(f"\n{name}: max |Y/Q| {float(np.nanmax(yq)):.2f} (Nadal's limit "
            f"{ds.attrs['nadal_limit']:.2f}), 99.9th percentile "
            f"{float(np.nanpercentile(yq, 99.9)):.2f}")
    Path(args.out or HERE / "dynamics_online_strips.md").write_text("\n".join(lines) + "\n")
    return lines


if __name__ == "__main__":
    main()
