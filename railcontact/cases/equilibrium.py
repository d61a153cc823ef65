"""The vertical balance of a wheelset as a small nonlinear system: :func:`balance`.

The unknowns are the vertical interpenetrations d_s of the wheels (s = left, right;
one wheel where the roll is given), the equations that the vertical force F_s(d)
each wheel exerts on its rail, normal and tangential contact forces of the case's
models, equals its load Q_s.  The forces come from a callable, the contact
evaluation (:class:`railcontact.cases.balance.WheelRailContact` builds it
from the contact search and the models), so that the method itself knows
nothing of profiles or solvers.

Both wheels: safeguarded Broyden steps
--------------------------------------
In the logarithms v_s = ln d_s the residuals r_s(v) = ln(F_s / Q_s) are nearly
linear: Hertz's F ~ d^1.5 gives r_s = 1.5 v_s + const.  Each pass takes the Newton
step of the linear model r + J dv = 0, J from 1.5 I (or a neighbouring case's) and
Broyden's ("good") rank-one update after every step (Broyden 1965; Dennis &
Schnabel 1996, ch. 8), each component clipped to a factor ``STEP_FACTOR`` of the
interpenetration.  The wheels are coupled through the roll (a deeper flange turns
the wheelset, which moves the other wheel's contact): J's off-diagonal terms learn
that.  An update that would give J an entry above ``JUMP_SLOPE`` (a step across a
jump) is not made; J without a positive diagonal and determinant is set back to
1.5 I.

The safeguard is a bracket per side: of the side's points of the history whose
residual's sign the other side's difference from the step could not flip (at most
``COUPLING_SLOPE`` times that difference), the nearest below the load and the
nearest above.  Where the Newton step of a side leaves its bracket, or the last two
steps did not halve the side's residual, the side is bisected in its bracket
(Brent's safeguard of the secant method).

A model's force may jump across the load (a strip entering the contact of a strip
model, the deepest point passing between two minima of the gap for Hertz).  A side
off the load whose bracket at the present point has its residual growing faster
than ``JUMP_SLOPE`` times ln d between its ends (the other side moving less) jumps:
by the mean-value theorem no continuous force of smaller slope has such a bracket.
It is held at the edge of the jump nearest its load and the other side balanced
with it; the iteration then stops with that evaluation (``force_jump``).  Where the
contact cannot be evaluated at a step (a model raises, as Hertz does where the
deepest point of a patch lies on a concave part of a profile), the step is halved.

Provisional and final evaluations
---------------------------------
An evaluation may be provisional: the callable may stand in for the lateral forces
(the tangential problems not solved), and says so by its ``final`` flag and by how
far off the load that may put each side (``uncertainty``, relative to the load).
The rule: steps may be taken from provisional evaluations, the load is met only by
a final one.  The next evaluation is final where the last step's contraction,
applied once more, predicts each side within the tolerance or its uncertainty
(r_k^2 / |r_(k-1)| below it, or r_k itself: a side already within it whose
residual grew by the other side's step); a provisional evaluation within them, or whose
brackets show a jump, is evaluated again as final at the same interpenetrations.
From then on every evaluation is final, with the Jacobian learnt and the history
started afresh (a provisional point's residual is no bound of a final one's).

One wheel (the roll given)
--------------------------
A scalar root: secant steps on r(v) from the start (slope 1.5, or the neighbour's,
before the second point) until the residual changes sign, then
:func:`scipy.optimize.brentq` on the bracket, on the residual with a dead zone of
the tolerance (brentq stops at the first point within it, where the residual is
0), interrupted where its bracket shows a jump; the provisional/final rule as for
both wheels.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from ..core.checks import shown
from ..core.errors import ConvergenceError, InputError, RailContactError
from ..core.status import SolverStatus

log = logging.getLogger(__name__)

#: d(ln F)/d(ln d) of Hertz's force, F ~ d^1.5: the Jacobian the steps start from
HERTZ_SLOPE = 1.5

#: a step changes a side's interpenetration by at most this factor
STEP_FACTOR = 5.0

#: a side's force that grows across the bracket of its load faster than this in
#: proportion to its interpenetration, d(ln F)/d(ln d), with both ends off the load,
#: jumps across it (Hertz: 1.5): by the mean-value theorem no force of smaller slope
#: has such a bracket (the slopes met: docs/tuning.md, section "Equilibrium")
JUMP_SLOPE = 100.0

#: the largest rate at which a wheel's force changes with the other wheel's
#: interpenetration, |d(ln F_s)/d(ln d_o)| (the roll moves the tread's contact; the
#: rates met: docs/tuning.md, section "Equilibrium"): a point of a side's history
#: brackets its load at other interpenetrations of the other side only where its
#: residual exceeds this times their difference
COUPLING_SLOPE = 10.0

#: the final evaluations (the tangential problems solved) start from the provisional
#: steps' Jacobian with each diagonal entry at least this, d(ln F)/d(ln d) (Hertz's):
#: on a flange's flat stretch the provisional steps learn a slope of 0.2-0.3, and the
#: first final step from a stand-in error of some 9 % of the load then overshoots
#: it 25-fold (docs/tuning.md, section "Equilibrium"); one side (a prescribed roll)
#: floors its secant slope alike; 0 turns it off
FINAL_SLOPE = 1.0

#: forces below this fraction of the load count as this fraction (ln 0 = -inf)
FORCE_FLOOR = 1e-6

#: a chain of cases' start (:func:`extrapolate_start`) extrapolates the roll where
#: its last two cases' rolls differ by less than this [rad]
EXTRAPOLATE_ROLL = 1e-3
#: a chain's start is not extrapolated where, the case before its last two known too
#: (``older`` of :func:`extrapolate_start`), a side's three interpenetrations bend: their
#: second difference larger than ``EXTRAPOLATE_BEND`` times the last step and than
#: ``EXTRAPOLATE_BEND_DEPTH`` times the last interpenetration (a chain turning at a
#: peak, where one step on overshoots: docs/tuning.md, section "Equilibrium", the
#: warm chain's bends)
EXTRAPOLATE_BEND = 0.35
EXTRAPOLATE_BEND_DEPTH = 1e-2


@dataclass
class Neighbour:
    """A neighbouring case's balance, where the next case of a sweep or time history
    starts: the one record of the case layer's balance
    (:attr:`VerticalBalance.neighbour`) and the compiled pass
    (:attr:`railcontact.cases.compiled_case.CaseForces.neighbour`, the start of
    :func:`railcontact.cases.compiled_case.solve_case_forces`).

    Attributes
    ----------
    interpenetration : dict
        The vertical interpenetration [m] of each side.
    roll : float
        The wheelset's roll [rad] (NaN: not known).
    loads : dict or None
        The vertical load [N] of each side (None: not kept).
    jacobian : ndarray or None
        The balance's d(ln F)/d(ln d) at the end (None: not kept).
    vertical : float
        The wheelset's vertical position [m] (NaN: not kept).
    before : dict or None
        The interpenetrations [m] of the case this neighbour itself started from
        (None: not kept; the compiled pass's chains keep it, ``older`` of
        :func:`extrapolate_start`).
    """

    interpenetration: dict
    roll: float
    loads: dict | None = None
    jacobian: np.ndarray | None = field(default=None, repr=False)
    vertical: float = math.nan
    before: dict | None = None


def extrapolate_start(last: dict, before: dict | None, ratio: float, roll: float = math.nan,
                      roll_before: float = math.nan, in_log: bool = False,
                      older: dict | None = None):
    """A chain of cases' start: the interpenetrations [m] of its last two cases
    extrapolated by one step, where they differ by less than the factor ``ratio``
    on every side (smooth neighbours; ``ratio`` <= 1 turns it off), and the roll
    [rad] too where the two rolls differ by less than ``EXTRAPOLATE_ROLL``.

    Parameters
    ----------
    last, before : dict
        Each side's interpenetration [m] of the last case and of the one before it
        (None: no case before; then no extrapolation).
    ratio : float
        The largest factor between the two cases' interpenetrations on a side.
    roll, roll_before : float
        The two cases' rolls [rad] (NaN: not known; not extrapolated).
    in_log : bool
        Extrapolate ln d (d_last^2 / d_before) rather than d (2 d_last - d_before):
        the compiled pass's rule; the case layer's is linear (docs/tuning.md,
        section "Equilibrium", on why each).
    older : dict, optional
        Each side's interpenetration [m] of the case before ``before`` (the compiled
        pass's chains keep it): no extrapolation where a side's three bend, its
        second difference |d_last - 2 d_before + d_older| above both
        ``EXTRAPOLATE_BEND`` |d_last - d_before| and ``EXTRAPOLATE_BEND_DEPTH``
        d_last.

    Returns
    -------
    dict, float, bool
        The interpenetrations [m] and roll [rad] to start from, and whether they
        were extrapolated (else ``last`` and ``roll`` as given).
    """
    if before is None or not all(before.get(s, 0.0) > 0.0 and last[s] > 0.0 for s in last):
        return last, roll, False
    limit = math.log(ratio) if ratio > 0.0 else -math.inf
    if not all(abs(math.log(last[s] / before[s])) < limit for s in last):
        return last, roll, False
    if older is not None:
        for s in last:
            if older.get(s, 0.0) > 0.0:
                bend = abs(last[s] - 2.0 * before[s] + older[s])
                if bend > EXTRAPOLATE_BEND * abs(last[s] - before[s]) and \
                        bend > EXTRAPOLATE_BEND_DEPTH * last[s]:
                    return last, roll, False
    if in_log:
        d = {s: last[s] * last[s] / before[s] for s in last}
    else:
        d = {s: 2.0 * last[s] - before[s] for s in last}
    if math.isfinite(roll_before) and abs(roll - roll_before) < EXTRAPOLATE_ROLL:
        roll = 2.0 * roll - roll_before
    return d, roll, True


@dataclass
class VerticalBalance:
    """How the vertical balance of a wheel-rail case ended (:func:`balance`).

    Attributes
    ----------
    converged : bool
        Whether each side's vertical force met its load to ``solver.force_tolerance``.
    force_jump : bool
        Whether the iteration stopped where the model's vertical force jumps across
        the load (a strip entering the contact): then no interpenetration carries it.
    passes : int
        How many times the contact was evaluated (each a contact search and the
        patches' normal problems, or the tangential problems of the last one).
    residual : dict
        Relative residual (F_z - Q)/Q [-] of each side's balance.
    standin : list of PatchResult or None
        FASTSIM's patch results (on the normal solutions of the last provisional
        evaluation) whose F_y stood in for the lateral forces.
    jacobian : ndarray or None
        The last Broyden Jacobian d(ln F)/d(ln d) (sides in the order of
        ``residual``), from which a neighbouring case may start.
    neighbour : Neighbour or None
        Where the balance started from a neighbouring case: that case's
        interpenetrations, roll and loads (:class:`Neighbour`), from which the next
        case of a sweep extrapolates its start (:func:`extrapolate_start`).
    search : tuple or None
        (lateral shift [m], yaw [rad], memo) of the case's last compiled contact
        search (:func:`railcontact.geometry.search.search_memo`), from which a
        neighbouring case's searches start (None: not kept).
    """

    converged: bool
    force_jump: bool
    passes: int
    residual: dict
    standin: list | None = field(default=None, repr=False)
    jacobian: np.ndarray | None = field(default=None, repr=False)
    neighbour: Neighbour | None = field(default=None, repr=False)
    search: tuple | None = field(default=None, repr=False)

    @property
    def status(self) -> SolverStatus:
        """The balance as a :class:`SolverStatus` (iterations: the passes)."""
        if self.converged:
            return SolverStatus(True, "", self.passes)
        worst = max(abs(v) for v in self.residual.values()) if self.residual else math.nan
        why = ("the model's vertical force jumps across the load" if self.force_jump
               else f"not met after {self.passes} passes")
        return SolverStatus.failed(f"{why}; the wheel load is missed by {worst:.2g} of it",
                                   self.passes)


class _Track:
    """The evaluations of one balance: residuals, history, passes, the best final."""

    def __init__(self, evaluate, sides, loads, tol, max_passes, start):
        self.evaluate, self.sides, self.tol, self.max_passes = evaluate, sides, tol, max_passes
        self.start = {s: float(start[s]) for s in sides}
        self.v0 = np.log([self.start[s] for s in sides])
        self.q = np.array([float(loads[s]) for s in sides])
        self.passes = 0
        self.final = False          # every evaluation from now on is final
        self.best = None            # (worst relative residual, evaluation) of the finals

    def __call__(self, v, final=False):
        """Evaluate at ln d = v; returns the evaluation and its residual ln(F/Q)."""
        # (the start as given: exp(ln d) may differ from d in the last bit)
        d = dict(self.start) if np.array_equal(v, self.v0) else {
            s: float(math.exp(x)) for s, x in zip(self.sides, v)}
        ev = self.evaluate(d, final=final or self.final)
        self.passes += 1
        self.last_v = v
        f = np.array([float(ev.forces[s]) for s in self.sides])
        if not np.all(np.isfinite(f)):
            raise ConvergenceError(f"vertical balance: the contact evaluation at the "
                                   f"interpenetrations {d} m gave the forces {list(f)} N")
        log.debug("balance pass %d: d %s, F/Q - 1 %s%s", self.passes, np.exp(v), f / self.q - 1,
                  "" if ev.final else " (provisional)")
        if ev.final:
            worst = self.worst(ev)
            if self.best is None or worst < self.best[0]:
                self.best = (worst, ev)
        return ev, np.log(np.maximum(f, FORCE_FLOOR * self.q) / self.q)

    def worst(self, ev) -> float:
        """The largest relative residual |F/Q - 1| of the sides of an evaluation."""
        return max(abs(float(ev.forces[s]) / float(q) - 1.0) for s, q in zip(self.sides, self.q))

    def limits(self, ev) -> np.ndarray:
        """Each side's limit of the relative residual: the tolerance, or, where
        ``ev`` is provisional, its uncertainty where that is larger."""
        unc = getattr(ev, "uncertainty", None) or {}
        return np.array([self.tol if ev.final else max(self.tol, float(unc.get(s, 0.0)))
                         for s in self.sides])

    def off(self, ev) -> np.ndarray:
        """Which sides miss the load by more than their limit (:meth:`limits`)."""
        f = np.array([float(ev.forces[s]) for s in self.sides])
        return np.abs(f / self.q - 1.0) > self.limits(ev)

    def make_final(self, v, ev, r):
        """Evaluate the point of the provisional ``ev`` again as final; from now on
        every evaluation is final."""
        self.final = True
        if not ev.final:
            ev, r = self(v, final=True)
        return ev, r


def balance(evaluate, start: dict, loads: dict, tol: float, max_passes: int = 40,
            jacobian=None):
    """Interpenetrations at which each side's vertical force meets its load.

    Parameters
    ----------
    evaluate : callable
        ``evaluate(d, final)`` with ``d`` the interpenetration [m] of each side
        (dict) returns an evaluation: any object with ``forces`` (dict, the vertical
        force [N] of each side) and ``final`` (bool: whether these are the forces of
        a result, e.g. with the tangential problems solved).  ``final=True`` asks for
        a final evaluation; at the interpenetrations of the last call it may reuse
        that call's work.
    start : dict
        The interpenetration [m] of each side to start from (> 0): both sides, or
        one (the roll given).
    loads : dict
        The vertical load [N] of each side of ``start``.
    tol : float
        Relative tolerance of the balance, |F/Q - 1| <= tol.
    max_passes : int
        Limit of evaluations.
    jacobian : ndarray, optional
        d(ln F)/d(ln d) to start from (a neighbouring case's,
        :attr:`VerticalBalance.jacobian`); default 1.5 I (Hertz).

    Returns
    -------
    evaluation, VerticalBalance
        The final evaluation that met the loads (else the final one nearest them)
        and how the iteration ended.
    """
    sides = tuple(start)
    if not all(math.isfinite(float(start[s])) and float(start[s]) > 0 for s in sides):
        raise InputError(f"balance start {shown(start)}: expected interpenetrations > 0 m")
    track = _Track(evaluate, sides, loads, tol, max_passes, start)
    v0 = track.v0
    jump = False
    if len(sides) == 1:
        jump = _scalar(track, v0, jacobian)
    else:
        J = np.asarray(jacobian, dtype=float) if jacobian is not None else None
        jump, J = _broyden(track, v0, J)
    if track.best is None:                   # out of passes before any final evaluation
        track(track.last_v, final=True)
    ev = track.best[1]
    residual = {s: float(ev.forces[s]) / float(q) - 1.0 for s, q in zip(sides, track.q)}
    converged = bool(track.best[0] <= tol)
    if not converged:
        log.info(
            "vertical force: %s; the evaluation nearest the load is %.2g of it off",
            "the model's force jumps across the load" if jump
            else f"not met to {tol:.0e} after {track.passes} passes", track.best[0])
    J_out = J if len(sides) > 1 else None
    return ev, VerticalBalance(converged, jump and not converged, track.passes, residual,
                               jacobian=J_out)


def _start_jacobian(n, J):
    """J where it has a positive diagonal and determinant, else 1.5 I."""
    if J is None or J.shape != (n, n) or not (np.all(np.diag(J) > 0) and np.linalg.det(J) > 0):
        return HERTZ_SLOPE * np.eye(n)
    return J.copy()


def _broyden(track, v, J):
    """The iteration for both sides (module docstring); returns (jump, J)."""
    n = v.size
    J = _start_jacobian(n, J)
    clip = math.log(STEP_FACTOR)
    ev, r = track(v)
    points = [(v, r)]               # the evaluations of the present fidelity
    prev_r = older_r = None         # the residuals one and two steps before
    held = {}                       # sides held at the edge of a jump: their ln d
    while True:
        off = track.off(ev)
        free = np.array([s not in held for s in range(n)])
        if not off[free].any():
            if not ev.final:                         # met by a provisional evaluation
                ev, r = track.make_final(v, ev, r)
                points, prev_r, older_r, held = [(v, r)], None, None, {}
                J = _final_jacobian(J)
                continue
            if off.any():                            # the others met, held at a jump:
                track.best = (track.worst(ev), ev)   # this evaluation is the result
            return bool(off.any()), J
        if track.passes >= track.max_passes:
            return False, J
        # a side off the load whose bracket (at the present point) shows a jump is
        # held at the edge of the jump nearest its load, the others balanced with it
        for s in np.flatnonzero(free & off):
            lo, hi = _bracket(points, s, v)
            if lo is not None and hi is not None and _jumps(*lo, *hi, s):
                held[s] = min(lo, hi, key=lambda e: abs(math.expm1(e[1][s])))[0][s]
        if held and not ev.final:
            # a jump of the provisional force: evaluated again with the final forces
            ev, r = track.make_final(v, ev, r)
            points, prev_r, older_r, held = [(v, r)], None, None, {}
            J = _final_jacobian(J)
            continue
        if held and all(s in held for s in np.flatnonzero(off)):
            return True, J                           # every side off the load jumps
        # the Newton step, safeguarded per free side by its bracket at the step
        cand = _newton(J, r, v, held, clip)
        for s in np.flatnonzero(np.array([s not in held for s in range(n)])):
            lo, hi = _bracket(points, s, cand)
            if lo is None or hi is None:
                continue
            # two steps that did not halve the side's residual: bisect (Brent's rule)
            slow = older_r is not None and off[s] and abs(r[s]) > 0.5 * abs(older_r[s])
            if slow or not lo[0][s] < cand[s] < hi[0][s]:
                cand[s] = 0.5 * (lo[0][s] + hi[0][s])
        # provisional steps end where the last step's contraction, applied once
        # more, predicts each side within its limit: the next evaluation is final
        # (a side within its limit counts as predicted within it: its residual may
        # have grown from a smaller one, by the other side's step)
        switch = not track.final and prev_r is not None and np.all(
            r * r <= track.limits(ev) * np.maximum(np.abs(prev_r), np.abs(r)))
        track.final = track.final or switch
        ev, r_new, cand = _trial(track, v, cand)
        if switch:
            points, prev_r, older_r = [], None, None    # afresh; J stays (floored)
            J = _final_jacobian(J)
        elif np.any(cand != v):
            # Broyden's update, except across a jump (it would leave J garbage)
            dv = cand - v
            new = J + np.outer(r_new - r - J @ dv, dv) / (dv @ dv)
            J = new if np.all(np.abs(new) <= JUMP_SLOPE) else J
            if not (np.all(np.diag(J) > 0) and np.linalg.det(J) > 0):
                J = HERTZ_SLOPE * np.eye(n)
        older_r, prev_r, v, r = prev_r, r, cand, r_new
        points.append((v, r))


def _final_jacobian(J):
    """The Jacobian the final evaluations start from: the provisional steps' with
    each diagonal entry at least ``FINAL_SLOPE`` (1.5 I where that leaves it
    without a positive determinant)."""
    if FINAL_SLOPE <= 0:
        return J
    out = J.copy()
    d = np.diag(out)
    np.fill_diagonal(out, np.maximum(d, FINAL_SLOPE))
    return out if np.linalg.det(out) > 0 else HERTZ_SLOPE * np.eye(J.shape[0])


def _newton(J, r, v, held, clip):
    """The Newton step of the linear model r + J dv = 0 from v, each component
    clipped to ``clip``, with the ``held`` sides (index: ln d) fixed."""
    cand = v + np.clip(np.linalg.solve(J, -r), -clip, clip)
    if held:
        h = np.array(sorted(held))
        f = np.array([s for s in range(v.size) if s not in held])
        dh = np.array([held[s] for s in h]) - v[h]
        cand[h] = v[h] + dh
        if f.size:
            step = np.linalg.solve(J[np.ix_(f, f)], -(r[f] + J[np.ix_(f, h)] @ dh))
            cand[f] = v[f] + np.clip(step, -clip, clip)
    return cand


def _trial(track, v, cand, halvings=5):
    """The evaluation at ``cand``; where the contact cannot be evaluated there (a
    model raises: a Hertzian patch with a concave curvature, say), the step from v
    is halved, up to ``halvings`` times.  Returns (evaluation, residual, point)."""
    for k in range(halvings + 1):
        try:
            ev, r = track(cand)
            return ev, r, cand
        except RailContactError as exc:
            if k == halvings or isinstance(exc, ConvergenceError):
                raise
            log.info("vertical balance: no evaluation at d %s (%s); the step halved",
                     np.exp(cand), exc)
            cand = v + 0.5 * (cand - v)


def _bracket(points, s, at):
    """Side ``s``'s bracket of the load at the other sides' coordinates of ``at``:
    the points (ln d of every side, residuals) nearest the load from below and above
    (None where there is none), counting only points whose residual's sign the
    other sides' difference from ``at`` cannot flip (``COUPLING_SLOPE``)."""
    lo = hi = None
    for p, q in points:
        moved = max((abs(p[o] - at[o]) for o in range(p.size) if o != s), default=0.0)
        if abs(q[s]) <= COUPLING_SLOPE * moved:
            continue
        if q[s] < 0 and (lo is None or p[s] > lo[0][s]):
            lo = (p, q)
        elif q[s] > 0 and (hi is None or p[s] < hi[0][s]):
            hi = (p, q)
    if lo is not None and hi is not None and hi[0][s] <= lo[0][s]:
        return None, None                   # not monotone on these points: no bracket
    return lo, hi


