"""railcontact.cases.compiled_case: a whole wheel-rail case in one compiled pass
meets the loads and agrees with the per-patch path (railcontact.solve)."""

import numpy as np
import pytest

import railcontact as rc
from railcontact.cases.compiled_case import (CaseForces, compiled_unsupported,
                                             solve_case_forces)


def _case(shift, yaw=0.0, creepage=None, **extra):
    raw = {"wheel": {"profile": "S1002"}, "rail": {"profile": "60E1"},
           "wheelset": {"lateral_shift": shift, "yaw": yaw, "vertical_force": 7e4,
                        "velocity": 30.0, **extra},
           "solver": {"grid": [40, 40]}}
    if creepage:
        raw["creepage"] = dict(zip(("longitudinal", "lateral", "spin"), creepage))
    return rc.case_from_dict(raw)


def _side_sums(sides, values):
    return {s: sum(v for t, v in zip(sides, values) if t == s) for s in ("left", "right")}


# tread contact, tread with yaw and given creepages, two-point and flange contact
@pytest.mark.parametrize("shift, yaw, creepage", [(0.0, 0.0, None),
                                                  (3e-3, 2e-3, (1e-3, -5e-4, 0.1)),
                                                  (5.5e-3, 0.0, None),
                                                  (8e-3, 4e-3, None)])
def test_loads_met_and_forces_of_the_per_patch_path(shift, yaw, creepage, **extra):
    case = _case(shift, yaw, creepage, **extra)
    res = solve_case_forces(case)
    assert res.converged and res.load_residual() <= case.force_tolerance
    ref = rc.solve(case, "hertz", "fastsim")
    assert ref.converged
    assert len(res.side) == len(ref.patches)
    q = 7e4
    fn = _side_sums(res.side, res.patches["normal_force"])
    fy = _side_sums(res.side, res.patches["fy"])
    fx = _side_sums(res.side, res.patches["fx"])
    for s in ("left", "right"):
        p = [r for r in ref.patches if r.geometry.side == s]
        # both balances meet the load to 1e-4: F_n within twice that of Q; the creep
        # forces differ by FASTSIM on the ellipse against FASTSIM on Hertz's grid
        assert abs(fn[s] - sum(r.normal.normal_force for r in p)) <= 2e-4 * q
        assert abs(fy[s] - sum(r.tangential.fy for r in p)) <= 1e-3 * 0.3 * q
        assert abs(fx[s] - sum(r.tangential.fx for r in p)) <= 1e-3 * 0.3 * q
        assert res.interpenetration[s] == pytest.approx(ref.contact.interpenetration[s],
                                                        rel=2e-4)


def test_the_load_is_met_where_the_deepest_points_curvature_jumps():
    # at 6.3 mm the deepest point of the right wheel's flange-root patch crosses a
    # joint of the profiles' arcs (its curvature B: 12 to 3.5 1/m) and, at a deeper
    # interpenetration, leaves the rail (0.05 1/m): with B alone the Hertzian force
    # jumped across the load there (28 to 232 kN) and both balances stopped (force
    # jump); the force's curvature (geometry.wheel_pass.force_curvature) is the
    # region's there, continuous, and both meet the load and agree as on the tread
    test_loads_met_and_forces_of_the_per_patch_path(6.3e-3, 0.0, None)


def test_a_neighbour_starts_the_balance():
    a, b = _case(2.0e-3, 2e-3), _case(2.05e-3, 2e-3)
    first = solve_case_forces(a)
    cold, warm = solve_case_forces(b), solve_case_forces(b, start=first)
    assert cold.converged and warm.converged
    assert warm.passes <= cold.passes
    for s in ("left", "right"):
        assert warm.interpenetration[s] == pytest.approx(cold.interpenetration[s], rel=2e-4)


def test_the_per_patch_balance_starts_from_the_compiled_one():
    res = rc.solve(_case(4e-3, 2e-3), "hertz", "fastsim")
    # the compiled balance's interpenetrations meet the loads with the case's own
    # models in the first pass (FASTSIM on the grid differs little from the ellipse)
    assert res.converged and res.balance.passes == 1


def test_unsupported_cases_say_why():
    assert "exact" in compiled_unsupported(_case(0.0), "exact", "exact")
    assert "online law" in compiled_unsupported(_case(0.0), "hertz", "fastrip")
    case = _case(0.0, roll=0.0, side="right")
    assert "roll" in compiled_unsupported(case)
    with pytest.raises(ValueError, match="roll"):
        solve_case_forces(case)
    # out-of-round wheels are not in the compiled pass (its loci are those of round
    # wheels): never silently ignored
    assert "out-of-round" in compiled_unsupported(_case(0.0, pitch=0.01))


