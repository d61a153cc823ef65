"""The vertical balance as a nonlinear system (railcontact.cases.equilibrium), on synthetic
force functions: smooth, coupled through the roll, steep, nearly flat, with jumps,
with provisional evaluations; one side (brentq) and both (Broyden)."""

import math
from dataclasses import dataclass

import numpy as np
import pytest

from railcontact.cases.equilibrium import (EXTRAPOLATE_BEND, EXTRAPOLATE_BEND_DEPTH,
                                          EXTRAPOLATE_ROLL, JUMP_SLOPE, VerticalBalance, balance,
                                          extrapolate_start)

SIDES = ("left", "right")
Q = {"left": 6e4, "right": 5e4}
#: the interpenetrations [m] at which the synthetic forces below meet the loads
ROOT = {"left": 8e-5, "right": 1.2e-4}


@dataclass
class Ev:
    forces: dict
    final: bool
    d: dict
    uncertainty: dict | None = None


class Forces:
    """A synthetic contact evaluation: ``force(d)`` -> {side: F [N]}; ``standin(d)``
    (optional) the provisional forces with their uncertainty (relative to the load).
    Records every call."""

    def __init__(self, force, standin=None):
        self.force, self.standin, self.calls = force, standin, []

    def __call__(self, d, final=False):
        self.calls.append((dict(d), final))
        if self.standin is not None and not final:
            f, unc = self.standin(d)
            return Ev(f, False, dict(d), unc)
        return Ev(self.force(d), True, dict(d))


def hertz(d, sides=SIDES, exponent=1.5):
    """F_s = Q_s (d_s / ROOT_s)^exponent."""
    return {s: Q[s] * (d[s] / ROOT[s]) ** exponent for s in sides}


def rolled(d, c=0.4, steep=1.0):
    """Coupled through the roll: each side's approach (relative to the root) is its
    relative interpenetration times the other's to the power -c (a deeper other side
    turns the wheelset away from it), Hertz's force on that; the right side's force
    to the power ``steep`` (flange contact)."""
    rl, rr = d["left"] / ROOT["left"], d["right"] / ROOT["right"]
    return {"left": Q["left"] * (rl * rr ** -c) ** 1.5,
            "right": Q["right"] * (rr * rl ** -c) ** (1.5 * steep)}


def start(factor_left, factor_right=None):
    f = {"left": factor_left, "right": factor_right if factor_right is not None else factor_left}
    return {s: ROOT[s] * f[s] for s in SIDES}


def residual(ev):
    return max(abs(ev.forces[s] / Q[s] - 1.0) for s in ev.forces)


@pytest.mark.parametrize("factor", [0.5, 0.97, 1.4, 3.0])
def test_smooth_hertzian_forces(factor):
    """Hertz's force meets the load from starts 0.5-3 times the root: Newton on
    ln F = 1.5 ln d + const is exact in one step, then the check."""
    ev, bal = balance(Forces(hertz), start(factor), Q, 1e-6)
    assert bal.converged and not bal.force_jump and isinstance(bal, VerticalBalance)
    assert residual(ev) <= 1e-6
    assert bal.passes <= 3
    assert bal.residual == pytest.approx({s: ev.forces[s] / Q[s] - 1 for s in SIDES})
    for s in SIDES:
        assert ev.d[s] == pytest.approx(ROOT[s], rel=1e-6)
    assert bal.status.converged and bal.status.iterations == bal.passes


@pytest.mark.parametrize("exponent", [1.1, 1.8, 3.0])
def test_other_exponents(exponent):
    """A force other than Hertz's (conformal contact, several patches): Broyden's
    update learns the slope; superlinear convergence to 1e-8."""
    ev, bal = balance(Forces(lambda d: hertz(d, exponent=exponent)), start(0.7, 1.3), Q, 1e-8)
    assert bal.converged and residual(ev) <= 1e-8
    assert bal.passes <= 8
    assert np.all(np.abs(np.diag(bal.jacobian) - exponent) < np.abs(1.5 - exponent) + 1e-12)


