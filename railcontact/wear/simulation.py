"""Wear simulation: operating conditions -> wear per step -> evolving profiles.

Scenario (TOML): the sections of a wheel-rail case file ([material], [friction],
[wheel], [rail], [track], [wheelset], [solver]) give the base case; ``[wear]`` the
law and the step control; ``[[condition]]`` the operating conditions (wheelset keys
that override the base case, plus ``weight``, their share of the distance).  See
``docs/wear.md``.

Per step every condition is solved (in parallel with Dask when asked to), the local
wear of each patch is summed along the rolling direction, mapped onto the profile
arc length of the wheel and rail it belongs to (left and right bodies separately),
averaged with the condition weights and scaled to the step:

* wheel: depth per metre travelled = depth per revolution / (2 pi r_rolling);
* rail: depth per metre = depth per wheel passage * ``rail_passages_per_meter``.

The step distance is fixed (``step_distance``) or chosen so that the largest depth of
the worn bodies equals ``max_depth_per_step`` (default 0.1 mm).  The depth is
smoothed with a Gaussian of physical length ``smoothing`` (area conserved) and the
profiles move along their inward normals.  A checkpoint after every step makes an
interrupted run resume without loss.
"""

from __future__ import annotations

import copy
import json
import logging
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..cases.bodies import build_wheelset_track
from ..cases.case import case_from_dict
from ..core.files import read_toml
from ..cases.solve import solve
from ..core.errors import CaseFileError, InputError, RailContactError
from ..core.files import write_netcdf, written_whole
from ..core.parallel import compute
from ..core.progress import TqdmCallback
from ..profiles.profile import Profile
from .laws import get_wear_law
from .mapping import arc_length_grid, profile_depth, smooth_depth, strip_depth, wear_profile
from .vehicle_scenario import (WearSettings, apply_wear_settings, is_vehicle_scenario,
                               number, vehicle_scenario_from_dict)

log = logging.getLogger(__name__)

BODIES = ("wheel_left", "wheel_right", "rail_left", "rail_right")
_WEAR_KEYS = {"law", "parameters", "body", "steps", "max_depth_per_step", "step_distance",
              "smoothing", "rail_passages_per_meter", "grid_step", "scheduler", "history",
              "history_stride", "profile_smoothing"}
#: columns of an imported time history (SI units); the first six are required
HISTORY_COLUMNS = ("time", "lateral_shift", "yaw", "vertical_force_left", "vertical_force_right",
                   "velocity", "pitch_velocity", "creepage_longitudinal", "creepage_lateral",
                   "creepage_spin")
_COND_KEYS = {"weight", "lateral_shift", "yaw", "vertical_force", "velocity", "pitch_velocity",
              "lateral_velocity", "yaw_rate", "roll", "side", "creepage", "curve_radius"}


@dataclass
class WearScenario(WearSettings):
    """A validated open-loop wear scenario: the base case (``base``, a case file's
    dict), its operating conditions with their weights (``conditions``) and the
    rail passages per metre of wheel travel."""

    base: dict
    rail_passages_per_meter: float = 1.0
    conditions: list = field(default_factory=list)


def load_scenario(path):
    """Read and validate a wear scenario TOML file: a :class:`WearScenario`
    (operating conditions or a time history) or, with ``[vehicle]`` and
    ``[[route]]``, a closed-loop
    :class:`~railcontact.wear.vehicle_scenario.VehicleWearScenario`."""
    path = Path(path)
    return scenario_from_dict(read_toml(path, "wear scenario"), path.parent)


