"""A wheel-rail case with its wheel loads met: the contact evaluation that
:func:`railcontact.cases.equilibrium.balance` drives (:class:`WheelRailContact`), and a
wheel at a prescribed vertical position (CONTACT's NORM = 0)."""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from .bodies import build_wheelset_track, contact_search
from .conformal import is_conformal
from .compiled_case import (MAX_PATCHES, NRF, case_contact, case_pass_inputs,
                            compiled_unsupported, evaluate_wheelset, near_pose,
                            solve_case_forces)
from .equilibrium import (JUMP_SLOPE, Neighbour, VerticalBalance,
                          balance as solve_balance, extrapolate_start)
from ..core.checks import shown
from ..core.errors import ContactNotFoundError, InputError, RailContactError
from ..geometry.locus import depth_at
from ..geometry.search import WheelsetContact, search_memo
from ..geometry.track import WheelsetPose
from .patches import (add_tangential, coupled_models, lateral_ratio, nearest_patch,
                      patch_creepage, patch_friction, solve_case_patches, wheel_rail_validity)
from .results import PatchResult, patch_vertical_force, vertical_force_on_rail
from ..normal import get_normal_model
from ..tangential import get_tangential_model

from ..core.status import SolverStatus

log = logging.getLogger(__name__)


def solve_at_position(case, nmodel, tmodel, kw):
    """Patches of one wheel (``wheelset.side``) at a prescribed vertical position and
    roll of the wheelset (CONTACT's NORM = 0): the interpenetration follows from
    the position, and no vertical-force iteration runs.  Returns the patch results
    (none where the wheel does not reach the rail) and the contact search."""
    bodies = build_wheelset_track(case)
    ws, tr = bodies
    s = case.wheel_rail
    side, y, yaw, roll, z = s.side, s.lateral_shift, s.yaw, s.roll, s.vertical_position
    # the deepest interpenetration: the wheel lowered from where it touches to z
    depth = depth_at(ws, tr, side, y, z, roll, yaw)
    if not depth > 0:
        log.info("the %s wheel at z = %.4f mm does not reach the rail (gap %.4f mm)", side,
                 z * 1e3, -depth * 1e3)
        return [], WheelsetContact(WheelsetPose(y, z, roll, yaw), [], {}, None, {side: 0.0})
    contact = contact_search(case, interpenetration={side: depth}, bodies=bodies)
    results = solve_case_patches(case, contact, nmodel, tmodel, kw,
                             coupled=coupled_models(case, nmodel, tmodel))
    results = [r for r in results if r.geometry.side == side]
    wheel_rail_validity(results, bodies)
    return results, contact



def _first_search(case, bodies, loads, sides, start, before=None,
                  ratio=None):
    """The contact search the vertical balance starts from.

    With ``start`` (the contact of a neighbouring case's result, e.g. the previous
    case of a sweep): at its interpenetrations, scaled to this case's loads as
    Hertz's approach (Q^(2/3)), from its roll; where that case itself started from
    a neighbour, ``before`` (its :attr:`VerticalBalance.neighbour`, a
    :class:`~railcontact.cases.equilibrium.Neighbour`), the linear extrapolation of
    the two (:func:`~railcontact.cases.equilibrium.extrapolate_start` with the
    factor ``ratio``, default ``EXTRAPOLATE_RATIO``): a sweep's next step.  Else
    (or where ``start`` has no interpenetration on a side): the geometry layer's
    multi-Hertzian estimate, one load iteration (why these starts: docs/tuning.md,
    section "Equilibrium")."""
    if start is not None and start.interpenetration and start.loads:
        d1 = _scaled(start.interpenetration, start.loads, loads, sides)
        if d1 is not None:
            roll = start.pose.roll
            d0 = _scaled(before.interpenetration, before.loads, loads, sides) \
                if before is not None and before.loads else None
            d1, roll, _ = extrapolate_start(
                d1, d0, EXTRAPOLATE_RATIO if ratio is None else ratio, roll,
                before.roll if before is not None else math.nan)
            return contact_search(case, interpenetration=d1, bodies=bodies,
                                  roll_start=roll)
    return contact_search(case, bodies=bodies, load_iterations=1)


def _scaled(interpenetration, their_loads, loads, sides):
    """A case's interpenetrations [m] scaled to ``loads`` as Hertz's approach
    (Q^(2/3)); None where a side has none."""
    d = {}
    for s in sides:
        v, q = interpenetration.get(s, 0.0), their_loads.get(s, math.nan)
        d[s] = v * (loads[s] / q) ** (2.0 / 3.0) if q > 0 else math.nan
    return d if all(math.isfinite(v) and v > 0 for v in d.values()) else None


