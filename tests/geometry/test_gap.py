"""The gap evaluator of a wheel-rail patch (railcontact.geometry.gap) on S1002 /
60E1 1:40 at the central position: the wheel's rolling curvature, left-right
symmetry, the finite-difference curvatures and the guard against far surfaces."""

import math

import numpy as np
import pytest

from railcontact.geometry import Track, Wheelset, find_contact
from railcontact.geometry.gap import (DEEPEST_GAP, LINES_TOGETHER, GapEvaluator,
                                      SampledWheelGap, Spline, _rail_distance,
                                      _rail_distances, _wheel_newton, curvatures_fd,
                                      sample_gap_lines, sane_gap)
from railcontact.profiles import rail_profile, s1002


@pytest.fixture(scope="module")
def central():
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    c = find_contact(ws, tr, lateral_shift=0.0, vertical_force=6e4)
    return {p.side: p for p in c.patches}


def test_rolling_curvature_is_the_wheel_radius(central):
    """Along the rolling direction the rail is straight: h(x) - h(0) = x^2 / (2 r)
    to within the small tilt of the normal (cos delta ~ 1 - 6e-4)."""
    p = central["right"]
    assert isinstance(p.gap_function, GapEvaluator)
    r = p.rolling_radius
    x = np.array([-3e-3, -1e-3, 1e-3, 3e-3])
    rise = p.gap(x, np.zeros(4)) - p.gap(0.0, 0.0)
    assert rise == pytest.approx(x ** 2 / (2 * r), rel=1e-3)
    A, B, h0 = curvatures_fd(p.gap_function, 0.0, 0.0)
    assert A == pytest.approx(1 / (2 * r), rel=1e-3)
    assert h0 == pytest.approx(float(p.gap(0.0, 0.0)), abs=1e-15)
    assert 0 < B < A and -p.approach <= h0 < 0.0


def test_left_and_right_are_mirror_images_at_the_central_position(central):
    left, right = central["left"], central["right"]
    assert left.contact_angle == pytest.approx(-right.contact_angle, abs=1e-12)
    x = np.array([-2e-3, 0.0, 1.5e-3])
    y = np.array([-4e-3, 1e-3, 3e-3])
    # the patch y axis points to the right on both sides: mirror y
    assert left.gap(x, -y) == pytest.approx(right.gap(x, y), abs=1e-12)


def test_sane_gap_drops_far_surfaces():
    h = np.array([1e-4, -1e-4, DEEPEST_GAP * 0.99, DEEPEST_GAP * 1.01, -1.0])
    assert list(sane_gap(h)) == [1e-4, -1e-4, DEEPEST_GAP * 0.99, 1.0, 1.0]


@pytest.fixture(scope="module")
def flange_root():
    """The right wheel's patch at 7 mm lateral shift: S1002's flange root on the
    gauge corner of 60E1 (contact angle about 0.6 rad, concave wheel profile)."""
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    c = find_contact(ws, tr, lateral_shift=7e-3, vertical_force=6e4)
    return max(c.side_patches("right"), key=lambda p: abs(p.contact_angle))


def test_sampled_wheel_meets_the_exact_gap_at_its_samples(flange_root):
    """CONTACT's wheel sampling (SampledWheelGap): at the wheel samples (DS = 0.4 mm
    apart along the profile) the gap is the exact one."""
    g = flange_root
    assert abs(g.contact_angle) > 0.3
    sw = SampledWheelGap(g.gap_function, g.y_wheel, 4e-4)
    xs = np.array([-2e-3, 0.0, 1.5e-3])
    nodes = sw._nodes(xs, *sw._samples(2e-3))
    for x, row in zip(xs, nodes):
        y = row[np.abs(row) < 1.5e-3]
        assert sw(np.full(y.size, x), y) == pytest.approx(g.gap(np.full(y.size, x), y),
                                                          abs=1e-12)


def test_sampled_wheel_chord_sag(flange_root):
    """Midway between two samples the chord of the wheel lies off its arc by
    DS^2 / 8 times the wheel's second derivative w'' across the plane (w: the
    wheel's normal coordinate, rail distance minus gap; finite differences), within
    3 %: on S1002's flange root about 1 um."""
    g = flange_root
    ds = 4e-4
    sw = SampledWheelGap(g.gap_function, g.y_wheel, ds)
    ev = g.gap_function
    rail = Spline(ev.rail._breaks, ev.rail._coefs)
    x = 0.0
    row = sw._nodes(np.array([x]), *sw._samples(2e-3))[0]
    mids = 0.5 * (row[:-1] + row[1:])
    mids = mids[np.abs(mids) < 1.2e-3]
    d = 2e-5

    def w(y):
        tr = _rail_distances(np.ascontiguousarray(ev.sign * y), ev.patch_frame, rail)
        return tr - ev.points(np.full(y.size, x), y)

    w2 = (w(mids + d) - 2 * w(mids) + w(mids - d)) / d ** 2
    spacing = np.interp(mids, 0.5 * (row[:-1] + row[1:]), np.diff(row))
    sag = sw(np.full(mids.size, x), mids) - g.gap(np.full(mids.size, x), mids)
    assert sag == pytest.approx(-spacing ** 2 / 8 * w2, rel=0.03)
    assert np.all(np.abs(sag) > 1e-7) and np.all(np.abs(sag) < 2e-6)


