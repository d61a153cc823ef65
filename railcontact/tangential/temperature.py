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

Two discretisations of the own element (``scheme``):

* ``"jaeger"`` (the default): the temperature at each element's centre, the own
  element's flux integrated exactly from its entry edge to its centre,
  2 sqrt(dx/2) q_i.  On a constant flux this is Jaeger's closed form exactly.
* ``"contact"``: CONTACT's (Vollebregt's steady-state temperature routine, read
  from its open source release): the upstream elements as above, but the own
  element counted twice as strongly, 4 sqrt(dx/2) q_i.  It converges to the same
  limit as dx -> 0 (the own element's share falls as sqrt(dx)), but on a
  0.2 mm grid it lies 14.5 K above Jaeger's in Ertz & Knothe's sliding case
  (166.8 against 152.3 C).  Used to reproduce CONTACT's printed MAX(T1,T2).

Functions work on the arrays of a grid (rolling direction x first), SI units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

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


#: the discretisations of the own element's heat input (module docstring)
SCHEMES = ("jaeger", "contact")


def _abel_matrix(m: int, dx: float, scheme: str = "jaeger") -> np.ndarray:
    """A[i, j]: the integral of 1/sqrt(x_i - xi) over element j (upstream of or at
    the centre x_i of element i; elements of length dx, material moving towards
    increasing index): 2 (sqrt(x_i - xi_lo) - sqrt(x_i - xi_hi)), the own element
    to its centre (``scheme = "contact"``: twice that, CONTACT's weight)."""
    i = np.arange(m)[:, None]
    j = np.arange(m)[None, :]
    lo = (i - j + 0.5) * dx            # x_i - (left end of element j)
    hi = np.maximum((i - j - 0.5) * dx, 0.0)
    A = np.where(j <= i, 2.0 * (np.sqrt(np.maximum(lo, 0.0)) - np.sqrt(hi)), 0.0)
    if scheme == "contact":
        A[np.diag_indices(m)] *= 2.0
    return A


@njit(cache=True, nogil=True)
def _split_flux(A, q, contact, dT0, k1, k2):
    """Body 1's share q1 of the heat flux q (m, n) that makes both surfaces equally
    hot on every contact element: per strip (column) the lower-triangular system
    (k1 + k2) sum_j A_ij q1_j = dT0 + k2 sum_j A_ij q_j over the contact elements
    i, j of the strip, solved by forward substitution from the entry on; q1 = 0
    outside the contact."""
    m, n = q.shape
    q1 = np.zeros((m, n))
    ks = k1 + k2
    for c in range(n):
        for i in range(m):
            if not contact[i, c]:
                continue
            s_q, s_q1 = 0.0, 0.0
            for j in range(i):
                if contact[j, c]:
                    s_q += A[i, j] * q[j, c]
                    s_q1 += A[i, j] * q1[j, c]
            s_q += A[i, i] * q[i, c]
            q1[i, c] = ((dT0 + k2 * s_q) / ks - s_q1) / A[i, i]
    return q1


def flash_temperatures(heat_flux, contact, dx, velocity, body1: ThermalProperties,
                       body2: ThermalProperties, scheme: str = "jaeger"):
    """Surface temperatures (T_1, T_2) [deg C] of both bodies on the grid, and the
    heat flux q_1 [W/m^2] into body 1.

    ``heat_flux`` (mx, my) [W/m^2]: the frictional power density; ``contact``:
    the contact mask; ``dx`` [m]: element length along the material's path, which
    runs along increasing x index (mirror a grid for the other direction);
    ``velocity`` [m/s] the rolling velocity; ``scheme``: the own element's weight,
    ``"jaeger"`` or ``"contact"`` (module docstring).  In each strip the split of
    the flux is the one that makes both surfaces equally hot in every contact
    element (a triangular system solved from the entry on, compiled); elsewhere no
    heat crosses.
    """
    q = np.ascontiguousarray(heat_flux, dtype=float)
    c = np.ascontiguousarray(contact, dtype=bool)
    if q.shape != c.shape or q.ndim != 2:
        raise InputError(f"heat flux {q.shape} and contact {c.shape}: expected equal 2-D grids")
    if not (velocity > 0 and dx > 0):
        raise InputError(f"velocity {velocity!r} m/s, dx {dx!r} m: expected positive values")
    if scheme not in SCHEMES:
        raise InputError(f"temperature scheme {scheme!r}: expected one of {SCHEMES}")
    k1, k2 = body1.jaeger_factor(velocity), body2.jaeger_factor(velocity)
    A = _abel_matrix(q.shape[0], dx, scheme)
    dT0 = body2.bulk_temperature - body1.bulk_temperature
    q1 = _split_flux(A, q, c, float(dT0), float(k1), float(k2))
    q2 = np.where(c, q - q1, 0.0)
    t1 = body1.bulk_temperature + k1 * (A @ q1)
    t2 = body2.bulk_temperature + k2 * (A @ q2)
    return t1, t2, q1


#: rail steel's thermal constants (Ertz & Knothe 2002): 450 J/(kg K), 50 W/(m K),
#: 7850 kg/m^3, at a bulk temperature of 20 deg C
STEEL = ThermalProperties(20.0, 450.0, 50.0, 7850.0)


def patch_temperatures(solution, rail: ThermalProperties = STEEL,
                       wheel: ThermalProperties = STEEL, scheme: str = "jaeger"):
    """Surface temperatures (T_rail, T_wheel) [deg C] on the grid of a steady
    rolling :class:`~railcontact.tangential.base.TangentialSolution`: the heat
    flux |p_t| |s| V of its tractions and slips, the material passing the patch
    from its leading edge (+x, the rolling direction) backwards; None where the
    grid has fewer than two elements along x or no contact."""
    x = np.asarray(solution.x, dtype=float)
    if x.ndim != 1 or x.size < 2 or not np.any(solution.contact):
        return None
    q = (np.hypot(solution.traction_x, solution.traction_y)
         * np.hypot(solution.slip_x, solution.slip_y) * abs(float(solution.velocity)))
    if not abs(float(solution.velocity)) > 0:
        return None
    f = lambda a: np.ascontiguousarray(np.asarray(a)[::-1])      # noqa: E731
    t1, t2, _ = flash_temperatures(f(q), f(solution.contact), float(abs(x[1] - x[0])),
                                   abs(float(solution.velocity)), rail, wheel, scheme)
    return f(t1), f(t2)