@pytest.mark.parametrize("shift, yaw", [(3e-3, 4e-3), (6e-3, 6e-3)])
def test_contact_locus_loads_met_and_forces_of_the_per_patch_path(shift, yaw, monkeypatch):
    # CONTACT's locus (wheelset.locus = "contact", every .inp case's) runs in the
    # pass: the per-patch path's own balance (not started from the pass) agrees as
    # with the lowest points
    from railcontact.cases import balance
    assert compiled_unsupported(_case(shift, yaw, locus="contact")) is None
    monkeypatch.setattr(balance, "DEFAULT_OPTIONS", balance.BalanceOptions(compiled_start=False))
    test_loads_met_and_forces_of_the_per_patch_path(shift, yaw, None, locus="contact")
    lowest = solve_case_forces(_case(shift, yaw))
    contact = solve_case_forces(_case(shift, yaw, locus="contact"))
    assert not np.allclose(lowest.patches["y_rail"], contact.patches["y_rail"], rtol=0,
                           atol=5e-9)


def test_to_xarray_has_the_patches():
    res = solve_case_forces(_case(1e-3))
    assert isinstance(res, CaseForces)
    ds = res.to_xarray()
    assert ds.sizes["patch"] == len(res.side) >= 2
    assert ds["normal_force"].attrs["units"] == "N"
    assert np.all(ds["pmax"].values > 0)


def test_a_far_neighbour_still_gives_the_case():
    # a chain's jump (the next block of a sweep): the neighbour's start and wheel
    # samples do not serve; the case is solved again cold where they fail
    far = solve_case_forces(_case(9e-3, 2e-3))
    res = solve_case_forces(_case(-4e-3, 4e-3), start=far)
    cold = solve_case_forces(_case(-4e-3, 4e-3))
    assert res.converged and cold.converged
    for s in ("left", "right"):
        assert res.interpenetration[s] == pytest.approx(cold.interpenetration[s], rel=2e-4)


def test_the_first_estimate_uses_the_balances_force_curvature():
    # on S1002/60E1's tread (two minima of the gap: the force curvature is the
    # region's, not the deepest point's) the first estimate carries the load by the
    # balance's own model: its evaluation lies within 2 % of the load (a median 9 % of
    # it over the benchmark sweep with the deepest point's curvature, 0.9 % now), and
    # its slope d ln F / d ln d is the
    # force's (above Hertz's 1.5 where the region's curvature falls as it widens)
    from railcontact.cases import compiled_case as cc
    from railcontact.geometry.wheel_pass import new_memo
    case = _case(1.221e-3)
    prof, pose, model, loads = cc.case_pass_inputs(case)
    memo, d, slope = new_memo(0.0), np.empty(2), np.empty(2)
    assert cc.first_estimate(prof, pose, model, loads, memo, d, slope)
    out, fz = np.zeros((2 * cc.MAX_PATCHES, cc.NRF)), np.empty(2)
    cc.evaluate_wheelset(prof, pose, model, d.copy(), memo, out, fz)
    assert np.all(np.abs(fz / loads - 1) < 0.02)
    assert 1.5 <= slope[1] <= 2.5
    res = solve_case_forces(case)
    assert res.converged and res.passes <= 3


@pytest.mark.parametrize("yaw", [0.0, 2e-3])
def test_flange_root_cases_converge_in_few_passes(yaw):
    # 6.29-6.39 mm: the flange and its root share the right wheel's load; the
    # deepest point's vertical interpenetration moves with the pose at a rate that
    # jumps between the two, so that its force is S-shaped in it (9-12 passes
    # before, measured); the pose's Newton steps (compiled_case.pose_newton) take
    # at most 7, cold and from the neighbouring case, and meet the load as the
    # per-patch path does
    prev = solve_case_forces(_case(6.233e-3, yaw))
    for shift in (6.285e-3, 6.337e-3, 6.390e-3):
        case = _case(shift, yaw)
        cold = solve_case_forces(case)
        warm = solve_case_forces(case, start=prev)
        assert cold.converged and warm.converged
        assert cold.passes <= 7 and warm.passes <= 7
        assert cold.interpenetration["right"] == pytest.approx(
            warm.interpenetration["right"], rel=2e-3)
        prev = warm


