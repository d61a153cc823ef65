"""A whole wheel-rail case in one compiled pass: contact search, Hertz and an
online creep law, and the vertical balance, with Python only where the case enters
and leaves (:func:`solve_case_forces`, :func:`solve_cases_forces`).

Per evaluation of the balance, one compiled function
(:func:`evaluate_wheelset`) searches the pose and the patches of both wheels under
the interpenetrations (:func:`railcontact.geometry.wheel_pass.search_patches`,
the geometry layer's search in compiled form), solves Hertz's problem of every
patch (Hertz 1882; the semi-axes interpolated in the table of
:func:`railcontact.core.hertz_theory.hertz_ellipses_table`, relative error below
1e-7), Kalker's coefficients (:func:`railcontact.tangential.kalker.kalker_coefficients`)
and the creep forces of the case's online law
(:func:`railcontact.tangential.online.patch_forces`: FASTSIM, Polach or Kalker's
linear theory), and sums each wheel's vertical force on its rail,
F_n cos(d) - F_y sin(d) (:func:`railcontact.cases.results.patch_vertical_force`).

The vertical balance (:func:`balance_wheelset`) starts from the first estimate
(:func:`first_estimate`: the rigid pose, and each side's load carried by the
balance's own model on its locus there, the regions' force curvature included,
:func:`approach_for_load`) or a neighbour's interpenetrations, evaluated by the
search under those interpenetrations.  From there it takes Newton steps on the
wheelset's pose (vertical position and roll, :func:`pose_newton`): for
g_s = (F_s/Q_s)^(2/3) - 1, linear in a Hertzian patch's approach, with the
Jacobian of the patches' dN/d(delta) = e N/delta (e: the estimate's or the
neighbour's exponent) and their approaches' rates with the pose, then Broyden's
update (Broyden 1965), a trust region on the approaches and halved steps.  Where
those do not meet the load (a force not smooth in the pose), the method of
:func:`railcontact.cases.equilibrium.balance` for both wheels in compiled form
takes over: in v = ln d the residuals r = ln(F/Q), Newton steps of the linear
model with Broyden's update, each component clipped to a factor
``STEP_FACTOR``, safeguarded by each side's bracket of the load (bisection where
a step leaves it or two steps did not halve the residual).  A case it cannot
finish (a force jumping across the load, a pose not found, a patch without
curvatures) is flagged and left to the Python path
(:func:`railcontact.cases.balance.solve_wheel_rail`).

Which cases run here: wheel-rail cases with given loads and a free roll, the same
wheel and rail profile on both sides, a normal model with the ``"ellipse"``
capability (Hertz) and a tangential model with a compiled online law, or a strip
model (``kik-piotrowski``, ``kpec``, ``stripes``, ``analyn``; without normal
options) with a compiled online law or ``fastsim-strips``
(:mod:`railcontact.cases.strip_pass`: the strips of each patch sampled on its
exact gap, the model's own compiled kernel, the strips' FASTSIM march), no
``friction.variation``, no patch turning (``wheelset.turn_distance`` 0) and
similar materials (:func:`compiled_unsupported` says why not); either contact
locus (``wheelset.locus``: each wheel circle's lowest point, or CONTACT's; the
geometry layer's locus kernel, :func:`railcontact.geometry.locus._locus_kernel`).

FASTSIM runs on the case's grid (``solver.grid``; default 40 x 40): strips across
the ellipse and elements per strip, as the per-patch model marches the Hertzian
grid.  The per-patch path (:func:`railcontact.solve`) and this one share the
balance's interpenetrations: the per-patch path starts from them
(:func:`compiled_start`), so that its own balance is met in one or two passes.
"""

from __future__ import annotations

import math
import time
from collections import namedtuple
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from numba import njit

from ..core.hertz_theory import _axes_table
from ..geometry.locus import LOCUS_WINDOW  # noqa: F401  (documented neighbour)
from ..geometry.search import ESTIMATE_WINDOW
from ..geometry.wheel_pass import (LOCUS_MARGIN, M_GAPS, MAX_PATCHES, NPF, TRIM_MARGIN, P_A, P_APPROACH, P_B, P_CONTACT_ANGLE,
                                   P_B_FORCE, P_ETA, P_PHI, P_ROLLING_RADIUS, P_SIDE, P_VELOCITY, P_XI, P_Y,
                                   PATCH_FIELDS, PassPose, gap_candidates, make_patch,
                                   locus_curvatures, new_memo, pass_profiles, search_patches,
                                   side_locus, solve_roll)
from ..core.materials import STEEL
from ..normal import normal_supports
from ..normal.strip_theory import STRIP_MODELS
from ..tangential.kalker import _TAB_AB, _TAB_BA, _coefficients_kernel
from ..tangential.online import online_law, patch_forces
from ..geometry.track import WheelsetPose
from ..geometry.patch_curvature import force_curvature
from ..geometry.wheel_pass import locus_regions, rows_contact
from .bodies import build_wheelset_track
from .strip_pass import MARCHES, strip_pass, strip_row
from .equilibrium import (COUPLING_SLOPE, FORCE_FLOOR, HERTZ_SLOPE, JUMP_SLOPE, STEP_FACTOR,
                          Neighbour, extrapolate_start)

#: the fields of a row of :func:`evaluate_wheelset`'s output: the patch's geometry
#: (:data:`railcontact.geometry.wheel_pass.PATCH_FIELDS`) and its solution
ROW_FIELDS = PATCH_FIELDS + ("normal_force", "fx", "fy", "mz", "a", "b", "pmax", "area")
RF = {name: i for i, name in enumerate(ROW_FIELDS)}
NRF = len(ROW_FIELDS)
R_NORMAL_FORCE = NPF + 0
R_FX = NPF + 1
R_FY = NPF + 2
R_MZ = NPF + 3
R_A = NPF + 4
R_B = NPF + 5
R_PMAX = NPF + 6
R_AREA = NPF + 7

#: the models of a compiled case: contact modulus ``Es`` [Pa], shear modulus ``G``
#: [Pa], Poisson's ratio ``nu``, the online law's code ``law`` and its parameters
#: ``tp`` (:func:`railcontact.tangential.online.patch_forces`), the case's
#: creepages ``creepage`` (xi, eta, phi; NaN: the kinematic ones); the Hertz table
#: ``dt``, ``hertz`` and Kalker's tables ``kalker_ab``, ``kalker_ba``; the strip
#: model ``strips`` (:class:`~railcontact.cases.strip_pass.StripPass`; by default
#: none: Hertz's ellipse)
PassModel = namedtuple("PassModel", "Es G nu law tp creepage dt hertz kalker_ab kalker_ba "
                       "strips", defaults=(strip_pass(None, "fastsim", STEEL),))

#: the first estimate (:func:`approach_for_load`) iterates on the balance's model
#: until its vertical force meets the load to this |ln(F/Q)| (the balance's own
#: evaluation differs from it by the roll that the two sides' interpenetrations
#: give and the exact gap: some 1e-3 to 1e-2), at most ``ESTIMATE_PASSES`` times
ESTIMATE_TOLERANCE = 1e-3
ESTIMATE_PASSES = 30
#: the step in ln d of the difference that gives the first estimate's slope
#: d(ln F)/d(ln d) (the balance's first Jacobian), and the range it is held in
ESTIMATE_DIFFERENCE = 0.02
SLOPE_RANGE = (1.0, 20.0)
#: the estimate carries the load with the creep forces' share of the vertical force
#: (:func:`creep_factor`) where that factor lies in this range
CREEP_RANGE = (0.2, 5.0)
#: ... and differs from 1 by more than this (the first evaluation lies within some
#: 1e-3 to 1e-2 of the estimate's load anyway); a side whose friction times the rail
#: slope under its interpenetration is below it is not evaluated
CREEP_MIN = 1e-2

#: the balance's steps after its first evaluation are Newton steps on the pose
#: (:func:`pose_newton`), at most ``POSE_PASSES`` evaluations, a step that does
#: not reduce the residual halved up to ``POSE_HALVINGS`` times; then (or with
#: False) the steps on the interpenetrations (:func:`balance_wheelset`)
POSE_BALANCE = True
#: where those steps do not meet the load, the steps on the interpenetrations start
#: from the last accepted pose with the pose's evaluations as their history
POSE_PASSES = 16
POSE_HALVINGS = 3
#: a step of :func:`pose_newton` changes no loaded patch's approach by more than
#: this fraction of itself
POSE_TRUST = 1.0
#: a warm start whose first evaluation lies further than this from the load in
#: |ln(F/Q)| evaluates the neighbour's pose too and goes on from the better
POSE_RESTART = 0.3
#: the range of the exponents of :func:`pose_jacobian`
EXPONENT_RANGE = (1.2, 3.0)

