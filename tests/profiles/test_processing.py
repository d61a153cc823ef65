"""Profiles processed along the arc length, as CONTACT processes them."""

import math

import numpy as np
import pytest

from railcontact.core.errors import ProfileError
from railcontact.profiles import Profile, ProfileOptions, Smoothing, process_points
from railcontact.profiles.processing import (find_kinks, remove_zigzags, smooth_points,
                                             visible_surface, z_points_down)


def _sine_line(wavelength, amplitude=1e-5, length=0.12, step=2.5e-4):
    """A straight line along y with a sine of the given wavelength in z [m]."""
    y = np.arange(0.0, length + step / 2, step) - length / 2
    return y, amplitude * np.sin(2 * np.pi * y / wavelength)


@pytest.mark.parametrize("ratio, lo, hi", [(1.0, 0.45, 0.55), (4.0, 0.99, 1.01),
                                           (1 / 3, 0.0, 0.02)])
def test_weighted_spline_halves_the_filter_wavelength(ratio, lo, hi):
    """CONTACT's weighted smoothing spline, lambda = (L / 2 pi)^4: a fluctuation of
    wavelength L keeps half its amplitude (the transfer 1 / (1 + lambda k^4)), a
    four times longer one all of it, a three times shorter one almost nothing."""
    L = 4e-3
    y, z = _sine_line(ratio * L)
    ys, zs = smooth_points(y, z, Smoothing("weighted", L))
    mid = np.abs(ys) < 0.03                      # away from the free ends
    gain = np.ptp(zs[mid]) / np.ptp(z[np.abs(y) < 0.03])
    assert lo <= gain <= hi


def test_unweighted_lambda_is_the_weighted_one_over_the_spacing():
    """CONTACT's user guide: at uniform point spacing ds the unweighted spline with
    lambda smooths as the weighted one with lambda * ds (its lambda depends on the
    sampling density)."""
    y, z = _sine_line(8e-3)
    ds = y[1] - y[0]
    lam = 1e-8                                     # 10 mm^3
    a = smooth_points(y, z, Smoothing("unweighted", lam))
    L = 2 * math.pi * (lam * ds) ** 0.25
    b = smooth_points(y, z, Smoothing("weighted", L))
    mid = np.abs(a[0]) < 0.05                      # the end weights differ (half intervals)
    assert 0.2 < np.ptp(a[1][mid]) / np.ptp(z) < 0.9
    np.testing.assert_allclose(a[1][mid], b[1][mid], atol=1e-3 * np.ptp(z))


def test_zigzag_of_a_stitched_point_is_replaced_by_its_mean():
    y = np.linspace(0, 0.05, 51)
    z = 1e-3 * np.sin(40 * y)
    # a point repeated with a 10 um offset backwards: two turns of almost 180 deg
    yy = np.insert(y, 21, y[20] - 1e-5)
    zz = np.insert(z, 21, z[20] + 1e-6)
    ny, nz, n = remove_zigzags(yy, zz)
    assert n == 1 and ny.size == y.size
    assert np.all(np.diff(ny) > 0)
    assert nz[20] == pytest.approx(0.5 * (z[20] + z[20] + 1e-6))


def test_kinks_are_isolated_corners_not_roughness():
    # a V with its corner at y = 0, and a rough stretch of alternating points
    y = np.linspace(-0.02, 0.02, 81)
    z = 0.5 * np.abs(y)
    rough = (y > 0.008) & (y < 0.014)
    z[rough] += 2e-4 * (-1.0) ** np.arange(rough.sum())
    k = find_kinks(y, z)
    assert list(y[k[1:-1]]) == [pytest.approx(0.0)]
    assert k[0] == 0 and k[-1] == y.size - 1
    assert find_kinks(y, z, high=math.pi).tolist() == [0, y.size - 1]