@pytest.mark.parametrize("c, steep", [(0.1, 1.0), (0.6, 1.0), (0.15, 10.0)])
def test_coupled_through_the_roll(c, steep):
    """Each side's force depends on the other's interpenetration (up to 0.6 times
    as much as on its own; the right side steep as flange contact, where on the
    benchmark sweep d ln F_r / d ln d = 15.8 and d ln F_r / d ln d_l = -2.2): the
    Jacobian's off-diagonal terms learn it (in ln F and ln d this force is linear:
    Broyden meets it in at most 2n + 1 steps)."""
    f = Forces(lambda d: rolled(d, c, steep))
    ev, bal = balance(f, start(1.2, 0.8), Q, 1e-8)
    assert bal.converged and residual(ev) <= 1e-8
    assert bal.passes <= 6 if steep == 1 else 12
    assert bal.jacobian[0, 1] < 0 and bal.jacobian[1, 0] < 0


def test_steep_force():
    """A side whose force grows as d^20 (flange contact where the lateral creep
    force nearly cancels the vertical component of the normal force), started 2.5
    times too deep (F 10^8 Q) and 20 % too shallow: the clipped steps and the
    bracket bring it in."""
    for factor in (2.5, 0.8):
        f = Forces(lambda d: {"left": hertz(d)["left"],
                              "right": Q["right"] * (d["right"] / ROOT["right"]) ** 20})
        ev, bal = balance(f, start(1.1, factor), Q, 1e-4)
        assert bal.converged and residual(ev) <= 1e-4
        assert bal.passes <= 14


def test_nearly_flat_force():
    """A force that hardly grows with the interpenetration (d ln F / d ln d = 0.05):
    after the first step Broyden's slope is small and the steps are clipped to a
    factor 5; met all the same."""
    f = Forces(lambda d: {s: Q[s] * (d[s] / ROOT[s]) ** 0.05 for s in SIDES})
    ev, bal = balance(f, start(1.0 / 30.0, 12.0), Q, 1e-4)
    assert bal.converged and residual(ev) <= 1e-4
    steps = [abs(math.log(b[0]["left"] / a[0]["left"])) for a, b in zip(f.calls, f.calls[1:])]
    assert max(steps) <= math.log(5.0) + 1e-12


def jumping(size=0.3, at=1.0):
    """Hertz's force on the right side scaled by 1 - size/2 below ``at`` times its
    root and by 1 + size/2 above (a step of ``size`` times the load; the load falls
    into it where ``at`` is 1)."""
    def force(d):
        f = hertz(d)
        f["right"] *= 1.0 + (0.5 if d["right"] >= at * ROOT["right"] else -0.5) * size
        return f
    return force


def test_a_jump_across_the_load_stops_with_the_evaluation_nearest_it(caplog):
    """The right side's force jumps from 1 to 1.3 times the load at its root: no
    interpenetration meets the load.  The iteration stops once the bracket shows a
    slope above JUMP_SLOPE and returns the final evaluation nearest the load (the
    left side balanced), flagged; a warning says so."""
    import logging
    f = Forces(jumping(0.3))
    with caplog.at_level(logging.INFO, logger="railcontact.cases.equilibrium"):
        ev, bal = balance(f, start(0.9, 1.2), Q, 1e-4)
    assert not bal.converged and bal.force_jump
    assert "jumps across the load" in bal.status.message
    assert any("jumps across the load" in r.getMessage() for r in caplog.records)
    assert abs(ev.forces["left"] / Q["left"] - 1) <= 1e-4
    near = min(residual(Ev(jumping(0.3)(c[0]), True, {})) for c in f.calls)
    assert residual(ev) == pytest.approx(near)
    # the bracket narrowed until the secant across it exceeded JUMP_SLOPE: the last
    # points below and above the root lie within 0.3 / JUMP_SLOPE (ln d)
    right = sorted(math.log(c[0]["right"] / ROOT["right"]) for c in f.calls)
    below = max(x for x in right if x < 0)
    above = min(x for x in right if x >= 0)
    assert above - below <= 0.3 / JUMP_SLOPE
    assert bal.passes <= 20