#: the outcome codes of :func:`balance_wheelset`
CONVERGED, NOT_CONVERGED, NO_POSE, JUMP = 0, 1, 2, 3
OUTCOMES = {CONVERGED: "converged", NOT_CONVERGED: "not converged", NO_POSE: "pose not found",
            JUMP: "force jumps across the load"}

#: fields of the balance's ``info`` array
INFO_FIELDS = ("outcome", "passes", "d_left", "d_right", "vertical", "roll", "fz_left",
               "fz_right", "J00", "J01", "J10", "J11", "patches", "pose_passes")
I_OUTCOME = 0
I_PASSES = 1
I_D_LEFT = 2
I_D_RIGHT = 3
I_VERTICAL = 4
I_ROLL = 5
I_FZ_LEFT = 6
I_FZ_RIGHT = 7
I_J00 = 8
I_J01 = 9
I_J10 = 10
I_J11 = 11
I_PATCHES = 12
I_POSE_PASSES = 13


@njit(cache=True, nogil=True)
def hertz_patch(A, B, d, model):
    """Semi-axes a, b [m] and force [N] of Hertz's ellipse of curvatures (A, B) at
    the approach d (the table of :func:`railcontact.core.hertz_theory.hertz_ellipses_table`)."""
    tab = model.hertz
    n = tab.shape[1]
    small = min(A, B)
    t = math.log(max(A, B) / small) / model.dt
    j = min(int(t), n - 2)
    w = t - j
    dp = max(d, 0.0)
    major = math.sqrt(dp / small) * ((1.0 - w) * tab[0, j] + w * tab[0, j + 1])
    minor = ((1.0 - w) * tab[1, j] + w * tab[1, j + 1]) * major
    F = 2.0 * math.pi * major * dp * model.Es / 3.0 * ((1.0 - w) * tab[2, j] + w * tab[2, j + 1])
    if A <= B:
        return major, minor, F
    return minor, major, F


@njit(cache=True, nogil=True)
def patch_hertz(row, model):
    """Hertz's semi-axes a, b [m] and force [N] of a patch row at its approach: the
    force with the lateral curvature ``B_force``
    (:func:`railcontact.geometry.wheel_pass.force_curvature`), the ellipse with the
    deepest point's curvatures (A, B) scaled to that force (a, b ~ F^(1/3)).  The
    deepest point's curvature jumps where the gap has two minima of equal depth
    (S1002 on 60E1's near-conformal tread: 3.95 to 0.28 1/m); there the region's
    (its depth and width, continuous in the pose) takes over, so that the force is
    continuous in the interpenetration.  The compiled case and the online dynamics
    (:mod:`railcontact.dynamics.online_contact`) share it."""
    A, d = row[P_A], row[P_APPROACH]
    a, b, F = hertz_patch(A, row[P_B], d, model)
    bf = row[P_B_FORCE]
    if bf > 0.0 and bf != row[P_B]:
        _, _, Fs = hertz_patch(A, bf, d, model)
        if F > 0.0 and Fs > 0.0:
            scale = (Fs / F) ** (1.0 / 3.0)
            a, b, F = a * scale, b * scale, Fs
    return a, b, F


@njit(cache=True, nogil=True)
def solve_patch(row, model):
    """Hertz (:func:`patch_hertz`) and the online law on one patch row
    (:data:`ROW_FIELDS`)."""
    a, b, F = patch_hertz(row, model)
    fx = fy = mz = 0.0
    if F > 0.0 and a > 0.0 and b > 0.0:
        c = np.empty((3, 1))
        _coefficients_kernel(np.array([a / b]), model.nu, model.kalker_ab, model.kalker_ba, c)
        cr = model.creepage
        xi = cr[0] if cr[0] == cr[0] else row[P_XI]
        eta = cr[1] if cr[1] == cr[1] else row[P_ETA]
        phi = cr[2] if cr[2] == cr[2] else row[P_PHI]
        fx, fy, mz = patch_forces(model.law, model.tp, F, a, b, c[0, 0], c[1, 0], c[2, 0],
                                  xi, eta, phi, row[P_VELOCITY])
    area = math.pi * a * b
    store_patch(row, (F, fx, fy, mz, a, b, 1.5 * F / area if area > 0.0 else 0.0, area))


@njit(cache=True, nogil=True)
def solve_strip_patch(row, prof, pose, z, roll, model):
    """The strip model and creep law of ``model.strips`` on one patch row
    (:func:`railcontact.cases.strip_pass.strip_row`) into its :data:`ROW_FIELDS`."""
    store_patch(row, strip_row(row, prof, pose, z, roll, model))


@njit(cache=True, nogil=True)
def store_patch(row, solved):
    """A patch's solution ``solved`` = (F_n, F_x, F_y, M_z, a, b, p_max, area), as a
    strip model's row returns it, into the row's :data:`ROW_FIELDS`."""
    F, fx, fy, mz, a, b, pmax, area = solved
    row[R_NORMAL_FORCE] = F
    row[R_FX] = fx
    row[R_FY] = fy
    row[R_MZ] = mz
    row[R_A] = a
    row[R_B] = b
    row[R_AREA] = area
    row[R_PMAX] = pmax


@njit(cache=True, nogil=True)
def solve_row(row, prof, pose, z, roll, model):
    """One patch row at the pose (vertical position z [m], roll [rad]) solved by the
    balance's model: the strip model of ``model.strips``
    (:func:`solve_strip_patch`) or Hertz (:func:`solve_patch`).  Both the
    evaluation under given interpenetrations (:func:`evaluate_wheelset`) and at a
    given pose (:func:`evaluate_pose`, the steps of :func:`pose_newton`) solve
    their patches here, so that the balance meets the load by the case's model."""
    if model.strips.rule.code >= 0:
        solve_strip_patch(row, prof, pose, z, roll, model)
    else:
        solve_patch(row, model)


@njit(cache=True, nogil=True)
def evaluate_wheelset(prof, pose, model, targets, memo, out, fz):
    """One evaluation of the balance: the search at the interpenetrations
    ``targets`` [m] (left, right), every patch solved (Hertz, or the strip model
    of ``model.strips``), each wheel's vertical force on its rail into ``fz`` [N].
    Returns (patches, vertical position, roll); -1 patches where the pose is not
    found."""
    m, z, roll = search_patches(prof, pose, targets, memo, out)
    fz[0] = 0.0
    fz[1] = 0.0
    for i in range(max(m, 0)):
        row = out[i]
        solve_row(row, prof, pose, z, roll, model)
        dl = row[P_CONTACT_ANGLE]
        fz[int(row[P_SIDE])] += row[R_NORMAL_FORCE] * math.cos(dl) - \
            row[R_FY] * math.sin(dl)
    return m, z, roll


@njit(cache=True, nogil=True)
def estimate_force(loc, gs, d, pose, prof, model):
    """The vertical force [N] that the rigid pose's locus ``loc`` (the wheel
    lowered by ``d`` [m] below its closest approach, no roll) carries by the
    balance's model: every interpenetration region of the lowered gap (``gs``, a
    work array, takes it) a patch at its deepest sample, Hertz with that point's
    curvatures (:func:`railcontact.geometry.wheel_pass.locus_curvatures`) but the
    lateral one the region's force curvature
    (:func:`railcontact.geometry.patch_curvature.force_curvature`, as
    :func:`patch_hertz`), at the approach (d - off) cos(theta) (off: the sample's
    gap above the closest approach, theta: the rail's slope angle there), its
    vertical component."""
    gap = loc[5]
    gmin = np.min(gap)
    for j in range(gap.size):
        gs[j] = gap[j] - gmin - d
    low = (loc[0], loc[1], loc[2], loc[3], loc[4], gs, loc[6], loc[7], loc[8], loc[9])
    regions = locus_regions(gs, loc[3], loc[4], pose.combine)
    total = 0.0
    for r in range(regions.shape[0]):
        i0, i1 = regions[r, 0], regions[r, 1]
        im = i0
        for i in range(i0, i1 + 1):
            if gs[i] < gs[im]:
                im = i
        if not gs[im] < 0.0:
            continue
        A, B = locus_curvatures(loc, im, pose.r0, prof.zw[loc[0]:])
        bf = force_curvature(low, i0, i1, im, B)
        if bf > 0.0:
            B = bf
        c = math.cos(math.atan(loc[6][im]))
        _, _, F = hertz_patch(A, B, -gs[im] * c, model)
        total += F * c
    return total


