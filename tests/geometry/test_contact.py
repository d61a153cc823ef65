"""The geometry of one contact patch (railcontact.geometry.contact)."""

import math

import numpy as np
import pytest

from railcontact.geometry.contact import ContactGeometry


def test_interaction_factor_is_contacts_rule():
    from railcontact.geometry.contact import interaction_factor
    assert interaction_factor(3e-3, 4e-3, 8e-3) == 1.0
    assert interaction_factor(4e-3, 4e-3, 8e-3) == 1.0
    assert interaction_factor(6e-3, 4e-3, 8e-3) == pytest.approx(0.5 ** 0.8, rel=1e-12)
    assert interaction_factor(8e-3, 4e-3, 8e-3) == 0.0
    assert interaction_factor(9e-3, 4e-3, 8e-3) == 0.0


def test_quadratic_gap_and_own_band():
    g = ContactGeometry(curvatures=(2.0, 5.0), approach=1e-4, bounds=(-3e-3, 4e-3))
    assert (g.A, g.B) == (2.0, 5.0)
    assert g.gap(np.array([1e-3, 0.0]), np.array([2e-3, 0.0])) == \
        pytest.approx([2e-6 + 2e-5 - 1e-4, -1e-4], rel=1e-12)
    assert list(g.foreign([-4e-3, 0.0, 4e-3, 5e-3])) == [True, False, False, True]
    assert not ContactGeometry(curvatures=(1.0, 1.0)).foreign(1e3)


def test_spin_per_strip_turns_with_the_local_contact_angle():
    """phi(y) = phi cos D + phi' sin D with D the local contact angle minus the
    patch's (docs/conventions.md); constant without profile geometry, and the patch
    value off the profile (NaN angle)."""
    flat = ContactGeometry(curvatures=(1.0, 1.0))
    assert flat.spin_at([0.0, 1e-3], 0.2) == pytest.approx([0.2, 0.2])
    g = ContactGeometry(curvatures=(1.0, 1.0), contact_angle=0.1, spin_derivative=-1.5,
                        local_contact_angle=lambda y: np.where(y > 5e-3, np.nan, 0.1 + 20 * y))
    y = np.array([0.0, 2e-3, 6e-3])
    D = 20 * y[1]
    assert g.spin_at(y, 0.2) == pytest.approx([0.2, 0.2 * math.cos(D) - 1.5 * math.sin(D),
                                               0.2], rel=1e-12)


def test_json_patch_contract():
    g = ContactGeometry(curvatures=(2.0, 5.0), side="left", contact_angle=0.05,
                        rolling_radius=0.46, creepage=(1e-3, -2e-3, 0.1))
    d = g.to_dict()
    assert d["side"] == "left" and d["curvatures"] == [2.0, 5.0]
    assert d["y_rail"] is None and d["position"] == [None, None, None]     # NaN -> null
    assert d["creepage"] == {"longitudinal": 1e-3, "lateral": -2e-3, "spin": 0.1}
    assert "creepage" not in ContactGeometry(curvatures=(1.0, 1.0)).to_dict()
