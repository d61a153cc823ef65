"""One contact case from end to end: :func:`solve` and its result types."""

from __future__ import annotations

import json
import logging
import math
import time
from dataclasses import dataclass, field

import numpy as np

from .case import Case, body_curvatures
from .case_surfaces import is_surface_case
from .errors import ContactNotFoundError
from .geometry.contact import ContactGeometry
from .geometry.locus import min_gap
from .geometry.search import WheelsetContact, find_contact
from .geometry.track import SIDES, Track, Wheelset, WheelsetPose
from .geometry.validity import HALF_SPACE_LIMIT, contact_size, patch_validity
from .normal import NormalSolution, get_normal_model
from .profiles.library import DEFAULT_INCLINATION, RAIL_PROFILES, get_profile
from .status import SolverStatus
from .tangential import TangentialSolution, get_tangential_model

log = logging.getLogger(__name__)


@dataclass
class PatchResult:
    """Geometry, normal and tangential solution of one contact patch.

    ``validity`` says where the patch leaves the range of its models (flange climb,
    derailment, a patch large against the radii of curvature:
    :mod:`railcontact.geometry.validity`); ``halfspace_ratio`` is the patch's size
    against those radii (NaN where not evaluated)."""

    geometry: ContactGeometry
    normal: NormalSolution
    tangential: TangentialSolution | None
    creepage: tuple
    validity: SolverStatus = field(default_factory=SolverStatus)
    halfspace_ratio: float = math.nan

    @property
    def status(self) -> SolverStatus:
        """The patch's solutions and validity combined."""
        label = f"{self.geometry.side} patch" if self.geometry.side else "patch"
        return SolverStatus.combine([
            (f"{label}, {self.normal.model} normal", self.normal.status),
            (f"{label}, {self.tangential.model} tangential" if self.tangential else "",
             self.tangential.status if self.tangential is not None else None),
            ("", self.validity)])

    def to_dict(self) -> dict:
        """The JSON patch contract of ``DESIGN.md`` (SI units) plus extra keys."""
        g, n, t = self.geometry, self.normal, self.tangential
        d = {"side": g.side, "area": n.area, "pmax": n.pmax, "penetration": n.penetration,
             "Fn": n.normal_force, "Fx": t.fx if t else 0.0, "Fy": t.fy if t else 0.0,
             "Mz": t.mz if t else 0.0, "contact_angle": float(g.contact_angle),
             "rolling_radius": _f(g.rolling_radius), "y_rail": _f(g.y_rail),
             "y_wheel": _f(g.y_wheel),
             "creepage": {"longitudinal": self.creepage[0], "lateral": self.creepage[1],
                          "spin": self.creepage[2]}}
        if n.semi_axes is not None:
            d["semi_axes"] = [float(n.semi_axes[0]), float(n.semi_axes[1])]
        d["curvatures"] = [float(c) for c in g.curvatures]
        if t is not None:
            d["stick_fraction"] = t.stick_fraction
            d["frictional_power"] = t.frictional_power
        d["halfspace_ratio"] = _f(self.halfspace_ratio)
        if math.isfinite(getattr(n, "pressure_limit", math.inf)):
            d["pressure_limit"] = n.pressure_limit
            d["plastic_area"] = n.plastic_area
        return d


@dataclass
class VerticalBalance:
    """How the vertical-force iteration of a wheel-rail case ended.

    Attributes
    ----------
    converged : bool
        Whether each side's vertical force met its load to ``solver.force_tolerance``.
    force_jump : bool
        Whether the iteration stopped where the model's vertical force jumps across
        the load (a strip entering the contact): then no interpenetration carries it.
    passes : int
        How many times the patches' normal problems were solved (each pass one
        contact search).
    residual : dict
        Relative residual (F_z - Q)/Q [-] of each side's balance.
    standin : list of PatchResult or None
        The Hertz + FASTSIM patch results whose F_y/F_n stood in for the lateral
        forces before the tangential solutions (a warm start of a neighbouring case
        corrects them by its own, :class:`_CorrectedRatio`).
    """

    converged: bool
    force_jump: bool
    passes: int
    residual: dict
    standin: list | None = field(default=None, repr=False)

    @property
    def status(self) -> SolverStatus:
        """The balance as a :class:`SolverStatus` (iterations: the passes)."""
        if self.converged:
            return SolverStatus(True, "", self.passes)
        worst = max(abs(v) for v in self.residual.values()) if self.residual else math.nan
        why = ("the model's vertical force jumps across the load" if self.force_jump
               else f"not met after {self.passes} passes")
        return SolverStatus.failed(f"{why}; the wheel load is missed by {worst:.2g} of it",
                                   self.passes)