def test_smoothing_keeps_a_kink_in_place():
    y = np.linspace(-0.02, 0.02, 161)
    z = 0.5 * np.abs(y) + 2e-5 * np.sin(3000 * y)
    k = find_kinks(y, z)
    ys, zs = smooth_points(y, z, Smoothing("unweighted", 1e-8), k)
    i = np.argmin(np.abs(ys))
    assert ys[i] == pytest.approx(0.0, abs=1e-12) and zs[i] == pytest.approx(z[80], abs=1e-12)
    # without the kink the corner is rounded off
    ys2, zs2 = smooth_points(y, z, Smoothing("unweighted", 1e-8))
    assert np.interp(0.0, ys2, zs2) > 2e-5


def _folded_rail():
    """A rail head whose gauge face folds back below the corner (an undercut)."""
    t = np.linspace(0, np.pi, 200)
    y_head = -0.03 * np.cos(t)                    # crown from y = -30 to +30 mm
    z_head = -0.01 * np.sin(t) + 0.01
    # gauge face: from the corner (-30 mm, 10 mm) it bulges out 1 mm at 15 mm, then
    # runs back in under the head to -26 mm at 30 mm
    zf = np.linspace(0.03, 0.0105, 80)
    yf = np.where(zf < 0.015, -0.03 - 0.001 * np.sin(np.pi / 2 * (zf - 0.01) / 0.005),
                  -0.031 + 0.005 * (zf - 0.015) / 0.015)
    return np.concatenate((yf, y_head)), np.concatenate((zf, z_head))


def test_a_folded_gauge_face_gives_the_surface_seen_from_above():
    y, z = _folded_rail()
    assert np.any(np.diff(y) < 0)
    yv, zv = visible_surface(y, z, "rail")
    assert np.all(np.diff(yv) > 0)
    # every point of the curve lies on or below (z down) the visible surface
    assert np.all(z >= np.interp(y, yv, zv) - 1e-12)
    # the undercut below the leftmost point of the face (1 mm out at 15 mm) is hidden
    left = y.argmin()
    assert yv[0] == pytest.approx(y[left], abs=2e-5) and zv[0] == pytest.approx(z[left], abs=3e-4)
    assert np.interp(-0.0305, yv, zv) < 0.015
    p = Profile(y, z, kind="rail", name="folded")
    assert p.y_min == pytest.approx(yv[0]) and np.all(np.isfinite(p.z_at(yv[1:-1])))


def test_a_wheel_is_seen_from_the_rail():
    y, z = _folded_rail()
    yv, zv = visible_surface(y, -z, "wheel")       # mirrored in z: a "wheel" bulging down
    assert np.all(-z <= np.interp(y, yv, zv) + 1e-12)


def test_a_curve_crossing_itself_is_an_error():
    y = np.array([0.0, 0.01, 0.02, 0.03, 0.015, 0.015, 0.04, 0.05, 0.06])
    z = np.array([0.0, 0.0, 0.0, 0.0, -0.002, 0.002, 0.001, 0.0, 0.0])
    with pytest.raises(ProfileError, match="crosses itself"):
        visible_surface(y, z, "rail", "loop")


def test_vertical_axis_detection():
    y, z = _folded_rail()
    assert z_points_down(y, z, "rail") and not z_points_down(y, -z, "rail")
    from railcontact.profiles import s1002
    w = s1002()
    assert z_points_down(w.y, w.z, "wheel") and not z_points_down(w.y, -w.z, "wheel")


def test_options_mirror_and_scale():
    y, z = _folded_rail()
    base = process_points(y, z, "rail")
    m = process_points(-y[::-1] * 1e3, z[::-1] * 1e3, "rail",
                       ProfileOptions(mirror_y=True, scale=1e-3))
    np.testing.assert_allclose(m.y, base.y, atol=1e-12)
    np.testing.assert_allclose(m.z, base.z, atol=1e-12)
    up = process_points(y, -z, "rail", ProfileOptions(mirror_z=True))
    np.testing.assert_allclose(up.z, base.z, atol=1e-12)


