"""Hertz's theory of elliptic contact, with complete elliptic integrals.

For an undeformed gap h = A x^2 + B y^2 (A, B > 0, relative curvatures) between two
elastic half-spaces with contact modulus E* (1/E* = sum (1 - nu^2)/E), the contact
area is an ellipse with semi-axes a (along x) and b (along y), and the pressure is
p = p0 sqrt(1 - x^2/a^2 - y^2/b^2), p0 = 3 F / (2 pi a b).

With the major semi-axis along the smaller curvature, k = minor/major, e^2 = 1 - k^2,
and K = K(e), E = E(e) the complete elliptic integrals of the first and second kind
(Johnson, *Contact Mechanics*, 1985, section 4.2):

    A_small = (p0 k / (E* a_major)) (K - E) / e^2
    A_large = (p0 k / (E* a_major)) (E / k^2 - K) / e^2
    delta   =  p0 a_minor K / E*

so the curvature ratio fixes e, and the force (or the penetration) the size.
No curve fits are used.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk

from ..errors import InputError


def _k_minus_e_over_m(m: float) -> float:
    """(K(m) - E(m)) / m, accurate also for small m."""
    if m < 1e-6:
        return math.pi / 4.0 * (1.0 + 3.0 * m / 8.0 + 45.0 * m * m / 256.0)
    return (ellipk(m) - ellipe(m)) / m


def _ratio(m: float) -> float:
    """Curvature ratio A_large / A_small of an ellipse with e^2 = m."""
    if m < 1e-6:
        # series of (E/(1-m) - K)/(K - E) about m = 0
        return 1.0 + 1.5 * m + 1.03125 * m * m
    K, E = ellipk(m), ellipe(m)
    return (E / (1.0 - m) - K) / (K - E)


def eccentricity_from_ratio(ratio: float) -> float:
    """e^2 of the Hertz ellipse for a curvature ratio A_large/A_small >= 1."""
    if ratio < 1.0:
        raise InputError(f"curvature ratio {ratio}: expected >= 1")
    if ratio - 1.0 < 1e-12:
        return 0.0
    hi = 1.0 - 1e-15
    if _ratio(hi) < ratio:
        raise InputError(f"curvature ratio {ratio:.4g} is beyond the range of Hertz theory "
                         "handled here (semi-axis ratio above 1e7)")
    return brentq(lambda m: _ratio(m) - ratio, 0.0, hi, xtol=1e-17, rtol=1e-15, maxiter=400)


@dataclass(frozen=True)
class HertzEllipse:
    """Hertz solution: semi-axes a (x), b (y) [m], p0 [Pa], penetration [m], force [N]."""

    a: float
    b: float
    p0: float
    penetration: float
    force: float

    @property
    def area(self) -> float:
        return math.pi * self.a * self.b


def hertz_ellipse(A: float, B: float, contact_modulus: float, force: float | None = None,
                  penetration: float | None = None) -> HertzEllipse:
    """Solve Hertz's elliptic contact for a given force or penetration.

    Parameters
    ----------
    A, B : float
        Relative curvatures [1/m] in the gap h = A x^2 + B y^2 (x rolling, y lateral);
        a concave body enters with its negative curvature, the sum must stay > 0.
    contact_modulus : float
        E* [Pa].
    force, penetration : float
        Exactly one: normal force F [N] >= 0 or approach delta [m] >= 0.
    """
    for name, v in (("A", A), ("B", B)):
        if not (math.isfinite(v) and v > 0.0):
            raise InputError(f"relative curvature {name} = {v!r} 1/m: expected > 0 (the surfaces "
                             "must form a point contact; for conformal or flat geometry use a "
                             "non-Hertzian model)")
    if (force is None) == (penetration is None):
        raise InputError("give exactly one of normal force and penetration")
    small, large = min(A, B), max(A, B)
    m = eccentricity_from_ratio(large / small)
    k = math.sqrt(1.0 - m)
    K = math.pi / 2.0 if m == 0.0 else float(ellipk(m))
    kme = _k_minus_e_over_m(m)
    Es = contact_modulus
    if force is not None:
        if not (math.isfinite(force) and force >= 0.0):
            raise InputError(f"normal force {force!r} N: expected a finite value >= 0")
        a_major = (3.0 * force * kme / (2.0 * math.pi * Es * small)) ** (1.0 / 3.0)
        a_minor = k * a_major
        p0 = 3.0 * force / (2.0 * math.pi * a_major * a_minor) if force > 0 else 0.0
        delta = p0 * a_minor * K / Es
        F = force
    else:
        if not (math.isfinite(penetration) and penetration >= 0.0):
            raise InputError(f"penetration {penetration!r} m: expected a finite value >= 0")
        a_major = math.sqrt(penetration * kme / (K * small))
        a_minor = k * a_major
        F = 2.0 * math.pi * a_major * penetration * Es / (3.0 * K)
        p0 = 3.0 * F / (2.0 * math.pi * a_major * a_minor) if F > 0 else 0.0
        delta = penetration
    a, b = (a_major, a_minor) if A <= B else (a_minor, a_major)
    return HertzEllipse(a, b, p0, delta, F)


def hertz_force_vectorised(A: np.ndarray, B: np.ndarray, contact_modulus: float,
                           penetration: np.ndarray) -> np.ndarray:
    """Hertz normal force [N] for arrays of curvatures and penetrations (0 where <= 0)."""
    out = np.zeros(np.broadcast(A, B, penetration).shape)
    for idx in np.ndindex(out.shape):  # few patches per wheel; not a grid loop
        d = float(np.broadcast_to(penetration, out.shape)[idx])
        if d > 0:
            out[idx] = hertz_ellipse(float(np.broadcast_to(A, out.shape)[idx]),
                                     float(np.broadcast_to(B, out.shape)[idx]),
                                     contact_modulus, penetration=d).force
    return out
