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
  - x^2), x = s - ``position``; a deviated profile (turned and lowered) revolved
  about the same axis, and for the undeformed distance either that surface or
  CONTACT's: the roller as read, turned and lowered as a whole (``turn``).

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


#: the values of :class:`RollerSurface`'s ``turn`` (``ContactRules.roller_turn``)
ROLLER_TURNS = ("profile", "surface")


def _revolved(profile: Profile, radius: float, x, y):
    """The profile revolved about the axis along y at depth ``radius`` below its
    origin: height z [m] (down) and slope dz/dy at (x, y) (NaN beyond the section's
    radius)."""
    zp, dp = profile.z_and_slope(y)
    rho = radius - zp
    root = np.sqrt(np.maximum(rho * rho - x * x, 0.0))
    with np.errstate(invalid="ignore", divide="ignore"):
        z = np.where(np.abs(x) < rho, radius - root, np.nan)
        dz = rho * dp / root
    return z, dz


class RollerSurface:
    """A roller of radius ``radius`` [m] at its crown (the profile origin), its axis
    along y at track position ``position`` [m], carrying the lateral profile
    ``profile`` (a rail profile: z down into the roller).

    ``deviation`` (dz [m], roll [rad]) or None deviates the roller's profile
    (CONTACT's DZRAIL, DROLLR of a roller): the profile turned by roll about +x
    about its origin (a positive roll lowers the field side), then lowered by dz,
    and revolved about the roller's axis, which stays: the surface of
    :meth:`height` (the contact search) and of the roller's kinematics (it turns
    about its axis; a flat profile turned becomes a cone).  ``turn`` picks the
    surface of the undeformed distance (:meth:`gap_height`):

    - ``"profile"`` (railcontact's): the same surface;
    - ``"surface"`` (CONTACT's, its ``m_wr_undefdist``: the profile as read
      revolved, then the whole surface turned and lowered with the rail's marker):
      the undeviated roller turned by roll about +x through the profile origin and
      lowered by dz, its axis tilted (a flat profile: a cylinder of radius R with a
      tilted axis).  Both surfaces share the turned profile at x = 0; along x the
      cone's curvature is cos(roll) / (R - z_p) at its section's radius, the tilted
      cylinder's 1 / R (test-rollers3 case 11: 1/412 against 1/400 per mm, the
      undeformed distance 1.34 um larger 6 mm from the contact line).

    ``profile`` is the deviated profile (that of the search); ``profile_as_read`` the
    one given.
    """

    def __init__(self, profile: Profile, radius: float, position: float = 0.0,
                 deviation: tuple | None = None, turn: str = "profile"):
        if profile.kind != "rail":
            raise ProfileError(f"profile {profile.name!r} is a wheel profile; expected the "
                               "roller's (rail) profile")
        if not (isinstance(radius, (int, float)) and math.isfinite(radius) and 0.02 <= radius <= 10):
            raise InputError(f"roller.radius = {radius!r} m: expected a radius in [0.02, 10] m")
        if turn not in ROLLER_TURNS:
            raise InputError(f"roller.turn = {turn!r}: expected 'profile' (the turned profile "
                             "revolved about the roller's axis) or 'surface' (CONTACT's: the "
                             "revolved roller turned as a whole)")
        self.profile_as_read = profile
        self.deviation = None
        if deviation is not None:
            dz, roll = (float(v) for v in deviation)
            if not (math.isfinite(dz) and math.isfinite(roll)):
                raise InputError(f"roller.profile_deviation = {deviation!r}: expected finite "
                                 "[dz, roll] (m, rad)")
            self.deviation = (dz, roll)
            profile = profile.rotated(-roll).shifted(0.0, dz)
        self.profile, self.radius, self.position = profile, float(radius), float(position)
        self.turn = turn
        self.name = f"roller {profile.name}"

    def height(self, s, y):
        """Height z [m] and slope dz/dy [-] at (s, y) of the roller's surface (its
        deviated profile revolved about its axis)."""
        s, y = np.broadcast_arrays(np.asarray(s, float), np.asarray(y, float))
        return _revolved(self.profile, self.radius, s - self.position, y)

    @property
    def tilted(self) -> bool:
        """Whether the undeformed distance follows CONTACT's turned surface (a
        deviation that turns or lowers, and ``turn = "surface"``)."""
        return self.turn == "surface" and self.deviation is not None \
            and any(v != 0.0 for v in self.deviation)

    def gap_height(self, s, y, iterations: int = 30):
        """Height z [m] and slope dz/dy [-] at (s, y) of the surface of the
        undeformed distance (``turn``): :meth:`height`, or CONTACT's turned
        surface, z solved by Newton's method from the search's surface (both meet
        on the contact line, x = 0)."""
        z0, d0 = self.height(s, y)
        if not self.tilted:
            return z0, d0
        s, y = np.broadcast_arrays(np.asarray(s, float), np.asarray(y, float))
        dz, roll = self.deviation
        c, sn = math.cos(roll), -math.sin(roll)     # the profile's turn by -roll
        x = s - self.position
        # a point (y, z) of the turned surface comes from (c y - sn (z - dz), sn y + c
        # (z - dz)) of the roller as read
        z = np.where(np.isfinite(z0), z0, 0.0)
        for _ in range(iterations):
            zd = z - dz
            h, hy = _revolved(self.profile_as_read, self.radius, x, c * y - sn * zd)
            step = (sn * y + c * zd - h) / (c + sn * hy)
            z = z - step
            if np.all(~np.isfinite(step) | (np.abs(step) < 1e-14)):
                break
        h, hy = _revolved(self.profile_as_read, self.radius, x, c * y - sn * (z - dz))
        with np.errstate(invalid="ignore", divide="ignore"):
            slope = (c * hy - sn) / (c + sn * hy)
        bad = ~np.isfinite(h)
        return np.where(bad, np.nan, z), np.where(bad, np.nan, slope)

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
        return self._placed(yr, *self.surface.height(s, yr))

    def gap_height(self, s, y):
        """:meth:`height` of the surface of the undeformed distance: a roller's
        (:meth:`RollerSurface.gap_height`, CONTACT's turned surface under its rule),
        else the rail's surface itself."""
        if not self.is_roller:
            return self.height(s, y)
        yr = np.asarray(y, float) - self.lateral_position
        return self._placed(yr, *self.surface.gap_height(s, yr))

    def _placed(self, yr, z, d):
        """The surface's height z and slope d at its own lateral positions ``yr``
        [m] placed in the side frame: NaN outside the lateral range, the vertical
        position added."""
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
