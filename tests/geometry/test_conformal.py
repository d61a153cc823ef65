"""The curved reference surface of a conformal patch (railcontact.geometry.conformal):
a straight reference curve reproduces the planar gap exactly, the rigid slip
against the wheel's rigid-body kinematics, the bar forces of a circular arc, and
the reference curve against the one CONTACT prints for mbench_conf.inp."""

import math
import re

import numpy as np
import pytest

from railcontact.geometry import Track, Wheelset, find_contact
from railcontact.geometry.conformal import (ConformalGap, ReferenceCurve, bar_forces,
                                            conformal_geometry, conformal_slip, flat_curve,
                                            reference_curve)
from railcontact.geometry.gap import GapEvaluator
from railcontact.profiles import rail_profile, s1002


@pytest.fixture(scope="module")
def flange_root():
    """S1002 on 60E1 1:40 shifted 7 mm to the right: a flange patch on the right
    wheel (-62 deg, its surface turning along the flange), a tread patch on the
    left."""
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    c = find_contact(ws, tr, lateral_shift=7e-3, vertical_force=6e4)
    return c.patches


def test_a_straight_curve_is_the_planar_gap(flange_root):
    """With the straight reference curve (the tangent plane) the conformal gap is the
    planar one, on both sides, to rounding: the same surfaces, the same normals."""
    x = np.linspace(-4e-3, 4e-3, 9)
    y = np.linspace(-3e-3, 3e-3, 13)
    for p in flange_root:
        assert isinstance(p.gap_function, GapEvaluator)
        flat = ConformalGap(p.gap_function, flat_curve(-5e-3, 5e-3))
        h_planar = p.gap(x[:, None], y[None, :])
        assert np.abs(flat(x[:, None], y[None, :]) - h_planar).max() < 1e-12


def test_reference_curve_of_a_flange_root(flange_root):
    """The mid-line's curve spans the patch and beyond, its arc length grows with
    y and at least as fast, at y = 0 its angle is nearly the patch's (the patch's
    angle is the interpenetration's weighted one) and the gap there the planar
    one."""
    for p in flange_root:
        g = conformal_geometry(p)
        c = g.surface.curve
        assert c.s[0] < -3e-3 and c.s[-1] > 3e-3
        a0, b0, d0 = c.at(0.0)
        assert abs(a0) < 1e-12 and abs(d0) < 0.02
        assert np.all(np.diff(c.s) > 0) and np.all(np.isfinite(c.b))
        # the gap along the curve's normals is the planar one where the curve runs
        # parallel to the tangent plane (at y = 0, D ~ 0), to second order in D
        h_c = g.gap(np.array([0.0]), np.array([0.0]))
        h_p = p.gap(np.array([0.0]), np.array([0.0]))
        assert abs(h_c - h_p)[0] < 1e-8
        # the arc length grows faster than the abscissa where the curve turns
        s = c.s_of_y(np.array([-2e-3, 2e-3]))
        assert abs(s[0]) >= 2e-3 - 1e-12 and s[1] >= 2e-3 - 1e-12


def _arc(R, theta_max=0.5, n=2001):
    th = np.linspace(-theta_max, theta_max, n)
    return ReferenceCurve(R * th, R * np.sin(th), R * (1 - np.cos(th)), th)


class _Geom:
    """The few attributes conformal_slip and bar_forces read."""

    def __init__(self, curve, dphi):
        from railcontact.geometry.conformal import ConformalPatch
        self.surface = ConformalPatch(curve, 0.0)
        self.spin_derivative = dphi


def test_rigid_slip_is_the_wheels_rigid_rotation():
    """On a circular arc (R = 12 mm) the planar slip plus the conformal part equals
    the slip of the rail relative to a wheel turning rigidly with omega (no
    component along x) and with the rigid velocity u0 (tangential) at the
    reference point: w = (u(P) . x_c, u(P) . y_c(s)) / V, u(P) = u0 - omega x (P - Q),
    in the patch frame (x_c, y_c, n), n = x_c x y_c, y_c(s) = cos D y_c + sin D n."""
    R, V = 12e-3, 20.0
    curve = _arc(R)
    omega = np.array([0.0, -31.0, 17.0])            # (x, y_c, n) components [rad/s]
    u0 = np.array([0.004 * V, -0.011 * V, 0.0])
    xi, eta = u0[0] / V, u0[1] / V
    phi, dphi = -omega[2] / V, omega[1] / V            # phi = -omega . n / V
    x = np.array([-3e-3, 0.0, 2e-3])
    s = np.array([-4e-3, -1e-3, 0.0, 2.5e-3, 5e-3])
    wx, wy = conformal_slip(_Geom(curve, dphi), (xi, eta, phi), x, s)
    for i, xv in enumerate(x):
        for j, sv in enumerate(s):
            a, b, D = (float(v) for v in curve.at(sv))
            P = np.array([xv, a, b])
            u = u0 - np.cross(omega, P)
            yj = np.array([0.0, math.cos(D), math.sin(D)])
            want = (u[0] / V, u @ yj / V)
            planar = (xi - phi * sv, eta + phi * xv)
            assert planar[0] + wx[i, j] == pytest.approx(want[0], abs=1e-12)
            assert planar[1] + wy[i, j] == pytest.approx(want[1], abs=1e-12)


