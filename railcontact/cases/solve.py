"""One contact case from end to end: :func:`solve`.

A bodies case is solved on its given curvatures; a wheel-rail case with its wheel
loads met (:mod:`railcontact.cases.balance`) or at a prescribed position; a case
on rail surfaces by :mod:`railcontact.cases.surfaces`.  The results are
:mod:`railcontact.cases.results`'s.
"""

from __future__ import annotations

import logging
import time

from .case import Case
from .surface_setup import is_surface_case
from .coupling import solve_coupled
from ..geometry.contact import ContactGeometry
from .patches import bodies_validity, case_models, coupled_models
from .results import PatchResult, SolveResult
from .surfaces import solve_on_surfaces
from ..tangential.inverse import solve_for_forces
from .balance import BalanceOptions, solve_at_position, solve_wheel_rail
from ..core.checks import shown
from ..core.errors import InputError

log = logging.getLogger(__name__)


def solve(case: Case, normal: str | None = None, tangential: str | None = None,
          warm_start: "SolveResult | None" = None,
          options: BalanceOptions | None = None) -> SolveResult:
    """Solve one contact case.

    Parameters
    ----------
    case : Case
        From :func:`railcontact.load_case` or :func:`railcontact.cases.case.case_from_dict`.
    normal, tangential : str, optional
        Model names overriding the case's ``[solver]``.
    warm_start : SolveResult, optional
        The result of a similar case (the previous case of a sweep or time history):
        models that accept warm starts (the exact solvers) start from its patches'
        solutions (same side, within 3 mm on the rail) instead of cold.
    options : BalanceOptions, optional
        How a wheel-rail case's vertical balance runs
        (:class:`railcontact.cases.balance.BalanceOptions`; default: the package's),
        e.g. for a comparison of its starts.

    For wheel-rail cases the geometry layer finds the wheelset position under the
    vertical load and the patches; each patch is solved with its own penetration.
    A warm-started case that does not converge is solved again cold (except where
    the model's vertical force jumps across the load: ``balance.force_jump``).

    A case on rail surfaces (rails given by slices, several rails, a roller:
    :mod:`railcontact.cases.surfaces`) is solved by
    :func:`railcontact.cases.surfaces.solve_on_surfaces`.
    """
    if not isinstance(case, Case):
        raise InputError(f"case = {shown(case)}: expected a Case (railcontact.load_case(path) "
                         "or railcontact.case_from_dict(dict))")
    for name, value in (("normal", normal), ("tangential", tangential)):
        if value is not None and not isinstance(value, str):
            raise InputError(f"{name} = {shown(value)}: expected a model name (str) or None")
    if warm_start is not None and not isinstance(warm_start, SolveResult):
        raise InputError(f"warm_start = {shown(warm_start)}: expected a SolveResult or None")
    if options is not None and not isinstance(options, BalanceOptions):
        raise InputError(f"options = {shown(options)}: expected a "
                         "railcontact.cases.balance.BalanceOptions or None")
    if not case.is_bodies and is_surface_case(case):
        return _finish(solve_on_surfaces(case, normal, tangential, warm_start=warm_start),
                       case)
    if warm_start is not None:
        res = _solve(case, normal, tangential, warm_start, options)
        # a force that jumps across the load is the model's: a cold start meets it too
        if res.converged or (res.balance is not None and res.balance.force_jump):
            return _finish(res, case)
        log.info("warm-started case did not converge; solving it again cold")
        cold = _solve(case, normal, tangential, None, options)
        cold.cpu_time += res.cpu_time                 # the failed attempt counts
        return _finish(cold, case)
    return _finish(_solve(case, normal, tangential, None, options), case)


#: p_max [Pa] beyond which a result is flagged where the case gives no yield stress:
#: Tabor's hardness, 3 x the yield stress, of a rail steel of 1 GPa yield stress
#: (head-hardened grades): no elastic-perfectly-plastic contact carries more
#: (docs/case_files.md, "Convergence and validity")
DEFAULT_PRESSURE_LIMIT = 3.0e9


