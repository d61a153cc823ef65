"""Before and after, interleaved in one process: the package at a git ref (``OLD``,
extracted as ``railcontact_old``) against this checkout, on the dynamics demo
(rk4 and LSODA, FASTSIM and Polach), Polonsky-Keer (force-controlled, the plastic
cap, two regions), FASTSIM, FaStrip and the exact tangential solver on an exact
pressure, and the contact search; CPU time of the calling thread (the machine may be
shared), medians and minima over REPS alternating runs, and whether the results are
bit-identical (else their largest relative difference).

    .venv/bin/python benchmarks/compare_builds.py OLD [REPS]

e.g. ``compare_builds.py 03fff67 7`` for issue 29's named kernel inputs.
"""
import importlib
import math
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
OLD = sys.argv[1] if len(sys.argv) > 1 else "HEAD"
REPS = int(sys.argv[2]) if len(sys.argv) > 2 else 5
_tmp = tempfile.TemporaryDirectory(prefix="railcontact_old_")
subprocess.run(f"git -C {ROOT} archive {OLD} railcontact | tar -x -C {_tmp.name}", shell=True,
               check=True)
(Path(_tmp.name) / "railcontact").rename(Path(_tmp.name) / "railcontact_old")
sys.path.insert(0, _tmp.name)

PKGS = ("railcontact_old", "railcontact")
DEMO = str(ROOT / "examples" / "dynamics_demo.toml")


def mod(pkg, name):
    return importlib.import_module(f"{pkg}.{name}")


class _Scenario:
    """A dynamics scenario of either build: a dict (before issue 29's typed
    configuration) or a DynamicsScenario, read by attribute."""

    def __init__(self, pkg):
        try:
            sc = mod(pkg, "inputs").load_dynamics_scenario(DEMO)
            self.sc, self.typed = sc, True
            self.wheelset_track = (sc.wheelset, sc.track)
        except ModuleNotFoundError:
            sc = mod(pkg, "dynamics.scenario").load_simulation(DEMO)
            self.sc, self.typed = sc, False
            self.wheelset_track = mod(pkg, "cases.bodies").build_wheelset_track(sc["case"])
        self.table = mod(pkg, "dynamics.scenario").build_table(sc)

    def __getattr__(self, key):
        sc = self.__dict__["sc"]
        if self.__dict__["typed"]:
            return getattr(sc, key)
        if key in ("friction", "material"):
            return getattr(sc["case"], key)
        return sc[key]


def sim_call(pkg, sc, table, duration, integrator, tangential=None):
    sim = mod(pkg, "dynamics.simulation")
    tangential = tangential or sc.tangential
    if hasattr(sim, "Integration"):
        integ = sim.Integration(method=integrator, sample_rate=sc.sample_rate, rtol=sc.rtol,
                                step=sc.step)
        return sim.simulate_vehicle(sc.model, sc.route, table, sc.velocity, duration,
                                    tangential, sc.friction, sc.material,
                                    sc.initial_lateral_shift, sc.tangential_options,
                                    sc.fastsim_grid, integ)
    return sim.simulate_vehicle(sc.model, sc.route, table, sc.velocity, duration,
                                tangential, sc.friction, sc.material,
                                sc.initial_lateral_shift, sc.sample_rate, sc.rtol, False,
                                sc.tangential_options, sc.fastsim_grid,
                                integrator=integrator, step=sc.step)


def sphere(pkg, n):
    mat = mod(pkg, "core.materials").Material(2.1e11, 0.28)
    E = mat.contact_modulus
    R, F = 0.3, 1e4
    a = (3 * F * R / (4 * E)) ** (1 / 3)
    x = np.linspace(-1.5 * a, 1.5 * a, n)
    dx = x[1] - x[0]
    X, Y = np.meshgrid(x, x, indexing="ij")
    h = (X ** 2 + Y ** 2) / (2 * R)
    op = mod(pkg, "normal.influence").normal_operator(n, n, dx, dx, E)
    return a, dx, h, op, F, R


def tangential_setup(pkg):
    geo = mod(pkg, "geometry.contact").ContactGeometry(curvatures=(2.0, 8.0))
    steel = mod(pkg, "core.materials").STEEL
    ns = mod(pkg, "normal").get_normal_model("exact").solve(geo, steel, normal_force=80e3,
                                                            grid=(60, 60))
    tm = mod(pkg, "tangential")
    return geo, steel, ns, tm.get_tangential_model("fastsim"), tm.get_tangential_model("exact"), \
        tm.get_tangential_model("fastrip")


state = {}
for pkg in PKGS:
    sc = _Scenario(pkg)
    table = sc.table
    state[pkg] = dict(sc=sc, table=table, sph=sphere(pkg, 101), pk=mod(pkg, "normal.polonsky_keer"),
                      tang=tangential_setup(pkg), wt=sc.wheelset_track,
                      search=mod(pkg, "geometry.search"))
    # warm-up: compile / load the caches
    sim_call(pkg, sc, table, 0.2, "rk4")
    sim_call(pkg, sc, table, 0.05, "lsoda")
    a, dx, h, op, F, R = state[pkg]["sph"]
    state[pkg]["pk"].polonsky_keer(op, h, dx * dx, force=F)


def job_rk4(pkg):
    s = state[pkg]
    return sim_call(pkg, s["sc"], s["table"], s["sc"].duration, "rk4")