def test_rigid_slip_of_a_straight_curve_is_planar():
    wx, wy = conformal_slip(_Geom(flat_curve(-1e-2, 1e-2), 0.7), (0.01, -0.02, 1.5),
                            np.linspace(-1e-3, 1e-3, 3), np.linspace(-2e-3, 2e-3, 5))
    assert np.abs(wx).max() < 1e-15 and np.abs(wy).max() < 1e-15     # rounding only


def test_bar_forces_of_an_arc():
    """A uniform pressure p over a symmetric arc of half-angle t0: the bar force
    along the patch normal is p L (sin t0 / t0) per unit length in x (the chord's
    projection), the lateral one zero; a lateral traction tau turns likewise:
    F_y = tau L sin t0 / t0, F_n gets nothing (symmetric); TILDE_FN = p L."""
    R, t0 = 10e-3, 0.3
    curve = _arc(R, 0.6)
    n = 400
    ds = 2 * R * t0 / n
    s = -R * t0 + (np.arange(n) + 0.5) * ds
    p = np.full((1, n), 1e8)
    fn, fy, tilde = bar_forces(_Geom(curve, 0.0), s, p, None, ds)
    L = 2 * R * t0
    assert tilde == pytest.approx(1e8 * L, rel=1e-12)
    assert fn == pytest.approx(1e8 * L * math.sin(t0) / t0, rel=1e-5)
    assert abs(fy) < 1e-9 * fn
    fn2, fy2, _ = bar_forces(_Geom(curve, 0.0), s, 0 * p, 0.3 * p, ds)
    assert fy2 == pytest.approx(0.3e8 * L * math.sin(t0) / t0, rel=1e-5)
    assert abs(fn2) < 1e-9 * fy2


def _printed_curve(path, patch):
    """CONTACT's "CURVED REFERENCE SURFACE" table of a patch: (y, z, angle)."""
    text = path.read_text()
    blocks = text.split("----- DATA FOR CONTACT PATCH")[1:]
    tab = blocks[patch - 1].split("CURVED REFERENCE SURFACE")[1]
    rows = re.findall(r"^\s+\d+\s+([-\d.]+)\s+([-\d.]+)\s+([-\d.]+)\s*$", tab, re.M)
    return np.array(rows, dtype=float)


def test_reference_curve_is_contacts(testbank):
    """mbench_conf.inp, flange-root patch (S1002 on UIC60 1:40, y_ws = 6.25 mm, yaw
    24 mrad): the local contact angle along our reference curve, at CONTACT's 21
    printed curve points (lateral positions y_tr from 723.0 to 726.6 mm, angles
    -0.579 to -0.310 rad), within 1 mrad, and its height within 1 um; measured:
    0.23 mrad and 0.14 um at most (the flange patch's 9 points: 1.8 mrad, 3.2 um,
    on a slope dz/dy of 2.7)."""
    from railcontact.cases.bodies import build_wheelset_track, contact_search
    from railcontact.cases.case import case_from_dict
    from railcontact.contact_inp import load_inp
    from railcontact.geometry.locus import depth_at
    path = testbank / "examples_conformal" / "mbench_conf.inp"
    (m,) = load_inp(path)
    case = case_from_dict(m.raw, path.parent)
    ws, tr = build_wheelset_track(case)
    s = case.wheel_rail
    d = depth_at(ws, tr, s.side, s.lateral_shift, s.vertical_position, s.roll, s.yaw)
    contact = contact_search(case, interpenetration={s.side: d}, bodies=(ws, tr))
    p = min(contact.patches, key=lambda q: abs(q.contact_angle + 0.42))   # the root
    g = conformal_geometry(p)
    ref = _printed_curve(path.with_suffix(".ref_out"), 1)
    # our curve's lateral track positions and angles (right side: side frame = track's)
    sv = np.linspace(-6e-3, 6e-3, 1201)
    P, _ = g.gap_function.frames(sv)
    y_tr = P[:, 1] * 1e3
    angle = g.local_contact_angle(sv)
    ours = np.interp(ref[:, 0], y_tr, angle)
    assert np.abs(ours - ref[:, 2]).max() < 1e-3
    z = np.interp(ref[:, 0], y_tr, P[:, 2] * 1e3)
    assert np.abs(z - ref[:, 1]).max() < 1e-3