@njit(cache=True, nogil=True)
def approach_for_load(loc, load, pose, prof, model):
    """The deepest point's vertical interpenetration d [m] that carries ``load``
    [N] by the balance's own model on the rigid pose's locus
    (:func:`estimate_force`: the regions' force curvature, as the balance's
    patches have it), and the slope d(ln F)/d(ln d) there (the balance's first
    Jacobian).  From the multi-Hertzian estimate of the candidates' deepest-point
    curvatures (:func:`railcontact.geometry.search._approach_for_load`), a
    safeguarded secant iteration in ln d (a bracket of the load kept from the
    start, bisection where a step leaves it) to ``ESTIMATE_TOLERANCE``.  Returns
    (NaN, NaN) where no interpenetration below 50 mm carries the load."""
    i0, gap, slope = loc[0], loc[5], loc[6]
    cands = gap_candidates(gap)
    gmin = np.min(gap)
    k = cands.size
    off = np.empty(k)
    kc = np.empty(k)
    deepest = 0
    for j in range(k):
        i = cands[j]
        A, B = locus_curvatures(loc, i, pose.r0, prof.zw[i0:])
        _, _, F = hertz_patch(A, B, 1e-4, model)
        off[j] = gap[i] - gmin
        kc[j] = F / 1e-6 * math.cos(math.atan(slope[i])) ** 2.5
        if off[j] < off[deepest]:
            deepest = j
    hi = off[deepest] + (load / kc[deepest]) ** (2.0 / 3.0)
    if not hi <= 0.05:
        return math.nan, math.nan
    # the candidates' summed force is convex and increasing in d: Newton from above
    d = hi
    for _ in range(100):
        f = -load
        df = 0.0
        for j in range(k):
            p = d - off[j]
            if p > 0.0:
                f += kc[j] * p * math.sqrt(p)
                df += 1.5 * kc[j] * math.sqrt(p)
        if df <= 0.0:
            break
        step = f / df
        d -= step
        if abs(step) <= 1e-13:
            break
    # the balance's model from there: secant steps in v = ln d on r = ln(F / load)
    gs = np.empty(gap.size)
    v = math.log(d)
    r = math.log(max(estimate_force(loc, gs, d, pose, prof, model), FORCE_FLOOR * load) / load)
    lo_v, lo_r, hi_v, hi_r = -math.inf, math.nan, math.inf, math.nan
    slope_v = HERTZ_SLOPE
    pv, pr = math.nan, math.nan
    for _ in range(ESTIMATE_PASSES):
        if r < 0.0:
            lo_v, lo_r = v, r
        else:
            hi_v, hi_r = v, r
        if abs(r) <= ESTIMATE_TOLERANCE:
            break
        if pv == pv and v != pv:
            sec = (r - pr) / (v - pv)
            if sec > 0.0:
                slope_v = min(sec, JUMP_SLOPE)
        nv = v - r / slope_v
        nv = min(max(nv, v - math.log(STEP_FACTOR)), v + math.log(STEP_FACTOR))
        if lo_r == lo_r and hi_r == hi_r and not lo_v < nv < hi_v:
            nv = 0.5 * (lo_v + hi_v)
        if not nv < math.log(0.05):
            nv = 0.5 * (v + math.log(0.05))
        pv, pr = v, r
        v = nv
        r = math.log(max(estimate_force(loc, gs, math.exp(v), pose, prof, model),
                         FORCE_FLOOR * load) / load)
    # the slope at the root by a difference of ESTIMATE_DIFFERENCE in ln d
    h = ESTIMATE_DIFFERENCE if v + ESTIMATE_DIFFERENCE < math.log(0.05) else -ESTIMATE_DIFFERENCE
    rh = math.log(max(estimate_force(loc, gs, math.exp(v + h), pose, prof, model),
                      FORCE_FLOOR * load) / load)
    slope_v = min(max((rh - r) / h, SLOPE_RANGE[0]), SLOPE_RANGE[1])
    return math.exp(v), slope_v


@njit(cache=True, nogil=True)
def creep_factor(loc, d, s, z, roll, pose, prof, model):
    """The factor by which the creep forces change a side's vertical force on its
    rail at the rigid pose's locus ``loc`` (side ``s``, vertical position ``z`` [m],
    roll [rad]) lowered by ``d`` [m]: every region a
    patch (:func:`railcontact.geometry.wheel_pass.make_patch`, the wheel lowered
    with it) solved by Hertz and the online law (:func:`solve_patch`), sum (F_n cos
    d - F_y sin d) / sum F_n cos d (d: contact angle).  On a flange (some 70
    degrees) F_y tan d changes the vertical force by a factor 0.3 to 2 (the
    benchmark sweep's flange cases at 6.4-6.8 mm): the first estimate
    (:func:`first_estimate`) carries the load with it.  NaN where no region is
    loaded."""
    gap = loc[5]
    gmin = np.min(gap)
    gs = np.empty(gap.size)
    steep = 0.0
    for j in range(gap.size):
        gs[j] = gap[j] - gmin - d
        if gs[j] < 0.0:
            steep = max(steep, abs(loc[6][j]))
    # |F_y| <= mu F_n: the factor lies within mu tan(d) of 1 (the tread: some 1e-3)
    if model.tp[0] * steep <= CREEP_MIN:
        return 1.0
    O = loc[8].copy()
    O[2] -= gmin + d
    low = (loc[0], loc[1], loc[2], loc[3], loc[4], gs, loc[6], loc[7], O, loc[9])
    regions = locus_regions(gs, loc[3], loc[4], pose.combine)
    row = np.zeros(NRF)
    vert = 0.0
    normal = 0.0
    for r in range(min(regions.shape[0], MAX_PATCHES)):
        i0, i1 = regions[r, 0], regions[r, 1]
        deepest = 0.0
        for i in range(i0, i1 + 1):
            deepest = min(deepest, gs[i])
        if not deepest < 0.0:
            continue
        make_patch(prof, pose, s, low, i0, i1, z - gmin - d, roll, row)
        solve_patch(row, model)
        dl = row[P_CONTACT_ANGLE]
        normal += row[R_NORMAL_FORCE] * math.cos(dl)
        vert += row[R_NORMAL_FORCE] * math.cos(dl) - row[R_FY] * math.sin(dl)
    return vert / normal if normal > 0.0 else math.nan


@njit(cache=True, nogil=True)
def first_estimate(prof, pose, model, loads, memo, d, slope):
    """The first estimate of each side's interpenetration into ``d`` and of its
    slope d(ln F)/d(ln d) into ``slope``: the rigid pose (both wheels touching,
    roll to 1e-8 rad) and each side's load carried by the balance's model on its
    locus there (:func:`approach_for_load`).  Returns whether it was found."""
    rigid = np.zeros(2)
    for attempt in range(2):
        roll, z = solve_roll(prof, pose, rigid, 1e-8, memo)
        if not math.isfinite(roll):
            return False
        memo[0] = roll
        loc0 = side_locus(prof, pose, 0, z, roll, max(ESTIMATE_WINDOW, 2e-4), memo)
        loc1 = side_locus(prof, pose, 1, z, roll, max(ESTIMATE_WINDOW, 2e-4), memo)
        if loc0[5].size == 0 or loc1[5].size == 0:
            return False
        # (the roll to 1e-8 rad puts the sides' gaps within ~15 nm)
        if np.min(loc0[5]) > -3e-8 and np.min(loc1[5]) > -3e-8:
            break
        memo[6] = np.nan
        memo[12] = np.nan
    d[0], slope[0] = approach_for_load(loc0, loads[0], pose, prof, model)
    d[1], slope[1] = approach_for_load(loc1, loads[1], pose, prof, model)
    # the load with the creep forces' share of the vertical force: the normal force
    # that carries it (the factor at the estimate's depth)
    for s in range(2):
        if not d[s] > 0.0:
            continue
        k = creep_factor(loc0 if s == 0 else loc1, d[s], s, z, roll, pose, prof, model)
        if k == k and CREEP_RANGE[0] < k < CREEP_RANGE[1] and abs(math.log(k)) > CREEP_MIN:
            d[s], slope[s] = approach_for_load(loc0 if s == 0 else loc1, loads[s] / k,
                                               pose, prof, model)
    # the first search's loci: the samples that the estimate puts within the
    # interpenetration plus the locus margin (not the estimate's wider window)
    for s in range(2):
        loc = loc0 if s == 0 else loc1
        gap = loc[5]
        edge = np.min(gap) + d[s] + LOCUS_MARGIN
        first, last = -1, -1
        for j in range(gap.size):
            if gap[j] <= edge:
                if first < 0:
                    first = j
                last = j
        k = 2 + 6 * s
        if first >= 0:
            memo[k + 1] = max(loc[0] + first - TRIM_MARGIN, 0)
            memo[k + 2] = min(loc[0] + last + TRIM_MARGIN + 1, prof.eta.size)
    return d[0] > 0.0 and d[1] > 0.0


