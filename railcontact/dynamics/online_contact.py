"""Wheel-rail contact searched online in the vehicle dynamics: every wheelset on
elastic contact, with vertical and roll freedom, its patches searched at every
evaluation of the right-hand side at the actual lateral shift, yaw, roll and
vertical position (no table, no clamp).

The contact is the *equivalent elastic* contact of multibody codes (Shabana,
Zaazaa & Sugiyama, *Railroad Vehicle Dynamics: A Computational Approach*, 2008,
ch. 5; Pombo, Ambrósio & Silva, Veh. Syst. Dyn. 45 (2007) 165): the wheel and the
rail interpenetrate as rigid bodies, and each interpenetration region is a patch
whose normal force is Hertz's non-linear spring of its approach δ along the normal,

    N = K δ^(3/2) + c δ'        (Hertz 1882; K from the patch's curvature A and its
                                  region's force curvature B_f and the contact
                                  modulus: the case layer's Hertz patch,
                                  :func:`railcontact.cases.compiled_case.patch_hertz`,
                                  one rule for every Hertz path),

with a viscous term c δ' (``damping`` [N s/m], only while the spring is loaded)
that damps the stiff wheel-rail vertical mode.  The patches come from the
geometry layer's compiled search (:mod:`railcontact.geometry.wheel_pass`): each
side's locus at the pose (:func:`~railcontact.geometry.wheel_pass.side_locus`),
its interpenetration regions and each region's patch (CONTACT's weighted
reference point and contact angle, the curvatures of the undeformed distance at
the deepest point, the approach, the kinematic creepages of the wheelset's
motion; :func:`~railcontact.geometry.wheel_pass.make_patch`).  The wheel's
samples are spaced ``ONLINE_STEP`` [m] instead of the case layer's 25 um: the
approach and curvatures are computed at the deepest point by the exact gap, so
that the spacing only moves the patch's weighted reference point (measured in
tests/dynamics/test_online_contact.py).

Creep forces: the compiled law of the run (FASTSIM, Polach or Kalker's linear
theory; :func:`railcontact.tangential.online.patch_forces`) in compiled code, or
any registered pair per patch in Python (``mode`` 1 of :func:`rhs_online`, the
forces given by the caller).

The wheelset's vertical position z (down) and roll φ (right wheel down) are
degrees of freedom; the suspension carries the quasi-static wheel loads of the
table path (the supported mass M and first moment H,
:mod:`railcontact.dynamics.equations_of_motion`) as vertical forces P_l, P_r at
±``LOAD_BASE`` from the wheelset's centre:

    m_w z'' = P_l + P_r − Σ Q_k,       I_w φ'' = b0 (P_r − P_l) − Σ Q_k y_k

with Q_k the vertical force of patch k on the wheel (up) at lateral position y_k.
The moment of the lateral contact forces about the axle is taken by the axle
boxes (quasi-static, as the table path's load transfer taken at rail level), so
that both paths distribute the same loads.

The rk4 step follows the springs' stiffness (:func:`spring_stiffness`,
:func:`contact_rate`, :func:`rk4_online`): a step is divided where the contact
modes have become faster than the step was chosen for.

A wheel whose loaded contact reaches ``TIP_ZONE`` of its flange tip's radius
stands on its flange: the wheelset is derailing, and the run ends there
(:func:`rk4_online`), reporting the time, wheel and Y/Q.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from ..cases.compiled_case import PassModel, _tables, hertz_patch, patch_hertz
from ..cases.strip_pass import MARCHES, strip_pass, strip_row_ends
from ..normal.strip_theory import STRIP_MODELS
from ..core.errors import InputError
from ..core.materials import Material, STEEL
from ..geometry.locus import _wheel_samples
from ..geometry.patch_curvature import force_curvature
from ..geometry.validity import TIP_ZONE, flange
from ..geometry.wheel_pass import (LOCUS_MARGIN, MAX_PATCHES, NPF, P_A,
                                   P_APPROACH, P_B, P_B_FORCE, P_CONTACT_ANGLE, P_ETA, P_PHI,
                                   P_ROLLING_RADIUS, P_X, P_XI, P_Y, P_Y_RAIL, P_Y_WHEEL,
                                   P_Z_WHEEL, PassPose, PassProfiles, locus_regions,
                                   make_patch, new_memo,
                                   side_locus)
from ..tangential.kalker import _TAB_AB, _TAB_BA, _coefficients_kernel
from ..tangential.online import patch_forces
from .equations_of_motion import LOAD_BASE, suspension_forces, track_under
from .vehicle import G_ACC

#: spacing [m] of the wheel samples of the online search (the case layer's loci
#: take 25 um; the approach and curvatures do not depend on it)
ONLINE_STEP = 2e-4
#: contact damping [N s/m] per patch, by default: about 0.3 of the critical damping
#: of a Manchester wheelset's vertical and roll modes on its two tread springs
#: (k = 1.5 N / d ~ 1e9 N/m per wheel at 55 kN; 2 sqrt(2 k m_w) ~ 3.8e6 N s/m)
DEFAULT_DAMPING = 6e5
#: a patch steeper than this [rad] is reported in the flange slot
FLANGE_ANGLE = 0.35
#: smallest locus window [m] (the interpenetration plus this margin is searched)
WINDOW_FLOOR = 1e-4
#: the next search's locus window: this times the deepest interpenetration plus the
#: locus margin (a search whose interpenetration outgrows it searches again wider)
WINDOW_GROWTH = 1.2
#: most substeps of one rk4 step (:func:`rk4_online`)
MAX_SUBSTEPS = 64
#: a step is divided where the contact's rate exceeds the rate it was chosen for by
#: more than this factor (the step 1 / rate keeps a margin of 2.78 to RK4's
#: stability limit on the real axis; 1.5 leaves 1.85)
RATE_MARGIN = 1.5

#: the fields of the ``frame`` array of :class:`OnlineContact`
FRAME_FIELDS = ("y_off_left", "y_off_right", "wheel_offset", "nominal_radius", "combine",
                "damping", "tip_z", "tip_zone", "rate", "stiffness", "match",
                "warm_strips")
(G_YOFF_L, G_YOFF_R, G_E, G_R0, G_COMBINE, G_DAMPING, G_TIP_Z, G_TIP_ZONE, G_RATE,
 G_STIFFNESS, G_MATCH, G_WARM) = range(12)

#: per row of :attr:`OnlineContact.rows` after the patch geometry: normal force N
#: [N] (Hertz spring and damper), Hertz semi-axes a, b [m], creep forces Fx, Fy [N],
#: spin moment Mz [N m] on the wheel, lateral Y and vertical Q force of the rail on
#: the wheel [N] (track plane), the lateral position of the patch relative to the
#: wheelset centre [m] and the approach rate [m/s]
#: (Kalker's coefficients, the spring's stiffness dN/d(delta) [N/m]), the
#: stand-in's creep forces Fx, Fy [N] and spin moment Mz [N m] at the row's normal
#: force (``mode`` 1, 3 and 4 of :func:`rhs_online`) and the spring's force before
#: the damper [N]
ROW_EXTRA = ("normal_force", "a", "b", "fx", "fy", "mz", "Y", "Q", "y_contact",
             "approach_rate", "C11", "C22", "C23", "stiffness", "standin_fx", "standin_fy",
             "standin_mz", "spring_force")
(R_N, R_AA, R_BB, R_FX, R_FY, R_MZ, R_YF, R_QF, R_YC, R_DDOT, R_C11, R_C22,
 R_C23, R_STIFF, R_SFX, R_SFY, R_SMZ, R_SPRING) = range(NPF, NPF + len(ROW_EXTRA))
NROW = NPF + len(ROW_EXTRA)
#: rows per wheelset
MAX_ROWS = 2 * MAX_PATCHES

#: what the compiled stand-ins take over at the inner stages of a Runge-Kutta step
#: on the Python path (:class:`OnlineWheelRail`)
STAND_IN = ("none", "tangential", "both")

#: per row of :attr:`OnlineContact.corrections`, the stand-ins' corrections of
#: each patch, from the last evaluation with the models solved: its side (0 left,
#: 1 right) and slot (1: flange, contact angle over :data:`FLANGE_ANGLE`), where it
#: lay on the rail profile [m] and how far it may move from there (its grid's
#: element across [m]), the normal model's force over Hertz's spring's at its
#: approach [-], and the creep forces Fx, Fy [N] and spin moment Mz [N m] of the
#: tangential model less the stand-in's at the same normal force
CORRECTION_FIELDS = ("side", "flange", "y_rail", "tolerance", "normal_ratio", "fx", "fy",
                     "mz")
C_SIDE, C_FLANGE, C_YRAIL, C_TOL, C_RATIO, C_FX, C_FY, C_MZ = range(len(CORRECTION_FIELDS))

#: derailment codes of :attr:`OnlineContact.status` per wheelset and side
ON_TRACK, ON_FLANGE_TIP, OFF_RAIL = 0, 1, 2


class OnlineContact(NamedTuple):
    """The online contact's compiled inputs and its state between evaluations."""

    #: the wheel samples and splines (:class:`~railcontact.geometry.wheel_pass.PassProfiles`)
    profiles: PassProfiles
    #: :data:`FRAME_FIELDS`: rail offsets, wheel-profile offset, r0 [m], combine distance
    #: [m], contact damping [N s/m], the flange tip's profile height and the tip zone [m],
    #: the contact's rate [1/s] that the run's rk4 step resolves (:func:`rk4_online`;
    #: NaN until its first step), whether an evaluation computes the springs'
    #: stiffness (1; 0: not, :data:`R_STIFF` 0), and whether a strip model's
    #: strips are laid from the last evaluation's (1; 0: each evaluation afresh)
    frame: np.ndarray
    #: Hertz and the creep law (:class:`~railcontact.cases.compiled_case.PassModel`)
    model: PassModel
    #: (nw,) roll inertia of the wheelsets [kg m²]
    roll_inertia: np.ndarray
    #: (nw, MEMO_SIZE) the searches' memos (loci windows), one per wheelset
    memo: np.ndarray
    #: (nw,) locus window [m] of each wheelset's next search
    window: np.ndarray
    #: (nw, MAX_ROWS, NROW) the last evaluation's patches
    rows: np.ndarray
    #: (nw,) number of rows of each wheelset
    count: np.ndarray
    #: (nw, 2) derailment code per wheel (:data:`ON_TRACK`, ...), set by an evaluation
    status: np.ndarray
    #: (nw, 4) the last evaluation's pose of each wheelset relative to the rails:
    #: lateral shift [m], vertical position [m], roll [rad], yaw [rad]
    poses: np.ndarray
    #: (1,) rk4 steps made, substeps counted (:func:`rk4_online`)
    count_substeps: np.ndarray
    #: (nw, MAX_ROWS, len(CORRECTION_FIELDS)) the stand-ins' corrections per row
    #: (:data:`CORRECTION_FIELDS`, modes 3 and 4 of :func:`rhs_online`)
    corrections: np.ndarray
    #: (nw,) rows of each wheelset in :attr:`corrections` (-1: none)
    corrected: np.ndarray
    #: (nw, MAX_ROWS, 3) the last evaluation's strip runs per row of a strip model:
    #: side (-1: none) and the run's lateral ends [m] in the rail's frame, where the
    #: next evaluation's strips start from (:func:`strip_ends_guess`)
    strip_ends: np.ndarray