def test_conformal_influence_angles():
    """Blanco's column inclinations (ConformalInfluence.angles): "detailed" the
    reference curve's angle at each column, "fast" its least-squares line in s
    (CONTACT's IF_METH = 0, 1); on a circular curve (D = s/R) the two agree to
    rounding, also where the grid reaches beyond the curve's samples (only the
    columns the samples reach are fitted); on one whose angle bends they differ by
    the fit's residual, which sums to zero.  Wrong options are named."""
    from railcontact.core.errors import InputError
    from railcontact.geometry.conformal import ConformalInfluence

    R = 0.01
    s = np.linspace(-8e-3, 8e-3, 161)
    circle = ReferenceCurve(s, R * np.sin(s / R), R * (1 - np.cos(s / R)), s / R)
    cols = np.linspace(-6e-3, 6e-3, 49)
    det = ConformalInfluence("detailed", 3).angles(circle, cols)
    fast = ConformalInfluence("fast", 3).angles(circle, cols)
    assert np.allclose(det, cols / R, rtol=0, atol=1e-12)
    assert np.allclose(fast, det, rtol=0, atol=1e-12)
    bent = ReferenceCurve(s, s, np.zeros_like(s), 300.0 * s + 2e4 * s ** 2)
    d, f = (ConformalInfluence(m).angles(bent, cols) for m in ("detailed", "fast"))
    assert np.max(np.abs(d - f)) > 0.1 and abs(np.sum(d - f)) < 1e-10
    assert np.allclose(np.diff(f, 2), 0.0, atol=1e-12)
    # columns beyond the curve's samples (its straight continuation) stay out of
    # the fit: on the circle the line is s/R there too (CONTACT's fit on its
    # groove_li grid equals its detailed angles)
    wide = np.linspace(-12e-3, 12e-3, 97)
    assert np.allclose(ConformalInfluence("fast").angles(circle, wide), wide / R, atol=1e-12)
    assert np.allclose(ConformalInfluence("detailed").angles(circle, wide),
                       np.clip(wide, -8e-3, 8e-3) / R, atol=1e-12)
    with pytest.raises(InputError, match="method 'slow'"):
        ConformalInfluence("slow")
    with pytest.raises(InputError, match="variant 4: expected 3"):
        ConformalInfluence("fast", 4)


def test_sampled_conformal_gap_is_contacts_rule(flange_root):
    """CONTACT's conformal undeformed distance (``ConformalGap.sampled``): the
    planar gap at each column's tangent-plane point a(s), times cos D(s).  With
    wheel samples 1 um apart the chords are the arc (DS^2 / (8 R) ~ 1e-11 m), so
    it is the exact planar gap there times cos D to 1e-9 m; with CONTACT's 0.4 mm
    the wheel lies between the samples on their chords, inside the arc, so that
    the gap is nowhere smaller than with the fine samples and differs by at most
    DS^2 / (8 R) (R >= 10 mm here: 2 um) times the cosine: measured 1.0 um on the
    flange root, 0.06 um on the tread."""
    x = np.linspace(-3e-3, 3e-3, 7)
    s = np.linspace(-3e-3, 3e-3, 61)
    chord = {}
    for p in flange_root:
        g = conformal_geometry(p)
        cg = g.gap_function
        a, _, D = cg.curve.at(s)
        fine = cg.sampled(p.y_wheel, 1e-6)
        expect = p.gap(x[:, None], a[None, :]) * np.cos(D)[None, :]
        h = fine(x[:, None], s[None, :])
        near = expect < 1e-4
        assert near.sum() > 20
        assert np.abs(h - expect)[near].max() < 1e-9
        coarse = cg.sampled(p.y_wheel, 4e-4)(x[:, None], s[None, :])
        assert coarse.shape == h.shape
        assert np.all(coarse[near] >= h[near] - 1e-9)
        assert np.abs(coarse - h)[near].max() < (4e-4) ** 2 / (8 * 1e-2)
        chord[p.side] = np.abs(coarse - h)[near].max()
        # the wheel samples, once taken, are kept by sampled_wheel_geometry
        from railcontact.geometry.gap import sampled_wheel_geometry
        import dataclasses
        gs = dataclasses.replace(g, gap_function=cg.sampled(p.y_wheel, 4e-4))
        assert sampled_wheel_geometry(gs, 1e-3).gap_function is gs.gap_function
        assert sampled_wheel_geometry(g, 4e-4).gap_function.planar.ds == 4e-4
    # measured: 1.0 um on the flange root (right), 0.06 um on the tread (left)
    assert chord["right"] > 5e-7 and chord["left"] < 2e-7
