"""Helpers of the compiled equations of motion (railcontact.dynamics.equations_of_motion):
the bump-stop characteristic and the track's curvature and cant along a transition."""

import numpy as np
import pytest

from railcontact.dynamics.equations_of_motion import _bump_force, _track_at
from railcontact.dynamics.vehicle import MANCHESTER

BX = np.array(MANCHESTER["bump_stop_deflection"])
BF = np.array(MANCHESTER["bump_stop_force"])


def test_manchester_bump_stop():
    """Free play up to 25 mm, the tabulated force between, the last slope beyond,
    odd in the deflection."""
    assert _bump_force(0.02, BX, BF) == 0.0
    assert _bump_force(0.0325, BX, BF) == pytest.approx(0.5 * (600.0 + 1760.0), rel=1e-12)
    assert _bump_force(-0.0325, BX, BF) == pytest.approx(-1180.0, rel=1e-12)
    slope = (230000.0 - 29200.0) / 0.005
    assert _bump_force(0.066, BX, BF) == pytest.approx(230000.0 + 0.001 * slope, rel=1e-12)


def test_track_along_a_transition():
    """Curvature rising linearly from 0 to 1/300 m^-1 over 50 m with the cant: the
    slope is 1/(300 * 50) per m inside, 0 outside, and the values clamp at the ends."""
    ks = np.array([0.0, 100.0, 150.0, 400.0])
    kk = np.array([0.0, 0.0, 1 / 300, 1 / 300])
    kc = np.array([0.0, 0.0, 0.1, 0.1])
    k, dk, c = _track_at(120.0, ks, kk, kc)
    assert (k, dk, c) == pytest.approx((0.4 / 300, 1 / (300 * 50), 0.04), rel=1e-12)
    assert _track_at(50.0, ks, kk, kc) == (0.0, 0.0, 0.0)
    assert _track_at(-5.0, ks, kk, kc) == (0.0, 0.0, 0.0)
    assert _track_at(500.0, ks, kk, kc) == pytest.approx((1 / 300, 0.0, 0.1))
