"""The strip models and their creep forces on a patch of the compiled pass: one
compiled function per patch row (:func:`strip_row`), called by the compiled case
(:func:`railcontact.cases.compiled_case.evaluate_wheelset`) and the online
dynamics (:mod:`railcontact.dynamics.online_contact`).

The steps are those of the batch path (:func:`railcontact.cases.batch.solve_patches`
on the strip models), on the same compiled kernels:

* the patch's gap frame from its row (:func:`railcontact.geometry.wheel_pass.row_frame`,
  the frame of :func:`~railcontact.geometry.wheel_pass.patch_geometry`'s
  :class:`~railcontact.geometry.gap.GapEvaluator`);
* the gap sampled on three lines per strip and the strip quantities
  (:func:`railcontact.normal.strip_batch.strip_window_geometry`);
* the strip model's half-lengths and peaks
  (:func:`railcontact.normal.strip_theory.strip_patch`, the per-patch models' own
  kernel: Kik-Piotrowski, KPEC, STRIPES, ANALYN);
* the normal force, area, p_max and equivalent ellipse
  (:func:`railcontact.normal.strip_batch.strip_totals`);
* the creep forces: FASTSIM marching the strips' semi-elliptic pressures
  (:func:`railcontact.tangential.fastsim.strip_patch_forces`) with the
  flexibilities of the equivalent ellipse (``fastsim``) or of each strip's local
  ellipse and the spin of its local contact angle (``fastsim-strips``,
  :func:`~railcontact.tangential.fastsim.strip_flexibilities`,
  :func:`~railcontact.geometry.gap.strip_spin`), or an online law (Polach, linear)
  on the equivalent ellipse (:func:`railcontact.tangential.online.patch_forces`).

The strips: in a case, ``solver.grid`` (elements per strip, strips), as the
per-patch models lay their strips on the grid's columns; in the dynamics, the
batch path's 40 strips with 20 elements in Kik-Piotrowski's displacement sum and
the run's FASTSIM elements.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from ..geometry.gap import Spline, strip_spin
from ..geometry.wheel_pass import (P_A, P_APPROACH, P_B, P_CONTACT_ANGLE, P_ETA, P_PHI,
                                   P_SPIN_DERIVATIVE, P_VELOCITY, P_XI, P_Y_RAIL, row_frame)
from ..normal.strip_batch import StripGrid, strip_totals, strip_window_ends
from ..normal.strip_theory import (MIN_CURVATURE, STRIP_MODELS, StripRule, StripSet, strip_patch,
                                    strip_rule)
from ..tangential.fastsim import (StripArrays, flex_material, semi_ellipse_weights,
                                  strip_flexibilities, strip_patch_forces)
from ..tangential.kalker import Creepage, Flexibilities, _coefficients_kernel
from ..tangential.online import patch_forces

#: how the creep forces of a strip patch are found (:class:`StripPass` ``march``):
#: an online law on the equivalent ellipse, FASTSIM on the strips with the
#: ellipse's flexibilities, ``fastsim-strips`` (local ellipses and spin)
ELLIPSE_LAW, MARCH_FASTSIM, MARCH_LOCAL = 0, 1, 2
#: the tangential models that march the strips here, by name
MARCHES = {"fastsim": MARCH_FASTSIM, "fastsim-strips": MARCH_LOCAL}

#: the strip model of a compiled pass: ``rule``
#: (:class:`~railcontact.normal.strip_theory.StripRule`; code -1: no strip model,
#: Hertz's ellipse), ``grid`` (:class:`~railcontact.normal.strip_batch.StripGrid`),
#: ``march`` (:data:`ELLIPSE_LAW`, ...), FASTSIM's ``elements`` per strip, and the
#: material and tables of the flexibilities ``mat``
#: (:class:`~railcontact.tangential.fastsim.FlexMaterial`)
StripPass = namedtuple("StripPass", "rule grid march elements mat")


def strip_pass(normal: str | None, tangential: str, material, strips: int = 40,
               elements: int = 20, march_elements: int = 20) -> StripPass:
    """The :class:`StripPass` of a model pair (``normal`` None or not a strip model:
    Hertz, code -1) for a material: ``strips`` strips per patch, ``elements`` per
    strip in Kik-Piotrowski's and KPEC's displacement sum and ``march_elements`` in
    FASTSIM's march."""
    if normal is not None and normal in STRIP_MODELS:
        rule = strip_rule(normal, material.contact_modulus, elements=int(elements))
    else:
        rule = strip_rule("analyn", material.contact_modulus)._replace(code=-1)
    return StripPass(rule, StripGrid(max(int(strips), 5), 0.15, 4, True),
                     MARCHES.get(tangential, ELLIPSE_LAW), max(int(march_elements), 2),
                     flex_material(material))