#: a sweep's case extrapolates its start linearly from its two previous cases
#: where their interpenetrations differ by less than this factor on every side
#: (else the previous case's alone; docs/tuning.md, section "Equilibrium"); the
#: default of :attr:`BalanceOptions.extrapolate_ratio`
EXTRAPOLATE_RATIO = 2.0

#: the uncertainty of a stand-in lateral force: FASTSIM's F_y on the exact normal
#: solution is taken to be within this fraction of the exact F_y (docs/tuning.md,
#: section "Equilibrium")
STANDIN_UNCERTAINTY = 0.1



@dataclass
class ContactEvaluation:
    """The contact of a wheel-rail case evaluated at given interpenetrations.

    ``interpenetration`` [m] per side, the contact search's result ``contact``, the
    loaded patches' ``results``, the vertical force each wheel exerts on its rail
    (``forces`` [N], :func:`vertical_force_on_rail`) and whether those are the
    forces of a result (``final``: the tangential problems solved); where not, the
    lateral forces are stand-ins and ``uncertainty`` says how far off the load that
    may put each side's force (relative to the load)."""

    interpenetration: dict
    contact: WheelsetContact
    results: list
    forces: dict
    final: bool
    uncertainty: dict | None = None



class WheelRailContact:
    """The contact evaluation that :func:`railcontact.cases.equilibrium.balance` drives for
    a wheel-rail case.

    ``evaluate(d, final)`` searches the contact at the interpenetrations ``d`` (from
    the last search's roll) and solves the loaded patches' normal problems,
    warm-started from the last evaluation's solutions (on its grids where they
    fit); at the interpenetrations of the last call its normal solutions are
    reused.  With the exact tangential model the tangential problems are solved
    where ``final`` is asked (warm-started from the last tangential solutions), and
    else FASTSIM on the normal solutions stands in for the lateral forces (the
    exact solver's own first estimate), each side's uncertainty
    ``STANDIN_UNCERTAINTY`` times its lateral forces' share of the balance,
    sum |F_y sin(d)| / Q; the other tangential models solve every time.

    ``start``: the :class:`SolveResult` of a neighbouring case (warm start: the
    first search at its interpenetrations, the solvers from its solutions).
    ``compiled``: the case's balance in the compiled pass
    (:class:`~railcontact.cases.compiled_case.CaseForces`): the first search at its
    interpenetrations and roll instead.  ``extrapolate_ratio``: that of
    :func:`_first_search` (:attr:`BalanceOptions.extrapolate_ratio`)."""

    def __init__(self, case, nmodel, tmodel, kw, start=None, compiled=None,
                 extrapolate_ratio=EXTRAPOLATE_RATIO):
        self.case, self.nmodel, self.tmodel, self.kw = case, nmodel, tmodel, kw
        self.bodies = build_wheelset_track(case)
        self.loads = case.wheel_rail.loads
        self.sides = case.wheel_rail.balanced_sides
        _seed_search(case, self.bodies, compiled, start)
        if compiled is not None:
            # the compiled pass's patches (no second search), or a search at its
            # interpenetrations where it combined regions
            self.first = case_contact(compiled, case) or contact_search(
                case, interpenetration=dict(compiled.interpenetration), bodies=self.bodies,
                roll_start=compiled.roll)
        else:
            self.first = _first_search(
                case, self.bodies, self.loads, self.sides,
                start.contact if start is not None else None,
                start.balance.neighbour if start is not None and start.balance is not None
                else None, extrapolate_ratio)
        self.coupled = coupled_models(case, nmodel, tmodel)
        self.lazy = (tmodel is not None and "lazy" in tmodel.capabilities
                     and not self.coupled)
        self.previous = start.patches if start is not None else None
        # the results whose tangential solutions start the next tangential solves
        self.tangential_start = self.previous
        if start is None and compiled is not None and self.lazy \
                and "warm-start" in nmodel.capabilities:
            # a cold case from the compiled pass: Hertz's pressure on its patches
            # starts the first normal solves
            self.previous = _hertz_pressures(case, self.first)
        # the neighbour's solved patches and FASTSIM's on them: the stand-in's correction
        self.neighbour = None
        if start is not None and start.balance is not None and start.balance.standin:
            self.neighbour = (start.patches, start.balance.standin)
        self.standin = None         # FASTSIM on the last provisional evaluation's patches
        self.last = None

    def restart(self, compiled):
        """Start again from the compiled pass's result ``compiled`` (its patches, or
        a search at its interpenetrations and roll; its search memo that of the
        case's next searches); the neighbour's solutions stay the solvers' warm
        starts."""
        _seed_search(self.case, self.bodies, compiled, None)
        self.first = case_contact(compiled, self.case) or contact_search(
            self.case, interpenetration=dict(compiled.interpenetration), bodies=self.bodies,
            roll_start=compiled.roll)
        self.last = self.standin = None

    def start(self) -> dict:
        """The interpenetrations [m] of the first search."""
        return {s: self.first.interpenetration[s] for s in self.sides}

    def __call__(self, d: dict, final: bool = False) -> ContactEvaluation:
        last, case = self.last, self.case
        if last is not None and last.interpenetration == d:
            contact, results = last.contact, last.results
        else:
            if last is None and d == self.start():
                contact = self.first
            else:
                roll = (last.contact if last is not None else self.first).pose.roll
                contact = contact_search(case, interpenetration=d, bodies=self.bodies,
                                         roll_start=roll)
            results = solve_case_patches(case, contact, self.nmodel, self.tmodel, self.kw,
                                     previous=last.results if last else self.previous,
                                     normal_only=self.lazy, coupled=self.coupled,
                                     same_case=last is not None)
        if final and self.lazy and any(r.tangential is None for r in results):
            results = add_tangential(case, results, self.tmodel,
                                      previous=self.tangential_start or self.standin)
            self.tangential_start = results
        done = all(r.tangential is not None for r in results) or self.tmodel is None
        lateral = uncertainty = None
        if not done:
            if last is None or last.results is not results or self.standin is None:
                self.standin = add_tangential(case, results, get_tangential_model("fastsim"))
            fy = _standin_lateral(self.standin, self.neighbour)
            lateral = lambda r: fy[id(r.geometry)]                      # noqa: E731
            uncertainty = {s: STANDIN_UNCERTAINTY * sum(
                abs(fy[id(r.geometry)] * math.sin(r.geometry.contact_angle))
                for r in results if r.geometry.side == s) / self.loads[s] for s in self.sides}
        forces = {s: vertical_force_on_rail(results, s, lateral) for s in self.sides}
        self.last = ContactEvaluation(dict(d), contact, results, forces, done, uncertainty)
        return self.last