def online_contact(wheelset, track, n_wheelsets: int, material: Material = STEEL,
                   law: int = 1, law_params=None, damping: float = DEFAULT_DAMPING,
                   roll_inertia: float = 1120.0, strips=None) -> OnlineContact:
    """The :class:`OnlineContact` of a wheelset (its profiles) on a track for
    ``n_wheelsets`` wheelsets: the compiled creep law ``law`` with parameters
    ``law_params`` (:func:`railcontact.tangential.online.patch_forces`), the contact
    ``damping`` [N s/m] per patch, the wheelsets' ``roll_inertia`` [kg m²] and a
    strip model with its creep forces (``strips``, a
    :class:`~railcontact.cases.strip_pass.StripPass`; None: Hertz's spring)."""
    wheel, rail = wheelset.wheel("right"), track.rail("right")
    if wheelset.wheel("left") is not wheel or track.rail("left") is not rail:
        raise InputError("online contact: expected the same wheel and rail profile on both "
                         "sides (mirrored)")
    if not (math.isfinite(damping) and damping >= 0):
        raise InputError(f"contact damping {damping!r} N s/m: expected >= 0")
    if not (math.isfinite(roll_inertia) and roll_inertia > 0):
        raise InputError(f"wheelset roll inertia {roll_inertia!r} kg m^2: expected > 0")
    yw, zw, eta, rho = _wheel_samples(wheel, ONLINE_STEP, wheelset.wheel_offset,
                                      wheelset.nominal_radius)
    prof = PassProfiles(eta, rho, yw, zw, rail._breaks, rail._coefs, wheel._breaks,
                        wheel._coefs)
    fl = flange(wheel)
    frame = np.array([track.rail_offset("left"), track.rail_offset("right"),
                      wheelset.wheel_offset, wheelset.nominal_radius, 0.0, float(damping),
                      fl.tip_z if fl is not None else math.inf, TIP_ZONE, math.nan, 1.0,
                      1.0, 1.0])
    tp = np.array(law_params if law_params is not None else
                  [0.3, material.shear_modulus, 12, 12, 1.0, 1.0, 1.0, 0.0], float)
    dt, tab = _tables()
    model = PassModel(material.contact_modulus, material.shear_modulus, material.nu,
                      int(law), tp, np.full(3, np.nan), dt, tab, _TAB_AB, _TAB_BA)
    if strips is not None:
        model = model._replace(strips=strips)
    memo = np.stack([new_memo() for _ in range(n_wheelsets)])
    return OnlineContact(prof, frame, model, np.full(n_wheelsets, float(roll_inertia)), memo,
                         np.full(n_wheelsets, WINDOW_FLOOR),
                         np.zeros((n_wheelsets, MAX_ROWS, NROW)),
                         np.zeros(n_wheelsets, np.int64), np.zeros((n_wheelsets, 2), np.int64),
                         np.zeros((n_wheelsets, 4)), np.zeros(1, np.int64),
                         np.zeros((n_wheelsets, MAX_ROWS, len(CORRECTION_FIELDS))),
                         np.full(n_wheelsets, -1, np.int64),
                         np.full((n_wheelsets, MAX_ROWS, 3), -1.0))