@njit(cache=True, nogil=True)
def evaluate_pose(prof, pose, model, zr, window, memo, out, fz, depth):
    """One evaluation of the balance at a given pose, ``zr`` = (vertical position
    [m], roll [rad]) relative to the rails: each side's locus (over the wheel
    samples within ``window`` [m] of its closest approach; widened where its
    interpenetration, into ``depth`` [m], needs more), its regions' patches
    solved by the balance's model (Hertz or the strip model: :func:`solve_row`),
    each wheel's vertical force on its rail into ``fz`` [N].  Returns the number
    of patches (-1 where a side has no locus)."""
    z, roll = zr[0], zr[1]
    m = 0
    fz[0] = 0.0
    fz[1] = 0.0
    memo[0] = roll
    for s in range(2):
        w = window[s]
        loc = side_locus(prof, pose, s, z, roll, w, memo, False)
        for _ in range(3):
            if loc[5].size == 0:
                return -1
            need = -np.min(loc[5]) + LOCUS_MARGIN
            if not need > w:
                break
            w = 1.5 * need
            loc = side_locus(prof, pose, s, z, roll, w, memo, False)
        gap = loc[5]
        if gap.size == 0 or not math.isfinite(np.min(gap)):
            return -1
        depth[s] = -np.min(gap)
        regions = locus_regions(gap, loc[3], loc[4], pose.combine)
        for r in range(min(regions.shape[0], MAX_PATCHES)):
            row = out[m]
            make_patch(prof, pose, s, loc, regions[r, 0], regions[r, 1], z, roll, row)
            solve_row(row, prof, pose, z, roll, model)
            dl = row[P_CONTACT_ANGLE]
            fz[s] += row[R_NORMAL_FORCE] * math.cos(dl) - row[R_FY] * math.sin(dl)
            m += 1
    return m


@njit(cache=True, nogil=True)
def pose_jacobian(out, m, pose, fz, loads, expo, J):
    """d g_s / d(z, roll) into ``J`` (2 x 2) of the residuals g_s = (F_s/Q_s)^(2/3) - 1
    of :func:`pose_newton` at an evaluation's patches ``out[:m]``: every patch's
    dN/d(delta) = e N / delta, e = ``expo`` of its side (Hertz: 3/2 with its
    curvatures held; more where its region's force curvature falls as it widens:
    the first estimate's or the neighbouring case's d ln F / d ln d), its approach's rate
    with the pose d(delta)/dz = cos(d), d(delta)/d(roll) = y_c cos(d) + r sin(d)
    (d: contact angle, y_c: the patch's lateral position from the wheelset's
    centre, r: rolling radius; as the online dynamics' approach rate), the vertical
    component cos(d).  Returns whether each side has a loaded patch."""
    J[:, :] = 0.0
    for i in range(m):
        row = out[i]
        F, d = row[R_NORMAL_FORCE], row[P_APPROACH]
        if not (F > 0.0 and d > 0.0):
            continue
        s = int(row[P_SIDE])
        a = row[P_CONTACT_ANGLE]
        ca, sa = math.cos(a), math.sin(a)
        k = expo[s] * F / d * ca
        J[s, 0] += k * ca
        J[s, 1] += k * ((row[P_Y] - pose.shift) * ca + row[P_ROLLING_RADIUS] * sa)
    for s in range(2):
        if not (fz[s] > 0.0 and J[s, 0] != 0.0):
            return False
        c = 2.0 / 3.0 * (fz[s] / loads[s]) ** (-1.0 / 3.0) / loads[s]
        J[s, 0] *= c
        J[s, 1] *= c
    return True


@njit(cache=True, nogil=True)
def pose_newton(prof, pose, model, loads, tol, max_passes, zr, memo, out, state, m, hist):
    """The vertical balance from an evaluation at the pose ``zr`` (vertical position
    [m], roll [rad]) whose ``m`` patches are ``out``; ``state`` (3 x 2): its
    vertical forces fz [N], interpenetrations [m] and the exponents of
    :func:`pose_jacobian` per side (each the last evaluation's at the end, the
    exponents those that Broyden's updates learnt): Newton steps on the pose (z, roll) for g_s = (F_s/Q_s)^(2/3) - 1 = 0
    (linear in the approach of a Hertzian patch), the Jacobian from the patches
    (:func:`pose_jacobian` with the exponents ``expo``, held in ``EXPONENT_RANGE``)
    and then Broyden's update (Broyden 1965); a step that
    does not reduce max |g_s| is halved, up to ``POSE_HALVINGS`` times.

    Why the pose and not each side's interpenetration (:func:`balance_wheelset`):
    where the flange and its root share a wheel's load, the deepest point's
    vertical interpenetration moves with the pose at a rate that jumps as the
    deepest point passes from one to the other (the roll moves the flange
    sideways, up its 70 degree slope), so that the force in it is S-shaped and
    steep (d ln F / d ln d from 1.5 to 10 within 10 %, measured at 6.3 mm on the
    benchmark sweep: 9-12 passes); in the pose the force is smooth.
    Every evaluation goes into ``hist`` (rows: interpenetrations [m] and vertical
    forces [N] of both sides), the history that the steps on the
    interpenetrations start from where these steps do not meet the load.
    Returns (passes made, whether the load is met, patches of the last evaluation,
    rows of ``hist`` filled)."""
    fz, depth, expo = state[0], state[1], state[2]
    J = np.empty((2, 2))
    g = np.empty(2)
    g2 = np.empty(2)
    fz2 = np.empty(2)
    d2 = np.empty(2)
    window = np.empty(2)
    cand = np.empty(2)
    for s in range(2):
        g[s] = (max(fz[s], 0.0) / loads[s]) ** (2.0 / 3.0) - 1.0
    passes = 0
    nh = 0
    slow = 0
    have_j = False
    while passes < max_passes:
        if abs(fz[0] / loads[0] - 1.0) <= tol and abs(fz[1] / loads[1] - 1.0) <= tol:
            if have_j:
                # the exponents learnt: each side's row of J projected on the
                # row of exponent 1 at the last evaluation
                Ja = np.empty((2, 2))
                if pose_jacobian(out, m, pose, fz, loads, np.ones(2), Ja):
                    for s in range(2):
                        den = Ja[s, 0] * Ja[s, 0] + Ja[s, 1] * Ja[s, 1]
                        num = J[s, 0] * Ja[s, 0] + J[s, 1] * Ja[s, 1]
                        if den > 0.0 and num > 0.0:
                            expo[s] = num / den
            return passes, True, m, nh
        if not have_j:
            for s in range(2):
                expo[s] = min(max(expo[s], EXPONENT_RANGE[0]), EXPONENT_RANGE[1])
            if not pose_jacobian(out, m, pose, fz, loads, expo, J):
                return passes, False, m, nh
            have_j = True
        det = J[0, 0] * J[1, 1] - J[0, 1] * J[1, 0]
        if not (det != 0.0 and math.isfinite(det)):
            return passes, False, m, nh
        dz = -(J[1, 1] * g[0] - J[0, 1] * g[1]) / det
        dr = -(-J[1, 0] * g[0] + J[0, 0] * g[1]) / det
        # the trust region: no loaded patch's approach changes by more than
        # POSE_TRUST of itself (a Newton step from far below the load, on one
        # patch whose approach grows slowly with the pose, e.g. a flange that
        # the roll moves sideways, overshoots by a factor of tens)
        scale = 1.0
        for i in range(m):
            row = out[i]
            d = row[P_APPROACH]
            if not (row[R_NORMAL_FORCE] > 0.0 and d > 0.0):
                continue
            a = row[P_CONTACT_ANGLE]
            dd = abs(math.cos(a) * dz + ((row[P_Y] - pose.shift) * math.cos(a)
                                         + row[P_ROLLING_RADIUS] * math.sin(a)) * dr)
            if dd * scale > POSE_TRUST * d:
                scale = POSE_TRUST * d / dd
        dz *= scale
        dr *= scale
        size = max(abs(g[0]), abs(g[1]))
        ok = False
        for h in range(POSE_HALVINGS + 1):
            cand[0], cand[1] = zr[0] + dz, zr[1] + dr
            # each side's locus over its interpenetration and the locus margin,
            # as the search under given interpenetrations (widened where the
            # interpenetration found needs more: evaluate_pose)
            grow = abs(dz) + pose.r0 * abs(dr)
            window[0] = depth[0] + grow + LOCUS_MARGIN
            window[1] = depth[1] + grow + LOCUS_MARGIN
            mm = evaluate_pose(prof, pose, model, cand, window, memo, out, fz2, d2)
            passes += 1
            if mm > 0 and nh < hist.shape[0]:
                hist[nh, 0], hist[nh, 1], hist[nh, 2], hist[nh, 3] = d2[0], d2[1], fz2[0], fz2[1]
                nh += 1
            if mm > 0:
                for s in range(2):
                    g2[s] = (max(fz2[s], 0.0) / loads[s]) ** (2.0 / 3.0) - 1.0
                if math.isfinite(g2[0]) and math.isfinite(g2[1]) and \
                        max(abs(g2[0]), abs(g2[1])) < size:
                    # a halved step that did not halve the residual: the force is
                    # not smooth here (e.g. a small jump where two regions
                    # combine): the steps on the interpenetrations take over
                    ok = h == 0 or max(abs(g2[0]), abs(g2[1])) <= 0.5 * size
                    break
            if passes >= max_passes:
                break
            dz *= 0.5
            dr *= 0.5
        if not ok:
            return passes, False, m, nh
        # Broyden's update of J with the step made (z and roll in m and rad: both
        # some 1e-4 here)
        nn = dz * dz + dr * dr
        e0 = g2[0] - g[0] - (J[0, 0] * dz + J[0, 1] * dr)
        e1 = g2[1] - g[1] - (J[1, 0] * dz + J[1, 1] * dr)
        J[0, 0] += e0 * dz / nn
        J[0, 1] += e0 * dr / nn
        J[1, 0] += e1 * dz / nn
        J[1, 1] += e1 * dr / nn
        zr[0], zr[1] = cand[0], cand[1]
        for s in range(2):
            g[s] = g2[s]
            fz[s] = fz2[s]
            depth[s] = d2[s]
        m = mm
        # two steps in a row that did not halve the residual (the force curved
        # between flange and root: Broyden's steps converge slowly there): the steps
        # on the interpenetrations take over, with these evaluations as brackets
        slow = slow + 1 if max(abs(g[0]), abs(g[1])) > 0.5 * size else 0
        if slow >= 2 and not (
                abs(fz[0] / loads[0] - 1.0) <= tol and abs(fz[1] / loads[1] - 1.0) <= tol):
            return passes, False, m, nh
    return passes, abs(fz[0] / loads[0] - 1.0) <= tol and abs(fz[1] / loads[1] - 1.0) <= tol, \
        m, nh


