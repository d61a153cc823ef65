"""The ``railcontact`` command line tool."""

from __future__ import annotations

import argparse
import json
import logging
import sys
from pathlib import Path

from .core.checks import MAX_JOB_CASES, check_job_size, check_output, shown
from .core.errors import InputError, RailContactError
from .core.files import write_netcdf, write_text
from .core.parallel import check_scheduler

log = logging.getLogger("railcontact")


def _print_json(obj):
    sys.stdout.write(json.dumps(obj, allow_nan=False, default=float) + "\n")


def _print_table(result):
    head = f"{'side':>6} {'area mm2':>9} {'pmax MPa':>9} {'Fn kN':>8} {'Fx kN':>8} {'Fy kN':>8} " \
           f"{'Mz Nm':>8} {'angle deg':>9} {'r mm':>9}"
    print(head)
    import math
    for p in result["patches"]:
        print(f"{str(p['side']):>6} {p['area'] * 1e6:9.2f} {p['pmax'] / 1e6:9.1f} "
              f"{p['Fn'] / 1e3:8.3f} {p['Fx'] / 1e3:8.3f} {p['Fy'] / 1e3:8.3f} {p['Mz']:8.3f} "
              f"{math.degrees(p['contact_angle']):9.3f} "
              f"{(p['rolling_radius'] or float('nan')) * 1e3:9.3f}")


def _report_status(converged: bool, message: str, warnings, what: str = "") -> int:
    """Warnings and a missed convergence on stderr; the exit status (1: the result
    was written but is not a solution to its tolerance, or a wheel derailed)."""
    for w in warnings:
        print(f"railcontact: warning: {what}{w}", file=sys.stderr)
    if not converged:
        print(f"railcontact: not converged: {what}{message}", file=sys.stderr)
        return 1
    return 0


def _check_models(normal, tangential) -> None:
    """Model names given on the command line, known before any work."""
    if normal:
        from .normal import normal_model_class
        normal_model_class(normal)
    if tangential and str(tangential).lower() != "none":
        from .tangential import tangential_model_class
        tangential_model_class(tangential)


def _check_pairs(pairs) -> None:
    for normal, tangential in pairs:
        _check_models(normal, tangential)


def _is_inp(path: str) -> bool:
    return str(path).lower().endswith(".inp")


def _parse_cases(spec):
    """``--case 1,3-5`` -> [1, 3, 4, 5]."""
    if not spec:
        return None
    out = []
    try:
        for part in spec.split(","):
            lo, _, hi = part.partition("-")
            out += list(range(int(lo), int(hi or lo) + 1))
    except ValueError:
        raise InputError(f"--case {shown(spec)}: expected case numbers such as 1,3-5") from None
    return out


def _run_inp(args, scheduler: str, warm: bool = False) -> int:
    """``solve``/``sweep`` of a CONTACT input file: the per-patch table in CONTACT's
    units and frames (text, ``--json``, or ``--out`` .csv/.json)."""
    from .contact_inp import solve_inp, to_csv, to_json, to_text
    if getattr(args, "vary", None):
        raise InputError("--vary applies to case files (TOML); a CONTACT input file sweeps "
                         "over the cases it holds")
    out = Path(args.out) if args.out else None
    if out is not None and out.suffix.lower() not in (".csv", ".json"):
        raise InputError(f"--out {shown(args.out)}: expected a .csv or .json file for a CONTACT "
                         "input file")
    if out is not None:
        check_output(out)
    subs = Path(args.subsurface) if getattr(args, "subsurface", None) else None
    if subs is not None:
        if subs.suffix.lower() not in (".csv", ".nc"):
            raise InputError(f"--subsurface {shown(args.subsurface)}: expected a .csv or .nc "
                             "file")
        check_output(subs)
    _check_models(args.normal, args.tangential)
    table = solve_inp(args.case, cases=_parse_cases(args.cases), profile_dirs=args.profiles or (),
                      scheduler=scheduler, warm=warm, normal=args.normal,
                      tangential=args.tangential, subsurface=subs is not None,
                      progress=sys.stderr.isatty() and scheduler != "sync")
    blocks = [b for r in table for b in r.pop("subsurface", [])]
    if args.json:
        sys.stdout.write(to_json(table, args.case) + "\n")
    else:
        print(to_text(table))
    if subs is not None:
        _write_subsurface(subs, blocks, quiet=args.json)
    if out is not None:
        text = to_csv(table) if out.suffix.lower() == ".csv" else to_json(table, args.case)
        write_text(out, text + ("" if text.endswith("\n") else "\n"))
    status = 0
    seen = set()
    for r in table:
        if not r.get("converged", True) and r["case"] not in seen:
            seen.add(r["case"])
            status = _report_status(False, r.get("message", ""), [], f"case {r['case']}: ")
    return status