@dataclass
class SolveResult:
    """All patches of one case, with the models used and the CPU time; for a
    wheel-rail case also the contact search's result (``contact``: wheelset pose,
    patch geometries, loci) and how the vertical-force iteration ended
    (``balance``)."""

    patches: list
    normal: str
    tangential: str
    cpu_time: float
    title: str = ""
    pose: WheelsetPose | None = None
    contact: WheelsetContact | None = field(default=None, repr=False)
    balance: VerticalBalance | None = field(default=None, repr=False)

    @property
    def status(self) -> SolverStatus:
        """The case's status: the vertical balance's and every patch's solutions and
        validity combined (:meth:`SolverStatus.combine`), so that no unconverged part
        hides behind a converged whole."""
        parts = [("vertical balance", self.balance.status if self.balance else None)]
        parts += [("", p.status) for p in self.patches]
        return SolverStatus.combine(parts)

    @property
    def converged(self) -> bool:
        """False when the vertical-force iteration did not meet the load to its
        tolerance (also where the model's force jumps across it: then
        ``balance.force_jump``), a solver or the normal-tangential coupling did not
        converge, or a wheel derailed (``status.message`` says which)."""
        return self.status.converged

    @property
    def warnings(self) -> list:
        """Where the result leaves the range of its models (``status.warnings``)."""
        return list(self.status.warnings)

    @property
    def vertical_residual(self) -> dict | None:
        """Relative residual (F_z - Q)/Q [-] of each side's vertical balance for a
        wheel-rail case (None for a bodies case): within ``solver.force_tolerance``
        unless the model's force jumps across the load (see ``docs/case_files.md``)."""
        return self.balance.residual if self.balance is not None else None

    def to_dict(self) -> dict:
        status = self.status
        d = {"patches": [p.to_dict() for p in self.patches], "normal": self.normal,
             "tangential": self.tangential, "cpu_time": self.cpu_time,
             "converged": status.converged, "message": status.message,
             "warnings": list(status.warnings)}
        if self.vertical_residual is not None:
            d["vertical_residual"] = dict(self.vertical_residual)
        return d

    def to_json(self, **kw) -> str:
        return json.dumps(self.to_dict(), **kw)

    def to_xarray(self):
        """Patch results as an :class:`xarray.Dataset` along a ``patch`` dimension."""
        import xarray as xr
        rows = [p.to_dict() for p in self.patches]
        units = {"area": "m2", "pmax": "Pa", "penetration": "m", "Fn": "N", "Fx": "N",
                 "Fy": "N", "Mz": "N m", "contact_angle": "rad", "rolling_radius": "m",
                 "y_rail": "m", "y_wheel": "m"}
        data = {k: ("patch", np.array([np.nan if r[k] is None else r[k] for r in rows], float),
                    {"units": u}) for k, u in units.items()}
        for c, u in (("longitudinal", "1"), ("lateral", "1"), ("spin", "m-1")):
            data[f"creepage_{c}"] = ("patch", np.array([r["creepage"][c] for r in rows]),
                                     {"units": u})
        return xr.Dataset(data, coords={"side": ("patch", [str(r["side"]) for r in rows])},
                          attrs={"normal_model": self.normal, "tangential_model": self.tangential,
                                 "title": self.title})


def _f(v):
    v = float(v)
    return None if math.isnan(v) else v


def build_wheelset_track(case: Case):
    """Wheelset and track of a wheel-rail case."""
    base = case.base_dir
    kw = {}
    for body in ("wheel", "rail"):
        # a profile file's options (mirroring, scale, smoothing, ...) and length unit
        options, units = case.profile_options(body)
        kw[body] = {"base_dir": base, "units": units,
                    **({"options": options} if options is not None else {})}
    wheel = get_profile(case.get("wheel.profile", "S1002"), "wheel", **kw["wheel"])
    wl = case.get("wheel.profile_left")
    wheel_left = get_profile(wl, "wheel", **kw["wheel"]) if wl else None
    incl = case.get("rail.inclination")
    rail = get_profile(case.get("rail.profile", "60E1"), "rail", inclination=incl, **kw["rail"])
    rl = case.get("rail.profile_left")
    rail_left = get_profile(rl, "rail", inclination=incl, **kw["rail"]) if rl else None
    ws = Wheelset(wheel, wheel_left, nominal_radius=case.number("wheel.nominal_radius", 0.46),
                  flange_back_distance=case.number("wheelset.flange_back_distance", 1.360),
                  flange_back_position=case.number("wheelset.flange_back_position", -0.070))
    offset = case.get("track.rail_offset")
    tr = Track(rail, rail_left, gauge=case.number("track.gauge", 1.435),
               gauge_height=case.number("track.gauge_height", 0.014),
               rail_offsets=None if offset is None else {s: float(offset) for s in SIDES})
    return ws, tr


def contact_search(case: Case, interpenetration: dict | None = None,
                   bodies=None, roll_start: float = 0.0,
                   load_iterations: int = 10) -> WheelsetContact:
    """Geometry layer only: wheelset position and contact patches of a wheel-rail case.

    ``bodies`` = (Wheelset, Track) built once by the caller, else built here;
    ``roll_start`` the roll [rad] where the search starts (an earlier search's);
    ``load_iterations`` as in :func:`railcontact.geometry.find_contact`.
    """
    ws, tr = bodies or build_wheelset_track(case)
    pv = case.get("wheelset.pitch_velocity")
    roll = case.get("wheelset.roll")
    fid = case.get("wheelset.full_interaction_distance")
    combine = case.number("wheelset.combine_distance", 0.0, 0.0, 0.1)
    return find_contact(ws, tr, case.number("wheelset.lateral_shift", 0.0),
                        case.number("wheelset.yaw", 0.0),
                        vertical_force=(case.wheel_loads()["left"], case.wheel_loads()["right"]),
                        material=case.material, velocity=case.number("wheelset.velocity", 30.0),
                        pitch_velocity=None if pv is None else case.number("wheelset.pitch_velocity"),
                        lateral_velocity=case.number("wheelset.lateral_velocity", 0.0),
                        yaw_rate=case.number("wheelset.yaw_rate", 0.0),
                        combine_distance=combine,
                        full_interaction_distance=None if fid is None else case.number(
                            "wheelset.full_interaction_distance", 0.0, 0.0, combine,
                            "m (at most wheelset.combine_distance)"),
                        interpenetration=interpenetration,
                        roll=None if roll is None else case.number("wheelset.roll"),
                        side=case.get("wheelset.side", "both") if roll is not None else "both",
                        roll_start=roll_start if roll is None else 0.0,
                        load_iterations=load_iterations,
                        turn_distance=case.number("wheelset.turn_distance", 0.0),
                        separation_angle=case.number("wheelset.separation_angle", math.pi / 2))