def _jumps(a, ra, b, rb, s) -> bool:
    """Whether side ``s`` jumps between the points a and b (ln d of every side) with
    residuals ra, rb: the slope of its residual between them exceeds
    ``JUMP_SLOPE`` while the other sides differ by less (so that no coupling below
    JUMP_SLOPE explains it)."""
    width = abs(b[s] - a[s])
    return abs(rb[s] - ra[s]) > JUMP_SLOPE * width and all(
        abs(b[o] - a[o]) <= width for o in range(a.size) if o != s)


class _Jump(Exception):
    """The bracket of a scalar balance shows a jump (ends :func:`brentq`)."""


def _scalar(track, v0, jacobian):
    """The iteration for one side (module docstring); returns whether it stopped at
    a jump."""
    slope = HERTZ_SLOPE
    if jacobian is not None and np.size(jacobian) == 1 and float(np.ravel(jacobian)[0]) > 0:
        slope = float(np.ravel(jacobian)[0])
    clip = math.log(STEP_FACTOR)
    evals = {}                      # ln d -> (evaluation, residual) of the present fidelity

    def at(x):
        if x not in evals:
            evals[x] = track(np.array([x]))
        return evals[x]

    def residual(x):
        """ln(F/Q), 0 where the load is met (brentq stops there); raises _Jump where
        the bracket shows a jump."""
        ev, r = at(x)
        if not track.off(ev)[0]:
            return 0.0
        below = [(p, float(q[0])) for p, (e, q) in evals.items() if q[0] < 0 and track.off(e)[0]]
        above = [(p, float(q[0])) for p, (e, q) in evals.items() if q[0] > 0 and track.off(e)[0]]
        if below and above:
            lo, hi = max(below), min(above)
            if lo[0] < hi[0] and _jumps(np.array([lo[0]]), np.array([lo[1]]),
                                        np.array([hi[0]]), np.array([hi[1]]), 0):
                raise _Jump
        return float(r[0])

    x = float(v0[0])
    while True:
        try:
            # secant steps from x until the residual meets the load or changes sign
            pts = [x]
            while residual(pts[-1]) != 0.0 and track.passes < track.max_passes and (
                    len(pts) < 2 or residual(pts[-1]) * residual(pts[-2]) > 0.0):
                if len(pts) >= 2:
                    secant = (residual(pts[-1]) - residual(pts[-2])) / (pts[-1] - pts[-2])
                    slope = secant if secant > 0 else slope
                pts.append(pts[-1] + min(max(-residual(pts[-1]) / slope, -clip), clip))
            x = pts[-1]
            if residual(x) != 0.0 and len(pts) >= 2 and residual(x) * residual(pts[-2]) < 0 \
                    and track.passes < track.max_passes:
                # Brent's method on the bracket, to a point that meets the load
                x, info = brentq(residual, min(x, pts[-2]), max(x, pts[-2]),
                                 xtol=track.tol / JUMP_SLOPE,
                                 maxiter=track.max_passes - track.passes, full_output=True,
                                 disp=False)
                if not info.converged:
                    return False                        # out of passes
            jump = residual(x) != 0.0
        except _Jump:
            jump = True
        if jump:                    # the evaluation nearest the load
            x = min(evals, key=lambda p: float(np.max(np.abs(np.expm1(evals[p][1])))))
        ev, r = at(x)
        if track.passes >= track.max_passes and track.off(ev)[0]:
            return False
        if ev.final:
            return jump
        # provisional: met, or a jump of the provisional force; evaluate it as final
        ev, r = track.make_final(np.array([x]), ev, r)
        evals = {x: (ev, r)}
        if FINAL_SLOPE > 0:
            slope = max(slope, FINAL_SLOPE)
        if not track.off(ev)[0]:
            return False