def test_the_pose_steps_solve_the_patches_by_the_strip_model():
    # the balance's Newton steps on the pose (compiled_case.evaluate_pose) solve
    # each patch by the case's model: with a strip model every row carries the
    # strip model's force (strip_row), not Hertz's (before: Hertz's, so that the
    # strip cases were balanced on Hertz's force: KP + fastsim-strips 69973 N on
    # a patch the strip model gives 73948 N), and the balanced pose meets the
    # loads by the strip model
    from railcontact.cases import compiled_case as cc
    from railcontact.cases.strip_pass import strip_row
    from railcontact.geometry.wheel_pass import LOCUS_MARGIN, new_memo
    case = _case(3e-3, 2e-3, (1e-3, -5e-4, 0.1))
    res = solve_case_forces(case, "kik-piotrowski", "fastsim-strips")
    assert res.converged
    prof, pose, model, loads = cc.case_pass_inputs(case, "kik-piotrowski", "fastsim-strips")
    zr = np.array([res.vertical, res.roll])
    d = np.array([res.interpenetration["left"], res.interpenetration["right"]])
    out, fz, depth = np.zeros((2 * cc.MAX_PATCHES, cc.NRF)), np.empty(2), np.empty(2)
    m = cc.evaluate_pose(prof, pose, model, zr, d + LOCUS_MARGIN, new_memo(res.roll), out,
                         fz, depth)
    assert m > 0
    hertz_off = 0.0
    for row in out[:m]:
        F = strip_row(row.copy(), prof, pose, zr[0], zr[1], model)[0]
        assert row[cc.R_NORMAL_FORCE] == pytest.approx(F, rel=1e-12)
        hertz_off = max(hertz_off, abs(cc.patch_hertz(row, model)[2] / F - 1.0))
    assert hertz_off > 0.01             # the strip model's force is not Hertz's here
    assert np.all(np.abs(fz / loads - 1.0) <= 2 * case.force_tolerance)


def _sweep_case(j):
    """Case j of the benchmark's 1000-case sweep (benchmarks/run_all.sweep_raws)."""
    import math
    iy, k = divmod(j, 250)
    return _case(-4e-3 + 13e-3 * k / 249, 2e-3 * iy,
                 (1.5e-3 * math.sin(2 * math.pi * j / 97), 1e-3 * math.cos(2 * math.pi * j / 61),
                  0.2 * math.sin(2 * math.pi * j / 43)))


#: the path before the handling of joining regions (``solve_case_forces(case,
#: joins=False)`` on afa9b5a, the switch since removed): balance passes and roll-search
#: evaluations of the benchmark sweep's cases 203 and 949, measured
BEFORE_JOINS = {203: (18, 68), 949: (6, 67)}


def test_joining_regions_take_fewer_passes_and_roll_evaluations():
    # the benchmark sweep's slowest cases, where the flange root joins: 6.60 mm
    # (the estimate 0.32 of the load without the creep forces' share, 18 passes
    # before), 6.39 mm at 6 mrad (the roll search missed the flange's minimum and
    # cycled: 67 evaluations before); with the handling of joining regions 10 passes
    # and 24 evaluations (measured); the forces those of the per-patch path
    # (rc.solve, its own balance and search) to the tolerances of the tread cases
    for j, passes, gaps in ((203, 11, 50), (949, 8, 35)):
        case = _sweep_case(j)
        new = solve_case_forces(case)
        old_passes, old_gaps = BEFORE_JOINS[j]
        assert new.converged and new.load_residual() <= 1e-4
        assert new.passes <= passes < old_passes or new.gap_evaluations <= gaps < old_gaps
        ref = rc.solve(case, "hertz", "fastsim")
        assert ref.converged
        for name, scale, tol in (("normal_force", 7e4, 2e-4), ("fy", 0.3 * 7e4, 1e-3)):
            a = _side_sums(new.side, new.patches[name])
            b = _side_sums([p.geometry.side for p in ref.patches],
                           [p.normal.normal_force if name == "normal_force" else p.tangential.fy
                            for p in ref.patches])
            for s in ("left", "right"):
                assert abs(a[s] - b[s]) <= tol * scale


