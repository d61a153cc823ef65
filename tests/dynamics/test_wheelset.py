"""Single wheelset: kinematic oscillation (Klingel) and linear stability."""

import math

import numpy as np
import pytest

from railcontact.dynamics.wheelset import WheelsetModel, critical_speed, simulate, wavelength
from railcontact.core.errors import InputError


@pytest.mark.parametrize("gamma", [0.05, 0.15, 0.3])
def test_klingel_conical(gamma):
    m = WheelsetModel.conical(gamma)
    ds = simulate(m, 2.0, 80.0, y0=2e-3)
    assert wavelength(ds) == pytest.approx(2 * math.pi * math.sqrt(m.r0 * m.l / gamma), rel=0.02)


def test_s1002_wavelength_matches_equivalent_conicity():
    from railcontact.geometry import Track, Wheelset, contact_table, equivalent_conicity
    from railcontact.profiles import rail_profile, s1002
    table = contact_table(Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40))),
                          np.arange(-6e-3, 6.01e-3, 2.5e-4), vertical_force=75e3)
    m = WheelsetModel.from_table(table)
    amp = 3e-3
    gamma = equivalent_conicity(table, amp, half_contact_distance=m.l)
    ds = simulate(m, 2.0, 100.0, y0=amp)
    assert wavelength(ds) == pytest.approx(2 * math.pi * math.sqrt(m.r0 * m.l / gamma), rel=0.02)


def _growth(model, v, duration=25.0):
    ds = simulate(model, v, duration, y0=1e-4)
    y = np.abs(ds["lateral_displacement"].values)
    n = y.size
    return y[-n // 4:].max() / y[:n // 4].max()


def test_simulated_critical_speed_matches_eigenvalues():
    m = WheelsetModel.conical(0.15, k_y=1e6, k_psi=2e6)
    vc = critical_speed(m)
    lo, hi = 0.8 * vc, 1.2 * vc
    assert _growth(m, lo) < 1 < _growth(m, hi)
    for _ in range(8):                     # bisection on the simulated growth
        mid = 0.5 * (lo + hi)
        if _growth(m, mid) < 1:
            lo = mid
        else:
            hi = mid
    assert 0.5 * (lo + hi) == pytest.approx(vc, rel=0.02)


def test_bad_input():
    with pytest.raises(InputError):
        WheelsetModel(mass=-1.0, table_y=np.linspace(-1, 1, 3), table_dr=np.zeros(3))
    with pytest.raises(InputError):
        simulate(WheelsetModel.conical(0.1), -1.0, 1.0)
