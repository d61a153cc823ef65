"""Contact locus: the lowest point of each wheel circle relative to the rail.

For straight track the rail is a cylinder along x, so for every wheel cross-section
(lateral wheel-profile position y_w, radius r0 + z_w) the vertical gap to the rail
is minimal at one angle theta of the wheel circle.  With the wheelset axes R
(columns: axle-fixed x, y, z) the stationarity of the vertical gap gives

    tan(theta) = (s R10 - R20) / (s R12 - R22),

with s the rail slope dz/dy at the point, iterated because s depends on where the
point falls.  This uses the wheel's surface of revolution with yaw and roll (no 2-D
cross-section approximation); the gap along the locus is the vertical distance.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .track import Track, Wheelset, rotation

#: sampling step of the wheel profile along the locus [m]
LOCUS_STEP = 2.5e-5


@lru_cache(maxsize=32)
def _wheel_samples(wheel, step):
    n = int((wheel.y_max - wheel.y_min) / step) + 1
    yw = np.linspace(wheel.y_min, wheel.y_max, n)
    return yw, wheel.z_at(yw)


@dataclass
class Locus:
    """Contact locus of one side, in the side frame (lateral axis to the field side).

    Arrays along the wheel profile: ``y_wheel``, ``z_wheel`` (profile coordinates),
    ``theta`` (angle on the wheel circle), ``point`` (3 x n, the wheel point),
    ``y_rail`` (rail-profile coordinate below it), ``gap`` (vertical, m, negative
    means interpenetration; +inf outside the rail), ``slope`` (rail dz/dy).
    """

    y_wheel: np.ndarray
    z_wheel: np.ndarray
    theta: np.ndarray
    point: np.ndarray
    y_rail: np.ndarray
    gap: np.ndarray
    slope: np.ndarray
    origin: np.ndarray          # wheelset centre in the side frame
    axes: np.ndarray            # rotation matrix of the wheelset in the side frame

    @property
    def i_min(self) -> int:
        return int(np.argmin(self.gap))

    @property
    def gap_min(self) -> float:
        return float(self.gap[self.i_min])


def side_pose(side: str, lateral_shift: float, vertical: float, roll: float, yaw: float):
    """Wheelset pose expressed in the side frame (mirrored for the left side)."""
    if side == "right":
        return lateral_shift, vertical, roll, yaw
    return -lateral_shift, vertical, -roll, -yaw


def compute_locus(wheelset: Wheelset, track: Track, side: str, lateral_shift: float,
                  vertical: float, roll: float, yaw: float, step: float = LOCUS_STEP) -> Locus:
    """Contact locus and vertical gap for one side at the given wheelset pose."""
    wheel, rail = wheelset.wheel(side), track.rail(side)
    y_ws, z_ws, roll_s, yaw_s = side_pose(side, lateral_shift, vertical, roll, yaw)
    r0 = wheelset.nominal_radius
    yw, zw = _wheel_samples(wheel, step)
    eta = wheelset.wheel_offset + yw
    rho = r0 + zw
    R = rotation(yaw_s, roll_s)
    O = np.array([0.0, y_ws, z_ws - r0])
    y_off = track.rail_offset(side)
    s = np.zeros_like(yw)
    for _ in range(3):
        theta = np.arctan((s * R[1, 0] - R[2, 0]) / (s * R[1, 2] - R[2, 2]))
        st, ct = np.sin(theta), np.cos(theta)
        P = (O[:, None] + eta[None, :] * R[:, 1:2]
             + rho[None, :] * (st[None, :] * R[:, 0:1] + ct[None, :] * R[:, 2:3]))
        yr = P[1] - y_off
        s = np.nan_to_num(rail.slope(yr))
    zr = rail.z_at(yr)
    gap = np.where(np.isfinite(zr), zr - P[2], np.inf)
    return Locus(yw, zw, theta, P, yr, gap, s, O, R)
