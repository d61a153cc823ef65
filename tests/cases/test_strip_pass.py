"""railcontact.cases.strip_pass: the strip models and their creep forces on a patch
row of the compiled pass agree with the batch path on the same patches, and their
force is continuous in the approach (the compiled balance meets the load)."""

import dataclasses
import math

import numpy as np
import pytest

import railcontact as rc
from railcontact.cases.batch import solve_patches
from railcontact.cases.compiled_case import (RF, case_contact, case_pass_inputs,
                                             evaluate_wheelset, solve_case_forces)
from railcontact.cases.strip_pass import strip_pass, strip_row
from railcontact.core.materials import STEEL
from railcontact.geometry.wheel_pass import new_memo

PAIRS = [("kik-piotrowski", "fastsim-strips"), ("analyn", "fastsim-strips"),
         ("kpec", "fastsim"), ("stripes", "polach")]


def _case(shift, yaw=0.0, creepage=(1e-3, -5e-4, 0.1)):
    return rc.case_from_dict({
        "wheel": {"profile": "S1002"}, "rail": {"profile": "60E1"},
        "wheelset": {"lateral_shift": shift, "yaw": yaw, "vertical_force": 7e4,
                     "velocity": 30.0},
        "creepage": dict(zip(("longitudinal", "lateral", "spin"), creepage)),
        "solver": {"grid": [40, 40]}})


@pytest.mark.parametrize("normal, tangential", PAIRS)
def test_rows_agree_with_the_batch_path(normal, tangential):
    """A balanced case's rows against :func:`solve_patches` on the same patches (the
    geometry objects of the rows with the case's creepages, 40 strips, 40
    elements): the same kernels, the strips laid on the patch's run (the compiled
    pass) or on the geometry's extent (the batch): F_n within 0.5 %, the creep
    forces within 1 % of mu F_n."""
    case = _case(3e-3, 2e-3)
    res = solve_case_forces(case, normal, tangential)
    assert res.converged
    geos = case_contact(res, case).patches
    assert len(geos) == len(res.rows)
    for geo in geos:
        row = min(res.rows, key=lambda r: abs(r[RF["y_rail"]] - geo.y_rail))
        geo = dataclasses.replace(geo, creepage=tuple(case.creepage))
        b = solve_patches([geo], normal, tangential, STEEL, 0.3, (40, 40), strips=40)
        F = row[RF["normal_force"]]
        assert F == pytest.approx(b.normal_force[0], rel=5e-3)
        assert abs(row[RF["fx"]] - b.Fx[0]) <= 1e-2 * 0.3 * F
        assert abs(row[RF["fy"]] - b.Fy[0]) <= 1e-2 * 0.3 * F


@pytest.mark.parametrize("normal", ["kik-piotrowski", "analyn"])
def test_force_continuous_in_the_interpenetration(normal):
    """On S1002/60E1's near-conformal tread (2.1 mm, 2 mrad: a flat-bottomed gap
    whose deepest strip moves between neighbours) the wheel's vertical force grows
    continuously with the interpenetration: each step (0.2 % of the force) within
    5 % of the one before (before the strips were laid on the run's ends and KP's
    displacement taken at the deepest point between strips: steps up to 2.5 times
    their neighbours, and the balance stopped at a force jump)."""
    case = _case(2.108e-3, 2e-3)
    prof, pose, model, loads = case_pass_inputs(case, normal, "fastsim-strips")
    res = solve_case_forces(case, normal, "fastsim-strips")
    assert res.converged
    d0 = np.array([res.interpenetration["left"], res.interpenetration["right"]])
    out = np.zeros_like(res.rows, shape=(16, res.rows.shape[1]))
    fz = np.empty(2)
    forces = []
    for s in np.linspace(0.985, 1.015, 25):
        d = d0.copy()
        d[1] *= s
        m, z, roll = evaluate_wheelset(prof, pose, model, d, new_memo(res.roll), out, fz)
        forces.append(fz[1])
    steps = np.diff(forces)
    assert np.all(steps > 0)
    # each step within 5 % of the one before (a jump of the force doubles a step)
    assert np.max(np.abs(steps[1:] / steps[:-1] - 1.0)) < 0.05


