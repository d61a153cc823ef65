"""Closed-loop wear scenarios: a vehicle and a route mix (``[vehicle]``, ``[[route]]``).

A scenario file holds the profile sections of a case file (``[wheel]``, ``[rail]``,
``[track]``, ``[material]``, ``[friction]``, ``[solver]``: the local contact model of
the post-processing), the vehicle (``[vehicle]``, as for ``railcontact simulate``),
the settings of the dynamics runs (``[dynamics]``), the wear law and the step
control (``[wear]``) and the load collective: ``[[route]]`` items, each a piece of
track with its design, speed, friction, irregularities, simulated length and weight
(its share of the distance).  See ``docs/wear.md``.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field, fields
from pathlib import Path

from ..cases.case import Case
from ..dynamics.scenario import (creep_law_settings, route_from_section, vehicle_from_section,
                                 vehicle_length)
from ..core.errors import CaseFileError
from ..core.parallel import check_scheduler
from .laws import get_wear_law

#: keys of [wear] in a vehicle scenario
WEAR_KEYS = {"law", "parameters", "body", "steps", "max_depth_per_step", "step_distance",
             "smoothing", "profile_smoothing", "grid_step", "scheduler", "wheels",
             "sample_distance", "reuse_tolerance", "rail_traffic", "records"}
#: keys of [dynamics]
DYNAMICS_KEYS = {"tangential", "tangential_options", "fastsim_grid", "sample_rate",
                 "table_range", "table_step", "integrator", "step", "rtol",
                 "initial_lateral_shift"}
#: keys of one [[route]] item
ROUTE_KEYS = {"name", "weight", "speed", "friction", "length", "segment", "irregularities",
              "radius", "cant", "transition", "lead"}
#: numeric [wear] settings: (key, low, high); "steps" is an integer
WEAR_RANGES = (("steps", 1, 100000), ("max_depth_per_step", 1e-9, 1e-2),
               ("smoothing", 0.0, 0.05), ("profile_smoothing", 0.0, 0.05),
               ("grid_step", 1e-6, 1e-3), ("step_distance", 1e-6, 1e12))
WHEEL_MODES = ("vehicle", "side", "individual")


def number(section: dict, name: str, key: str, default, lo: float, hi: float) -> float:
    """``section[key]`` (or ``default``) as a float in [lo, hi]; CaseFileError naming
    ``name.key`` otherwise."""
    v = section.get(key, default)
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not lo <= v <= hi:
        raise CaseFileError(f"{name}.{key} = {v!r}: expected a value in [{lo:g}, {hi:g}]")
    return float(v)


@dataclass(kw_only=True)
class WearSettings:
    """The [wear] settings common to the open-loop and the closed-loop scenario
    (set from a file by :func:`apply_wear_settings`).

    Attributes
    ----------
    law : str                   wear law by name (:func:`~railcontact.wear.get_wear_law`)
    parameters : dict           the law's parameters
    body : str                  what wears: "wheel", "rail" or "both"
    steps : int                 number of wear steps
    max_depth_per_step : float  largest depth of a worn profile per step [m]
    step_distance : float       fixed distance per step instead [m] (None: by depth)
    smoothing : float           length of the Gaussian smoothing of the depth [m]
    profile_smoothing : float   smoothing spline of the worn profiles [m] (0: none)
    grid_step : float           arc-length resolution of the wear distributions [m]
    scheduler : str             Dask scheduler ("threads", "processes", "sync" or an address)
    base_dir : Path             folder that relative paths of the scenario start from
    distances : list            imposed step distances [m] (None: by the step control)
    """

    law: str = "frictional-power"
    parameters: dict = field(default_factory=dict)
    body: str = "wheel"
    steps: int = 5
    max_depth_per_step: float = 1e-4
    step_distance: float | None = None
    smoothing: float = 2e-3
    profile_smoothing: float = 0.0
    grid_step: float = 1e-4
    scheduler: str = "threads"
    base_dir: Path = field(default_factory=Path.cwd)
    #: imposed step distances [m] (wear-compare runs every model over the first's)
    distances: list | None = None

    def identity(self) -> dict:
        """The settings that decide the results (a checkpoint must match them)."""
        return {f.name: getattr(self, f.name) for f in fields(WearSettings)}


def apply_wear_settings(target, wear: dict) -> None:
    """The [wear] settings common to both scenario kinds, validated, set on ``target``
    (law, parameters, body, scheduler and the numbers of ``WEAR_RANGES``)."""
    if "max_depth_per_step" in wear and "step_distance" in wear:
        raise CaseFileError("wear: give max_depth_per_step (the step chosen by the depth) or "
                            "step_distance (a fixed step), not both")
    for key in ("law", "body", "scheduler"):
        if key in wear:
            setattr(target, key, str(wear[key]))
    if "scheduler" in wear:
        check_scheduler(target.scheduler, "wear.scheduler")
    target.parameters = dict(wear.get("parameters", {}))
    for key, lo, hi in WEAR_RANGES:
        if key in wear:
            v = number(wear, "wear", key, None, lo, hi)
            setattr(target, key, int(v) if key == "steps" else v)
    if target.body not in ("wheel", "rail", "both"):
        raise CaseFileError(f"wear.body = {target.body!r}: expected 'wheel', 'rail' or 'both'")
    get_wear_law(target.law, **target.parameters)          # fail early on a bad law


@dataclass
class RouteItem:
    """One route of the load collective.

    Attributes
    ----------
    name : str
    route : railcontact.dynamics.Route
        Design geometry and irregularities.
    speed : float       vehicle speed [m/s]
    friction : float    friction coefficient of the route (dynamics and local contact)
    length : float      distance the vehicle runs on it per simulation [m]
    weight : float      share of the distance (normalised over the routes)
    """

    name: str
    route: object
    speed: float
    friction: float
    length: float
    weight: float

    @property
    def duration(self) -> float:
        return self.length / self.speed


@dataclass
class VehicleWearScenario(WearSettings):
    """A validated closed-loop wear scenario (see the module docstring)."""

    case: Case
    model: object
    routes: list
    dynamics: dict
    wheels: str = "vehicle"
    sample_distance: float = 1.0
    reuse_tolerance: float = 1e-3
    rail_traffic: float = 1.0
    records: bool = False
    title: str = ""
    #: the [vehicle], [[route]] and [dynamics] sections as read
    sections: dict = field(default_factory=dict)

    def identity(self) -> dict:
        """The settings a checkpoint must match (:meth:`WearSettings.identity`): the
        case sections (but the title), the vehicle, the routes, the dynamics and the
        closed loop's [wear] keys."""
        case = {k: v for k, v in self.case.raw.items() if k != "title"}
        return {**super().identity(), "case": case, **self.sections,
                "dynamics_settings": self.dynamics, "wheels": self.wheels,
                "sample_distance": self.sample_distance,
                "reuse_tolerance": self.reuse_tolerance, "rail_traffic": self.rail_traffic}

    @property
    def normal(self) -> str:
        return self.case.normal

    @property
    def tangential(self) -> str:
        return self.case.tangential

    def driver(self, out_dir=None, progress: bool = True):
        """The closed-loop wear run of this scenario
        (:class:`~railcontact.wear.closed_loop.ClosedLoopWear`)."""
        from .closed_loop import ClosedLoopWear
        return ClosedLoopWear(self, out_dir, progress)

    def with_models(self, normal: str | None = None, tangential: str | None = None):
        """A copy with other local contact models (the ``[solver]`` keys)."""
        out = copy.copy(self)
        out.case = self.case.with_models(normal, tangential)
        if out.case.tangential == "none":
            raise CaseFileError("wear needs a tangential model (solver.tangential is 'none')")
        return out


