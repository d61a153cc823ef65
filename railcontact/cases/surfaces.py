"""A wheel on 3-D rail surfaces: crossings, several rails at once, roller rigs.

:func:`solve_on_surfaces` solves a case whose rails vary along the track (slices),
whose wheel runs on several rails (wing rail and nose, check rail, switch blade
and stock rail, each placed on its own), or whose rail is a roller.  The contact
search runs over the 3-D surfaces (:mod:`railcontact.geometry.surface_search`);
every patch found, on whichever rail and wherever along the track, is solved with
the case's normal and tangential models.  The wheel's vertical position is either
given (``wheelset.vertical_position``, CONTACT's Z_WS) or found so that the
vertical force on the rails equals ``wheelset.vertical_force`` (Brent's method on
the vertical position, the force's tangential share included).  One wheel is
solved (``wheelset.side``, its roll prescribed: CONTACT's single-wheel mode).

Case keys (``docs/case_files.md``, "Rails along the track, several rails, rollers"):
``rail.slices`` (a ``.slcs`` file or a list of ``{s, profile}``),
``rail.lateral_position`` / ``vertical_position`` / ``name``, ``[[rails]]`` (several
rails, each with those keys and ``profile`` or ``slices``), ``[roller]``
(``radius``, ``angular_velocity``, ``position``), ``wheelset.position`` (s) and
``wheelset.vertical_position``.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from .bodies import load_profiles
from .case import Case
from .surface_setup import RailSpec
from .equilibrium import VerticalBalance
from ..core.errors import CaseFileError, ContactNotFoundError, ProfileError
from ..geometry.surface_search import (FINE, Motion, SurfaceContact, SurfacePose,
                                      SurfaceWheel, contact_gap_mesh, midplane_slip, search,
                                      surface_slip)
from ..geometry.sliced_surface import SlicedSurface
from ..geometry.surfaces import PlacedRail, ProfileSurface, RollerSurface
from ..geometry.track import Track
from ..geometry.validity import HALF_SPACE_LIMIT, flange_state, halfspace_ratio
from .patches import case_models
from ..profiles.slices import is_slices_file, read_slices, slices_from_list
from .results import PatchResult, SolveResult, patch_vertical_force, vertical_force_on_rail
from ..core.status import SolverStatus

log = logging.getLogger(__name__)

def _rail_surface(spec: RailSpec, base_dir):
    """The surface of one parsed rail (profile or slices), files relative to
    ``base_dir``."""
    if spec.slices is not None:
        opts = spec.options
        kw = {} if opts is None else {"options": opts, "mirror_y": bool(opts.mirror_y)}
        if opts is not None and opts.mirror_z is not None:
            kw["z_down"] = not opts.mirror_z
        if is_slices_file(spec.slices):
            p = Path(spec.slices)
            slices = read_slices(p if p.is_absolute() else base_dir / p, units=spec.units, **kw)
        elif isinstance(spec.slices, list):
            if kw:
                raise CaseFileError(f"[{spec.where}]: CONTACT's profile processing (mirror_y, "
                                    "scale, smoothing, ...) applies to a .slcs file's slices; "
                                    "expected slices = 'FILE.slcs' with these keys")
            slices = slices_from_list(spec.slices, base_dir, units=spec.units,
                                      name=spec.name or spec.where)
        else:
            raise CaseFileError(f"{spec.where}.slices = {spec.slices!r}: expected a .slcs file "
                                "or a list of {s, profile}")
        return SlicedSurface(slices) if spec.slice_spacing is None else \
            SlicedSurface(slices, spec.slice_spacing)
    return ProfileSurface(load_profiles(spec.profile, "rail", base_dir)[0])


@dataclass
class SurfaceScene:
    """A surface case built: the wheel, the placed rails, the side, the pose
    (vertical position prescribed or an estimate), the motion and the load."""

    wheel: SurfaceWheel
    rails: list
    side: str
    pose: SurfacePose
    motion: Motion
    load: float | None
    search_length: float | None = None
    inclination: str = "local"
    rigid_slip: str = "planar"
    combine_distance: float = 0.0
    reference_weights: str = "surface"
    fine: tuple = FINE
    #: the rule of the rigid slip on the surfaces (``ContactRules.surface_slip``)
    #: and the rail's share of the mid-plane velocity in CONTACT's
    slip_rule: str = "sections"
    rail_share: float = 0.5


def build_surface_case(case: Case) -> SurfaceScene:
    """The wheel, rails, pose and motion of a surface case, from its parsed keys
    (:class:`~railcontact.cases.surface_setup.SurfaceCaseSetup`); the profile and
    slice files are read here."""
    s = case.surfaces
    if s is None:
        raise CaseFileError("expected a case on rail surfaces (slices, several rails, a "
                            "roller, a rail or wheelset placed along the track)")
    base = case.base_dir
    wheel_p = load_profiles(s.wheel, "wheel", base)[0]
    r0 = s.nominal_radius
    dev = s.wheel_deviation
    if dev is not None and s.side == "left":
        # wheelset coordinates (y to the right) -> the left wheel's side frame
        dev = (dev[0], -dev[1], dev[2], -dev[3], -dev[4], dev[5])
    wheel = SurfaceWheel(wheel_p, r0, s.flange_back_distance / 2.0 - s.flange_back_position,
                         deviation=dev if dev is not None and any(dev) else None)
    pv = -s.velocity / r0 if s.pitch_velocity is None else s.pitch_velocity
    rails = []
    shared = {}           # rails naming one slices file share its surface (and cache)
    for spec in s.rails:
        key = (spec.slices, spec.units, spec.slice_spacing) \
            if isinstance(spec.slices, str) else None
        surf = shared.get(key) if key is not None else None
        if surf is None:
            surf = _rail_surface(spec, base)
            if key is not None:
                shared[key] = surf
        omega = 0.0
        if s.roller is not None:
            R = s.roller.radius
            # the profile turned about +x (z down: a positive roll lowers the field
            # side) and lowered, the roller's axis where it was; the undeformed
            # distance on that surface or CONTACT's turned roller (roller.turn)
            surf = RollerSurface(surf.profile, R, s.roller.position,
                                 s.roller.profile_deviation, case.rules.roller_turn)
            omega = -pv * r0 / R if s.roller.angular_velocity is None else \
                s.roller.angular_velocity
        y0 = spec.lateral_position
        if y0 is None:
            # a prismatic rail placed by gauge, as on a track
            tr = Track(surf.section(0.0) if not isinstance(surf, RollerSurface) else surf.profile,
                       gauge=s.gauge, gauge_height=s.gauge_height)
            y0 = tr.rail_offset("right")
        rails.append(PlacedRail(surf, spec.name or surf.name, float(y0),
                                spec.vertical_position, omega, spec.lateral_range))
    pose = SurfacePose(s.position, s.lateral_shift,
                       0.0 if s.vertical_position is None else s.vertical_position,
                       s.roll, s.yaw)
    motion = Motion(0.0 if s.roller is not None else s.velocity, pv, s.lateral_velocity,
                    0.0, 0.0, s.yaw_rate)
    rules = case.rules
    # the rail's share of CONTACT's mid-plane velocity, (1 - nu_r) G_w over its sum
    # with (1 - nu_w) G_r
    (e_r, nu_r), (e_w, nu_w) = case.material.bodies
    g_r, g_w = e_r / (2.0 * (1.0 + nu_r)), e_w / (2.0 * (1.0 + nu_w))
    return SurfaceScene(wheel, rails, s.side, pose, motion, s.load, s.search_length,
                        rules.contact_angle, s.rigid_slip, s.combine_distance,
                        rules.reference_weights,
                        contact_gap_mesh(s.nominal_radius, *case.element_size)
                        if rules.search_grid == "contact" else FINE, rules.surface_slip,
                        (1 - nu_r) * g_w / ((1 - nu_r) * g_w + (1 - nu_w) * g_r))


def beyond_slices(setup: SurfaceScene) -> list:
    """One line per rail given by slices whose range of s the wheelset's position
    lies outside (the wheel beyond the first or the last slice): such a rail has
    no surface under the wheel's axle, and a patch is found on it only where the
    search reaches back into its slices."""
    out = []
    s = setup.pose.s
    for rail in setup.rails:
        surf = rail.surface
        if isinstance(surf, SlicedSurface):
            lo, hi = surf.s_range()
            if not lo <= s <= hi:
                out.append(f"the wheel at s = {s:.6g} m lies beyond the "
                           f"{'last' if s > hi else 'first'} slice of the rail {rail.name!r} "
                           f"(its slices cover s = [{lo:.6g}, {hi:.6g}] m)")
    return out


@dataclass
class SurfaceResult(SolveResult):
    """:class:`railcontact.cases.results.SolveResult` of a case on rail surfaces: also the
    search (``surface_contact``); each patch's JSON carries the rail it lies on
    (``rail``), its reference point in the track frame (``position`` [m]) and its
    track position ``s`` [m]."""

    surface_contact: SurfaceContact | None = field(default=None, repr=False)

    def to_dict(self) -> dict:
        d = super().to_dict()
        for pd, p in zip(d["patches"], self.patches):
            g = p.geometry
            pd["rail"] = g.rail
            pd["position"] = [float(v) for v in g.position]
            pd["s"] = float(g.s)
        if self.pose is not None:
            d["vertical_position"] = float(self.pose.vertical)
        return d

    def rail_forces(self) -> dict:
        """Vertical force [N] on each rail (track z, forces on the rail)."""
        out = {}
        for p in self.patches:
            out[p.geometry.rail] = out.get(p.geometry.rail, 0.0) + patch_vertical_force(p)
        return out


def _validity(result: PatchResult, setup: SurfaceScene) -> PatchResult:
    """Flange climb / derailment and the half-space ratio of a patch on a rail
    surface (the rail's cross-section at the patch, and a roller's radius)."""
    g = result.geometry
    rail = setup.rails[g.rail_index]
    try:
        section = rail.section(g.s)
    except ProfileError:
        section = None
    warnings = []
    ratio = halfspace_ratio(g, result.normal, setup.wheel.profile, section,
                            rail_rolling_radius=g.rail_rolling_radius) if section is not None \
        else math.nan
    state = flange_state(g, setup.wheel.profile)
    if state is not None:
        warnings.append(f"{state}: the {g.side} wheel's contact on the {g.rail} at "
                        f"{g.y_wheel * 1e3:.1f} mm on the wheel")
    if ratio > HALF_SPACE_LIMIT:
        warnings.append(f"half-space: the patch on the {g.rail} is large against the radii of "
                        f"curvature (size/radius {ratio:.2f} > {HALF_SPACE_LIMIT})")
    status = SolverStatus.failed(warnings[0]) if state == "derailment" else SolverStatus()
    result.validity = status.with_warnings(*warnings[1 if state == "derailment" else 0:])
    result.halfspace_ratio = ratio
    return result


def _surface_slip_field(g, ns, setup, creep):
    """The rigid slip on the actual surfaces (:func:`railcontact.geometry.
    surface_search.surface_slip`) minus the planar rigid slip of the patch's
    creepages (xi - phi y, eta + phi x), on the normal solution's grid: the exact
    tangential solver's ``extra_slip`` (``solver.rigid_slip = "surfaces"``)."""
    X, Y = np.meshgrid(ns.x, ns.y, indexing="ij")
    if setup.slip_rule == "midplane":
        sx, sy = midplane_slip(g, setup.wheel, setup.rails[g.rail_index], setup.motion, X, Y,
                               setup.rail_share)
    else:
        sx, sy = surface_slip(g, setup.wheel, setup.rails[g.rail_index], setup.motion, X, Y)
    xi, eta, phi = creep
    return sx - (xi - phi * Y), sy - (eta + phi * X)


