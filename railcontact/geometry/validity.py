"""Where a wheel-rail result leaves the range in which its models hold.

Two checks, applied to every patch of a wheel-rail result
(:func:`patch_validity`):

* **Flange climb and derailment.**  A wheel in flange contact is held laterally by
  its flange face; beyond the steepest part of the face (towards the tip) the
  contact angle falls as the wheel moves further out, the lateral force that holds
  it falls with it, and the wheel is climbing (Nadal's limit is reached at the
  steepest angle).  A contact point on the flange beyond that part is flagged as
  *flange climb*.  A contact within ``TIP_ZONE`` of the flange tip's radius, or
  beyond the tip, means the wheel stands on its flange tip: *derailment*, a state
  with no equilibrium on track, which makes the case unconverged.
* **Elastic half-space.**  Every model here (Hertz, the strip models, Kalker's exact
  theory) treats wheel and rail as half-spaces, which needs the contact to be small
  against the radii of curvature of the surfaces.  Each patch reports
  ``halfspace_ratio``: the larger of (lateral half-width / smallest lateral radius of
  curvature of wheel and rail under the patch) and (longitudinal half-length / wheel
  rolling radius), each half-width taken along the direction its radius curves in
  (a long, narrow patch on the 13 mm gauge corner is planar across its width).
  Above ``HALF_SPACE_LIMIT`` = 0.5 the patch is flagged: the surface normal then
  turns by more than asin(0.5) = 30 degrees between the patch's centre and edge,
  and the planar contact of the half-space models no longer describes it (a case
  for scale: docs/tuning.md, section "Geometry search").
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from ..profiles.profile import Profile

#: a wheel whose contact lies within this [m] of its flange tip's radius (or beyond
#: the tip) stands on its flange: derailment (qR is measured 2 mm below the tip)
TIP_ZONE = 2e-3

#: the steepest part of the flange face: where its angle is within this [rad] of the
#: largest (S1002's face is a straight line at 70 degrees)
STEEPEST_BAND = math.radians(0.5)

#: patches whose size-to-radius ratio exceeds this are flagged (see the module notes)
HALF_SPACE_LIMIT = 0.5


@dataclass(frozen=True)
class Flange:
    """The flange of a wheel profile, in its coordinates [m] (y to the field side,
    the flange at y < 0; z down, away from the axle).

    Attributes
    ----------
    tip_y, tip_z : the flange tip (the largest z)
    steep_y : the tip-side end of the steepest part of the flange face
    max_angle : the largest flange angle [rad]
    """

    tip_y: float
    tip_z: float
    steep_y: float
    max_angle: float


def _find_flange(profile: Profile) -> Flange | None:
    y = np.linspace(profile.y_min, min(0.0, profile.y_max), 4001)
    z = np.asarray(profile.z_at(y), float)
    if not np.isfinite(z).all():
        return None
    i_tip = int(np.argmax(z))
    if z[i_tip] - float(profile.z_at(0.0)) < 0.01 or i_tip == y.size - 1:
        return None                                   # no flange (a roller, a rail)
    face = slice(i_tip, y.size)
    angle = np.arctan(np.abs(np.asarray(profile.slope(y[face]), float)))
    steep = np.flatnonzero(angle >= angle.max() - STEEPEST_BAND)
    return Flange(float(y[i_tip]), float(z[i_tip]), float(y[face][steep[0]]),
                  float(angle.max()))


#: flanges of the profiles seen, by identity (profiles are immutable; bounded)
_FLANGES: dict = {}


def flange(profile: Profile) -> Flange | None:
    """The flange of a wheel profile (None where the profile has none)."""
    if profile.kind != "wheel":
        return None
    hit = _FLANGES.get(id(profile))
    if hit is None or hit[0] is not profile:
        if len(_FLANGES) > 64:
            _FLANGES.clear()
        hit = _FLANGES[id(profile)] = (profile, _find_flange(profile))
    return hit[1]


def contact_size(normal) -> tuple:
    """Half-length and half-width (a, b) [m] of a normal solution's contact: the
    ellipse's semi-axes, else half the extents of the contact on its grid."""
    if normal.semi_axes is not None:
        return float(normal.semi_axes[0]), float(normal.semi_axes[1])
    mask = normal.contact
    if not mask.any():
        return 0.0, 0.0
    xs, ys = normal.x[mask.any(axis=1)], normal.y[mask.any(axis=0)]
    return (0.5 * float(xs.max() - xs.min() + normal.dx),
            0.5 * float(ys.max() - ys.min() + normal.dy))


#: the samples of a profile's curvature over a patch's half-width (:func:`_smallest_radius`)
CURVATURE_SAMPLES = 21