@njit(cache=True, nogil=True)
def _bracket(hv, hr, n, s, at):
    """Side s's bracket of the load at ``at`` among the history points (their ln d
    ``hv`` and residuals ``hr``): indices below / above (-1: none), the points
    whose residual's sign the other side's difference cannot flip
    (:func:`railcontact.cases.equilibrium._bracket`)."""
    lo = hi = -1
    o = 1 - s
    for k in range(n):
        moved = abs(hv[k, o] - at[o])
        if abs(hr[k, s]) <= COUPLING_SLOPE * moved:
            continue
        if hr[k, s] < 0 and (lo < 0 or hv[k, s] > hv[lo, s]):
            lo = k
        elif hr[k, s] > 0 and (hi < 0 or hv[k, s] < hv[hi, s]):
            hi = k
    if lo >= 0 and hi >= 0 and hv[hi, s] <= hv[lo, s]:
        return -1, -1
    return lo, hi


@njit(cache=True, nogil=True)
def _history_jacobian(hv, hr, n, v, fz, loads, J):
    """The Jacobian d(ln F)/d(ln d) into ``J`` with which the steps on the
    interpenetrations start at ln d = ``v`` (vertical forces ``fz`` [N]) from a
    history of ``n`` points (ln d ``hv``, residuals ``hr``): each side's slope
    across its bracket of the load (:func:`_bracket`; the force may be steep and
    S-shaped there), held in ``SLOPE_RANGE``; a side without one keeps its slope,
    and its rate with the other side's interpenetration (the roll moves its contact)
    is the least-squares fit of its residual's change that its own slope leaves,
    held to ``COUPLING_SLOPE``.  Back to diagonal where that is no Jacobian the
    steps can take (a non-positive determinant)."""
    r = np.empty(2)
    for s in range(2):
        r[s] = math.log(max(fz[s], FORCE_FLOOR * loads[s]) / loads[s])
    bracketed = np.zeros(2, dtype=np.bool_)
    for s in range(2):
        lo, hi = _bracket(hv, hr, n, s, v)
        if lo >= 0 and hi >= 0:
            sl = (hr[hi, s] - hr[lo, s]) / (hv[hi, s] - hv[lo, s])
            if sl > 0.0:
                J[s, s] = min(max(sl, SLOPE_RANGE[0]), SLOPE_RANGE[1])
                J[s, 1 - s] = 0.0
                bracketed[s] = True
    for s in range(2):
        if bracketed[s]:
            continue
        o = 1 - s
        num = 0.0
        den = 0.0
        for k in range(n):
            do = hv[k, o] - v[o]
            num += (hr[k, s] - r[s] - J[s, s] * (hv[k, s] - v[s])) * do
            den += do * do
        if den > 0.0:
            J[s, o] = min(max(num / den, -COUPLING_SLOPE), COUPLING_SLOPE)
    if not (J[0, 0] > 0.0 and J[1, 1] > 0.0 and J[0, 0] * J[1, 1] - J[0, 1] * J[1, 0] > 0.0):
        J[0, 1] = J[1, 0] = 0.0
    if not (J[0, 0] > 0.0 and J[1, 1] > 0.0):
        J[0, 0], J[1, 1] = HERTZ_SLOPE, HERTZ_SLOPE


@njit(cache=True, nogil=True)
def _trial(prof, pose, model, v, cand, memo, out, fz):
    """The evaluation at ln d = ``cand``; where it fails (no pose, a force not
    finite) the step from ``v`` is halved, up to five times.  Returns (patches,
    vertical position, roll, the point evaluated, evaluations made)."""
    m, z, roll = -1, math.nan, math.nan
    for k in range(6):
        m, z, roll = evaluate_wheelset(prof, pose, model, np.exp(cand), memo, out, fz)
        if m > 0 and math.isfinite(fz[0]) and math.isfinite(fz[1]):
            return m, z, roll, cand, k + 1
        if v[0] != v[0]:
            break
        cand = v + 0.5 * (cand - v)
    return -1, z, roll, cand, 6


