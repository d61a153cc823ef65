"""Arnold's quasi-elastic contact on S1002/60E1 1:40: the soft minimum against its
closed form, the rigid limit, no jump across the rigid contact jumps, the
penetration against the multi-Hertzian (elastic) one at the documented α, and the
equivalent conicity against the multi-Hertzian table's."""

import math

import numpy as np
import pytest

from railcontact.core.errors import InputError
from railcontact.geometry import Track, Wheelset, contact_table, equivalent_conicity, find_contact
from railcontact.geometry.quasi_elastic import (quasi_elastic_contact, quasi_elastic_table,
                                                soft_min_offset)
from railcontact.profiles import rail_profile, s1002

#: the α that matches the elastic approach of a 70 kN wheel (docs/dynamics.md)
ALPHA_70KN = 3e-5


@pytest.fixture(scope="module")
def bodies():
    return Wheelset(s1002()), Track(rail_profile("60E1", inclination=math.atan(1 / 40)))


def test_soft_min_of_a_parabola():
    """g = g0 + c s^2 sampled over a width L: delta = alpha ln(L sqrt(c / (pi alpha)))."""
    h, L, c, alpha = 2.5e-5, 0.12, 2.0, 2e-5
    s = np.arange(-L / 2, L / 2 + h / 2, h)
    delta, w = soft_min_offset(1e-4 + c * s * s, h, L, alpha)
    assert delta == pytest.approx(alpha * math.log(L * math.sqrt(c / (math.pi * alpha))),
                                  rel=1e-6)
    assert w.sum() == pytest.approx(1.0) and np.dot(w, s) == pytest.approx(0.0, abs=1e-12)
    # the weights' spread: the Gaussian's sqrt(alpha / (2 c))
    assert math.sqrt(np.dot(w, s * s)) == pytest.approx(math.sqrt(alpha / (2 * c)), rel=1e-6)


def test_rigid_limit_and_symmetry(bodies):
    ws, tr = bodies
    rigid = find_contact(ws, tr, 0.003, 0.0)
    q = quasi_elastic_contact(ws, tr, 0.003, alpha=1e-8)
    # the penetration vanishes with alpha (alpha ln(L / h) ~ 9e-8 m at most)
    assert q.pose.vertical == pytest.approx(rigid.pose.vertical, abs=2e-7)
    assert q.pose.roll == pytest.approx(rigid.pose.roll, abs=2e-7)
    right = max(rigid.side_patches("right"), key=lambda p: p.weight)
    assert q.points["right"].y_rail == pytest.approx(right.y_rail, abs=3e-5)
    c = quasi_elastic_contact(ws, tr, 0.0, alpha=ALPHA_70KN)
    L, R = c.points["left"], c.points["right"]
    assert L.penetration == pytest.approx(R.penetration, rel=1e-9)
    assert L.contact_angle == pytest.approx(-R.contact_angle, rel=1e-9)
    assert c.pose.roll == pytest.approx(0.0, abs=1e-12)
    with pytest.raises(InputError, match="alpha"):
        quasi_elastic_contact(ws, tr, 0.0, alpha=0.01)


def _jump(ws, tr, lo, hi, size):
    """The lateral shift [m] where the rigid contact angle of the right wheel jumps by
    more than ``size`` [rad] (bisection to 0.1 um)."""
    a = lambda y: quasi_elastic_contact(ws, tr, y, alpha=1e-8).points["right"].contact_angle
    alo = a(lo)
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        if abs(a(mid) - alo) < size:
            lo = mid
        else:
            hi = mid
        if hi - lo < 1e-7:
            break
    return 0.5 * (lo + hi)


@pytest.mark.parametrize("window", [(4.9e-3, 5.1e-3, 0.05), (6.2e-3, 6.3e-3, 0.3)])
def test_no_jump_in_the_normal_force_across_the_contact_jumps(bodies, window):
    """The wheel's normal force at a 70 kN load, N = Q / cos(delta): across each jump
    of the rigid contact point (tread to flange root, flange root to flange) the rigid
    N jumps by the same amount however fine the sampling; the quasi-elastic N is
    continuous: its largest step shrinks with the sampling step."""
    ws, tr = bodies
    yj = _jump(ws, tr, *window)

    def largest_step(alpha, h, half=2e-5):
        ys = np.arange(yj - half, yj + half + h / 2, h)
        d = np.array([quasi_elastic_contact(ws, tr, y, alpha=alpha).points["right"].contact_angle
                      for y in ys])
        return np.abs(np.diff(70e3 / np.cos(d))).max()

    rigid = [largest_step(1e-8, h) for h in (4e-6, 1e-6)]
    quasi = [largest_step(ALPHA_70KN, h) for h in (4e-6, 1e-6)]
    assert rigid[1] > 1e3 and rigid[1] > 0.8 * rigid[0]          # a jump
    assert quasi[1] < 0.35 * quasi[0]                            # Lipschitz: ~ h
    assert quasi[1] < 0.25 * rigid[1]


def test_penetration_against_the_elastic_one(bodies):
    """At alpha = 3e-5 m the quasi-elastic penetration is the multi-Hertzian vertical
    interpenetration of a 70 kN wheel within -19 % ... +22 % on tread contact (shifts
    -4 ... 4 mm; 1.00 on average); it does not depend on the load."""
    ws, tr = bodies
    ratio = []
    for y in np.arange(-4e-3, 4.01e-3, 1e-3):
        e = find_contact(ws, tr, y, 0.0, vertical_force=70e3)
        q = quasi_elastic_contact(ws, tr, y, alpha=ALPHA_70KN)
        ratio += [q.points[s].penetration / e.interpenetration[s] for s in ("left", "right")]
    ratio = np.array(ratio)
    assert 0.80 < ratio.min() and ratio.max() < 1.23
    assert np.mean(ratio) == pytest.approx(1.0, abs=0.02)


def test_equivalent_conicity_against_the_elastic_table(bodies):
    """Equivalent conicity (EN 15302 wavelength method) at 2, 3 and 4 mm amplitude:
    quasi-elastic (alpha = 3e-5 m) within 0.011 of the multi-Hertzian table at 70 kN;
    the rigid contact differs by more at 2 mm."""
    ws, tr = bodies
    ys = np.arange(-4.5e-3, 4.51e-3, 5e-4)
    elastic = contact_table(ws, tr, ys, vertical_force=70e3)
    quasi = quasi_elastic_table(ws, tr, ys, alpha=ALPHA_70KN)
    rigid = quasi_elastic_table(ws, tr, ys, alpha=1e-8)
    for amp in (2e-3, 3e-3, 4e-3):
        ge, gq = equivalent_conicity(elastic, amp), equivalent_conicity(quasi, amp)
        assert abs(gq - ge) < 0.011, (amp, gq, ge)
    assert abs(equivalent_conicity(rigid, 2e-3) - equivalent_conicity(elastic, 2e-3)) > 0.04
    assert quasi["penetration"].attrs["units"] == "m"
