"""A wheelset on a roller rig (railcontact/dynamics/roller_rig.py): the contact
leaving the rollers' apexes with yaw against the 3-D roller search, the creepages
from the rollers' speed, the equations on track against the vehicle dynamics', the
rig's lower critical speed and the example's excited hunting through the CLI."""

import dataclasses
import math
import runpy
from pathlib import Path

import numpy as np
import pytest

import railcontact as rc
from railcontact.dynamics import VehicleModel
from railcontact.dynamics.roller_rig import (O_ETA, O_N, O_PHI, O_RHO, O_X, O_XC, O_XI,
                                             RigScenario, RigSystem, RollerRig, critical_speed,
                                             rig_tables)
from railcontact.dynamics.simulation import state_matrix
from railcontact.dynamics.wheel_rail import F_A, F_CA, F_DELTA, F_R, F_YP, WheelRailTable
from railcontact.inputs import load_dynamics_scenario

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "roller_rig_dynamics.toml"


@pytest.fixture(scope="module")
def scenario():
    sc = load_dynamics_scenario(EXAMPLE)
    assert isinstance(sc, RigScenario)
    # a smaller table (61 shifts, the example's step) for the tests
    return dataclasses.replace(sc, table_range=1.2e-3)


@pytest.fixture(scope="module")
def tables(scenario):
    return rig_tables(scenario)


def _forces(scenario, table, rig, state, law="fastsim"):
    s = RigSystem(scenario.vehicle, rig, table, law, scenario.friction, scenario.material)
    return s.forces(np.asarray(state, float))[0, 0]


def test_contact_leaves_the_apex_with_yaw_as_the_3d_roller_search(scenario, tables):
    """The centred wheelset yawed by psi: the right wheel's contact lies at
    x_c = -y_n sin(psi) rho / (r + rho) (y_n = y_p + r tan(delta), where its normal
    meets the axle), behind the apex for psi > 0.  Against the 3-D search on the
    roller's surface (examples/roller_rig_scaled.py; centred at psi = 0.838 and
    -2 mrad: x = -0.0815 and +0.1945 mm; shifted 0.4 mm at 1 mrad: -0.0935 mm):
    within 0.3 % (measured 0.05, 0.04 and 0.11 %).  The small-yaw estimate
    -y_p psi R_r / (R_r + r0) (y_p the contact's lateral distance from the yaw axis)
    lies within 3 %.  The roller's curvature enters the patch as the search finds
    it."""
    ex = runpy.run_path(str(ROOT / "examples" / "roller_rig_scaled.py"))
    rig_tab, _ = tables
    rig = scenario.rig
    out = _forces(scenario, rig_tab, rig, [[4e-4, 1e-3, 0.0, 0.0]])
    (p,) = rc.solve(ex["case"](4e-4, 1e-3)).patches
    assert out[1, 0, O_XC] == pytest.approx(p.geometry.position[0], rel=3e-3)
    for psi in (0.838e-3, -2e-3):
        out = _forces(scenario, rig_tab, rig, [[0.0, psi, 0.0, 0.0]])
        xc = out[1, 0, O_XC]
        # the left wheel is the right one mirrored: the same x at (-y, -psi)
        mirror = _forces(scenario, rig_tab, rig, [[-4e-4, -psi, 0.0, 0.0]])[0, 0, O_XC]
        assert mirror == pytest.approx(
            _forces(scenario, rig_tab, rig, [[4e-4, psi, 0.0, 0.0]])[1, 0, O_XC], rel=1e-9)
        (p,) = rc.solve(ex["case"](0.0, psi)).patches
        assert np.sign(xc) == -np.sign(psi)
        assert xc == pytest.approx(p.geometry.position[0], rel=3e-3)
        i0 = rig_tab.shift.size // 2
        # the roller's curvature along the track in the patch: A = 8.2118 1/m against
        # the search's 8.2121 (5.435 on a rail); the Hertz semi-axis a at the search's
        # 2.8 kN within 0.5 % (measured 0.13 % at 0.838 mrad, 0.38 % at -2 mrad: the
        # table is at zero yaw)
        assert rig_tab.data[i0, 1, 0, F_CA] == pytest.approx(p.geometry.curvatures[0],
                                                             rel=1e-4)
        a = rig_tab.data[i0, 1, 0, F_A] * (2800 / rig_tab.reference_load) ** (1 / 3)
        assert a == pytest.approx(p.normal.semi_axes[0], rel=5e-3)
        yp, r = rig_tab.data[i0, 1, 0, F_YP], rig_tab.data[i0, 1, 0, F_R]
        assert xc == pytest.approx(-yp * psi * rig.radius / (rig.radius + r), rel=0.03)
        # on a rail the contact lies further out: rho -> inf
        track = _forces(scenario, tables[1], rig.on_track(), [[0.0, psi, 0.0, 0.0]])
        assert track[1, 0, O_XC] == pytest.approx(xc * (1 + r / out[1, 0, O_RHO]), rel=1e-9)
        # the normal leans with the contact: N x_c cos(delta) / rho along the track
        # (Kalker's linear law: F_x from xi alone, the same at both yaws)
        out = _forces(scenario, rig_tab, rig, [[0.0, psi, 0.0, 0.0]], "linear")
        base = _forces(scenario, rig_tab, rig, [[0.0, 0.0, 0.0, 0.0]], "linear")
        d = rig_tab.data[i0, 1, 0, F_DELTA]
        assert out[1, 0, O_X] - base[1, 0, O_X] == pytest.approx(
            out[1, 0, O_N] * xc * math.cos(d) / out[1, 0, O_RHO], rel=1e-9)