#: the approach's relative step [-] of the spring's stiffness (:func:`spring_stiffness`)
STIFFNESS_STEP = 0.05


@njit(cache=True, nogil=True)
def spring_stiffness(loc, i0, i1, row, F, model, work):
    """The stiffness dN/d(delta) [N/m] of a patch's Hertz spring N = F(delta) at its
    approach delta: e N / delta, the exponent e = 3/2 + d ln K / d ln delta of
    Hertz's force with the region's force curvature B_f (K: its factor at fixed
    curvatures), by the region's force curvature at the gap lowered by
    ``STIFFNESS_STEP`` of the deepest point's vertical interpenetration (``work``:
    the lowered gap, as long as the locus's).  B_f falls where the region widens
    faster than a paraboloid's (two minima of the gap joining; the flange and its
    root): there the spring is stiffer than Hertz's 3/2 N/delta."""
    d = row[P_APPROACH]
    if not (F > 0.0 and d > 0.0):
        return 0.0
    gap = loc[5]
    im = i0
    for i in range(i0, i1 + 1):
        if gap[i] < gap[im]:
            im = i
    e = 1.5
    bf = row[P_B_FORCE]
    h = STIFFNESS_STEP * (-gap[im])
    if bf > 0.0 and h > 0.0:
        for j in range(gap.size):
            work[j] = gap[j] - h
        j0, j1 = i0, i1
        while j0 > 0 and work[j0 - 1] < 0.0:
            j0 -= 1
        while j1 < gap.size - 1 and work[j1 + 1] < 0.0:
            j1 += 1
        low = (loc[0], loc[1], loc[2], loc[3], loc[4], work, loc[6], loc[7], loc[8], loc[9])
        b2 = force_curvature(low, j0, j1, im, row[P_B])
        if b2 > 0.0:
            _, _, F1 = hertz_patch(row[P_A], bf, d, model)
            _, _, F2 = hertz_patch(row[P_A], b2, d, model)
            if F1 > 0.0 and F2 > 0.0:
                e += math.log(F2 / F1) / math.log1p(STIFFNESS_STEP)
    return max(e, 0.0) * F / d