def _seed_search(case, bodies, compiled, start) -> None:
    """The memo the case's compiled contact searches start from
    (:func:`~railcontact.geometry.search.search_memo`): the compiled pass's at the
    case's pose (``compiled``), else a neighbouring case's (``start``'s
    :attr:`VerticalBalance.search`) where its lateral shift and yaw are within
    ``MEMO_SHIFT`` and ``MEMO_YAW`` of the case's (the compiled pass's rule), else
    none (the first search starts afresh).  The searches' results are those of a
    fresh memo to the roll search's tolerance (1e-12 rad; measured: docs/tuning.md,
    section "Geometry search")."""
    s = case.wheel_rail
    if s.roll is not None:
        return
    memo = None
    if compiled is not None:
        memo = getattr(compiled, "memo", None)
    elif start is not None and start.balance is not None and start.balance.search is not None:
        shift, yaw, held = start.balance.search
        if near_pose((shift, yaw), s.lateral_shift, s.yaw):
            memo = held
    if memo is not None:
        search_memo(*bodies, s.lateral_shift, s.yaw, memo)


def _hertz_pressures(case, contact):
    """Hertz's normal solutions of the loaded patches of ``contact`` (patch results
    without a tangential solution), whose pressure (``pressure_at``) starts a cold
    exact case's first normal solves from the compiled pass's patches (measured on
    every 10th case of the 1000-case sweep: 13.1 against 14.1 Polonsky-Keer
    iterations per solve, 12.39 against 12.87 ms per case, the same forces to 3e-6
    of Q: docs/tuning.md, section "Equilibrium"); None where there are none."""
    hertz = get_normal_model("hertz")
    out = []
    for g in contact.patches:
        if g.approach > 0:
            try:
                ns = hertz.solve(g, case.material, penetration=g.approach)
            except RailContactError as exc:           # e.g. a concave curvature
                log.debug("no Hertzian pressure start on a patch: %s", exc)
                continue
            out.append(PatchResult(g, ns, None, patch_creepage(case, g)))
    return out or None