def test_sampled_wheel_on_the_tread(central):
    """On S1002's tread (lateral radius of some 0.3 m) the chords lie within 0.1 um
    of the arc (the approach: 28 um)."""
    p = central["right"]
    sw = SampledWheelGap(p.gap_function, p.y_wheel, 4e-4)
    x, y = np.linspace(-4e-3, 4e-3, 9)[:, None], np.linspace(-3e-3, 3e-3, 13)[None, :]
    assert np.max(np.abs(sw(x, y) - p.gap(x, y))) < 1e-7


def test_sampled_wheel_counted_from_another_origin(flange_root):
    """The samples counted from another point's wheel coordinate (a transient CONTACT
    grid's origin): from a point a whole number of DS along the chord length the
    samples, and so the gap, are the reference's; from half a DS further they fall
    midway, where the chords' sag (S1002's flange root: some 0.1-1 um) now is."""
    g = flange_root
    ds = 4e-4
    base = SampledWheelGap(g.gap_function, g.y_wheel, ds)
    c = g.gap_function.wheel.chord_spline
    s_ref = c.s_at_y(g.y_wheel)
    same = SampledWheelGap(g.gap_function, g.y_wheel, ds, y_origin=c.point(s_ref + 7 * ds)[0])
    half = SampledWheelGap(g.gap_function, g.y_wheel, ds,
                           y_origin=c.point(s_ref + 7.5 * ds)[0])
    x, y = np.array([[0.0]]), np.linspace(-1e-3, 1e-3, 9)[None, :]
    assert same(x, y) == pytest.approx(base(x, y), abs=1e-12)
    row = base._nodes(np.array([0.0]), *base._samples(2e-3))[0]
    nodes = row[np.abs(row) < 1.2e-3][None, :]
    exact = g.gap(np.zeros_like(nodes), nodes)
    assert base(np.zeros_like(nodes), nodes) == pytest.approx(exact, abs=1e-12)
    sag = half(np.zeros_like(nodes), nodes) - exact
    assert np.all(np.abs(sag) > 2e-8) and np.all(np.abs(sag) < 2e-6)


def test_grid_lines_meet_the_pointwise_gap_across_a_steep_patch(flange_root):
    """On a grid over the whole rail head in a steep patch's tangent plane (contact
    angle about 1.1 rad; lines of 0.4 mm over 120 mm, as a combined tread-flange
    patch's potential area reaches), the line-by-line evaluation (each projection
    started from its neighbours') gives the pointwise gap: every projection is a
    converged one or a missed surface (1 m).  Before, an unconverged Newton iterate
    was returned as a distance (t1_zws_pos, case 1: an overlap of 4.4 mm beyond the
    rail's end collapsed the pressure) and a start extrapolated from the
    neighbouring lines lost lines inside the contact (82 of these points wrong)."""
    ev = flange_root.gap_function
    assert abs(flange_root.contact_angle) > 1.0
    x = np.linspace(-20e-3, 20e-3, 41)
    y = np.arange(-60e-3, 60e-3, 0.4e-3)
    lines = ev(x[:, None], y[None, :])
    X, Y = np.meshgrid(x, y, indexing="ij")
    points = ev.points(X.ravel(), Y.ravel()).reshape(X.shape)
    assert (points == 1.0).any() and (points < 0).any()   # missed, and overlapping
    assert np.array_equal(lines == 1.0, points == 1.0)
    assert lines == pytest.approx(points, abs=1e-9)
    assert lines.min() >= -flange_root.approach - 1e-6      # no overlap beyond the approach


