"""The contact searched online in the dynamics (railcontact.dynamics.online_contact):
the Hertz springs' static equilibrium, the springs' stiffness, the
online run against the table run on tangent track, Nadal's limit in the results,
a flange climb to derailment, the scenario option and a strip model per patch."""

import math

import numpy as np
import pytest

from railcontact.core.errors import CaseFileError, InputError
from railcontact.dynamics import Integration, Route, VehicleModel, WheelRailTable, simulate_vehicle
from railcontact.dynamics.online_contact import OnlineWheelRail
from railcontact.dynamics.vehicle import G_ACC
from railcontact.geometry.validity import flange, nadal_limit
from railcontact.core.materials import STEEL

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def bodies():
    """S1002 on 60E1 1:40 (the wheel and rail of examples/dynamics_online.toml)."""
    from railcontact.inputs import load_dynamics_scenario
    sc = load_dynamics_scenario(ROOT / "examples" / "dynamics_online.toml")
    return sc.wheelset, sc.track


def _wheelset(**kw):
    return VehicleModel.from_parameters("wheelset", kw.pop("parameters", None))


def _loc(y, gap, theta):
    return (0, y.size, None, None, y, gap, np.full(y.size, math.tan(theta)), None, None,
            None)


def _spring(gap, y, theta, d):
    """spring_stiffness's exponent e (dN/d(delta) = e N / delta) of the region of
    ``gap`` below 0, at approach ``d`` [m]: the Hertz spring with the region's force
    curvature, as the online search makes it."""
    from railcontact.cases.compiled_case import hertz_patch
    from railcontact.dynamics.online_contact import spring_stiffness
    from railcontact.geometry.patch_curvature import force_curvature
    from railcontact.geometry.wheel_pass import NPF, P_A, P_APPROACH, P_B, P_B_FORCE
    loc = _loc(y, gap, theta)
    neg = np.flatnonzero(gap < 0)
    i0, i1 = int(neg[0]), int(neg[-1])
    im = int(np.argmin(gap))
    B = float(np.polyfit(y[im - 3:im + 4], gap[im - 3:im + 4], 2)[0]) * math.cos(theta) ** 3
    row = np.zeros(NPF)
    row[P_A], row[P_B], row[P_APPROACH] = 0.9, B, d
    row[P_B_FORCE] = force_curvature(loc, i0, i1, im, B)
    from railcontact.dynamics.online_contact import online_contact
    from railcontact.geometry import Track, Wheelset
    from railcontact.profiles import rail_profile, s1002
    model = online_contact(Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40))),
                           1).model
    _, _, F = hertz_patch(row[P_A], row[P_B_FORCE], d, model)
    k = spring_stiffness(loc, i0, i1, row, F, model, np.empty(gap.size))
    return k * d / F


def test_the_spring_of_a_hertzian_gap_has_hertz_stiffness():
    """For the gap g = -d + B y² the force curvature is B (the region's moment
    curvature of a paraboloid) at every depth, and the spring's stiffness is
    Hertz's 3/2 N / delta (to the trapezoidal moment: 1 %)."""
    d, B, theta = 8e-5, 3.5, 0.05
    y = np.arange(-0.01, 0.01 + 1e-9, 2e-4) + 3e-5           # not centred on a sample
    assert _spring(-d + B * y * y, y, theta, d * math.cos(theta)) == pytest.approx(1.5, rel=1e-2)


def test_a_region_that_widens_fast_stiffens_the_spring():
    """A gap g = -d + c |y|^1.5, whose region widens as d^(2/3), faster than a
    paraboloid's d^(1/2), has the region's curvature d / w^2 fall as d^(-1/3): the
    spring's exponent is above Hertz's 3/2 (the force's factor grows as the
    curvature falls; measured 1.562, the force curvature a blend with the deepest
    point's), stiffer than 3/2 N / delta: the stiffness that the online rk4 step
    follows (rk4_online)."""
    d, theta = 8e-5, 0.0
    c = d / 5e-3 ** 1.5
    y = np.arange(-0.01, 0.01 + 1e-9, 2e-4) + 3e-5
    assert 1.54 < _spring(-d + c * np.abs(y) ** 1.5, y, theta, d) < 1.8


