"""The kinematic creepages of a contact patch from the wheelset's motion."""

from __future__ import annotations

import math



def kinematic_creepage(side, q_side, n_tr, delta_tr, pose, r0, velocity, pitch_velocity,
              lateral_velocity, yaw_rate):
    """Kinematic creepages (xi, eta, phi), rolling velocity V and d(phi)/d(delta) at
    the contact point ``q_side`` (side frame), normal ``n_tr`` (track frame)."""
    sgn = 1.0 if side == "right" else -1.0
    # omega = R (0, pitch_velocity, 0) + (0, 0, yaw_rate), R the wheelset's axes
    cy, sy = math.cos(pose.yaw), math.sin(pose.yaw)
    cr, sr = math.cos(pose.roll), math.sin(pose.roll)
    w0 = -sy * cr * pitch_velocity
    w1 = cy * cr * pitch_velocity
    w2 = sr * pitch_velocity + yaw_rate
    # d = Q - O, O the wheelset centre; v = (V, lateral velocity, 0) + omega x d
    dx, dy, dz = (float(q_side[0]), sgn * float(q_side[1]) - pose.lateral_shift,
                  float(q_side[2]) - (pose.vertical - r0))
    rot0 = w1 * dz - w2 * dy
    v0 = velocity + rot0
    v1 = lateral_velocity + (w2 * dx - w0 * dz)
    v2 = w0 * dy - w1 * dx
    V = 0.5 * (abs(velocity) + abs(rot0))
    c, s = math.cos(delta_tr), math.sin(delta_tr)
    xi = -v0 / V
    eta = -(v1 * c + v2 * s) / V
    phi = -(w0 * n_tr[0] + w1 * n_tr[1] + w2 * n_tr[2]) / V
    # d(phi)/d(delta): the spin on a surface element whose normal is turned by
    # d(delta) about x is phi cos + dphi sin (n' = -s for the normal (0, -sin, cos))
    dphi = (w1 * c + w2 * s) / V
    return (float(xi), float(eta), float(phi)), float(V), float(dphi)
