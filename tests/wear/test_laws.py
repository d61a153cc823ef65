"""Wear laws (railcontact.wear.laws): local rates at the points of their published
tables (REFERENCES.md 8.1 USFD, 8.2 Archard/Jendel), on hand-made fields."""

from types import SimpleNamespace

import numpy as np
import pytest

from railcontact.core.errors import InputError
from railcontact.wear import get_wear_law
from railcontact.wear.laws import USFD, wear_laws


def fields(p, sx, sy=0.0, tx=0.0, ty=0.0):
    """A normal and tangential 'solution' with the given fields on a 1 x n grid."""
    p = np.atleast_2d(np.asarray(p, float))
    full = lambda v: np.broadcast_to(np.asarray(v, float), p.shape).copy()  # noqa: E731
    normal = SimpleNamespace(pressure=p)
    tang = SimpleNamespace(slip_x=full(sx), slip_y=full(sy), traction_x=full(tx),
                           traction_y=full(ty), contact=p > 0, options={},
                           creepage=(0.0, 0.0, 0.0))
    return normal, tang


def test_usfd_regimes_as_published():
    K = USFD.wear_rate([5.0, 10.4, 50.0, 77.2, 100.0])
    assert K == pytest.approx([26.5, 55.0, 55.0, 55.0, 61.9 * 100 - 4778.7])


def test_usfd_rate_converts_ug_per_m_mm2_to_depth():
    # I = |tau . s| = 2e7 Pa * 1 = 20 N/mm^2 (severe): K = 55 ug/(m mm^2)
    # = 55e-9 kg / (1 m * 1e-6 m^2) = 5.5e-2 kg/m^3 -> depth rate K / rho
    normal, tang = fields([1e9, 0.0], sx=1.0, tx=2e7)
    r = get_wear_law("usfd", density=7850.0).rate(normal, tang, 10.0)
    assert r[0, 0] == pytest.approx(5.5e-2 / 7850.0, rel=1e-12)
    assert r[0, 1] == 0.0                        # outside the contact
    # mild regime: I = 5 N/mm^2, K = 26.5
    normal, tang = fields([1e9], sx=0.5, sy=0.0, tx=1e7)
    assert get_wear_law("usfd").rate(normal, tang, 1.0)[0, 0] == \
        pytest.approx(26.5e-3 / 7850.0, rel=1e-12)


def test_frictional_power_rate():
    normal, tang = fields([1e9], sx=0.01, sy=-0.02, tx=3e8, ty=-2e8)
    r = get_wear_law("frictional-power", k=2e-13).rate(normal, tang, 5.0)
    assert r[0, 0] == pytest.approx(2e-13 * (3e6 + 4e6), rel=1e-12)


@pytest.mark.parametrize("p_over_H, slip, k", [
    (0.9, 0.001, 350e-4),        # p > 0.8 H: seizure, k1 (any velocity)
    (0.5, 0.001, 5.5e-4),        # v = 0.01 m/s < 0.2: k2
    (0.5, 0.04, 35e-4),          # v = 0.4 m/s in [0.2, 0.7]: k3
    (0.5, 0.1, 5.5e-4),          # v = 1.0 m/s > 0.7: k4
])
def test_archard_wear_map_regions(p_over_H, slip, k):
    H = 2.75e9
    normal, tang = fields([p_over_H * H], sx=0.6 * slip, sy=0.8 * slip)
    r = get_wear_law("archard").rate(normal, tang, 10.0)
    assert r[0, 0] == pytest.approx(k * p_over_H * slip, rel=1e-9)
    # the default coefficients are the mid-points of Jendel's ranges (REFERENCES 8.2)
    law = get_wear_law("archard")
    assert law.k == pytest.approx((350e-4, 5.5e-4, 35e-4, 5.5e-4))


def test_laws_registered_and_bad_parameters():
    assert {"frictional-power", "usfd", "archard"} <= set(wear_laws())
    with pytest.raises(InputError, match="frictional-power"):
        get_wear_law("frictional-power", k=-1.0)
    with pytest.raises(InputError, match="usfd density"):
        get_wear_law("usfd", density=0.0)
    with pytest.raises(InputError, match="archard hardness"):
        get_wear_law("archard", hardness=-2e9)