@njit(cache=True, nogil=True)
def strip_row(row, prof, pose, z, roll, model):
    """The strip model of ``model.strips`` (:class:`StripPass`) and the creep forces
    on a patch row of :func:`railcontact.geometry.wheel_pass.search_patches` at the
    pose (vertical position z [m], roll [rad]), at the row's approach; ``prof`` the
    :class:`~railcontact.geometry.wheel_pass.PassProfiles`, ``model`` a
    :class:`~railcontact.cases.compiled_case.PassModel` (friction ``tp[0]``, the
    online law and the case's creepages, NaN: the row's).  Returns (F_n [N], F_x,
    F_y [N], M_z [N m] on the wheel, equivalent semi-axes a, b [m], p_max [Pa],
    area [m^2])."""
    return strip_row_ends(row, prof, pose, z, roll, model, np.full(3, np.nan))


@njit(cache=True, nogil=True)
def strip_row_ends(row, prof, pose, z, roll, model, ends):
    """:func:`strip_row` with the strips laid from the run's ends of an earlier
    evaluation of the patch (``ends`` (3,): the run's two ends [m] in the strips'
    lateral coordinate of the row's gap frame, NaN: none), which take the ends
    found and whether the warm start was kept (1) or not (0)
    (:func:`railcontact.normal.strip_batch.strip_window_ends`: a warm start for a
    time history, the same layout to the ends' tolerance, 1e-9 m)."""
    sp = model.strips
    pen = row[P_APPROACH]
    if not pen > 0.0:
        ends[0] = ends[1] = math.nan
        ends[2] = 0.0
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    frame = np.empty(24)
    win = np.empty(8)
    sgn = row_frame(row, pose, z, roll, frame, win[4:])
    win[0], win[1] = pen, pen
    win[2], win[3] = max(row[P_A], MIN_CURVATURE), max(row[P_B], MIN_CURVATURE)
    n = sp.grid.strips
    y = np.empty(n)
    q = np.empty((4, n))
    rail = Spline(prof.rb, prof.rc)
    dy = strip_window_ends(frame, sgn, rail, Spline(prof.wb, prof.wc), win, sp.grid, y, q,
                           ends)
    hstar = q[1] - pen
    half = np.empty(n)
    peak = np.empty(n)
    work = np.empty((3, n))
    strip_patch(StripSet(y, dy, q[0], hstar, q[2], q[3]), sp.rule, half, peak, work)
    F, area, pmax, a, b = strip_totals(q[0], half, peak, dy)
    fx = fy = mz = 0.0
    if F > 0.0 and a > 0.0 and b > 0.0:
        cr = model.creepage
        xi = cr[0] if cr[0] == cr[0] else row[P_XI]
        eta = cr[1] if cr[1] == cr[1] else row[P_ETA]
        phi = cr[2] if cr[2] == cr[2] else row[P_PHI]
        mu = model.tp[0]
        if sp.march == ELLIPSE_LAW:
            c = np.empty((3, 1))
            _coefficients_kernel(np.array([a / b]), model.nu, model.kalker_ab,
                                 model.kalker_ba, c)
            fx, fy, mz = patch_forces(model.law, model.tp, F, a, b, c[0, 0], c[1, 0],
                                      c[2, 0], xi, eta, phi, row[P_VELOCITY])
        else:
            L = np.empty((3, n))
            local = sp.march == MARCH_LOCAL
            # the local ellipses' approach: the deepest strip's interpenetration, not
            # the row's (the gap at the locus's deepest sample, which jumps, by some
            # 0.5 um on a deep flange patch, where that sample passes to the next:
            # the creep forces, and the balance's vertical force, jumped with it)
            deep = -np.min(hstar)
            strip_flexibilities(half, q[2], q[3], deep if deep > 0.0 else pen, (a, b, F),
                                (xi, eta, phi), mu, sp.mat, local, L)
            phis = np.full(n, phi)
            if local:
                d = row[P_CONTACT_ANGLE]
                strip_spin(rail, (sgn, row[P_Y_RAIL], math.cos(d), d, phi,
                                  row[P_SPIN_DERIVATIVE]), y, phis)
            nx = sp.elements
            fx, fy, mz = strip_patch_forces(StripArrays(y, dy, q[0], half, peak),
                                            Flexibilities(L[0], L[1], L[2]), mu,
                                            Creepage(xi, eta, phis),
                                            semi_ellipse_weights(nx), np.empty(n),
                                            np.empty(n), np.empty((n, nx)))
    return F, fx, fy, mz, a, b, pmax, area


__all__ = ["StripPass", "StripRule", "strip_pass", "strip_row", "strip_row_ends", "MARCHES"]