def _mirrored_normal(ns):
    """A normal solution mirrored in x (x -> -x): the rolling direction reversed."""
    flip = (lambda a: None if a is None else np.ascontiguousarray(a[::-1]))  # noqa: E731
    return dataclasses.replace(ns, x=np.ascontiguousarray(-ns.x[::-1]), pressure=flip(ns.pressure),
                               contact=flip(ns.contact), gap=flip(ns.gap), strips=None,
                               pressure_at=None)


def _unmirrored_tangential(ts, creep):
    """The tangential solution of a problem solved mirrored in x, back in the patch's
    frame (``creep`` its own creepages): tractions and slip along x negated."""
    flip = lambda a: np.ascontiguousarray(np.asarray(a)[::-1])  # noqa: E731
    return dataclasses.replace(ts, x=np.ascontiguousarray(-ts.x[::-1]),
                               traction_x=-flip(ts.traction_x), traction_y=flip(ts.traction_y),
                               slip_x=-flip(ts.slip_x), slip_y=flip(ts.slip_y),
                               stick=flip(ts.stick), contact=flip(ts.contact), fx=-ts.fx,
                               mz=-ts.mz, creepage=tuple(creep))


def _backwards(setup) -> bool:
    """Whether the wheel rolls towards -x over a rail at rest (VS < 0 on a track or
    test rig): the steady rolling problem is then solved mirrored in x."""
    return setup is not None and setup.motion.velocity < 0 and not any(
        r.is_roller for r in setup.rails)