def test_unconverged_projection_misses_the_surface():
    """A projection whose Newton steps do not converge gives a missing distance
    (NaN), never the last iterate: a profile z = y^3 - 2 y + 2 along the normal
    direction (0, 1, 0) from the origin, where Newton from 0 cycles between 0 and 1
    (the line meets the profile at y = -1.77 only)."""
    b0 = -3.0
    shifted = np.polynomial.Polynomial([2.0, -2.0, 0.0, 1.0])(np.polynomial.Polynomial([b0, 1.0]))
    coefs = np.ascontiguousarray(shifted.coef[::-1].reshape(4, 1))
    breaks = np.array([b0, 3.0])
    zero, n = np.zeros(3), np.array([0.0, 1.0, 0.0])
    tr, _ = _rail_distance(0.0, zero, n, n, 0.0, breaks, coefs, 0.0)
    assert math.isnan(tr)
    tr, _ = _rail_distance(0.0, zero, n, n, 0.0, breaks, coefs, -2.0)   # near the root
    assert tr ** 3 - 2 * tr + 2 == pytest.approx(0.0, abs=1e-9)


def _grid_one_point_at_a_time(ev, x, ys):
    """The gap of ``ev`` on the grid x[:, None], ys[None, :] (ys in the side's sense)
    solved point by point in Python through :func:`_rail_distance` and
    :func:`_wheel_newton`, line after line, each Newton started as the grid kernel
    documents it: along the line from its three points before, else from the last
    three lines quadratically (the last line's for the first lines), again from the
    plane where a start fails; an interval guess of -1 everywhere."""
    f = ev.frame
    C, t, n, y_off, Rt, O, e, r0 = f[0:3], f[3:6], f[6:9], f[9], f[10:19].reshape(3, 3), \
        f[19:22], f[22], f[23]
    nl = Rt @ n
    rb, rc, wb, wc = ev.rail._breaks, ev.rail._coefs, ev.wheel._breaks, ev.wheel._coefs
    h = np.empty((x.size, ys.size))
    w = np.zeros((ys.size, x.size))
    rails = [0.0, 0.0, 0.0]
    for j in range(ys.size):
        c = (3.0, -3.0, 1.0) if j >= 3 else (1.0 if j >= 1 else 0.0, 0.0, 0.0)
        start = c[0] * rails[0] + c[1] * rails[1] + c[2] * rails[2]
        r, _ = _rail_distance(ys[j], C, t, n, y_off, rb, rc, start, -1)
        if not math.isfinite(r) and start != 0.0:
            r, _ = _rail_distance(ys[j], C, t, n, y_off, rb, rc, 0.0, -1)
        if not math.isfinite(r):            # the line misses the rail: 1 m
            c = (0.0, 0.0, 0.0)
        rails = [r if math.isfinite(r) else 0.0, rails[0], rails[1]]
        d1 = C[1] + ys[j] * t[1] - O[1]
        d2 = C[2] + ys[j] * t[2] - O[2]
        for i in range(x.size):
            if i >= 3:
                start = 3.0 * w[j, i - 1] - 3.0 * w[j, i - 2] + w[j, i - 3]
            else:
                start = sum(c[m] * (w[j - 1 - m, i] if j - 1 - m >= 0 else 0.0)
                            for m in range(3))
            d0 = C[0] + x[i] - O[0]
            l0 = Rt[0, 0] * d0 + Rt[0, 1] * d1 + Rt[0, 2] * d2
            l1 = Rt[1, 0] * d0 + Rt[1, 1] * d1 + Rt[1, 2] * d2
            l2 = Rt[2, 0] * d0 + Rt[2, 1] * d1 + Rt[2, 2] * d2
            tw, _ = _wheel_newton(l0, l1, l2, nl[0], nl[1], nl[2], e, r0, wb, wc, start, -1)
            if not math.isfinite(tw) and start != 0.0:
                tw, _ = _wheel_newton(l0, l1, l2, nl[0], nl[1], nl[2], e, r0, wb, wc, 0.0, -1)
            assert math.isfinite(tw)
            w[j, i] = tw
            h[i, j] = r - tw if math.isfinite(r) else 1.0
    return h


