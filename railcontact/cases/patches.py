"""The patches of a case solved with its models: model selection through the
registries, warm starts from a neighbouring result, the friction and creepages of
each patch, and each result's validity (:mod:`railcontact.geometry.validity`)."""

from __future__ import annotations

import logging

import numpy as np

from .conformal import (conformal_extra_slip, conformal_friction, conformal_normal,
                        conformal_patch, conformal_tangential, is_conformal)
from .coupling import CoupledStart, solve_coupled
from ..geometry.validity import HALF_SPACE_LIMIT, contact_size, patch_validity
from ..normal import get_normal_model
from ..profiles.library import DEFAULT_INCLINATION, RAIL_PROFILES
from .results import PatchResult
from ..core.status import SolverStatus
from ..tangential import get_tangential_model

log = logging.getLogger(__name__)


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



def coupled_models(case, nmodel, tmodel) -> bool:
    """Whether the case's normal and tangential problems are coupled and its models
    solve them together (:func:`railcontact.cases.coupling.solve_coupled`):
    dissimilar materials, or Blanco's conformal coefficients
    (``solver.influence = "blanco"``), with both exact models."""
    blanco = is_conformal(case) and case.wheel_rail.influence is not None
    if not (case.material.is_dissimilar or blanco):
        return False
    if tmodel is not None and "coupled" in nmodel.capabilities & tmodel.capabilities:
        return True
    if case.material.is_dissimilar:
        log.info("dissimilar materials: the %s/%s models use the combined constants G, nu, "
                 "E*; the normal-tangential coupling needs normal = tangential = 'exact'",
                 nmodel.name, tmodel.name if tmodel is not None else "none")
    return False



#: a previous patch serves as warm start for a patch within this lateral distance [m]
WARM_DISTANCE = 3e-3



def nearest_patch(previous, geom):
    """The previous patch result of the same side nearest to ``geom`` on the rail
    (within ``WARM_DISTANCE``), or None."""
    near = [r for r in previous or () if r.geometry.side == geom.side
            and abs(r.geometry.y_rail - geom.y_rail) <= WARM_DISTANCE]
    return min(near, key=lambda r: abs(r.geometry.y_rail - geom.y_rail)) if near else None



def solve_case_patches(case, contact, nmodel, tmodel, kw, previous=None, normal_only=False,
                   coupled=False, same_case=False):
    """Solve every loaded patch; ``previous`` results (an earlier evaluation of the
    same case, or a neighbouring case of a sweep) serve as warm starts where a model
    accepts them.  ``normal_only``: leave the tangential problems to
    :func:`add_tangential`.  ``coupled``: coupled problems (dissimilar materials,
    Blanco's coefficients) with the exact models (:func:`coupled_models`), both
    solved together.  ``same_case``:
    ``previous`` is an earlier evaluation of this case, whose grids a model may
    keep."""
    out = []
    nwarm = "warm-start" in nmodel.capabilities
    for geom in contact.patches:
        if geom.approach <= 0:
            continue
        geom = conformal_patch(case, geom)            # the curved surface, where asked
        creep = patch_creepage(case, geom)
        nkw = dict(kw)
        best = nearest_patch(previous, geom) if nwarm else None
        if best is not None:
            nkw["warm_start"] = best.normal
            if same_case and "grid-reuse" in nmodel.capabilities:
                nkw["reuse_grid"] = best.normal
        if coupled:
            start = CoupledStart(normal={k: v for k, v in nkw.items() if k not in kw},
                                 tangential=_tangential_kw(case, tmodel, previous, geom))
            ns, ts = solve_coupled(nmodel, tmodel, geom, case.material, creep,
                                   patch_friction(case, geom), geom.velocity,
                                   penetration=geom.approach, **kw, start=start)
            out.append(PatchResult(geom, *conformal_tangential(geom, ns, ts), creep))
            continue
        ns = conformal_normal(geom, nmodel.solve(geom, case.material,
                                                 penetration=geom.approach, **nkw))
        out.append(PatchResult(geom, ns, None, creep))
    if normal_only or coupled:
        return out
    return add_tangential(case, out, tmodel, previous)



def _tangential_kw(case, tmodel, previous, geom):
    """The keywords of a coupled patch's tangential solves on its normal solution
    ``ns`` (a function of it): those of :func:`_tangential_extra` and a conformal
    patch's rigid slip."""
    def kw(ns):
        extra = _tangential_extra(case, tmodel, previous, geom, ns)
        slip = conformal_extra_slip(geom, ns, patch_creepage(case, geom))
        if slip is not None:
            extra["extra_slip"] = slip
        return extra
    return kw


