"""Friction laws (railcontact.tangential.friction): Polach's falling friction."""

import math

import numpy as np
import pytest

from railcontact.core.errors import InputError
from railcontact.tangential.friction import FallingFriction, falling_friction


def test_falling_friction_values():
    law = FallingFriction(A=0.4, B=0.6)
    w = np.array([0.0, 1 / 0.6, 5.0, 1e3])
    mu = law(0.5, w)
    # mu0 at rest, mu0 ((1 - A)/e + A) at w = 1/B, mu0 A = mu_inf for w -> inf
    assert mu == pytest.approx([0.5, 0.5 * (0.6 / math.e + 0.4),
                                0.5 * (0.6 * math.exp(-3.0) + 0.4), 0.2], rel=1e-12)
    assert np.all(np.diff(mu) < 0)
    assert FallingFriction(A=1.0, B=2.0)(0.3, 10.0) == pytest.approx(0.3, rel=1e-15)


def test_falling_friction_from_spec():
    assert falling_friction(None) is None
    law = FallingFriction(0.3, 1.0)
    assert falling_friction(law) is law
    assert falling_friction({"A": "0.3", "B": 1}) == law
    with pytest.raises(InputError, match="unknown keys"):
        falling_friction({"A": 0.3, "C": 1.0})
    with pytest.raises(InputError, match="A and B"):
        falling_friction(0.3)
    with pytest.raises(InputError, match="mu_inf/mu0"):
        FallingFriction(A=1.5)
    with pytest.raises(InputError, match="s/m"):
        FallingFriction(B=-1.0)
    with pytest.raises(InputError, match="s/m"):
        FallingFriction(B=math.inf)


def test_slip_velocity_friction_laws():
    """CONTACT's laws L = 2, 3, 4 (user guide, "Slip velocity dependent friction"):
    static value mu_kin + c1 + c2; at s_a = s_h1 the exponential term is halved, the
    rational one halved, the linear one halved; large s_a gives mu_kin."""
    from railcontact.tangential.friction import SlipVelocityFriction
    for kind in ("linear", "rational", "exponential"):
        law = SlipVelocityFriction(kind, 0.18, (0.12, 0.0), (0.1, 1.0))
        assert law.static == pytest.approx(0.30)
        assert float(law(0.1)) == pytest.approx(0.18 + 0.06)
        assert float(law(1e3)) == pytest.approx(0.18, abs=2e-5)
    two = SlipVelocityFriction("rational", 0.1, (0.1, 0.2), (1.0, 2.0))
    assert float(two(2.0)) == pytest.approx(0.1 + 0.1 / 3 + 0.2 / 2)
    # Polach's law as CONTACT writes it: mu_kin = A mu0, c1 = (1 - A) mu0, s_h = ln2 / B
    mu0, A, B = 0.4, 0.4, 0.6
    law = SlipVelocityFriction("exponential", A * mu0, ((1 - A) * mu0, 0.0),
                               (math.log(2) / B, 1.0))
    w = np.array([0.0, 0.5, 3.0])
    assert law(w) == pytest.approx(FallingFriction(A, B)(mu0, w))
    with pytest.raises(InputError, match="expected 'linear'"):
        SlipVelocityFriction("cubic", 0.2)


def test_temperature_friction_is_piecewise_linear():
    """CONTACT's L = 6 law: mu_ref below T_ref, linear over dT, mu_ref + dmu above."""
    from railcontact.tangential.friction import TemperatureFriction
    law = TemperatureFriction(0.3, 100.0, -0.1, 200.0)
    assert law([-50.0, 100.0, 200.0, 300.0, 1000.0]) == pytest.approx(
        [0.3, 0.3, 0.25, 0.2, 0.2], abs=1e-15)
    assert (law.static, law.mu_kin) == pytest.approx((0.3, 0.2))
    with pytest.raises(InputError, match="kinetic"):
        TemperatureFriction(0.1, 0.0, -0.2, 100.0)
    with pytest.raises(InputError, match="dT"):
        TemperatureFriction(0.3, 0.0, -0.1, 0.0)
