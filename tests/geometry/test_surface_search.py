"""The contact search over rail surfaces (railcontact.geometry.surface_search): the
descent to the deepest point where a rail ends, and where the rail's inclination in
the weighted contact angle is taken.  Against CONTACT's switch-and-crossing
testbank (../shared/contact_testbank/examples_s+c)."""

import pytest

import railcontact as rc
from tests.conftest import read_ref_out
from tests.cases.test_surfaces import _case


def test_wheel_just_before_the_nose_begins(testbank):
    """The wheel at s = -0.05, -1 and -5 mm, before the nose's front face (s = 0):
    the deepest point of the gap, at the face, is found by a descent that stops
    there (a Newton step past the face used to leave the rail: approach 0, no
    patch) and CONTACT's contact angle on the cross-section at the wheelset,
    where the nose does not exist yet, falls back to the rail's own inclination
    (was NaN).  The contact lies ahead of the face and the load falls as the
    wheel's lowest point moves away from it."""
    fn = []
    for s in (-0.05e-3, -1e-3, -5e-3):
        res = rc.solve(_case(testbank, "cross+wing_extd.slcs", s, z=2.5287e-3))
        assert res.converged
        (p,) = res.patches
        n = p.normal
        assert s + p.geometry.position[0] + n.x[n.contact.any(axis=1)].min() > 0.0
        assert p.geometry.contact_angle == pytest.approx(-0.0084, abs=1e-3)
        fn.append(n.normal_force)
    assert fn[0] == pytest.approx(9900, rel=0.01)
    assert fn[0] > fn[1] > fn[2] > 0.03 * fn[0]


def test_local_contact_angle_on_the_shifting_wing_rail(testbank):
    """By default the contact angle is weighted with the rail's own inclination at
    each point of the patch; CONTACT takes it on the cross-section at the
    wheelset's position.  On the wing rail shifting 1:10 the patch lies 2.4 mm
    behind the axle, where the rail has moved 0.24 mm sideways: -0.052 rad against
    CONTACT's -0.077; F_n and area hardly change."""
    ref = read_ref_out(testbank / "examples_s+c" / "wing_brute.ref_out")[0]["patches"][0]
    (p,) = rc.solve(_case(testbank, "wing_rail.slcs", 0.1, z=0.6589e-3,
                          contact_angle="local")).patches
    assert p.geometry.contact_angle == pytest.approx(-0.0526, abs=2e-3)
    assert p.normal.normal_force == pytest.approx(ref["fn"], rel=0.01)
    assert p.normal.area / (0.2e-3 * 0.05e-3) == pytest.approx(ref["ncon"], rel=0.03)


def test_wheel_deviation_moves_the_surface_only():
    """A wheel's deviation by flexibility (CONTACT's DXWHL .. DPITCHW): the wheel
    turned about its profile origin P0 = (0, offset, r0) and displaced.  A sphere
    (circular profile of radius r0 about the axle) rolled by 0.1 rad about its
    lowest point has its centre moved by r0 sin 0.1 sideways; lifted by r0 (1 -
    cos 0.1) it touches the plane there again (test-rollers 1e: y = 209.98 mm).
    Its velocities stay those of the design axle (no spin from the roll)."""
    import math

    import numpy as np

    from railcontact.geometry.surface_search import SurfacePose, SurfaceWheel
    from railcontact.profiles import Profile
    y = np.linspace(-0.09, 0.09, 361)
    prof = Profile(y, np.sqrt(0.1 ** 2 - y ** 2) - 0.1, kind="wheel", name="sphere")
    pose = SurfacePose(lateral=0.2 - 0.1, vertical=0.0)
    plain = SurfaceWheel(prof, 0.1, 0.1)
    dev = SurfaceWheel(prof, 0.1, 0.1, deviation=(0.0, 0.0, -0.1 * (1 - math.cos(0.1)), 0.1,
                                                 0.0, 0.0))
    O, R = plain.shape_frame(pose)
    assert np.allclose(O, plain.frame(pose)[0]) and np.allclose(R, plain.frame(pose)[1])
    Od, Rd = dev.shape_frame(pose)
    centre = Od + Rd @ np.array([0.0, 0.1, 0.0])           # the sphere's centre
    assert centre[1] == pytest.approx(0.2 + 0.1 * math.sin(0.1), abs=1e-12)
    assert centre[2] == pytest.approx(-0.1, abs=1e-12)
    # the lowest point of the deviated sphere lies under its centre, on the plane
    q0 = np.array([[0.0, centre[1], -0.05]])
    lam = dev.intersect(pose, q0, np.array([0.0, 0.0, 1.0]))
    assert q0[0, 2] + lam[0] == pytest.approx(0.0, abs=1e-9)
    # the design rotation is kept for the kinematics
    assert np.allclose(dev.frame(pose)[1], plain.frame(pose)[1])


def test_rigid_slip_on_the_surfaces_keeps_the_spin(testbank):
    """D = 3 (the rigid slip on the actual surfaces, test-rollers3): each body's
    velocity is taken at its section's apex, and a point at x off the apex moves
    across the plane by the body's rotation about the normal, x (omega . n): the
    spin's lateral slip phi x.  An ellipsoid on a roller coned by 0.2 rad (case 10,
    spin 2e-3 /mm): F_s 14179 N against CONTACT's 13930 N (0.85 % of mu F_n; without
    the term 674 N, -45 %); the ellipsoid rolled on the cone (case 12) F_s -102.3 N
    against -100.1."""
    from railcontact.contact_inp import solve_inp
    path = testbank / "examples_conformal" / "test-rollers3.inp"
    rows = {r["case"]: r for r in solve_inp(path, cases=[10, 12])}
    refs = read_ref_out(path.with_suffix(".ref_out"))
    for case, r in rows.items():
        (q,) = refs[case - 1]["patches"]
        for k, c in (("fx_N", "fx"), ("fs_N", "fs")):
            assert abs(r[k] - q[c]) <= 0.01 * 0.3 * q["fn"], (case, k, r[k], q[c])
    assert rows[10]["fs_N"] == pytest.approx(13930, rel=0.02)


def test_locus_weights_of_a_yawed_paraboloid():
    """``weights = "locus"`` (CONTACT's contact locus): on a gap
    g = -d + A (x - c y)^2 + B y^2 sampled on a grid whose nodes miss the lowest
    points, each lateral line's lowest point is found by the parabola through its
    three lowest nodes exactly (x = c y, g = -d + B y^2, to 1e-15 m), weighted with
    (-g)^2.5 times the x step."""
    import numpy as np
    from railcontact.geometry.surface_search import _FineGrid, _locus_weights
    d, A, B, c = 2e-5, 1.1, 40.0, 0.3
    x = np.arange(-3e-3, 3e-3, 2e-4) + 0.37e-4
    y = np.arange(-1e-3, 1e-3, 7.5e-5)
    X, Y = np.meshgrid(x, y, indexing="ij")
    g = -d + A * (X - c * Y) ** 2 + B * Y ** 2
    grid = _FineGrid(x, y, g, np.zeros_like(g), np.full_like(g, 0.1), (2e-4, 7.5e-5))
    w, xs, ys, inc = _locus_weights(grid, g < 0)
    gm = -d + B * ys ** 2
    assert ys.size > 5 and np.all(gm < 0)
    assert np.allclose(xs, c * ys, atol=1e-15, rtol=0)
    assert np.allclose(w, (-gm) ** 2.5 * 2e-4, rtol=1e-9, atol=0)
    assert np.all(inc == 0.1)