def solve(case: Case, normal: str | None = None, tangential: str | None = None,
          warm_start: "SolveResult | None" = None) -> SolveResult:
    """Solve one contact case.

    Parameters
    ----------
    case : Case
        From :func:`railcontact.load_case` or :func:`railcontact.case.case_from_dict`.
    normal, tangential : str, optional
        Model names overriding the case's ``[solver]``.
    warm_start : SolveResult, optional
        The result of a similar case (the previous case of a sweep or time history):
        models that accept warm starts (the exact solvers) start from its patches'
        solutions (same side, within 3 mm on the rail) instead of cold.

    For wheel-rail cases the geometry layer finds the wheelset position under the
    vertical load and the patches; each patch is solved with its own penetration.
    A warm-started case that does not converge is solved again cold (except where
    the model's vertical force jumps across the load: ``balance.force_jump``).

    A case on rail surfaces (rails given by slices, several rails, a roller:
    :mod:`railcontact.surface_contact`) is solved by
    :func:`railcontact.surface_contact.solve_on_surfaces`.
    """
    from .surface_contact import solve_on_surfaces
    if not case.is_bodies and is_surface_case(case):
        return solve_on_surfaces(case, normal, tangential, warm_start=warm_start)
    if warm_start is not None:
        res = _solve(case, normal, tangential, warm_start)
        # a force that jumps across the load is the model's: a cold start meets it too
        if res.converged or (res.balance is not None and res.balance.force_jump):
            return res
        log.info("warm-started case did not converge; solving it again cold")
        cold = _solve(case, normal, tangential, None)
        cold.cpu_time += res.cpu_time                 # the failed attempt counts
        return cold
    return _solve(case, normal, tangential, None)


def case_models(case, normal=None, tangential=None):
    """The normal and tangential models of a case (names overridden by ``normal``,
    ``tangential``; the case's options with its own names) and their grid keywords:
    (normal name, tangential name, normal model, tangential model or None, kw)."""
    nname = (normal or case.normal).lower()
    tname = (tangential or case.tangential).lower()
    nmodel = get_normal_model(nname, **(case.normal_options if normal is None else {}))
    tmodel = None if tname == "none" else get_tangential_model(
        tname, **(case.tangential_options if tangential is None else {}))
    return nname, tname, nmodel, tmodel, {"grid": case.grid, "element_size": case.element_size}


def _solve(case, normal, tangential, warm_start):
    """:func:`solve` with or without a warm start."""
    t0 = time.perf_counter()
    nname, tname, nmodel, tmodel, kw = case_models(case, normal, tangential)
    results, pose, contact, balance = [], None, None, None
    if case.is_bodies:
        A, B = body_curvatures(case)
        r = case.get("bodies.radii").get("wheel_rolling", math.nan)
        geom = ContactGeometry(curvatures=(A, B), rolling_radius=float(r))
        wkw = {}
        if warm_start is not None and warm_start.patches:
            if "warm-start" in nmodel.capabilities:
                wkw["warm_start"] = warm_start.patches[0].normal
        ns = nmodel.solve(geom, case.material, normal_force=case.number("bodies.normal_force"),
                          **kw, **wkw)
        creep = case.creepage or (0.0, 0.0, 0.0)
        V = case.number("bodies.velocity", 1.0, 1e-6, 1e3, "m/s")
        if _coupled(case, nmodel, tmodel) and "force" not in case.raw:
            from .coupling import solve_coupled
            ns, ts = solve_coupled(nmodel, tmodel, geom, case.material, creep, case.friction,
                                   V, normal_force=case.number("bodies.normal_force"), **kw)
        elif "force" in case.raw and tmodel is not None:
            from .tangential.inverse import solve_for_forces
            ts = solve_for_forces(tmodel, ns, geom, case.material,
                                  (case.number("force.longitudinal", 0.0),
                                   case.number("force.lateral", 0.0)),
                                  spin=creep[2], friction=case.friction, velocity=V)
            creep = ts.creepage
        else:
            tkw = {}
            if (warm_start is not None and warm_start.patches and tmodel is not None
                    and "warm-start" in tmodel.capabilities
                    and warm_start.patches[0].tangential is not None):
                tkw["warm_start"] = warm_start.patches[0].tangential
            ts = (tmodel.solve(ns, geom, case.material, creep, case.friction, V, **tkw)
                  if tmodel else None)
        results.append(_bodies_validity(case, PatchResult(geom, ns, ts, tuple(creep))))
    elif case.get("wheelset.vertical_position") is not None:
        results, contact = _solve_at_position(case, nmodel, tmodel, kw)
        pose = contact.pose
    else:
        results, contact, balance = _solve_wheel_rail(case, nmodel, tmodel, kw,
                                                      rtol=case.force_tolerance,
                                                      start=warm_start)
        pose = contact.pose
    return SolveResult(results, nname, tname, time.perf_counter() - t0, case.title, pose, contact,
                       balance)


def _solve_at_position(case, nmodel, tmodel, kw):
    """Patches of one wheel (``wheelset.side``) at a prescribed vertical position and
    roll of the wheelset (CONTACT's NORM = 0): the interpenetration follows from
    the position, and no vertical-force iteration runs.  Returns the patch results
    (none where the wheel does not reach the rail) and the contact search."""
    bodies = build_wheelset_track(case)
    ws, tr = bodies
    side = case.get("wheelset.side")
    y, yaw = case.number("wheelset.lateral_shift", 0.0), case.number("wheelset.yaw", 0.0)
    roll, z = case.number("wheelset.roll"), case.number("wheelset.vertical_position")
    # the deepest interpenetration: the wheel lowered from where it touches (gap g0
    # at z = 0) to z
    g0 = min_gap(ws, tr, side, y, 0.0, roll, yaw)
    if not math.isfinite(g0):
        raise ContactNotFoundError(f"no wheel-rail overlap found on the {side} side at lateral "
                                   f"shift {y * 1e3:.3f} mm")
    depth = z - g0
    if not depth > 0:
        log.info("the %s wheel at z = %.4f mm does not reach the rail (gap %.4f mm)", side,
                 z * 1e3, -depth * 1e3)
        return [], WheelsetContact(WheelsetPose(y, z, roll, yaw), [], {}, None, {side: 0.0})
    contact = contact_search(case, interpenetration={side: depth}, bodies=bodies)
    results = _solve_patches(case, contact, nmodel, tmodel, kw,
                             coupled=_coupled(case, nmodel, tmodel))
    results = [r for r in results if r.geometry.side == side]
    _wheel_rail_validity(results, bodies)
    return results, contact