@njit(cache=True, nogil=True)
def strip_ends_guess(prev, s, row, warm, ends):
    """The strips' run ends [m] (their lateral coordinate in the row's gap frame)
    of the patch row on side s from the last evaluation's runs ``prev``
    (:attr:`OnlineContact.strip_ends` of the wheelset): the run on the same side
    whose ends hold the row's reference point, else (or not ``warm``) NaN."""
    ends[0] = ends[1] = math.nan
    if not warm:
        return
    ca = math.cos(row[P_CONTACT_ANGLE])
    for i in range(prev.shape[0]):
        if prev[i, 0] == s and prev[i, 1] <= row[P_Y] <= prev[i, 2]:
            ends[0] = (prev[i, 1] - row[P_Y]) / ca
            ends[1] = (prev[i, 2] - row[P_Y]) / ca
            return


@njit(cache=True, nogil=True)
def search_wheelset(online, w, pose, z, roll):
    """Wheelset w's patches at the pose (lateral shift and yaw in ``pose``, vertical
    position z [m] and roll [rad] relative to the rails) into ``online.rows[w]``,
    their Hertz springs solved; the derailment codes into ``online.status[w]``.
    Returns the number of rows."""
    prof, g = online.profiles, online.frame
    rows = online.rows[w]
    m = 0
    deepest = 0.0
    strip = online.model.strips.rule.code >= 0
    if strip:
        prev = online.strip_ends[w].copy()
        online.strip_ends[w, :, 0] = -1.0
        ends = np.empty(3)
    for s in range(2):
        win = online.window[w]
        loc = side_locus(prof, pose, s, z, roll, win, online.memo[w], False)
        gap = loc[5]
        online.status[w, s] = ON_TRACK
        if gap.size == 0 or not math.isfinite(np.min(gap)):
            online.status[w, s] = OFF_RAIL
            continue
        if -np.min(gap) + LOCUS_MARGIN > win:
            # the locus must hold the whole interpenetration (a region cut at its
            # edge has no region curvature, and a wrong reference point)
            win = WINDOW_GROWTH * (-np.min(gap)) + LOCUS_MARGIN
            loc = side_locus(prof, pose, s, z, roll, win, online.memo[w], False)
            gap = loc[5]
        deepest = max(deepest, -np.min(gap))
        work = np.empty(gap.size if g[G_STIFFNESS] > 0.0 else 0)
        regions = locus_regions(gap, loc[3], loc[4], g[G_COMBINE])
        for r in range(min(regions.shape[0], MAX_PATCHES)):
            row = rows[m]
            row[:] = 0.0
            make_patch(prof, pose, s, loc, regions[r, 0], regions[r, 1], z, roll, row)
            d = row[P_APPROACH]
            if not d > 0.0:
                continue
            row[R_YC] = row[P_Y] - pose.shift
            if strip:
                # a strip model: its normal force at the approach and its creep
                # forces (:mod:`railcontact.cases.strip_pass`, the compiled case's),
                # the strips laid from the last evaluation's run of the patch
                strip_ends_guess(prev, s, row, g[G_WARM] > 0.0, ends)
                F, fx, fy, mz, a, b, _, _ = strip_row_ends(row, prof, pose, z, roll,
                                                           online.model, ends)
                ca = math.cos(row[P_CONTACT_ANGLE])
                se = online.strip_ends[w, m]
                se[0], se[1], se[2] = s, row[P_Y] + ends[0] * ca, row[P_Y] + ends[1] * ca
                row[R_N], row[R_AA], row[R_BB] = F, a, b
                row[R_FX], row[R_FY], row[R_MZ] = fx, fy, mz
                if g[G_STIFFNESS] > 0.0:
                    # the strip model's spring: its force with the exponent of the
                    # region's Hertz spring (the rk4 step's substeps follow it)
                    row[R_STIFF] = spring_stiffness(loc, regions[r, 0], regions[r, 1], row,
                                                    F, online.model, work)
                if F > 0.0 and row[P_Z_WHEEL] >= g[G_TIP_Z] - g[G_TIP_ZONE]:
                    online.status[w, s] = ON_FLANGE_TIP
                m += 1
                continue
            # the spring and the ellipse: the case layer's Hertz patch (the force
            # with the region's force curvature, geometry.patch_curvature, the
            # ellipse with the deepest point's curvatures scaled to that force):
            # one rule for the compiled case, the per-patch path and the dynamics
            a, b, F = patch_hertz(row, online.model)
            if g[G_STIFFNESS] > 0.0:
                row[R_STIFF] = spring_stiffness(loc, regions[r, 0], regions[r, 1], row, F,
                                                online.model, work)
            row[R_N] = F
            row[R_AA] = a
            row[R_BB] = b
            if F > 0.0 and row[P_Z_WHEEL] >= g[G_TIP_Z] - g[G_TIP_ZONE]:
                online.status[w, s] = ON_FLANGE_TIP
            m += 1
    online.window[w] = max(WINDOW_GROWTH * deepest + LOCUS_MARGIN, WINDOW_FLOOR)
    online.count[w] = m
    return m