def test_the_flange_force_has_no_sawtooth_in_the_interpenetration():
    """At 6.76 mm / 0 mrad (Hertz, the right wheel on its flange, some 350 um of
    approach) the vertical force fell by 1.8 % of Q every ~23 um of interpenetration
    where the locus's deepest sample passed to the next (the approach taken at that
    sample: 1.4 um lost at each step).  The deepest point is now the locus's minimum
    between the samples (geometry.patch_curvature.deepest_fraction): over 30 um the
    right wheel's vertical force rises monotonically, its steps within 20 % of
    their mean."""
    from railcontact.cases import compiled_case as cc
    from railcontact.geometry.wheel_pass import MAX_PATCHES, new_memo
    case = _case(6.755e-3, 0.0, (3.8e-4, 2.6e-5, 0.0))
    res = solve_case_forces(case)
    assert res.converged
    prof, pose, model, loads = cc.case_pass_inputs(case)
    memo = new_memo(res.roll)
    out = np.zeros((2 * MAX_PATCHES, cc.NRF))
    fz = np.zeros(2)
    dl, dr = res.interpenetration["left"], res.interpenetration["right"]
    force = []
    for d in np.linspace(dr - 15e-6, dr + 15e-6, 31):
        cc.evaluate_wheelset(prof, pose, model, np.array([dl, d]), memo, out, fz)
        force.append(fz[1] / loads[1])
    steps = np.diff(force)
    assert np.all(steps > 0.0)
    assert np.max(np.abs(steps / steps.mean() - 1.0)) < 0.2


#: the extrapolated start before the bend's test (equilibrium.EXTRAPOLATE_BEND),
#: measured on the chains below: balance passes and roll-search evaluations of the
#: last case
BEFORE_BEND = {206: (9, 19), 455: (9, 33)}


@pytest.mark.parametrize("j", [206, 455])
def test_a_warm_chain_past_the_flanges_peak_starts_from_the_last_case(j):
    # 6.76 mm / 0 mrad and 6.70 mm / 2 mrad of the benchmark sweep, warm from the
    # four cases before: the right wheel's interpenetration peaks there (1060, 1109,
    # then 1006 um; 755, 799, then 796 um), the start extrapolated in ln d from the
    # last two lay 15 % and 6 % off (where the vertical force is flat in it, d ln F /
    # d ln d some 0.5: 3 % of the load), and the pose's steps, then the steps on the
    # interpenetrations with a roll search each, took 9 passes; the chain's last
    # three interpenetrations bend there, so the start is the last case's own
    from railcontact.cases.equilibrium import extrapolate_start
    prev = None
    for i in range(j - 4, j + 1):
        before = prev
        prev = solve_case_forces(_sweep_case(i), start=prev)
        assert prev.converged and prev.load_residual() <= 1e-4
    nb = before.neighbour
    _, _, done = extrapolate_start(before.interpenetration, nb.interpenetration, 1.2,
                                   in_log=True, older=nb.before)
    assert nb.before is not None and not done
    passes, gaps = BEFORE_BEND[j]
    assert prev.passes <= 5 < passes and prev.gap_evaluations <= 8 < gaps
    cold = solve_case_forces(_sweep_case(j))
    assert cold.converged
    assert prev.interpenetration["right"] == pytest.approx(cold.interpenetration["right"],
                                                           rel=2e-3)


def test_the_linear_law_runs_in_the_pass():
    """Hertz + ``linear`` in the compiled pass is Kalker's linear theory, not FASTSIM
    (the law's code 0 once read as "none" and the pass ran FASTSIM under the linear
    law's name): the creep forces agree with the per-patch path's linear theory to
    1 % (the same theory on the ellipse of the row against that of Hertz's grid)
    and, at these creepages below saturation, differ from FASTSIM's by more than
    2 %."""
    case = _case(3e-3, 2e-3, (1e-3, -5e-4, 0.1))
    lin = solve_case_forces(case, "hertz", "linear")
    fs = solve_case_forces(case, "hertz", "fastsim")
    ref = rc.solve(case, "hertz", "linear")
    assert lin.converged and fs.converged and ref.converged
    for key, attr in (("fx", "fx"), ("fy", "fy")):
        got = _side_sums(lin.side, lin.patches[key])
        other = _side_sums(fs.side, fs.patches[key])
        for s in ("left", "right"):
            want = sum(getattr(r.tangential, attr) for r in ref.patches if r.geometry.side == s)
            assert got[s] == pytest.approx(want, rel=1e-2)
            assert abs(got[s] - other[s]) > 2e-2 * abs(want)