def test_static_equilibrium_on_tangent_track(bodies):
    """A wheelset at rest on the centre of tangent track, on its Hertz springs: each
    wheel carries half the axle load (the supported mass times g) to 1e-4, and the
    wheelset sits at the geometry layer's vertical position for that load within
    the springs' difference (region against point curvature: 20 um)."""
    ws, tr = bodies
    m = _wheelset()
    ds = simulate_vehicle(m, Route.tangent(100.0), OnlineWheelRail(ws, tr), 20.0, 0.05,
                          "fastsim", 0.3, STEEL, 0.0, integration=Integration(sample_rate=200))
    axle = m.wheelsets[0][1] * G_ACC
    Q = ds["Q"].isel(time=-1, wheelset=0).values
    assert Q == pytest.approx([axle / 2, axle / 2], rel=1e-4)
    assert ds.attrs["contact_mode"] == "online" and ds.attrs["status"] == "completed"
    assert abs(float(ds["wheelset_roll"].isel(time=-1, wheelset=0))) < 1e-6
    from railcontact.geometry import find_contact
    c = find_contact(ws, tr, 0.0, 0.0, vertical_force=axle / 2)
    assert float(ds["wheelset_vertical"].isel(time=-1, wheelset=0)) == pytest.approx(
        c.pose.vertical, abs=2e-5)


def test_online_against_the_table_on_tangent_track(bodies):
    """The single wheelset let go 3 mm off centre on smooth tangent track, online
    against the contact table (built at yaw 0 at the static load): the wheel forces
    Q, Y, Fx, Fy differ by under 2 % of the static wheel load Q0 rms (measured
    0.45, 0.78, 0.52, 0.80 %), the lateral displacement by under 3 % of the table
    run's rms (measured 2.6 %).  Against their own rms the lateral forces differ
    more (Y 14 %): in the near-conformal tread contact the two paths' deepest
    points, and so the Hertz ellipses, differ (a, b = 4.55, 9.1 mm online against
    4.05, 8.2 mm in the table at rest), and with them the spin creep force
    (docs/dynamics.md, "Online contact")."""
    ws, tr = bodies
    m = _wheelset()
    load = m.wheelsets[0][1] * G_ACC / 2
    table = WheelRailTable.build(ws, tr, load, shift_range=0.006, step=2e-4)
    runs = [simulate_vehicle(m, Route.tangent(100.0), c, 30.0, 0.4, "fastsim", 0.3, STEEL,
                             0.003, integration=Integration(sample_rate=500))
            for c in (table, OnlineWheelRail(ws, tr, damping=6e5))]
    t, o = runs

    def rms(v):
        return float(np.sqrt(np.mean(v ** 2)))
    y_t, y_o = t["lateral_displacement"].values, o["lateral_displacement"].values
    assert rms(y_o - y_t) < 0.03 * rms(y_t)
    for name in ("Q", "Y", "longitudinal_force", "lateral_creep_force"):
        assert rms(o[name].values - t[name].values) < 0.02 * load, name


def test_nadal_limit_in_the_results(bodies):
    """Nadal's limit (tan b - mu) / (1 + mu tan b): 1.2 for EN 14363's 70 deg and
    mu = 0.36; the run's attribute is that of S1002's flange angle and its friction."""
    assert nadal_limit(math.radians(70.0), 0.36) == pytest.approx(1.2, abs=5e-3)
    ws, tr = bodies
    ds = simulate_vehicle(_wheelset(), Route.tangent(50.0), OnlineWheelRail(ws, tr), 20.0,
                          0.01, "fastsim", 0.4, STEEL, 0.0,
                          integration=Integration(sample_rate=200))
    beta = flange(ws.wheel("right")).max_angle
    t = math.tan(beta)
    assert ds.attrs["nadal_limit"] == pytest.approx((t - 0.4) / (1 + 0.4 * t), rel=1e-12)
    assert math.degrees(beta) == pytest.approx(70.0, abs=0.5)