def _standin_lateral(standin, neighbour) -> dict:
    """F_y [N] standing in for each patch's tangential solution (by the id of its
    geometry): FASTSIM's on the patch's normal solution (``standin``), where a
    neighbouring case (``neighbour``: its solved patch results and FASTSIM's on
    them) has a patch of the same side within ``WARM_DISTANCE`` plus the neighbour's
    difference of the solved F_y/F_n from FASTSIM's, times F_n: FASTSIM's own error
    largely cancels between neighbours (docs/tuning.md, section "Equilibrium")."""
    out = {}
    for r in standin:
        fy = r.tangential.fy
        if neighbour is not None:
            a, b = nearest_patch(neighbour[0], r.geometry), nearest_patch(neighbour[1], r.geometry)
            if a is not None and b is not None and a.tangential is not None:
                fy += (lateral_ratio(a) - lateral_ratio(b)) * r.normal.normal_force
        out[id(r.geometry)] = fy
    return out



@dataclass(frozen=True)
class BalanceOptions:
    """How :func:`solve_wheel_rail` balances a wheel-rail case (the defaults are
    the package's; the others serve comparisons, e.g. the benchmarks' before and
    after: ``railcontact.cases.solve.solve(case, options=BalanceOptions(...))``).

    Attributes
    ----------
    compiled_start : bool
        Start the balance from the compiled pass's (:func:`compiled_start`), where
        it runs the case's models or their nearest compiled forms; False: from the
        geometry layer's estimate or a neighbour's interpenetrations, as before the
        pass.
    extrapolate_ratio : float
        A warm-started case extrapolates its start from its two previous cases
        where their interpenetrations differ by less than this factor
        (:func:`~railcontact.cases.equilibrium.extrapolate_start`); 1 turns it off.
    force_control : bool
        Balance a case with the exact models whose balanced sides have one patch
        each force-controlled (:func:`_force_controlled`): issue 30's named design,
        "a side with one patch force-controlled".  Measured slower than the general
        balance on the benchmark sweep: cold 17.7 against 11.9 ms, warm 10.5
        against 7.2 ms per case (more normal and tangential solves for fewer
        passes; docs/tuning.md, section "Equilibrium"), so off; its figures are
        measured by ``benchmarks/run_all.py``'s ``bench_force_controlled``.

    A case with models the compiled pass does not run but whose tangential model
    is lazy (the exact ones) starts from the compiled pass's balance of Hertz +
    FASTSIM (:func:`hertz_estimate`): a cold case always (its patches, no first
    search), a warm-started one where its first evaluation, at the neighbour's
    (extrapolated) interpenetrations, misses a side's load by more than
    ``RESTART_MISS`` in |ln(F/Q)| (the S-shaped force of flange contact:
    docs/tuning.md, section "Equilibrium").  Not an option: the start before it is
    measured against the commit before it (``benchmarks/exact_case.py --before
    REF``).
    """

    compiled_start: bool = True
    extrapolate_ratio: float = EXTRAPOLATE_RATIO
    force_control: bool = False

    def __post_init__(self):
        for name in ("compiled_start", "force_control"):
            if not isinstance(getattr(self, name), bool):
                raise InputError(f"BalanceOptions.{name} = {shown(getattr(self, name))}: "
                                 "expected True or False")
        r = self.extrapolate_ratio
        if isinstance(r, bool) or not isinstance(r, (int, float)) or not r >= 1.0:
            raise InputError(f"BalanceOptions.extrapolate_ratio = {shown(r)}: expected a "
                             "factor >= 1 (1: no extrapolation)")


#: the balance's options where none are given
DEFAULT_OPTIONS = BalanceOptions()


def compiled_start(case, nmodel, tmodel, neighbour=None):
    """The case's vertical balance in the compiled pass
    (:func:`railcontact.cases.compiled_case.solve_case_forces`), where it runs the
    case's models or, as a start, their nearest compiled forms (an ellipse normal
    model, an online creep law), started from ``neighbour`` (a neighbouring case's
    :class:`SolveResult`) where given: its interpenetrations, roll and Jacobian
    start the balance of the case's own models, which then usually meets the loads
    in its first pass.  None where the pass does not run the case or does not meet
    the loads (the balance then starts as it would without it)."""
    if tmodel is None:
        return None
    names = (nmodel.name, tmodel.name)
    if compiled_unsupported(case, *names):
        # other models (the exact ones): their own balance, which takes the
        # compiled Hertz + FASTSIM balance as its start (solve_wheel_rail:
        # hertz_estimate), not as their result
        return None
    return _compiled_balance(case, names, neighbour, jacobian=True)


