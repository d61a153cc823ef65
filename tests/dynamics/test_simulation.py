"""Vehicle simulation (railcontact.dynamics.simulation): the compiled creep laws it
uses, Klingel, linear stability of a bogie, steady curving of the Manchester
benchmark vehicle."""

import math

import numpy as np
import pytest

from railcontact.dynamics import (Integration, Route, VehicleModel, WheelRailTable, amplitude_growth,
                                  critical_speed, simulate_vehicle, state_matrix)
from railcontact.dynamics.vehicle import G_ACC
from railcontact.dynamics.wheel_rail import patch_forces, python_patch_forces
from railcontact.core.errors import InputError
from railcontact.core.materials import STEEL
from railcontact.core.hertz_theory import hertz_ellipse
from railcontact.tangential import get_tangential_model
from railcontact.tangential.kalker import Creepage, KalkerCoefficients, kalker_coefficients
from railcontact.tangential.polach import polach_forces, polach_kernel

G, NU = STEEL.shear_modulus, STEEL.poisson_ratio
A_CURV, B_CURV = 1 / (2 * 0.46), 1 / 0.3


def _patch(N=60e3):
    hz = hertz_ellipse(A_CURV, B_CURV, STEEL.contact_modulus, force=N)
    return hz.a, hz.b, kalker_coefficients(hz.a / hz.b, NU)


@pytest.mark.parametrize("creep", [(1e-4, 0, 0), (0, 1e-4, 0), (-2e-3, 1e-3, 0.1),
                                   (0, -3e-3, 0.5), (0.02, 0.0, 0.0)])
def test_compiled_fastsim_equals_the_fastsim_model(creep):
    """The online FASTSIM (forces only) gives the registered model's forces."""
    N, mu = 60e3, 0.3
    a, b, C = _patch(N)
    fx, fy, mz = patch_forces(1, np.array([mu, G, 40, 40, 1, 1, 1, 0]), N, a, b, *C, *creep,
                              30.0)
    ref = python_patch_forces(get_tangential_model("fastsim"), STEEL, mu, N, A_CURV, B_CURV,
                              *creep, 30.0, (40, 40))
    assert fx == pytest.approx(ref[0], abs=5e-3 * mu * N)
    assert fy == pytest.approx(ref[1], abs=5e-3 * mu * N)


def test_compiled_laws_linear_limit_and_saturation():
    N, mu = 60e3, 0.3
    a, b, C = _patch(N)
    c2 = a * b
    tp = np.array([mu, G, 30, 30, 1, 1, 1, 0])
    for law in (0, 1, 2):
        fx, fy, _ = patch_forces(law, tp, N, a, b, *C, 1e-6, 0.0, 0.0, 30.0)
        assert fx == pytest.approx(G * c2 * C[0] * 1e-6, rel=0.01)
        fx, fy, _ = patch_forces(law, tp, N, a, b, *C, 0.0, 1e-6, 0.0, 30.0)
        assert fy == pytest.approx(G * c2 * C[1] * 1e-6, rel=0.01)
    for law in (1, 2):                              # full sliding: mu N
        fx, fy, _ = patch_forces(law, tp, N, a, b, *C, -0.05, 0.0, 0.0, 30.0)
        assert fx == pytest.approx(-mu * N, rel=0.02)
    # Polach compiled kernel = Polach's function
    ref = polach_forces(N, mu, a, b, G, NU, 2e-3, -1e-3, 0.3, 0.8, 0.5)
    got = polach_kernel(N, mu, a, b, G, KalkerCoefficients(*C), Creepage(2e-3, -1e-3, 0.3),
                        0.8, 0.5)
    np.testing.assert_allclose(got, ref, rtol=1e-12)


@pytest.mark.parametrize("gamma", [0.05, 0.2])
def test_klingel_with_the_vehicle_simulator(gamma):
    m = VehicleModel.single_wheelset(k_y=0.0, k_yaw=0.0, wheel_load=60e3)
    tab = WheelRailTable.conical(gamma, reference_load=60e3)
    ds = simulate_vehicle(m, Route.tangent(500), tab, 2.0, 80.0, "linear",
                          initial_lateral_shift=2e-3,
                          integration=Integration(sample_rate=50, rtol=1e-9))
    y, x = ds["lateral_displacement"].values[:, 0], ds["distance"].values
    s = np.flatnonzero((y[:-1] < 0) & (y[1:] >= 0))
    xc = x[s] - y[s] * (x[s + 1] - x[s]) / (y[s + 1] - y[s])
    assert np.mean(np.diff(xc)) == pytest.approx(2 * math.pi * math.sqrt(0.46 * 0.75 / gamma),
                                                 rel=0.02)