def test_flange_climb_to_derailment(bodies):
    """A lightly loaded wheelset (20 kN per wheel) free laterally, into a 60 m
    curve without cant at 40 m/s (27 m/s² uncompensated), friction 0.5: the outer
    (left) wheel's Y/Q passes Nadal's limit (0.95), the wheel climbs its flange and
    stands on its tip; the run ends there and says so."""
    ws, tr = bodies
    m = VehicleModel.single_wheelset(k_y=0.0, k_yaw=20e6, wheel_load=20e3)
    route = Route.from_segments([{"type": "tangent", "length": 5.0},
                                 {"type": "transition", "length": 10.0},
                                 {"type": "curve", "radius": 60.0, "length": 200.0}])
    ds = simulate_vehicle(m, route, OnlineWheelRail(ws, tr, damping=6e5), 40.0, 1.5,
                          "fastsim", 0.5, STEEL, 0.0, integration=Integration(sample_rate=500))
    assert ds.attrs["status"] == "derailed"
    assert ds.attrs["derailment_wheelset"] == 1 and ds.attrs["derailment_side"] == "left"
    assert 0.2 < ds.attrs["derailment_time_s"] < 1.5
    assert float(ds["time"][-1]) <= ds.attrs["derailment_time_s"] + 2e-3
    assert "derailment at t = " in ds.attrs["warnings"] and "left wheel" in ds.attrs["warnings"]
    yq = float(np.nanmax(np.abs(ds["Y_over_Q"].sel(wheelset=1, side="left").values)))
    assert yq > ds.attrs["nadal_limit"]
    # the climbing wheel rose: the wheelset rolled, its left side up, by over 3 mm
    assert float(ds["wheelset_roll"].isel(time=-1, wheelset=0)) * 0.75 > 3e-3


def test_strip_model_per_patch_runs_online(bodies):
    """A strip model with fastsim-strips (ANALYN's patches, compiled:
    railcontact.cases.strip_pass) runs online: at rest its wheels carry the axle
    load within 1 % (the springs are the normal model's at the approach)."""
    ws, tr = bodies
    m = _wheelset()
    ds = simulate_vehicle(m, Route.tangent(50.0), OnlineWheelRail(ws, tr, normal="analyn"),
                          20.0, 2e-3, "fastsim-strips", 0.3, STEEL, 0.0,
                          integration=Integration(method="rk4", sample_rate=1000))
    axle = m.wheelsets[0][1] * G_ACC
    assert float(ds["Q"].isel(time=-1).sum()) == pytest.approx(axle, rel=1e-2)
    assert ds.attrs["tangential"] == "fastsim-strips"