def test_creepages_follow_the_rollers_speed(scenario, tables):
    """Centred, the wheel turning at 6 m/s on rollers 1 % faster: xi = (v_w r / r0 -
    v_r rho / R_r) / v_r = -0.0099 (the wheel braked as on track); the spin has the
    roller's rotation added: phi_rig / phi_track = 1 + (v_r / R_r) / (v_w / r0)."""
    rig_tab, track_tab = tables
    i0 = rig_tab.shift.size // 2
    vw, vr, R = 6.0, 6.06, scenario.rig.radius
    rig = RollerRig(R, vr, vw)
    out = _forces(scenario, rig_tab, rig, [[0.0, 0.0, 0.0, 0.0]])[1, 0]
    r, r0 = rig_tab.data[i0, 1, 0, F_R], rig_tab.nominal_radius
    rho = out[O_RHO]
    assert out[O_XI] == pytest.approx((vw * r / r0 - vr * rho / R) / vr, rel=1e-9)
    assert out[O_XI] == pytest.approx(-0.0099, abs=3e-4)
    assert abs(out[O_ETA]) < 1e-15
    trk = _forces(scenario, track_tab, rig.on_track(), [[0.0, 0.0, 0.0, 0.0]])[1, 0]
    assert out[O_PHI] / trk[O_PHI] == pytest.approx(1 + (vr / R) / (vw / r0), rel=1e-9)
    # the same speeds on both: pure rolling but for the profiles' radii
    same = _forces(scenario, rig_tab, RollerRig(R, 6.0), [[0.0, 0.0, 0.0, 0.0]])[1, 0]
    assert abs(same[O_XI]) < 5e-4


def test_on_track_the_equations_are_the_vehicle_dynamics(scenario, tables):
    """With 1/R_r = 0 the rig's state matrix is that of the vehicle dynamics
    (:func:`railcontact.dynamics.simulation.state_matrix`, the same wheelset on
    tangent track) to 0.5 % (measured 0.26 % on the yaw stiffness: the moment of the
    lateral force at the contact's x, which the vehicle model leaves out)."""
    w = scenario.vehicle
    _, track_tab = tables
    tb = WheelRailTable.build(scenario.wheelset, scenario.track, w.wheel_load,
                              scenario.material, 1.2e-3, 4e-5)
    vm = VehicleModel.single_wheelset(w.mass, w.yaw_inertia, w.k_y, w.k_yaw,
                                      wheel_load=w.wheel_load)
    for v in (6.0, 60.0):
        J = RigSystem(w, RollerRig(None, v), track_tab, "linear").state_matrix()
        K = state_matrix(vm, tb, v)
        assert J == pytest.approx(K, rel=5e-3, abs=1e-6 * np.abs(K).max())


