"""Polach's creep-force law (``tangential="polach"``).

Polach, O. (1999), "A fast wheel-rail forces calculation computer code", *Vehicle
System Dynamics* 33 (Suppl.), 728-739; extended model: Polach (2005), "Creep forces
in simulations of traction vehicles running on adhesion limit", *Wear* 258, 992-1000.
Formulas as collected in ``REFERENCES.md`` section 6 (forces positive along the
creepages, which with this package's creepage convention are the forces on the
wheel):

    s_yC = s_y + psi a   if |s_y + psi a| > |s_y|, else s_y
    s_C = sqrt(s_x^2 + s_yC^2),  c_jj = sqrt((C11 s_x/s)^2 + (C22 s_y/s)^2)
    eps = pi G a b c_jj s_C / (4 Q mu)
    F = 2 Q mu / pi (k_A eps / (1 + (k_A eps)^2) + arctan(k_S eps))   (k_A = k_S = 1: 1999)
    spin: K_S = 1 + 6.3 (1 - exp(-a/b)),
          eps_M = 8/3 G b sqrt(ab) C23 |s_yC| / (Q mu K_S),  d = (eps_M^2 - 1)/(eps_M^2 + 1),
          K_M = |eps_M| (d^3/3 - d^2/2 + 1/6) - sqrt((1 - d^2)^3)/3,
          F_yS = -9/16 a Q mu K_M K_S psi / s_C
    F_x = F s_x / s_C,  F_y = F s_y / s_C + F_yS

With falling friction mu = mu0 ((1 - A) exp(-B w) + A), w = s_C V (the slip velocity of
Polach's global model).  The model gives patch forces only: the traction, slip and
stick fields of the result are empty (all zero, no stick area), and
``options["local_fields"]`` is False.

Parameter presets (``preset="dry"`` / ``"wet"``) for the extended model are those of
``REFERENCES.md`` section 6.4, attributed there to Polach (2005) and marked as not
yet verified against the paper.
"""

from __future__ import annotations

import math
import time

import numpy as np
from numba import njit

from ..core.checks import shown
from ..core.errors import InputError
from ..core.materials import Material, STEEL
from .base import TangentialSolution, register
from .fastsim import equivalent_ellipse
from .friction import falling_friction
from .kalker import Creepage, KalkerCoefficients, kalker_coefficients

#: extended-model presets: (k_A, k_S, mu0, A, B [s/m]); source REFERENCES.md 6.4
#: (Polach 2005 as transcribed there, unverified against the paper)
PRESETS = {"dry": (1.00, 0.40, 0.55, 0.40, 0.60), "wet": (0.30, 0.10, 0.30, 0.40, 0.09)}


def polach_forces(Q, mu, a, b, G, nu, sx, sy, psi, kA=1.0, kS=1.0):
    """Polach's creep forces (F_x, F_y) [N] along the creepages; spin moment is not
    part of the method."""
    if Q <= 0 or a <= 0 or b <= 0:
        return 0.0, 0.0
    C = KalkerCoefficients(*kalker_coefficients(a / b, nu))
    return polach_kernel(Q, mu, a, b, G, C, Creepage(sx, sy, psi), kA, kS)