def _write_subsurface(path: Path, blocks: list, quiet: bool) -> None:
    """The subsurface stresses of a CONTACT input file's cases (S >= 1) to .csv or
    .nc, CONTACT's units (mm, N/mm^2); their maxima per block on the terminal."""
    from .contact_inp import subsurface as subs
    if path.suffix.lower() == ".csv":
        write_text(path, subs.to_csv(blocks))
    else:
        write_netcdf(subs.to_dataset(blocks), path)
    if not quiet:
        print(subs.maxima_text(blocks) if blocks else
              "no case of the file asks for subsurface stresses (STRESS S = 0)")


def cmd_solve(args):
    from .cases.case import load_case
    from .cases.solve import solve
    if _is_inp(args.case):
        return _run_inp(args, "sync")
    if args.cases or args.profiles:
        raise InputError("--case and --profiles apply to CONTACT input files (.inp)")
    if args.subsurface:
        raise InputError("--subsurface applies to CONTACT input files (.inp)")
    if args.out:
        check_output(args.out)
    _check_models(args.normal, args.tangential)
    case = load_case(args.case)
    log.info("solving %s", args.case)
    res = solve(case, args.normal, args.tangential)
    d = res.to_dict()
    if args.json:
        _print_json(d)
    else:
        _print_table(d)
    if args.out:
        write_netcdf(res.to_xarray(), args.out)
    return _report_status(d["converged"], d["message"], d["warnings"])


def cmd_geometry(args):
    from .cases.case import load_case
    from .cases.bodies import contact_search
    from .cases.results import geometry_dict
    case = load_case(args.case)
    if case.is_bodies:
        raise RailContactError("geometry needs a wheel-rail case ([wheel], [rail]); this case "
                               "gives [bodies]")
    d = geometry_dict(contact_search(case), case.wheel_rail.side)
    if args.json:
        _print_json(d)
    else:
        for p in d["patches"]:
            print(p)


def cmd_sweep(args):
    from .cases.case import load_case
    from .cases.sweep import parse_vary, sweep
    check_scheduler(args.scheduler, auto=True)
    if _is_inp(args.case):
        return _run_inp(args, args.scheduler, warm=args.warm)
    if not args.vary:
        raise InputError("sweep: give --vary KEY=START:STOP:STEP (a case file) or a CONTACT "
                         "input file (.inp)")
    if args.cases or args.profiles or args.out:
        raise InputError("--case, --profiles and --out apply to CONTACT input files (.inp)")
    if args.subsurface:
        raise InputError("--subsurface applies to CONTACT input files (.inp)")
    _check_models(args.normal, args.tangential)
    vary = dict(parse_vary(v, allow_large=args.allow_large) for v in args.vary)
    case = load_case(args.case)
    out = sweep(case, vary, args.normal, args.tangential, scheduler=args.scheduler,
                progress=not args.json or sys.stderr.isatty(), warm=args.warm,
                allow_large=args.allow_large)
    if args.json:
        _print_json(out)
    else:
        for c in out["cases"]:
            print(c["params"], c.get("error", ""))
            _print_table(c)
            if "error" not in c and not c["converged"]:
                print(f"  not converged: {c['message']}")
    solved = [c for c in out["cases"] if "error" not in c]
    bad = [c for c in solved if not c["converged"]]
    warned = sum(bool(c["warnings"]) for c in solved)
    if warned:
        print(f"railcontact: warning: {warned} of {len(solved)} cases have warnings (see "
              "'warnings' in the JSON)", file=sys.stderr)
    for c in bad:
        print(f"railcontact: not converged: {c['params']}: {c['message']}", file=sys.stderr)
    return 1 if bad else 0