def _bodies_validity(case, result: PatchResult) -> PatchResult:
    """A bodies case's patch with its size against the given radii (the larger of
    half-width / smallest lateral radius and half-length / smallest rolling radius;
    :mod:`railcontact.geometry.validity`)."""
    radii = case.get("bodies.radii")
    a, b = contact_size(result.normal)

    def smallest(*keys):
        return min(abs(float(radii.get(k, math.inf))) for k in keys)

    ratio = max(b / smallest("wheel_lateral", "rail_lateral"),
                a / smallest("wheel_rolling", "rail_rolling"))
    status = SolverStatus()
    if ratio > HALF_SPACE_LIMIT:
        status = status.with_warnings(f"half-space: the patch is large against the radii of "
                                      f"curvature (size/radius {ratio:.2f} > {HALF_SPACE_LIMIT})")
    result.validity, result.halfspace_ratio = status, ratio
    return result


def _wheel_rail_validity(results, bodies) -> None:
    """Flange climb, derailment and half-space checks of a wheel-rail case's patches
    (:func:`railcontact.geometry.validity.patch_validity`), stored in the results."""
    ws, tr = bodies
    for r in results:
        side = r.geometry.side
        derailed, warnings, ratio = patch_validity(r.geometry, r.normal, ws.wheel(side),
                                                   tr.rail(side))
        status = SolverStatus.failed(warnings[0]) if derailed else SolverStatus()
        r.validity = status.with_warnings(*warnings[1 if derailed else 0:])
        r.halfspace_ratio = ratio
        for w in warnings:
            log.info("%s", w)


def _coupled(case, nmodel, tmodel) -> bool:
    """Dissimilar materials with both exact models: solve the coupled problems."""
    if not case.material.is_dissimilar:
        return False
    if tmodel is not None and "coupled" in nmodel.capabilities & tmodel.capabilities:
        return True
    log.info("dissimilar materials: the %s/%s models use the combined constants G, nu, E*; "
             "the normal-tangential coupling needs normal = tangential = 'exact'",
             nmodel.name, tmodel.name if tmodel is not None else "none")
    return False


#: a previous patch serves as warm start for a patch within this lateral distance [m]
WARM_DISTANCE = 3e-3


def _nearest(previous, geom):
    """The previous patch result of the same side nearest to ``geom`` on the rail
    (within ``WARM_DISTANCE``), or None."""
    near = [r for r in previous or () if r.geometry.side == geom.side
            and abs(r.geometry.y_rail - geom.y_rail) <= WARM_DISTANCE]
    return min(near, key=lambda r: abs(r.geometry.y_rail - geom.y_rail)) if near else None


def _solve_patches(case, contact, nmodel, tmodel, kw, previous=None, normal_only=False,
                   coupled=False, same_case=False, kept=()):
    """Solve every loaded patch; ``previous`` results (an earlier iteration of the
    same case, or a neighbouring case of a sweep) serve as warm starts where a model
    accepts them.  ``normal_only``: leave the tangential problems to
    :func:`_add_tangential`.  ``coupled``: dissimilar materials with the exact
    models (:func:`_coupled`), both problems solved together.  ``same_case``:
    ``previous`` is an earlier pass of this case, whose grids a model may keep.
    ``kept``: results (of an earlier pass) taken as they are, for the patches of
    their sides."""
    out = []
    keep = {id(r.geometry): r for r in kept}
    nwarm = "warm-start" in nmodel.capabilities
    for geom in contact.patches:
        if id(geom) in keep:
            out.append(keep[id(geom)])
            continue
        if geom.approach <= 0:
            continue
        creep = _creepage(case, geom)
        if coupled:
            from .coupling import solve_coupled
            ns, ts = solve_coupled(nmodel, tmodel, geom, case.material, creep,
                                   _friction(case, geom), geom.velocity,
                                   penetration=geom.approach, **kw)
            out.append(PatchResult(geom, ns, ts, creep))
            continue
        nkw = dict(kw)
        best = _nearest(previous, geom) if nwarm else None
        if best is not None:
            nkw["warm_start"] = best.normal
            if same_case and getattr(nmodel, "reuses_grids", False):
                nkw["reuse_grid"] = best.normal
        ns = nmodel.solve(geom, case.material, penetration=geom.approach, **nkw)
        out.append(PatchResult(geom, ns, None, creep))
    if normal_only or coupled:
        return out
    return _add_tangential(case, out, tmodel, previous)


def _add_tangential(case, results, tmodel, previous=None):
    """The tangential solutions of patch results that have none (warm-started from
    the nearest of ``previous`` where the model accepts it)."""
    if tmodel is None:
        return results
    warm = "warm-start" in tmodel.capabilities
    out = []
    for r in results:
        if r.tangential is None:
            extra = {}
            best = _nearest(previous, r.geometry) if warm else None
            if best is not None and best.tangential is not None:
                extra["warm_start"] = best.tangential
            ts = tmodel.solve(r.normal, r.geometry, case.material, r.creepage,
                              _friction(case, r.geometry), r.geometry.velocity, **extra)
            r = PatchResult(r.geometry, r.normal, ts, r.creepage)
        out.append(r)
    return out