def test_state_matrix_of_a_wheelset_is_the_classical_one():
    """With zero contact angles (no spin, no tilt of the contact plane) the
    linearised wheelset is the textbook one (Wickens): check it entry by entry."""
    m = VehicleModel.single_wheelset(k_y=1e6, k_yaw=2e6, wheel_load=60e3)
    tab = WheelRailTable.conical(0.1, reference_load=60e3, contact_angles=False)
    V = 20.0
    J = state_matrix(m, tab, V)            # states y, psi, y', psi'
    a, b = 6e-3, 4e-3
    C11, C22, _ = kalker_coefficients(a / b, NU)
    f11, f22 = G * a * b * C11, G * a * b * C22
    cd2 = 1.0
    assert J[2, 2] == pytest.approx(-2 * f22 * cd2 / (1813 * V), rel=1e-6)
    assert J[2, 1] == pytest.approx(2 * f22 * cd2 / 1813, rel=1e-6)
    assert J[3, 0] == pytest.approx(-2 * f11 * 0.75 * 0.1 / (0.46 * 1120), rel=1e-6)
    assert J[3, 3] == pytest.approx(-2 * f11 * 0.75 ** 2 / (1120 * V), rel=1e-6)
    assert J[2, 0] == pytest.approx(-1e6 / 1813, rel=1e-6)
    assert J[3, 1] == pytest.approx(-2e6 / 1120, rel=1e-6)


def test_bogie_critical_speed_simulation_matches_eigenvalues():
    """Manchester bogie, conical wheels (gamma 0.15), linear creep: bisection on the
    simulated amplitude growth lands within 2 % of the eigenvalue critical speed."""
    m = VehicleModel.bogie()
    tab = WheelRailTable.conical(0.15, reference_load=m.wheelsets[0][1] * G_ACC / 2)
    vc = critical_speed(m, tab)
    lo, hi = 0.9 * vc, 1.1 * vc
    assert amplitude_growth(m, tab, lo, 6.0) < 1 < amplitude_growth(m, tab, hi, 6.0)
    for _ in range(6):
        mid = 0.5 * (lo + hi)
        if amplitude_growth(m, tab, mid, 8.0) < 1:
            lo = mid
        else:
            hi = mid
    assert 0.5 * (lo + hi) == pytest.approx(vc, rel=0.02)


@pytest.fixture(scope="module")
def s1002_table():
    from railcontact.geometry import Track, Wheelset
    from railcontact.profiles import rail_profile, s1002
    m = VehicleModel.vehicle()
    return WheelRailTable.build(Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40))),
                                m.wheelsets[0][1] * G_ACC / 2, shift_range=0.01, step=2.5e-4)


@pytest.mark.parametrize("R, V", [(1200.0, 40.0), (300.0, 20.0)])
def test_steady_curving_force_balance(s1002_table, R, V):
    """Benchmark vehicle in a canted curve: the lateral wheel-rail forces balance the
    uncompensated centrifugal force; the outer wheels carry more load; in the tight
    curve the leading wheelsets run in flange contact on the outer rail, with their
    front turned outwards, and the trailing ones lie towards the inner rail."""
    m = VehicleModel.vehicle()
    h = 0.1
    route = Route.from_segments([{"type": "tangent", "length": 30},
                                 {"type": "transition", "length": 60},
                                 {"type": "curve", "radius": R, "cant": h, "length": 600}])
    ds = simulate_vehicle(m, route, s1002_table, V, (90 + 300) / V, "fastsim",
                          integration=Integration(sample_rate=20))
    last = ds.isel(time=-1)
    phi = math.asin(h / 1.5)
    au = V * V / R * math.cos(phi) - G_ACC * math.sin(phi)
    assert float(last["Y"].sum()) == pytest.approx(m.total_mass * au, rel=0.01)
    Q = last["Q"].values                      # (wheelset, side): left is outer
    assert np.all(Q[:, 0] > Q[:, 1])
    y = last["lateral_displacement"].values
    assert np.all(y[[0, 2]] < 0)              # leading wheelsets towards the outer rail
    if R == 300.0:
        flange = last["patch_normal_force"].values[:, 0, 1]
        assert np.all(flange[[0, 2]] > 10e3) and np.all(flange[[1, 3]] == 0)
        yaw = last["yaw"].values
        assert np.all(yaw[[0, 2]] < -2e-3)        # front turned outwards
        assert np.all(y[[1, 3]] > y[[0, 2]] + 5e-3)
        assert float(last["Y_over_Q"].sel(side="left")[0]) < 0.8