def is_vehicle_scenario(raw: dict) -> bool:
    """Whether a parsed wear scenario is a closed-loop one (has [vehicle] or [[route]])."""
    return "vehicle" in raw or "route" in raw


#: the sections of a closed-loop wear scenario that are not a case's
VEHICLE_SCENARIO_SECTIONS = ("vehicle", "route", "dynamics", "wear", "condition")


def vehicle_scenario_from_sections(sections: dict, base_dir, read_case) -> VehicleWearScenario:
    """Validate a closed-loop wear scenario (nothing is computed): its own sections
    (:data:`VEHICLE_SCENARIO_SECTIONS`, with ``title``) here, then its case sections by
    ``read_case()``,
    which returns them parsed (a :class:`~railcontact.cases.case.Case`: the front end
    :func:`railcontact.inputs.wear_scenario_from_dict` reads them)."""
    raw = copy.deepcopy(sections)
    base_dir = Path(base_dir or Path.cwd())
    veh = raw.pop("vehicle", {})
    routes = raw.pop("route", None)
    dyn = raw.pop("dynamics", {})
    wear = raw.pop("wear", {})
    for name, sec in (("vehicle", veh), ("dynamics", dyn), ("wear", wear)):
        if not isinstance(sec, dict):
            raise CaseFileError(f"[{name}] must be a table")
    for name, sec, keys in (("wear", wear, WEAR_KEYS), ("dynamics", dyn, DYNAMICS_KEYS)):
        bad = set(sec) - keys
        if bad:
            raise CaseFileError(f"unknown key(s) {name}.{sorted(bad)}; expected {sorted(keys)}")
    if "condition" in raw or "history" in wear:
        raise CaseFileError("a vehicle wear scenario takes its operating conditions from the "
                            "dynamics of its [[route]] items; remove [[condition]] / "
                            "wear.history")
    if not isinstance(routes, list) or not routes:
        raise CaseFileError("missing [[route]] items; expected at least one route (segments "
                            "or radius, speed, length, weight)")
    model = vehicle_from_section(veh, base_dir)
    case = read_case()
    if case.is_bodies:
        raise CaseFileError("a wear scenario needs [wheel] and [rail] profiles, not [bodies]")
    if case.tangential == "none":
        raise CaseFileError("wear needs a tangential model (solver.tangential is 'none')")
    tang, grid, integ = creep_law_settings(dyn, "dynamics")
    dynamics = {"tangential": tang, "tangential_options": dict(dyn.get("tangential_options", {})),
                "fastsim_grid": grid, "integrator": integ,
                "sample_rate": number(dyn, "dynamics", "sample_rate", 100.0, 1.0, 1e5),
                "table_range": number(dyn, "dynamics", "table_range", 0.012, 1e-3, 0.03),
                "table_step": number(dyn, "dynamics", "table_step", 2e-4, 1e-5, 1e-3),
                "step": number(dyn, "dynamics", "step", 1e-3, 1e-6, 1e-2),
                "rtol": number(dyn, "dynamics", "rtol", 1e-6, 1e-12, 1e-2),
                "initial_lateral_shift": number(dyn, "dynamics", "initial_lateral_shift", 0.0,
                                                -0.015, 0.015)}
    items = [_route_item(r, i, base_dir, case.friction, vehicle_length(model))
             for i, r in enumerate(routes)]
    names = [r.name for r in items]
    if len(set(names)) != len(names):
        raise CaseFileError(f"route names {names}: expected distinct names")
    sc = VehicleWearScenario(case=case, model=model, routes=items, dynamics=dynamics,
                             title=str(raw.get("title", "")), base_dir=base_dir,
                             sections={"vehicle": veh, "route": routes, "dynamics": dyn})
    apply_wear_settings(sc, wear)
    if "wheels" in wear:
        sc.wheels = str(wear["wheels"])
    if sc.wheels not in WHEEL_MODES:
        raise CaseFileError(f"wear.wheels = {sc.wheels!r}: expected one of {list(WHEEL_MODES)}")
    sc.sample_distance = number(wear, "wear", "sample_distance", 1.0, 1e-3, 1e3)
    sc.reuse_tolerance = number(wear, "wear", "reuse_tolerance", 1e-3, 0.0, 0.05)
    sc.rail_traffic = number(wear, "wear", "rail_traffic", 1.0, 1e-9, 1e9)
    sc.records = wear.get("records", False)
    if not isinstance(sc.records, bool):
        raise CaseFileError(f"wear.records = {sc.records!r}: expected true or false")
    return sc