@njit(cache=True, nogil=True)
def balance_wheelset(prof, pose, model, loads, tol, max_passes, start, memo, out, info):
    """The vertical balance of both wheels (module docstring).

    ``start``: (d_left, d_right, J00, J01, J10, J11, z, roll): the
    interpenetrations [m] to start from (NaN: the first estimate), d(ln F)/d(ln d)
    (NaN: the first estimate's slopes, else 1.5 I; its diagonal the exponents of
    :func:`pose_newton`) and a neighbour's pose (vertical position [m], roll
    [rad]; NaN: none), evaluated too where the first evaluation lies further than
    ``POSE_RESTART`` from the load (into rows of its own: the first evaluation's are
    kept where it serves better).
    ``out``: the patch rows of the last evaluation; ``info``: :data:`INFO_FIELDS`.
    Returns the outcome code (:data:`OUTCOMES`)."""
    d = np.empty(2)
    info[:] = np.nan
    J = np.empty((2, 2))
    J[0, 0], J[0, 1], J[1, 0], J[1, 1] = start[2], start[3], start[4], start[5]
    if start[0] == start[0] and start[1] == start[1] and start[0] > 0 and start[1] > 0:
        d[0], d[1] = start[0], start[1]
    else:
        slope = np.empty(2)
        if not first_estimate(prof, pose, model, loads, memo, d, slope):
            info[I_OUTCOME] = NO_POSE
            info[I_PASSES] = 0
            return NO_POSE
        J[0, 0], J[0, 1], J[1, 0], J[1, 1] = slope[0], 0.0, 0.0, slope[1]
    if not (J[0, 0] > 0 and J[1, 1] > 0 and J[0, 0] * J[1, 1] - J[0, 1] * J[1, 0] > 0):
        J[0, 0], J[0, 1], J[1, 0], J[1, 1] = HERTZ_SLOPE, 0.0, 0.0, HERTZ_SLOPE
    clip = math.log(STEP_FACTOR)
    hv = np.empty((2 * max_passes + 2, 2))
    hr = np.empty((2 * max_passes + 2, 2))
    n = 0
    fz = np.empty(2)
    nan2 = np.full(2, np.nan)
    m, z, roll, v, passes = _trial(prof, pose, model, nan2, np.log(d), memo, out, fz)
    # the evaluations at poses (interpenetrations [m], vertical forces [N])
    hist = np.empty((POSE_PASSES + 2, 4))
    nh = 0
    if m > 0:
        hist[0, 0], hist[0, 1], hist[0, 2], hist[0, 3] = math.exp(v[0]), math.exp(v[1]), \
            fz[0], fz[1]
        nh = 1
    if POSE_BALANCE and m > 0 and not (abs(fz[0] / loads[0] - 1.0) <= tol and
                                       abs(fz[1] / loads[1] - 1.0) <= tol):
        zr = np.array([z, roll])
        state = np.empty((3, 2))
        state[0] = fz
        state[1] = np.exp(v)
        state[2, 0], state[2, 1] = J[0, 0], J[1, 1]
        worst = max(abs(math.log(max(fz[0], FORCE_FLOOR * loads[0]) / loads[0])),
                    abs(math.log(max(fz[1], FORCE_FLOOR * loads[1]) / loads[1])))
        if worst > POSE_RESTART and start.size > 7 and start[6] == start[6] and \
                start[7] == start[7]:
            # a neighbour's interpenetrations far off the load (where the deepest
            # point passes between flange and flange root, they move fastest): its
            # pose instead, where that serves better
            zn = np.array([start[6], start[7]])
            fzn = np.empty(2)
            dn = np.empty(2)
            wn = np.array([1.5 * start[0] + LOCUS_MARGIN, 1.5 * start[1] + LOCUS_MARGIN])
            on = np.empty_like(out)
            mn = evaluate_pose(prof, pose, model, zn, wn, memo, on, fzn, dn)
            passes += 1
            if mn > 0:
                hist[nh, 0], hist[nh, 1], hist[nh, 2], hist[nh, 3] = dn[0], dn[1], fzn[0], fzn[1]
                nh += 1
                wn_ = max(abs(math.log(max(fzn[0], FORCE_FLOOR * loads[0]) / loads[0])),
                          abs(math.log(max(fzn[1], FORCE_FLOOR * loads[1]) / loads[1])))
                if wn_ < worst:
                    zr[:] = zn
                    state[0] = fzn
                    state[1] = dn
                    m = mn
                    out[:mn] = on[:mn]
        k, met, mp, nk = pose_newton(prof, pose, model, loads, tol,
                                     min(max_passes - passes, POSE_PASSES), zr, memo, out,
                                     state, m, hist[nh:])
        nh += nk
        fz[:] = state[0]
        depth = state[1]
        expo = state[2]
        passes += k
        info[I_POSE_PASSES] = k
        if met:
            info[I_OUTCOME] = CONVERGED
            info[I_PASSES] = passes
            info[I_D_LEFT], info[I_D_RIGHT] = depth[0], depth[1]
            info[I_VERTICAL], info[I_ROLL] = zr[0], zr[1]
            info[I_FZ_LEFT], info[I_FZ_RIGHT] = fz[0], fz[1]
            # (the next case's start: the exponents, as d ln F / d ln d)
            info[I_J00], info[I_J01], info[I_J10], info[I_J11] = expo[0], 0.0, 0.0, expo[1]
            info[I_PATCHES] = mp
            return CONVERGED
        # not met in the pose: the balance in the interpenetrations from the last
        # accepted pose's, its history the pose's evaluations (the brackets of the
        # load they hold, and each side's slope across its bracket: where the
        # flange and its root share the load the force is steep and S-shaped in
        # the interpenetration, and a step from the Hertzian slope overshoots far)
        if depth[0] > 0.0 and depth[1] > 0.0 and passes < max_passes:
            if mp > 0:
                for j in range(nh):
                    if hist[j, 0] > 0.0 and hist[j, 1] > 0.0:
                        for s in range(2):
                            hv[n, s] = math.log(hist[j, s])
                            hr[n, s] = math.log(max(hist[j, 2 + s], FORCE_FLOOR * loads[s])
                                                / loads[s])
                        n += 1
                v = np.log(depth)
                m, z, roll = mp, zr[0], zr[1]
                _history_jacobian(hv, hr, n, v, fz, loads, J)
            else:
                m, z, roll, v, k = _trial(prof, pose, model, nan2, np.log(depth), memo, out,
                                          fz)
                passes += k
    r = np.empty(2)
    prev_r = np.full(2, np.nan)
    older_r = np.full(2, np.nan)
    outcome = NOT_CONVERGED
    while True:
        if m <= 0:
            outcome = NO_POSE
            break
        for s in range(2):
            r[s] = math.log(max(fz[s], FORCE_FLOOR * loads[s]) / loads[s])
        hv[n] = v
        hr[n] = r
        n += 1
        off0 = abs(fz[0] / loads[0] - 1.0) > tol
        off1 = abs(fz[1] / loads[1] - 1.0) > tol
        if not (off0 or off1):
            outcome = CONVERGED
            break
        if passes >= max_passes or n >= hv.shape[0] - 1:
            break
        # a side whose bracket shows a jump: left to the Python path
        jump = False
        for s in range(2):
            if off0 if s == 0 else off1:
                lo, hi = _bracket(hv, hr, n, s, v)
                if lo >= 0 and hi >= 0:
                    width = abs(hv[hi, s] - hv[lo, s])
                    if abs(hr[hi, s] - hr[lo, s]) > JUMP_SLOPE * width and \
                            abs(hv[hi, 1 - s] - hv[lo, 1 - s]) <= width:
                        jump = True
        if jump:
            outcome = JUMP
            break
        # the Newton step, clipped, safeguarded per side by its bracket
        det = J[0, 0] * J[1, 1] - J[0, 1] * J[1, 0]
        s0 = -(J[1, 1] * r[0] - J[0, 1] * r[1]) / det
        s1 = -(-J[1, 0] * r[0] + J[0, 0] * r[1]) / det
        nxt = np.empty(2)
        nxt[0] = v[0] + min(max(s0, -clip), clip)
        nxt[1] = v[1] + min(max(s1, -clip), clip)
        for s in range(2):
            lo, hi = _bracket(hv, hr, n, s, nxt)
            if lo < 0 or hi < 0:
                continue
            off = off0 if s == 0 else off1
            slow = older_r[s] == older_r[s] and off and abs(r[s]) > 0.5 * abs(older_r[s])
            if slow or not hv[lo, s] < nxt[s] < hv[hi, s]:
                nxt[s] = 0.5 * (hv[lo, s] + hv[hi, s])
        m, z, roll, cand, k = _trial(prof, pose, model, v, nxt, memo, out, fz)
        passes += k
        if m <= 0:
            outcome = NO_POSE
            break
        # Broyden's update (not across a jump: no entry above JUMP_SLOPE)
        dv0, dv1 = cand[0] - v[0], cand[1] - v[1]
        nn = dv0 * dv0 + dv1 * dv1
        r0n = math.log(max(fz[0], FORCE_FLOOR * loads[0]) / loads[0])
        r1n = math.log(max(fz[1], FORCE_FLOOR * loads[1]) / loads[1])
        if nn > 0:
            e0 = r0n - r[0] - (J[0, 0] * dv0 + J[0, 1] * dv1)
            e1 = r1n - r[1] - (J[1, 0] * dv0 + J[1, 1] * dv1)
            N00, N01 = J[0, 0] + e0 * dv0 / nn, J[0, 1] + e0 * dv1 / nn
            N10, N11 = J[1, 0] + e1 * dv0 / nn, J[1, 1] + e1 * dv1 / nn
            if max(abs(N00), abs(N01), abs(N10), abs(N11)) <= JUMP_SLOPE:
                J[0, 0], J[0, 1], J[1, 0], J[1, 1] = N00, N01, N10, N11
            if not (J[0, 0] > 0 and J[1, 1] > 0 and J[0, 0] * J[1, 1] - J[0, 1] * J[1, 0] > 0):
                J[0, 0], J[0, 1], J[1, 0], J[1, 1] = HERTZ_SLOPE, 0.0, 0.0, HERTZ_SLOPE
        older_r[:] = prev_r
        prev_r[:] = r
        v = cand
    info[I_OUTCOME] = outcome
    info[I_PASSES] = passes
    info[I_D_LEFT] = math.exp(v[0])
    info[I_D_RIGHT] = math.exp(v[1])
    info[I_VERTICAL] = z
    info[I_ROLL] = roll
    info[I_FZ_LEFT] = fz[0]
    info[I_FZ_RIGHT] = fz[1]
    info[I_J00], info[I_J01], info[I_J10], info[I_J11] = \
        J[0, 0], J[0, 1], J[1, 0], J[1, 1]
    info[I_PATCHES] = m
    if info[I_POSE_PASSES] != info[I_POSE_PASSES]:
        info[I_POSE_PASSES] = 0
    return outcome