def test_a_jump_on_one_side_holds_it_at_the_edge_and_balances_the_other():
    """The right side's force jumps across its load while the left side's depends
    on the right's interpenetration (the roll): the right side is held at the edge of
    its jump nearest the load and the left side balanced with it; the result is
    that evaluation."""
    def force(d):
        f = rolled(d, 0.3)
        f["right"] *= 0.8 if d["right"] < ROOT["right"] else 1.3
        return f
    ev, bal = balance(Forces(force), start(1.1, 0.9), Q, 1e-6)
    assert bal.force_jump and not bal.converged
    assert abs(ev.forces["left"] / Q["left"] - 1) <= 1e-6
    assert ev.forces["right"] / Q["right"] - 1 == pytest.approx(-0.2, abs=0.02)
    assert bal.residual["left"] == pytest.approx(ev.forces["left"] / Q["left"] - 1)


def test_a_failed_evaluation_halves_the_step():
    """Where the contact cannot be evaluated (a model raises, as Hertz does on a
    concave patch), the step is halved; an evaluation that keeps failing raises."""
    from railcontact.core.errors import InputError

    def force(d):
        if d["right"] > 1.3 * ROOT["right"]:
            raise InputError("relative curvature B < 0")
        return hertz(d)
    f = Forces(force)
    ev, bal = balance(f, start(1.0, 0.45), Q, 1e-6)      # the first step goes to 2.2
    assert bal.converged and residual(ev) <= 1e-6
    begin = start(1.5)

    def only_at_the_start(d):
        if d != begin:
            raise InputError("relative curvature B < 0")
        return hertz(d)
    f = Forces(only_at_the_start)
    with pytest.raises(InputError, match="curvature"):
        balance(f, dict(begin), Q, 1e-6)
    assert len(f.calls) == 7                # the start, the step and five halvings


def test_a_jump_beside_the_load_is_no_obstacle():
    """A jump of the force that does not cross the load (the root, at 1.11 times the
    interpenetration where Hertz's force met it, lies below the jump at 1.3) is
    passed: the load is met."""
    ev, bal = balance(Forces(jumping(0.3, at=1.3)), start(0.9, 1.5), Q, 1e-6)
    assert bal.converged and not bal.force_jump and residual(ev) <= 1e-6


def test_out_of_passes():
    """With too few passes the result is the final evaluation nearest the load,
    flagged unconverged (no jump)."""
    ev, bal = balance(Forces(lambda d: rolled(d, 0.3, 3.0)), start(3.0, 0.5), Q, 1e-10,
                      max_passes=3)
    assert not bal.converged and not bal.force_jump and bal.passes == 3
    assert "not met after 3 passes" in bal.status.message


def test_provisional_evaluations_then_final():
    """Provisional forces off by 0.5 % with an uncertainty of 1 %: the steps use them
    until they are within their uncertainty (or the last step's contraction
    predicts it); from then on every evaluation is final, and only a final one
    meets the load."""
    def standin(d):
        f = hertz(d)
        return {s: 1.005 * f[s] for s in SIDES}, {s: 0.01 for s in SIDES}
    f = Forces(hertz, standin)
    ev, bal = balance(f, start(0.6, 1.5), Q, 1e-6)
    assert bal.converged and ev.final and residual(ev) <= 1e-6
    kinds = [final for _, final in f.calls]
    first = kinds.index(True)
    assert first >= 1 and all(kinds[first:])             # provisional, then final only
    assert bal.passes == len(f.calls) <= 5
    # the first final evaluation was at a point where the provisional forces were
    # within their uncertainty, or the last step's contraction predicted it
    assert residual(Ev(hertz(f.calls[first][0]), True, {})) <= 0.03