def _tangential_extra(case, tmodel, previous, geom, normal) -> dict:
    """The warm start and friction-field keywords of :func:`_tangential_kw`."""
    extra = {}
    best = nearest_patch(previous, geom) if "warm-start" in tmodel.capabilities else None
    if best is not None and best.tangential is not None:
        extra["warm_start"] = best.tangential
    mu = patch_friction(case, geom)
    if "friction-field" in tmodel.capabilities:
        # friction varying across the patch, relative to the patch's
        # coefficient: along the track, and over a conformal patch's columns
        # by their local angle (a stand-in model of the balance's early
        # passes takes the patch's coefficient at its reference point)
        scale = None
        if case.friction_along_track is not None:
            scale = friction_along_track(case, geom, normal)
        local = conformal_friction(case, geom, normal)
        if local is not None and mu > 0:
            scale = local / mu if scale is None else scale * (local / mu)
        if scale is not None:
            extra["friction_scale"] = scale
    return extra


def add_tangential(case, results, tmodel, previous=None):
    """The tangential solutions of patch results that have none (warm-started from
    the nearest of ``previous`` where the model accepts it)."""
    if tmodel is None:
        return results
    out = []
    for r in results:
        if r.tangential is None:
            extra = _tangential_extra(case, tmodel, previous, r.geometry, r.normal)
            slip = conformal_extra_slip(r.geometry, r.normal, r.creepage)
            if slip is not None and "extra-slip" in tmodel.capabilities:
                extra["extra_slip"] = slip
            ts = tmodel.solve(r.normal, r.geometry, case.material, r.creepage,
                              patch_friction(case, r.geometry), r.geometry.velocity, **extra)
            r = PatchResult(r.geometry, *conformal_tangential(r.geometry, r.normal, ts),
                            r.creepage)
        out.append(r)
    return out



def lateral_ratio(result) -> float:
    """F_y/F_n of a patch result; 0 without its tangential solution or load."""
    if result is None or result.tangential is None or not result.normal.normal_force > 0:
        return 0.0
    return result.tangential.fy / result.normal.normal_force



def patch_friction(case, geom) -> float:
    """The friction coefficient of a wheel-rail patch: ``friction.coefficient``, or
    ``friction.variation`` at the inclination of its rail surface in rail-profile
    coordinates (the contact angle in the side frame plus the rail's inclination;
    CONTACT's VARFRC = 1)."""
    if case.friction_along_track is not None:
        xs, cs = case.friction_along_track
        return float(np.interp(float(geom.position[0]), xs, cs))
    if case.friction_variation is None:
        return case.friction
    sgn = 1.0 if geom.side == "right" else -1.0
    rail = case.wheel_rail.rail
    incl = rail.inclination
    if incl is None:
        incl = DEFAULT_INCLINATION if str(rail.name).upper() in RAIL_PROFILES else 0.0
    return case.friction_at(sgn * geom.contact_angle + float(incl))



def friction_along_track(case, geom, normal) -> np.ndarray:
    """Friction along the track (``friction.variation.x``, CONTACT's VARFRC = 2): the
    coefficient of each element of a patch's grid at its position along the track
    (x from the wheelset centre: the patch's reference point plus the element's x),
    over the patch's coefficient at its reference point (:func:`patch_friction`)."""
    xs, cs = case.friction_along_track
    mu = np.interp(float(geom.position[0]) + np.asarray(normal.x, float), xs, cs)
    ref = patch_friction(case, geom)
    scale = mu / ref if ref > 0 else np.ones_like(mu)
    return np.ascontiguousarray(np.broadcast_to(scale[:, None], np.shape(normal.pressure)))



def patch_creepage(case, geom) -> tuple:
    """The case's creepages where given, else the patch's kinematic ones."""
    return tuple(float(c) for c in (case.creepage or geom.creepage))



def bodies_validity(case, result: PatchResult) -> PatchResult:
    """A bodies case's patch with its size against the given radii (the larger of
    half-width / smallest lateral radius and half-length / smallest rolling radius;
    :mod:`railcontact.geometry.validity`)."""
    a, b = contact_size(result.normal)
    ratio = max(b / case.bodies.smallest_radius("wheel_lateral", "rail_lateral"),
                a / case.bodies.smallest_radius("wheel_rolling", "rail_rolling"))
    status = SolverStatus()
    if ratio > HALF_SPACE_LIMIT:
        status = status.with_warnings(f"half-space: the patch is large against the radii of "
                                      f"curvature (size/radius {ratio:.2f} > {HALF_SPACE_LIMIT})")
    result.validity, result.halfspace_ratio = status, ratio
    return result



def wheel_rail_validity(results, bodies) -> None:
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
