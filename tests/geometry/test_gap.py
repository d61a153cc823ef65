"""The gap evaluator of a wheel-rail patch (railcontact.geometry.gap) on S1002 /
60E1 1:40 at the central position: the wheel's rolling curvature, left-right
symmetry, the finite-difference curvatures and the guard against far surfaces."""

import math

import numpy as np
import pytest

from railcontact.geometry import Track, Wheelset, find_contact
from railcontact.geometry.gap import DEEPEST_GAP, GapEvaluator, curvatures_fd, sane_gap
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