def job_lsoda(pkg):
    s = state[pkg]
    return sim_call(pkg, s["sc"], s["table"], 0.5, "lsoda")


def job_pk_force(pkg):
    a, dx, h, op, F, R = state[pkg]["sph"]
    return state[pkg]["pk"].polonsky_keer(op, h, dx * dx, force=F, tol=1e-10)


def job_pk_plastic(pkg):
    a, dx, h, op, F, R = state[pkg]["sph"]
    p0 = 3 * F / (2 * math.pi * a * a)
    return state[pkg]["pk"].polonsky_keer(op, h - a * a / R, dx * dx, pressure_limit=0.8 * p0,
                                         tol=1e-10)


def job_pk_regions(pkg):
    a, dx, h, op, F, R = state[pkg]["sph"]
    n = h.shape[1]
    cols = (np.arange(n) >= n // 2).astype(np.int64)
    fm = np.array([[1.0, 0.7], [0.7, 1.0]])
    return state[pkg]["pk"].polonsky_keer(op, h, dx * dx, force=F, tol=1e-10, regions=(cols, fm))


CREEP = (-1e-3, 5e-4, 0.1)


def job_fastsim(pkg):
    geo, steel, ns, fs, te, fr = state[pkg]["tang"]
    return [fs.solve(ns, geo, steel, CREEP, 0.3, 30.0).fx for _ in range(20)]


def job_fastrip(pkg):
    geo, steel, ns, fs, te, fr = state[pkg]["tang"]
    return [fr.solve(ns, geo, steel, CREEP, 0.3, 30.0).fx for _ in range(20)]


def job_exact_tangential(pkg):
    geo, steel, ns, fs, te, fr = state[pkg]["tang"]
    t = te.solve(ns, geo, steel, CREEP, 0.3, 30.0)
    return t.traction_x, t.traction_y


def job_find_contact(pkg):
    ws, tr = state[pkg]["wt"]
    out = []
    for y in np.linspace(-8e-3, 8e-3, 9):
        c = state[pkg]["search"].find_contact(ws, tr, float(y), 0.0, vertical_force=60e3)
        out.extend([p.approach for p in c.patches])
    return out


def job_rk4_polach(pkg):
    s = state[pkg]
    return sim_call(pkg, s["sc"], s["table"], 5.0, "rk4", "polach")


JOBS = {"dynamics demo rk4 fastsim 15 s": job_rk4, "dynamics demo lsoda fastsim 0.5 s": job_lsoda,
        "PK 101x101 force-controlled": job_pk_force, "PK 101x101 plastic cap": job_pk_plastic,
        "PK 101x101 two regions": job_pk_regions,
        "dynamics demo rk4 polach 5 s": job_rk4_polach,
        "FASTSIM on exact p 60x60 (x20)": job_fastsim, "FaStrip on exact p 60x60 (x20)": job_fastrip,
        "exact tangential 60x60": job_exact_tangential,
        "find_contact S1002/60E1, 9 shifts": job_find_contact}
for name, job in JOBS.items():
    if job not in (job_rk4, job_lsoda, job_rk4_polach):
        for pkg in PKGS:
            job(pkg)
for pkg in PKGS:
    sim_call(pkg, state[pkg]["sc"], state[pkg]["table"], 0.2, "rk4", "polach")
times = {(j, p): [] for j in JOBS for p in PKGS}
results = {}
for rep in range(REPS):
    for name, job in JOBS.items():
        order = PKGS if rep % 2 == 0 else PKGS[::-1]
        for pkg in order:
            t0 = time.thread_time()          # CPU time: the machine is shared
            r = job(pkg)
            times[name, pkg].append(time.thread_time() - t0)
            results[name, pkg] = r


def same(a, b):
    if hasattr(a, "data_vars"):
        return all(np.array_equal(a[v].values, b[v].values, equal_nan=True) for v in a.data_vars) \
            and set(a.data_vars) == set(b.data_vars)
    return all(np.array_equal(np.asarray(x), np.asarray(y)) for x, y in zip(a, b)) and len(a) == len(b)


def maxrel(a, b):
    if hasattr(a, "data_vars"):
        return max(float(np.nanmax(np.abs(a[v].values - b[v].values)) /
                         max(float(np.nanmax(np.abs(a[v].values))), 1e-300))
                   for v in a.data_vars if a[v].dtype.kind == "f" and np.isfinite(a[v].values).any())
    return max(float(np.max(np.abs(np.asarray(x, float) - np.asarray(y, float))) /
                     max(float(np.max(np.abs(np.asarray(x, float)))), 1e-300)) for x, y in zip(a, b))


print(f"{'job':36s} {'old med CPU [s]':>14s} {'new med CPU [s]':>14s} {'new/old':>8s}  "
      f"{'old min':>8s} {'new min':>8s}  bit-identical")
for name in JOBS:
    o, n = times[name, PKGS[0]], times[name, PKGS[1]]
    print(f"{name:36s} {statistics.median(o):14.4f} {statistics.median(n):14.4f} "
          f"{statistics.median(n) / statistics.median(o):8.3f}  {min(o):8.4f} {min(n):8.4f}  "
          f"{same(results[name, PKGS[0]], results[name, PKGS[1]])} "
          f"(max rel. diff {maxrel(results[name, PKGS[0]], results[name, PKGS[1]]):.1e})")