def cmd_compare(args):
    from .cases.case import load_case
    from .cases.compare import DEFAULT_MODELS, compare, format_table, write_outputs
    models = tuple(m.strip() for m in args.models.split(",")) if args.models else DEFAULT_MODELS
    for m in models:
        _check_models(m, None)
    _check_models(None, args.tangential)
    if args.out:
        check_output(args.out, folder=True)
    case = load_case(args.case)
    rows, results = compare(case, models, args.tangential)
    if args.json:
        _print_json({"rows": rows})
    else:
        print(format_table(rows))
    if args.out:
        side = case.get("wheelset.side", "both")
        write_outputs(rows, results, Path(args.out), None if side == "both" else side)


def cmd_wear(args):
    from .inputs import load_wear_scenario
    from .wear.vehicle_scenario import VehicleWearScenario
    out = check_output(args.out, folder=True)
    if args.scheduler:
        check_scheduler(args.scheduler)
    _check_models(args.normal, args.tangential)
    sc = load_wear_scenario(args.scenario)
    if args.scheduler:
        sc.scheduler = args.scheduler
    sc = sc.with_models(args.normal, args.tangential)     # an unknown name fails here
    out.mkdir(parents=True, exist_ok=True)
    driver = sc.driver(out)
    ds = driver.run(resume=not args.restart)
    if isinstance(sc, VehicleWearScenario):               # closed loop: a vehicle on routes
        from .wear.plots import plot_closed_loop
        plot_closed_loop(ds, out)
        bad = int(ds["not_converged"].sum()) if "not_converged" in ds else 0
        print(f"{ds.sizes['step']} steps, {ds.attrs['total_distance_m'] / 1e3:.1f} km, "
              f"{sc.normal} + {sc.tangential}; wrote {out / 'wear.nc'}, wear.png, "
              f"measures.png" + (", rcf.png" if "rcf_damage_wheel" in ds else "")
              + (" and records/" if sc.records else ""))
        return _report_status(bad == 0, f"{bad} local solves did not converge (see "
                              "'not_converged' in wear.nc)", [])
    from .wear.plots import plot_wear
    plot_wear(ds, driver, out)
    print(f"{ds.sizes['step']} steps, {ds.attrs['total_distance_m'] / 1e3:.1f} km; wrote "
          f"{out / 'wear.nc'} and plots")


def cmd_wear_compare(args):
    from .inputs import load_wear_scenario
    from .wear.compare import (compare_wear, comparison_rows, format_rows, pairing_note,
                               parse_models)
    from .wear.vehicle_scenario import VehicleWearScenario
    check_output(args.out, folder=True)
    if args.scheduler:
        check_scheduler(args.scheduler)
    if args.models:
        _check_pairs(parse_models(args.models))
    sc = load_wear_scenario(args.scenario)
    if args.scheduler:
        sc.scheduler = args.scheduler
    closed = isinstance(sc, VehicleWearScenario)
    spec = args.models or ("hertz+fastsim,kik-piotrowski+fastsim,stripes+fastsim,"
                           "analyn+fastsim,exact+exact" if closed else
                           "hertz+fastsim,kpec+fastsim,analyn+fastsim")
    pairs = parse_models(spec)
    _check_pairs(pairs)
    res = compare_wear(sc, pairs, Path(args.out))
    print(pairing_note(pairs))
    print(format_rows(comparison_rows(res)))
    print(f"wrote {Path(args.out) / 'wear_comparison.png'} and wear_comparison.csv")