def test_the_rig_lowers_the_critical_speed(scenario, tables):
    """The same wheelset (k_psi 5e4 N m/rad) on rollers of 0.18 m and on tangent
    track: linear critical speeds measured 75.1 and 101.4 m/s (as with the example's
    121-shift table: the same step, 40 um, about the centre);
    the rig is destabilising, as the published comparison of a 1:5 vehicle on track
    and on rollers finds "for most cases" (docs/dynamics.md, "On a roller rig")."""
    rig_tab, track_tab = tables
    vr = critical_speed(scenario.vehicle, scenario.rig, rig_tab)
    vt = critical_speed(scenario.vehicle, scenario.rig.on_track(), track_tab)
    assert vr == pytest.approx(75.1, rel=0.005) and vt == pytest.approx(101.4, rel=0.005)
    assert vr / vt < 0.8


def test_example_excited_hunting_through_the_cli(tmp_path):
    """``railcontact simulate examples/roller_rig_dynamics.toml``: two cycles of the
    seed's hunting (0.5 Hz, 1.6 mm at 1:5, yaw 2 pi f A / V); the forces repeat each
    cycle, the right wheel's contact lies behind its roller's apex where the wheelset
    yaws to the right (t = 0) and ahead of it half a cycle later, the normal force
    is the wheel load on the tread at the centre; the figure is written."""
    from railcontact.cli import main
    assert main(["simulate", str(EXAMPLE), "--out", str(tmp_path)]) == 0
    import xarray as xr
    ds = xr.load_dataset(tmp_path / "simulation.nc")
    assert (tmp_path / "rig_forces.png").stat().st_size > 10_000
    assert ds.attrs["critical_speed_m_s"] < ds.attrs["track_critical_speed_m_s"]
    r = ds.sel(wheelset=1, side="right")
    t = ds["time"].values
    i0, i1, i2 = 0, int(np.argmin(abs(t - 1.0))), int(np.argmin(abs(t - 2.0)))
    for name in ("normal_force", "longitudinal_force", "lateral_force"):
        assert r[name].values[i2] == pytest.approx(r[name].values[i0], rel=1e-9, abs=1e-9)
    psi0 = 2 * math.pi * 0.5 * 1.6e-3 / 6.0
    assert r["yaw"].values[0] == pytest.approx(psi0)
    xc = r["x_contact"].sel(patch="tread").values
    assert xc[i0] < 0 < xc[i1] and xc[i1] == pytest.approx(-xc[i0], rel=1e-6)
    assert r["normal_force"].values[i0] == pytest.approx(3000 / math.cos(0.034), rel=0.01)
    # into the flange root at 1.2 mm: the lateral force on the right wheel peaks
    assert r["lateral_force"].values.min() < -3000


def _scaled_manchester():
    """The Manchester preset scaled 1:5 with the same stresses: length 1/5, force
    1/25, mass 1/125 (speed 1:1)."""
    from railcontact.dynamics import MANCHESTER
    p = dict(MANCHESTER)
    L, F, M = 0.2, 1 / 25, 1 / 125
    for k in ("frame_mass", "wheelset_mass", "carbody_mass"):
        p[k] *= M
    for k in ("frame_yaw_inertia", "wheelset_yaw_inertia", "carbody_yaw_inertia"):
        p[k] *= M * L * L
    for k in ("frame_height", "wheel_radius", "semi_wheelbase", "primary_spacing",
              "secondary_spacing", "secondary_height", "carbody_height"):
        p[k] *= L
    for k in ("primary_kx", "primary_ky", "secondary_kx", "secondary_ky"):
        p[k] *= F / L
    for k in ("primary_cx", "primary_cy", "secondary_cy"):
        p[k] *= F
    p["secondary_bending"] *= F * L
    return p


