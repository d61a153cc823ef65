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