def test_a_provisional_evaluation_within_tolerance_is_evaluated_again():
    """A provisional evaluation that meets the load is evaluated again, as final, at
    the same interpenetrations (where the evaluation may reuse its work); the first
    evaluation is at the start exactly as given (not exp(ln d), which may differ in
    the last bit, so that the evaluation may reuse the search it started from)."""
    def standin(d):
        return hertz(d), {s: 0.0 for s in SIDES}
    f = Forces(lambda d: {s: 1.00001 * v for s, v in hertz(d).items()}, standin)
    begin = {"left": 7.015463661686019e-05, "right": 1.2e-4}   # exp(ln d) != d
    ROOT_saved = dict(ROOT)
    try:
        ROOT.update(begin)
        ev, bal = balance(f, dict(begin), Q, 1e-4)
    finally:
        ROOT.update(ROOT_saved)
    assert bal.converged and [c[1] for c in f.calls] == [False, True]
    assert f.calls[0][0] == f.calls[1][0] == begin
    with pytest.raises(Exception, match="expected interpenetrations > 0"):
        balance(f, {"left": 0.0, "right": 1e-4}, Q, 1e-4)


def test_bad_evaluations_are_named():
    """A start that is no interpenetration, or an evaluation that returns no finite
    force, is an error naming what was given (no silent NaN steps)."""
    from railcontact.core.errors import ConvergenceError, InputError
    with pytest.raises(InputError, match="expected interpenetrations > 0"):
        balance(Forces(hertz), {"left": -1e-5, "right": 1e-4}, Q, 1e-4)
    with pytest.raises(ConvergenceError, match="contact evaluation .* gave the forces"):
        balance(Forces(lambda d: {"left": math.nan, "right": 1.0}), start(1.0), Q, 1e-4)


def test_warm_jacobian():
    """Started from the Jacobian of a neighbouring case (here the exact one), the
    coupled balance takes fewer passes than from Hertz's 1.5 I."""
    c = 0.6
    cold_f, warm_f = Forces(lambda d: rolled(d, c)), Forces(lambda d: rolled(d, c))
    _, cold = balance(cold_f, start(1.1, 0.9), Q, 1e-8)
    _, warm = balance(warm_f, start(1.1, 0.9), Q, 1e-8, jacobian=cold.jacobian)
    assert cold.converged and warm.converged
    assert warm.passes < cold.passes
    # a Jacobian without a positive diagonal is not used (Hertz's instead)
    _, bad = balance(Forces(hertz), start(1.5), Q, 1e-6, jacobian=-np.eye(2))
    assert bad.converged and bad.passes <= 3


# ------------------------------------------------------------------ one side
def one(force):
    return lambda d: {"right": force(d["right"])}


@pytest.mark.parametrize("factor", [0.3, 0.99, 4.0])
def test_one_side_smooth(factor):
    """One side (the roll given): secant steps to a sign change, then brentq; a
    start off by a factor 0.3-4 meets the load."""
    f = Forces(one(lambda d: Q["right"] * (d / ROOT["right"]) ** 1.7))
    ev, bal = balance(f, {"right": factor * ROOT["right"]}, {"right": Q["right"]}, 1e-8)
    assert bal.converged and abs(ev.forces["right"] / Q["right"] - 1) <= 1e-8
    assert bal.jacobian is None and bal.passes <= 8
    assert set(bal.residual) == {"right"}


def test_one_side_jump():
    """One side whose force jumps across the load: brentq is interrupted where its
    bracket shows the jump; the evaluation nearest the load is returned."""
    def force(d):
        return Q["right"] * (d / ROOT["right"]) ** 1.5 * (1.1 if d >= ROOT["right"] else 0.9)
    f = Forces(one(force))
    ev, bal = balance(f, {"right": 0.5 * ROOT["right"]}, {"right": Q["right"]}, 1e-4)
    assert bal.force_jump and not bal.converged
    assert abs(ev.forces["right"] / Q["right"] - 1) == pytest.approx(
        min(abs(force(c[0]["right"]) / Q["right"] - 1) for c in f.calls))
    assert bal.passes <= 16


