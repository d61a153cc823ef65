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
import logging
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..cases.bodies import build_wheelset_track
from ..cases.case import Case
from ..cases.solve import solve
from ..core.checks import shown
from ..core.errors import CaseFileError, InputError
from ..core.parallel import compute
from ..core.progress import TqdmCallback
from .driver import StepLoads, Variable, WearDriver, WornBody
from .laws import get_wear_law
from .mapping import profile_depth, strip_depth
from .vehicle_scenario import WearSettings, apply_wear_settings, number

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
    dict as read), its operating conditions with their weights (``conditions``, as
    read), each condition's parsed case (``cases``) and the rail passages per metre
    of wheel travel."""

    base: dict
    rail_passages_per_meter: float = 1.0
    conditions: list = field(default_factory=list)
    cases: list = field(default_factory=list)

    def identity(self) -> dict:
        """The settings a checkpoint must match (:meth:`WearSettings.identity`), the
        base case and the conditions."""
        return {**super().identity(), "base": self.base, "conditions": self.conditions,
                "rail_passages_per_meter": self.rail_passages_per_meter}

    def driver(self, out_dir=None, progress: bool = True) -> "WearSimulation":
        """The wear run of this scenario (:class:`WearSimulation`)."""
        return WearSimulation(self, out_dir, progress)

    def with_models(self, normal: str | None = None, tangential: str | None = None):
        """A copy with other local contact models (the ``[solver]`` keys); an unknown
        name is an error here, before any work."""
        if not (normal or tangential):
            return self
        out = copy.copy(self)
        out.cases = [c.with_models(normal, tangential) for c in self.cases]
        out.base = copy.deepcopy(self.base)
        out.base["solver"] = dict(out.cases[0].raw.get("solver", {}))
        if out.cases[0].tangential == "none":
            raise CaseFileError("wear needs a tangential model (solver.tangential is 'none')")
        return out


#: the sections of an open-loop wear scenario that are not a case's
WEAR_SCENARIO_SECTIONS = ("wear", "condition")


def scenario_from_sections(sections: dict, base_dir, read_base) -> WearScenario:
    """Validate an open-loop wear scenario (nothing is computed): its ``[wear]`` and
    ``[[condition]]`` tables (``sections``) here, then its base case by
    ``read_base()``, which returns it parsed (a :class:`~railcontact.cases.case.Case`:
    the front end :func:`railcontact.inputs.wear_scenario_from_dict` reads it); every
    condition's case is checked here, before any work."""
    wear = copy.deepcopy(sections.get("wear", {}))
    conds = copy.deepcopy(sections.get("condition"))
    if not isinstance(wear, dict):
        raise CaseFileError("[wear] must be a table")
    if "history" in wear:
        if conds:
            raise CaseFileError("give either [[condition]] tables or wear.history, not both")
        conds = read_history(Path(base_dir or Path.cwd()) / str(wear["history"]),
                             wear.get("history_stride", 1))
    unknown = set(wear) - _WEAR_KEYS
    if unknown:
        raise CaseFileError(f"unknown key(s) wear.{sorted(unknown)}; expected {sorted(_WEAR_KEYS)}")
    if not conds or not isinstance(conds, list):
        raise CaseFileError("missing [[condition]] tables; expected at least one operating "
                            "condition (lateral_shift, yaw, vertical_force, weight, ...)")
    for i, c in enumerate(conds):
        if not isinstance(c, dict):
            raise CaseFileError(f"condition {i + 1}: expected a table of wheelset keys")
        bad = set(c) - _COND_KEYS
        if bad:
            raise CaseFileError(f"condition {i + 1}: unknown key(s) {sorted(bad)}; expected "
                                f"{sorted(_COND_KEYS)}")
        w = c.get("weight", 1.0)
        if not (isinstance(w, (int, float)) and w > 0):
            raise CaseFileError(f"condition {i + 1}: weight = {w!r}; expected a value > 0")
    base = read_base()
    sc = WearScenario(base=copy.deepcopy(base.raw), conditions=conds,
                      base_dir=Path(base_dir or Path.cwd()))
    apply_wear_settings(sc, wear)
    sc.rail_passages_per_meter = number(wear, "wear", "rail_passages_per_meter", 1.0, 1e-9, 1e3)
    sc.cases = [base.with_values(_condition_values(base, c)) for c in conds]
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
    if isinstance(stride, bool) or not isinstance(stride, int) or stride < 1:
        raise CaseFileError(f"wear.history_stride = {shown(stride)}: expected an integer >= 1")
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


def _condition_values(base: Case, cond: dict) -> dict:
    """The dotted case keys that an operating condition sets on the base case."""
    out = {}
    for k, v in cond.items():
        if k == "weight":
            continue
        if k == "curve_radius":
            # steady curving: the wheelset turns with the track at V / R (positive R:
            # curve to the right); cant enters through the per-wheel vertical loads
            if not (isinstance(v, (int, float)) and abs(v) >= 10.0):
                raise CaseFileError(f"condition curve_radius = {v!r}: expected |R| >= 10 m")
            vel = cond.get("velocity", base.raw.get("wheelset", {}).get("velocity", 30.0))
            out["wheelset.yaw_rate"] = float(vel) / float(v)
        elif k == "creepage":
            out["creepage"] = dict(v)
        else:
            out[f"wheelset.{k}"] = v
    return out