@pytest.mark.parametrize("yaw", [0.0, 4e-3])
def test_grid_kernel_is_its_points_solved_one_at_a_time(yaw):
    """The grid kernel (lines walked side by side, the wheel's Newton written out in
    its loop, profile intervals guessed from the neighbours) gives each point of a
    grid bit for bit the value of solving it alone with the same start
    (:func:`_grid_one_point_at_a_time`), and within 1e-12 m that of the pointwise
    evaluation started from the tangent plane (``GapEvaluator.points``: Newton's
    quadratic convergence leaves kappa * NEWTON_TOL^2); the patches of a wheelset at
    7 mm lateral shift, with and without yaw (the right wheel's flange, the left's
    tread), on a 23 x 19 grid (lines not a multiple of LINES_TOGETHER), and each
    as it is with all of them stacked in one call (:func:`sample_gap_lines`)."""
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    c = find_contact(ws, tr, lateral_shift=7e-3, yaw=yaw, vertical_force=6e4)
    patches = c.patches
    assert len(patches) >= 2 and 19 % LINES_TOGETHER != 0
    x = np.linspace(-6e-3, 6e-3, 23)
    y = np.linspace(-5e-3, 4e-3, 19)
    for p in patches:
        ev = p.gap_function
        grid = ev(x[:, None], y[None, :])
        assert (grid < 0).any() and (grid > 0).any()            # overlap and apart
        assert np.array_equal(grid, _grid_one_point_at_a_time(ev, x, ev.sign * y))
        X, Y = np.meshgrid(x, y, indexing="ij")
        points = ev.points(X.ravel(), Y.ravel()).reshape(X.shape)
        assert np.abs(grid - points).max() <= 1e-12
    m = len(patches)
    both = sample_gap_lines(patches, x + 1e-3 * np.arange(m)[:, None], np.tile(y, (m, 1)))
    for k, p in enumerate(patches):
        assert np.array_equal(both[k], p.gap_function((x + k * 1e-3)[:, None], y[None, :]))


def _ppoly_newton_rail(ysp, C, t, n, y_off, rb, rc, tr):
    """:func:`_rail_distance`'s Newton in Python, every lookup through ``ppoly_at``
    from no guess."""
    from railcontact.geometry.gap import NEWTON_STEPS, NEWTON_TOL
    from railcontact.profiles.profile import ppoly_at
    p1, p2 = C[1] + ysp * t[1], C[2] + ysp * t[2]
    for _ in range(NEWTON_STEPS):
        zr, dzr, _ = ppoly_at(p1 + tr * n[1] - y_off, rb, rc, -1)
        step = (zr - (p2 + tr * n[2])) / (dzr * n[1] - n[2])
        tr -= step
        if not abs(step) > NEWTON_TOL:
            return tr
    return math.nan


def test_newton_lookups_written_out_are_ppoly_at_bit_for_bit(central):
    """:func:`_rail_distance` and :func:`_wheel_newton` evaluate the profile in the
    piece guessed where it holds the point, written out in their loops (else
    ``ppoly_at``): across a patch of the central position, 1 m to either side
    included (a miss: NaN), every guess of the piece (none, the first, the last,
    the right one) gives the distance bit for bit that of Newton with every lookup
    through ``ppoly_at`` from no guess, and the same piece."""
    from railcontact.geometry.gap import NEWTON_STEPS, NEWTON_TOL
    from railcontact.profiles.profile import ppoly_at
    ev = central["right"].gap_function
    f = ev.frame
    C, t, n, y_off, Rt, O, e, r0 = f[0:3], f[3:6], f[6:9], f[9], f[10:19].reshape(3, 3), \
        f[19:22], f[22], f[23]
    nl = Rt @ n
    rb, rc, wb, wc = ev.rail._breaks, ev.rail._coefs, ev.wheel._breaks, ev.wheel._coefs
    found = 0
    for ys in list(np.linspace(-8e-3, 8e-3, 41)) + [-1.0, 1.0]:
        ref = _ppoly_newton_rail(ys, C, t, n, y_off, rb, rc, 0.0)
        pieces = set()
        for k in (-1, 0, rb.size - 2, 10 ** 6):
            tr, kr = _rail_distance(ys, C, t, n, y_off, rb, rc, 0.0, k)
            assert tr == ref or (math.isnan(tr) and math.isnan(ref))
            pieces.add(kr if math.isfinite(tr) else -1)
        assert len(pieces) == 1
        found += math.isfinite(ref)
        # the wheel's distance at x = 3 mm, every lookup through ppoly_at
        d = np.array([C[0] + 3e-3 - O[0], C[1] + ys * t[1] - O[1], C[2] + ys * t[2] - O[2]])
        l0, l1, l2 = Rt @ d
        tw, ref_w = 0.0, math.nan
        for _ in range(NEWTON_STEPS):
            a0, a2 = l0 + tw * nl[0], l2 + tw * nl[2]
            rho = math.sqrt(a0 * a0 + a2 * a2)
            zw, dzw, _ = ppoly_at(l1 + tw * nl[1] - e, wb, wc, -1)
            step = (rho - (r0 + zw)) / ((a0 * nl[0] + a2 * nl[2]) / rho - dzw * nl[1])
            tw -= step
            if not abs(step) > NEWTON_TOL:
                ref_w = tw
                break
        for k in (-1, 0, wb.size - 2, 10 ** 6):
            w, _ = _wheel_newton(l0, l1, l2, nl[0], nl[1], nl[2], e, r0, wb, wc, 0.0, k)
            assert w == ref_w or (math.isnan(w) and math.isnan(ref_w))
    assert found >= 41
