"""Contact locus and minimum gap (railcontact.geometry.locus)."""

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from railcontact.geometry import Track, Wheelset
from railcontact.geometry.locus import compute_locus, depth_at, min_gap, side_pose
from railcontact.geometry.track import rotation
from railcontact.profiles import rail_profile, s1002


def test_min_gap_on_a_locus_window_equals_the_full_search():
    """Searching only the wheel samples of a locus at a roll within 1e-4 rad gives the
    same minimum gap, to the bit, as the search over the whole wheel (tread, flange
    root and flange positions)."""
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    for y in (-3e-3, 2e-3, 6e-3, 8e-3):
        for side in ("left", "right"):
            loc = compute_locus(ws, tr, side, y, 0.0, 2e-4, 1e-3)
            i0, i1 = loc.samples
            assert 0 <= i0 < i1 and loc.y_wheel.size == i1 - i0
            for roll in (2e-4, 2.5e-4, 1.1e-4):
                full = min_gap(ws, tr, side, y, 0.0, roll, 1e-3)
                assert np.isfinite(full)
                assert min_gap(ws, tr, side, y, 0.0, roll, 1e-3, samples=(i0, i1)) == full


def test_locus_on_the_samples_of_a_nearby_locus():
    """A locus computed on the wheel samples of one at a nearby pose, without the
    coarse pass, holds every sample within its window and has the same gaps as the
    full computation there; where the samples do not hold the window (cut to its
    middle here), the full computation runs instead."""
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    for y, side in ((2e-3, "right"), (6e-3, "right"), (-3e-3, "left")):
        z = min_gap(ws, tr, side, y, 0.0, 2e-4, 1e-3) + 5e-5
        first = compute_locus(ws, tr, side, y, z, 2e-4, 1e-3, window=2.5e-4)
        full = compute_locus(ws, tr, side, y, z + 1e-7, 2.2e-4, 1e-3, window=2.5e-4)
        near = compute_locus(ws, tr, side, y, z + 1e-7, 2.2e-4, 1e-3, window=2.5e-4,
                             samples=first.samples)
        assert near.samples == first.samples
        inside = full.gap <= full.gap_min + 2.5e-4
        yw = full.y_wheel[inside]
        sel = np.isin(near.y_wheel, yw)
        assert sel.sum() == yw.size
        np.testing.assert_array_equal(near.gap[sel], full.gap[inside])
        i0, i1 = first.samples
        mid = (i0 + (i1 - i0) // 3, i1 - (i1 - i0) // 3)
        cut = compute_locus(ws, tr, side, y, z + 1e-7, 2.2e-4, 1e-3, window=2.5e-4,
                            samples=mid)
        assert cut.samples == full.samples
        np.testing.assert_array_equal(cut.gap, full.gap)


def test_locus_gap_is_the_lowest_point_of_each_wheel_circle():
    """Each locus sample's vertical gap is the (local) minimum over the wheel
    circle's angle of rail height minus wheel point height, to 1e-12 m, with yaw
    (where the angle depends on the rail slope and is found by iteration) and
    without; tread and flange contact, 0.1 mm interpenetration, samples on rail
    slopes up to 3 (the gauge corner)."""
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    rail = tr.rail("right")
    checked = 0
    for y, roll, yaw in ((2e-3, 2e-4, 0.0), (2e-3, 2e-4, 0.02), (7e-3, -1e-3, 6e-3)):
        z = min_gap(ws, tr, "right", y, 0.0, roll, yaw) + 1e-4
        loc = compute_locus(ws, tr, "right", y, z, roll, yaw, window=5e-4)
        y_ws, z_ws, roll_s, yaw_s = side_pose("right", y, z, roll, yaw)
        R = rotation(yaw_s, roll_s)
        O = np.array([0.0, y_ws, z_ws - ws.nominal_radius])
        for i in np.flatnonzero(np.abs(loc.slope) <= 3.0)[::10]:
            eta = ws.wheel_offset + loc.y_wheel[i]
            rho = ws.nominal_radius + loc.z_wheel[i]

            def gap(theta):
                P = O + eta * R[:, 1] + rho * (math.sin(theta) * R[:, 0]
                                               + math.cos(theta) * R[:, 2])
                return float(rail.z_at(P[1] - tr.rail_offset("right"))) - P[2]

            t0 = loc.theta[i]
            best = minimize_scalar(gap, bounds=(t0 - 0.01, t0 + 0.01), method="bounded",
                                   options={"xatol": 1e-10})
            assert abs(loc.gap[i] - best.fun) < 1e-12
            assert abs(loc.theta[i] - best.x) < 1e-6
            checked += 1
        assert loc.gap.min() == pytest.approx(-1e-4, abs=1e-9)
    assert checked > 100


def test_depth_at_a_vertical_position():
    """The interpenetration at a prescribed vertical position is that position less
    the touching one (the gap at z = 0), on either side; negative off the rail."""
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    for side in ("left", "right"):
        g0 = min_gap(ws, tr, side, 0.002, 0.0, 0.0, 0.001)
        assert depth_at(ws, tr, side, 0.002, 1e-4, 0.0, 0.001) == pytest.approx(1e-4 - g0,
                                                                                abs=1e-15)
        assert depth_at(ws, tr, side, 0.002, g0 - 1e-4, 0.0, 0.001) == pytest.approx(-1e-4)


def test_contact_locus_normal_is_perpendicular_to_the_rolling_direction():
    """CONTACT's locus (``Wheelset.locus = "contact"``): at each sample the wheel
    surface's normal (cross product of the surface's tangents in theta and along
    the profile, by central differences) has no x component, to 1e-6, with yaw and
    roll, on the tread and on the flange; without yaw it is the lowest-point locus
    to the bit; with yaw its gaps where they interpenetrate are never below the
    lowest points' (each wheel circle's minimum) and meet them where the
    interpenetration is deepest, within 10 nm."""
    wheel = s1002()
    tr = Track(rail_profile("60E1", math.atan(1 / 40)))
    low, con = Wheelset(wheel), Wheelset(wheel, locus="contact")
    for y, roll, yaw in ((2e-3, 2e-4, 0.02), (7e-3, -1e-3, 6e-3)):
        z = min_gap(low, tr, "right", y, 0.0, roll, yaw) + 1e-4
        a = compute_locus(low, tr, "right", y, z, roll, yaw, window=5e-4)
        b = compute_locus(con, tr, "right", y, z, roll, yaw, window=5e-4)
        y_ws, z_ws, roll_s, yaw_s = side_pose("right", y, z, roll, yaw)
        R = rotation(yaw_s, roll_s)
        O = np.array([0.0, y_ws, z_ws - con.nominal_radius])

        def point(theta, yw):
            rho = con.nominal_radius + float(wheel.z_at(yw))
            return O + (con.wheel_offset + yw) * R[:, 1] + rho * (
                math.sin(theta) * R[:, 0] + math.cos(theta) * R[:, 2])

        checked = 0
        for i in range(5, b.y_wheel.size - 5, 2):
            t, yw, h = b.theta[i], b.y_wheel[i], 1e-6
            if abs(math.sin(t)) >= 0.5:
                continue                       # clipped (near-vertical sections)
            dt = point(t + h, yw) - point(t - h, yw)
            dy = point(t, yw + h) - point(t, yw - h)
            n = np.cross(dt, dy)
            assert abs(n[0]) <= 1e-6 * np.linalg.norm(n)
            checked += 1
        assert checked > 20
        # same samples: the lowest points lie at or below CONTACT's
        k0 = max(a.samples[0], b.samples[0])
        k1 = min(a.samples[1], b.samples[1])
        ga = a.gap[k0 - a.samples[0]:k1 - a.samples[0]]
        gb = b.gap[k0 - b.samples[0]:k1 - b.samples[0]]
        ok = np.isfinite(ga) & np.isfinite(gb) & (ga < 0.0)
        assert ok.sum() > 20
        assert np.all(ga[ok] <= gb[ok] + 1e-12)
        assert b.gap_min == pytest.approx(a.gap_min, abs=1e-8)
    # no yaw: both loci the same
    z = min_gap(low, tr, "right", 3e-3, 0.0, 1e-3, 0.0) + 1e-4
    a = compute_locus(low, tr, "right", 3e-3, z, 1e-3, 0.0)
    b = compute_locus(con, tr, "right", 3e-3, z, 1e-3, 0.0)
    assert np.array_equal(a.gap, b.gap) and np.array_equal(a.point, b.point)


@pytest.mark.parametrize("rule, yaw", [("lowest", 0.0), ("contact", 0.0), ("contact", 6e-3)])
def test_locus_kernel_is_its_samples_computed_one_at_a_time(rule, yaw):
    """The locus kernels look the rail profile up in the previous sample's piece,
    written out in their loops, and call ``ppoly_at`` only where that piece does
    not hold the point: where each sample's locus does not depend on its
    neighbours' (the lowest points without yaw, CONTACT's locus always), the
    kernel over 1600 samples of the wheel's tread and flange gives every sample
    bit for bit its locus computed alone (one sample: the lookup always through
    ``ppoly_at``), the sample order reversed too."""
    from railcontact.geometry.locus import _locus_kernel, _wheel_samples, _wheel_slopes
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    wheel, rail = ws.wheel("right"), tr.rail("right")
    _, _, eta, rho = _wheel_samples(wheel, 2.5e-5, ws.wheel_offset, ws.nominal_radius)
    sl = slice(eta.size // 2 - 800, eta.size // 2 + 800)
    eta, rho = np.ascontiguousarray(eta[sl]), np.ascontiguousarray(rho[sl])
    slopes = (np.ascontiguousarray(_wheel_slopes(wheel, 2.5e-5)[sl]) if rule == "contact"
              else None)
    R = rotation(yaw, 1e-3)
    O = np.array([0.0, 4e-3, -ws.nominal_radius - 1e-4])
    y_off = tr.rail_offset("right")

    def kernel(i):
        return _locus_kernel(eta[i], rho[i], None if slopes is None else slopes[i], R, O,
                             y_off, rail._breaks, rail._coefs)

    whole = kernel(slice(None))
    backwards = kernel(slice(None, None, -1))
    assert np.isfinite(whole[3]).sum() > 1000                   # over the rail
    assert np.unique(np.searchsorted(rail._breaks, whole[2][np.isfinite(whole[2])])).size > 20
    for i in range(0, eta.size, 7):
        alone = kernel(slice(i, i + 1))
        for a, w, b in zip(alone, whole, backwards):
            assert np.array_equal(a[..., 0], w[..., i], equal_nan=True)
            assert np.array_equal(a[..., 0], b[..., eta.size - 1 - i], equal_nan=True)


@pytest.mark.parametrize("rule, yaw", [("lowest", 0.0), ("lowest", 6e-3), ("contact", 6e-3)])
def test_locus_gaps_are_the_locus_kernels_gaps(rule, yaw):
    """The minimum-gap searches' kernel (``_locus_gaps``: the lowest points without
    their angle theta) gives the gaps of the locus kernel bit for bit, over every
    sample of the wheel (on and off the rail)."""
    from railcontact.geometry.locus import (_locus_gaps, _locus_kernel, _wheel_samples,
                                            _wheel_slopes)
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    wheel, rail = ws.wheel("right"), tr.rail("right")
    _, _, eta, rho = _wheel_samples(wheel, 2.5e-5, ws.wheel_offset, ws.nominal_radius)
    slopes = _wheel_slopes(wheel, 2.5e-5) if rule == "contact" else None
    args = (eta, rho, slopes, rotation(yaw, 1e-3),
            np.array([0.0, 4e-3, -ws.nominal_radius - 1e-4]), tr.rail_offset("right"),
            rail._breaks, rail._coefs)
    gaps = _locus_gaps(*args)
    full = _locus_kernel(*args)[3]
    assert np.isfinite(full).sum() > 1000 and np.isinf(full).any()
    assert np.array_equal(gaps, full)
