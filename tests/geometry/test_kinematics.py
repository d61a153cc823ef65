"""Kinematic creepages (railcontact.geometry.kinematics) of a yawed, yawing and
sliding wheelset, against the closed form of the rigid wheelset's motion and its
small-angle textbook form (xi = dr/r0 + l psi'/V, eta = psi - y'/V (tread), phi = -sin(delta)/r0
- psi' cos(delta)/V on the right wheel; docs/conventions.md)."""

import math
from types import SimpleNamespace

import pytest

from railcontact.geometry.kinematics import kinematic_creepage

R0, V, L = 0.46, 30.0, 0.75           # nominal radius, speed, half the contact spacing


def creep(side, delta, dr, yaw=0.0, lateral_velocity=0.0, yaw_rate=0.0, pitch=None):
    pose = SimpleNamespace(yaw=yaw, roll=0.0, lateral_shift=0.0, vertical=0.0)
    n = (0.0, -math.sin(delta), math.cos(delta))
    return kinematic_creepage(side, (0.0, L, dr), n, delta, pose, R0, V,
                              -V / R0 if pitch is None else pitch, lateral_velocity, yaw_rate)


def test_pure_rolling_on_the_nominal_radius_has_no_creepage():
    (xi, eta, phi), Vm, _ = creep("right", 0.0, 0.0)
    assert (xi, eta, phi) == pytest.approx((0.0, 0.0, 0.0), abs=1e-15)
    assert Vm == pytest.approx(V, rel=1e-15)


def test_yawed_yawing_sliding_wheelset_closed_form():
    """Rigid motion: omega = (-sin psi, cos psi, 0) Omega + (0, 0, psi'); Q - O =
    (0, l, r) with r = r0 + dr; creepages of the rail relative to the wheel over the
    mean rolling velocity."""
    psi, dr, delta, yd, psid, Om = 4e-3, 1.5e-3, -0.05, 0.2, 0.1, -V / R0 * 1.001
    (xi, eta, phi), Vm, dphi = creep("right", delta, dr, psi, yd, psid, Om)
    r = R0 + dr
    w0, w1, w2 = -math.sin(psi) * Om, math.cos(psi) * Om, psid
    rot = w1 * r - w2 * L
    Vm_ = 0.5 * (V + abs(rot))
    assert Vm == pytest.approx(Vm_, rel=1e-14)
    assert xi == pytest.approx(-(V + rot) / Vm_, rel=1e-12)
    v1, v2 = yd - w0 * r, w0 * L
    assert eta == pytest.approx(-(v1 * math.cos(delta) + v2 * math.sin(delta)) / Vm_, rel=1e-12)
    assert phi == pytest.approx((w1 * math.sin(delta) - w2 * math.cos(delta)) / Vm_, rel=1e-12)
    assert dphi == pytest.approx((w1 * math.cos(delta) + w2 * math.sin(delta)) / Vm_, rel=1e-12)


def test_small_angle_textbook_creepages():
    psi, dr, delta, yd, psid = 1e-4, 2e-5, -0.03, 0.0015, 1e-3
    (xi, eta, phi), _, _ = creep("right", delta, dr, psi, yd, psid)
    assert xi == pytest.approx(dr / R0 + L * psid / V, rel=2e-3)
    # the lateral direction tilted by delta picks up the yaw's vertical slip psi l / r0
    assert eta == pytest.approx(psi - yd / V - psi * L * math.sin(delta) / R0, rel=2e-3)
    assert phi == pytest.approx(-math.sin(delta) / R0 - psid * math.cos(delta) / V, rel=1e-3)


def test_left_and_right_wheels_mirror():
    """A yawed wheelset on mirrored contacts: the same xi and eta on both wheels,
    opposite conicity spin."""
    right = creep("right", -0.03, 1e-3, yaw=2e-3)[0]
    left = creep("left", 0.03, 1e-3, yaw=2e-3)[0]
    assert left[0] == pytest.approx(right[0], rel=1e-12)
    assert left[1] == pytest.approx(right[1], rel=1e-12)
    assert left[2] == pytest.approx(-right[2], rel=1e-12)
    assert right[2] == pytest.approx(math.sin(0.03) / R0, rel=2e-3)