def cmd_simulate(args):
    from .inputs import load_dynamics_scenario
    check_output(args.out, folder=True)
    if len(args.scenario) > 1:
        check_scheduler(args.scheduler)
        from .dynamics.scenario import simulate_batch
        outs = [Path(args.out) / Path(s).stem for s in args.scenario]
        if len(set(outs)) != len(outs):
            raise InputError("simulate: scenario files with the same name would share an "
                             "output folder; rename them")
        # every scenario is read and checked before any runs
        scenarios = {str(s): load_dynamics_scenario(s) for s in args.scenario}
        from .dynamics.roller_rig import RigScenario
        rigs = [n for n, sc in scenarios.items() if isinstance(sc, RigScenario)]
        if rigs:
            raise InputError(f"simulate: roller-rig scenarios {rigs} run one at a time")
        res = simulate_batch(scenarios, outs, scheduler=args.scheduler)
        for r in res:
            if "error" in r:
                print(f"{r['scenario']}: FAILED: {r['error']}")
            else:
                print(f"{r['scenario']}: {r['duration_s']:.2f} s simulated in "
                      f"{r['wall_time_s']:.1f} s; wrote {r['out']}/simulation.nc")
        if any("error" in r for r in res):
            raise SystemExit(1)
        return
    from .dynamics.roller_rig import RigScenario, run_rig_scenario
    from .dynamics.scenario import run_scenario
    sc = load_dynamics_scenario(args.scenario[0])
    if isinstance(sc, RigScenario):
        ds = run_rig_scenario(sc, args.out)
        print(f"{ds.attrs['run']} of the {ds.attrs['model']}: {float(ds['time'][-1]):.2f} s in "
              f"{ds.attrs['wall_time_s']:.1f} s ({ds.attrs['tangential']}); linear critical "
              f"speed {ds.attrs['critical_speed_m_s']:.1f} m/s on the rig, "
              f"{ds.attrs['track_critical_speed_m_s']:.1f} m/s on tangent track; wrote "
              f"{Path(args.out) / 'simulation.nc'} and rig_forces.png")
        return 0
    ds = run_scenario(sc, args.out)
    vc = ds.attrs['critical_speed_m_s']
    speed = (f"linear critical speed {vc:.1f} m/s" if ds.attrs.get("contact_mode") != "online"
             else "contact online (no table, no linear critical speed)")
    print(f"simulated {float(ds['time'][-1]):.2f} s of {ds.attrs['model']} in "
          f"{ds.attrs['wall_time_s']:.1f} s ({ds.attrs['tangential']}); {speed}; wrote "
          f"{Path(args.out) / 'simulation.nc'}")
    warnings = [w for w in ds.attrs.get("warnings", "").split("; ") if w]
    return _report_status(True, "", warnings)


def cmd_profile(args):
    from .profiles import get_profile, write_profile
    from .core.plotting import plot_profile
    kind = args.kind
    if args.out:
        check_output(args.out)
    prof = get_profile(args.profile, kind, inclination=args.inclination)
    if args.action == "plot":
        path = plot_profile(prof, args.out or f"{prof.name}.png")
    else:
        if not args.out:
            raise RailContactError("profile export needs --out FILE (.csv, .txt, .prr or .prw)")
        path = write_profile(prof, args.out, units=args.units)
    print(path)


def cmd_track(args):
    """A quasi-static pass along the track of a case on rail surfaces."""
    import numpy as np
    from .cases.case import load_case
    from .cases.crossing import plot_track_sweep, sweep_along_track
    if not (args.step > 0 and args.stop >= args.start):
        raise InputError(f"track: --from {args.start} --to {args.stop} --step {args.step}: "
                         "expected start <= stop and a step > 0 (m)")
    if not all(np.isfinite([args.start, args.stop, args.step])):
        raise InputError(f"track: --from {args.start} --to {args.stop} --step {args.step}: "
                         "expected finite lengths (m)")
    count = int((args.stop - args.start) / args.step + 1e-9) + 1
    check_job_size(count, f"track --from {args.start:g} --to {args.stop:g} --step "
                   f"{args.step:g}", allow_large=args.allow_large, seconds_each=0.5)
    out = check_output(args.out, folder=True)
    _check_models(args.normal, args.tangential)
    positions = np.arange(args.start, args.stop + 0.5 * args.step, args.step)
    ds = sweep_along_track(load_case(args.case), positions, args.normal, args.tangential,
                           progress=True)
    out.mkdir(parents=True, exist_ok=True)
    write_netcdf(ds, out / "track_sweep.nc")
    plot_track_sweep(ds, out / "track_sweep.png")
    print(f"{ds.sizes['s']} positions, rails {', '.join(map(str, ds['rail'].values))}; wrote "
          f"{out / 'track_sweep.nc'} and track_sweep.png")
    return 0 if bool(ds["converged"].all()) else _report_status(
        False, "the vertical load was not met at some positions (see 'converged')", [])