def _solve_patches(case, contact, nmodel, tmodel, kw, previous=None, tangential=True,
                   setup=None):
    """Normal (and tangential) solutions of the patches of a search; ``previous``
    results warm-start the models that accept it (the nearest patch on the same
    rail)."""
    out = []
    for g in contact.patches:
        if g.approach <= 0:
            continue
        nkw = dict(kw)
        best = _nearest(previous, g)
        if best is not None and "warm-start" in nmodel.capabilities:
            nkw["warm_start"] = best.normal
        ns = nmodel.solve(g, case.material, penetration=g.approach, **nkw)
        creep = tuple(case.creepage) if case.creepage is not None else tuple(g.creepage)
        ts = None
        if tangential and tmodel is not None and ns.normal_force > 0:
            tkw = {}
            if setup is not None and setup.rigid_slip == "surfaces":
                tkw["extra_slip"] = _surface_slip_field(g, ns, setup, creep)
            if _backwards(setup) and getattr(tmodel, "mode", "rolling") == "rolling":
                # rolling towards -x: the problem mirrored in x (x' = -x; xi, phi and
                # the slip along x change sign), solved, and mirrored back
                if "extra_slip" in tkw:
                    ex, ey = tkw["extra_slip"]
                    tkw["extra_slip"] = (-np.asarray(ex)[::-1], np.asarray(ey)[::-1])
                mc = (-creep[0], creep[1], -creep[2])
                ts = _unmirrored_tangential(tmodel.solve(_mirrored_normal(ns), g, case.material,
                                                         mc, case.friction, g.velocity,
                                                         **tkw), creep)
                out.append(PatchResult(g, ns, ts, creep))
                continue
            if best is not None and best.tangential is not None and \
                    "warm-start" in tmodel.capabilities:
                tkw["warm_start"] = best.tangential
            ts = tmodel.solve(ns, g, case.material, creep, case.friction, g.velocity, **tkw)
        out.append(PatchResult(g, ns, ts, creep))
    return out