def _fast_estimate(case, contact):
    """Hertz + FASTSIM on the loaded patches (stand-in lateral forces)."""
    hz, fs = get_normal_model("hertz"), get_tangential_model("fastsim")
    out = []
    for g in contact.patches:
        if g.approach > 0:
            ns = hz.solve(g, case.material, penetration=g.approach, grid=(20, 20))
            creep = _creepage(case, g)
            out.append(PatchResult(g, ns, fs.solve(ns, g, case.material, creep,
                                                   _friction(case, g), g.velocity), creep))
    return out


def vertical_force_on_rail(results, side: str, lateral=None) -> float:
    """Total vertical force [N] the wheel exerts on the rail of one side (track z).

    On the rail, F_z = f_n cos(d) + f_s sin(d) with f_s = -F_y the lateral force on
    the rail (the patch results hold forces on the wheel).  A patch without a
    tangential solution takes the ratio F_y/F_n of the nearest of the results
    ``lateral`` (an earlier iteration; near saturation F_y follows F_n), else F_y = 0.
    """
    total = 0.0
    for r in results:
        if r.geometry.side == side:
            d = r.geometry.contact_angle
            fn = r.normal.normal_force
            if r.tangential is not None:
                fy = r.tangential.fy
            else:
                fy = _standin_ratio(lateral, r.geometry) * fn
            total += fn * math.cos(d) - fy * math.sin(d)
    return total


def _standin_ratio(lateral, geom) -> float:
    """F_y/F_n of the result among ``lateral`` nearest to the patch ``geom`` (see
    :func:`_nearest`), 0 without one; ``lateral`` may also be a function of the
    patch giving the ratio (:class:`_CorrectedRatio`)."""
    if callable(lateral):
        return lateral(geom)
    return _ratio(_nearest(lateral, geom))


def _ratio(result) -> float:
    """F_y/F_n of a patch result; 0 without one, its tangential solution or load."""
    if result is None or result.tangential is None or not result.normal.normal_force > 0:
        return 0.0
    return result.tangential.fy / result.normal.normal_force


class _CorrectedRatio:
    """Stand-in F_y/F_n of a warm-started case: the neighbouring case's solved ratio
    plus the change of Hertz + FASTSIM's ratio from the neighbour's patch to this
    one, r = r_neighbour + (r_HF - r_HF,neighbour).  FASTSIM's own error, 10 % of
    F_y, largely cancels: on the benchmark sweep the balance's stand-in term
    F_y sin(d) is then within 1e-4 F_n for 78 % of the patches (FASTSIM's alone for
    50 %), so fewer passes of the vertical-force iteration solve the tangential
    problems again.  Where a patch has no counterpart in either of the neighbour's
    lists, FASTSIM's ratio stands in alone."""

    def __init__(self, fast, neighbour, neighbour_fast):
        self.fast, self.neighbour, self.neighbour_fast = fast, neighbour, neighbour_fast

    def __call__(self, geom) -> float:
        r = _standin_ratio(self.fast, geom)
        a, b = _nearest(self.neighbour, geom), _nearest(self.neighbour_fast, geom)
        if a is None or b is None or a.tangential is None or b.tangential is None:
            return r
        return r + _ratio(a) - _ratio(b)


def _friction(case, geom) -> float:
    """The friction coefficient of a wheel-rail patch: ``friction.coefficient``, or
    ``friction.variation`` at the inclination of its rail surface in rail-profile
    coordinates (the contact angle in the side frame plus the rail's inclination;
    CONTACT's VARFRC = 1)."""
    if case.get("friction.variation") is None:
        return case.friction
    sgn = 1.0 if geom.side == "right" else -1.0
    incl = case.get("rail.inclination")
    if incl is None:
        incl = DEFAULT_INCLINATION if str(case.get("rail.profile", "60E1")).upper() in \
            RAIL_PROFILES else 0.0
    return case.friction_at(sgn * geom.contact_angle + float(incl))


def _creepage(case, geom) -> tuple:
    """The case's creepages where given, else the patch's kinematic ones."""
    return tuple(float(c) for c in (case.creepage or geom.creepage))


#: the vertical-force iteration solves the tangential problems once the balance with
#: stand-in lateral forces holds to this many times its tolerance (at least 1)
STANDIN_FACTOR = 10.0

#: the first step of the vertical-force iteration solves for the normal force on
#: sides with one loaded patch whose contact angle is below this [rad] (a flange's
#: interpenetration moves with the roll as much as with the height)
FORCE_STEP_ANGLE = 0.5


#: a side whose vertical balance holds keeps its patch results while the other side's
#: interpenetration is corrected, where the new contact search changed its patches
#: by under this: relative approach, contact angle [rad], relative creepages (the
#: side's vertical force then changes by a few of this relative to the load, far
#: below the balance's tolerance)
KEEP_TOLERANCE = 1e-6


def _unmoved(case, results, contact, side) -> bool:
    """Whether the side's loaded patches of ``contact`` are those of ``results`` to
    ``KEEP_TOLERANCE`` (as many; approach, contact angle, the creepages solved
    with): their solutions then hold for them."""
    old = [r for r in results if r.geometry.side == side]
    new = [g for g in contact.patches if g.side == side and g.approach > 0]
    if not old or len(old) != len(new):
        return False
    k = KEEP_TOLERANCE
    for r, g in zip(old, new):
        a = r.geometry
        if not (abs(a.approach - g.approach) <= k * a.approach
                and abs(a.contact_angle - g.contact_angle) <= k
                and all(abs(p - q) <= k * max(abs(p), 1e-3)
                        for p, q in zip(r.creepage, _creepage(case, g)))):
            return False
    return True