@njit(cache=True, nogil=True)
def _largest_curvature(breaks, coefs, y0, half, y_min, y_max):
    """The largest |curvature| [1/m] of a cubic piecewise polynomial (``breaks``,
    ``coefs`` as scipy's PPoly holds them) at ``CURVATURE_SAMPLES`` points evenly over
    y0 +- half (numpy's linspace), those within [y_min, y_max] and the breaks; -1
    where there is none."""
    n = CURVATURE_SAMPLES
    start, stop = y0 - half, y0 + half
    step = (stop - start) / (n - 1)
    nb = breaks.size - 1
    best = -1.0
    for i in range(n):
        y = start + i * step if i < n - 1 else stop
        if not (y_min <= y <= y_max) or not (breaks[0] <= y <= breaks[nb]):
            continue
        k = np.searchsorted(breaks, y, side="right") - 1
        k = min(max(k, 0), nb - 1)
        t = y - breaks[k]
        d1 = (3.0 * coefs[0, k] * t + 2.0 * coefs[1, k]) * t + coefs[2, k]
        d2 = 6.0 * coefs[0, k] * t + 2.0 * coefs[1, k]
        c = abs(d2 / (1.0 + d1 * d1) ** 1.5)
        if c == c and c > best:
            best = c
    return best


def _smallest_radius(profile: Profile, y0: float, half: float) -> float:
    """Smallest radius of curvature [m] of a profile over y0 +- half (its own y):
    the curvature at ``CURVATURE_SAMPLES`` points (compiled on a cubic spline's
    coefficients, as :meth:`Profile.curvature` evaluates them)."""
    coefs = getattr(profile, "_coefs", None)
    if coefs is not None and coefs.ndim == 2 and coefs.shape[0] == 4:
        k = _largest_curvature(profile._breaks, coefs, float(y0), float(half),
                               profile.y_min, profile.y_max)
        if k < 0.0:
            return math.inf
        return 1.0 / k if k > 0 else math.inf
    ys = np.linspace(y0 - half, y0 + half, CURVATURE_SAMPLES)
    ys = ys[(ys >= profile.y_min) & (ys <= profile.y_max)]
    if ys.size == 0:
        return math.inf
    k = np.abs(np.asarray(profile.curvature(ys), float))
    k = k[np.isfinite(k)]
    return 1.0 / k.max() if k.size and k.max() > 0 else math.inf


def halfspace_ratio(geometry, normal, wheel: Profile, rail: Profile,
                    rail_rolling_radius: float = math.inf) -> float:
    """Size of a patch against the radii of curvature of the surfaces it touches
    (see the module notes): max(b / R_lateral, a / R_rolling), R_rolling the
    smaller of the wheel's rolling radius and ``rail_rolling_radius`` (a roller's
    radius; a rail is straight along the track).  For a rail that varies along the
    track, ``rail`` is its cross-section at the patch."""
    a, b = contact_size(normal)
    if not (a > 0 and b > 0):
        return 0.0
    # the patch's lateral half-width along each profile's own y (the tangent plane is
    # inclined by the contact angle against the profile's lateral axis)
    half = b * abs(math.cos(geometry.contact_angle))
    r_lat = min(_smallest_radius(rail, geometry.y_rail, half),
                _smallest_radius(wheel, geometry.y_wheel, half))
    r_roll = geometry.rolling_radius if math.isfinite(geometry.rolling_radius) else math.inf
    r_roll = min(r_roll, abs(rail_rolling_radius))
    return max(b / r_lat, a / r_roll if r_roll > 0 else 0.0)


def flange_state(geometry, wheel: Profile) -> str | None:
    """``"derailment"``, ``"flange climb"`` or None for a patch on ``wheel``."""
    fl = flange(wheel)
    y, z = geometry.y_wheel, geometry.z_wheel
    if fl is None or not (math.isfinite(y) and math.isfinite(z)):
        return None
    if y < fl.tip_y or z >= fl.tip_z - TIP_ZONE:
        return "derailment"
    if y < fl.steep_y:
        return "flange climb"
    return None


def patch_validity(geometry, normal, wheel: Profile, rail: Profile) -> tuple:
    """(derailed, warnings, halfspace_ratio) of one wheel-rail patch."""
    state = flange_state(geometry, wheel)
    ratio = halfspace_ratio(geometry, normal, wheel, rail)
    side = geometry.side
    warnings = []
    if state == "derailment":
        warnings.append(f"derailment: the {side} wheel stands on its flange tip (contact at "
                        f"{geometry.y_wheel * 1e3:.1f} mm on the wheel, rolling radius "
                        f"{geometry.rolling_radius * 1e3:.1f} mm); no equilibrium on track")
    elif state == "flange climb":
        fl = flange(wheel)
        warnings.append(f"flange climb: the {side} wheel's contact ({geometry.y_wheel * 1e3:.1f}"
                        f" mm) lies beyond the steepest part of its flange "
                        f"({math.degrees(fl.max_angle):.1f} deg, up to {fl.steep_y * 1e3:.1f} mm)"
                        f"; contact angle {math.degrees(abs(geometry.contact_angle)):.1f} deg")
    if ratio > HALF_SPACE_LIMIT:
        warnings.append(f"half-space: the {side} patch is large against the radii of curvature "
                        f"(size/radius {ratio:.2f} > {HALF_SPACE_LIMIT})")
    return state == "derailment", warnings, ratio


def nadal_limit(flange_angle: float, friction: float) -> float:
    """Nadal's limit of Y/Q [-] for flange climb: (tan b - mu) / (1 + mu tan b) with
    b the largest flange angle [rad] and mu the friction coefficient (Nadal 1908;
    EN 14363 uses it with b = 70 deg, mu = 0.36: 1.2)."""
    t = math.tan(flange_angle)
    return (t - friction) / (1.0 + friction * t)
