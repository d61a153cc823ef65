"""Contact search: wheelset position, contact patches and their geometry.

Algorithm
---------
1. For a wheelset pose (lateral shift, yaw given; vertical position and roll
   unknown) the contact locus of each side gives the vertical gap g(y_w) along the
   wheel profile (:mod:`railcontact.geometry.locus`).
2. Vertical position and roll are solved so that the deepest interpenetration of
   each side equals its target: zero (rigid contact, both wheels touch) or the
   elastic approach that carries the given vertical wheel load.  The approach is
   found with Hertz's theory applied to every local minimum of the gap
   (multi-Hertzian), so that two-point contact shares the load between tread and
   flange.
3. Each connected interpenetration region of the locus is a contact patch (regions
   closer than ``combine_distance`` are merged).  Its reference point and contact
   angle are the weighted means over the region with CONTACT's default weight, the
   integral of the squared interpenetration over x for a parabolic gap in x,
   (-g)^2.5 (``GAP_WEIGHT``; CONTACT's "weighted centre, weighted angle",
   ``compute_wgt_center_1d``, whose linear option integrates the interpenetration
   itself, (-g)^1.5).
4. Per patch: lateral positions on wheel and rail, rolling radius, principal
   relative curvatures (finite differences of the exact gap), kinematic creepages,
   and the undeformed distance h(x, y) on any grid of the tangent plane, computed
   from the rail cylinder and the wheel's surface of revolution with yaw and roll.

The steps live in modules of their own: the pose (:mod:`~railcontact.geometry.pose`),
the regions (:mod:`~railcontact.geometry.regions`), the gap
(:mod:`~railcontact.geometry.gap`) and the creepages
(:mod:`~railcontact.geometry.kinematics`); this module holds the multi-Hertzian
estimate and :func:`find_contact`, which runs them.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq
from scipy.signal import find_peaks

from ..core.errors import ContactNotFoundError, InputError
from ..core.hertz_theory import hertz_ellipse
from ..core.materials import STEEL, Material
from .contact import ContactGeometry, WheelsetContact, interaction_factor  # noqa: F401
from .gap import GapEvaluator, curvatures_fd
from .kinematics import kinematic_creepage
from .locus import Locus, compute_locus
from .patch_curvature import at_fraction, deepest_fraction, deepest_gap, force_curvature
from .pose import REGION_MARGIN, ROLL_SLOPE, _memo, locus_window, solve_pose
from .regions import GAP_WEIGHT, contact_regions, end_distance, territories, weighted_angle
from .track import SIDES, Track, Wheelset, WheelsetPose
from .turning import turned_angles
from .wheel_pass import (MAX_PATCHES, MISSED_DEPTH, NPF, P_SIDE, PassPose, make_patch,
                         new_memo, pass_profiles, patch_geometry, rows_contact,
                         search_patches, side_locus, side_min_gap)


log = logging.getLogger(__name__)


#: local minima of the gap deeper than the global minimum plus this are candidates [m]
CANDIDATE_DEPTH = 3e-4


def _locus_curvatures(loc: Locus, i: int, r0: float):
    """Relative curvatures (A, B) [1/m] at locus index i, in the normal section."""
    ang = math.atan(loc.slope[i])
    rho = r0 + loc.z_wheel[i]
    A = math.cos(ang) / (2.0 * rho)
    sel = np.abs(loc.y_rail - loc.y_rail[i]) <= 2.5e-4
    sel &= np.isfinite(loc.gap)
    if sel.sum() >= 5:
        # least-squares parabola g ~ c0 t^2 + c1 t + c2 in t = dy / 0.25 mm (normal
        # equations: a 3 x 3 system, well conditioned in the scaled t)
        t = (loc.y_rail[sel] - loc.y_rail[i]) / 2.5e-4
        V = np.stack((t * t, t, np.ones_like(t)), axis=1)
        c = np.linalg.solve(V.T @ V, V.T @ loc.gap[sel])
        B = c[0] / 2.5e-4 ** 2 * math.cos(ang) ** 3
    else:
        B = 0.0
    return A, max(B, 1e-3)


def _candidates(loc: Locus):
    g = np.where(np.isfinite(loc.gap), loc.gap, 1.0)
    peaks, _ = find_peaks(-g, prominence=1e-7)
    gmin = loc.gap_min
    idx = [int(i) for i in peaks if g[i] <= gmin + CANDIDATE_DEPTH]
    if loc.i_min not in idx:
        idx.append(loc.i_min)
    return sorted(idx)


def _approach_for_load(loc: Locus, load: float, r0: float, material: Material) -> float:
    """Vertical interpenetration [m] of the deepest point that carries ``load`` [N]:
    the root of the candidates' summed Hertzian vertical forces, each
    k c^2.5 (d - off)^1.5 (k: Hertz's force per approach^1.5 at the candidate's
    curvatures, c: cosine of its contact angle, off: its gap above the deepest
    point).  The deepest candidate alone carries the load at the largest d, so that
    its closed form bounds the root (and is the root where it is the only one)."""
    cands = _candidates(loc)
    gmin = loc.gap_min
    Es = material.contact_modulus
    off, kc = np.empty(len(cands)), np.empty(len(cands))
    for j, i in enumerate(cands):
        A, B = _locus_curvatures(loc, i, r0)
        # at fixed curvatures Hertz's force grows as the approach^(3/2): one solution
        # gives its factor
        k = hertz_ellipse(A, B, Es, penetration=1e-4).force / 1e-6
        off[j] = loc.gap[i] - gmin
        kc[j] = k * math.cos(math.atan(loc.slope[i])) ** 2.5
    deepest = int(np.argmin(off))
    hi = float(off[deepest] + (load / kc[deepest]) ** (2.0 / 3.0))
    if not hi <= 0.05:
        raise ContactNotFoundError(f"wheel load {load:g} N cannot be carried "
                                   "(interpenetration above 50 mm)")
    if np.count_nonzero(off < hi) == 1:
        return hi

    def vertical_force(d):
        pen = np.maximum(d - off, 0.0)
        return float(np.dot(kc, pen * np.sqrt(pen)))

    return brentq(lambda d: vertical_force(d) - load, 0.0, hi, xtol=1e-13)


#: the loci of the multi-Hertzian estimate cover the wheel samples within this [m] of
#: the closest approach: every candidate (a local minimum within CANDIDATE_DEPTH of
#: it) with the samples of its curvature fit, and the same candidates (their
#: prominence is decided within 0.1 mm of them)
ESTIMATE_WINDOW = CANDIDATE_DEPTH + 2e-4


@dataclass(frozen=True)
class WheelsetMotion:
    """The wheelset's motion for the kinematic creepages: forward speed ``velocity``
    V [m/s]; ``pitch_velocity`` [rad/s] about the axle (None: pure rolling at the
    nominal radius, -V / r0); ``lateral_velocity`` [m/s]; ``yaw_rate`` [rad/s]."""

    velocity: float = 30.0
    pitch_velocity: float | None = None
    lateral_velocity: float = 0.0
    yaw_rate: float = 0.0


@dataclass(frozen=True)
class PatchRules:
    """How interpenetration regions become patches (CONTACT's rules).

    ``combine_distance`` [m]: regions whose facing ends are closer form one patch
    (0: every region its own; CONTACT combines within 8 mm).
    ``full_interaction_distance`` [m]: within a combined patch, sub-regions closer
    than this interact fully in the normal problem, between it and
    ``combine_distance`` reduced (:func:`railcontact.geometry.contact.interaction_factor`;
    CONTACT: 4 mm); None: ``combine_distance`` (full interaction).
    ``turn_distance`` [m]: separate patches of a wheel whose facing ends lie between
    ``combine_distance`` and this apart have their contact angles turned towards
    their weighted mean (CONTACT's D_TURN,
    :func:`railcontact.geometry.turning.turned_angles`; 0: no turning) ...
    ``separation_angle`` [rad]: ... except where their angles differ by more (A_SEP).
    """

    combine_distance: float = 0.0
    full_interaction_distance: float | None = None
    turn_distance: float = 0.0
    separation_angle: float = math.pi / 2


@dataclass(frozen=True)
class SearchStart:
    """Where a search starts and how it runs: ``roll`` [rad], the estimate of the
    roll angle where the search for it starts (e.g. an earlier search's of the same
    case; it changes the work, not the result); ``load_iterations``, the limit of
    the fixed-point iterations between the multi-Hertzian interpenetrations and the
    wheelset position under a vertical force (they stop earlier when the
    interpenetrations change by less than 1 nm; one gives a first estimate, what
    :func:`railcontact.solve` needs)."""

    roll: float = 0.0
    load_iterations: int = 10


def find_contact(wheelset: Wheelset, track: Track, lateral_shift: float = 0.0,
                 yaw: float = 0.0, vertical_force=None, material: Material = STEEL,
                 motion: WheelsetMotion | None = None, rules: PatchRules | None = None,
                 interpenetration: dict | None = None, roll: float | None = None,
                 side: str = "both", start: SearchStart | None = None) -> WheelsetContact:
    """Find the wheelset position and all contact patches.

    Parameters
    ----------
    wheelset, track : Wheelset, Track
    lateral_shift : float
        Wheelset lateral displacement y [m], positive to the right.
    yaw : float
        Yaw angle [rad]; positive turns the front to the right.
    vertical_force : float or (float, float), optional
        Vertical wheel load [N] (one value for both wheels, or (left, right)).  When
        given, the elastic approach is included (multi-Hertzian); otherwise the
        wheelset rests rigidly on both rails.
    material : Material
    motion : WheelsetMotion, optional
        The wheelset's motion for the creepages (default: 30 m/s, pure rolling).
    rules : PatchRules, optional
        How regions become patches (default: one patch per region, no turning).
    interpenetration : dict, optional
        Prescribed vertical interpenetration [m] of the deepest point per side
        (``{"left": d, "right": d}``) instead of one derived from ``vertical_force``;
        used by :func:`railcontact.solve` to meet the vertical force with the
        normal and tangential model of the case.
    roll : float, optional
        Prescribed roll angle [rad].  Then only one wheel (``side``) is considered and
        its vertical position alone is solved (CONTACT's single-wheel mode).
    side : {"both", "left", "right"}
        Wheels to consider; a prescribed roll needs "left" or "right".
    start : SearchStart, optional
        The roll where the search starts and the limit of the load iterations
        (default: roll 0, 10 iterations).

    Notes
    -----
    Under prescribed interpenetrations with a free roll, one patch per region
    (``rules.combine_distance`` 0), no turning and round wheels with the same
    profiles on both sides, the compiled pass searches
    (:func:`railcontact.geometry.wheel_pass.search_patches`: the same steps on the
    same locus kernel; on the benchmark sweep's poses its patches agree with this
    module's own search to 4e-9 relative, positions to 1e-13 m).  Under a prescribed
    roll (one wheel; every ``.inp`` wheel-rail case) with round wheels of the same
    profiles on both sides, the pose and the locus come from the compiled pass's
    kernels (:func:`_fixed_roll_pose`; the regions here, which combine and turn as
    ``rules`` say, and the patches of regions neither combined nor turned by the
    pass's :func:`~railcontact.geometry.wheel_pass.make_patch`, :func:`_pass_patches`).
    Every other search runs here.
    """
    motion = motion or WheelsetMotion()
    rules = rules or PatchRules()
    start = start or SearchStart()
    velocity, pitch_velocity = motion.velocity, motion.pitch_velocity
    lateral_velocity, yaw_rate = motion.lateral_velocity, motion.yaw_rate
    combine_distance, full_interaction_distance = (rules.combine_distance,
                                                   rules.full_interaction_distance)
    turn_distance, separation_angle = rules.turn_distance, rules.separation_angle
    roll_start, load_iterations = start.roll, start.load_iterations
    for name, v, lim in (("wheelset.lateral_shift", lateral_shift, 0.05),
                         ("wheelset.yaw", yaw, 0.1)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and abs(v) <= lim):
            raise InputError(f"{name} = {v!r}: expected |value| <= {lim}")
    if not (isinstance(velocity, (int, float)) and math.isfinite(velocity) and velocity > 0):
        raise InputError(f"wheelset.velocity = {velocity!r} m/s: expected a value > 0")
    loads = None
    if vertical_force is not None:
        vf = np.atleast_1d(np.asarray(vertical_force, dtype=float))
        if vf.size == 1:
            vf = np.repeat(vf, 2)
        if vf.size != 2 or not np.all(np.isfinite(vf)) or np.any(vf <= 0):
            raise InputError(f"wheelset.vertical_force = {vertical_force!r}: expected a load > 0 N"
                             " per wheel, or (left, right)")
        loads = {"left": float(vf[0]), "right": float(vf[1])}
    r0 = wheelset.nominal_radius
    if pitch_velocity is None:
        pitch_velocity = -velocity / r0
    if side not in ("both", "left", "right"):
        raise InputError(f"wheelset.side = {side!r}: expected 'left', 'right' or 'both'")
    if roll is not None:
        if side == "both":
            raise InputError("wheelset.roll is prescribed: give wheelset.side = 'left' or "
                             "'right' (with a given roll only one wheel can be in equilibrium)")
        if not (math.isfinite(roll) and abs(roll) <= 0.1):
            raise InputError(f"wheelset.roll = {roll!r}: expected |roll| <= 0.1 rad")
    sides = SIDES if roll is None else (side,)
    pose_kw = {"roll_given": roll, "sides": sides}
    if not (isinstance(load_iterations, int) and load_iterations >= 1):
        raise InputError(f"load_iterations = {load_iterations!r}: expected an integer >= 1")
    if not (isinstance(roll_start, (int, float)) and abs(roll_start) <= 0.1):
        raise InputError(f"roll_start = {roll_start!r}: expected |roll| <= 0.1 rad")

    targets = {"left": 0.0, "right": 0.0}
    if interpenetration is not None:
        targets = {s: float(interpenetration.get(s, 0.0)) for s in SIDES}
        if not all(math.isfinite(v) and v >= 0 for v in targets.values()):
            raise InputError(f"interpenetration = {interpenetration!r}: expected values >= 0 m")
        loads = loads or {s: math.nan for s in SIDES}
    if interpenetration is not None and roll is None:
        found = _pass_contact(wheelset, track, (lateral_shift, yaw, float(roll_start)), targets,
                              loads, (velocity, pitch_velocity, lateral_velocity, yaw_rate),
                              rules)
        if found is not None:
            return found
    # the rigid pose under a load is only the start of the multi-Hertzian estimate:
    # its roll to 1e-8 rad (gaps to 15 nm), the poses of the patches' to 1e-12
    estimate = loads is not None and interpenetration is None
    # a prescribed roll (one side): the compiled pass's kernels where they serve,
    # round wheels with the same profiles on both sides
    prof = _pass_profiles(wheelset, track) if roll is not None and \
        wheelset.out_of_round is None else None
    fixed = (side, lateral_shift, yaw, roll)        # the prescribed roll, bound here

    def pose_of(targets, roll0, tol, loci_window):
        if prof is not None:
            return _fixed_roll_pose(wheelset, track, prof, fixed,
                                    targets, loci_window)
        return solve_pose(wheelset, track, lateral_shift, yaw, targets, roll0=roll0, tol=tol,
                          loci_window=loci_window, **pose_kw)

    z, roll, loci = pose_of(targets, float(roll_start), 1e-8 if estimate else 1e-12,
                            "regions" if interpenetration is not None
                            else ESTIMATE_WINDOW if estimate else None)
    if estimate:
        for k in range(load_iterations):
            new = dict(targets)
            new.update({s: _approach_for_load(loci[s], loads[s], r0, material) for s in sides})
            change = max(abs(new[s] - targets[s]) for s in sides)
            targets = new
            # the last iteration's loci need to hold the patches only
            z, roll, loci = pose_of(targets, roll, 1e-12, "regions"
                                    if k == load_iterations - 1 else ESTIMATE_WINDOW)
            if change < 1e-9:
                break
    pose = WheelsetPose(lateral_shift, z, roll, yaw)

    patches = []
    full = combine_distance if full_interaction_distance is None else full_interaction_distance
    for sd in sides:
        loc = loci[sd]
        regions = contact_regions(loc, loads is None, combine_distance)
        angles = [None] * len(regions)
        if turn_distance > combine_distance and len(regions) > 1 and loads is not None:
            aw = [weighted_angle(loc, i0, i1) for i0, i1, _ in regions]
            angles = turned_angles([a for a, _ in aw], [w for _, w in aw],
                                   [end_distance(loc, p[1], q[0], p[0], q[1])
                                    for p, q in zip(regions[:-1], regions[1:])],
                                   combine_distance, turn_distance, separation_angle)
        if prof is not None and loads is not None and all(
                a is None for a in angles) and not any(j for _, _, j in regions):
            # a prescribed roll, regions of one patch each (none combined, none
            # turned): the compiled pass's patches of the same locus
            patches.extend(reversed(_pass_patches(
                wheelset, track, prof, sd, loc, regions, (pose, z, roll),
                (velocity, pitch_velocity, lateral_velocity, yaw_rate))))
            continue
        side_patches = []
        for (i0, i1, joins), lim, angle in zip(regions, territories(loc, regions), angles):
            factors = [(y, interaction_factor(d, full, combine_distance)) for y, d in joins]
            side_patches.append(_make_patch(wheelset, track, sd, loc, (i0, i1), pose,
                                            loads is None,
                                            (velocity, pitch_velocity, lateral_velocity,
                                             yaw_rate), lim, factors, angle))
        # the regions run along the locus from the gauge side (its y points to the
        # field side); CONTACT numbers a wheel's patches from the field side
        patches.extend(reversed(side_patches))
    return WheelsetContact(pose, patches, loci, loads, targets)


def _pass_contact(wheelset, track, keys, targets, loads, motion, rules):
    """The :class:`WheelsetContact` of the compiled search at
    ``keys`` = (lateral shift [m], yaw [rad], start roll [rad]) under the
    interpenetrations ``targets`` [m], with each side's locus at the pose over its
    regions (as :func:`find_contact`'s, computed where read: :class:`SearchLoci`);
    None where the pass does not serve (then :func:`find_contact` searches itself,
    and says why a pose is not found)."""
    if (wheelset.out_of_round is not None or rules.combine_distance != 0.0
            or rules.turn_distance > rules.combine_distance):
        return None
    prof = _pass_profiles(wheelset, track)
    if prof is None:
        return None
    shift, yaw, roll0 = keys
    r0 = wheelset.nominal_radius
    pose = PassPose(float(shift), float(yaw), track.rail_offset("left"),
                    track.rail_offset("right"), wheelset.wheel_offset, r0, *motion, 0.0)
    out = np.zeros((2 * MAX_PATCHES, NPF))
    # the case's searches share one memo (the wheel samples of the last loci and
    # the roll search's secant slope; issue 30; docs/tuning.md, section "Geometry
    # search")
    held = _memo(wheelset, track, shift, yaw)
    if held.search is None:
        held.search = new_memo(roll0)
    memo = held.search
    # the roll search as from a fresh memo (its start and secant slope): only the
    # loci's wheel samples carry over, so that its pose is a fresh search's
    memo[0], memo[1] = roll0, ROLL_SLOPE
    m, z, roll = search_patches(prof, pose, np.array([targets["left"], targets["right"]]),
                                memo, out)
    if m < 0 or max(np.count_nonzero(out[:m, P_SIDE] == s) for s in (0, 1)) >= MAX_PATCHES:
        return None                  # no pose, or regions beyond the pass's rows
    contact = rows_contact(out[:m], wheelset, track, WheelsetPose(shift, z, roll, yaw), loads,
                           targets)
    contact.loci = SearchLoci(wheelset, track, contact.pose,
                              {s: targets[s] + REGION_MARGIN for s in SIDES})
    return contact


def search_memo(wheelset, track, lateral_shift, yaw, memo=None):
    """The compiled search's memo that a case's searches at the lateral shift [m] and
    yaw [rad] share (:func:`find_contact` under prescribed interpenetrations;
    :data:`~railcontact.geometry.wheel_pass.MEMO_SIZE` floats; None: none yet).
    With ``memo``, a copy of it is held first: the wheel samples and secant slope
    of a search at the same pose (the compiled pass's) or a neighbouring one (the
    previous case of a sweep), from which the next search starts (each use checks
    that they hold what it needs, else searches afresh)."""
    held = _memo(wheelset, track, float(lateral_shift), float(yaw))
    if memo is not None:
        held.search = np.array(memo, dtype=float)
    return held.search


def _pass_profiles(wheelset, track):
    """The compiled search's :class:`~railcontact.geometry.wheel_pass.PassProfiles`
    of a wheelset on a track (None where the sides' profiles differ), made once per
    wheelset and track and kept in the wheelset's ``gap_memo`` (the track held, so
    that the identity check is sound): a case's searches share them (issue 30)."""
    hit = wheelset.gap_memo.get("pass profiles")
    if hit is None or hit[0] is not track:
        hit = wheelset.gap_memo["pass profiles"] = (track, pass_profiles(wheelset, track))
    return hit[1]


class SearchLoci(Mapping):
    """The contact locus of each side (``side`` -> :class:`Locus`) of a compiled
    search at ``pose`` over the wheel samples within ``window`` [m] per side of the
    closest approach, computed where first read (:func:`compute_locus`, the same
    loci as :func:`find_contact`'s): the solvers read the patches alone, so a
    case's balance does not compute them per search (issue 30)."""

    def __init__(self, wheelset, track, pose, window):
        self._args = (wheelset, track, pose)
        self._window = dict(window)
        self._loci = {}

    def __getitem__(self, side):
        if side not in self._window:
            raise KeyError(side)
        if side not in self._loci:
            ws, tr, p = self._args
            self._loci[side] = compute_locus(ws, tr, side, p.lateral_shift, p.vertical,
                                             p.roll, p.yaw, window=self._window[side])
        return self._loci[side]

    def __iter__(self):
        return iter(self._window)

    def __len__(self):
        return len(self._window)

    def __repr__(self):
        return f"SearchLoci({sorted(self._window)})"


def _fixed_roll_pose(wheelset, track, prof, keys, targets, loci_window):
    """:func:`~railcontact.geometry.pose.solve_pose` under a prescribed roll (one
    side, ``keys`` = (side, lateral shift [m], yaw [rad], roll [rad])) by the compiled
    pass's kernels on the wheelset's profiles ``prof``
    (:class:`~railcontact.geometry.wheel_pass.PassProfiles`): the side's minimum gap at vertical position 0
    (:func:`~railcontact.geometry.wheel_pass.side_min_gap`), which the interpenetration
    does not change and which is found once per case and roll, puts the wheelset at
    z = gap + target, and the side's locus there
    (:func:`~railcontact.geometry.wheel_pass.side_locus`, the same locus kernel, over
    the wheel samples that the last locus of the case held within its window:
    the pass's memo, kept per case and roll), trimmed to its samples within the
    window and one on either side (:func:`_window_span`), so that the locus's extent
    does not depend on the case's earlier searches (before, it spanned the memo's
    samples: on 384 combinations of shift, yaw, roll, side, interpenetration and
    earlier searches, 162 loci spanned other samples, their patches within 2.8e-13
    relative).  Returns (z, roll, {side: Locus}), or
    :func:`~railcontact.geometry.pose.solve_pose`'s where no contact is found (its
    error says why)."""
    side, shift, yaw, roll = keys
    s = SIDES.index(side)
    pose = PassPose(float(shift), float(yaw), track.rail_offset("left"),
                    track.rail_offset("right"), wheelset.wheel_offset,
                    wheelset.nominal_radius, 1.0, 0.0, 0.0, 0.0, 0.0)
    cache = _memo(wheelset, track, shift, yaw).fixed_roll
    key = (side, float(roll))
    if key not in cache:
        memo = new_memo(float(roll))
        cache[key] = (memo, float(side_min_gap(prof, pose, s, float(roll), memo)))
    memo, g = cache[key]
    target = float(targets[side])
    window = locus_window(loci_window, target)
    if math.isfinite(g):
        i0, i1, theta, P, yr, gap, slope, R, O, _ = side_locus(prof, pose, s, g + target,
                                                               float(roll), window, memo)
        # (a locus deeper than the target: a minimum the gap search missed)
        if gap.size and -target - MISSED_DEPTH <= float(np.min(gap)) < np.inf:
            a, b = _window_span(gap, window)
            return g + target, roll, {side: Locus(
                prof.yw[i0 + a:i0 + b], prof.zw[i0 + a:i0 + b], theta[a:b], P[:, a:b],
                yr[a:b], gap[a:b], slope[a:b], O, R, (int(i0 + a), int(i0 + b)))}
    return solve_pose(wheelset, track, shift, yaw, targets, tol=1e-12, roll_given=roll,
                      sides=(side,), loci_window=loci_window)


def _pass_patches(wheelset, track, prof, side, loc, regions, at, motion) -> list:
    """The patches of a side's locus regions (none combined or turned) by the
    compiled pass's :func:`~railcontact.geometry.wheel_pass.make_patch` on the
    locus ``loc`` of :func:`_fixed_roll_pose` (the same kernel's samples), each
    within its territory (:func:`~railcontact.geometry.regions.territories`), as
    :func:`~railcontact.geometry.wheel_pass.patch_geometry` makes the geometry of
    a row: :func:`_make_patch`'s patches to round-off (their rows agree to 4e-9
    relative on the benchmark sweep's poses, issue 30) for some 30 us per patch
    instead of 150.  ``at`` = (WheelsetPose, vertical position [m], roll [rad]);
    ``motion`` as :func:`_make_patch`'s."""
    pose, z, roll = at
    pp = PassPose(float(pose.lateral_shift), float(pose.yaw), track.rail_offset("left"),
                  track.rail_offset("right"), wheelset.wheel_offset,
                  wheelset.nominal_radius, *(float(v) for v in motion), 0.0)
    j0, j1 = loc.samples
    kernel_loc = (j0, j1, loc.theta, loc.point, loc.y_rail, loc.gap, loc.slope, loc.axes,
                  loc.origin, track.rail_offset(side))
    rows = np.zeros((len(regions), NPF))
    for k, (i0, i1, _) in enumerate(regions):
        make_patch(prof, pp, SIDES.index(side), kernel_loc, int(i0), int(i1), float(z),
                   float(roll), rows[k])
    return [patch_geometry(row, wheelset, track, pose, lim)
            for row, lim in zip(rows, territories(loc, regions))]


def _window_span(gap, window):
    """The samples [a, b) of a locus's gap ``gap`` [m] within ``window`` [m] of its
    minimum, and one on either side where the locus has it: what the prescribed-roll
    locus keeps (:func:`_fixed_roll_pose`; the memo's span covers it, its ends lying
    beyond the window)."""
    inside = np.flatnonzero(gap <= float(np.min(gap)) + window)
    return max(int(inside[0]) - 1, 0), min(int(inside[-1]) + 2, gap.size)


def _make_patch(wheelset, track, side, loc, region, pose, rigid, motion,
                territory=(-math.inf, math.inf), joins=(), angle=None) -> ContactGeometry:
    """The geometry of the patch of locus region ``region`` = (i0, i1); ``motion``:
    (velocity [m/s], pitch velocity [rad/s], lateral velocity [m/s], yaw rate
    [rad/s]) for the creepages; ``angle``: its contact angle [rad] in the side frame
    instead of the weighted one (a turned angle, :mod:`railcontact.geometry.turning`)."""
    i0, i1 = region
    velocity, pitch_velocity, lateral_velocity, yaw_rate = motion
    sl = slice(i0, i1 + 1)
    g = loc.gap[sl]
    im = i0 + int(np.argmin(g))
    ang = np.arctan(loc.slope[sl])
    if rigid or i1 == i0:
        # parabolic refinement of the minimum
        j = min(max(im, 1), loc.gap.size - 2)
        g3 = loc.gap[j - 1:j + 2]
        den = g3[0] - 2 * g3[1] + g3[2]
        frac = 0.5 * (g3[0] - g3[2]) / den if den > 0 else 0.0
        frac = float(np.clip(frac, -1.0, 1.0))
        y_ref = float(loc.y_rail[j] + frac * (loc.y_rail[j + 1] - loc.y_rail[j - 1]) / 2)
        x_ref = float(loc.point[0, j])
        a_ref = float(np.arctan(track.rail(side).slope(y_ref)))
        weight = 1.0
    else:
        w = loc.weights(sl, GAP_WEIGHT)
        weight = float(w.sum() * abs(loc.y_wheel[1] - loc.y_wheel[0]))
        y_ref = float(np.dot(w, loc.y_rail[sl]) / w.sum())
        x_ref = float(np.dot(w, loc.x_centres(sl)) / w.sum())
        a_ref = float(np.dot(w, ang) / w.sum()) if angle is None else float(angle)
    rail = track.rail(side)
    y_off = track.rail_offset(side)
    z_ref = float(rail.z_at(y_ref))
    C = np.array([x_ref, y_off + y_ref, z_ref])
    gapf = GapEvaluator(wheelset, track, side, loc, C, a_ref)
    # wheel coordinates of the reference point
    L = loc.axes.T @ (C - loc.origin)
    y_w = float(L[1] - wheelset.wheel_offset)
    z_w = float(wheelset.wheel(side).z_at(y_w))
    rolling_radius = wheelset.nominal_radius + z_w
    if wheelset.out_of_round is not None:
        # an out-of-round wheel: its radial deviation at its pitch angle
        # (the patch's origin x_ref along the track; the locus already the wheel's)
        gapf = wheelset.out_of_round.patch_gap(gapf, y_w, rolling_radius, a_ref,
                                               x_ref - float(loc.origin[0]))
    # curvatures at the deepest point, in the patch's tangent-plane coordinates
    sgn = 1.0 if side == "right" else -1.0
    # the locus's minimum between the samples (continuous in the pose; as the
    # compiled pass, wheel_pass.make_patch)
    gl = np.ascontiguousarray(loc.gap, dtype=float)
    f = float(deepest_fraction(gl, im))
    y_min = float(at_fraction(np.ascontiguousarray(loc.y_rail, dtype=float), im, f))
    x_min = float(at_fraction(np.ascontiguousarray(loc.point[0], dtype=float), im, f))
    Pm = np.array([x_min, y_off + y_min, float(rail.z_at(y_min))])
    d = Pm - C
    x_m = float(d[0])
    y_m = sgn * float(d @ gapf.t)
    A, B, h_m = curvatures_fd(gapf, x_m, y_m)
    if not (A > 0.0 and B > 0.0 and abs(h_m) < 0.5):
        # the stencil at the deepest point left a surface (a patch spanning a strongly
        # curved part of the profile, e.g. flange root to flange, whose deepest point
        # projects beyond the rail profile's end): the curvatures at the reference
        # point, on the rail by construction; the approach from the fallback below
        log.debug("%s patch: no curvatures at its deepest point; taken at its reference "
                  "point", side)
        A, B, _ = curvatures_fd(gapf, 0.0, 0.0)
        h_m = math.nan
    approach = -h_m
    # robust fallback: vertical interpenetration of the deepest locus point projected on n
    # (the gap and the slope both at the locus's minimum between the samples)
    vertical = -float(deepest_gap(gl, im)) * math.cos(math.atan(float(at_fraction(
        np.ascontiguousarray(loc.slope, dtype=float), im, f))))
    if not math.isfinite(approach) or (approach <= 0.0 < vertical):
        approach = vertical
    approach = max(0.0, approach)
    n_side = gapf.n
    delta_tr = sgn * a_ref
    n_tr = np.array([0.0, sgn * n_side[1], n_side[2]])
    Q = C + approach * n_side
    creep, V, dphi = kinematic_creepage(side, Q, n_tr, delta_tr, pose, wheelset.nominal_radius, velocity,
                         pitch_velocity, lateral_velocity, yaw_rate)
    ys = loc.y_rail[sl]
    ext_y = (sgn * (ys.min() - y_ref), sgn * (ys.max() - y_ref))
    if not (A > 0.0 and B > 0.0):
        # a conformal or rough patch (measured profiles): the curvatures of the
        # paraboloid that has the interpenetration region's extent at its approach
        # (so that the approximate models, and the vertical-force iteration's
        # Hertzian start, see a patch of the right size)
        half_y = 0.5 * (max(ext_y) - min(ext_y)) / math.cos(a_ref)
        B = B if B > 0.0 else max(approach, 1e-9) / max(half_y, 1e-4) ** 2
        A = A if A > 0.0 else math.cos(a_ref) / (2.0 * (wheelset.nominal_radius + z_w))
        log.debug("%s patch: curvatures of its interpenetration region's extent "
                  "(%.3g, %.3g) 1/m", side, A, B)
    # the force's lateral curvature: the region's where the deepest point's is
    # meaningless (two minima of equal depth, a joint of the profiles' arcs)
    bf = float(force_curvature((0, loc.gap.size, None, None,
                                np.ascontiguousarray(loc.y_rail, dtype=float),
                                np.ascontiguousarray(loc.gap, dtype=float),
                                np.ascontiguousarray(loc.slope, dtype=float)),
                               i0, i1, im, float(B)))
    half_x = math.sqrt(max(approach, 0.0) / max(A, 1e-9))
    extent = (x_m - half_x, x_m + half_x, min(ext_y) / math.cos(a_ref) if rigid is False else 0.0,
              max(ext_y) / math.cos(a_ref) if rigid is False else 0.0)
    pos_tr = np.array([C[0], sgn * C[1], C[2]])
    # the territory in patch coordinates (y along t, sgn-mirrored as the extent)
    lim = sorted(sgn * (v - y_ref) / math.cos(a_ref) for v in territory)
    inter = tuple(sorted((sgn * (v - y_ref) / math.cos(a_ref), f) for v, f in joins))
    return ContactGeometry(curvatures=(A, B), side=side, contact_angle=delta_tr,
                           rolling_radius=rolling_radius, y_rail=y_ref, y_wheel=y_w,
                           z_rail=z_ref, z_wheel=z_w, position=pos_tr, approach=approach,
                           weight=weight, creepage=creep, velocity=V, extent=extent,
                           gap_function=gapf, spin_derivative=dphi, bounds=tuple(lim),
                           interaction=inter,
                           local_contact_angle=gapf.contact_angle_at,
                           force_curvature=bf if bf != B else None)