def _force_step(case, contact, nmodel, kw, loads, sides, lateral, previous):
    """First step of the vertical-force iteration: where every side has one loaded
    patch (contact angle below ``FORCE_STEP_ANGLE``), its normal problem solved for
    the normal force that carries the side's load with the stand-in lateral force,
    F_n = Q / (cos d - (F_y/F_n) sin d); the interpenetration of the side then moves
    by the change of approach over cos d.  Returns (interpenetrations, patch results)
    or None where the step does not apply."""
    warm = "warm-start" in nmodel.capabilities
    d, out = dict(contact.interpenetration), []
    for s in sides:
        pats = [g for g in contact.patches if g.side == s and g.approach > 0]
        if len(pats) != 1 or abs(pats[0].contact_angle) >= FORCE_STEP_ANGLE:
            return None
        g = pats[0]
        ratio = _standin_ratio(lateral, g)
        c, sn = math.cos(g.contact_angle), math.sin(g.contact_angle)
        if c - ratio * sn < 0.5 * c:
            return None
        nkw = dict(kw)
        near = _nearest(previous, g) if warm else None
        if near is not None:
            nkw["warm_start"] = near.normal
        ns = nmodel.solve(g, case.material, normal_force=loads[s] / (c - ratio * sn), **nkw)
        if not (ns.converged and ns.penetration > 0):
            return None
        d[s] = max(d[s] + (ns.penetration - g.approach) / c, 0.2 * d[s])
        creep = _creepage(case, g)
        out.append(PatchResult(g, ns, None, creep))
    return d, out


#: a point of one side's history of the vertical-force iteration stands for the
#: side's force curve while the other side's interpenetration is within this
#: fraction of the one it was taken at: the other side's height turns the
#: wheelset and so moves this side's force (on the benchmark sweep at 6.4 mm shift
#: the tread side's force moved by 2 % of the load when the flange side's
#: interpenetration grew 2.7-fold).  With 2 % 989 of the sweep's 1000 cases meet
#: the load cold (the others jump, residuals up to 1.3 %), with 5 or 10 % 982 or
#: 975, with the whole history 973 (residuals up to 39 %); as many passes
COUPLED_CHANGE = 0.02


def _current(hist, d, side):
    """The points (interpenetration, force, interpenetrations of all sides) of a
    side's history taken where the other sides' interpenetrations were those of
    ``d`` to ``COUPLED_CHANGE``: a bracket or secant of points taken at a far other
    height of the other side (an early pass, before its first large correction)
    would hold this side's force curve of another wheelset position, and the
    steps would stall on it."""
    return [p for p in hist if all(abs(p[2][o] - d[o]) <= COUPLED_CHANGE * d[o]
                                   for o in d if o != side)]


def _collapsed(current, err, loads, d, sides, rtol) -> bool:
    """Whether the bracket of the load has collapsed on every side off the balance
    (a model whose force jumps with the interpenetration, e.g. a strip entering the
    contact, may have no exact solution), from each side's ``current`` history
    points."""
    for s in sides:
        # a jump shows at one interpenetration of the other side too (to ten
        # tolerances): where that moved, a side's force moves with the roll, also at
        # its own unchanged interpenetration (a side held in balance while the other
        # was corrected: its points above and below the load at one interpenetration
        # are no bracket of a jump)
        pts = [p for p in current[s] if _same_other(p, d, s, STANDIN_FACTOR * rtol)]
        lo = [p[0] for p in pts if p[1] < loads[s]]
        hi = [p[0] for p in pts if p[1] > loads[s]]
        # collapsed: narrower than a tenth of the tolerance times the interpenetration,
        # across which a force continuous at 1.5 Q/d (Hertz's slope) would change by
        # 0.15 tolerances; missing the load at both ends of it takes a slope over 13
        # times that, i.e. a jump
        width = max(1e-11, 0.1 * rtol * d[s])
        if abs(err[s]) > rtol * loads[s] and not (lo and hi and min(hi) - max(lo) < width):
            return False
    return True


def _with_solved_forces(case, results, tmodel, previous, loads, sides):
    """The results with their tangential solutions (solved where missing) and the
    largest relative residual of the sides' vertical balances with them."""
    if tmodel is not None and any(r.tangential is None for r in results):
        results = _add_tangential(case, results, tmodel, previous=previous)
    return results, max(abs(vertical_force_on_rail(results, s) - loads[s]) / loads[s]
                        for s in sides)


def _bracket(pts, load):
    """The history points nearest the load below and above it (by interpenetration;
    None where there is none)."""
    below = [p for p in pts if p[1] < load]
    above = [p for p in pts if p[1] > load]
    return (max(below, key=lambda p: p[0]) if below else None,
            min(above, key=lambda p: p[0]) if above else None)


def _same_other(point, d, side, rel) -> bool:
    """Whether a history point (interpenetration, force, interpenetrations of all
    sides) was taken at the other sides' interpenetrations of ``d`` to ``rel``."""
    return all(abs(point[2][o] - d[o]) <= rel * d[o] for o in d if o != side)


def _step(pts, load, d, s, rtol) -> float:
    """The next interpenetration [m] of side ``s`` from its history points ``pts``
    (interpenetration, force, interpenetrations of all sides): a secant step,
    safeguarded by bisection in the bracket of the load, within 0.2 to 5 times the
    present interpenetration ``d[s]``."""
    # bracket of the load from the history (force grows with the interpenetration)
    lo, hi = _bracket(pts, load)
    near = STANDIN_FACTOR * rtol
    if lo is not None and hi is not None and hi[0] - lo[0] <= near * d[s] \
            and not _same_other(lo, hi[2], s, near):
        # no bracket but the roll's effect: points at about one interpenetration
        # of this side (to ten tolerances), above and below the load, taken while
        # the other side moved (a steep flange side's correction by 1 % moves the
        # other side's force by a few tolerances); bisecting on them held the
        # side in place.  The points at the other side's present
        # interpenetration (to ten tolerances) bracket it, if any do
        lo, hi = _bracket([p for p in pts if _same_other(p, d, s, near)], load)
    if lo is not None and hi is not None and hi[0] <= lo[0]:
        # the force is not monotone on these points (taken at other wheelset
        # positions): no bracket (bisecting between such ends stood still)
        lo = hi = None
    # a secant needs two interpenetrations (a side held while the other was
    # corrected has points at one, whose forces differ by the roll's effect: a
    # secant through them stays put): the last point and the latest before it
    # at another interpenetration
    other = [p for p in pts[:-1] if p[0] != pts[-1][0] and p[1] != pts[-1][1]]
    if other:
        (d0, f0, _), (d1, f1, _) = other[-1], pts[-1]
        cand = d1 + (load - f1) * (d1 - d0) / (f1 - f0)
    else:  # Hertz-like F ~ d^1.5
        fz = max(pts[-1][1], 1e-9 * load)
        cand = pts[-1][0] * (load / fz) ** (2.0 / 3.0)
    slow = len(pts) >= 3 and abs(pts[-1][1] - load) > 0.5 * abs(pts[-3][1] - load)
    if lo is not None and hi is not None and (slow or not (lo[0] < cand < hi[0])):
        # safeguard: bisection in the bracket, also where the last two steps
        # did not halve the residual (a jump, on which secant steps stall)
        cand = 0.5 * (lo[0] + hi[0])
    return min(max(cand, 0.2 * d[s]), 5.0 * d[s] + 1e-7)