def _compiled_balance(case, names, neighbour, jacobian):
    """:func:`~railcontact.cases.compiled_case.solve_case_forces` of the case with
    the models ``names``, started from ``neighbour`` (a neighbouring case's
    :class:`SolveResult`, both sides in contact) where given: its interpenetrations
    and roll, and with ``jacobian`` its balance's Jacobian.  None where the pass
    raises (the Python path says it properly) or does not meet the loads."""
    start = None
    if (neighbour is not None and neighbour.contact is not None
            and set(neighbour.contact.interpenetration or ()) >= {"left", "right"}
            and not (jacobian and neighbour.balance is None)):
        start = Neighbour(dict(neighbour.contact.interpenetration),
                          neighbour.contact.pose.roll,
                          jacobian=neighbour.balance.jacobian if jacobian else None)
    try:
        res = solve_case_forces(case, *names, start=start)
    except RailContactError as exc:
        log.debug("compiled pass (%s + %s): %s", *names, exc)
        return None
    return res if res.converged else None



#: a warm-started case with the exact models whose first evaluation misses a side's
#: load by more than this in |ln(F/Q)| starts again from :func:`hertz_estimate`
#: (docs/tuning.md, section "Equilibrium")
RESTART_MISS = 0.5


def hertz_estimate(case, neighbour=None):
    """The compiled pass's balance of the case with Hertz + FASTSIM
    (:func:`railcontact.cases.compiled_case.solve_case_forces`), the start of a
    case whose models it does not run (the exact ones): its interpenetrations,
    roll, Jacobian and patches; ``neighbour`` (a neighbouring case's
    :class:`SolveResult`) starts its search from that case's interpenetrations and
    roll.  None where the pass does not run the case, the case asks for a conformal
    contact surface, or the pass does not meet its loads."""
    if compiled_unsupported(case, "hertz", "fastsim") or is_conformal(case):
        return None             # (the pass's patches are planar)
    return _compiled_balance(case, ("hertz", "fastsim"), neighbour, jacobian=False)


#: the step in ln d of :func:`hertz_jacobian`'s central differences
SLOPE_DIFFERENCE = 0.02


def hertz_jacobian(case, est):
    """d(ln F)/d(ln d) of the compiled Hertz + FASTSIM balance ``est``
    (:func:`hertz_estimate`) at its interpenetrations, each side's column by central
    differences of ``SLOPE_DIFFERENCE`` in its ln d (four evaluations of the pass's
    search and patches from its search memo; some 0.8 ms on the shared 2-core
    machine, about one evaluation of the pass each): the Jacobian an exact
    case's balance starts from there.  The pass's own Jacobian (its pose steps',
    from the patches' exponents) cannot hold the flange root's S-shaped force: at
    6.29-6.44 mm the differences give 10-17 where it holds 1.0-2.0, and the exact
    force's slope there is 11-23 (docs/tuning.md, section "Equilibrium").  None
    where an evaluation finds no pose or no force on a side, or the differences
    leave no positive diagonal and determinant or an entry beyond ``JUMP_SLOPE``."""
    prof, pose, model, loads = case_pass_inputs(case, "hertz", "fastsim")
    d0 = np.array([est.interpenetration["left"], est.interpenetration["right"]])
    out, fz = np.zeros((2 * MAX_PATCHES, NRF)), np.zeros(2)
    J = np.empty((2, 2))
    for k in range(2):
        r = []
        for sign in (1.0, -1.0):
            d = d0.copy()
            d[k] *= math.exp(sign * SLOPE_DIFFERENCE)
            m, _, _ = evaluate_wheelset(prof, pose, model, d, est.memo.copy(), out, fz)
            if m <= 0 or not np.all(fz > 0):
                return None
            r.append(np.log(fz / loads))
        J[:, k] = (r[0] - r[1]) / (2.0 * SLOPE_DIFFERENCE)
    if not (np.all(np.isfinite(J)) and np.all(np.abs(J) <= JUMP_SLOPE)
            and np.all(np.diag(J) > 0) and np.linalg.det(J) > 0):
        return None
    return J


#: a cold exact case starts from :func:`hertz_jacobian` where the compiled pass took
#: more than this many evaluations (its steps did not settle at once: the flange's
#: S-shaped force; on the 1000-case sweep 32 cases, all at 6.29-6.96 mm), else from
#: the pass's own Jacobian (some 0.8 ms saved where the two agree: 2-3 evaluations
#: in 928 of the 1000 cases, 4 in 40)
SLOPE_PASSES = 4


def _start_jacobian(case, est, sides, restarted=False):
    """The Jacobian an exact case's balance starts from at the compiled pass's
    balance ``est``: :func:`hertz_jacobian` in the order of ``sides`` where the
    case was ``restarted`` (its first evaluation missed by more than
    ``RESTART_MISS``) or the pass took more than ``SLOPE_PASSES`` evaluations,
    else (or where the differences give none) the pass's own."""
    J = None
    if est.memo is not None and len(sides) == 2 and (restarted or est.passes > SLOPE_PASSES):
        J = hertz_jacobian(case, est)
    if J is None:
        return est.jacobian
    order = [("left", "right").index(s) for s in sides]
    return J[np.ix_(order, order)]


