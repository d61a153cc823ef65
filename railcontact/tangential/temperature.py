"""Flash temperatures of the contact surfaces in steady rolling.

Each body's material passes the contact at the rolling velocity V; at the Peclet
numbers of wheel-rail contact (V a / 2 kappa of thousands) heat flows into the
bodies only normal to the surface, so that along each strip the surface
temperature of body a follows the one-dimensional solution of a moving heat
source (Jaeger 1942; Carslaw & Jaeger 1959, sec. 2.9; Ertz & Knothe 2002, *Wear*
253, 498-508, on whose scheme CONTACT's calculation rests):

    T_a(x) = T0_a + 1 / sqrt(pi lambda_a rho_a c_a V) * int_{x_in}^{x} q_a(xi) / sqrt(x - xi) dxi,

x along the material's path (it enters at x_in), q_a the heat flux into body a.
The frictional power density q = |p_t| |s_a| (tangential traction times the
absolute slip velocity) is split between the bodies, q_1 + q_2 = q, such that
their surface temperatures are equal in the contact area; outside it no heat
crosses.  With piecewise constant fluxes per element the integral is exact per
element: element j contributes 2 (sqrt(x - xi_lo) - sqrt(x - xi_hi)) q_j at x.

Functions work on the arrays of a grid (rolling direction x first), SI units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError


@dataclass(frozen=True)
class ThermalProperties:
    """Heat-related constants of a body: bulk temperature [deg C], specific heat
    capacity [J/(kg K)], thermal conductivity [W/(m K)], density [kg/m^3]."""

    bulk_temperature: float
    heat_capacity: float
    conductivity: float
    density: float

    def __post_init__(self):
        for name in ("heat_capacity", "conductivity", "density"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise InputError(f"thermal {name} = {v!r}: expected a positive value")

    def jaeger_factor(self, velocity: float) -> float:
        """1 / sqrt(pi lambda rho c V) [K m^2 / (W sqrt(m))]."""
        return 1.0 / math.sqrt(math.pi * self.conductivity * self.density * self.heat_capacity
                               * velocity)


def _abel_matrix(m: int, dx: float) -> np.ndarray:
    """A[i, j]: the integral of 1/sqrt(x_i - xi) over element j (upstream of or at
    the centre x_i of element i; elements of length dx, material moving towards
    increasing index): 2 (sqrt(x_i - xi_lo) - sqrt(x_i - xi_hi)), the own element
    to its centre."""
    i = np.arange(m)[:, None]
    j = np.arange(m)[None, :]
    lo = (i - j + 0.5) * dx            # x_i - (left end of element j)
    hi = np.maximum((i - j - 0.5) * dx, 0.0)
    return np.where(j <= i, 2.0 * (np.sqrt(np.maximum(lo, 0.0)) - np.sqrt(hi)), 0.0)


def flash_temperatures(heat_flux, contact, dx, velocity, body1: ThermalProperties,
                       body2: ThermalProperties):
    """Surface temperatures (T_1, T_2) [deg C] of both bodies on the grid, and the
    heat flux q_1 [W/m^2] into body 1.

    ``heat_flux`` (mx, my) [W/m^2]: the frictional power density; ``contact``:
    the contact mask; ``dx`` [m]: element length along the material's path, which
    runs along increasing x index (mirror a grid for the other direction);
    ``velocity`` [m/s] the rolling velocity.  In each strip the split of the flux
    is the one that makes both surfaces equally hot in every contact element
    (a triangular system solved from the entry on); elsewhere no heat crosses.
    """
    q = np.asarray(heat_flux, dtype=float)
    c = np.asarray(contact, dtype=bool)
    if q.shape != c.shape or q.ndim != 2:
        raise InputError(f"heat flux {q.shape} and contact {c.shape}: expected equal 2-D grids")
    if not (velocity > 0 and dx > 0):
        raise InputError(f"velocity {velocity!r} m/s, dx {dx!r} m: expected positive values")
    k1, k2 = body1.jaeger_factor(velocity), body2.jaeger_factor(velocity)
    A = _abel_matrix(q.shape[0], dx)
    dT0 = body2.bulk_temperature - body1.bulk_temperature
    q1 = np.zeros_like(q)
    for j in np.flatnonzero(c.any(axis=0)):          # strips with contact: a few dozen
        idx = np.flatnonzero(c[:, j])
        # T0_1 + k1 A q1 = T0_2 + k2 A (q - q1) on the contact elements, q1 = 0 elsewhere
        sub = A[np.ix_(idx, idx)]
        rhs = dT0 + k2 * (sub @ q[idx, j])
        q1[idx, j] = np.linalg.solve((k1 + k2) * sub, rhs)
    q2 = np.where(c, q - q1, 0.0)
    t1 = body1.bulk_temperature + k1 * (A @ q1)
    t2 = body2.bulk_temperature + k2 * (A @ q2)
    return t1, t2, q1