def _route_item(r, i: int, base_dir: Path, friction: float, vehicle_length: float) -> RouteItem:
    """One [[route]] item: segments (``[[route.segment]]``, as in ``railcontact
    simulate``) or the shorthand ``radius``, ``cant``, ``transition``, ``lead``."""
    if not isinstance(r, dict):
        raise CaseFileError(f"route {i + 1}: expected a table")
    name = str(r.get("name", f"route {i + 1}"))
    where = f"route {name!r}"
    bad = set(r) - ROUTE_KEYS
    if bad:
        raise CaseFileError(f"{where}: unknown key(s) {sorted(bad)}; expected {sorted(ROUTE_KEYS)}")
    speed = number(r, where, "speed", None if "speed" in r else 30.0, 0.1, 200.0)
    weight = number(r, where, "weight", 1.0, 0.0, 1e9)
    if not weight > 0:
        raise CaseFileError(f"{where}.weight = {weight!r}: expected a share > 0")
    mu = number(r, where, "friction", friction, 1e-3, 2.0)
    short = {"radius", "cant", "transition", "lead"} & set(r)
    if short and "segment" in r:
        raise CaseFileError(f"{where}: give either [[route.segment]] items or the shorthand "
                            f"{sorted(short)}, not both")
    if "segment" in r:
        segs = r["segment"]
        if not isinstance(segs, list) or not segs:
            raise CaseFileError(f"{where}: [[route.segment]] must be a list of segments")
        total = sum(float(s["length"]) for s in segs if isinstance(s, dict)
                    and isinstance(s.get("length"), (int, float)))
        # by default the vehicle runs until its last wheelset reaches the route's end
        length = number(r, where, "length", total - vehicle_length
                        if total > vehicle_length + 1.0 else None, 1.0, 1e6)
    else:
        length = number(r, where, "length", 100.0, 1.0, 1e6)
        segs = _shorthand(r, where, vehicle_length, length)
    sec = {"segment": segs}
    if "irregularities" in r:
        sec["irregularities"] = r["irregularities"]
    try:
        route = route_from_section(sec, base_dir, length + vehicle_length + 10.0)
    except CaseFileError as exc:
        raise CaseFileError(f"{where}: {exc}") from None
    return RouteItem(name, route, speed, mu, length, weight)


