"""Given tangential forces instead of creepages: solve for (xi, eta).

For any tangential model, find the creepages (xi, eta) at a given spin phi for which
the creep forces on the wheel equal (F_x, F_y).  Newton's method with a finite-
difference Jacobian, started from Kalker's linear theory (F = G c^2 C xi), with
step halving when the residual does not decrease.  Forces at or beyond the
saturation mu F_n cannot be prescribed (error).
"""

from __future__ import annotations

import math

import numpy as np

from ..core.checks import shown
from ..core.errors import ConvergenceError, InputError
from .fastsim import equivalent_ellipse
from .kalker import kalker_coefficients


def solve_for_forces(model, normal, geometry, material, forces, spin: float = 0.0,
                     friction: float = 0.3, velocity: float = 1.0, rtol: float = 1e-6,
                     maxiter: int = 40):
    """Tangential solution with prescribed forces (F_x, F_y) [N] on the wheel.

    Returns the model's :class:`TangentialSolution`; ``creepage`` holds the
    creepages found.
    """
    fx_t, fy_t = (float(f) for f in forces)
    fn = normal.normal_force
    if not (math.isfinite(fx_t) and math.isfinite(fy_t)):
        raise InputError(f"forces = {shown(forces)}: expected finite values in N")
    if math.hypot(fx_t, fy_t) >= 0.999 * friction * fn:
        raise InputError(f"tangential force {math.hypot(fx_t, fy_t):.6g} N: expected less than "
                         f"the saturation mu F_n = {friction * fn:.6g} N")
    a, b = equivalent_ellipse(normal)
    c11, c22, _ = kalker_coefficients(a / b, material.nu)
    G, c2 = material.shear_modulus, a * b
    x = np.array([fx_t / (G * c2 * c11), fy_t / (G * c2 * c22)])
    scale = friction * fn

    def residual(v):
        t = model.solve(normal, geometry, material, (v[0], v[1], spin), friction, velocity)
        return np.array([t.fx - fx_t, t.fy - fy_t]), t

    r, t = residual(x)
    for _ in range(maxiter):
        if np.max(np.abs(r)) <= rtol * scale:
            return t
        h = 1e-6 * max(np.max(np.abs(x)), 1e-6)
        J = np.empty((2, 2))
        for k in range(2):
            e = x.copy()
            e[k] += h
            J[:, k] = (residual(e)[0] - r) / h
        try:
            dx = np.linalg.solve(J, -r)
        except np.linalg.LinAlgError:
            dx = -r / np.array([G * c2 * c11, G * c2 * c22])
        step = 1.0
        for _ in range(20):
            r_new, t_new = residual(x + step * dx)
            if np.linalg.norm(r_new) < np.linalg.norm(r):
                break
            step *= 0.5
        x, r, t = x + step * dx, r_new, t_new
    raise ConvergenceError(f"creepages for forces {shown(forces)} N not found in {maxiter} "
                           f"iterations (residual {np.max(np.abs(r)):.3g} N)")
