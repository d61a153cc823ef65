"""Where a result leaves the range of its models: flange climb, derailment, half-space."""

import math

import numpy as np
import pytest

import railcontact as rc
from railcontact.geometry.validity import HALF_SPACE_LIMIT, flange, nadal_limit
from railcontact.profiles import rail_profile, s1002


def test_s1002_flange():
    """S1002's flange: the tip 28 mm below the tape circle and 55 mm from it; its
    face's steepest part is the 70 degree line."""
    fl = flange(s1002())
    assert fl.tip_z == pytest.approx(0.028, abs=1e-6)
    assert fl.tip_y == pytest.approx(-0.055, abs=2e-5)
    assert math.degrees(fl.max_angle) == pytest.approx(70.0, abs=0.01)
    assert -0.041 < fl.steep_y < -0.039
    assert flange(rail_profile("60E1")) is None


def _bodies(wheel_lateral, rail_lateral=0.013, force=111.5e3):
    return rc.case_from_dict({
        "bodies": {"radii": {"wheel_rolling": 0.46, "wheel_lateral": wheel_lateral,
                             "rail_rolling": math.inf, "rail_lateral": rail_lateral},
                   "normal_force": force},
        "solver": {"normal": "hertz", "tangential": "fastsim"}})


def test_half_space_ratio_of_a_bodies_case():
    """The ratio is the patch's lateral half-width over the smallest lateral radius
    (here the rail's 13 mm) or its half-length over the rolling radius, whichever is
    larger; above HALF_SPACE_LIMIT the result warns, and stays converged.  Seed 003's
    crossing nose (wheel -18 mm, rail 13 mm, 111.5 kN): 0.16; a wheel that conforms
    more closely spreads the patch across the rail's corner."""
    ratios = {}
    for R in (-0.018, -0.0135, -0.0132):
        res = rc.solve(_bodies(R))
        (p,) = res.patches
        a, b = p.normal.semi_axes
        assert p.halfspace_ratio == pytest.approx(max(b / 0.013, a / 0.46), rel=1e-12)
        warned = any("half-space" in w for w in res.warnings)
        assert warned == (p.halfspace_ratio > HALF_SPACE_LIMIT)
        assert res.converged
        ratios[R] = p.halfspace_ratio
    assert ratios[-0.018] == pytest.approx(0.163, abs=0.001)
    assert ratios[-0.0135] < HALF_SPACE_LIMIT < ratios[-0.0132]


def test_half_space_ratio_of_wheel_rail_patches():
    """Tread contact on S1002/60E1 at 0 mm: a 20 mm wide patch on the rail crown,
    whose radius falls from 300 to 80 mm across it (ratio 0.12); flange contact at
    6 mm: a narrow patch on the 13 mm gauge corner."""
    base = {"wheel": {"profile": "S1002"}, "rail": {"profile": "60E1", "inclination": 0.025},
            "wheelset": {"vertical_force": 70e3, "side": "right"},
            "solver": {"normal": "hertz", "tangential": "fastsim"}}
    ratios = []
    for shift in (0.0, 0.006):
        base["wheelset"]["lateral_shift"] = shift
        res = rc.solve(rc.case_from_dict(base))
        ratios.append([p.halfspace_ratio for p in res.patches])
        assert all(np.isfinite(r) and 0 < r < HALF_SPACE_LIMIT for r in ratios[-1])
    assert ratios[0][0] == pytest.approx(0.124, abs=0.01)


def test_nadal_limit():
    """EN 14363's flange-climb limit: 70 degrees and mu = 0.36 give Y/Q = 1.2."""
    assert nadal_limit(math.radians(70.0), 0.36) == pytest.approx(1.2, abs=2e-3)
    assert nadal_limit(math.radians(70.0), 0.0) == pytest.approx(math.tan(math.radians(70)))


def test_a_run_over_nadals_limit_is_flagged():
    """A dynamics run whose Y/Q on a wheel in flange contact exceeds Nadal's limit
    says so (wheelset, wheel, the largest |Y/Q| and when); the same Y/Q without
    flange contact, or under the limit, does not."""
    from types import SimpleNamespace

    from railcontact.dynamics.simulation import _validity
    # (the system's flange angle: its tables' smallest, or the online contact's)
    sysm = SimpleNamespace(flange_angle=math.radians(70.0), friction=0.36)
    t = np.linspace(0.0, 1.0, 11)
    YQ = np.zeros((11, 2, 2))
    YQ[4, 1, 1] = -1.5                                    # wheelset 2, right wheel
    loaded = np.ones_like(YQ, dtype=bool)
    (w,) = _validity(sysm, t, YQ, loaded)
    assert "wheelset 2, right wheel" in w and "1.50" in w and "t = 0.400 s" in w
    assert _validity(sysm, t, YQ, ~loaded) == []
    assert _validity(sysm, t, 0.7 * YQ, loaded) == []
    sysm.flange_angle = math.nan                           # a conical table: no flange
    assert _validity(sysm, t, YQ, loaded) == []


def test_smallest_radius_compiled_as_the_profiles_curvature():
    """The half-space check's smallest radius of curvature, compiled on the profile's
    spline coefficients, is that of Profile.curvature at the same 21 points to
    round-off (1e-14 relative), inside, across and beyond a profile's ends."""
    from railcontact.geometry import validity
    rng = np.random.default_rng(3)
    for prof in (s1002(), rail_profile("60E1")):
        for _ in range(300):
            y0 = rng.uniform(prof.y_min - 0.004, prof.y_max + 0.004)
            half = rng.uniform(0.0, 0.008)
            ys = np.linspace(y0 - half, y0 + half, validity.CURVATURE_SAMPLES)
            ys = ys[(ys >= prof.y_min) & (ys <= prof.y_max)]
            k = np.abs(np.asarray(prof.curvature(ys), float)) if ys.size else np.zeros(0)
            k = k[np.isfinite(k)]
            want = 1.0 / k.max() if k.size and k.max() > 0 else math.inf
            got = validity._smallest_radius(prof, y0, half)
            if math.isinf(want):
                assert math.isinf(got)
            else:
                assert got == pytest.approx(want, rel=1e-14)