def scenario_from_dict(raw: dict, base_dir=None):
    """Validate a parsed wear scenario (see :func:`load_scenario`)."""
    if is_vehicle_scenario(raw):
        return vehicle_scenario_from_dict(raw, base_dir)
    raw = copy.deepcopy(raw)
    wear = raw.pop("wear", {})
    conds = raw.pop("condition", None)
    if not isinstance(wear, dict):
        raise CaseFileError("[wear] must be a table")
    if "history" in wear:
        if conds:
            raise CaseFileError("give either [[condition]] tables or wear.history, not both")
        conds = read_history(Path(base_dir or Path.cwd()) / str(wear["history"]),
                             int(wear.get("history_stride", 1)))
    unknown = set(wear) - _WEAR_KEYS
    if unknown:
        raise CaseFileError(f"unknown key(s) wear.{sorted(unknown)}; expected {sorted(_WEAR_KEYS)}")
    if not conds or not isinstance(conds, list):
        raise CaseFileError("missing [[condition]] tables; expected at least one operating "
                            "condition (lateral_shift, yaw, vertical_force, weight, ...)")
    for i, c in enumerate(conds):
        bad = set(c) - _COND_KEYS
        if bad:
            raise CaseFileError(f"condition {i + 1}: unknown key(s) {sorted(bad)}; expected "
                                f"{sorted(_COND_KEYS)}")
        w = c.get("weight", 1.0)
        if not (isinstance(w, (int, float)) and w > 0):
            raise CaseFileError(f"condition {i + 1}: weight = {w!r}; expected a value > 0")
    sc = WearScenario(base=raw, conditions=conds, base_dir=Path(base_dir or Path.cwd()))
    apply_wear_settings(sc, wear)
    sc.rail_passages_per_meter = number(wear, "wear", "rail_passages_per_meter", 1.0, 1e-9, 1e3)
    # validate the base case with the first condition
    case_from_dict(_condition_raw(sc, conds[0], None), sc.base_dir)
    return sc


def read_history(path: Path, stride: int = 1) -> list:
    """Operating conditions from a time history (CSV with a header row).

    Columns (SI units): time [s], lateral_shift [m], yaw [rad], vertical_force_left [N],
    vertical_force_right [N], velocity [m/s]; optional pitch_velocity [rad/s] and
    creepage_longitudinal, creepage_lateral [-], creepage_spin [1/m] (these override
    the kinematic creepages).  Every ``stride``-th row becomes a condition weighted by
    the distance it stands for (velocity x time step).
    """
    if not path.is_file():
        raise CaseFileError(f"wear.history {str(path)!r} does not exist")
    if stride < 1:
        raise CaseFileError(f"wear.history_stride = {stride}: expected an integer >= 1")
    try:
        data = np.genfromtxt(path, delimiter=",", names=True, dtype=float, encoding="utf-8")
    except ValueError as exc:
        raise CaseFileError(f"{path}: cannot read the time history: {exc}") from None
    names = data.dtype.names or ()
    missing = [c for c in HISTORY_COLUMNS[:6] if c not in names]
    if missing:
        raise CaseFileError(f"{path}: missing column(s) {missing}; expected "
                            f"{list(HISTORY_COLUMNS[:6])} (SI units)")
    data = np.atleast_1d(data)
    if data.size < 2:
        raise CaseFileError(f"{path}: expected at least two rows")
    for c in names:
        if not np.all(np.isfinite(data[c])):
            raise CaseFileError(f"{path}: column {c!r} has non-numeric or NaN values")
    t = data["time"]
    if np.any(np.diff(t) <= 0):
        raise CaseFileError(f"{path}: time must increase")
    dt = np.gradient(t)
    conds = []
    for i in range(0, data.size, stride):
        sl = slice(i, min(i + stride, data.size))
        c = {"lateral_shift": float(data["lateral_shift"][i]), "yaw": float(data["yaw"][i]),
             "vertical_force": [float(data["vertical_force_left"][i]),
                                float(data["vertical_force_right"][i])],
             "velocity": float(data["velocity"][i]),
             "weight": float(np.sum(np.abs(data["velocity"][sl]) * dt[sl]))}
        if "pitch_velocity" in names:
            c["pitch_velocity"] = float(data["pitch_velocity"][i])
        if "creepage_longitudinal" in names:
            c["creepage"] = {"longitudinal": float(data["creepage_longitudinal"][i]),
                             "lateral": float(data["creepage_lateral"][i])
                             if "creepage_lateral" in names else 0.0,
                             "spin": float(data["creepage_spin"][i])
                             if "creepage_spin" in names else 0.0}
        conds.append(c)
    return conds


def _condition_raw(sc: WearScenario, cond: dict, profiles: dict | None) -> dict:
    raw = copy.deepcopy(sc.base)
    ws = raw.setdefault("wheelset", {})
    for k, v in cond.items():
        if k in ("weight",):
            continue
        if k == "curve_radius":
            # steady curving: the wheelset turns with the track at V / R (positive R:
            # curve to the right); cant enters through the per-wheel vertical loads
            if not (isinstance(v, (int, float)) and abs(v) >= 10.0):
                raise CaseFileError(f"condition curve_radius = {v!r}: expected |R| >= 10 m")
            vel = cond.get("velocity", raw.get("wheelset", {}).get("velocity", 30.0))
            ws["yaw_rate"] = float(vel) / float(v)
        elif k == "creepage":
            raw["creepage"] = dict(v)
        else:
            ws[k] = v
    if profiles is not None:
        raw.setdefault("wheel", {})["profile"] = profiles["wheel_right"]
        raw["wheel"]["profile_left"] = profiles["wheel_left"]
        raw.setdefault("rail", {})["profile"] = profiles["rail_right"]
        raw["rail"]["profile_left"] = profiles["rail_left"]
        raw["rail"]["inclination"] = 0.0       # worn rails are kept as mounted
    return raw