def _nearest(previous, g, distance: float = 3e-3):
    near = [r for r in previous or () if r.geometry.rail == g.rail
            and np.hypot(*(np.asarray(r.geometry.position[:2]) - g.position[:2])) <= distance]
    return min(near, key=lambda r: np.hypot(*(np.asarray(r.geometry.position[:2])
                                               - g.position[:2]))) if near else None


def solve_on_surfaces(case: Case, normal: str | None = None, tangential: str | None = None,
                      setup: SurfaceScene | None = None, warm_start=None,
                      tangential_model=None) -> SurfaceResult:
    """Solve a case on rail surfaces (see the module notes).

    Parameters
    ----------
    case : Case
    normal, tangential : str, optional
        Model names overriding the case's ``[solver]``.
    setup : SurfaceScene, optional
        The wheel and rails built once by the caller (a sweep), else built here.
    warm_start : SurfaceResult, optional
        A neighbouring case's result (a sweep's previous position): its vertical
        position starts the iteration and its patches warm-start the models.
    tangential_model : object, optional
        A tangential model instance used in place of the case's (a transient time
        step of CONTACT's module 1, :mod:`railcontact.contact_inp.transient_m1`).
    """
    t0 = time.perf_counter()
    setup = setup or build_surface_case(case)
    nname, tname, nmodel, tmodel, kw = case_models(case, normal, tangential)
    if tangential_model is not None:
        tname, tmodel = tangential_model.name, tangential_model
    previous = warm_start.patches if warm_start is not None else None
    beyond = beyond_slices(setup)
    for line in beyond:
        log.warning("%s", line)

    def at(z, tang=True, prev=None):
        pose = SurfacePose(setup.pose.s, setup.pose.lateral, z, setup.pose.roll, setup.pose.yaw)
        c = search(setup.wheel, setup.rails, pose, setup.side, setup.motion,
                   x_range=setup.search_length, inclination=setup.inclination,
                   combine_distance=setup.combine_distance, weights=setup.reference_weights,
                   fine=setup.fine)
        return c, _solve_patches(case, c, nmodel, tmodel, kw, prev, tang, setup)

    balance = None
    if setup.load is None:
        contact, results = at(setup.pose.vertical, prev=previous)
    else:
        try:
            contact, results, balance = _vertical_balance(case, setup, at, warm_start,
                                                          previous)
        except ContactNotFoundError as exc:
            if not beyond:
                raise
            raise ContactNotFoundError(f"{exc}; " + "; ".join(beyond)) from None
    if not results:
        raise ContactNotFoundError(
            f"no contact of the {setup.side} wheel with the rails at s = {setup.pose.s:.4f} m "
            f"(vertical position {contact.pose.vertical * 1e3:.4f} mm; smallest vertical gap "
            f"{contact.min_gap * 1e3:.4f} mm)" + "".join(f"; {b}" for b in beyond))
    results = [_validity(r, setup) for r in results]
    for r in results:
        if beyond:
            r.validity = r.validity.with_warnings(*beyond)
    res = SurfaceResult(results, nname, tname, time.perf_counter() - t0, case.title,
                        contact.pose, None, balance, surface_contact=contact)
    return res


