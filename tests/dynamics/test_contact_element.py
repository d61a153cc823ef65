"""The contact element (forces of both rails on a wheelset at a pose): the vertical
balance of the load mode, position and load modes against each other, mirror
symmetry, the creepage of the roll rate and vertical velocity, and the wrench of
a patch against its closed form."""

import math

import numpy as np
import pytest

from railcontact.dynamics.contact_element import WheelsetState, patch_wrench
from railcontact.inputs import contact_element
from railcontact.core.errors import InputError


@pytest.fixture(scope="module")
def elements():
    return (contact_element(mode="position"), contact_element(mode="load"))


@pytest.mark.parametrize("y", [0.0, 0.003, 0.007])
def test_load_mode_meets_the_loads_and_position_mode_reproduces_it(elements, y):
    pos, load = elements
    a = load.evaluate(WheelsetState(lateral_shift=y, yaw=1e-3, loads=(60e3, 80e3)))
    assert a.converged
    # vertical balance: each rail pushes its wheel up by its load (solver.force_tolerance 1e-4)
    assert a.side_force["left"][2] == pytest.approx(-60e3, rel=1e-4)
    assert a.side_force["right"][2] == pytest.approx(-80e3, rel=1e-4)
    # the same pose given as a position gives the same patches and forces
    b = pos.evaluate(WheelsetState(lateral_shift=y, yaw=1e-3, vertical_position=a.pose.vertical,
                                   roll=a.pose.roll))
    np.testing.assert_allclose(b.force, a.force, rtol=0, atol=1e-6 * 140e3)
    np.testing.assert_allclose(b.torque, a.torque, rtol=0, atol=1e-6 * 140e3)


def test_mirror_symmetry(elements):
    """S1002 on 60E1 both sides: the wheelset at -y, -yaw is the mirror image of +y, +yaw
    (lateral force, roll and yaw torques change sign; longitudinal and vertical forces,
    pitch torque do not)."""
    pos, load = elements
    a = load.evaluate(WheelsetState(lateral_shift=0.004, yaw=2e-3, loads=(70e3, 70e3)))
    st = dict(vertical_position=a.pose.vertical, velocity=30.0)
    p = pos.evaluate(WheelsetState(lateral_shift=0.004, yaw=2e-3, roll=a.pose.roll, **st))
    m = pos.evaluate(WheelsetState(lateral_shift=-0.004, yaw=-2e-3, roll=-a.pose.roll, **st))
    sign = np.array([1.0, -1.0, 1.0])
    np.testing.assert_allclose(m.force, sign * p.force, rtol=0, atol=1e-6 * 140e3)
    np.testing.assert_allclose(m.torque, -sign * p.torque, rtol=0, atol=1e-6 * 140e3)
    np.testing.assert_allclose(m.side_force["left"], sign * p.side_force["right"], rtol=0,
                               atol=1e-6 * 140e3)


def test_wheel_off_the_rail_carries_nothing(elements):
    pos, _ = elements
    r = pos.evaluate(WheelsetState(lateral_shift=0.0, vertical_position=-1e-3))
    assert r.patches == [] and np.all(r.force == 0) and np.all(r.torque == 0)


def test_roll_rate_and_vertical_velocity_creepage(elements):
    """Their slip velocity at the contact point, (0, -w_x d_z, w_x d_y + dz/dt), changes
    the lateral creepage by -(v_y cos d + v_z sin d)/V and nothing else."""
    pos, load = elements
    a = load.evaluate(WheelsetState(lateral_shift=0.006, loads=(70e3, 70e3)))
    base = WheelsetState(lateral_shift=0.006, vertical_position=a.pose.vertical,
                         roll=a.pose.roll)
    wx, zd = 0.2, 0.05
    moved = WheelsetState(lateral_shift=0.006, vertical_position=a.pose.vertical,
                          roll=a.pose.roll, roll_rate=wx, vertical_velocity=zd)
    r0, r1 = pos.evaluate(base), pos.evaluate(moved)
    O = np.array([0.0, 0.006, a.pose.vertical - pos.nominal_radius])
    assert len(r0.patches) == len(r1.patches) >= 2
    for p0, p1 in zip(r0.patches, r1.patches):
        d = np.asarray(p0.geometry.position) - O
        c, s = math.cos(p0.geometry.contact_angle), math.sin(p0.geometry.contact_angle)
        deta = -(-wx * d[2] * c + (wx * d[1] + zd) * s) / p0.geometry.velocity
        assert p1.creepage[0] == p0.creepage[0] and p1.creepage[2] == p0.creepage[2]
        assert p1.creepage[1] - p0.creepage[1] == pytest.approx(deta, rel=1e-12, abs=1e-15)
    # a roll rate of 0.2 rad/s moves the lateral force measurably
    assert abs(r1.force[1] - r0.force[1]) > 10.0


def test_patch_wrench_closed_form(elements):
    """A patch's force in the track frame, (F_x, F_y cos d + F_n sin d, F_y sin d - F_n cos d),
    and its torque about a point: the lever times the force plus M_z along the normal."""
    pos, load = elements
    a = load.evaluate(WheelsetState(lateral_shift=0.008, loads=(70e3, 70e3)))
    flange = min(a.patches, key=lambda p: p.geometry.contact_angle)       # right flange
    g, t, fn = flange.geometry, flange.tangential, flange.normal.normal_force
    d = g.contact_angle
    assert d < -0.5
    F, T = patch_wrench(flange, np.zeros(3))
    np.testing.assert_allclose(F, [t.fx, t.fy * math.cos(d) + fn * math.sin(d),
                                   t.fy * math.sin(d) - fn * math.cos(d)], rtol=1e-14)
    # lateral force of the flange patch pushes the wheelset to the left
    assert F[1] < -0.5 * fn
    P = np.asarray(g.position)
    Tz = P[0] * F[1] - P[1] * F[0] + t.mz * math.cos(d)
    assert T[2] == pytest.approx(Tz, rel=1e-12)


def test_bad_inputs(elements):
    pos, load = elements
    with pytest.raises(InputError, match="velocity"):
        pos.evaluate(WheelsetState(velocity=0.0))
    with pytest.raises(InputError, match="loads"):
        load.evaluate(WheelsetState())
    with pytest.raises(InputError, match="mode"):
        contact_element(mode="elastic")
    with pytest.raises(InputError, match="yaw"):
        pos.evaluate(WheelsetState(yaw=0.2))
    assert pos.evaluate(WheelsetState(vertical_position=3e-4)).to_xarray()["force"].attrs[
        "units"] == "N"
