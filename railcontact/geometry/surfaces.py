"""Rail surfaces in three dimensions: prismatic rails, rails that vary along the
track (slices), rollers; and their placement.

A surface gives the height z(s, y) [m] (down, rail-profile coordinates) and its
lateral slope dz/dy at track positions s [m] and lateral profile positions y [m]
(positive to the field side of a right rail); NaN where there is no surface.

* :class:`ProfileSurface`: one profile, the same at every s (a straight rail).
* :class:`~railcontact.geometry.sliced_surface.SlicedSurface`: a rail given by
  slices, interpolated as CONTACT does (:mod:`railcontact.geometry.sliced_surface`).
* :class:`RollerSurface`: a roller of a roller rig, the profile revolved about an
  axis along y at depth ``radius`` below its crown: z(x, y) = R - sqrt((R - z_p(y))^2
  - x^2), x = s - ``position``.

:class:`PlacedRail` places a surface in the side frame of a wheel (y to the field
side, z down): its profile origin at (``lateral_position``, ``vertical_position``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError, ProfileError
from ..profiles.profile import Profile


class ProfileSurface:
    """A prismatic rail: the profile ``profile`` at every position s."""

    def __init__(self, profile: Profile):
        if profile.kind != "rail":
            raise ProfileError(f"profile {profile.name!r} is a wheel profile; expected a rail")
        self.profile = profile
        self.name = profile.name

    def height(self, s, y):
        """Height z [m] and slope dz/dy [-] at (s, y) (arrays of one shape)."""
        s, y = np.broadcast_arrays(np.asarray(s, float), np.asarray(y, float))
        z, d = self.profile.z_and_slope(y)
        return np.asarray(z, float), np.asarray(d, float)

    def section(self, s: float) -> Profile:
        """The cross-section at s."""
        return self.profile

    def s_range(self) -> tuple:
        return (-math.inf, math.inf)


class RollerSurface:
    """A roller of radius ``radius`` [m] at its crown (the profile origin), its axis
    along y at track position ``position`` [m], carrying the lateral profile
    ``profile`` (a rail profile: z down into the roller)."""

    def __init__(self, profile: Profile, radius: float, position: float = 0.0):
        if profile.kind != "rail":
            raise ProfileError(f"profile {profile.name!r} is a wheel profile; expected the "
                               "roller's (rail) profile")
        if not (isinstance(radius, (int, float)) and math.isfinite(radius) and 0.02 <= radius <= 10):
            raise InputError(f"roller.radius = {radius!r} m: expected a radius in [0.02, 10] m")
        self.profile, self.radius, self.position = profile, float(radius), float(position)
        self.name = f"roller {profile.name}"

    def height(self, s, y):
        s, y = np.broadcast_arrays(np.asarray(s, float), np.asarray(y, float))
        zp, dp = self.profile.z_and_slope(y)
        rho = self.radius - zp
        x = s - self.position
        root = np.sqrt(np.maximum(rho * rho - x * x, 0.0))
        with np.errstate(invalid="ignore", divide="ignore"):
            z = np.where(np.abs(x) < rho, self.radius - root, np.nan)
            dz = rho * dp / root
        return z, dz

    def section(self, s: float) -> Profile:
        return self.profile

    def rolling_radius(self, y) -> np.ndarray:
        """Radius [m] of the roller at lateral profile position y."""
        return self.radius - np.asarray(self.profile.z_at(y), float)

    def s_range(self) -> tuple:
        return (self.position - self.radius, self.position + self.radius)


@dataclass
class PlacedRail:
    """A rail surface placed in a wheel's side frame (y to the field side, z down).

    Attributes
    ----------
    surface : ProfileSurface, SlicedSurface or RollerSurface
    name : str
        Label of the rail in results ("wing rail", "nose", "check rail", ...).
    lateral_position, vertical_position : float
        Position [m] of the rail-profile origin in the side frame.
    lateral_range : (float, float) or None
        The part [m] of the surface (rail-profile y) that belongs to this rail: one
        set of slices may hold several rails side by side (a crossing's wing rail
        and nose with the flangeway between), each named on its own.
    angular_velocity : float
        For a roller: its angular velocity [rad/s] about +y (CONTACT's VPITCH_ROL;
        positive with the wheel's negative pitch velocity in pure rolling); 0 for a
        rail (at rest).
    """

    surface: object
    name: str = "rail"
    lateral_position: float = 0.75
    vertical_position: float = 0.0
    angular_velocity: float = 0.0
    lateral_range: tuple | None = None

    def __post_init__(self):
        if self.lateral_range is not None:
            lo, hi = (float(v) for v in self.lateral_range)
            if not lo < hi:
                raise InputError(f"rail {self.name!r}: lateral_range = {self.lateral_range!r}:"
                                 " expected [y_min, y_max] with y_min < y_max (m)")
            self.lateral_range = (lo, hi)

    def height(self, s, y):
        """Surface height z [m] and slope dz/dy in the side frame at track position s
        and side-frame lateral position y (NaN outside the rail's lateral range)."""
        yr = np.asarray(y, float) - self.lateral_position
        z, d = self.surface.height(s, yr)
        if self.lateral_range is not None:
            out = (yr < self.lateral_range[0]) | (yr > self.lateral_range[1])
            z = np.where(out, np.nan, z)
            d = np.where(out, np.nan, d)
        return z + self.vertical_position, d

    @property
    def is_roller(self) -> bool:
        return isinstance(self.surface, RollerSurface)

    def section(self, s: float) -> Profile:
        return self.surface.section(s)

    def rolling_radius(self, y_profile: float) -> float:
        """The rail's radius in the rolling direction at a lateral profile position
        (a roller's radius there; inf for a rail)."""
        if self.is_roller:
            return float(self.surface.rolling_radius(y_profile))
        return math.inf