def _on_profiles(case: Case, profiles: dict) -> Case:
    """A condition's case on the current (worn) profiles; worn rails are kept as
    mounted (inclination 0)."""
    return case.with_values({"wheel.profile": profiles["wheel_right"],
                             "wheel.profile_left": profiles["wheel_left"],
                             "rail.profile": profiles["rail_right"],
                             "rail.profile_left": profiles["rail_left"],
                             "rail.inclination": 0.0})


def condition_wear(case: Case, law_name: str, law_params: dict, grids: dict,
                   profiles: dict) -> dict:
    """Wear of one operating condition (its case on the current profiles): depth per
    revolution (wheels) and per passage (rails) on the s-grids, the rolling radii, and
    the frictional energy [J/m]."""
    law = get_wear_law(law_name, **law_params)
    res = solve(case)
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


class WearSimulation(WearDriver):
    """A wear run under fixed operating conditions (or a recorded history): the
    :class:`~railcontact.wear.driver.WearDriver` whose loads are the conditions
    solved on the current profiles (see the module docstring).

    Parameters
    ----------
    scenario : WearScenario
    out_dir : path, optional
        Folder of ``wear.nc`` and ``checkpoint.nc``.
    progress : bool
        Progress bars over the steps and the conditions.
    """

    def __init__(self, scenario: WearScenario, out_dir=None, progress: bool = True):
        super().__init__(scenario, out_dir, progress)
        case = scenario.cases[0]
        ws, tr = build_wheelset_track(case)
        self.profiles = {"wheel_left": ws.wheel_left, "wheel_right": ws.wheel_right,
                         "rail_left": tr.rail_left, "rail_right": tr.rail_right}
        self.initial = dict(self.profiles)
        self.models = (case.normal, case.tangential)

    # ------------------------------------------------------------ profiles
    def slots(self) -> list:
        return list(BODIES)

    def profile(self, slot):
        return self.profiles[slot]

    def set_profile(self, slot, profile) -> None:
        self.profiles[slot] = profile

    def initial_profiles(self) -> list:
        return [self.initial[b] for b in BODIES]

    # ------------------------------------------------------------ one step
    def loads(self, grid_of: dict) -> StepLoads:
        """Every condition solved on the current profiles (a Dask graph); the wear per
        metre run of each worn body is their weighted mean."""
        import dask
        sc = self.sc
        grids = {b: grid_of[id(self.profiles[b])] for b in BODIES}
        w = np.array([c.get("weight", 1.0) for c in sc.conditions], dtype=float)
        w /= w.sum()
        cases = [_on_profiles(c, self.profiles) for c in sc.cases]
        tasks = [dask.delayed(condition_wear)(c, sc.law, sc.parameters, grids, self.profiles)
                 for c in cases]
        bar = TqdmCallback(len(cases), f"wear step {self.step + 1}", prefix="condition_wear",
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
        bodies = [WornBody(b.split("_")[0], self.profiles[b], grids[b], per_m[b],
                           self.initial[b].y, [b]) for b in BODIES if self._worn(b)]
        return StepLoads(bodies, {"energy": energy, "not_converged":
                                  float(sum(not r["converged"] for r in results))})

    def _worn(self, body_key):
        return self.sc.body in (body_key.split("_")[0], "both")

    def record(self, rec: dict, worn: list) -> None:
        """Depth, areas and profile height of the four bodies on their new profiles'
        lateral positions (zero for a body that does not wear)."""
        for b in BODIES:
            y = self.initial[b].y
            rec[f"wear_depth_{b}"] = np.zeros_like(y)
            rec[f"law_area_{b}"] = rec[f"removed_area_{b}"] = 0.0
        for w in worn:
            (b,) = w.body.slots
            rec[f"wear_depth_{b}"] = w.depth_on_y
            rec[f"law_area_{b}"] = w.law_area
            rec[f"removed_area_{b}"] = w.removed_area
        for b in BODIES:
            rec[f"profile_z_{b}"] = self.profiles[b].z_at(self.initial[b].y)

    # ------------------------------------------------------------ outputs
    def variables(self) -> tuple:
        out = [Variable("distance", (), "m", "distance of the step"),
               Variable("energy", (), "J m-1", "weighted frictional energy per metre"),
               Variable("not_converged", (), "1", "conditions whose solve did not converge"),
               Variable("wall_time", (), "s", "wall time of the step")]
        for b in BODIES:
            dim = (f"y_{b}",)
            out += [Variable(f"law_area_{b}", (), "m2", "worn cross-section area given by "
                             "the wear law"),
                    Variable(f"removed_area_{b}", (), "m2", "cross-section area between the "
                             "profiles before and after the step"),
                    Variable(f"wear_depth_{b}", dim, "m", "wear depth of the step"),
                    Variable(f"profile_z_{b}", dim, "m", "profile height after the step")]
        return tuple(out)

    def coords(self) -> dict:
        return {f"y_{b}": (f"y_{b}", self.initial[b].y, {"units": "m"}) for b in BODIES}

    def attrs(self) -> dict:
        return {"law": self.sc.law, "worn_body": self.sc.body, "normal": self.models[0],
                "tangential": self.models[1]}
