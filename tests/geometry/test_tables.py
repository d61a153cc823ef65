"""Contact tables and equivalent conicity."""

import math

import numpy as np
import pytest

from railcontact.geometry import Track, Wheelset, contact_table, equivalent_conicity
from railcontact.profiles import Profile, rail_profile, s1002


def conical_wheel(gamma):
    y = np.linspace(-0.065, 0.065, 800)
    return Profile(y, -gamma * y, kind="wheel", name=f"cone {gamma}")


@pytest.mark.parametrize("gamma", [0.025, 0.05])
def test_conical_wheel(gamma):
    ws = Wheelset(conical_wheel(gamma))
    tr = Track(rail_profile("60E1", math.atan(1 / 40)))
    table = contact_table(ws, tr, np.arange(-4e-3, 4.01e-3, 0.5e-3))
    # A cone touches where the rail slope equals gamma (here on the R300 crown).  The
    # wheelset rolls by phi = gamma y / l, which moves the contact across the wheel by
    # (r0 + R_rail) phi: delta_r = 2 gamma y [1 + gamma (r0 + R_rail) / l], l the half
    # distance between the contact points.
    dr = table["delta_r"].values
    y = table["lateral_shift"].values
    l = ws.wheel_offset + float(table.sel(side="right")["y_wheel"].values[len(y) // 2])
    factor = 1 + gamma * (0.46 + 0.300) / l
    assert np.allclose(dr, 2 * gamma * factor * y, rtol=2e-3, atol=1e-8)
    for method in ("wavelength", "harmonic"):
        assert equivalent_conicity(table, 3e-3, method) == pytest.approx(gamma * factor,
                                                                          rel=3e-3)
    # angle of the contact normal: the cone angle (rail inclination absorbed in the rail)
    assert np.allclose(np.abs(table.sel(side="right")["contact_angle"].values), math.atan(gamma),
                       atol=2e-3)


def test_s1002_60e1_table():
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    table = contact_table(ws, tr, np.arange(-3e-3, 3.01e-3, 0.5e-3), vertical_force=1e4)
    dr = table["delta_r"].values
    assert abs(dr[len(dr) // 2]) < 1e-9           # symmetric
    assert np.allclose(dr, -dr[::-1], atol=1e-9)
    assert np.all(np.diff(dr) > 0)
    g = equivalent_conicity(table, 3e-3)
    assert 0.1 < g < 0.25                          # S1002/60E1 1:40, gauge 1435: ~0.15
    assert table["delta_r"].attrs["units"] == "m"
    with pytest.raises(Exception, match="cover"):
        equivalent_conicity(table, 5e-3)