def _shorthand(r: dict, where: str, vehicle_length: float, length: float) -> list:
    """Segments of the shorthand for a run of ``length`` [m]: a tangent ``lead``
    (default: the vehicle's length plus 10 m, so that it starts on tangent track), a
    ``transition`` (default 0: none) and a curve of ``radius`` and ``cant`` over the
    rest (tangent track without ``radius``)."""
    lead = number(r, where, "lead", vehicle_length + 10.0, 0.0, 1e6)
    total = length + vehicle_length
    if "radius" not in r:
        if "cant" in r or "transition" in r:
            raise CaseFileError(f"{where}: cant and transition belong to a curve; give radius")
        return [{"type": "tangent", "length": total + 1.0}]
    radius = r["radius"]
    if isinstance(radius, bool) or not isinstance(radius, (int, float)) or abs(radius) < 10 \
            or math.isinf(radius):
        raise CaseFileError(f"{where}.radius = {radius!r}: expected |radius| >= 10 m (positive: "
                            "curve to the right)")
    trans = number(r, where, "transition", 0.0, 0.0, 1e5)
    cant = number(r, where, "cant", 0.0, 0.0, 0.3)
    segs = [{"type": "tangent", "length": max(lead, 1.0)}]
    if trans > 0:
        segs.append({"type": "transition", "length": trans})
    rest = total - lead - trans
    if rest <= 1.0:
        raise CaseFileError(f"{where}: length {length:g} m leaves no curve after the lead "
                            f"({lead:g} m) and transition ({trans:g} m) with the vehicle "
                            f"({vehicle_length:g} m long); make it longer")
    segs.append({"type": "curve", "radius": float(radius), "cant": cant, "length": rest + 1.0})
    return segs
