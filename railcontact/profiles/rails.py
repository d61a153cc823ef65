"""Rail head profiles of EN 13674-1 from their arc construction.

Each head is a chain of circular arcs, each tangent to the one before it, from
the crown to the gauge corner, followed by the head flank inclined 1:20 to the
vertical (``REFERENCES.md`` sections 1.2-1.4; dimensions from EN 13674-1:2017 as
cited there).  The construction uses y from the rail's axis of symmetry and z
downwards from the top of the crown; the other half is the mirror image.

A rail as mounted is inclined (canted) towards the track centre; the built-in
profiles are returned in the mounted position, with their origin at the highest
point of the inclined head (the convention of the Manchester benchmark files).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..core.errors import ProfileError
from .profile import Profile


@dataclass(frozen=True)
class HeadGeometry:
    """Arc chain of a rail head: radii [mm] and the y [mm] where each arc ends.

    The last arc runs until its tangent reaches the flank inclination (1:20).
    """

    name: str
    radii: tuple
    y_ends: tuple       # one fewer than radii
    flank_slope: float = 20.0   # dz/dy of the head flank (1:20 to the vertical)
    depth: float = 36.0         # how far down the flank is generated [mm]


#: flank parts steeper than this [rad] are not part of a profile z(y)
MAX_FLANK_ANGLE = math.radians(89.5)

HEADS = {
    "60E1": HeadGeometry("60E1", (300.0, 80.0, 13.0), (10.228, 26.0265)),
    "54E1": HeadGeometry("54E1", (300.0, 80.0, 13.0), (10.012, 24.8635)),
    "60E2": HeadGeometry("60E2", (200.0, 70.0, 16.0, 8.0), (11.889, 24.4565, 35.387)),
}
ALIASES = {"UIC60": "60E1", "UIC54": "54E1"}


def head_points(geom: HeadGeometry, step: float = 0.05):
    """Half head contour (y >= 0) of an upright rail, in mm.

    Returns arrays (y, z) from the crown centre line down the field-side flank.
    Arc i has centre C_i and the point at angle phi is C_i + R_i (sin phi, -cos phi).
    """
    ys, zs = [], []
    cy, cz = 0.0, geom.radii[0]          # centre of the crown arc
    phi0 = 0.0
    for i, R in enumerate(geom.radii):
        if i < len(geom.y_ends):
            phi1 = math.asin((geom.y_ends[i] - cy) / R)
        else:
            phi1 = math.atan(geom.flank_slope)
        n = max(int(R * (phi1 - phi0) / step), 2)
        phi = np.linspace(phi0, phi1, n + 1)[:-1]
        ys.append(cy + R * np.sin(phi))
        zs.append(cz - R * np.cos(phi))
        if i + 1 < len(geom.radii):
            Rn = geom.radii[i + 1]
            cy, cz = cy + (R - Rn) * math.sin(phi1), cz - (R - Rn) * math.cos(phi1)
        phi0 = phi1
    # flank: straight line from the end of the last arc
    y0 = cy + geom.radii[-1] * math.sin(phi0)
    z0 = cz - geom.radii[-1] * math.cos(phi0)
    zf = np.linspace(z0, geom.depth, max(int((geom.depth - z0) / step), 2))
    ys.append(y0 + (zf - z0) / geom.flank_slope)
    zs.append(zf)
    return np.concatenate(ys), np.concatenate(zs)


@lru_cache(maxsize=32)
def rail_profile(name: str = "60E1", inclination: float = math.atan(1 / 40),
                 step: float = 5e-5) -> Profile:
    """Built-in rail head profile, mounted with the given inclination.

    Parameters
    ----------
    name : {"60E1", "54E1", "60E2"} (aliases "UIC60", "UIC54")
        Rail section of EN 13674-1.
    inclination : float
        Rail inclination (cant) [rad] towards the track centre: atan(1/40)
        (default), atan(1/20), or 0 for an upright rail.
    step : float
        Point spacing along the contour [m].

    Returns
    -------
    Profile
        Rail profile of a right rail (y positive to the field side, z down), origin
        at the highest point of the inclined head.
    """
    key = ALIASES.get(name.upper(), name.upper())
    if key not in HEADS:
        raise ProfileError(f"rail profile {name!r}: unknown; expected one of "
                           f"{sorted(HEADS) + sorted(ALIASES)}")
    if not (isinstance(inclination, (int, float)) and abs(inclination) <= 0.1):
        raise ProfileError(f"rail inclination {inclination!r} rad: expected |value| <= 0.1 rad "
                           "(1:40 = 0.025, 1:20 = 0.05)")
    y, z = head_points(HEADS[key], step * 1e3)
    y = np.concatenate((-y[:0:-1], y)) * 1e-3
    z = np.concatenate((z[:0:-1], z)) * 1e-3
    c, s = math.cos(inclination), math.sin(inclination)
    y, z = c * y + s * z, -s * y + c * z          # same rotation as Profile.rotated
    # keep the part of the contour that is a function z(y) with flanks steeper than
    # MAX_FLANK_ANGLE cut off (at 1:20 inclination the gauge flank is vertical)
    steep = np.abs(np.arctan2(np.diff(z), np.diff(y))) > MAX_FLANK_ANGLE
    top = int(np.argmin(z))
    lo = np.flatnonzero(steep[:top])
    hi = np.flatnonzero(steep[top:])
    i0 = lo[-1] + 1 if lo.size else 0
    i1 = top + hi[0] + 1 if hi.size else y.size
    prof = Profile(y[i0:i1], z[i0:i1], kind="rail", name=key)
    return prof.with_origin_at_top()