def _elastic_plastic(res: SolveResult, case: Case) -> SolveResult:
    """``[plasticity] model = "elastic-plastic"``: every loaded patch solved again
    elastic-plastically under its normal force
    (:func:`railcontact.subsurface.elastoplastic.solve_elastic_plastic`), the result
    in ``patch.elastic_plastic``; the elastic solution stays in ``patch.normal``."""
    from ..subsurface.elastoplastic import solve_elastic_plastic
    for p in res.patches:
        if p.normal is not None and p.normal.normal_force > 0:
            t0 = time.perf_counter()
            p.elastic_plastic = solve_elastic_plastic(p.geometry, case.material,
                                                      p.normal.normal_force,
                                                      case.elastic_plastic)
            res.cpu_time += time.perf_counter() - t0
    return res


def _finish(res: SolveResult, case: Case) -> SolveResult:
    """The pressure check, and the case's thermal constants on every patch (its
    flash temperatures, :attr:`PatchResult.temperatures`)."""
    for p in res.patches:
        p.thermal = case.thermal
    return _check_pressure(res, case)


def _check_pressure(res: SolveResult, case: Case) -> SolveResult:
    """A warning on each patch whose p_max exceeds the material's pressure limit:
    ``material.yield_stress`` x 3 (Tabor's hardness) where given, else
    :data:`DEFAULT_PRESSURE_LIMIT`; none where ``[plasticity]`` bounds the pressure
    (the pressure cap) or the patches are solved elastic-plastically."""
    if case.elastic_plastic is not None:
        return _elastic_plastic(res, case)
    if "pressure_limit" in case.normal_options:
        return res
    ys = case.yield_stress
    limit = 3.0 * ys if ys is not None else DEFAULT_PRESSURE_LIMIT
    for p in res.patches:
        if p.normal is not None and p.normal.pmax > limit * (1 + 1e-9):
            p.validity = p.validity.with_warnings(
                f"plasticity: p_max {p.normal.pmax / 1e9:.2f} GPa exceeds the elastic "
                f"material's limit {limit / 1e9:.2f} GPa (3 x yield stress); the elastic "
                "result overstates the pressure: give [plasticity] with the exact model")
    return res



def _solve(case, normal, tangential, warm_start, options=None):
    """:func:`solve` with or without a warm start."""
    t0 = time.perf_counter()
    nname, tname, nmodel, tmodel, kw = case_models(case, normal, tangential)
    results, pose, contact, balance = [], None, None, None
    if case.is_bodies:
        bodies = case.bodies
        geom = ContactGeometry(curvatures=bodies.curvatures, rolling_radius=bodies.rolling_radius)
        wkw = {}
        if warm_start is not None and warm_start.patches:
            if "warm-start" in nmodel.capabilities:
                wkw["warm_start"] = warm_start.patches[0].normal
        ns = nmodel.solve(geom, case.material, normal_force=bodies.normal_force, **kw, **wkw)
        creep = case.creepage or (0.0, 0.0, 0.0)
        V = bodies.velocity
        if coupled_models(case, nmodel, tmodel) and bodies.forces is None:
            ns, ts = solve_coupled(nmodel, tmodel, geom, case.material, creep, case.friction,
                                   V, normal_force=bodies.normal_force, **kw)
        elif bodies.forces is not None and tmodel is not None:
            ts = solve_for_forces(tmodel, ns, geom, case.material, bodies.forces,
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
        results.append(bodies_validity(case, PatchResult(geom, ns, ts, tuple(creep))))
    elif case.wheel_rail.vertical_position is not None:
        results, contact = solve_at_position(case, nmodel, tmodel, kw)
        pose = contact.pose
    else:
        results, contact, balance = solve_wheel_rail(case, nmodel, tmodel, kw,
                                                      rtol=case.force_tolerance,
                                                      start=warm_start, options=options)
        pose = contact.pose
    return SolveResult(results, nname, tname, time.perf_counter() - t0, case.title, pose, contact,
                       balance)