def _vertical_balance(case, setup, at, warm_start, previous, rtol=None, max_iter: int = 40):
    """The vertical position at which the vertical force on the rails meets the load:
    Brent's method on z in a bracket found from the touching position (the gap falls
    by dz when the wheel is lowered by dz) by steps of a Hertzian F ~ d^1.5; the
    tangential forces' share (F_y sin d) is included in every evaluation."""
    rtol = case.force_tolerance if rtol is None else rtol
    load, side = setup.load, setup.side
    cache = {}
    state = {"prev": previous, "n": 0}

    def force(z):
        if z not in cache:
            c, res = at(z, prev=state["prev"])
            state["n"] += 1
            if res:
                state["prev"] = res
            cache[z] = (vertical_force_on_rail(res, side), c, res)
        return cache[z][0]

    if warm_start is not None and warm_start.pose is not None:
        z0 = float(warm_start.pose.vertical)
    else:
        z0 = setup.pose.vertical
    c0, _ = at(z0, tang=False)
    touch = z0 + c0.min_gap if math.isfinite(c0.min_gap) else z0
    if not math.isfinite(c0.min_gap):
        raise ContactNotFoundError(f"the {side} wheel does not reach the rails at s = "
                                   f"{setup.pose.s:.4f} m (no overlapping surfaces)")
    d = 3e-5 * (load / 1e4) ** (2.0 / 3.0)
    if warm_start is not None and warm_start.pose is not None and z0 > touch:
        d = z0 - touch
    lo, hi = touch, None
    f_lo = 0.0
    for _ in range(12):
        f = force(touch + d)
        if f >= load:
            hi = touch + d
            break
        lo, f_lo = touch + d, f
        d = d * (load / max(f, 1e-3 * load)) ** (2.0 / 3.0) * 1.05 if f > 0 else 2 * d
    if hi is None:
        raise ContactNotFoundError(f"the {side} wheel cannot carry {load:g} N on the rails at "
                                   f"s = {setup.pose.s:.4f} m")
    z = brentq(lambda v: force(v) - load, lo, hi, xtol=1e-12, rtol=1e-12, maxiter=max_iter) \
        if abs(force(hi) - load) > rtol * load else hi
    fz, c, res = cache[z] if z in cache else (force(z), *cache[z][1:])
    residual = fz / load - 1.0
    ok = abs(residual) <= rtol
    if not ok:
        log.info("vertical force on the rails %.6g N misses the load %.6g N", fz, load)
    return c, res, VerticalBalance(ok, False, state["n"], {side: residual})