def test_python_tangential_model_online(s1002_table, monkeypatch):
    """Models without a compiled law run through their Python ``solve`` online: at
    the same states the Python path with FASTSIM gives the compiled FASTSIM's wheel
    forces, and FaStrip runs by name."""
    import railcontact.dynamics.simulation as sim
    m = VehicleModel.single_wheelset(wheel_load=s1002_table.reference_load)
    route = Route.from_segments([{"type": "curve", "radius": 600.0, "length": 200}])
    states = [np.array([-4e-3, -2e-3, 0, 0.01, 1e-3, 0]), np.array([2e-3, 1e-3, 0, 0, 0, 0]),
              np.array([-6e-3, 0, 0, 0, 0, 0])]
    compiled = sim._System(m, route, s1002_table, 10.0, "fastsim", fastsim_grid=(20, 20))
    monkeypatch.setattr(sim, "online_law", lambda name: None)
    python = sim._System(m, route, s1002_table, 10.0, "fastsim")
    assert python.py_model is not None and compiled.py_model is None
    mu_n = 0.3 * s1002_table.reference_load
    for u in states:
        compiled.rhs(0.1, u)
        python.rhs(0.1, u)
        for force in ("Fx", "Fy"):
            np.testing.assert_allclose(python.pout[force], compiled.pout[force], atol=0.01 * mu_n)
    ds = simulate_vehicle(m, route, s1002_table, 10.0, 0.2, "fastrip",
                          integration=Integration(sample_rate=20))
    assert ds.attrs["tangential"] == "fastrip"
    assert np.all(np.isfinite(ds["Y"].values))
    assert float(np.abs(ds["longitudinal_force"][-1]).max()) > 0.05 * mu_n


def test_bad_inputs(s1002_table):
    m = VehicleModel.single_wheelset()
    with pytest.raises(InputError, match="velocity"):
        simulate_vehicle(m, Route.tangent(), s1002_table, -3.0, 1.0)
    with pytest.raises(InputError, match="unknown tangential model"):
        simulate_vehicle(m, Route.tangent(), s1002_table, 10.0, 1.0, "hertzian")
    with pytest.raises(InputError, match="wheelset_mas"):
        VehicleModel.from_parameters("vehicle", {"wheelset_mas": 1.0})
    with pytest.raises(InputError, match="carbody_mass"):
        VehicleModel.from_parameters("vehicle", {"carbody_mass": float("nan")})
    with pytest.raises(InputError, match="train"):
        VehicleModel.from_parameters("train")


def test_rk4_equals_lsoda(s1002_table):
    """The compiled fixed-step loop and LSODA agree on an irregular curved run."""
    from railcontact.dynamics import Irregularities
    m = VehicleModel.bogie()
    route = Route.from_segments([{"type": "tangent", "length": 20},
                                 {"type": "curve", "radius": 1000.0, "cant": 0.05,
                                  "length": 300}], Irregularities.from_psd(400, "ERRI-high"))
    runs = [simulate_vehicle(m, route, s1002_table, 40.0, 3.0, "fastsim",
                             integration=Integration(i, rtol=1e-8)) for i in ("rk4", "lsoda")]
    assert runs[0].attrs["integrator"] == "rk4" and runs[0].attrs["step_s"] <= 1e-3
    y = [r["lateral_displacement"].values for r in runs]
    assert np.abs(y[0]).max() > 1e-3
    np.testing.assert_allclose(y[0], y[1], atol=1e-5)
    with pytest.raises(InputError, match="compiled creep law"):
        simulate_vehicle(m, route, s1002_table, 40.0, 0.1, "fastrip",
                         integration=Integration("rk4"))
    with pytest.raises(InputError, match="integrator"):
        simulate_vehicle(m, route, s1002_table, 40.0, 0.1, integration=Integration("euler"))
