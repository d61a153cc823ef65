"""Closed-loop wear: the vehicle runs on its worn profiles at every step.

Each wear step of a :class:`~railcontact.wear.vehicle_scenario.VehicleWearScenario`:

1. the contact tables of every wheelset on every route's rails are built from the
   current (worn) profiles (:meth:`WheelRailTable.build`, keeping the patches'
   geometry), one per distinct pair of wheel and rail profiles;
2. every route is simulated (:func:`railcontact.dynamics.simulate_vehicle`); the
   routes run in parallel as one Dask graph with the tables (``wear.scheduler``:
   ``"threads"``, ``"processes"``, ``"sync"`` or a ``dask.distributed`` address);
3. each run is post-processed with the local contact model of ``[solver]``
   (:class:`~railcontact.wear.postprocess.PatchPostProcessor`): per wheel and patch,
   its position, load, creepages and contact geometry, solved force-controlled;
4. the wear per metre of every wheel is the routes' weighted mean; the wheels are
   worn individually, per side or averaged over the vehicle (``wear.wheels``);
   each route's rails wear by the vehicle's passages over them;
5. the step distance is fixed or chosen so that the largest depth is
   ``max_depth_per_step``; the depth is smoothed (Gaussian, area conserved) and the
   profiles move along their inward normals; the next step runs on them.

Results go to ``wear.nc`` after every step (see ``docs/wear.md``), with a checkpoint
from which an interrupted run resumes; with ``wear.records = true``, ``records/``
holds per step and route the post-processed samples (the dynamics' inputs and the
local model's results per patch).
"""

from __future__ import annotations

import json
import logging
import math
import re
import sys
import time
from pathlib import Path

import numpy as np

from ..cases.bodies import build_wheelset_track
from ..dynamics.vehicle import G_ACC
from ..core.errors import InputError, RailContactError
from ..core.files import write_netcdf, written_whole
from ..geometry.tables import equivalent_conicity
from ..profiles.measures import wheel_measures
from ..profiles.profile import Profile
from ..core.parallel import compute
from ..core.progress import TqdmCallback
from .mapping import arc_length_grid, removed_area, smooth_depth, wear_profile
from .rcf import accumulate
from .route_tasks import build_table, run_route

log = logging.getLogger(__name__)

SIDES = ("left", "right")
#: amplitude of the equivalent conicity (EN 15302's usual 3 mm) [m]
CONICITY_AMPLITUDE = 3e-3