def _first_search(case, bodies, loads, sides, start):
    """The contact search the vertical-force iteration starts from.

    With ``start`` (the contact of a neighbouring case's result, e.g. the previous
    case of a sweep): at its interpenetrations, scaled to this case's loads as
    Hertz's approach (Q^(2/3)), from its roll; a neighbour's balanced
    interpenetrations are a closer start than an estimate, and one search at given
    interpenetrations costs about half the estimate's.  Else (or where ``start``
    has no interpenetration on a side): the geometry layer's multi-Hertzian
    estimate, one load iteration (its own fixed-point iteration costs more passes
    of the iteration than it saves)."""
    if start is not None and start.interpenetration and start.loads:
        d0 = {}
        for s in sides:
            d, q = start.interpenetration.get(s, 0.0), start.loads.get(s, math.nan)
            d0[s] = d * (loads[s] / q) ** (2.0 / 3.0) if q > 0 else math.nan
        if all(math.isfinite(v) and v > 0 for v in d0.values()):
            return contact_search(case, interpenetration=d0, bodies=bodies,
                                  roll_start=start.pose.roll)
    return contact_search(case, bodies=bodies, load_iterations=1)


def _solve_wheel_rail(case, nmodel, tmodel, kw, max_iter: int = 40, rtol: float = 1e-4,
                      start=None):
    """Patches of a wheel-rail case with the vertical wheel load met per side.

    The geometry layer's multi-Hertzian estimate gives the first wheelset height
    (a neighbouring case's interpenetrations where ``start``, its result, is given:
    :func:`_first_search`);
    where each side has one loaded patch of small contact angle, a first step
    solves those normal problems for the force that carries the load and moves the
    interpenetrations by the change of approach (:func:`_force_step`); then the
    vertical interpenetration of each side is corrected by secant steps
    until the vertical force of normal plus tangential contact forces (the chosen
    models) equals the load, as CONTACT does with its Newton iteration on z (each
    side's steps from the points of its history taken at about the other side's
    present interpenetration, :func:`_current`).

    The tangential forces enter the balance only through F_y sin(d): the passes
    solve the normal problems with the lateral forces of the last tangential
    solution (Hertz + FASTSIM's before the first); once the balance holds to
    ``STANDIN_FACTOR`` tolerances the tangential problems are solved on those
    normal solutions and the balance checked again (the iteration goes on, with the
    new lateral forces, until it holds with the forces of the result).

    ``start`` (the :class:`SolveResult` of a neighbouring case) warm-starts the
    models that accept it with its patch results.  Returns the patch results, the
    final contact search and the :class:`VerticalBalance`.
    """
    bodies = build_wheelset_track(case)
    converged, jump = True, False
    side = case.get("wheelset.side", "both")
    loads = case.wheel_loads()
    sides = ("left", "right") if case.get("wheelset.roll") is None else (side,)
    previous = start.patches if start is not None else None
    contact = _first_search(case, bodies, loads, sides,
                            start.contact if start is not None else None)
    coupled = _coupled(case, nmodel, tmodel)
    lazy = tmodel is not None and not coupled
    # whose F_y/F_n stands in until the tangential solution: Hertz + FASTSIM's on
    # these patches (cheap, with this case's creepages, within about 10 % of the
    # exact F_y: a few 1e-4 of the load in the balance)
    lateral = standin = _fast_estimate(case, contact) if lazy else None
    if lazy and previous and start is not None and start.balance is not None \
            and start.balance.standin:
        lateral = _CorrectedRatio(standin, previous, start.balance.standin)
    # the normal problems start from the force step's solutions where it ran (else
    # from the neighbouring case's), the tangential ones from the neighbour's
    step = None if coupled else _force_step(case, contact, nmodel, kw, loads, sides, lateral,
                                            previous)
    normal_start = previous
    if step is not None:
        d_step, normal_start = step
        contact = contact_search(case, interpenetration=d_step, bodies=bodies,
                                 roll_start=contact.pose.roll)
    results = _solve_patches(case, contact, nmodel, tmodel, kw, previous=normal_start,
                             normal_only=lazy, coupled=coupled, same_case=step is not None)
    passes = 1 if step is None else 2
    tangential_start = previous   # warm starts of the tangential solver (a neighbour's)
    d = dict(contact.interpenetration)
    hist = {s: [] for s in sides}
    # points of each side's balance with the tangential forces solved at them (the
    # passes' own balance uses the last solution's F_y/F_n, whose change with F_n
    # it lags)
    solved = {s: [] for s in sides}
    best = None
    eager = False          # every pass solves the tangential problems
    for _ in range(max_iter):
        err = {}
        final = all(r.tangential is not None for r in results) or tmodel is None
        for s in sides:
            fz = vertical_force_on_rail(results, s, lateral)
            err[s] = fz - loads[s]
            hist[s].append((d[s], fz, dict(d)))
            if final and lazy:                  # a pass that solved them (``eager``)
                solved[s].append((d[s], fz, dict(d)))
        # with stand-in lateral forces, solve the tangential problems once the balance
        # is within ten tolerances: the stand-in's F_y sin(d) is itself a few 1e-4 of
        # the load off, so converging further on it is wasted; the passes after that
        # run with the solved forces
        tol = {s: (1.0 if final else STANDIN_FACTOR) * rtol * loads[s] for s in sides}
        met = all(abs(err[s]) <= tol[s] for s in sides)
        if met and final:
            break
        # each side's points taken at about the other side's present interpenetration
        current = {s: _current(hist[s], d, s) for s in sides}
        # a jump of the stand-in's balance is no jump of the result's: its F_y sin(d)
        # may be several per cent of the load off (ANALYN + Polach in flange contact:
        # 10 %), which moves where the load lies against the jump.  From there on
        # every pass solves the tangential problems, so that the jump test sees
        # balances with solved forces
        if not met and not final and _collapsed(current, err, loads, d, sides, rtol):
            met = eager = True
        if met:
            # met (or stuck at a jump) with the stand-in lateral forces: solve the
            # tangential problems and check the balance with their forces
            results = _add_tangential(case, results, tmodel, previous=tangential_start)
            lateral = tangential_start = results
            final = True
            err = {}
            for s in sides:
                fz = vertical_force_on_rail(results, s)
                err[s] = fz - loads[s]
                # the force curve moved with the new F_y: shift its history by the
                # change at this point (the slope stays), then go on from there
                shift = fz - hist[s][-1][1]
                hist[s] = [(dd, ff + shift, other) for dd, ff, other in hist[s]]
                solved[s].append((d[s], fz, dict(d)))
            if all(abs(err[s]) <= rtol * loads[s] for s in sides):
                break
            current = {s: _current(hist[s], d, s) for s in sides}
        # the pass nearest the load (where the force jumps across it, its results are
        # returned rather than the last pass's, which may lie on the far side)
        score = max(abs(err[s]) / loads[s] for s in sides)
        if final and (best is None or score < best[0]):
            best = (score, results, contact)
        if final and lazy:
            # two balances with solved forces: their secant holds the change of F_y/F_n
            # with F_n, which the stand-in lags (a flange side's balance then
            # converged by a factor of about -0.2 per pass); the steps and the jump
            # test use those
            for s in sides:
                own = _current(solved[s], d, s)
                if len(own) >= 2 and own[-1][0] != own[-2][0]:
                    current[s] = own
        # stop at a jump of the result's balance (a collapsed bracket of a balance
        # with solved forces; with stand-in ones the branch above has solved them)
        if final and _collapsed(current, err, loads, d, sides, rtol):
            results, worst = _with_solved_forces(case, results, tmodel, tangential_start,
                                                 loads, sides)
            if best is not None and best[0] < worst:
                worst, results, contact = best
            (log.warning if worst > STANDIN_FACTOR * rtol else log.info)(
                "vertical force: the model's force jumps across the load; the pass nearest "
                "it is %.2g of the load off", worst)
            jump = True
            break
        new = dict(d)
        # with the solved lateral forces, a side already in balance stays where it is
        balanced = {s for s in sides if final and abs(err[s]) <= rtol * loads[s]}
        for s in sides:
            if s in balanced:
                continue
            new[s] = _step(current[s], loads[s], d, s, rtol)
        d = new
        contact = contact_search(case, interpenetration=d, bodies=bodies,
                                 roll_start=contact.pose.roll)
        if lazy and all(r.tangential is not None for r in results):
            lateral = tangential_start = results
        # the balanced sides' patches, where the search (the other side's correction
        # turns the wheelset slightly) left them in place: their results stand
        still = {s for s in balanced if _unmoved(case, results, contact, s)}
        kept = [r for r in results if r.geometry.side in still]
        if kept:
            contact.patches = [g for s in SIDES for g in (
                [r.geometry for r in kept if r.geometry.side == s] if s in still
                else [g for g in contact.patches if g.side == s])]
        results = _solve_patches(case, contact, nmodel, tmodel, kw, previous=results,
                                 normal_only=lazy and not eager, coupled=coupled,
                                 same_case=True, kept=kept)
        passes += 1
    else:
        converged = False
        results, last = _with_solved_forces(case, results, tmodel, tangential_start, loads,
                                            sides)
        if best is not None and best[0] < last:
            last, results, contact = best
        log.warning("vertical force not met to %.0e after %d iterations; the pass nearest "
                    "it is %.2g of the load off", rtol, max_iter, last)
    if any(r.tangential is None for r in results):   # left the iteration without them
        results = _add_tangential(case, results, tmodel, previous=tangential_start)
    residual = {s: vertical_force_on_rail(results, s) / loads[s] - 1.0 for s in sides}
    # a load missed by more than the tolerance is not a solution of the case, also
    # where the model's force jumps across it (no interpenetration carries it)
    converged &= all(abs(v) <= rtol for v in residual.values())
    if side != "both":
        results = [r for r in results if r.geometry.side == side]
    if not results:
        raise ContactNotFoundError("no loaded contact patch found")
    _wheel_rail_validity(results, bodies)
    return results, contact, VerticalBalance(converged, jump, passes, residual, standin)


def geometry_dict(contact: WheelsetContact, side: str = "both") -> dict:
    """JSON of the contact points found by the geometry layer (no forces)."""
    patches = [p.to_dict() for p in contact.patches if side == "both" or p.side == side]
    return {"patches": patches, "roll": contact.pose.roll, "vertical": contact.pose.vertical,
            "lateral_shift": contact.pose.lateral_shift, "yaw": contact.pose.yaw}
