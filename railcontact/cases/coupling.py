"""Dissimilar materials: the coupled normal and tangential problems of the exact
theory, solved by alternation (Kalker 1990, section 5.2; the "Panagiotopoulos
process" of CONTACT).

For bodies of different materials the difference parameter
K = G [(1 - 2 nu1)/G1 - (1 - 2 nu2)/G2] / 4 is not zero and the tractions couple
the two problems (:func:`railcontact.normal.influence.coupling_kernels`,
D = K / (pi G)):

* tangential tractions t on body 1 (the rail) open the gap by
  u_n = D (I(x/r^2) * t_x + I(y/r^2) * t_y);
* the pressure p displaces the surfaces tangentially by
  u_t = -D (I(x/r^2), I(y/r^2)) * p, which in steady rolling adds the rigid slip
  -(u_t(I+) - u_t(I)) / dx (and u_t itself in the shift problem).

The alternation solves the normal problem with the tractions' gap, then the
tangential problem with the pressure's slip, until both change by less than
``tol`` (relative to p_max and mu p_max).  For quasi-identical bodies (K = 0) one
pass gives the decoupled solution.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..core.errors import InputError
from ..normal.influence import Convolution, ShiftedConvolution, coupling_kernels
from ..core.status import SolverStatus

log = logging.getLogger(__name__)


@lru_cache(maxsize=16)
def _operators(mx, my, dx, dy, D):
    kx, ky = coupling_kernels(mx, my, dx, dy, D)
    kxs, kys = coupling_kernels(mx, my, dx, dy, D, extra_rows=1)
    return ((Convolution(kx, mx, my), Convolution(ky, mx, my)),
            (ShiftedConvolution(kxs, mx, my, 1), ShiftedConvolution(kys, mx, my, 1)))


def _grid(x, y, material):
    G = material.shear_modulus
    D = material.difference_parameter / (np.pi * G)
    return _operators(x.size, y.size, float(x[1] - x[0]), float(y[1] - y[0]), D)


def normal_gap_from_tractions(x, y, tx_rail, ty_rail, material) -> np.ndarray:
    """Normal displacement difference [m] on the grid from tractions on the rail [Pa]."""
    (cx, cy), _ = _grid(x, y, material)
    return cx(tx_rail) + cy(ty_rail)


def slip_from_pressure(x, y, p, material, mode: str = "rolling"):
    """Additional rigid slip (s_x, s_y) of the pressure p [Pa] on the grid:
    -(u_t(I+) - u_t(I))/dx in steady rolling, u_t in the shift problem."""
    _, (sx, sy) = _grid(x, y, material)
    ux, uy = -sx(p), -sy(p)
    if mode == "shift":
        return np.ascontiguousarray(ux[:-1]), np.ascontiguousarray(uy[:-1])
    dx = float(x[1] - x[0])
    return (np.ascontiguousarray(-(ux[1:] - ux[:-1]) / dx),
            np.ascontiguousarray(-(uy[1:] - uy[:-1]) / dx))


#: largest number of alternations between the normal and the tangential problem
MAX_ALTERNATIONS = 30


@dataclass(frozen=True)
class Alternation:
    """When the alternation between the normal and the tangential problem stops."""

    #: largest change of the pressure and of the traction between two alternations,
    #: relative to p_max and mu p_max [-]
    tol: float = 1e-5
    #: alternations at most (None: ``MAX_ALTERNATIONS``)
    maxiter: int | None = None


def alternate(solve_normal, solve_tangential, friction: float,
              alternation: Alternation | None = None, coupled: bool = True):
    """The alternation between the normal and the tangential problem (CONTACT's
    Panagiotopoulos process): ``solve_normal(ns, ts)`` the normal solution given the
    last normal and tangential solutions (both None at first), ``solve_tangential(ns,
    ts)`` the tangential one on the normal solution ``ns`` (``ts`` the last one or
    None), until the pressure and the traction change by less than the tolerance
    (relative to p_max and ``friction`` p_max).  ``coupled`` False: one pass.
    Returns the normal and tangential solutions, the alternations and whether they
    converged."""
    alternation = alternation or Alternation()
    tol = alternation.tol
    maxiter = MAX_ALTERNATIONS if alternation.maxiter is None else int(alternation.maxiter)
    ns = solve_normal(None, None)
    ts = solve_tangential(ns, None)
    converged = not coupled
    it = 1
    while not converged and it < maxiter:
        it += 1
        ns_new = solve_normal(ns, ts)
        ts_new = solve_tangential(ns_new, ts)
        pm = max(ns_new.pmax, 1e-300)
        dp = float(np.max(np.abs(ns_new.pressure - ns.pressure))) / pm
        dt = float(np.max(np.hypot(ts_new.traction_x - ts.traction_x,
                                   ts_new.traction_y - ts.traction_y))) / (max(friction, 1e-300) * pm)
        ns, ts = ns_new, ts_new
        log.debug("coupling iteration %d: change p %.2e, t %.2e", it, dp, dt)
        converged = dp <= tol and dt <= tol
    return ns, ts, it, converged


def flag_alternation(ts, it: int, converged: bool, what: str):
    """Record the alternations in the tangential solution ``ts`` (its options'
    ``coupling_iterations``) and flag it unconverged where they did not converge
    (``what``: the coupling, for the message)."""
    ts.options.update(coupling_iterations=it)
    if converged:
        return ts
    log.info("%s: the normal-tangential alternation did not converge in %d iterations "
             "(flagged in the result)", what, it)
    msg = f"normal-tangential alternation ({what}) did not converge in {it} iterations"
    if not ts.status.converged:
        msg = f"{ts.status.message}; {msg}"
    ts.status = SolverStatus.failed(msg, it, ts.status.warnings)
    return ts


def solve_coupled(nmodel, tmodel, geometry, material, creepage, friction, velocity,
                  normal_force=None, penetration=None, grid=None, element_size=None,
                  alternation: Alternation | None = None):
    """Normal and tangential solution of one patch of dissimilar bodies.

    ``nmodel`` and ``tmodel`` must be the exact models.  Returns the normal and
    tangential solutions; the tangential one's ``status`` is unconverged where the
    alternation did not converge (its ``options`` hold ``coupling_iterations``).
    """
    if "coupled" not in nmodel.capabilities & tmodel.capabilities:
        raise InputError("coupled normal-tangential solution of dissimilar materials needs "
                         "normal = 'exact' and tangential = 'exact'")
    kw = {"grid": grid, "element_size": element_size}
    load = {"normal_force": normal_force, "penetration": penetration}
    mode = tmodel.mode                      # declared with "coupled"

    def normal(ns, ts):
        if ns is None:
            return nmodel.solve(geometry, material, **load, **kw)
        gap = normal_gap_from_tractions(ns.x, ns.y, -ts.traction_x, -ts.traction_y, material)
        return nmodel.solve(geometry, material, **load, **kw, warm_start=ns, extra_gap=gap)

    def tangential(ns, ts):
        return tmodel.solve(ns, geometry, material, creepage, friction, velocity,
                            warm_start=ts,
                            extra_slip=slip_from_pressure(ns.x, ns.y, ns.pressure, material,
                                                          mode))

    ns, ts, it, converged = alternate(normal, tangential, friction, alternation,
                                      material.is_dissimilar)
    ts.options.update(difference_parameter=material.difference_parameter)
    return ns, flag_alternation(ts, it, converged, "dissimilar materials")