def test_options_from_a_case_table():
    o = ProfileOptions.from_table({"mirror_y": True, "mirror_z": "auto", "scale": 25.4,
                                   "smoothing": {"method": "unweighted", "lambda": 1e-8},
                                   "kinks": {"high": 0.6, "width": 1e-3}}, "rail")
    assert o.mirror_y and o.mirror_z is None and o.scale == 25.4
    assert o.smoothing == Smoothing("unweighted", 1e-8)
    assert o.kink_high == 0.6 and o.low == pytest.approx(0.12) and o.kink_width == 1e-3
    assert ProfileOptions.from_table({"smoothing": 0.005}, "wheel").smoothing == \
        Smoothing("weighted", 0.005)
    for bad, match in (({"mirror_y": 1}, "true, false"), ({"smoothing": {"lam": 1}}, "unknown"),
                       ({"smoothing": {"method": "weighted"}}, "needs length"),
                       ({"kinks": {"hi": 1}}, "kinks"), ({"scale": -1.0}, "scale"),
                       ({"smoothing": {"method": "cubic", "lambda": 1.0}}, "method")):
        with pytest.raises(ProfileError, match=match):
            ProfileOptions.from_table(bad, "rail")


def test_chord_spline_through_the_points_along_their_chord_length():
    """CONTACT's parametric spline (ChordSpline): y(s), z(s) natural cubic through
    every point, s the summed chord length, 0 where y = 0 (y increasing strictly);
    on points of a circle of radius 20 mm every 1 mm (the flange root's curvature)
    it lies within 5 nm of the circle between them five intervals or more from a
    free end (0.16 um in the second interval: the natural end conditions), and s(y)
    inverts y(s) to 1e-12 m."""
    from railcontact.profiles.processing import ChordSpline
    t = np.linspace(-0.6, 0.6, 25)                    # 1.0 mm chords on R = 20 mm
    R = 0.02
    y, z = R * np.sin(t), R * (1.0 - np.cos(t))
    cs = ChordSpline(y, z)
    chord = 2 * R * math.sin(0.025)
    assert cs.s == pytest.approx(chord * np.arange(-12, 13), abs=1e-15)
    py, pz = cs.point(cs.s)
    assert py == pytest.approx(y, abs=1e-15) and pz == pytest.approx(z, abs=1e-15)
    mid = 0.5 * (cs.s[5:-6] + cs.s[6:-5])             # away from the free ends
    my, mz = cs.point(mid)
    assert np.max(np.abs(np.hypot(my, mz - R) - R)) < 5e-9
    for v in (-3.3e-3, 0.0, 7.1e-3):
        assert cs.point(cs.s_at_y(v))[0] == pytest.approx(v, abs=1e-12)
    # beyond the profile: the nearer end's s, as CONTACT's spline_get_s_at_y
    assert cs.s_at_y(1.0) == cs.s[-1] and cs.s_at_y(-1.0) == cs.s[0]


def test_chord_spline_of_a_folded_curve():
    """Points folding back in y (a measured gauge face turning under): the origin of
    s is the point nearest (0, 0) (CONTACT: y not strictly increasing), and s(y) is
    taken on the part seen from above (a rail: the smallest z)."""
    from railcontact.profiles.processing import ChordSpline
    yf = np.array([-0.0300, -0.0310, -0.0320])         # the fold: y decreasing
    zf = np.array([0.0200, 0.0190, 0.0180])
    yh = np.linspace(-0.0325, 0.03, 126)               # then the head, y increasing
    zh = 0.016 * (yh / 0.0325) ** 2
    y, z = np.concatenate((yf, yh)), np.concatenate((zf, zh))
    cs = ChordSpline(y, z, kind="rail")
    i0 = int(np.argmin(y * y + z * z))
    assert cs.s[i0] == 0.0
    s = cs.s_at_y(-0.0305)                             # on the head, not the fold
    py, pz = cs.point(s)
    assert py == pytest.approx(-0.0305, abs=1e-12)
    assert pz == pytest.approx(0.016 * (0.0305 / 0.0325) ** 2, abs=1e-7)