def test_one_side_provisional():
    """One side with provisional forces 2 % off (uncertainty 3 %): the provisional
    root, then final evaluations only."""
    def force(d):
        return Q["right"] * (d / ROOT["right"]) ** 1.5
    f = Forces(one(force), lambda d: ({"right": 1.02 * force(d["right"])}, {"right": 0.03}))
    ev, bal = balance(f, {"right": 2.0 * ROOT["right"]}, {"right": Q["right"]}, 1e-7)
    assert bal.converged and ev.final
    kinds = [final for _, final in f.calls]
    assert not kinds[0] and all(kinds[kinds.index(True):])


def test_extrapolate_start_linear_and_in_log():
    """A chain's start: one step of the last two cases' interpenetrations, linear
    (2 d1 - d0) or in ln d (d1^2 / d0), and the roll's, where the two differ by less
    than the factor (ratio 1: off) and the rolls by less than EXTRAPOLATE_ROLL."""
    d1, d0 = {"left": 1.1e-4, "right": 2.0e-4}, {"left": 1.0e-4, "right": 1.8e-4}
    d, roll, done = extrapolate_start(d1, d0, 2.0, 1e-4, 0.5e-4)
    assert done and d == {"left": 2.0 * 1.1e-4 - 1.0e-4, "right": 2.0 * 2.0e-4 - 1.8e-4}
    assert roll == pytest.approx(1.5e-4, rel=1e-12)
    d, _, _ = extrapolate_start(d1, d0, 1.2, in_log=True)
    assert d["left"] == pytest.approx(1.21e-4, rel=1e-12)
    assert d["right"] == pytest.approx(4e-4 / 1.8, rel=1e-12)
    # off: a side beyond the factor, ratio 1, no case before, none > 0 there
    for before, ratio in ((d0, 1.05), (d0, 1.0), (None, 2.0), ({"left": 0.0, "right": 1e-4}, 2.0)):
        d, roll, done = extrapolate_start(d1, before, ratio, 1e-4, 0.0)
        assert not done and d is d1 and roll == 1e-4
    # the roll kept where the two rolls differ by more than EXTRAPOLATE_ROLL
    _, roll, done = extrapolate_start(d1, d0, 2.0, 1e-4, 1e-4 - 2 * EXTRAPOLATE_ROLL)
    assert done and roll == 1e-4


def test_final_jacobian_floors_the_diagonal():
    """The final evaluations start from the provisional Jacobian with each diagonal
    entry at least FINAL_SLOPE (1.5 I where that leaves no positive determinant)."""
    from railcontact.cases import equilibrium as E
    assert E.FINAL_SLOPE == 1.0
    J = np.array([[0.25, 0.1], [-0.2, 2.0]])
    assert np.allclose(E._final_jacobian(J), [[1.0, 0.1], [-0.2, 2.0]])
    assert np.allclose(E._final_jacobian(np.array([[0.2, 3.0], [3.0, 0.2]])), 1.5 * np.eye(2))


def test_a_flat_provisional_force_does_not_overshoot_the_final_step(monkeypatch):
    """Provisional forces flat in d (slope 0.25, as on a flange's flat stretch) and 2 %
    above the final ones at their root: the provisional steps learn that slope, and
    the first final step from a residual of -0.12 in ln F takes it to 1.81 of the
    load without the floor, 1.43 with FINAL_SLOPE = 1."""
    from railcontact.cases import equilibrium as E

    def standin(d):
        return ({s: 1.02 * Q[s] * (d[s] / ROOT[s]) ** 0.25 for s in SIDES},
                {s: 1e-3 for s in SIDES})
    peak = {}
    for floor in (0.0, 1.0):
        monkeypatch.setattr(E, "FINAL_SLOPE", floor)
        f = Forces(hertz, standin)
        ev, bal = balance(f, start(0.8), Q, 1e-4)
        assert bal.converged and ev.final and residual(ev) <= 1e-4
        peak[floor] = max(max(hertz(d)[s] / Q[s] for s in SIDES) for d, fin in f.calls if fin)
    assert peak[0.0] > 1.7 and peak[1.0] < 1.5