@pytest.mark.parametrize("normal", ["analyn", "kik-piotrowski"])
def test_compiled_strips_equal_the_batch_on_the_searched_patches(bodies, normal):
    """The compiled strip model online (cases.strip_pass per row of the search)
    against the case layer's batch (cases.batch.solve_patches, the Python path of
    the online contact before) on the same patches, a wheelset 4 mm off centre with
    2 mrad yaw and creepages from its motion: normal forces within 0.5 %, creep
    forces within 1 % of mu N (the batch lays the strips on the geometry's extent,
    the pass on the patch's run)."""
    from railcontact.cases.batch import solve_patches
    from railcontact.dynamics.online_contact import (R_FX, R_FY, R_N, search_wheelset,
                                                     NPF)
    from railcontact.geometry.track import WheelsetPose
    from railcontact.geometry.wheel_pass import PassPose, patch_geometry
    ws, tr = bodies
    on = OnlineWheelRail(ws, tr, normal=normal)
    tp = np.array([0.3, STEEL.shear_modulus, 12, 12, 1.0, 1.0, 1.0, 0.0])
    oc = on.compiled(1, 1, tp, 1120.0, "fastsim-strips")
    g = oc.frame
    pose = PassPose(4e-3, 2e-3, g[0], g[1], g[2], g[3], 30.0, -30.0 / g[3], 0.02, 0.001, 0.0)
    from railcontact.geometry import find_contact
    c = find_contact(ws, tr, 4e-3, 2e-3, vertical_force=6e4)
    m = search_wheelset(oc, 0, pose, c.pose.vertical, c.pose.roll)
    assert m >= 2
    wp = WheelsetPose(4e-3, c.pose.vertical, c.pose.roll, 2e-3)
    rows = oc.rows[0, :m]
    geos = [patch_geometry(r[:NPF], ws, tr, wp) for r in rows]
    b = solve_patches(geos, normal, "fastsim-strips", STEEL, 0.3, (12, 12))
    for k, r in enumerate(rows):
        assert r[R_N] == pytest.approx(b.normal_force[k], rel=5e-3)
        assert abs(r[R_FX] - b.Fx[k]) <= 1e-2 * 0.3 * r[R_N]
        assert abs(r[R_FY] - b.Fy[k]) <= 1e-2 * 0.3 * r[R_N]


def _exact_system(bodies, stand_in="both"):
    """A wheelset on exact + exact online contact 2 mm off centre, at its static
    equilibrium, moving sideways at 0.05 m/s (creepages) at 20 m/s."""
    from railcontact.dynamics.simulation import _System, static_contact
    ws, tr = bodies
    m = _wheelset()
    sysm = _System(m, Route.tangent(50.0), OnlineWheelRail(ws, tr, normal="exact",
                                                           stand_in=stand_in), 20.0, "exact")
    u = np.zeros(sysm.n_states)
    u[0] = 2e-3
    u = static_contact(sysm, u)
    u[3 * len(m.bodies)] = 0.05
    return sysm, u


def test_exact_stand_ins_give_the_solution_where_they_were_corrected(bodies):
    """The compiled stand-ins of the Python path (exact + exact), corrected by a
    full evaluation (the exact problems solved, mode 1), give that evaluation's
    derivative again at the same state: Hertz's spring and FASTSIM (stand_in
    "both", mode 4: no solve) to rounding (1e-9 of the largest entry); FASTSIM at
    the normal solution's force ("tangential", mode 3: the normal problem solved
    again from its kept grid, to its tolerance 1e-5) within 1e-4.  A stage whose
    patch moved on the rail beyond its grid's element is solved in full (the
    corrections then renewed)."""
    from railcontact.dynamics.online_contact import C_YRAIL, G_MATCH, R_SFY, R_FY
    sysm, u = _exact_system(bodies)
    on = sysm.online
    sysm.rhs(0.0, u)
    full = sysm.rhs(0.0, u)           # (on the grids kept from the first)
    assert on.corrected[0] == on.count[0] >= 2
    # the correction is not nothing: exact F_y differs from FASTSIM's
    fy = on.rows[0, :on.count[0], R_FY]
    assert np.max(np.abs(fy - on.rows[0, :on.count[0], R_SFY])) > 1e-3 * np.max(np.abs(fy))
    stage = sysm.rhs(0.0, u, stage=True)
    assert on.frame[G_MATCH] == 1.0
    scale = np.max(np.abs(full))
    assert np.max(np.abs(stage - full)) <= 1e-9 * scale
    sysm.stand_in = "tangential"
    stage = sysm.rhs(0.0, u, stage=True)
    assert on.frame[G_MATCH] == 1.0
    assert np.max(np.abs(stage - full)) <= 1e-4 * scale
    sysm.stand_in = "both"
    y_rail = float(on.corrections[0, 0, C_YRAIL])
    on.corrections[0, 0, C_YRAIL] += 1e-3              # as if the patch had moved 1 mm
    stage = sysm.rhs(0.0, u, stage=True)
    assert float(on.corrections[0, 0, C_YRAIL]) == pytest.approx(y_rail, abs=1e-12)
    assert np.max(np.abs(stage - full)) <= 1e-4 * scale