def _hertz_restart(evaluate, start):
    """A warm-started case's restart from :func:`hertz_estimate` where the first
    evaluation (made here, at the balance's start) misses a side's load by more
    than ``RESTART_MISS``: returns the compiled pass's result (``evaluate`` then
    starts from its patches) and the Jacobian d(ln F)/d(ln d) the balance starts
    from (:func:`_start_jacobian`: the restart says the force is S-shaped there), or
    (None, None) (no restart; the first evaluation is kept for the balance's first
    pass)."""
    ev = evaluate(evaluate.start())
    miss = max(abs(math.log(max(ev.forces[s], 1e-6 * q) / q)) for s, q in evaluate.loads.items()
               if s in evaluate.sides)
    if miss <= RESTART_MISS:
        return None, None
    est = hertz_estimate(evaluate.case, start)
    if est is None:
        return None, None
    log.debug("first evaluation %.3g off the load: restarted from the compiled Hertz "
              "balance", miss)
    evaluate.restart(est)
    return est, _start_jacobian(evaluate.case, est, evaluate.sides, restarted=True)


#: searches of the force-controlled balance at most (:func:`_force_controlled`)
FORCE_CONTROL_SEARCHES = 5

#: normal-tangential solves on one search's patch at most, until F_y/F_n settles
FORCE_CONTROL_ROUNDS = 3



@dataclass
class _Side:
    """One side's state in :func:`_force_controlled`: its last patch result (the
    tangential solution once solved), F_y/F_n and whether that is the exact
    model's, FASTSIM's patch result, d(ln F_n)/d(ln delta), and the
    (interpenetration, patch approach) pairs of its searches."""

    result: PatchResult | None = None
    ratio: float = 0.0
    exact: bool = False
    standin: PatchResult | None = None
    slope: float | None = None
    path: list | None = None



def _force_controlled(evaluate, rtol):
    """The vertical balance of a case whose balanced sides each have one loaded
    patch, with the exact models (the normal one force-controlled, the tangential
    one lazy).

    Each side's normal problem is solved for the normal force that meets its load,
    F_n = Q / (cos d - (F_y/F_n) sin d), the approach found inside the normal
    solver (CONTACT's NORM = 1), on the patch of the last contact search; F_y/F_n
    is first a neighbouring case's exact one (or 0), then FASTSIM's on the solution
    (corrected by the neighbour's exact solutions as the general balance's
    stand-in), then the exact model's.  Where the approach under the load differs
    from the search's patch's by more than the tolerance allows (the residual of
    the load at the search's approach, by the contact stiffness
    d(ln F_n)/d(ln delta) = K delta / F_n, over ``rtol``), the contact is searched
    again at the interpenetrations of that approach (the secant of the side's
    searches); at a search whose approaches meet the load, the exact tangential
    problem is solved once per side (warm-started from FASTSIM's solution or the
    neighbour's), and where its F_y/F_n moves the balance beyond ``rtol``, the
    normal problem again and, its approach still within the tolerance, the
    tangential one.  So the result's patches are the last search's, and the load
    is met at their approaches to ``rtol``, as the general balance meets it.

    Returns (results, contact, VerticalBalance), or None where a balanced side has
    not one loaded patch, the searches do not settle in ``FORCE_CONTROL_SEARCHES``
    or a solver fails: then the general balance runs."""
    case, nmodel, kw = evaluate.case, evaluate.nmodel, evaluate.kw
    sides, loads = evaluate.sides, evaluate.loads
    contact, d = evaluate.first, evaluate.start()
    previous, neighbour = evaluate.previous, evaluate.neighbour
    state = {s: _Side(path=[]) for s in sides}
    for search in range(1, FORCE_CONTROL_SEARCHES + 1):
        patches = {s: [g for g in contact.patches if g.side == s and g.approach > 0]
                   for s in sides}
        if any(len(v) != 1 for v in patches.values()):
            return None
        met = True
        for s in sides:
            st, geom = state[s], patches[s][0]
            st.path.append((d[s], geom.approach))
            if st.result is None:
                near = nearest_patch(previous, geom)
                st.ratio, st.exact = lateral_ratio(near), False
                start = near
            else:
                start = st.result
            ok = _side_on_patch(evaluate, st, geom, loads[s], rtol, start, neighbour)
            if ok is None:
                return None
            met &= ok
        if met:
            break
        if search == FORCE_CONTROL_SEARCHES:
            log.debug("force-controlled balance: the searches do not settle in %d; the "
                      "general balance runs", search)
            return None
        d = {s: _next_interpenetration(state[s].path, state[s].result.normal.penetration)
             for s in sides}
        contact = contact_search(case, interpenetration=d, bodies=evaluate.bodies,
                                 roll_start=contact.pose.roll)
    results = [state[s].result for s in sides]
    # the other side's patches (a prescribed roll: one side balanced) as the
    # general balance leaves them: solved at their approach
    others = [g for g in contact.patches if g.side not in sides and g.approach > 0]
    if others:
        results += solve_case_patches(case, WheelsetContact(contact.pose, others), nmodel,
                                      evaluate.tmodel, kw, previous=previous)
    residual = {s: vertical_force_on_rail(results, s) / loads[s] - 1.0 for s in sides}
    if not all(abs(v) <= rtol for v in residual.values()):
        return None
    jac = np.diag([state[s].slope for s in sides]) if len(sides) > 1 else None
    balance = VerticalBalance(True, False, search, residual, jacobian=jac)
    balance.standin = [state[s].standin for s in sides]
    return results, contact, balance