def test_creep_force_continuous_where_the_deepest_sample_moves():
    """The 1000-case sweep's case 7.38 mm / 6 mrad (its creepages), KP +
    fastsim-strips: on its deep flange patch the row's approach (the gap at the
    locus's deepest sample) jumps by 0.58 um between 289.66 and 289.69 um of the
    right wheel's interpenetration, as that sample passes to the next; the local
    ellipses of fastsim-strips take the deepest strip's interpenetration, so F_y
    and the vertical force do not jump with it: each step within 10 % of the first
    (before: the last step 2.8 times the others, F_y up 23 N, and the balance
    stopped at a force jump across the load, 999 of 1000 met).  The case meets its
    load."""
    j = 968
    case = _case(float(np.linspace(-4e-3, 9e-3, 250)[j - 750]), 6e-3,
                 (1.5e-3 * math.sin(2 * math.pi * j / 97), 1e-3 * math.cos(2 * math.pi * j / 61),
                  0.2 * math.sin(2 * math.pi * j / 43)))
    res = solve_case_forces(case, "kik-piotrowski", "fastsim-strips")
    assert res.converged
    prof, pose, model, loads = case_pass_inputs(case, "kik-piotrowski", "fastsim-strips")
    out = np.zeros((16, res.rows.shape[1]))
    fz = np.empty(2)
    forces = []
    for dr in np.linspace(289.40e-6, 289.69e-6, 11):
        evaluate_wheelset(prof, pose, model, np.array([8.6126e-5, dr]), new_memo(-7.08e-3),
                          out, fz)
        forces.append(fz[1])
    steps = np.diff(forces)
    assert np.all(steps > 0)
    assert np.max(np.abs(steps / steps[0] - 1.0)) < 0.1


def test_hertz_code_and_strip_pass_of_names():
    sp = strip_pass("hertz", "fastsim", STEEL)
    assert sp.rule.code == -1
    sp = strip_pass("kpec", "fastsim-strips", STEEL, 30, 25, 12)
    assert sp.rule.code >= 0 and sp.grid.strips == 30 and sp.rule.elements == 25
    assert sp.elements == 12 and sp.march == 2 and sp.grid.refine


def test_no_approach_gives_no_force():
    case = _case(0.0)
    res = solve_case_forces(case, "analyn", "fastsim-strips")
    prof, pose, model, _ = case_pass_inputs(case, "analyn", "fastsim-strips")
    row = res.rows[0].copy()
    row[RF["approach"]] = 0.0
    assert strip_row(row, prof, pose, res.vertical, res.roll, model) == (0.0,) * 8
    assert math.isfinite(res.patches["fy"][0])


@pytest.mark.parametrize("normal", ["analyn", "kik-piotrowski"])
def test_warm_start_lays_the_same_strips(normal):
    """:func:`strip_row_ends` from the run's ends of an earlier evaluation (the
    online dynamics' warm start) lays the strips the cold path lays: from the
    ends moved out by 2 % and 5 % of the run's width and in by 2 % and 20 %, the
    warm start is kept, the ends are found again to 1e-8 m and the forces equal
    the cold path's to 1e-9 (the ends' tolerance, 1e-9 m; measured 1e-12); from
    ends off the patch or outside the cold path's first window (out by 20 %: the
    region's extent widened by 15 % of its half-width), the cold path (the same
    numbers)."""
    from railcontact.cases.strip_pass import strip_row_ends
    case = _case(4e-3, 2e-3)
    res = solve_case_forces(case, normal, "fastsim-strips")
    prof, pose, model, _ = case_pass_inputs(case, normal, "fastsim-strips")
    for row in res.rows:
        cold = np.full(3, np.nan)
        ref = strip_row_ends(row.copy(), prof, pose, res.vertical, res.roll, model, cold)
        assert ref[0] > 0 and cold[2] == 0.0 and cold[1] > cold[0]
        assert ref == strip_row(row.copy(), prof, pose, res.vertical, res.roll, model)
        width = cold[1] - cold[0]
        for out in (0.02, 0.05, -0.02, -0.2):
            ends = np.array([cold[0] - out * width, cold[1] + out * width, np.nan])
            got = strip_row_ends(row.copy(), prof, pose, res.vertical, res.roll, model, ends)
            assert ends[2] == 1.0
            assert ends[:2] == pytest.approx(cold[:2], abs=1e-8)
            for a, b in zip(got, ref):
                assert a == pytest.approx(b, rel=1e-9, abs=1e-9 * ref[0])
        for lo, hi in ((cold[1] + 2 * width, cold[1] + 3 * width),
                       (cold[0] - 0.2 * width, cold[1] + 0.2 * width)):
            ends = np.array([lo, hi, np.nan])
            got = strip_row_ends(row.copy(), prof, pose, res.vertical, res.roll, model, ends)
            assert ends[2] == 0.0 and got == ref