@njit(cache=True, nogil=True)
def row_forces(row, online, mode, fe, rates, corr):
    """The forces of one row: the normal force with the damper at the approach rate
    (``rates``: lateral velocity of the wheelset centre relative to the rail [m/s],
    vertical velocity [m/s], roll rate [rad/s]), the creep forces of the compiled
    law (mode 0) or ``fe`` (mode 1: an :data:`~.equations_of_motion.EXTERNAL`
    record, the normal force and the creep forces; mode 2: none; mode 3: the
    normal force of ``fe`` and the compiled law's creep forces at it, the
    *stand-in*, plus the correction ``corr``'s; mode 4: as 3, the normal force
    Hertz's spring's times ``corr``'s ratio, with the damper: the row's
    :data:`CORRECTION_FIELDS`), and their lateral and vertical resultants (track
    plane).  Modes 1, 3 and 4 keep the stand-in's forces at the normal force in
    the row (:data:`R_SFX`, :data:`R_SFY`, :data:`R_SMZ`) and every mode the
    spring's force (:data:`R_SPRING`), so that the caller can correct the
    stand-ins by solutions of its own
    (:meth:`railcontact.dynamics.simulation._System.rhs`: the models solved at the
    first evaluation of each step, the stand-ins corrected by their difference
    there at the step's other stages)."""
    delta = row[P_CONTACT_ANGLE]
    cd, sd = math.cos(delta), math.sin(delta)
    yc = row[R_YC]
    r = row[P_ROLLING_RADIUS]
    vy = rates[0] - r * rates[2]
    vz = rates[1] + rates[2] * yc
    ddot = vz * cd - vy * sd
    row[R_DDOT] = ddot
    F = row[R_N]
    row[R_SPRING] = F
    Fs = F * corr[C_RATIO] if mode == 4 else F
    N = max(Fs + online.frame[G_DAMPING] * ddot, 0.0) if Fs > 0.0 else 0.0
    if (mode == 1 or mode == 3) and F > 0.0 and fe.normal_force > 0.0:
        N = fe.normal_force             # (the caller's normal force, damper included)
    row[R_N] = N
    fx = fy = mz = 0.0
    if N > 0.0:           # Hertz's ellipse at the force (a, b ~ N^(1/3))
        scale = (N / F) ** (1.0 / 3.0)
        row[R_AA] *= scale
        row[R_BB] *= scale
    a, b = row[R_AA], row[R_BB]
    if N > 0.0 and a > 0.0 and b > 0.0:
        c = np.empty((3, 1))
        _coefficients_kernel(np.array([a / b]), online.model.nu, online.model.kalker_ab,
                             online.model.kalker_ba, c)
        row[R_C11], row[R_C22], row[R_C23] = c[0, 0], c[1, 0], c[2, 0]
        if mode == 0 and online.model.strips.rule.code >= 0:
            # the strip model's creep forces at the spring's force (the damper
            # moves the normal force only, as the Python path has it)
            fx, fy, mz = row[R_FX], row[R_FY], row[R_MZ]
        elif mode == 0:
            fx, fy, mz = patch_forces(online.model.law, online.model.tp, N, a, b, c[0, 0],
                                      c[1, 0], c[2, 0], row[P_XI], row[P_ETA], row[P_PHI],
                                      rates[3])
        elif mode != 2:
            sfx, sfy, smz = patch_forces(online.model.law, online.model.tp, N, a, b,
                                         c[0, 0], c[1, 0], c[2, 0], row[P_XI], row[P_ETA],
                                         row[P_PHI], rates[3])
            row[R_SFX], row[R_SFY], row[R_SMZ] = sfx, sfy, smz
            if mode == 1:
                fx, fy, mz = fe.Fx, fe.Fy, fe.Mz
            else:
                fx, fy, mz = sfx + corr[C_FX], sfy + corr[C_FY], smz + corr[C_MZ]
    row[R_FX], row[R_FY], row[R_MZ] = fx, fy, mz
    row[R_YF] = N * sd + fy * cd
    row[R_QF] = N * cd - fy * sd
    return row[R_YF], row[R_QF]