def test_exact_small_patch_beside_a_loaded_one_takes_its_own_load(bodies):
    """A wheel with a small second tread region 9 mm beside its loaded patch (the
    pose of issue 30's 100 s route run, wheelset 3 at t = 23.8794 s, relative to
    the rails: shift -5.474 mm, yaw -1.066 mrad, roll 0.433 mrad, 8.7 um up): each
    patch's exact normal problem is solved in its own territory (halfway to its
    neighbour), so that its force is its own region's, within 25 % of its Hertz
    spring's (the exact and Hertz forces of the loaded patches differ by about 5
    %).  Without the territories the small region's grid grew over the loaded
    one's and took its load again, 58.8 kN for a spring of 0.46 kN, and the
    stand-ins multiplied that ratio: the run's single-sample spikes of Q."""
    from railcontact.dynamics.online_contact import R_SPRING, rhs_online
    from railcontact.dynamics.simulation import _System
    ws, tr = bodies
    m = _wheelset()
    sysm = _System(m, Route.tangent(50.0), OnlineWheelRail(ws, tr, normal="exact"), 50.0,
                   "exact")
    u = np.zeros(sysm.n_states)
    u[0:3] = -5.473997774641781e-3, -1.0659483875711468e-3, 4.332825936701933e-4
    u[6 * len(m.bodies)] = -8.737718498932018e-6
    on = sysm.online
    rhs_online(0.0, u, sysm.system, on, 2, sysm.fext_rows, sysm.out)
    rows = on.rows[0, :on.count[0]]
    left = rows[:, 0] == 0
    assert left.sum() == 2 and np.min(rows[left, R_SPRING]) < 1e3 < 5e4 < np.max(rows[:, R_SPRING])
    sysm._online_python_forces()
    N = sysm.fext_rows[0, :on.count[0]]["normal_force"]    # (at rest: no damper)
    assert np.all(np.abs(N / rows[:, R_SPRING] - 1.0) <= 0.25), (N, rows[:, R_SPRING])


def test_exact_stage_solves_only_the_wheelset_whose_patches_moved(bodies):
    """A bogie (2 wheelsets) on exact + exact online contact: at an inner stage
    where one wheelset's patch has moved on its rail beyond its grid's element
    (its correction displaced 1 mm), that wheelset's patches alone are solved
    (the exact normal solves counted: its rows, not the bogie's), the other keeps
    its stand-ins and its corrections unchanged, and the derivative equals the full
    evaluation's within the normal solver's tolerance (1e-4 of the largest entry,
    as where every patch is solved)."""
    from railcontact.dynamics.online_contact import C_YRAIL
    from railcontact.dynamics.simulation import _System, static_contact
    ws, tr = bodies
    m = VehicleModel.from_parameters("bogie")
    sysm = _System(m, Route.tangent(50.0), OnlineWheelRail(ws, tr, normal="exact"), 20.0,
                   "exact")
    u = np.zeros(sysm.n_states)
    for w in m.wheelsets:
        u[3 * w[0]] = 2e-3
    u = static_contact(sysm, u)
    u[3 * len(m.bodies) + 3 * m.wheelsets[0][0]] = 0.05
    on = sysm.online
    sysm.rhs(0.0, u)
    full = sysm.rhs(0.0, u)
    assert on.count.size == 2 and np.all(on.corrected == on.count) and on.count[0] >= 2
    solves = [0]
    real = sysm.py_normal.solve

    def counted(*a, **k):
        solves[0] += 1
        return real(*a, **k)
    sysm.py_normal.solve = counted
    other = on.corrections[1].copy()
    y_rail = float(on.corrections[0, 0, C_YRAIL])
    on.corrections[0, 0, C_YRAIL] += 1e-3              # as if the patch had moved 1 mm
    stage = sysm.rhs(0.0, u, stage=True)
    assert solves[0] == on.count[0]
    assert float(on.corrections[0, 0, C_YRAIL]) == pytest.approx(y_rail, abs=1e-12)
    assert np.array_equal(on.corrections[1], other)
    assert np.max(np.abs(stage - full)) <= 1e-4 * np.max(np.abs(full))
    solves[0] = 0
    sysm.rhs(0.0, u, stage=True)                       # both match again: no solve
    assert solves[0] == 0


