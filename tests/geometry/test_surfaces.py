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


def test_turned_roller_undeformed_distance_surface(testbank):
    """A roller's deviation (dz, roll) turns and lowers its profile, revolved about
    the fixed axis (``height``: the search's surface, a flat profile becomes a
    cone).  ``turn = "surface"`` (CONTACT's undeformed distance) turns the revolved
    roller as read instead: a flat profile gives the cylinder of radius R whose
    axis is turned by roll about the profile origin and lowered by dz, in closed
    form z = dz + (R - sqrt(R^2 - x^2) + sin(roll) y) / cos(roll), slope tan(roll);
    both surfaces share the turned profile on x = 0.  (test-rollers3 case 11, R
    0.4 m, roll 0.2 rad: 1.336 um apart 6 mm along x on the contact line, as
    CONTACT's undeformed distances of its cases 11 and 10 differ.)"""
    flat = read_profile(testbank / "profiles" / "flat_plane.prr")
    R, dz, roll = 0.4, 0.3e-3, 0.2
    cone = RollerSurface(flat, R, 0.1, deviation=(dz, roll))
    tilted = RollerSurface(flat, R, 0.1, deviation=(dz, roll), turn="surface")
    s = 0.1 + np.array([0.0, 0.006, -0.006, 0.02, 0.0, -0.03])
    y = np.array([-0.0203, -0.0203, 0.01, -0.02, 0.015, 0.03])
    x = s - 0.1
    z, d = tilted.gap_height(s, y)
    c, sn = math.cos(roll), math.sin(roll)
    assert np.allclose(z, dz + (R - np.sqrt(R * R - x * x) + sn * y) / c, rtol=0, atol=1e-13)
    assert np.allclose(d, sn / c, rtol=0, atol=1e-12)
    # the search's surface and railcontact's rule: the cone
    zc, dc = cone.height(s, y)
    assert tilted.height(s, y)[0] == pytest.approx(zc, abs=0)
    assert cone.gap_height(s, y)[0] == pytest.approx(zc, abs=0)
    assert tilted.profile.z_at(0.01) == pytest.approx(cone.profile.z_at(0.01), abs=0)
    on_line = x == 0.0
    assert z[on_line] == pytest.approx(zc[on_line], abs=1e-13)
    # the undeformed distance along x on the contact line (normal to the turned
    # profile) of test-rollers3 case 11 (dz = 0, the contact at y = -19.855 mm of
    # the turned profile, -20.2588 mm of the profile as read):
    # x^2 / 2 (1 / R - cos(roll) / rho), rho the cone's section radius
    cone = RollerSurface(flat, R, 0.1, deviation=(0.0, roll))
    tilted = RollerSurface(flat, R, 0.1, deviation=(0.0, roll), turn="surface")
    rail = PlacedRail(tilted, "roller", lateral_position=0.2, vertical_position=1e-3)
    yc = -0.019855
    rho = R - float(cone.profile.z_at(yc))
    n = np.array([-sn, c])                            # the turned profile's normal (y, z)
    lam = []
    for surf in (rail, PlacedRail(cone, "roller", lateral_position=0.2, vertical_position=1e-3)):
        P = np.array([0.2 + yc, 1e-3 + float(cone.profile.z_at(yc))])
        t = 0.0
        for _ in range(30):                           # along n from P at x = 6 mm
            zz, dd = surf.gap_height(np.array(0.1 + 0.006), np.array(P[0] + t * n[0]))
            t -= (P[1] + t * n[1] - float(zz)) / (n[1] - float(dd) * n[0])
        lam.append(t)
    assert lam[0] - lam[1] == pytest.approx(0.5 * 0.006 ** 2 * (1 / R - c / rho), rel=2e-3)
    assert lam[0] - lam[1] == pytest.approx(1.336e-6, abs=2e-9)
    # a deviation that neither turns nor lowers leaves the surface as it is
    assert not RollerSurface(flat, R, deviation=(0.0, 0.0), turn="surface").tilted
    with pytest.raises(InputError, match="roller.turn = 'axis'"):
        RollerSurface(flat, R, turn="axis")