class ClosedLoopWear:
    """Run a closed-loop wear scenario step by step (see the module docstring).

    Parameters
    ----------
    scenario : VehicleWearScenario
    out_dir : path, optional
        Folder for ``wear.nc``, ``checkpoint.npz`` and ``records/`` (``wear.records``).
    progress : bool
        Progress bars over the steps and the routes.
    """

    def __init__(self, scenario, out_dir=None, progress: bool = True):
        self.sc = scenario
        self.out = Path(out_dir) if out_dir else None
        self.progress = progress
        case = scenario.case
        ws, tr = build_wheelset_track(case)
        self.nw = len(scenario.model.wheelsets)
        self.nr = len(scenario.routes)
        self.rail_offsets = {s: tr.rail_offset(s) for s in SIDES}
        self.settings = {"nominal_radius": ws.nominal_radius,
                         "flange_back_distance": ws.flange_back_distance,
                         "flange_back_position": ws.flange_back_position,
                         "gauge": tr.gauge, "gauge_height": tr.gauge_height,
                         "reference_load": scenario.model.wheelsets[0][1] * G_ACC / 2,
                         "material": case.material,
                         "table_range": scenario.dynamics["table_range"],
                         "table_step": scenario.dynamics["table_step"]}
        self.initial_wheels = (ws.wheel_left, ws.wheel_right)
        self.initial_rails = (tr.rail_left, tr.rail_right)
        self.wheels = [[ws.wheel_left, ws.wheel_right] for _ in range(self.nw)]
        if scenario.wheels == "vehicle":          # one profile for every wheel
            self.wheels = [[ws.wheel_right, ws.wheel_right] for _ in range(self.nw)]
        self.rails = [[tr.rail_left, tr.rail_right] for _ in range(self.nr)]
        step = scenario.grid_step
        self.y_wheel = np.arange(min(p.y_min for p in self.initial_wheels),
                                 max(p.y_max for p in self.initial_wheels) + step / 2, step)
        self.y_rail = np.arange(min(p.y_min for p in self.initial_rails),
                                max(p.y_max for p in self.initial_rails) + step / 2, step)
        w = np.array([r.weight for r in scenario.routes], dtype=float)
        self.weights = w / w.sum()
        self.steps: list = []        # per step: dict of arrays
        self.states: list = []       # per state (0 = new profiles): dict of arrays
        self.step = 0
        self.distance = 0.0
        self.cpu_time = 0.0

    # ------------------------------------------------------------ profiles
    def wheel_groups(self) -> list:
        """Lists of (wheelset, side) that share one worn profile."""
        pairs = [(w, j) for w in range(self.nw) for j in range(2)]
        if self.sc.wheels == "vehicle":
            return [pairs]
        if self.sc.wheels == "side":
            return [[p for p in pairs if p[1] == j] for j in range(2)]
        return [[p] for p in pairs]

    def _worn(self, kind: str) -> bool:
        return self.sc.body in (kind, "both")

    # ------------------------------------------------------------ one step
    def _table_tasks(self):
        """Dask tasks of the contact tables of the current profiles, one per distinct
        (wheel pair, rail pair), and each route's list of task indices per wheelset."""
        import dask
        ids: dict = {}
        tasks, rows = [], []
        for r in range(self.nr):
            row = []
            for w in range(self.nw):
                key = (id(self.wheels[w][0]), id(self.wheels[w][1]), id(self.rails[r][0]),
                       id(self.rails[r][1]))
                if key not in ids:
                    ids[key] = len(tasks)
                    tasks.append(dask.delayed(build_table)(
                        self.wheels[w][0], self.wheels[w][1], self.rails[r][0],
                        self.rails[r][1], self.rail_offsets, self.settings))
                row.append(ids[key])
            rows.append(row)
        return tasks, rows

    def _compute(self, grid_of):
        """Tables and route runs of the current profiles as one Dask graph; returns
        (tables per route and wheelset, route results)."""
        import dask
        sc = self.sc
        tasks, rows = self._table_tasks()
        case = sc.case
        post = {"normal": case.normal, "tangential": case.tangential, "law": sc.law,
                "parameters": sc.parameters, "grid": case.grid,
                "element_size": case.element_size, "normal_options": case.normal_options,
                "tangential_options": case.tangential_options,
                "reuse_tolerance": sc.reuse_tolerance, "sample_distance": sc.sample_distance,
                "rcf": sc.rcf}
        wheel_grids = [[grid_of[id(p)] for p in pair] for pair in self.wheels]
        runs = [dask.delayed(run_route, name=f"run_route-{self.step}-{r}")(
                    item, sc.model, [tasks[i] for i in rows[r]], sc.dynamics, case.material,
                    self.wheels, self.rails[r], wheel_grids,
                    [grid_of[id(p)] for p in self.rails[r]], post)
                for r, item in enumerate(sc.routes)]
        bar = TqdmCallback(self.nr, f"step {self.step + 1}: routes", prefix="run_route",
                           unit="route", leave=False, disable=not self.progress)
        out = compute(tasks + runs, sc.scheduler, bar, "wear.scheduler")
        return [[out[i] for i in row] for row in rows], out[len(tasks):]

    def _state(self, tables) -> dict:
        """Measures of the current profiles: profile heights, flange height, flange
        thickness, qR, Δr(y) and the equivalent conicity per route and wheelset."""
        import xarray as xr
        rec = {"profile_z_wheel": np.array([[p.z_at(self.y_wheel) for p in pair]
                                            for pair in self.wheels]),
               "profile_z_rail": np.array([[p.z_at(self.y_rail) for p in pair]
                                           for pair in self.rails]),
               "cumulative_distance": self.distance}
        keys = ("flange_height", "flange_thickness", "qR")
        for key in keys:
            rec[key] = np.full((self.nw, 2), np.nan)
        meas: dict = {}
        for w in range(self.nw):
            for j in range(2):
                p = self.wheels[w][j]
                if id(p) not in meas:
                    try:
                        meas[id(p)] = wheel_measures(p)
                    except InputError as exc:
                        log.warning("wheel measures of wheelset %d, %s: %s", w + 1, SIDES[j],
                                    exc)
                        meas[id(p)] = {}
                for key in keys:
                    rec[key][w, j] = meas[id(p)].get(key, np.nan)
        rec["delta_r"] = np.array([[t.delta_r for t in row] for row in tables])
        rec["equivalent_conicity"] = np.full((self.nr, self.nw), np.nan)
        done: dict = {}
        for r, row in enumerate(tables):
            for w, t in enumerate(row):
                if id(t) not in done:
                    ds = xr.Dataset({"delta_r": ("lateral_shift", t.delta_r)},
                                    coords={"lateral_shift": t.shift},
                                    attrs={"nominal_radius_m": t.nominal_radius})
                    try:
                        done[id(t)] = equivalent_conicity(ds, CONICITY_AMPLITUDE)
                    except InputError as exc:
                        log.warning("equivalent conicity, route %s: %s",
                                    self.sc.routes[r].name, exc)
                        done[id(t)] = math.nan
                rec["equivalent_conicity"][r, w] = done[id(t)]
        return rec

    def _rcf_step(self, rec, results, wheels0, rails0, grid_of, dist):
        """The step's rolling contact fatigue (:mod:`railcontact.wear.rcf`): WLRM damage
        accumulated per profile position like the wear depth (wheels: the routes'
        weighted rate per metre run, the same for a group of wheels; rails: per
        passage times the traffic), the damage before the step reduced by the step's
        wear depth; the largest FI_surf (and FI_sub) per route and position; its CPU
        time."""
        sc = self.sc
        wt = self.weights
        layer = sc.rcf.layer_depth
        prev = self.steps[-1] if self.steps else {}
        add_w = np.zeros((self.nw, 2, self.y_wheel.size))
        for g in self.wheel_groups():
            rate = sum(wt[r] * results[r]["rcf_wheel"][w][j] for r in range(self.nr)
                       for w, j in g) / len(g)
            for w, j in g:
                old = wheels0[w][j]
                add_w[w, j] = np.interp(old.arc_length(self.y_wheel), grid_of[id(old)],
                                        rate * dist, left=0.0, right=0.0)
        add_r = np.array([[np.interp(rails0[r][j].arc_length(self.y_rail),
                                     grid_of[id(rails0[r][j])],
                                     results[r]["rcf_rail"][j] * sc.rail_traffic * wt[r]
                                     / sc.routes[r].length * dist, left=0.0, right=0.0)
                           for j in range(2)] for r in range(self.nr)])
        for kind, add in (("wheel", add_w), ("rail", add_r)):
            before = prev.get(f"rcf_damage_{kind}", np.zeros_like(add))
            rec[f"rcf_damage_{kind}"] = accumulate(before, add, rec[f"wear_depth_{kind}"], layer)
            rec[f"rcf_added_{kind}"] = add
        for name in ("fi_surf", "fi_sub") if sc.rcf.subsurface else ("fi_surf",):
            rec[f"{name}_wheel"] = np.array([[[np.interp(
                wheels0[w][j].arc_length(self.y_wheel), grid_of[id(wheels0[w][j])],
                results[r][f"{name}_wheel"][w][j], left=np.nan, right=np.nan)
                for j in range(2)] for w in range(self.nw)] for r in range(self.nr)])
            rec[f"{name}_rail"] = np.array([[np.interp(
                rails0[r][j].arc_length(self.y_rail), grid_of[id(rails0[r][j])],
                results[r][f"{name}_rail"][j], left=np.nan, right=np.nan)
                for j in range(2)] for r in range(self.nr)])
        rec["rcf_time"] = np.array([res["stats"].rcf_time for res in results])

    def run_step(self) -> dict:
        """One wear step (see the module docstring); returns its record."""
        sc = self.sc
        t0 = time.perf_counter()
        grid_of: dict = {}
        for p in [p for pair in self.wheels + self.rails for p in pair]:
            if id(p) not in grid_of:
                grid_of[id(p)] = arc_length_grid(p, sc.grid_step)
        wheels0 = [list(pair) for pair in self.wheels]
        rails0 = [list(pair) for pair in self.rails]
        tables, results = self._compute(grid_of)
        if len(self.states) == self.step:
            self.states.append(self._state(tables))
        wt = self.weights
        # wheels: the routes' weighted mean per metre run, averaged over each group
        per_m = [[sum(wt[r] * results[r]["wheel"][w][j] for r in range(self.nr))
                  for j in range(2)] for w in range(self.nw)]
        groups = self.wheel_groups()
        group_rate = [sum(per_m[w][j] for w, j in g) / len(g) for g in groups]
        # rails: depth per vehicle passage x passages per metre run (the vehicle runs
        # its share of the distance over the route, rail_traffic times)
        rail_rate = [[results[r]["rail"][j] * sc.rail_traffic * wt[r] / sc.routes[r].length
                      for j in range(2)] for r in range(self.nr)]
        bodies = []            # (kind, profile before, rate per metre, smoothed, members)
        if self._worn("wheel"):
            bodies += [("wheel", wheels0[g[0][0]][g[0][1]], rate,
                        smooth_depth(rate, sc.grid_step, sc.smoothing), g)
                       for g, rate in zip(groups, group_rate)]
        if self._worn("rail"):
            bodies += [("rail", self.rails[r][j], rail_rate[r][j],
                        smooth_depth(rail_rate[r][j], sc.grid_step, sc.smoothing), [(r, j)])
                       for r in range(self.nr) for j in range(2)]
        if sc.distances is not None and self.step < len(sc.distances):
            dist = float(sc.distances[self.step])
        elif sc.step_distance:
            dist = sc.step_distance
        else:
            peak = max((float(b[3].max()) for b in bodies), default=0.0)
            if not peak > 0:
                raise RailContactError("no wear in this step (no frictional work on the worn "
                                       "bodies); check the routes and the wear law")
            dist = sc.max_depth_per_step / peak
        rec = {"distance": dist}
        for kind, n, y in (("wheel", self.nw, self.y_wheel), ("rail", self.nr, self.y_rail)):
            rec[f"wear_depth_{kind}"] = np.zeros((n, 2, y.size))
            rec[f"law_area_{kind}"] = np.zeros((n, 2))
            rec[f"removed_area_{kind}"] = np.zeros((n, 2))
        for kind, old, rate, smoothed, members in bodies:
            grid = grid_of[id(old)]
            depth = smoothed * dist
            new = wear_profile(old, grid, depth, kind)
            if sc.profile_smoothing > 0:
                new = new.smoothed(sc.profile_smoothing)
            y = self.y_wheel if kind == "wheel" else self.y_rail
            on_y = np.interp(old.arc_length(y), grid, depth, left=0.0, right=0.0)
            law_area = float(np.trapezoid(rate, grid)) * dist
            area = removed_area(old, new, kind)
            target = self.wheels if kind == "wheel" else self.rails
            for a, j in members:
                target[a][j] = new
                rec[f"wear_depth_{kind}"][a, j] = on_y
                rec[f"law_area_{kind}"][a, j] = law_area
                rec[f"removed_area_{kind}"][a, j] = area
        self._rcf_step(rec, results, wheels0, rails0, grid_of, dist)
        # per route: each wheel's wear per metre run there (before smoothing)
        s_y = [[wheels0[w][j].arc_length(self.y_wheel) for j in range(2)]
               for w in range(self.nw)]
        rec["wear_rate_wheel"] = np.array([[[np.interp(
            s_y[w][j], grid_of[id(wheels0[w][j])], results[r]["wheel"][w][j], left=0.0,
            right=0.0) for j in range(2)] for w in range(self.nw)] for r in range(self.nr)])
        for key in results[0]["measures"]:
            rec[key] = np.array([res["measures"][key] for res in results])
        rec["energy"] = np.array([res["energy"] for res in results])
        stats = [res["stats"] for res in results]
        for key, attr in (("patches", "patches"), ("patches_solved", "solved"),
                          ("patches_reused", "reused"), ("patches_skipped", "skipped"),
                          ("not_converged", "not_converged"),
                          ("solve_time", "solve_time"), ("postprocess_time", "cpu_time"),
                          ("samples", "samples")):
            rec[key] = np.array([float(getattr(s, attr)) for s in stats])
        rec["dynamics_time"] = np.array([res["dynamics_time"] for res in results])
        rec["stride"] = np.array([float(res["stride"]) for res in results])
        unique = {id(t): t for row in tables for t in row}
        rec["table_time"] = float(sum(t.cpu_time for t in unique.values()))
        rec["outside_table"] = np.array([float(res["outside_table"]) for res in results])
        rec["wall_time"] = time.perf_counter() - t0
        for item, res in zip(sc.routes, results):
            for wtext, count in res["stats"].warnings.items():
                log.info("step %d, route %s: %d solves: %s", self.step + 1, item.name, count,
                         wtext)
            if res["warnings"]:
                log.warning("step %d, route %s: %s", self.step + 1, item.name, res["warnings"])
        self.step += 1
        self.distance += dist
        self.steps.append(rec)
        if self.out:
            if sc.records:
                self._write_records(results)
            self.save_checkpoint()
            self.write()
        return rec

    # ------------------------------------------------------------ run
    def run(self, resume: bool = True):
        """Run the remaining steps; returns the results (:meth:`to_xarray`)."""
        from tqdm.auto import tqdm
        if resume:
            self.load_checkpoint()
        t0 = time.perf_counter()
        for _ in tqdm(range(self.step, self.sc.steps), desc="wear", unit="step",
                      disable=not self.progress, file=sys.stderr):
            self.run_step()
        if len(self.states) == self.step:            # the final profiles' measures
            tasks, rows = self._table_tasks()
            out = compute(tasks, self.sc.scheduler, what="wear.scheduler")
            self.states.append(self._state([[out[i] for i in row] for row in rows]))
        self.cpu_time += time.perf_counter() - t0
        if self.out:
            self.save_checkpoint()
            self.write()
        return self.to_xarray()

    # ------------------------------------------------------------ outputs
    def _write_records(self, results):
        folder = self.out / "records"
        folder.mkdir(parents=True, exist_ok=True)
        for item, res in zip(self.sc.routes, results):
            name = re.sub(r"[^A-Za-z0-9_.-]+", "_", item.name)
            path = folder / f"step{self.step:03d}_{name}.nc"
            write_netcdf(res["records"], path)

    def write(self):
        """Write ``wear.nc`` (and ``wear.png``) into the output folder."""
        ds = self.to_xarray()
        write_netcdf(ds, self.out / "wear.nc")
        return ds

    def to_xarray(self):
        """The run's results as an :class:`xarray.Dataset` (see docs/wear.md)."""
        import xarray as xr
        sc = self.sc
        K = len(self.steps)
        coords = {"step": ("step", np.arange(1, K + 1)),
                  "state": ("state", np.arange(len(self.states))),
                  "route": ("route", [r.name for r in sc.routes]),
                  "wheelset": ("wheelset", np.arange(1, self.nw + 1)),
                  "side": ("side", list(SIDES)), "patch": ("patch", ["tread", "flange"]),
                  "y_wheel": ("y_wheel", self.y_wheel, {"units": "m", "long_name":
                                                       "lateral position on the new wheel "
                                                       "profile"}),
                  "y_rail": ("y_rail", self.y_rail, {"units": "m", "long_name":
                                                    "lateral position on the new rail "
                                                    "profile"})}
        if self.states and "delta_r" in self.states[0]:
            tab = self.settings["table_range"]
            n = self.states[0]["delta_r"].shape[-1]
            coords["lateral_shift"] = ("lateral_shift", np.linspace(-tab, tab, n),
                                       {"units": "m"})
        data = {}

        def put(name, dims, values, units, long_name, over="step"):
            rows = self.steps if over == "step" else self.states
            if not rows:
                return
            data[name] = ((over,) + dims, np.array([r[values] for r in rows], dtype=float),
                          {"units": units, "long_name": long_name})

        put("distance", (), "distance", "m", "distance run in the step")
        put("wear_depth_wheel", ("wheelset", "side", "y_wheel"), "wear_depth_wheel", "m",
            "wear depth of the step (smoothed)")
        put("wear_depth_rail", ("route", "side", "y_rail"), "wear_depth_rail", "m",
            "wear depth of the step (smoothed)")
        for kind, dim in (("wheel", "wheelset"), ("rail", "route")):
            put(f"law_area_{kind}", (dim, "side"), f"law_area_{kind}", "m2",
                "worn cross-section area given by the wear law")
            put(f"removed_area_{kind}", (dim, "side"), f"removed_area_{kind}", "m2",
                "cross-section area between the profiles before and after the step")
        put("wear_rate_wheel", ("route", "wheelset", "side", "y_wheel"), "wear_rate_wheel",
            "m/m", "wheel wear depth per metre run on the route (before smoothing)")
        put("lateral_position", ("route", "wheelset"), "lateral_position", "m",
            "mean wheelset lateral displacement on the route's full-curvature section (the "
            "whole run on tangent track)")
        put("yaw", ("route", "wheelset"), "yaw", "rad", "mean wheelset yaw there")
        put("max_Y_over_Q", ("route", "wheelset", "side"), "max_Y_over_Q", "1",
            "largest |Y/Q| of the run")
        put("Tgamma", ("route", "wheelset", "side"), "Tgamma", "N",
            "mean wear number T gamma of the run (dynamics' creep law)")
        put("contact_y_wheel", ("route", "wheelset", "side", "patch"), "contact_y_wheel", "m",
            "mean contact position on the wheel profile on the full-curvature section")
        put("contact_y_rail", ("route", "wheelset", "side", "patch"), "contact_y_rail", "m",
            "mean contact position on the rail profile on the full-curvature section")
        put("energy", ("route",), "energy", "J/m",
            "frictional energy per metre run (local contact model)")
        put("rcf_damage_wheel", ("wheelset", "side", "y_wheel"), "rcf_damage_wheel", "1",
            "accumulated WLRM RCF damage after the step (wear removal included)")
        put("rcf_damage_rail", ("route", "side", "y_rail"), "rcf_damage_rail", "1",
            "accumulated WLRM RCF damage after the step (wear removal included)")
        put("rcf_added_wheel", ("wheelset", "side", "y_wheel"), "rcf_added_wheel", "1",
            "WLRM RCF damage of the step")
        put("rcf_added_rail", ("route", "side", "y_rail"), "rcf_added_rail", "1",
            "WLRM RCF damage of the step")
        put("fi_surf_wheel", ("route", "wheelset", "side", "y_wheel"), "fi_surf_wheel", "1",
            "largest surface fatigue index FI_surf (Ekberg) at the position on the route "
            "(NaN: no contact)")
        put("fi_surf_rail", ("route", "side", "y_rail"), "fi_surf_rail", "1",
            "largest surface fatigue index FI_surf (Ekberg) at the position on the route "
            "(NaN: no contact)")
        if self.steps and "fi_sub_wheel" in self.steps[0]:
            put("fi_sub_wheel", ("route", "wheelset", "side", "y_wheel"), "fi_sub_wheel", "Pa",
                "largest subsurface fatigue index FI_sub (Ekberg) below the position on the "
                "route (NaN: no contact)")
            put("fi_sub_rail", ("route", "side", "y_rail"), "fi_sub_rail", "Pa",
                "largest subsurface fatigue index FI_sub (Ekberg) below the position on the "
                "route (NaN: no contact)")
        put("rcf_time", ("route",), "rcf_time", "s",
            "CPU time of the RCF damage measures (part of postprocess_time)")
        for key, units, text in (("patches", "1", "loaded patches post-processed"),
                                 ("patches_solved", "1", "patches solved by the local model"),
                                 ("patches_reused", "1", "patches that reused a repeated "
                                                         "state"),
                                 ("patches_skipped", "1", "loaded patches without a "
                                                          "table geometry (none expected)"),
                                 ("not_converged", "1", "solves not converged"),
                                 ("samples", "1", "samples post-processed"),
                                 ("stride", "1", "post-processed every stride-th sample"),
                                 ("solve_time", "s", "CPU time of the local solves"),
                                 ("postprocess_time", "s", "CPU time of the post-processing"),
                                 ("dynamics_time", "s", "CPU time of the dynamics run"),
                                 ("outside_table", "1", "1: a wheelset left the table")):
            put(key, ("route",), key, units, text)
        put("table_time", (), "table_time", "s", "CPU time of the contact tables")
        put("wall_time", (), "wall_time", "s", "wall time of the step")
        put("cumulative_distance", (), "cumulative_distance", "m",
            "distance run before the state", over="state")
        put("profile_z_wheel", ("wheelset", "side", "y_wheel"), "profile_z_wheel", "m",
            "wheel profile height z(y)", over="state")
        put("profile_z_rail", ("route", "side", "y_rail"), "profile_z_rail", "m",
            "rail profile height z(y)", over="state")
        for key, text in (("flange_height", "flange height Sh"),
                          ("flange_thickness", "flange thickness Sd"),
                          ("qR", "flange steepness qR")):
            put(key, ("wheelset", "side"), key, "m", text, over="state")
        put("delta_r", ("route", "wheelset", "lateral_shift"), "delta_r", "m",
            "rolling radius difference r_right - r_left", over="state")
        put("equivalent_conicity", ("route", "wheelset"), "equivalent_conicity", "1",
            f"equivalent conicity at {CONICITY_AMPLITUDE * 1e3:g} mm (EN 15302, "
            "integration of the kinematic oscillation)", over="state")
        attrs = {"law": sc.law, "normal": sc.normal, "tangential": sc.tangential,
                 "dynamics_tangential": sc.dynamics["tangential"], "worn_body": sc.body,
                 "wheels": sc.wheels, "sample_distance_m": sc.sample_distance,
                 "reuse_tolerance": sc.reuse_tolerance, "total_distance_m": float(self.distance),
                 "cpu_time_s": float(self.cpu_time), "title": sc.title,
                 "route_weights": [float(w) for w in self.weights],
                 "route_lengths_m": [float(r.length) for r in sc.routes],
                 "route_speeds_m_s": [float(r.speed) for r in sc.routes],
                 "rcf_shear_yield_Pa": sc.rcf.shear_yield,
                 "rcf_layer_depth_m": sc.rcf.layer_depth}
        return xr.Dataset(data, coords=coords, attrs=attrs)

    # ------------------------------------------------------------ checkpoints
    def _profiles(self):
        """The distinct profile objects and, per wheel and rail, their index."""
        uniq, index = [], {}
        for p in [p for pair in self.wheels + self.rails for p in pair]:
            if id(p) not in index:
                index[id(p)] = len(uniq)
                uniq.append(p)
        return uniq, [[index[id(p)] for p in pair] for pair in self.wheels], \
            [[index[id(p)] for p in pair] for pair in self.rails]

    def save_checkpoint(self):
        """Profiles, records and counters after the last step (``checkpoint.npz``)."""
        uniq, wi, ri = self._profiles()
        arrays = {}
        for k, p in enumerate(uniq):
            arrays[f"profile{k}_y"], arrays[f"profile{k}_z"] = p.y, p.z
        for kind, rows in (("step", self.steps), ("state", self.states)):
            for k, rec in enumerate(rows):
                for name, v in rec.items():
                    arrays[f"{kind}{k}__{name}"] = np.asarray(v, dtype=float)
        meta = {"step": self.step, "distance": self.distance, "wheels": wi, "rails": ri,
                "kinds": [p.kind for p in uniq], "names": [p.name for p in uniq],
                "smoothing": [p.smoothing for p in uniq],
                "steps": len(self.steps), "states": len(self.states),
                "cpu_time": self.cpu_time, "scenario": self._fingerprint()}
        arrays["meta"] = np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)
        with written_whole(self.out / "checkpoint.npz") as tmp, open(tmp, "wb") as f:
            np.savez(f, **arrays)

    def _fingerprint(self) -> str:
        """What a checkpoint must match to be resumed: routes, wheels, models."""
        sc = self.sc
        return json.dumps([sc.wheels, sc.body, sc.law, sc.normal, sc.tangential, self.nw,
                           [(r.name, r.length, r.speed) for r in sc.routes]])

    def load_checkpoint(self) -> bool:
        """Resume from ``checkpoint.npz`` of the output folder (False: none there)."""
        p = self.out / "checkpoint.npz" if self.out else None
        if p is None or not p.is_file():
            return False
        data = np.load(p)
        meta = json.loads(bytes(data["meta"]).decode())
        if meta.get("scenario") != self._fingerprint():
            raise InputError(f"{p}: the checkpoint belongs to another scenario (routes, "
                             "wheels, models); remove it or run with --restart")
        uniq = [Profile(data[f"profile{k}_y"], data[f"profile{k}_z"], kind=kind, name=name,
                        smoothing=sm)
                for k, (kind, name, sm) in enumerate(zip(meta["kinds"], meta["names"],
                                                         meta["smoothing"]))]
        self.wheels = [[uniq[k] for k in pair] for pair in meta["wheels"]]
        self.rails = [[uniq[k] for k in pair] for pair in meta["rails"]]
        self.step, self.distance = meta["step"], meta["distance"]
        self.cpu_time = meta.get("cpu_time", 0.0)
        for kind, n, rows in (("step", meta["steps"], self.steps),
                              ("state", meta["states"], self.states)):
            rows.clear()
            prefix = [f"{kind}{k}__" for k in range(n)]
            for pre in prefix:
                rec = {}
                for key in data.files:
                    if key.startswith(pre):
                        v = data[key]
                        rec[key[len(pre):]] = float(v) if v.ndim == 0 else v
                rows.append(rec)
        log.info("resumed from %s at step %d", p, self.step)
        return True