# ---------------------------------------------------------------------------------
# where a case enters and leaves


#: a compiled case's patch rows carry these fields to :class:`CaseForces`
FORCE_FIELDS = ("normal_force", "fx", "fy", "mz", "a", "b", "pmax", "area", "approach",
                "contact_angle", "y_rail", "y_wheel", "rolling_radius", "xi", "eta", "phi",
                "velocity", "A", "B")


@dataclass
class CaseForces:
    """A wheel-rail case solved in one compiled pass (:func:`solve_case_forces`):
    forces and patch geometry, no grids.

    ``side`` ("left"/"right") and the :data:`FORCE_FIELDS` per patch (SI units:
    normal_force, fx, fy [N] on the wheel in the patch's frame, mz [N m], a, b [m],
    pmax [Pa], area [m^2], approach [m], contact_angle [rad], y_rail, y_wheel,
    rolling_radius [m], the creepages xi, eta [-], phi [1/m] the patch was solved
    with, velocity [m/s], A, B [1/m]); ``interpenetration`` [m] and ``vertical_force``
    [N] per side, the pose's ``vertical`` [m] and ``roll`` [rad], how the balance
    ended (``outcome``, ``passes``) and its ``jacobian`` (the next case's start);
    ``cpu_time`` [s] from entry to exit."""

    side: list
    patches: dict
    interpenetration: dict
    vertical_force: dict
    loads: dict
    vertical: float
    roll: float
    outcome: str
    passes: int
    jacobian: np.ndarray = field(repr=False, default=None)
    cpu_time: float = 0.0
    normal: str = "hertz"
    tangential: str = "fastsim"
    #: the patch rows of the last evaluation (:data:`ROW_FIELDS`)
    rows: np.ndarray = field(repr=False, default=None)
    #: the interpenetrations [m] and roll [rad] of the neighbour this case started
    #: from (:class:`~railcontact.cases.equilibrium.Neighbour`; None: cold), from
    #: which the next case extrapolates its start
    neighbour: Neighbour | None = field(repr=False, default=None)
    #: the search's memo at the end (:data:`railcontact.geometry.wheel_pass.MEMO_SIZE`):
    #: the wheel samples of its loci and minima, where the next case's search starts
    memo: np.ndarray | None = field(repr=False, default=None)
    #: the case's lateral shift [m] and yaw [rad]
    pose_keys: tuple = (math.nan, math.nan)
    #: of ``passes``, the evaluations at a pose (:func:`pose_newton`'s steps)
    pose_passes: int = 0
    #: the roll searches' evaluations (each both sides' minimum gap,
    #: :func:`railcontact.geometry.wheel_pass.solve_roll`), over the case
    gap_evaluations: int = 0

    @property
    def converged(self) -> bool:
        return self.outcome == OUTCOMES[CONVERGED]

    def load_residual(self) -> float:
        """The largest |F_z/Q - 1| of the two wheels."""
        return max(abs(self.vertical_force[s] / self.loads[s] - 1.0) for s in ("left", "right"))

    def to_xarray(self):
        import xarray as xr
        units = {"normal_force": "N", "fx": "N", "fy": "N", "mz": "N m", "a": "m", "b": "m",
                 "pmax": "Pa", "area": "m^2", "approach": "m", "contact_angle": "rad",
                 "y_rail": "m", "y_wheel": "m", "rolling_radius": "m", "xi": "1",
                 "eta": "1", "phi": "1/m", "velocity": "m/s", "A": "1/m", "B": "1/m"}
        data = {k: ("patch", np.asarray(v), {"units": units[k]}) for k, v in self.patches.items()}
        data["side"] = ("patch", np.asarray(self.side))
        return xr.Dataset(data, attrs={
            "normal": self.normal, "tangential": self.tangential, "outcome": self.outcome,
            "passes": self.passes, "vertical_m": self.vertical, "roll_rad": self.roll,
            "interpenetration_left_m": self.interpenetration["left"],
            "interpenetration_right_m": self.interpenetration["right"],
            "cpu_time_s": self.cpu_time})


#: the rules of :class:`~railcontact.cases.rules.ContactRules` that apply to the
#: compiled pass's cases (the models' rules come as their options), followed there
#: only as railcontact's (the contact locus, ``wheelset.locus``, either way: the
#: shared locus kernel has both)
COMPILED_RULES = ("gauge_point",)


def compiled_unsupported(case, normal=None, tangential=None) -> str | None:
    """Why a case cannot run in the compiled pass, or None where it can."""
    s = case.wheel_rail
    if s is None:
        return "not a wheel-rail case"
    nname = (normal or case.normal).lower()
    tname = (tangential or case.tangential).lower()
    strip = nname in STRIP_MODELS
    if not (normal_supports(nname, "ellipse") or strip):
        return f"normal model {nname!r} is neither an ellipse (Hertz) nor a strip model"
    if tname == "none" or (online_law(tname) is None and not (strip and tname in MARCHES)):
        return f"tangential model {tname!r} has no compiled online law"
    if tangential is None and case.tangential_options:
        return "tangential options given"
    if normal is None and strip and case.normal_options:
        return "normal options given"
    if s.roll is not None or s.vertical_position is not None:
        return "roll or vertical position prescribed"
    if s.turn_distance > 0:
        return "patch turning (wheelset.turn_distance)"
    rules = case.rules.differing(COMPILED_RULES)
    if rules:
        return (f"CONTACT's rules {', '.join(rules)} (solver.rules, track.gauge_point; the "
                "compiled pass has railcontact's: the profile's gauge point)")
    if s.wheel_slices is not None or s.pitch != 0.0:
        return "an out-of-round wheel (wheel slices, pitch)"
    if s.wheel.left is not None or s.rail.left is not None:
        return "different profiles on the two sides"
    if case.friction_variation is not None or case.friction_along_track is not None:
        return "friction.variation"
    if case.material.is_dissimilar:
        return "dissimilar materials"
    if case.element_size is not None:
        return "solver.element_size"
    return None


_BODIES: dict = {}


def _bodies(case):
    """(PassProfiles, wheelset, track) of a case's bodies, once per set of body keys."""
    s = case.wheel_rail
    key = (s.wheel, s.rail, s.nominal_radius, s.flange_back_distance, s.flange_back_position,
           s.gauge, s.gauge_height, s.rail_offset, case.rules, str(case.base_dir))
    try:
        hit = _BODIES.get(key)
    except TypeError:                     # a profile object that does not hash
        key, hit = None, None
    if hit is None:
        ws, tr = build_wheelset_track(case)
        hit = (pass_profiles(ws, tr), ws, tr)
        if key is not None:
            if len(_BODIES) > 32:
                _BODIES.clear()
            _BODIES[key] = hit
    return hit


@lru_cache(maxsize=16)
def _strip_pass(normal, tangential, material, strips, elements):
    """The :class:`~railcontact.cases.strip_pass.StripPass` of a case's models (code
    -1 for Hertz), once per set (30 us to build)."""
    return strip_pass(normal, tangential, material, strips, elements, elements)


@lru_cache(maxsize=1)
def _tables():
    dt, tab = _axes_table()
    return dt, tab