def test_exact_online_with_stand_ins_against_every_stage_solved(bodies):
    """exact + exact online, 4 ms of the wheelset let go 2 mm off centre at 20 m/s:
    with the compiled stand-ins at the rk4 steps' inner stages (the default, the
    exact problems solved at each step's first evaluation) against the exact
    problems solved at every evaluation: the wheel forces Q and Y within 0.2 % of
    the static wheel load (measured: Q 0.050 %, Y 0.010 %), with fewer than 0.6 of
    the tangential solves (a quarter in the loop, the start's and the samples' alike)."""
    from railcontact.dynamics.online_contact import OnlineWheelRail as O
    import railcontact.tangential.exact as te
    ws, tr = bodies
    m = _wheelset()
    runs, solves = [], []
    real = te.ExactTangentialModel.solve
    for stand_in in ("none", "both"):
        calls = [0]

        def counted(self, *a, **k):
            calls[0] += 1
            return real(self, *a, **k)
        te.ExactTangentialModel.solve = counted
        try:
            runs.append(simulate_vehicle(m, Route.tangent(50.0),
                                         O(ws, tr, normal="exact", stand_in=stand_in), 20.0,
                                         4e-3, "exact", 0.3, STEEL, 2e-3,
                                         integration=Integration(method="rk4",
                                                                 sample_rate=1000)))
        finally:
            te.ExactTangentialModel.solve = real
        solves.append(calls[0])
    q0 = m.wheelsets[0][1] * G_ACC / 2
    for v in ("Q", "Y"):
        d = np.abs(runs[1][v].values - runs[0][v].values)
        assert np.max(d) <= 2e-3 * q0, (v, np.max(d) / q0)
    assert all(r.attrs["status"] == "completed" for r in runs)
    assert solves[1] < 0.6 * solves[0]