def _side_on_patch(evaluate, st, geom, load, rtol, start, neighbour):
    """One side of :func:`_force_controlled` on the patch ``geom`` of a search: the
    normal problem under the load with the side's F_y/F_n (warm-started from
    ``start``, on its grid where the patch keeps it), FASTSIM's F_y/F_n on it where
    the exact one is not known, and where the approach and F_y/F_n hold to
    ``rtol``, the exact tangential problem, up to ``FORCE_CONTROL_ROUNDS`` times.
    Updates ``st``; returns whether the side's result meets the load at this
    search's approach, or None where a solver fails or the patch cannot carry the
    load upright."""
    case, nmodel, tmodel, kw = evaluate.case, evaluate.nmodel, evaluate.tmodel, evaluate.kw
    creep = patch_creepage(case, geom)
    mu = patch_friction(case, geom)
    same = start is not None and start.geometry is geom
    nkw = dict(kw)
    if start is not None:
        nkw["warm_start"] = start.normal
        if same:
            nkw["reuse_grid"] = start.normal
    for _ in range(FORCE_CONTROL_ROUNDS):
        k = _load_factor(geom, st.ratio)
        if not k > 0:
            return None
        ns = nmodel.solve(geom, case.material, normal_force=load / k, **nkw)
        if not ns.status.converged or not ns.penetration > 0:
            return None
        nkw = dict(kw, warm_start=ns, reuse_grid=ns)
        bare = PatchResult(geom, ns, None, creep)
        if st.slope is None:        # d(ln F)/d(ln delta) changes slowly: the first's
            st.slope = _log_stiffness(nmodel, case, bare)
        if not st.exact:
            st.standin = add_tangential(case, [bare], get_tangential_model("fastsim"))[0]
            new = _standin_lateral([st.standin], neighbour)[id(geom)] / ns.normal_force
            moved = abs(_load_factor(geom, new) / k - 1.0) > 0.5 * rtol
            st.ratio = new
            if moved:
                continue                    # the normal problem again with it
        tstart = st.result if st.result is not None and st.result.tangential is not None \
            else start if start is not None and start.tangential is not None else st.standin
        ts = tmodel.solve(ns, geom, case.material, creep, mu, geom.velocity,
                          warm_start=tstart.tangential)
        st.result = PatchResult(geom, ns, ts, creep)
        st.ratio, st.exact = lateral_ratio(st.result), True
        if abs(patch_vertical_force(st.result) / load - 1.0) <= rtol:
            break
    else:
        return False if st.result is not None else None
    # the load met on this patch: at the search's approach too (by the stiffness)?
    return abs(st.slope * (geom.approach / st.result.normal.penetration - 1.0)) <= rtol


def _next_interpenetration(path, approach) -> float:
    """The interpenetration [m] of a side whose patch has the approach [m] under its
    load: from the (interpenetration, patch approach) pairs of the side's searches,
    the secant through the last two, or in proportion to the last one."""
    d1, a1 = path[-1]
    if len(path) > 1:
        d0, a0 = path[-2]
        if a1 != a0 and (d1 - d0) / (a1 - a0) > 0:
            return d1 + (approach - a1) * (d1 - d0) / (a1 - a0)
    return d1 * approach / a1


