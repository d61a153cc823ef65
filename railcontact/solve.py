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
from .equilibrium import VerticalBalance, balance as solve_balance
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
                   coupled=False, same_case=False):
    """Solve every loaded patch; ``previous`` results (an earlier evaluation of the
    same case, or a neighbouring case of a sweep) serve as warm starts where a model
    accepts them.  ``normal_only``: leave the tangential problems to
    :func:`_add_tangential`.  ``coupled``: dissimilar materials with the exact
    models (:func:`_coupled`), both problems solved together.  ``same_case``:
    ``previous`` is an earlier evaluation of this case, whose grids a model may
    keep."""
    out = []
    nwarm = "warm-start" in nmodel.capabilities
    for geom in contact.patches:
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
            if same_case and "grid-reuse" in nmodel.capabilities:
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


def vertical_force_on_rail(results, side: str, lateral=None) -> float:
    """Total vertical force [N] the wheel exerts on the rail of one side (track z).

    On the rail, F_z = f_n cos(d) + f_s sin(d) with f_s = -F_y the lateral force on
    the rail (the patch results hold forces on the wheel).  ``lateral``: a function
    of a patch result giving the lateral force F_y [N] that stands in for its
    tangential solution (:class:`WheelRailContact`); else the tangential
    solution's (0 without one).
    """
    total = 0.0
    for r in results:
        if r.geometry.side == side:
            d = r.geometry.contact_angle
            fn = r.normal.normal_force
            if lateral is not None:
                fy = lateral(r)
            else:
                fy = r.tangential.fy if r.tangential is not None else 0.0
            total += fn * math.cos(d) - fy * math.sin(d)
    return total


def _ratio(result) -> float:
    """F_y/F_n of a patch result; 0 without its tangential solution or load."""
    if result is None or result.tangential is None or not result.normal.normal_force > 0:
        return 0.0
    return result.tangential.fy / result.normal.normal_force


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


def _first_search(case, bodies, loads, sides, start):
    """The contact search the vertical balance starts from.

    With ``start`` (the contact of a neighbouring case's result, e.g. the previous
    case of a sweep): at its interpenetrations, scaled to this case's loads as
    Hertz's approach (Q^(2/3)), from its roll; a neighbour's balanced
    interpenetrations are a closer start than an estimate, and one search at given
    interpenetrations costs about half the estimate's.  Else (or where ``start``
    has no interpenetration on a side): the geometry layer's multi-Hertzian
    estimate, one load iteration (its own fixed-point iteration costs more passes
    of the balance than it saves)."""
    if start is not None and start.interpenetration and start.loads:
        d0 = {}
        for s in sides:
            d, q = start.interpenetration.get(s, 0.0), start.loads.get(s, math.nan)
            d0[s] = d * (loads[s] / q) ** (2.0 / 3.0) if q > 0 else math.nan
        if all(math.isfinite(v) and v > 0 for v in d0.values()):
            return contact_search(case, interpenetration=d0, bodies=bodies,
                                  roll_start=start.pose.roll)
    return contact_search(case, bodies=bodies, load_iterations=1)


#: the uncertainty of a stand-in lateral force: FASTSIM's F_y on the exact normal
#: solution is within this fraction of the exact F_y (measured on the benchmark
#: sweep's patches: median 3-4 %, in flange contact F_y sin(d) within 9 % of the load)
STANDIN_UNCERTAINTY = 0.1


@dataclass
class ContactEvaluation:
    """The contact of a wheel-rail case evaluated at given interpenetrations.

    ``interpenetration`` [m] per side, the contact search's result ``contact``, the
    loaded patches' ``results``, the vertical force each wheel exerts on its rail
    (``forces`` [N], :func:`vertical_force_on_rail`) and whether those are the
    forces of a result (``final``: the tangential problems solved); where not, the
    lateral forces are stand-ins and ``uncertainty`` says how far off the load that
    may put each side's force (relative to the load)."""

    interpenetration: dict
    contact: WheelsetContact
    results: list
    forces: dict
    final: bool
    uncertainty: dict | None = None