def test_one_side_floors_the_final_slope_too(monkeypatch):
    """The one-sided balance (a prescribed roll: every .inp wheel-rail case) on the
    flat provisional force above: the first final step takes the right wheel to 1.81
    of its load without FINAL_SLOPE's floor, 1.06 with it (measured)."""
    from railcontact.cases import equilibrium as E

    def standin(d):
        return ({s: 1.02 * Q[s] * (d[s] / ROOT[s]) ** 0.25 for s in d}, {s: 1e-3 for s in d})
    peak = {}
    for floor in (0.0, 1.0):
        monkeypatch.setattr(E, "FINAL_SLOPE", floor)
        f = Forces(lambda d: hertz(d, tuple(d)), standin)
        ev, bal = balance(f, {"right": 0.8 * ROOT["right"]}, {"right": Q["right"]}, 1e-4)
        assert bal.converged and ev.final and residual(ev) <= 1e-4
        peak[floor] = max(hertz(d, tuple(d))["right"] / Q["right"] for d, fin in f.calls if fin)
    assert peak[0.0] > 1.7 and peak[1.0] < 1.2


def test_extrapolate_start_not_where_the_last_three_bend():
    """With the case before the two (``older``): no extrapolation where a side's
    second difference exceeds EXTRAPOLATE_BEND times its last step and
    EXTRAPOLATE_BEND_DEPTH times its interpenetration (a chain turning at a peak,
    the flange's 957, 1060, 1109 um of the benchmark sweep); a straight or gently
    curving chain, and a bend small against the interpenetration, extrapolate as
    without it."""
    d1, d0 = {"left": 84.5e-6, "right": 1109.3e-6}, {"left": 84.2e-6, "right": 1060.0e-6}
    peak = {"left": 84.0e-6, "right": 957.0e-6}
    d, roll, done = extrapolate_start(d1, d0, 1.2, 1e-3, 1.2e-3, in_log=True, older=peak)
    assert not done and d is d1 and roll == 1e-3
    # the flange's approach (437, 574, 708 um): a bend of 2.7 um, extrapolated
    d, _, done = extrapolate_start({"left": 83.9e-6, "right": 707.7e-6},
                                   {"left": 83.8e-6, "right": 573.8e-6}, 2.0, in_log=True,
                                   older={"left": 83.7e-6, "right": 437.2e-6})
    assert done and d["right"] == pytest.approx(707.7e-6 ** 2 / 573.8e-6, rel=1e-12)
    # each bound alone does not stop it (bends of 5 um on a step of 1 um at 1 mm, of
    # 20 um on a step of 100 um); both do (50 um on 100 um)
    last = {"right": 1.0e-3}
    assert EXTRAPOLATE_BEND * 1e-6 < 5e-6 < EXTRAPOLATE_BEND_DEPTH * 1e-3
    assert extrapolate_start(last, {"right": 0.999e-3}, 1.2, older={"right": 1.003e-3})[2]
    assert EXTRAPOLATE_BEND_DEPTH * 1e-3 < 2e-5 < EXTRAPOLATE_BEND * 1e-4
    assert extrapolate_start(last, {"right": 0.9e-3}, 1.2, older={"right": 0.82e-3})[2]
    assert not extrapolate_start(last, {"right": 0.9e-3}, 1.2, older={"right": 0.85e-3})[2]
    # without the case before (the case layer's chains): as before
    assert extrapolate_start(d1, d0, 1.2, in_log=True)[2]
