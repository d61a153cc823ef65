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
   profiles move along their inward normals; the next step runs on them;
6. beside the wear, the rolling contact fatigue (:mod:`railcontact.wear.rcf`): the
   WLRM damage and the FI_surf exceedance (the sum over the passages of
   max(FI_surf, 0)) accumulate per profile position like the wear depth, the step's
   wear depth removing part of the damage before it; the largest FI_surf (and
   FI_sub) per route and position.

Results go to ``wear.nc`` as the steps run (see ``docs/wear.md``), with a checkpoint
from which an interrupted run resumes; with ``wear.records = true``, ``records/``
holds per step and route the post-processed samples (the dynamics' inputs and the
local model's results per patch).
"""

from __future__ import annotations

import logging
import math
import re
from dataclasses import dataclass

import numpy as np

from ..cases.bodies import build_wheelset_track
from ..core.errors import InputError
from ..core.files import write_netcdf
from ..core.parallel import compute
from ..core.progress import TqdmCallback
from ..dynamics.vehicle import G_ACC
from ..geometry.tables import equivalent_conicity
from ..profiles.measures import wheel_measures
from .driver import StepLoads, Variable, WearDriver, WornBody
from .rcf import accumulate
from .route_tasks import build_table, run_route

log = logging.getLogger(__name__)

SIDES = ("left", "right")
#: amplitude of the equivalent conicity (EN 15302's usual 3 mm) [m]
CONICITY_AMPLITUDE = 3e-3
#: per route: the step's record key <- the attribute of the post-processing's stats
STAT_VARIABLES = (("patches", "patches"), ("patches_solved", "solved"),
                  ("patches_reused", "reused"), ("patches_skipped", "skipped"),
                  ("not_converged", "not_converged"), ("solve_time", "solve_time"),
                  ("postprocess_time", "cpu_time"), ("samples", "samples"))

_WS, _RS = ("wheelset", "side"), ("route", "side")
_RWS, _RWSP = ("route", "wheelset", "side"), ("route", "wheelset", "side", "patch")
_AREA = ("worn cross-section area given by the wear law",
         "cross-section area between the profiles before and after the step")
#: the results of a closed-loop run (wear.nc, docs/wear.md)
VARIABLES = (
    Variable("distance", (), "m", "distance run in the step"),
    Variable("wear_depth_wheel", _WS + ("y_wheel",), "m", "wear depth of the step (smoothed)"),
    Variable("wear_depth_rail", _RS + ("y_rail",), "m", "wear depth of the step (smoothed)"),
    Variable("law_area_wheel", _WS, "m2", _AREA[0]),
    Variable("removed_area_wheel", _WS, "m2", _AREA[1]),
    Variable("law_area_rail", _RS, "m2", _AREA[0]),
    Variable("removed_area_rail", _RS, "m2", _AREA[1]),
    Variable("wear_rate_wheel", ("route", "wheelset", "side", "y_wheel"), "m/m",
             "wheel wear depth per metre run on the route (before smoothing)"),
    Variable("lateral_position", ("route", "wheelset"), "m",
             "mean wheelset lateral displacement on the route's full-curvature section (the "
             "whole run on tangent track)"),
    Variable("yaw", ("route", "wheelset"), "rad", "mean wheelset yaw there"),
    Variable("max_Y_over_Q", _RWS, "1", "largest |Y/Q| of the run"),
    Variable("Tgamma", _RWS, "N", "mean wear number T gamma of the run (dynamics' creep law)"),
    Variable("contact_y_wheel", _RWSP, "m",
             "mean contact position on the wheel profile on the full-curvature section"),
    Variable("contact_y_rail", _RWSP, "m",
             "mean contact position on the rail profile on the full-curvature section"),
    Variable("energy", ("route",), "J/m", "frictional energy per metre run (local contact "
             "model)"),
    Variable("rcf_damage_wheel", _WS + ("y_wheel",), "1",
             "accumulated WLRM RCF damage after the step (wear removal included)"),
    Variable("rcf_damage_rail", _RS + ("y_rail",), "1",
             "accumulated WLRM RCF damage after the step (wear removal included)"),
    Variable("rcf_added_wheel", _WS + ("y_wheel",), "1", "WLRM RCF damage of the step"),
    Variable("rcf_added_rail", _RS + ("y_rail",), "1", "WLRM RCF damage of the step"),
    Variable("rcf_surface_wheel", _WS + ("y_wheel",), "1",
             "accumulated FI_surf exceedance (sum over the passages of max(FI_surf, 0)) "
             "after the step (wear removal included)"),
    Variable("rcf_surface_rail", _RS + ("y_rail",), "1",
             "accumulated FI_surf exceedance (sum over the passages of max(FI_surf, 0)) "
             "after the step (wear removal included)"),
    Variable("rcf_surface_added_wheel", _WS + ("y_wheel",), "1",
             "FI_surf exceedance of the step"),
    Variable("rcf_surface_added_rail", _RS + ("y_rail",), "1",
             "FI_surf exceedance of the step"),
    Variable("rcf_surface_rate_wheel", ("route", "wheelset", "side", "y_wheel"), "1/m",
             "FI_surf exceedance per metre run on the route"),
    Variable("fi_surf_wheel", _RWS + ("y_wheel",), "1",
             "largest surface fatigue index FI_surf (Ekberg) at the position on the route "
             "(NaN: no contact)"),
    Variable("fi_surf_rail", _RS + ("y_rail",), "1",
             "largest surface fatigue index FI_surf (Ekberg) at the position on the route "
             "(NaN: no contact)"),
    Variable("fi_sub_wheel", _RWS + ("y_wheel",), "Pa",
             "largest subsurface fatigue index FI_sub (Ekberg) below the position on the "
             "route (NaN: no contact); with wear.rcf.subsurface"),
    Variable("fi_sub_rail", _RS + ("y_rail",), "Pa",
             "largest subsurface fatigue index FI_sub (Ekberg) below the position on the "
             "route (NaN: no contact); with wear.rcf.subsurface"),
    Variable("rcf_time", ("route",), "s",
             "CPU time of the RCF damage measures (part of postprocess_time)"),
    Variable("patches", ("route",), "1", "loaded patches post-processed"),
    Variable("patches_solved", ("route",), "1", "patches solved by the local model"),
    Variable("patches_reused", ("route",), "1", "patches that reused a repeated state"),
    Variable("patches_skipped", ("route",), "1",
             "loaded patches without a table geometry (none expected)"),
    Variable("not_converged", ("route",), "1", "solves not converged"),
    Variable("samples", ("route",), "1", "samples post-processed"),
    Variable("stride", ("route",), "1", "post-processed every stride-th sample"),
    Variable("solve_time", ("route",), "s", "CPU time of the local solves"),
    Variable("postprocess_time", ("route",), "s", "CPU time of the post-processing"),
    Variable("dynamics_time", ("route",), "s", "CPU time of the dynamics run"),
    Variable("outside_table", ("route",), "1", "1: a wheelset left the table"),
    Variable("table_time", (), "s", "CPU time of the contact tables"),
    Variable("wall_time", (), "s", "wall time of the step"),
    Variable("cumulative_distance", (), "m", "distance run before the state", "state"),
    Variable("profile_z_wheel", _WS + ("y_wheel",), "m", "wheel profile height z(y)", "state"),
    Variable("profile_z_rail", _RS + ("y_rail",), "m", "rail profile height z(y)", "state"),
    Variable("flange_height", _WS, "m", "flange height Sh", "state"),
    Variable("flange_thickness", _WS, "m", "flange thickness Sd", "state"),
    Variable("qR", _WS, "m", "flange steepness qR", "state"),
    Variable("delta_r", ("route", "wheelset", "lateral_shift"), "m",
             "rolling radius difference r_right - r_left", "state"),
    Variable("equivalent_conicity", ("route", "wheelset"), "1",
             f"equivalent conicity at {CONICITY_AMPLITUDE * 1e3:g} mm (EN 15302, integration "
             "of the kinematic oscillation)", "state"),
)


@dataclass
class _DamageRate:
    """A damage measure (``name``: "rcf_damage", the WLRM damage, or "rcf_surface",
    the FI_surf exceedance) of one wheel or rail slot in a step before its distance
    is known: the slot, the arc lengths of the recorded positions on its profile before
    the step [m], its arc-length grid [m] and the damage per metre run on it (wheels:
    the group's weighted mean over the routes; rails: per passage times the
    passages per metre run)."""

    name: str
    kind: str
    slot: tuple
    s_y: np.ndarray
    grid: np.ndarray
    rate: np.ndarray

    def added(self, dist: float) -> np.ndarray:
        """The damage added over ``dist`` [m] at the recorded positions."""
        return np.interp(self.s_y, self.grid, self.rate * dist, left=0.0, right=0.0)


class ClosedLoopWear(WearDriver):
    """Run a closed-loop wear scenario step by step (see the module docstring).

    Parameters
    ----------
    scenario : VehicleWearScenario
    out_dir : path, optional
        Folder for ``wear.nc``, ``checkpoint.nc`` and ``records/`` (``wear.records``).
    progress : bool
        Progress bars over the steps and the routes.
    """

    def __init__(self, scenario, out_dir=None, progress: bool = True):
        super().__init__(scenario, out_dir, progress)
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

    # ------------------------------------------------------------ profiles
    def slots(self) -> list:
        """("wheel", wheelset, side) and ("rail", route, side)."""
        return ([("wheel", w, j) for w in range(self.nw) for j in range(2)]
                + [("rail", r, j) for r in range(self.nr) for j in range(2)])

    def profile(self, slot):
        kind, a, j = slot
        return (self.wheels if kind == "wheel" else self.rails)[a][j]

    def set_profile(self, slot, profile) -> None:
        kind, a, j = slot
        (self.wheels if kind == "wheel" else self.rails)[a][j] = profile

    def initial_profiles(self) -> list:
        return list(self.initial_wheels + self.initial_rails)

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

    def loads(self, grid_of: dict) -> StepLoads:
        """The tables and route runs of the current profiles (one Dask graph), the
        measures of the profiles (the state before the step) and the worn bodies:
        each wheel group's rate (the routes' weighted mean per metre run) and each
        route's rails (per vehicle passage x passages per metre run)."""
        sc = self.sc
        wheels0 = [list(pair) for pair in self.wheels]
        rails0 = [list(pair) for pair in self.rails]
        tables, results = self._compute(grid_of)
        if len(self.states) == self.step:
            self.states.append(self._state(tables))
        wt = self.weights
        per_m = [[sum(wt[r] * results[r]["wheel"][w][j] for r in range(self.nr))
                  for j in range(2)] for w in range(self.nw)]
        bodies = []
        if self._worn("wheel"):
            for g in self.wheel_groups():
                old = wheels0[g[0][0]][g[0][1]]
                rate = sum(per_m[w][j] for w, j in g) / len(g)
                bodies.append(WornBody("wheel", old, grid_of[id(old)], rate, self.y_wheel,
                                       [("wheel", w, j) for w, j in g]))
        if self._worn("rail"):
            # the vehicle runs its share of the distance over the route, rail_traffic times
            for r in range(self.nr):
                for j in range(2):
                    old = self.rails[r][j]
                    rate = results[r]["rail"][j] * sc.rail_traffic * wt[r] / sc.routes[r].length
                    bodies.append(WornBody("rail", old, grid_of[id(old)], rate, self.y_rail,
                                           [("rail", r, j)]))
        self._log(results)
        if self.out and sc.records:
            self._write_records(results)
        rec = self._route_record(wheels0, grid_of, tables, results)
        rec.update(self._fatigue_record(wheels0, rails0, grid_of, results))
        # the step's damage rates (_DamageRate), turned into damage by record() once the
        # step's distance and wear are known
        rec["_damage_rates"] = self._damage_rates(wheels0, rails0, grid_of, results)
        return StepLoads(bodies, rec)

    def _damage_rates(self, wheels0, rails0, grid_of, results) -> list:
        """The step's WLRM damage and FI_surf exceedance per metre run of every wheel
        and rail slot (:class:`_DamageRate`), accumulated like the wear depth: wheels
        the routes' weighted rate per metre run, the same for a group of wheels; rails
        per passage times the traffic."""
        sc, wt = self.sc, self.weights
        out = []
        for name, key in (("rcf_damage", "rcf"), ("rcf_surface", "rcf_surface")):
            for g in self.wheel_groups():
                rate = sum(wt[r] * results[r][f"{key}_wheel"][w][j] for r in range(self.nr)
                           for w, j in g) / len(g)
                for w, j in g:
                    old = wheels0[w][j]
                    out.append(_DamageRate(name, "wheel", (w, j), old.arc_length(self.y_wheel),
                                           grid_of[id(old)], rate))
            for r in range(self.nr):
                for j in range(2):
                    old = rails0[r][j]
                    rate = (results[r][f"{key}_rail"][j] * sc.rail_traffic * wt[r]
                            / sc.routes[r].length)
                    out.append(_DamageRate(name, "rail", (r, j), old.arc_length(self.y_rail),
                                           grid_of[id(old)], rate))
        return out

    def _fatigue_record(self, wheels0, rails0, grid_of, results) -> dict:
        """The step's fatigue indices per route: the largest FI_surf (and, with
        ``wear.rcf.subsurface``, FI_sub) at each recorded position of the profiles
        before the step (NaN where no patch came), each wheel's FI_surf exceedance per
        metre run on the route, and the RCF measures' CPU time."""
        rec = {}
        for name in ("fi_surf", "fi_sub") if self.sc.rcf.subsurface else ("fi_surf",):
            rec[f"{name}_wheel"] = np.array([[[np.interp(
                wheels0[w][j].arc_length(self.y_wheel), grid_of[id(wheels0[w][j])],
                results[r][f"{name}_wheel"][w][j], left=np.nan, right=np.nan)
                for j in range(2)] for w in range(self.nw)] for r in range(self.nr)])
            rec[f"{name}_rail"] = np.array([[np.interp(
                rails0[r][j].arc_length(self.y_rail), grid_of[id(rails0[r][j])],
                results[r][f"{name}_rail"][j], left=np.nan, right=np.nan)
                for j in range(2)] for r in range(self.nr)])
        rec["rcf_surface_rate_wheel"] = np.array([[[np.interp(
            wheels0[w][j].arc_length(self.y_wheel), grid_of[id(wheels0[w][j])],
            results[r]["rcf_surface_wheel"][w][j], left=0.0, right=0.0)
            for j in range(2)] for w in range(self.nw)] for r in range(self.nr)])
        rec["rcf_time"] = np.array([res["stats"].rcf_time for res in results])
        return rec

    def _route_record(self, wheels0, grid_of, tables, results) -> dict:
        """The step's entries per route: each wheel's wear per metre run there (before
        smoothing), the run's measures, energy, counts and times."""
        rec = {}
        s_y = [[wheels0[w][j].arc_length(self.y_wheel) for j in range(2)]
               for w in range(self.nw)]
        rec["wear_rate_wheel"] = np.array([[[np.interp(
            s_y[w][j], grid_of[id(wheels0[w][j])], results[r]["wheel"][w][j], left=0.0,
            right=0.0) for j in range(2)] for w in range(self.nw)] for r in range(self.nr)])
        for key in results[0]["measures"]:
            rec[key] = np.array([res["measures"][key] for res in results])
        rec["energy"] = np.array([res["energy"] for res in results])
        for key, attr in STAT_VARIABLES:
            rec[key] = np.array([float(getattr(res["stats"], attr)) for res in results])
        for key in ("dynamics_time", "stride", "outside_table"):
            rec[key] = np.array([float(res[key]) for res in results])
        unique = {id(t): t for row in tables for t in row}
        rec["table_time"] = float(sum(t.cpu_time for t in unique.values()))
        return rec

    def _log(self, results) -> None:
        for item, res in zip(self.sc.routes, results):
            for wtext, count in res["stats"].warnings.items():
                log.info("step %d, route %s: %d solves: %s", self.step + 1, item.name, count,
                         wtext)
            if res["warnings"]:
                log.warning("step %d, route %s: %s", self.step + 1, item.name, res["warnings"])

    def record(self, rec: dict, worn: list) -> None:
        """Depths and areas per wheelset (route) and side; the WLRM damage after the
        step (:meth:`_record_damage`)."""
        for kind, n, y in (("wheel", self.nw, self.y_wheel), ("rail", self.nr, self.y_rail)):
            rec[f"wear_depth_{kind}"] = np.zeros((n, 2, y.size))
            rec[f"law_area_{kind}"] = np.zeros((n, 2))
            rec[f"removed_area_{kind}"] = np.zeros((n, 2))
        for w in worn:
            for kind, a, j in w.body.slots:
                rec[f"wear_depth_{kind}"][a, j] = w.depth_on_y
                rec[f"law_area_{kind}"][a, j] = w.law_area
                rec[f"removed_area_{kind}"][a, j] = w.removed_area
        self._record_damage(rec)

    def _record_damage(self, rec: dict) -> None:
        """The step's WLRM damage and FI_surf exceedance over its distance, and the
        accumulated ones: those before the step less the fraction of the surface layer
        its wear depth removed (:func:`~railcontact.wear.rcf.accumulate`), plus the
        step's."""
        dist = rec["distance"]
        shapes = {"wheel": (self.nw, 2, self.y_wheel.size), "rail": (self.nr, 2, self.y_rail.size)}
        added = {(n, k): np.zeros(shp) for n in ("rcf_damage", "rcf_surface")
                 for k, shp in shapes.items()}
        for d in rec.pop("_damage_rates", []):
            added[(d.name, d.kind)][d.slot] = d.added(dist)
        prev = self.steps[-1] if self.steps else {}
        for (name, kind), add in added.items():
            before = prev.get(f"{name}_{kind}", np.zeros_like(add))
            rec[f"{name}_{kind}"] = accumulate(before, add, rec[f"wear_depth_{kind}"],
                                               self.sc.rcf.layer_depth)
            new = "rcf_added" if name == "rcf_damage" else "rcf_surface_added"
            rec[f"{new}_{kind}"] = add

    def finish(self) -> None:
        """The measures of the final profiles (their tables, without a run)."""
        if len(self.states) == self.step:
            tasks, rows = self._table_tasks()
            out = compute(tasks, self.sc.scheduler, what="wear.scheduler")
            self.states.append(self._state([[out[i] for i in row] for row in rows]))

    # ------------------------------------------------------------ outputs
    def _write_records(self, results):
        folder = self.out / "records"
        folder.mkdir(parents=True, exist_ok=True)
        for item, res in zip(self.sc.routes, results):
            name = re.sub(r"[^A-Za-z0-9_.-]+", "_", item.name)
            path = folder / f"step{self.step + 1:03d}_{name}.nc"
            write_netcdf(res["records"], path)

    def variables(self) -> tuple:
        return VARIABLES

    def coords(self) -> dict:
        coords = {"route": ("route", [r.name for r in self.sc.routes]),
                  "wheelset": ("wheelset", np.arange(1, self.nw + 1)),
                  "side": ("side", list(SIDES)), "patch": ("patch", ["tread", "flange"]),
                  "y_wheel": ("y_wheel", self.y_wheel, {"units": "m", "long_name":
                                                       "lateral position on the new wheel "
                                                       "profile"}),
                  "y_rail": ("y_rail", self.y_rail, {"units": "m", "long_name":
                                                    "lateral position on the new rail "
                                                    "profile"})}
        if self.states and "delta_r" in self.states[0]:
            tab = self.sc.dynamics["table_range"]
            n = self.states[0]["delta_r"].shape[-1]
            coords["lateral_shift"] = ("lateral_shift", np.linspace(-tab, tab, n),
                                       {"units": "m"})
        return coords

    def attrs(self) -> dict:
        sc = self.sc
        return {"law": sc.law, "normal": sc.normal, "tangential": sc.tangential,
                "dynamics_tangential": sc.dynamics["tangential"], "worn_body": sc.body,
                "wheels": sc.wheels, "sample_distance_m": sc.sample_distance,
                "reuse_tolerance": sc.reuse_tolerance, "title": sc.title,
                "route_weights": [float(w) for w in self.weights],
                "route_lengths_m": [float(r.length) for r in sc.routes],
                "route_speeds_m_s": [float(r.speed) for r in sc.routes],
                "rcf_shear_yield_Pa": sc.rcf.shear_yield,
                "rcf_layer_depth_m": sc.rcf.layer_depth}

