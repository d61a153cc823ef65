"""Conformal contact in a wheel-rail case (``solver.contact_surface = "conformal"``,
CONTACT's DISCNS = 4): the exact solvers on the curved reference surface of
:mod:`railcontact.geometry.conformal`.

The same boundary-element machinery as the planar approach: the exact normal
solver on the developed grid (x, s) with the gap along the surface normals, the
exact tangential solver with the conformal part of the rigid slip as its extra
slip, and the patch's forces turned back to its tangent plane (CONTACT's bar
forces) so that the vertical balance and the results see them as a planar patch's.
``NormalSolution.y`` and ``TangentialSolution.y`` are then arc lengths s [m]
along the reference curve, and ``options["tilde_fn"]`` of the normal solution
holds CONTACT's TILDE_FN (the pressure's integral on the curved surface).

With ``solver.influence = "blanco"`` (CONTACT's INFLCF = 4) the exact solvers
take Blanco's influence coefficients, corrected for the turning of the surface
(:mod:`railcontact.normal.conformal_influence`); they couple the normal and the
tangential problem, which :func:`railcontact.cases.coupling.solve_coupled` solves
by alternation (CONTACT's Panagiotopoulos process), as it does for dissimilar
materials.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..geometry.conformal import bar_forces, conformal_geometry, conformal_slip
from ..tangential.exact import SPIN_OFFSET

__all__ = ["is_conformal", "conformal_patch", "conformal_normal", "conformal_extra_slip",
           "conformal_friction", "conformal_tangential"]


def is_conformal(case) -> bool:
    """Whether a wheel-rail case asks for the conformal approach."""
    setup = getattr(case, "wheel_rail", None)
    return bool(setup is not None and getattr(setup, "conformal", False))


def conformal_patch(case, geom):
    """The patch on its curved reference surface where the case asks for it (else
    ``geom`` as it is)."""
    if not is_conformal(case) or geom.surface is not None:
        return geom
    return conformal_geometry(geom, getattr(case.wheel_rail, "influence", None))


def conformal_normal(geom, ns, tangential=None):
    """The normal solution with CONTACT's bar F_n (the pressure, and the lateral
    traction of ``tangential`` where given, turned to the tangent plane) as its
    ``normal_force``; TILDE_FN in ``options``-like attribute ``tilde_fn``."""
    if geom.surface is None:
        return ns
    dA = float((ns.x[1] - ns.x[0]) * (ns.y[1] - ns.y[0])) if ns.x.size > 1 and \
        ns.y.size > 1 else 0.0
    ty = None if tangential is None else tangential.traction_y
    fn, _, tilde = bar_forces(geom, ns.y, ns.pressure, ty, dA)
    out = dataclasses.replace(ns, normal_force=fn)
    out.tilde_fn = tilde
    return out


def conformal_extra_slip(geom, normal, creepage):
    """The extra rigid slip of a conformal patch on its normal solution's grid (the
    spin taken where the exact solver takes it, SPIN_OFFSET elements downstream);
    None for a planar patch."""
    if geom.surface is None:
        return None
    x = normal.x
    dx = float(x[1] - x[0]) if x.size > 1 else 0.0
    return conformal_slip(geom, creepage, x, normal.y, x_spin=x + SPIN_OFFSET * dx)


def conformal_friction(case, geom, normal):
    """Friction coefficients per grid column of a conformal patch where the case's
    friction varies with the rail surface's inclination (``friction.variation``,
    CONTACT's VARFRC = 1): by the local angle of the reference curve at each column
    (CONTACT varies them over the curved surface's columns); None where the
    friction is one coefficient or the patch is planar."""
    if geom.surface is None or case.friction_variation is None:
        return None
    rail = case.wheel_rail.rail
    incl = rail.inclination
    if incl is None:
        from ..profiles.library import DEFAULT_INCLINATION, RAIL_PROFILES
        incl = DEFAULT_INCLINATION if str(rail.name).upper() in RAIL_PROFILES else 0.0
    sgn = 1.0 if geom.side == "right" else -1.0
    angles, coefficients = case.friction_variation
    local = sgn * np.asarray(geom.local_contact_angle(normal.y), dtype=float) + float(incl)
    return np.interp(local, angles, coefficients)[None, :]


def conformal_tangential(geom, ns, ts):
    """The normal and tangential solutions of a conformal patch with its bar
    forces: F_n and F_y in the patch's tangent plane (F_x unchanged)."""
    if geom.surface is None or ts is None:
        return ns, ts
    dA = float((ns.x[1] - ns.x[0]) * (ns.y[1] - ns.y[0]))
    fn, fy, tilde = bar_forces(geom, ns.y, ns.pressure, ts.traction_y, dA)
    n2 = dataclasses.replace(ns, normal_force=fn)
    n2.tilde_fn = tilde
    return n2, dataclasses.replace(ts, fy=fy)