@njit(cache=True, nogil=True)
def polach_kernel(Q, mu, a, b, G, C, creepage, kA, kS):
    """:func:`polach_forces` with the creep coefficients given (compiled, for online
    use in the dynamics layer): wheel load Q [N], friction mu, semi-axes a, b [m],
    shear modulus G [Pa], Kalker's coefficients ``C``
    (:class:`~railcontact.tangential.kalker.KalkerCoefficients`), the creepages
    (:class:`~railcontact.tangential.kalker.Creepage`: sx, sy [-], psi [1/m]) and
    Polach's reduction factors kA, kS."""
    C11, C22, C23 = C.C11, C.C22, C.C23
    sx, sy, psi = creepage.xi, creepage.eta, creepage.phi
    if Q <= 0.0 or a <= 0.0 or b <= 0.0:
        return 0.0, 0.0
    syc = sy + psi * a if abs(sy + psi * a) > abs(sy) else sy
    sC = math.hypot(sx, syc)
    s = math.hypot(sx, sy)
    if sC == 0.0:
        return 0.0, 0.0
    cjj = math.hypot(C11 * sx / s, C22 * sy / s) if s > 0 else 0.0
    eps = math.pi * G * a * b * cjj * sC / (4 * Q * mu)
    F = 2 * Q * mu / math.pi * (kA * eps / (1 + (kA * eps) ** 2) + math.atan(kS * eps))
    KS = 1 + 6.3 * (1 - math.exp(-a / b))
    epsM = 8.0 / 3.0 * G * b * math.sqrt(a * b) * C23 * abs(syc) / (Q * mu * KS)
    d = (epsM ** 2 - 1) / (epsM ** 2 + 1)
    KM = abs(epsM) * (d ** 3 / 3 - d ** 2 / 2 + 1.0 / 6.0) - math.sqrt(max(1 - d * d, 0.0) ** 3) / 3
    FyS = -9.0 / 16.0 * a * Q * mu * KM * KS * psi / sC
    return F * sx / sC, F * sy / sC + FyS


@register("polach")
class PolachModel:
    """Polach's method, basic (1999) or extended (2005, with falling friction).

    Parameters
    ----------
    kA, kS : float
        Reduction factors of the initial slope in adhesion and slip (1, 1: basic model).
    falling : dict, optional
        {"A": mu_inf/mu0, "B": s/m}: slip-velocity dependent friction.
    preset : {"dry", "wet"}, optional
        Extended-model parameters (k_A, k_S, mu0, A, B); mu0 replaces the case's
        friction coefficient.
    """

    capabilities = frozenset({"online"})
    #: code of the compiled law (:mod:`railcontact.tangential.online`)
    online_law = 2

    def __init__(self, kA: float = 1.0, kS: float = 1.0, falling=None, preset: str | None = None):
        self.mu0 = None
        if preset is not None:
            if preset not in PRESETS:
                raise InputError(f"polach preset {shown(preset)}"
                                 f": expected one of {sorted(PRESETS)}")
            kA, kS, self.mu0, A, B = PRESETS[preset]
            falling = {"A": A, "B": B}
        if not (0 < kS <= kA <= 1):
            raise InputError(f"polach kA = {shown(kA)}, kS = {shown(kS)}"
                             f": expected 0 < kS <= kA <= 1")
        self.kA, self.kS, self.falling, self.preset = kA, kS, falling_friction(falling), preset

    def solve(self, normal, geometry=None, material: Material = STEEL, creepage=(0.0, 0.0, 0.0),
              friction: float = 0.3, velocity: float = 1.0) -> TangentialSolution:
        """Patch creep forces [N] on the wheel for creepages (xi, eta, phi [1/m])."""
        t0 = time.perf_counter()
        xi, eta, phi = (float(c) for c in creepage)
        if not all(math.isfinite(c) for c in (xi, eta, phi)):
            raise InputError(f"creepage = {shown(creepage)}: expected finite values")
        mu0 = self.mu0 if self.mu0 is not None else friction
        if not (math.isfinite(mu0) and 0 < mu0 <= 5):
            raise InputError(f"friction.coefficient = {shown(mu0)}: expected a value in (0, 5]")
        a, b = equivalent_ellipse(normal)
        syc = eta + phi * a if abs(eta + phi * a) > abs(eta) else eta
        mu = mu0
        if self.falling is not None:
            mu = float(self.falling(mu0, math.hypot(xi, syc) * velocity))
        fx, fy = polach_forces(normal.normal_force, mu, a, b, material.shear_modulus,
                               material.nu, xi, eta, phi, self.kA, self.kS)
        z = np.zeros_like(normal.pressure)
        return TangentialSolution("polach", normal.x, normal.y, z, z.copy(), z.copy(), z.copy(),
                                  np.zeros(z.shape, bool), normal.contact, fx, fy, 0.0, velocity,
                                  (xi, eta, phi), mu, time.perf_counter() - t0,
                                  {"local_fields": False, "mu": mu, "kA": self.kA,
                                   "kS": self.kS, "preset": self.preset})