@njit(cache=True, nogil=True)
def _record(rows, m, w, out, V):
    """The rows of wheelset w into the outputs' two slots per side (tread, flange):
    forces summed over the patches of a slot, the geometry of its most loaded."""
    pin, pout = out.patch_in, out.patch_out
    for sd in range(2):
        for sl in range(2):
            p = pin[w, sd, sl]
            p.normal_force = 0.0
            p.velocity = V
            o = pout[w, sd, sl]
            o.Fx = o.Fy = o.Mz = o.Y = o.Q = o.Tgamma = 0.0
    best = np.zeros((2, 2))
    for i in range(m):
        row = rows[i]
        sd = int(row[0])
        sl = 1 if abs(row[P_CONTACT_ANGLE]) > FLANGE_ANGLE else 0
        N = row[R_N]
        o = pout[w, sd, sl]
        o.Fx += row[R_FX]
        o.Fy += row[R_FY]
        o.Mz += row[R_MZ]
        o.Y += row[R_YF]
        o.Q += row[R_QF]
        o.Tgamma += abs(row[R_FX] * row[P_XI]) + abs(row[R_FY] * row[P_ETA])
        p = pin[w, sd, sl]
        if N >= best[sd, sl]:
            best[sd, sl] = N
            p.a, p.b = row[R_AA], row[R_BB]
            p.C11, p.C22, p.C23 = row[R_C11], row[R_C22], row[R_C23]
            p.xi, p.eta, p.phi = row[P_XI], row[P_ETA], row[P_PHI]
            p.contact_angle, p.y_contact = row[P_CONTACT_ANGLE], row[R_YC]
            p.A, p.B = row[P_A], row[P_B]
            p.y_rail, p.y_wheel = row[P_Y_RAIL], row[P_Y_WHEEL]
        p.normal_force += N


@njit(cache=True, nogil=True)
def rhs_online(t, u, system, online, mode, fext, out):
    """Time derivative of the state u = (q, q', z, z') with q = (y, ψ, φ) per body
    and the vertical position z [m] (down) of every wheelset, the wheelsets' roll a
    degree of freedom; the contact searched at the pose (module notes).

    ``mode`` 0: the creep forces of the compiled law ``online.model.law``; 1: those
    of ``fext`` (nw, MAX_ROWS) :data:`~.equations_of_motion.EXTERNAL` records per
    row (given by the caller after a ``mode`` 2 evaluation: the search, the normal
    forces and no creep forces); 3: the compiled law's at ``fext``'s normal forces
    corrected by :attr:`~OnlineContact.corrections`; 4: Hertz's springs and the
    compiled law corrected by them (:func:`row_forces`); 5: per wheelset, 4 where
    its rows are those of its corrections, else 1 (the caller solved that
    wheelset's patches alone).  Every mode checks whether the rows are those of the
    corrections (:func:`matches`), ``online.frame``'s :data:`G_MATCH` 1 where they
    are (every wheelset's), 0 where not.  ``out``
    (:class:`~.equations_of_motion.Outputs`) takes the patches (two slots per side)
    and the wheelsets' loads, vertical position and roll."""
    V = system.velocity
    bodies, wsets = system.vehicle.bodies, system.vehicle.wheelsets
    g = online.frame
    nb = bodies.shape[0]
    nw = wsets.shape[0]
    nd = 3 * nb
    q = u[:nd]
    qd = u[nd:2 * nd]
    zs = u[2 * nd:2 * nd + nw]
    zd = u[2 * nd + nw:]
    F = suspension_forces(t, q, qd, system)
    acc_z = np.zeros(nw)
    mom = np.zeros(nw)
    wout = out.wheelset_out
    rates = np.empty(4)
    g[G_MATCH] = 1.0
    for w in range(nw):
        ws = wsets[w]
        b = ws.body
        k, dk, ct, ya, yad, cl = track_under(system, t, b)
        y, psi, phi = q[3 * b], q[3 * b + 1], q[3 * b + 2]
        yd, psid, phid = qd[3 * b], qd[3 * b + 1], qd[3 * b + 2]
        yrel = y - ya
        pose = PassPose(yrel, psi - yad, g[G_YOFF_L], g[G_YOFF_R], g[G_E], g[G_R0], V,
                        -V / g[G_R0], yd - V * yad, psid + V * k, g[G_COMBINE])
        m = search_wheelset(online, w, pose, zs[w], phi - cl)
        mw = mode
        if not matches(online, w, m):
            g[G_MATCH] = 0.0
            if mode == 5:
                mw = 1
        elif mode == 5:
            mw = 4
        online.poses[w, 0], online.poses[w, 1] = yrel, zs[w]
        online.poses[w, 2], online.poses[w, 3] = phi - cl, psi - yad
        rates[0], rates[1], rates[2], rates[3] = yd - V * yad, zd[w], phid, V
        Qt = ws.mass * (G_ACC * math.cos(ct) + V * V * k * math.sin(ct))
        dQ = ws.moment * (V * V * k * math.cos(ct) - G_ACC * math.sin(ct)) / (2 * LOAD_BASE)
        pl, pr = 0.5 * Qt + dQ, 0.5 * Qt - dQ
        fz = Qt
        mx = LOAD_BASE * (pr - pl)
        for i in range(m):
            row = online.rows[w, i]
            Yk, Qk = row_forces(row, online, mw, fext[w, i], rates,
                                online.corrections[w, i])
            F[3 * b] += Yk
            F[3 * b + 1] += row[P_X] * Yk - row[R_YC] * row[R_FX] + \
                row[R_MZ] * math.cos(row[P_CONTACT_ANGLE])
            fz -= Qk
            mx -= Qk * row[R_YC]
        F[3 * b] += Qt * cl
        acc_z[w] = fz / bodies[b].mass
        mom[w] = mx
        _record(online.rows[w], m, w, out, V)
        wo = wout[w]
        wo.relative_shift = yrel
        wo.outside_table = False
        wo.load_left = pl
        wo.load_right = pr
        wo.vertical = zs[w]
        wo.roll = phi - cl
    du = np.empty(u.size)
    du[:nd] = qd
    du[2 * nd:2 * nd + nw] = zd
    du[2 * nd + nw:] = acc_z
    for b in range(nb):
        body = bodies[b]
        du[nd + 3 * b] = F[3 * b] / body.mass
        du[nd + 3 * b + 1] = F[3 * b + 1] / body.yaw_inertia
        du[nd + 3 * b + 2] = F[3 * b + 2] / body.roll_inertia if body.roll else 0.0
    for w in range(nw):
        b = wsets[w].body
        du[nd + 3 * b + 2] = mom[w] / online.roll_inertia[w]
    return du