def test_bogie_on_track_is_the_vehicle_dynamics_bogie_and_the_rig_lowers_it(scenario, tables):
    """The Manchester bogie scaled 1:5 (its wheel loads from its masses, 436 N): with
    1/R_r = 0 the rig's bogie has the state matrix of the vehicle dynamics' bogie
    (``VehicleModel.from_parameters("bogie")``) to 1e-5 (measured 2.3e-6) and its
    critical speed to 1e-4 (42.86 m/s); on the rollers it is lower (measured 31.0 m/s:
    0.72).  A free run on track follows the vehicle dynamics' run."""
    from railcontact.dynamics.roller_rig import RigBogie
    from railcontact.dynamics.simulation import critical_speed as track_critical_speed
    p = _scaled_manchester()
    vm = VehicleModel.from_parameters("bogie", p)
    load = vm.wheelsets[0][1] * 9.81 / 2
    w = dataclasses.replace(scenario.vehicle, mass=p["wheelset_mass"],
                            yaw_inertia=p["wheelset_yaw_inertia"], k_y=2 * p["primary_ky"],
                            c_y=2 * p["primary_cy"],
                            k_yaw=2 * p["primary_kx"] * p["primary_spacing"] ** 2,
                            c_yaw=2 * p["primary_cx"] * p["primary_spacing"] ** 2,
                            wheel_load=load)
    bogie = RigBogie(p["frame_mass"], p["frame_yaw_inertia"], p["semi_wheelbase"],
                     2 * p["secondary_ky"],
                     2 * p["secondary_kx"] * p["secondary_spacing"] ** 2
                     + p["secondary_bending"], 2 * p["secondary_cy"], 0.0)
    # the defaults are this bogie (rounded)
    assert dataclasses.astuple(bogie) == pytest.approx(dataclasses.astuple(RigBogie()),
                                                       rel=1e-3)
    rig_tab, track_tab = tables
    tb = WheelRailTable.build(scenario.wheelset, scenario.track, 3000.0, scenario.material,
                              1.2e-3, 4e-5)
    J = RigSystem(w, RollerRig(None, 20.0), track_tab, "linear", bogie=bogie).state_matrix()
    K = state_matrix(vm, tb, 20.0)
    assert J == pytest.approx(K, rel=1e-5, abs=1e-9 * np.abs(K).max())
    vt = critical_speed(w, scenario.rig.on_track(), track_tab, bogie=bogie)
    assert vt == pytest.approx(track_critical_speed(vm, tb), rel=1e-4)
    vr = critical_speed(w, scenario.rig, rig_tab, bogie=bogie)
    assert vr / vt < 0.8
    # a free run on track with FASTSIM (both RK4, 20 us) from 0.3 mm: the wheelsets'
    # paths agree to 3e-7 m (measured 8e-8 m: the moment x_c Y)
    from railcontact.dynamics import Route
    from railcontact.dynamics.roller_rig import simulate_rig
    from railcontact.dynamics.simulation import Integration, simulate_vehicle
    s = RigSystem(w, RollerRig(None, 30.0), track_tab, "fastsim", bogie=bogie)
    a = simulate_rig(s, 0.3, 3e-4, 2e-5, 1000)["lateral_displacement"].values
    b = simulate_vehicle(vm, Route.tangent(100), tb, 30.0, 0.3, "fastsim",
                         initial_lateral_shift=3e-4,
                         integration=Integration("rk4", sample_rate=1000, step=2e-5)
                         )["lateral_displacement"].values
    assert a.shape == b.shape and np.abs(a - b).max() < 3e-7


def test_free_run_decays_and_grows_as_the_eigenvalues_say(scenario, tables):
    """The compiled RK4 run of the wheelset on the rollers (linear law, 10 um start):
    at 0.9 of the critical speed the oscillation decays at the rate of the least
    damped eigenvalue (measured -17.07 1/s against -17.05 1/s, within 1 %); at 1.1
    of it the oscillation grows, to a limit cycle of about 0.1 mm where the table's
    contact angle bends."""
    from railcontact.dynamics.roller_rig import simulate_rig
    rig_tab, _ = tables
    vc = critical_speed(scenario.vehicle, scenario.rig, rig_tab)
    for f in (0.9, 1.1):
        s = RigSystem(scenario.vehicle, RollerRig(scenario.rig.radius, f * vc), rig_tab,
                      "linear")
        ds = simulate_rig(s, duration=1.0, initial_lateral_shift=1e-5, step=2e-5,
                          sample_rate=1000)
        y = np.abs(ds["lateral_displacement"].sel(wheelset=1).values)
        n = y.size
        if f < 1:
            rate = np.log(y[-n // 4:].max() / y[n // 4:n // 2].max()) / 0.5
            growth = np.linalg.eigvals(s.state_matrix()).real.max()
            assert growth < 0 and rate == pytest.approx(growth, rel=0.01)
        else:
            assert y[-n // 4:].max() > 5 * y[0]