def case_pass_inputs(case, normal=None, tangential=None):
    """(PassProfiles, PassPose, PassModel, loads) of a case for the compiled pass;
    a :class:`ValueError` says why a case cannot run there."""
    why = compiled_unsupported(case, normal, tangential)
    if why:
        raise ValueError(f"the compiled pass does not run this case: {why}")
    s = case.wheel_rail
    prof, ws, tr = _bodies(case)
    if prof is None:
        raise ValueError("the compiled pass does not run this case: different profiles on "
                         "the two sides")
    pitch = s.pitch_velocity if s.pitch_velocity is not None else -s.velocity / ws.nominal_radius
    pose = PassPose(float(s.lateral_shift), float(s.yaw), tr.rail_offset("left"),
                    tr.rail_offset("right"), ws.wheel_offset, ws.nominal_radius,
                    float(s.velocity), float(pitch), float(s.lateral_velocity),
                    float(s.yaw_rate), float(s.combine_distance))
    m = case.material
    nx, ny = (int(v) for v in (case.grid or (40, 40)))
    tname = (tangential or case.tangential).lower()
    law = online_law(tname)
    if law is None:             # (a strip march: the law serves no patch; linear's code is 0)
        law = online_law("fastsim")
    tp = np.array([case.friction, m.shear_modulus, nx, ny, 1.0, 1.0, 1.0, 0.0])
    creep = np.array(case.creepage if case.creepage is not None else (np.nan,) * 3, float)
    dt, tab = _tables()
    model = PassModel(m.contact_modulus, m.shear_modulus, m.nu, int(law), tp, creep, dt, tab,
                      _TAB_AB, _TAB_BA, _strip_pass((normal or case.normal).lower(), tname, m,
                                                    ny, nx))
    loads = np.array([s.loads["left"], s.loads["right"]], float)
    return prof, pose, model, loads


#: a case's search starts from its neighbour's wheel samples where their lateral
#: shifts differ by at most this [m] and their yaws by at most ``MEMO_YAW`` [rad]
MEMO_SHIFT = 5e-4
MEMO_YAW = 1e-3


def near_pose(keys, shift: float, yaw: float) -> bool:
    """Whether the pose ``keys`` = (lateral shift [m], yaw [rad]) of a neighbouring
    case's search lies within ``MEMO_SHIFT`` and ``MEMO_YAW`` of (shift, yaw): where
    a case's searches start from that neighbour's memo (NaN keys: never)."""
    return abs(keys[0] - shift) <= MEMO_SHIFT and abs(keys[1] - yaw) <= MEMO_YAW

#: a chain of cases extrapolates its start from the last two where their
#: interpenetrations differ by less than this factor (smooth neighbours; else the
#: last case's alone): the default of :func:`solve_case_forces`'s ``extrapolate_ratio``
EXTRAPOLATE_RATIO = 1.2


def _start_array(start, ratio=EXTRAPOLATE_RATIO):
    """(start array of :func:`balance_wheelset`, roll to start from) for a
    neighbour's result (:class:`CaseForces` or a
    :class:`~railcontact.cases.equilibrium.Neighbour`): its interpenetrations, or
    where it started from its own neighbour and both are close, their extrapolation
    in ln d (and the roll's: :func:`~railcontact.cases.equilibrium.extrapolate_start`),
    not where the chain's last three interpenetrations bend (its ``older``)."""
    st = np.full(8, np.nan)
    if start is None:
        return st, 0.0
    st[6], st[7] = start.vertical, start.roll
    d1 = {"left": start.interpenetration["left"], "right": start.interpenetration["right"]}
    roll = start.roll if math.isfinite(start.roll) else 0.0
    before = getattr(start, "neighbour", None)
    d, roll, _ = extrapolate_start(d1, before.interpenetration if before is not None else None,
                                   ratio, roll, before.roll if before is not None else math.nan,
                                   in_log=True,
                                   older=getattr(before, "before", None))
    st[0], st[1] = d["left"], d["right"]
    if start.jacobian is not None:
        st[2:6] = np.ravel(start.jacobian)
    return st, roll


def solve_case_forces(case, normal=None, tangential=None,
                      start: CaseForces | Neighbour | None = None, max_passes: int = 40,
                      extrapolate_ratio: float = EXTRAPOLATE_RATIO) -> CaseForces:
    """Solve a wheel-rail case in one compiled pass (module docstring): both wheels'
    loads met, the forces of every patch.

    Parameters
    ----------
    case : Case
        A wheel-rail case the pass runs (:func:`compiled_unsupported`).
    normal, tangential : str, optional
        Model names overriding the case's.
    start : CaseForces or Neighbour, optional
        A neighbouring case's result (the previous case of a sweep) or balance: the
        balance starts from its interpenetrations and Jacobian, and the roll search
        from its roll.
    max_passes : int
        Limit of the balance's evaluations.
    extrapolate_ratio : float
        Where ``start`` itself started from a neighbour, the two are extrapolated
        where their interpenetrations differ by less than this factor
        (:func:`~railcontact.cases.equilibrium.extrapolate_start`, in ln d); 1
        turns it off.

    Returns
    -------
    CaseForces
        With ``outcome`` "converged" where each wheel's vertical force meets its
        load to ``solver.force_tolerance``; else the case belongs to the Python path
        (:func:`railcontact.solve`).
    """
    t0 = time.perf_counter()
    prof, pose, model, loads = case_pass_inputs(case, normal, tangential)
    st, roll0 = _start_array(start, extrapolate_ratio)
    memo = new_memo(roll0)
    s = case.wheel_rail
    keys = getattr(start, "pose_keys", (math.nan, math.nan))
    near = start is not None and near_pose(keys, s.lateral_shift, s.yaw)
    if start is not None and not near and math.isfinite(keys[0]):
        # a neighbour in the sweep's order that is no neighbour in the pose (the
        # first case of the next yaw after the last of this one): the first
        # estimate serves better (4 passes from such a start, 2 from the estimate)
        st[:] = np.nan
        memo = new_memo(0.0)
    if near and getattr(start, "memo", None) is not None:
        # the neighbour's wheel samples (each use checks that they hold what it
        # needs, else searches afresh), from the extrapolated roll
        memo[:] = start.memo
        memo[0] = roll0
    memo[M_GAPS] = 0.0
    out = np.zeros((2 * MAX_PATCHES, NRF))
    info = np.empty(len(INFO_FIELDS))
    code = balance_wheelset(prof, pose, model, loads, float(case.force_tolerance),
                            int(max_passes), st, memo, out, info)
    res = _case_forces(out, info, code, loads, (normal or case.normal).lower(),
                       (tangential or case.tangential).lower(), time.perf_counter() - t0)
    if start is not None and getattr(start, "converged", True):
        nb = getattr(start, "neighbour", None)
        res.neighbour = Neighbour(dict(start.interpenetration), float(start.roll),
                                  before=dict(nb.interpenetration) if nb is not None else None)
    res.memo = memo
    res.pose_keys = (float(s.lateral_shift), float(s.yaw))
    res.gap_evaluations = int(memo[M_GAPS])
    if info[I_POSE_PASSES] == info[I_POSE_PASSES]:
        res.pose_passes = int(info[I_POSE_PASSES])
    if code != CONVERGED and start is not None:
        # a start that did not serve: the case again, cold (its time counts)
        cold = solve_case_forces(case, normal, tangential, None, max_passes,
                                 extrapolate_ratio)
        cold.cpu_time += res.cpu_time
        return cold
    return res


def _case_forces(out, info, code, loads, nname, tname, cpu) -> CaseForces:
    m = max(int(info[I_PATCHES]), 0) if info[I_PATCHES] == info[I_PATCHES] else 0
    rows = out[:m]
    sides = ["left" if r[P_SIDE] == 0 else "right" for r in rows]
    patches = {k: rows[:, RF[k]].copy() for k in FORCE_FIELDS}
    return CaseForces(sides, patches, {"left": float(info[I_D_LEFT]),
                                       "right": float(info[I_D_RIGHT])},
                      {"left": float(info[I_FZ_LEFT]), "right": float(info[I_FZ_RIGHT])},
                      {"left": float(loads[0]), "right": float(loads[1])},
                      float(info[I_VERTICAL]), float(info[I_ROLL]), OUTCOMES[int(code)],
                      int(info[I_PASSES]),
                      info[I_J00:I_J11 + 1].reshape(2, 2).copy(), cpu, nname, tname,
                      rows.copy())


def case_contact(res: CaseForces, case):
    """The geometry layer's :class:`~railcontact.geometry.search.WheelsetContact` of a
    compiled case's last evaluation (its patches as
    :class:`~railcontact.geometry.contact.ContactGeometry`, no search), or None
    where the case combines regions into patches (their joins are not kept)."""
    s = case.wheel_rail
    if s.combine_distance > 0 or res.rows is None or not res.rows.size:
        return None
    _, ws, tr = _bodies(case)
    pose = WheelsetPose(s.lateral_shift, res.vertical, res.roll, s.yaw)
    return rows_contact(res.rows, ws, tr, pose, s.loads, res.interpenetration)
