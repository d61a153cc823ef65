"""Kalker's linear theory (``tangential="linear"``): creep forces proportional to
the creepages, without a traction bound.

Kalker (1967), *On the rolling contact of two elastic bodies in the presence of dry
friction*; the creep coefficients of :func:`~railcontact.tangential.kalker.
kalker_coefficients` on the patch's (equivalent) ellipse, c = sqrt(a b):

    F_x = G c^2 C11 xi,    F_y = G c^2 C22 eta + G c^3 C23 phi

(forces on the wheel, with this package's creepage convention).  Valid for small
creepages only; it is the law of the linear stability analysis (critical speed)
and of quick dynamics runs.  Forces only: the traction, slip and stick fields of
the result are empty and ``options["local_fields"]`` is False.
"""

from __future__ import annotations

import time

import numpy as np

from ..core.materials import STEEL, Material
from .base import TangentialSolution, check_inputs, register
from .fastsim import equivalent_ellipse
from .kalker import kalker_coefficients, linear_forces


@register("linear")
class LinearModel:
    """Kalker's linear theory on the patch's equivalent ellipse."""

    capabilities = frozenset({"online"})
    #: code of the compiled law (:mod:`railcontact.tangential.online`)
    online_law = 0

    def solve(self, normal, geometry=None, material: Material = STEEL, creepage=(0.0, 0.0, 0.0),
              friction: float = 0.3, velocity: float = 1.0) -> TangentialSolution:
        """Creep forces [N] on the wheel for creepages (xi, eta, phi [1/m]); the
        friction coefficient is checked but does not bound the forces."""
        t0 = time.perf_counter()
        xi, eta, phi = check_inputs(creepage, friction)
        a, b = equivalent_ellipse(normal)
        fx = fy = 0.0
        if a > 0 and b > 0 and normal.normal_force > 0:
            c11, c22, c23 = kalker_coefficients(a / b, material.nu)
            fx, fy = linear_forces(material.shear_modulus, a, b, c11, c22, c23, xi, eta, phi)
        z = np.zeros_like(normal.pressure)
        return TangentialSolution(self.name, normal.x, normal.y, z, z.copy(), z.copy(), z.copy(),
                                  np.zeros(z.shape, bool), normal.contact, fx, fy, 0.0, velocity,
                                  (xi, eta, phi), friction, time.perf_counter() - t0,
                                  {"local_fields": False})
