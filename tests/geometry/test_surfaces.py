"""Rail surfaces: prismatic rails, rollers, placement (the sliced rail:
test_sliced_surface.py)."""

import math

import numpy as np
import pytest

from railcontact.core.errors import InputError
from railcontact.geometry.surfaces import PlacedRail, ProfileSurface, RollerSurface
from railcontact.profiles.io import read_profile


def test_roller_surface_is_the_revolved_profile(testbank):
    p = read_profile(testbank / "profiles" / "circ_r100.prr")
    roller = RollerSurface(p, 0.4)
    x = np.array([0.0, 0.01, -0.03, 0.02])
    y = np.array([0.0, 0.0, 0.01, -0.02])
    z, dz = roller.height(x, y)
    rho = 0.4 - p.z_at(y)
    assert np.allclose(z, 0.4 - np.sqrt(rho ** 2 - x ** 2), atol=1e-12)
    assert roller.rolling_radius(0.0) == pytest.approx(0.4)
    rail = PlacedRail(roller, "roller", lateral_position=0.2, vertical_position=1e-3,
                      angular_velocity=0.25)
    z2, _ = rail.height(x, y + 0.2)
    assert np.allclose(z2, z + 1e-3) and rail.is_roller
    assert rail.rolling_radius(0.0) == pytest.approx(0.4)
    flat = PlacedRail(ProfileSurface(read_profile(testbank / "profiles" / "flat_plane.prr")))
    assert flat.rolling_radius(0.0) == math.inf and not flat.is_roller
    with pytest.raises(InputError, match="roller.radius"):
        RollerSurface(p, 0.0)