class WheelRailContact:
    """The contact evaluation that :func:`railcontact.equilibrium.balance` drives for
    a wheel-rail case.

    ``evaluate(d, final)`` searches the contact at the interpenetrations ``d`` (from
    the last search's roll) and solves the loaded patches' normal problems,
    warm-started from the last evaluation's solutions (on its grids where they
    fit); at the interpenetrations of the last call its normal solutions are
    reused.  With the exact tangential model the tangential problems are solved
    where ``final`` is asked (warm-started from the last tangential solutions), and
    else FASTSIM on the normal solutions stands in for the lateral forces (the
    exact solver's own first estimate), each side's uncertainty
    ``STANDIN_UNCERTAINTY`` times its lateral forces' share of the balance,
    sum |F_y sin(d)| / Q; the other tangential models solve every time.

    ``start``: the :class:`SolveResult` of a neighbouring case (warm start: the
    first search at its interpenetrations, the solvers from its solutions)."""

    def __init__(self, case, nmodel, tmodel, kw, start=None):
        self.case, self.nmodel, self.tmodel, self.kw = case, nmodel, tmodel, kw
        self.bodies = build_wheelset_track(case)
        self.loads = case.wheel_loads()
        side = case.get("wheelset.side", "both")
        self.sides = ("left", "right") if case.get("wheelset.roll") is None else (side,)
        self.first = _first_search(case, self.bodies, self.loads, self.sides,
                                   start.contact if start is not None else None)
        self.coupled = _coupled(case, nmodel, tmodel)
        self.lazy = (tmodel is not None and "lazy" in tmodel.capabilities
                     and not self.coupled)
        self.previous = start.patches if start is not None else None
        # the results whose tangential solutions start the next tangential solves
        self.tangential_start = self.previous
        # the neighbour's solved patches and FASTSIM's on them: the stand-in's correction
        self.neighbour = None
        if start is not None and start.balance is not None and start.balance.standin:
            self.neighbour = (start.patches, start.balance.standin)
        self.standin = None         # FASTSIM on the last provisional evaluation's patches
        self.last = None

    def start(self) -> dict:
        """The interpenetrations [m] of the first search."""
        return {s: self.first.interpenetration[s] for s in self.sides}

    def __call__(self, d: dict, final: bool = False) -> ContactEvaluation:
        last, case = self.last, self.case
        if last is not None and last.interpenetration == d:
            contact, results = last.contact, last.results
        else:
            if last is None and d == self.start():
                contact = self.first
            else:
                roll = (last.contact if last is not None else self.first).pose.roll
                contact = contact_search(case, interpenetration=d, bodies=self.bodies,
                                         roll_start=roll)
            results = _solve_patches(case, contact, self.nmodel, self.tmodel, self.kw,
                                     previous=last.results if last else self.previous,
                                     normal_only=self.lazy, coupled=self.coupled,
                                     same_case=last is not None)
        if final and self.lazy and any(r.tangential is None for r in results):
            results = _add_tangential(case, results, self.tmodel,
                                      previous=self.tangential_start or self.standin)
            self.tangential_start = results
        done = all(r.tangential is not None for r in results) or self.tmodel is None
        lateral = uncertainty = None
        if not done:
            if last is None or last.results is not results or self.standin is None:
                self.standin = _add_tangential(case, results, get_tangential_model("fastsim"))
            fy = _standin_lateral(self.standin, self.neighbour)
            lateral = lambda r: fy[id(r.geometry)]                      # noqa: E731
            uncertainty = {s: STANDIN_UNCERTAINTY * sum(
                abs(fy[id(r.geometry)] * math.sin(r.geometry.contact_angle))
                for r in results if r.geometry.side == s) / self.loads[s] for s in self.sides}
        forces = {s: vertical_force_on_rail(results, s, lateral) for s in self.sides}
        self.last = ContactEvaluation(dict(d), contact, results, forces, done, uncertainty)
        return self.last


def _standin_lateral(standin, neighbour) -> dict:
    """F_y [N] standing in for each patch's tangential solution (by the id of its
    geometry): FASTSIM's on the patch's normal solution (``standin``), where a
    neighbouring case (``neighbour``: its solved patch results and FASTSIM's on
    them) has a patch of the same side within ``WARM_DISTANCE`` plus the neighbour's
    difference of the solved F_y/F_n from FASTSIM's, times F_n: FASTSIM's own error
    (median 3-4 % of F_y on the benchmark sweep) largely cancels between
    neighbours."""
    out = {}
    for r in standin:
        fy = r.tangential.fy
        if neighbour is not None:
            a, b = _nearest(neighbour[0], r.geometry), _nearest(neighbour[1], r.geometry)
            if a is not None and b is not None and a.tangential is not None:
                fy += (_ratio(a) - _ratio(b)) * r.normal.normal_force
        out[id(r.geometry)] = fy
    return out


def _solve_wheel_rail(case, nmodel, tmodel, kw, max_iter: int = 40, rtol: float = 1e-4,
                      start=None):
    """Patches of a wheel-rail case with the vertical wheel load met per side.

    The balance of each wheel's vertical force, normal plus tangential contact
    forces of the case's models, with its load is solved by
    :func:`railcontact.equilibrium.balance` on the evaluations of
    :class:`WheelRailContact` (the sides' interpenetrations the unknowns), from the
    geometry layer's multi-Hertzian estimate or, where ``start`` (the
    :class:`SolveResult` of a neighbouring case) is given, from its
    interpenetrations and its Jacobian.  Returns the patch results, the final
    contact search and the :class:`VerticalBalance`.
    """
    evaluate = WheelRailContact(case, nmodel, tmodel, kw, start)
    jac = start.balance.jacobian if start is not None and start.balance is not None else None
    ev, balance = solve_balance(evaluate, evaluate.start(), evaluate.loads, rtol, max_iter,
                                jacobian=jac)
    balance.standin = evaluate.standin
    results = ev.results
    side = case.get("wheelset.side", "both")
    if side != "both":
        results = [r for r in results if r.geometry.side == side]
    if not results:
        raise ContactNotFoundError("no loaded contact patch found")
    _wheel_rail_validity(results, evaluate.bodies)
    return results, ev.contact, balance


def geometry_dict(contact: WheelsetContact, side: str = "both") -> dict:
    """JSON of the contact points found by the geometry layer (no forces)."""
    patches = [p.to_dict() for p in contact.patches if side == "both" or p.side == side]
    return {"patches": patches, "roll": contact.pose.roll, "vertical": contact.pose.vertical,
            "lateral_shift": contact.pose.lateral_shift, "yaw": contact.pose.yaw}