def cmd_fmu(args):
    """Write the contact element's FMI 3.0 co-simulation FMU."""
    try:
        from .fmu import build_fmu
    except ImportError as exc:
        raise InputError(f"fmu: {exc}; install the 'fmu' extra (pip install "
                         "'railcontact[fmu]')") from None
    out = Path(args.out)
    if not out.is_dir():
        check_output(out)
    params = {"mode": args.mode}
    for key, value in (("case_file", args.case), ("wheel_profile", args.wheel),
                       ("rail_profile", args.rail), ("normal_model", args.normal),
                       ("tangential_model", args.tangential), ("friction", args.friction)):
        if value is not None:
            params[key] = value
    path = build_fmu(args.out, params)
    print(f"wrote {path} (FMI 3.0 co-simulation; variables: docs/multibody.md)")


def cmd_demo(args):
    from .demo import run_demo
    run_demo(check_output(args.out, folder=True))


def _inp_arguments(p):
    p.add_argument("--case", dest="cases", metavar="N[,M-K]",
                   help=".inp: solve these cases only (numbered from 1 in file order)")
    p.add_argument("--profiles", action="append", metavar="DIR",
                   help=".inp: another folder with the profile files it names")
    p.add_argument("--subsurface", metavar="FILE",
                   help=".inp: write the subsurface stresses of the cases with STRESS "
                        "S >= 1 to FILE (.csv or .nc; mm, N/mm^2)")


