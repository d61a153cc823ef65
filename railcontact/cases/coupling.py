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

The driver (:func:`solve_coupled`, :func:`alternate`) is that of every coupling
of the two problems: it takes a coupling object with ``gap_from_tractions(x, y,
t_x, t_y)`` and ``slip_from_pressure(x, y, p, mode)`` on the grid a solve takes
(:func:`patch_coupling`): :class:`DissimilarCoupling` above, or Blanco's
conformal coefficients
(:class:`~railcontact.normal.conformal_influence.BlancoCoupling`).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from typing import Callable

from ..core.errors import InputError
from ..geometry.conformal import blanco_influence, influence_angles
from ..normal.base import bilinear, same_grid
from ..normal.conformal_influence import BlancoCoupling
from ..normal.influence import Convolution, ShiftedConvolution, coupling_kernels, rigid_slip_of
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
    -(u_t(I+) - u_t(I))/dx in steady rolling, u_t in the shift problem
    (:func:`~railcontact.normal.influence.rigid_slip_of`)."""
    _, (sx, sy) = _grid(x, y, material)
    return rigid_slip_of(-sx(p), -sy(p), float(x[1] - x[0]), mode)


class DissimilarCoupling:
    """The coupling of the normal and tangential problems of bodies of different
    ``material``s: one implementation of the coupling protocol of
    :func:`solve_coupled` (the other: Blanco's conformal coefficients,
    :class:`~railcontact.normal.conformal_influence.BlancoCoupling`)."""

    #: what couples the problems (for the messages)
    name = "dissimilar materials"

    def __init__(self, material):
        self.material = material
        #: whether the problems are coupled (K != 0) and what the result records
        self.couples = bool(material.is_dissimilar)
        self.options = {"difference_parameter": material.difference_parameter}

    def gap_from_tractions(self, x, y, tx_rail, ty_rail) -> np.ndarray:
        """The normal displacement difference [m] on the grid (x, y) [m] from the
        tangential tractions on the rail [Pa] (:func:`normal_gap_from_tractions`)."""
        return normal_gap_from_tractions(x, y, tx_rail, ty_rail, self.material)

    def slip_from_pressure(self, x, y, p, mode: str = "rolling"):
        """The rigid slip (s_x, s_y) the pressure p [Pa] on the grid adds
        (:func:`slip_from_pressure`)."""
        return slip_from_pressure(x, y, p, self.material, mode)


def patch_coupling(geometry, material):
    """The coupling of a patch's normal and tangential problems: Blanco's where the
    patch takes his conformal coefficients
    (:func:`~railcontact.geometry.conformal.blanco_influence`), else that of
    dissimilar materials (none for bodies of one material: K = 0)."""
    if blanco_influence(geometry) is not None:
        return BlancoCoupling(lambda s: influence_angles(geometry, s), material)
    return DissimilarCoupling(material)


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


@dataclass(frozen=True)
class CoupledStart:
    """How :func:`solve_coupled` starts and stops: its ``alternation``, the further
    keywords of the first normal solve (``normal``: a warm start, a kept grid) and
    those of the tangential solves on a normal solution ``ns``
    (``tangential(ns)``: a warm start, friction across the patch, an extra rigid
    slip such as a conformal patch's, to which the pressure's is added)."""

    alternation: Alternation | None = None
    normal: dict | None = None
    tangential: Callable | None = None


def solve_coupled(nmodel, tmodel, geometry, material, creepage, friction, velocity,
                  normal_force=None, penetration=None, grid=None, element_size=None,
                  start: CoupledStart | None = None):
    """Normal and tangential solution of one patch whose problems are coupled:
    dissimilar bodies, or Blanco's conformal coefficients (:func:`patch_coupling`).

    The exact normal solver with the gap's opening from the last tangential
    tractions (``gap_from_tractions``, on the grid the solve takes: the tractions
    interpolated where it differs from the last one's), the exact tangential solver
    with the pressure's rigid slip (``slip_from_pressure``), alternated until both
    settle (:func:`alternate`).  ``nmodel`` and ``tmodel`` must be the exact
    models.  Returns the normal and tangential solutions; the tangential one's
    ``status`` is unconverged where the alternation did not converge (its
    ``options`` hold ``coupling_iterations``).
    """
    if "coupled" not in nmodel.capabilities & tmodel.capabilities:
        raise InputError("coupled normal-tangential solution (dissimilar materials, Blanco's "
                         "coefficients) needs normal = 'exact' and tangential = 'exact'")
    start = start or CoupledStart()
    coupling = patch_coupling(geometry, material)
    kw = {"normal_force": normal_force, "penetration": penetration, "grid": grid,
          "element_size": element_size}
    mode = tmodel.mode                      # declared with "coupled"

    def normal(ns, ts):
        if ns is None:
            return nmodel.solve(geometry, material, **kw, **(start.normal or {}))

        def gap(x, y):
            # the last tractions on the rail on the grid the solve takes (the last
            # one's, unless its potential area changed: then interpolated)
            tx, ty = -ts.traction_x, -ts.traction_y
            if not same_grid(ts.x, ts.y, x, y):
                X, Y = np.meshgrid(x, y, indexing="ij")
                tx, ty = (bilinear(ts.x, ts.y, f, X, Y) for f in (tx, ty))
            return coupling.gap_from_tractions(x, y, tx, ty)
        return nmodel.solve(geometry, material, **kw, warm_start=ns, extra_gap=gap)

    def tangential(ns, ts):
        extra = dict(start.tangential(ns) if start.tangential is not None else {})
        if ts is not None:
            extra["warm_start"] = ts
        sx, sy = coupling.slip_from_pressure(ns.x, ns.y, ns.pressure, mode)
        base = extra.get("extra_slip")
        extra["extra_slip"] = (sx, sy) if base is None else (base[0] + sx, base[1] + sy)
        return tmodel.solve(ns, geometry, material, creepage, friction, velocity, **extra)

    ns, ts, it, converged = alternate(normal, tangential, friction, start.alternation,
                                      coupling.couples)
    ts.options.update(coupling.options)
    return ns, flag_alternation(ts, it, converged, coupling.name)