@njit(cache=True, nogil=True)
def matches(online, w, m):
    """Whether wheelset w's m rows of the last search are the patches of its
    :attr:`~OnlineContact.corrections`: as many, each on the same side and in the
    same slot (tread, flange) as its correction's, and within its tolerance of
    where it lay on the rail."""
    if online.corrected[w] != m:
        return False
    for i in range(m):
        row, c = online.rows[w, i], online.corrections[w, i]
        if (row[0] != c[C_SIDE]
                or (abs(row[P_CONTACT_ANGLE]) > FLANGE_ANGLE) != (c[C_FLANGE] > 0.5)
                or not abs(row[P_Y_RAIL] - c[C_YRAIL]) <= c[C_TOL]):
            return False
    return True


@njit(cache=True, nogil=True)
def _derailed(online):
    for w in range(online.status.shape[0]):
        for s in range(2):
            if online.status[w, s] != ON_TRACK:
                return True
    return False


@njit(cache=True, nogil=True)
def contact_rate(system, online):
    """The fastest rate [1/s] of the wheelsets' contact modes at the last
    evaluation: per wheelset, vertical and roll, the damped oscillator of the
    patches' springs (:data:`R_STIFF`, projected by the approach's rate with the
    vertical position, cos(d), and the roll, y_c cos(d) + r sin(d)) and dampers on
    the wheelset's mass and roll inertia, c / 2m + sqrt((c / 2m)^2 + k / m)
    (the modulus of its faster eigenvalue, overdamped or not)."""
    rate = 0.0
    wsets = system.vehicle.wheelsets
    c0 = online.frame[G_DAMPING]
    for w in range(wsets.shape[0]):
        kz = kr = cz = cr = 0.0
        for i in range(online.count[w]):
            row = online.rows[w, i]
            if not row[R_N] > 0.0:
                continue
            a = row[P_CONTACT_ANGLE]
            pz = math.cos(a)
            pr = row[R_YC] * math.cos(a) + row[P_ROLLING_RADIUS] * math.sin(a)
            kz += row[R_STIFF] * pz * pz
            kr += row[R_STIFF] * pr * pr
            cz += c0 * pz * pz
            cr += c0 * pr * pr
        mass = system.vehicle.bodies[wsets[w].body].mass
        inertia = online.roll_inertia[w]
        for k, c, m in ((kz, cz, mass), (kr, cr, inertia)):
            h = 0.5 * c / m
            rate = max(rate, h + math.sqrt(h * h + k / m))
    return rate


@njit(cache=True, nogil=True)
def rk4_online(u, t0, dt, n_steps, every, system, online, fext, out, samples):
    """Classical fixed-step Runge-Kutta (4th order) of :func:`rhs_online` with the
    compiled creep law: ``n_steps`` steps of ``dt`` [s] from (t0 [s], u); every
    ``every`` steps the state goes to the next row of ``samples``.  Stops at the
    first step that starts with a wheel on its flange tip or off the rail
    (``online.status``).  Returns (state, samples written, steps made).

    The step follows the contact's stiffness: a step whose first evaluation has the
    contact modes faster (:func:`contact_rate`) than the rate the run's step was
    chosen for (``online.frame[G_RATE]``: the larger of the first step's contact
    rate and 1 / ``dt``) is made in as many equal substeps as that ratio asks
    (the Hertz spring stiffens with its load and, with the regions' force
    curvature, where a region widens fast: a fixed step chosen at the start
    diverged where it stiffened, measured)."""
    k = 0
    fr = online.frame
    for n in range(n_steps):
        t = t0 + n * dt
        fr[G_STIFFNESS] = 1.0            # (the springs' stiffness at k1 only)
        k1 = rhs_online(t, u, system, online, 0, fext, out)
        fr[G_STIFFNESS] = 0.0
        if _derailed(online):
            fr[G_STIFFNESS] = 1.0
            return u, k, n
        rate = contact_rate(system, online)
        if not online.frame[G_RATE] == online.frame[G_RATE]:
            online.frame[G_RATE] = max(rate, 1.0 / dt)
        sub = min(max(int(math.ceil(rate / (RATE_MARGIN * online.frame[G_RATE]))), 1),
                  MAX_SUBSTEPS)
        h = dt / sub
        tt = t
        for j in range(sub):
            if j > 0:
                k1 = rhs_online(tt, u, system, online, 0, fext, out)
            k2 = rhs_online(tt + 0.5 * h, u + 0.5 * h * k1, system, online, 0, fext, out)
            k3 = rhs_online(tt + 0.5 * h, u + 0.5 * h * k2, system, online, 0, fext, out)
            k4 = rhs_online(tt + h, u + h * k3, system, online, 0, fext, out)
            u = u + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
            tt += h
        online.count_substeps[0] += sub
        if (n + 1) % every == 0 and k < samples.shape[0]:
            samples[k] = u
            k += 1
    fr[G_STIFFNESS] = 1.0
    return u, k, n_steps