@pytest.mark.parametrize("normal", ["analyn", "kik-piotrowski"])
def test_strip_springs_have_their_stiffness(bodies, normal):
    """A strip model's rows carry their spring's stiffness (the rk4 step's substeps
    follow it, as Hertz's): the strip force times the exponent of the region's
    Hertz spring over the approach, against dN/d(delta) of the strip model by
    central differences in the wheelset's vertical position (+-0.2 um), within
    20 % on the tread and the flange of S1002/60E1 (measured 0.88-1.15: the strip
    model's exponent 1.42-1.71 against Hertz's region's)."""
    from railcontact.dynamics.online_contact import (G_STIFFNESS, R_N, R_STIFF,
                                                     search_wheelset)
    from railcontact.geometry import find_contact
    from railcontact.geometry.wheel_pass import P_APPROACH, P_CONTACT_ANGLE, PassPose
    ws, tr = bodies
    tp = np.array([0.3, STEEL.shear_modulus, 12, 12, 1.0, 1.0, 1.0, 0.0])
    oc = OnlineWheelRail(ws, tr, normal=normal).compiled(1, 1, tp, 1120.0, "fastsim-strips")
    g = oc.frame
    flanges = 0
    for y, yaw in ((0.0, 0.0), (4e-3, 2e-3), (7e-3, 3e-3), (6.2e-3, 0.0)):
        pose = PassPose(y, yaw, g[0], g[1], g[2], g[3], 30.0, -30.0 / g[3], 0.02, 0.001, 0.0)
        c = find_contact(ws, tr, y, yaw, vertical_force=6e4)
        z, roll = c.pose.vertical, c.pose.roll
        g[G_STIFFNESS] = 1.0
        m = search_wheelset(oc, 0, pose, z, roll)
        rows = oc.rows[0, :m].copy()
        g[G_STIFFNESS] = 0.0
        moved = []
        for dz in (-2e-7, 2e-7):
            assert search_wheelset(oc, 0, pose, z + dz, roll) == m
            moved.append(oc.rows[0, :m].copy())
        g[G_STIFFNESS] = 1.0
        for k in range(m):
            k_fd = (moved[1][k, R_N] - moved[0][k, R_N]) / \
                (moved[1][k, P_APPROACH] - moved[0][k, P_APPROACH])
            assert rows[k, R_STIFF] == pytest.approx(k_fd, rel=0.2)
            flanges += abs(rows[k, P_CONTACT_ANGLE]) > 0.5
    assert flanges >= 1


def test_warm_strips_run_as_the_cold(bodies):
    """The online strip model with its strips laid from the last evaluation's
    (``warm_strips``, the default) runs as with each evaluation's afresh: a
    wheelset let go 3 mm off centre, 0.05 s, the wheel forces equal to 1e-3 N."""
    ws, tr = bodies
    m = _wheelset()
    runs = [simulate_vehicle(m, Route.tangent(50.0),
                             OnlineWheelRail(ws, tr, normal="analyn", warm_strips=w), 20.0,
                             0.05, "fastsim-strips", 0.3, STEEL, 3e-3,
                             integration=Integration(method="rk4", sample_rate=1000))
            for w in (False, True)]
    for v in ("Q", "Y", "longitudinal_force", "lateral_creep_force"):
        np.testing.assert_allclose(runs[1][v].values, runs[0][v].values, rtol=0, atol=1e-3)
    assert float(np.abs(runs[0]["Y"].values).max()) > 100.0


def test_online_input_checks(bodies):
    ws, tr = bodies
    with pytest.raises(InputError, match="damping"):
        OnlineWheelRail(ws, tr, damping=-1.0)
    with pytest.raises(InputError, match="normal model"):
        OnlineWheelRail(ws, tr, normal="nonsense")
    with pytest.raises(InputError, match="stand_in"):
        OnlineWheelRail(ws, tr, normal="exact", stand_in="some")
    with pytest.raises(InputError, match="online contact: expected 'rk4'"):
        simulate_vehicle(_wheelset(), Route.tangent(50.0), OnlineWheelRail(ws, tr), 20.0, 0.01,
                         integration=Integration(method="lsoda"))


def test_scenario_contact_section():
    """``[contact] mode = "online"`` in a dynamics scenario; a wrong mode or stand-in
    names the key."""
    from railcontact.inputs import load_dynamics_scenario
    sc = load_dynamics_scenario(ROOT / "examples" / "dynamics_online.toml")
    assert sc.contact_mode == "online" and sc.contact_damping == 6e5
    from railcontact.dynamics.scenario import _contact_section
    with pytest.raises(CaseFileError, match="contact.mode"):
        _contact_section({"mode": "sometimes"})
    with pytest.raises(CaseFileError, match="contact"):
        _contact_section({"dampin": 1.0})
    assert sc.contact_stand_in == "both"
    assert _contact_section({"mode": "online", "normal": "exact",
                             "stand_in": "tangential"})[4] == "tangential"
    with pytest.raises(CaseFileError, match="contact.stand_in"):
        _contact_section({"stand_in": "all"})
