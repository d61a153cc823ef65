"""The wheel-rail contact table of the dynamics (railcontact.dynamics.wheel_rail):
the conical test geometry, the compiled lookup, and one patch's forces through a
registered model's Python solve."""

import math

import numpy as np
import pytest

from railcontact.dynamics.wheel_rail import (F_DELTA, F_R, F_SHARE, FIELDS, WheelRailTable,
                                             lookup, python_patch_forces)
from railcontact.geometry.contact import ContactGeometry
from railcontact.core.materials import Material
from railcontact.normal import get_normal_model
from railcontact.tangential import get_tangential_model, kalker_coefficients


def test_conical_table_and_its_lookup():
    """Conical wheels r = r0 -+ gamma y: the lookup interpolates the linear radius
    exactly between table points and clamps (and says so) outside."""
    t = WheelRailTable.conical(0.05, shift_range=0.01)
    out = np.empty((2, 2, len(FIELDS)))
    y = 3.3333e-3                                          # between table points
    assert not lookup(t.shift, t.data, y, out)
    assert out[0, 0, F_R] == pytest.approx(0.46 - 0.05 * y, rel=1e-14)
    assert out[1, 0, F_R] == pytest.approx(0.46 + 0.05 * y, rel=1e-14)
    assert (out[0, 0, F_DELTA], out[1, 0, F_DELTA]) == (0.05, -0.05)
    assert (out[1, 0, F_SHARE], out[1, 1, F_SHARE]) == (1.0, 0.0)   # tread only
    assert t.delta_r == pytest.approx(0.1 * t.shift)
    assert lookup(t.shift, t.data, 0.015, out)
    assert out[1, 0, F_R] == pytest.approx(0.46 + 0.05 * 0.01, rel=1e-14)
    ds = t.to_xarray()
    assert ds["rolling_radius"].attrs["units"] == "m" and ds.sizes["lateral_shift"] == 401
    assert math.isnan(t.flange_angle)


def test_python_patch_forces_of_the_linear_model():
    mat = Material(2.1e11, 0.28)
    A, B, N = 1 / 0.92, 1 / 0.6, 6e4
    ns = get_normal_model("hertz").solve(ContactGeometry(curvatures=(A, B)), mat,
                                         normal_force=N)
    a, b = ns.semi_axes
    C11, C22, C23 = kalker_coefficients(a / b, 0.28)
    G, c = mat.shear_modulus, math.sqrt(a * b)
    fx, fy, mz = python_patch_forces(get_tangential_model("linear"), mat, 0.3, N, A, B,
                                     1e-4, -2e-4, 0.05, 30.0, (20, 20))
    assert fx == pytest.approx(G * c * c * C11 * 1e-4, rel=1e-9)
    assert fy == pytest.approx(G * c * c * C22 * -2e-4 + G * c ** 3 * C23 * 0.05, rel=1e-9)
    assert python_patch_forces(get_tangential_model("linear"), mat, 0.3, 0.0, A, B,
                               1e-4, 0.0, 0.0, 30.0, (20, 20)) == (0.0, 0.0, 0.0)


def test_quasi_elastic_table():
    """Arnold's quasi-elastic table: one point per wheel carrying the whole load, its
    geometry that of the geometry layer's quasi-elastic contact (continuous across the
    rigid contact's jumps: tests/geometry/test_quasi_elastic.py); the Manchester bogie's
    linear critical
    speed on it near the conical (gamma = 0.15) bogie's 77.7 m/s (docs/dynamics.md)."""
    from railcontact.dynamics import VehicleModel, critical_speed
    from railcontact.geometry import Track, Wheelset
    from railcontact.geometry.quasi_elastic import quasi_elastic_table
    from railcontact.profiles import rail_profile, s1002
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", inclination=math.atan(1 / 40)))
    t = WheelRailTable.quasi_elastic(ws, tr, 60e3, 3e-5, shift_range=0.008, step=2.5e-4)
    assert np.all(t.data[:, :, 0, F_SHARE] == 1.0) and np.all(t.data[:, :, 1, F_SHARE] == 0.0)
    q = quasi_elastic_table(ws, tr, t.shift[::8], alpha=3e-5)
    np.testing.assert_allclose(t.delta_r[::8], q["delta_r"].values, rtol=0, atol=1e-12)
    np.testing.assert_allclose(t.data[::8, 1, 0, F_DELTA],
                               q["contact_angle"].sel(side="right").values, atol=1e-12)
    vc = critical_speed(VehicleModel.from_parameters("bogie", {}), t)
    assert 70.0 < vc < 90.0