class OnlineWheelRail:
    """The online contact as a run's contact (instead of a
    :class:`~railcontact.dynamics.wheel_rail.WheelRailTable`): the wheelset and the
    track (their profiles as placed), the material, the contact ``damping`` [N s/m]
    per patch, the wheelsets' ``roll_inertia`` [kg m²] (None: their yaw inertia, as
    of an axisymmetric body) and the normal model of the Python path (``normal``:
    any registered normal model; the compiled laws run on Hertz's spring).

    ``stand_in``: what compiled stand-ins take over from the models of the Python
    path (per patch in Python, e.g. ``exact`` + ``exact``) at the inner three
    stages of each Runge-Kutta step, the models solved at its first evaluation:
    ``"both"``, Hertz's spring and FASTSIM, each corrected by the models'
    difference from it at the step's first evaluation (the normal force times
    the ratio of the normal model's to the spring's, the creep forces plus the
    difference; mode 4 of :func:`rhs_online`); ``"tangential"``, FASTSIM at the
    normal model's force, solved at every stage (mode 3); ``"none"``: the models
    solved at every evaluation (four times the solves).  A stage where a
    wheelset's patches are not the step's (another number, side or slot, or one
    moved on the rail by more than its grid's element) has the models solved on
    that wheelset's patches, the others keeping their stand-ins (mode 5 of
    :func:`rhs_online`; :meth:`railcontact.dynamics.simulation._System.rhs`).

    A compiled strip model lays each evaluation's strips from the last evaluation's
    run of the patch (``warm_strips``, :func:`strip_ends_guess`; False: afresh, as
    the compiled case; the same layout to 1e-9 m in the run's ends)."""

    def __init__(self, wheelset, track, material: Material = STEEL,
                 damping: float = DEFAULT_DAMPING, roll_inertia: float | None = None,
                 normal: str = "hertz", stand_in: str = "both", warm_strips: bool = True):
        from ..normal.base import normal_models
        if normal not in normal_models():
            raise InputError(f"online contact normal model {normal!r}: expected one of "
                             f"{normal_models()}")
        if stand_in not in STAND_IN:
            raise InputError(f"online contact stand_in {stand_in!r}: expected one of "
                             f"{STAND_IN}")
        self.stand_in = stand_in
        if not (isinstance(damping, (int, float)) and math.isfinite(damping) and damping >= 0):
            raise InputError(f"contact damping {damping!r} N s/m: expected >= 0")
        self.wheelset, self.track, self.material = wheelset, track, material
        self.damping, self.roll_inertia, self.normal = float(damping), roll_inertia, normal
        self.warm_strips = bool(warm_strips)
        fl = flange(wheelset.wheel("right"))
        #: the wheels' largest flange angle [rad] (NaN without a flange)
        self.flange_angle = fl.max_angle if fl is not None else math.nan
        #: nominal rolling radius r0 [m]
        self.nominal_radius = float(wheelset.nominal_radius)

    def compiled(self, n_wheelsets: int, law: int, law_params, roll_inertia: float,
                 tangential: str | None = None):
        """The :class:`OnlineContact` of a run; with ``tangential`` (a model that
        marches strips, or a compiled law) and a strip normal model, the strip
        model and its creep forces in compiled code
        (:mod:`railcontact.cases.strip_pass`, 40 strips, the run's FASTSIM
        elements per strip)."""
        strips = None
        if tangential is not None and self.compiled_strips(tangential):
            strips = strip_pass(self.normal, tangential, self.material, 40, 20,
                                int(law_params[2]))
        on = online_contact(self.wheelset, self.track, n_wheelsets, self.material, law,
                            law_params, self.damping,
                            self.roll_inertia if self.roll_inertia else roll_inertia, strips)
        on.frame[G_WARM] = 1.0 if self.warm_strips else 0.0
        return on

    def compiled_strips(self, tangential: str) -> bool:
        """Whether the run's models go in compiled code as a strip model with its
        creep forces: a strip normal model with ``fastsim``, ``fastsim-strips`` or
        a compiled online law."""
        from ..tangential.online import online_law
        return self.normal in STRIP_MODELS and (tangential in MARCHES
                                                or online_law(tangential) is not None)