def _log_stiffness(nmodel, case, res):
    """d(ln F_n)/d(ln delta) of a patch result from its contact stiffness
    (:meth:`~railcontact.normal.exact.ExactNormalModel.contact_stiffness`): the
    Jacobian a neighbouring case's general balance starts from (1.5 where it
    cannot be had)."""
    k = nmodel.contact_stiffness(res.normal, case.material, res.geometry)
    ns = res.normal
    v = k * ns.penetration / ns.normal_force if ns.normal_force > 0 else math.nan
    return v if math.isfinite(v) and v > 0 else 1.5


def _load_factor(geom, ratio) -> float:
    """F_z/F_n of a patch with lateral force ratio F_y/F_n: cos d - ratio sin d."""
    return math.cos(geom.contact_angle) - ratio * math.sin(geom.contact_angle)


def solve_wheel_rail(case, nmodel, tmodel, kw, max_iter: int = 40, rtol: float = 1e-4,
                      start=None, options: BalanceOptions | None = None):
    """Patches of a wheel-rail case with the vertical wheel load met per side.

    The balance of each wheel's vertical force, normal plus tangential contact
    forces of the case's models, with its load is solved by
    :func:`railcontact.cases.equilibrium.balance` on the evaluations of
    :class:`WheelRailContact` (the sides' interpenetrations the unknowns), from the
    geometry layer's multi-Hertzian estimate or, where ``start`` (the
    :class:`SolveResult` of a neighbouring case) is given, from its
    interpenetrations and its Jacobian; ``options`` (:class:`BalanceOptions`;
    default :data:`DEFAULT_OPTIONS`) says how.  Returns the patch results, the
    final contact search and the :class:`VerticalBalance`.
    """
    opt = DEFAULT_OPTIONS if options is None else options
    compiled = compiled_start(case, nmodel, tmodel, start) if opt.compiled_start else None
    # the exact models (a lazy tangential model: its stand-in balance), coupled or not
    hertz = (opt.compiled_start and compiled is None
             and tmodel is not None and "lazy" in tmodel.capabilities
             and not opt.force_control)
    if hertz and start is None:
        compiled = hertz_estimate(case)
    evaluate = WheelRailContact(case, nmodel, tmodel, kw, start, compiled,
                                opt.extrapolate_ratio)
    restarted = 0
    hertz_jac = None
    if hertz and start is None and compiled is not None:
        hertz_jac = _start_jacobian(case, compiled, evaluate.sides)
    if hertz and start is not None and compiled is None and RESTART_MISS > 0:
        compiled, hertz_jac = _hertz_restart(evaluate, start)
        restarted = int(compiled is not None)
    fc = None
    if opt.force_control and evaluate.lazy and "force-control" in nmodel.capabilities \
            and "warm-start" in tmodel.capabilities \
            and "contact-stiffness" in nmodel.capabilities:
        fc = _force_controlled(evaluate, rtol)
    if fc is not None:
        results, contact, balance = fc
    else:
        jac = start.balance.jacobian if start is not None and start.balance is not None \
            else None
        if compiled is not None:
            jac = compiled.jacobian if hertz_jac is None else hertz_jac
        ev, balance = solve_balance(evaluate, evaluate.start(), evaluate.loads, rtol,
                                    max_iter - restarted, jacobian=jac)
        balance.passes += restarted             # the evaluation before the restart
        balance.standin = evaluate.standin
        results, contact = ev.results, ev.contact
    if start is not None and start.contact is not None and start.contact.interpenetration:
        balance.neighbour = Neighbour(dict(start.contact.interpenetration),
                                      start.contact.pose.roll, dict(start.contact.loads or {}))
    ws = case.wheel_rail
    if ws.roll is None:
        held = search_memo(*evaluate.bodies, ws.lateral_shift, ws.yaw)
        if held is not None:
            balance.search = (float(ws.lateral_shift), float(ws.yaw), held.copy())
    side = case.wheel_rail.side
    wheel_rail_validity(results, evaluate.bodies)      # both wheels: either may derail
    if side != "both":
        other = [r for r in results if r.geometry.side != side]
        results = [r for r in results if r.geometry.side == side]
        if results:
            _report_other_wheel(results[0], other)
    if not results:
        raise ContactNotFoundError("no loaded contact patch found")
    return results, contact, balance


def _report_other_wheel(first, other) -> None:
    """A derailment or flange climb of the wheel not reported (``wheelset.side``)
    carried by the first reported patch's validity: a case is no solution where
    either wheel stands on its flange tip."""
    parts = [(f"the {r.geometry.side} wheel (not reported)", r.validity) for r in other
             if r.validity is not None and (not r.validity.converged or r.validity.warnings)]
    if parts:
        first.validity = SolverStatus.combine([("", first.validity), *parts])