def build_parser():
    p = argparse.ArgumentParser(prog="railcontact",
                                description="Wheel-rail rolling contact (SI units).")
    p.add_argument("-v", "--verbose", action="store_true", help="log progress details")
    sub = p.add_subparsers(dest="command", required=True)
    s = sub.add_parser("solve", help="solve one contact case, or the cases of a CONTACT "
                       "input file one after the other")
    s.add_argument("case", help="case file (TOML) or CONTACT input file (.inp)")
    s.add_argument("--json", action="store_true", help="print the JSON result contract (.inp: "
                   "the per-patch table in CONTACT's units)")
    s.add_argument("--normal", help="normal model (overrides [solver] or the .inp's)")
    s.add_argument("--tangential", help="tangential model (overrides [solver]); 'none' to skip")
    s.add_argument("--out", help="also write the patch results to NetCDF (.inp: the table to "
                   ".csv or .json)")
    _inp_arguments(s)
    s.set_defaults(func=cmd_solve)
    g = sub.add_parser("geometry", help="contact points from the geometry layer only")
    g.add_argument("case")
    g.add_argument("--json", action="store_true")
    g.set_defaults(func=cmd_geometry)
    w = sub.add_parser("sweep", help="solve every combination of varied case keys, or the "
                       "cases of a CONTACT input file, in parallel")
    w.add_argument("case", help="case file (TOML) or CONTACT input file (.inp)")
    w.add_argument("--vary", action="append", metavar="KEY=START:STOP:STEP")
    w.add_argument("--out", help=".inp: write the per-patch table to .csv or .json")
    _inp_arguments(w)
    w.add_argument("--json", action="store_true")
    w.add_argument("--normal")
    w.add_argument("--tangential")
    w.add_argument("--scheduler", default="auto",
                   help="sync, threads, processes, auto, or a Dask scheduler address")
    w.add_argument("--allow-large", action="store_true",
                   help=f"run a sweep of more than {MAX_JOB_CASES} cases")
    w.add_argument("--warm", action="store_true",
                   help="solve neighbouring cases in chains, each warm-started from the "
                        "previous solution (exact solvers)")
    w.set_defaults(func=cmd_sweep)
    c = sub.add_parser("compare", help="run several normal models on one case")
    c.add_argument("case")
    c.add_argument("--models", help="comma-separated normal models (default: all)")
    c.add_argument("--tangential", help="tangential model (default: the case's)")
    c.add_argument("--out", help="directory for comparison.csv and plots")
    c.add_argument("--json", action="store_true")
    c.set_defaults(func=cmd_compare)
    wr = sub.add_parser("wear", help="wear simulation of a scenario (profile evolution)")
    wr.add_argument("scenario", help="wear scenario (TOML)")
    wr.add_argument("--out", default="wear_output")
    wr.add_argument("--restart", action="store_true", help="ignore an existing checkpoint")
    wr.add_argument("--scheduler", help="sync, threads, processes or a Dask scheduler address")
    wr.add_argument("--normal", help="local normal model (overrides [solver])")
    wr.add_argument("--tangential", help="local tangential model (overrides [solver])")
    wr.set_defaults(func=cmd_wear)
    wc = sub.add_parser("wear-compare", help="one wear scenario with several contact models")
    wc.add_argument("scenario")
    wc.add_argument("--models", help="NORMAL+TANGENTIAL pairs, comma separated (default: "
                    "hertz+fastsim,kik-piotrowski+fastsim,stripes+fastsim,analyn+fastsim,"
                    "exact+exact for a vehicle scenario; hertz+fastsim,kpec+fastsim,"
                    "analyn+fastsim otherwise)")
    wc.add_argument("--scheduler", help="sync, threads, processes or a Dask scheduler address")
    wc.add_argument("--out", default="wear_comparison")
    wc.set_defaults(func=cmd_wear_compare)
    sm = sub.add_parser("simulate", help="vehicle dynamics: wheelset, bogie or vehicle on a "
                        "track, or a wheelset or bogie on a roller rig ([roller_rig]); "
                        "several track scenarios: one Dask batch")
    sm.add_argument("scenario", nargs="+")
    sm.add_argument("--out", default="simulation_output",
                    help="output folder (one sub-folder per scenario for a batch)")
    sm.add_argument("--scheduler", default="processes",
                    help="batch: processes, threads, synchronous or tcp://host:port")
    sm.set_defaults(func=cmd_simulate)
    pr = sub.add_parser("profile", help="plot or export a built-in or file profile")
    pr.add_argument("action", choices=["plot", "export"])
    pr.add_argument("profile", help="built-in name (S1002, 60E1, 54E1, 60E2) or file")
    pr.add_argument("--kind", choices=["wheel", "rail"], default=None)
    pr.add_argument("--inclination", type=float, default=None, help="rail inclination [rad]")
    pr.add_argument("--units", choices=["mm", "m"], default="mm", help="units of exported files")
    pr.add_argument("--out")
    pr.set_defaults(func=cmd_profile)
    t = sub.add_parser("track", help="a wheel passing along rails given by slices (a "
                       "crossing): force on each rail, contact positions, p_max, area vs s")
    t.add_argument("case", help="case file on rail surfaces (rail.slices or [[rails]])")
    t.add_argument("--from", dest="start", type=float, required=True, help="first s [m]")
    t.add_argument("--to", dest="stop", type=float, required=True, help="last s [m]")
    t.add_argument("--step", type=float, required=True, help="step of s [m]")
    t.add_argument("--normal")
    t.add_argument("--tangential")
    t.add_argument("--out", default="track_output")
    t.add_argument("--allow-large", action="store_true",
                   help=f"run more than {MAX_JOB_CASES} positions")
    t.set_defaults(func=cmd_track)
    f = sub.add_parser("fmu", help="write the wheel-rail contact element as an FMI 3.0 "
                       "co-simulation FMU for multibody tools (docs/multibody.md)")
    f.add_argument("--out", default="RailContactElement.fmu",
                   help="the .fmu file to write, or a folder")
    f.add_argument("--case", help="wheel-rail case file (TOML) giving profiles, dimensions, "
                   "material, friction and solver")
    f.add_argument("--wheel", help="wheel profile: built-in name or file (default S1002)")
    f.add_argument("--rail", help="rail profile: built-in name or file (default 60E1)")
    f.add_argument("--normal", help="normal model (default hertz)")
    f.add_argument("--tangential", help="tangential model (default fastsim)")
    f.add_argument("--friction", type=float, help="friction coefficient (default 0.3)")
    f.add_argument("--mode", choices=["position", "load"], default="position",
                   help="position: vertical position and roll are inputs (elastic contact); "
                        "load: the wheel loads are inputs")
    f.set_defaults(func=cmd_fmu)
    d = sub.add_parser("demo", help="lateral-shift sweep S1002 on 60E1 1:40 (Hertz + FASTSIM)")
    d.add_argument("--out", default="demo_output")
    d.set_defaults(func=cmd_demo)
    return p