def condition_wear(raw: dict, base_dir, law_name: str, law_params: dict, grids: dict,
                   profiles: dict) -> dict:
    """Wear of one operating condition: depth per revolution (wheels) and per passage
    (rails) on the s-grids, the rolling radii, and the frictional energy [J/m]."""
    law = get_wear_law(law_name, **law_params)
    res = solve(case_from_dict(raw, base_dir))
    out = {b: np.zeros_like(grids[b]) for b in BODIES}
    radius = {"left": math.nan, "right": math.nan}
    energy = 0.0
    for pr in res.patches:
        g, ns, ts = pr.geometry, pr.normal, pr.tangential
        if ts is None:
            raise InputError("wear needs a tangential model (solver.tangential is 'none')")
        rate = law.rate(ns, ts, ts.velocity)
        dy = strip_depth(rate, ns)
        for kind in ("wheel", "rail"):
            key = f"{kind}_{g.side}"
            out[key] += profile_depth(g, ns, dy, profiles[key], kind, grids[key])
        radius[g.side] = g.rolling_radius
        energy += ts.frictional_power / max(ts.velocity, 1e-12)
    return {"depth": out, "radius": radius, "energy": energy, "converged": res.converged}


class WearSimulation:
    """Run a wear scenario step by step (see the module docstring)."""

    def __init__(self, scenario: WearScenario, out_dir=None, progress: bool = True):
        self.sc = scenario
        self.out = Path(out_dir) if out_dir else None
        self.progress = progress
        case = case_from_dict(_condition_raw(scenario, scenario.conditions[0], None),
                              scenario.base_dir)
        ws, tr = build_wheelset_track(case)
        self.profiles = {"wheel_left": ws.wheel_left, "wheel_right": ws.wheel_right,
                         "rail_left": tr.rail_left, "rail_right": tr.rail_right}
        self.initial = dict(self.profiles)
        self.history = []
        self.step = 0
        self.distance = 0.0

    # ------------------------------------------------------------ checkpoints
    def _checkpoint_path(self):
        return self.out / "checkpoint.npz" if self.out else None

    def save_checkpoint(self):
        p = self._checkpoint_path()
        if p is None:
            return
        arrays = {}
        for b, prof in self.profiles.items():
            arrays[f"{b}_y"], arrays[f"{b}_z"] = prof.y, prof.z
        meta = {"step": self.step, "distance": self.distance,
                "history": [{k: (v.tolist() if isinstance(v, np.ndarray) else v)
                             for k, v in h.items()} for h in self.history]}
        arrays["meta"] = np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)
        with written_whole(p) as tmp, open(tmp, "wb") as f:
            np.savez(f, **arrays)

    def load_checkpoint(self) -> bool:
        p = self._checkpoint_path()
        if p is None or not p.is_file():
            return False
        data = np.load(p)
        meta = json.loads(bytes(data["meta"]).decode())
        for b in BODIES:
            kind = "wheel" if b.startswith("wheel") else "rail"
            self.profiles[b] = Profile(data[f"{b}_y"], data[f"{b}_z"], kind=kind, name=b)
        self.step, self.distance = meta["step"], meta["distance"]
        self.history = [{k: (np.array(v) if isinstance(v, list) else v) for k, v in h.items()}
                        for h in meta["history"]]
        log.info("resumed from %s at step %d", p, self.step)
        return True

    # ------------------------------------------------------------------ steps
    def _worn(self, body_key):
        kind = body_key.split("_")[0]
        return self.sc.body in (kind, "both")

    def run_step(self):
        sc = self.sc
        grids = {b: arc_length_grid(self.profiles[b], sc.grid_step) for b in BODIES}
        w = np.array([c.get("weight", 1.0) for c in sc.conditions], dtype=float)
        w /= w.sum()
        raws = [_condition_raw(sc, c, self.profiles) for c in sc.conditions]
        import dask
        tasks = [dask.delayed(condition_wear)(r, sc.base_dir, sc.law, sc.parameters, grids,
                                              self.profiles) for r in raws]
        bar = TqdmCallback(len(raws), f"wear step {self.step + 1}", prefix="condition_wear",
                           leave=False, disable=not self.progress)
        results = compute(tasks, sc.scheduler, bar, "wear.scheduler")
        per_m = {b: np.zeros_like(grids[b]) for b in BODIES}
        energy = 0.0
        for wi, r in zip(w, results):
            energy += wi * r["energy"]
            for b in BODIES:
                if b.startswith("wheel"):
                    rad = r["radius"][b.split("_")[1]]
                    if math.isfinite(rad):
                        per_m[b] += wi * r["depth"][b] / (2 * math.pi * rad)
                else:
                    per_m[b] += wi * r["depth"][b] * sc.rail_passages_per_meter
        worn = [b for b in BODIES if self._worn(b)]
        law_area = {b: float(np.trapezoid(per_m[b], grids[b])) for b in BODIES}
        per_m = {b: smooth_depth(per_m[b], sc.grid_step, sc.smoothing) for b in BODIES}
        peak = max(float(per_m[b].max()) for b in worn)
        if peak <= 0:
            raise RailContactError("no wear in this step (no frictional work); check the "
                                   "creepages and the operating conditions")
        dist = sc.step_distance if sc.step_distance else sc.max_depth_per_step / peak
        rec = {"step": self.step + 1, "distance": dist, "energy_per_m": energy,
               "converged": all(r["converged"] for r in results)}
        for b in BODIES:
            depth = per_m[b] * dist if b in worn else np.zeros_like(grids[b])
            rec[f"law_area_{b}"] = law_area[b] * dist if b in worn else 0.0
            old = self.profiles[b]
            if b in worn:
                new = wear_profile(old, grids[b], depth, b.split("_")[0])
                if sc.profile_smoothing > 0:
                    new = new.smoothed(sc.profile_smoothing)
                self.profiles[b] = new
            # record on the lateral coordinate of the original profile
            s_old = old.arc_length(self.initial[b].y)
            rec[f"depth_{b}"] = np.interp(s_old, grids[b], depth, left=0.0, right=0.0)
            rec[f"z_{b}"] = self.profiles[b].z_at(self.initial[b].y)
        self.step += 1
        self.distance += dist
        self.history.append(rec)
        self.save_checkpoint()
        return rec

    def run(self, resume: bool = True):
        """Run all remaining steps; returns the results as an xarray Dataset."""
        if resume:
            self.load_checkpoint()
        from tqdm.auto import tqdm
        t0 = time.perf_counter()
        for _ in tqdm(range(self.step, self.sc.steps), desc="wear", unit="step",
                      disable=not self.progress):
            self.run_step()
        ds = self.to_xarray()
        ds.attrs["cpu_time_s"] = time.perf_counter() - t0
        if self.out:
            write_netcdf(ds, self.out / "wear.nc")
        return ds

    def to_xarray(self):
        import xarray as xr
        steps = np.array([h["step"] for h in self.history], dtype=int)
        data = {"distance": ("step", np.array([h["distance"] for h in self.history]),
                             {"units": "m", "long_name": "distance of the step"}),
                "energy": ("step", np.array([h["energy_per_m"] for h in self.history]),
                           {"units": "J m-1", "long_name": "weighted frictional energy per "
                            "metre"})}
        for b in BODIES:
            data[f"law_area_{b}"] = ("step", np.array([h[f"law_area_{b}"] for h in self.history]),
                                     {"units": "m2", "long_name": "worn cross-section area given "
                                      "by the wear law"})
        coords = {"step": ("step", steps)}
        for b in BODIES:
            dim = f"y_{b}"
            coords[dim] = (dim, self.initial[b].y, {"units": "m"})
            data[f"wear_depth_{b}"] = (("step", dim),
                                       np.array([h[f"depth_{b}"] for h in self.history]),
                                       {"units": "m", "long_name": "wear depth of the step"})
            data[f"profile_z_{b}"] = (("step", dim), np.array([h[f"z_{b}"] for h in self.history]),
                                      {"units": "m", "long_name": "profile height after the step"})
        return xr.Dataset(data, coords=coords,
                          attrs={"law": self.sc.law, "worn_body": self.sc.body,
                                 "total_distance_m": float(self.distance)})