class _Format(logging.Formatter):
    """Log records on stderr in the one format of the command's messages:
    ``railcontact: warning: ...`` (``info``, ``debug`` with --verbose)."""

    def format(self, record):
        return f"railcontact: {record.levelname.lower()}: {record.getMessage()}"


def main(argv=None) -> int:
    """Run the command line ``argv`` in this process; returns the exit status (0 done,
    1 a result written that is not a solution or has a derailed wheel, 2 a bad input,
    130 interrupted)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(_Format())
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING,
                        handlers=[handler], force=True)
    if getattr(args, "kind", "x") is None:
        from .profiles.library import RAIL_PROFILES
        args.kind = "rail" if args.profile.upper() in RAIL_PROFILES or \
            args.profile.lower().endswith((".prr", ".ban")) else "wheel"
    try:
        status = args.func(args)
    except RailContactError as exc:
        print(f"railcontact: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("railcontact: interrupted", file=sys.stderr)
        return 130
    except OSError as exc:                   # the machine's: a full disk, a lost folder
        print(f"railcontact: error: {exc}", file=sys.stderr)
        return 2
    except Exception as exc:
        if not _interrupted(exc):
            raise
        # Ctrl-C inside a compiled function: Numba's dispatcher returns with the
        # KeyboardInterrupt set and Python raises a SystemError from it
        print("railcontact: interrupted", file=sys.stderr)
        return 130
    return int(status or 0)


def _interrupted(exc: BaseException) -> bool:
    """Whether a KeyboardInterrupt is in the chain of ``exc`` (its causes and
    contexts)."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return False


#: seconds the command is given to stop by itself after Ctrl-C before it is ended
INTERRUPT_GRACE = 0.3


def console_main() -> None:
    """The ``railcontact`` console script: :func:`main` in a child process that the
    parent ends within a second of Ctrl-C (SIGINT) or SIGTERM, so that a command
    stops even inside a compiled loop that does not look at signals; exit status
    130 then.  Every file is written whole (:mod:`railcontact.core.files`), so an
    ended command leaves no half-written output.  Where ``os.fork`` is missing the
    command runs in this process."""
    import os
    import signal
    import time
    signal.signal(signal.SIGINT, signal.default_int_handler)     # KeyboardInterrupt again
    if not hasattr(os, "fork") or os.environ.get("RAILCONTACT_NO_FORK"):
        sys.exit(main())
    sys.stdout.flush()
    sys.stderr.flush()
    pid = os.fork()
    if pid == 0:                                             # the child runs the command
        try:
            code = main()
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        except KeyboardInterrupt:
            print("railcontact: interrupted", file=sys.stderr)
            code = 130
        except BaseException:                                # a bug: its traceback
            import traceback
            traceback.print_exc()
            code = 1
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)

    def stop(signum, frame):
        raise KeyboardInterrupt

    signal.signal(signal.SIGINT, stop)
    signal.signal(signal.SIGTERM, stop)
    try:
        _, status = os.waitpid(pid, 0)
    except KeyboardInterrupt:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
        try:
            os.kill(pid, signal.SIGINT)                  # its own 'interrupted' line
        except ProcessLookupError:
            pass
        end = time.monotonic() + INTERRUPT_GRACE
        while time.monotonic() < end:
            if os.waitpid(pid, os.WNOHANG)[0]:
                break
            time.sleep(0.01)
        else:                                            # deaf to signals: ended
            os.kill(pid, signal.SIGKILL)
            print("railcontact: interrupted", file=sys.stderr)
        sys.stderr.flush()
        os._exit(130)                        # no clean-up of this process's imports
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(128 + os.WTERMSIG(status) if os.WIFSIGNALED(status) else os.WEXITSTATUS(status))


if __name__ == "__main__":
    console_main()
