"""Wear laws as local wear rates on the contact grid.

Every law gives the dimensionless local rate r(x, y) = wear depth per unit distance
that a surface point travels through the contact, so that a point crossing the patch
on strip y loses the depth d(y) = integral r dx.  All laws use the tangential
solution's traction tau [Pa] (on the wheel) and relative slip s [-] (rail relative
to wheel), and the normal pressure p [Pa]:

* ``frictional-power`` (seed 000): removed volume proportional to frictional energy,
  r = k |tau . s|, k [m^3/J] (= m^2/N).
* ``usfd`` (Braghin et al., Wear 261, 2006; Lewis & Dwyer-Joyce 2004): wear rate
  K(T gamma / A) [ug/(m mm^2)] by regime of I = |tau . s| [N/mm^2]: mild 5.3 I
  (I < 10.4), severe 55 (10.4 <= I <= 77.2), catastrophic 61.9 I - 4778.7 (as
  published, with its discontinuity at 77.2, see REFERENCES.md 8.1); r = K / rho.
* ``archard`` (Jendel, Wear 253, 2002): r = k p |s| / H with the wear coefficient k
  from the sliding velocity |s| V and the pressure relative to the hardness H
  (k1 for p > 0.8 H; else k2, k3, k4 for v < 0.2, 0.2-0.7, > 0.7 m/s); default
  coefficients are the mid-points of the ranges in REFERENCES.md 8.2 (unverified there).

For a tangential model without local fields (Polach) the patch-level variant applies
the law to the patch averages (T gamma / A with T gamma = |F_x xi + F_y eta| and A the
contact area) uniformly over the contact area.
"""

from __future__ import annotations

import math

import numpy as np

from ..core.errors import InputError
from ..core.registry import Registry

_LAWS = Registry("wear law")
register = _LAWS.register


def get_wear_law(name: str, **params):
    return _LAWS.create(name, **params)


def wear_laws() -> list:
    return _LAWS.names()


def _energy_density(tang):
    """|tau . s| [N/m^2] on the grid; patch average where no local fields exist."""
    if tang.options.get("local_fields", True):
        return np.abs(tang.traction_x * tang.slip_x + tang.traction_y * tang.slip_y)
    contact = tang.contact
    dA = (tang.x[1] - tang.x[0]) * (tang.y[1] - tang.y[0])
    area = contact.sum() * dA
    xi, eta, _ = tang.creepage
    tg = abs(tang.fx * xi + tang.fy * eta)          # T gamma per unit distance [N]
    return np.where(contact, tg / area if area > 0 else 0.0, 0.0)


@register("frictional-power")
class FrictionalPower:
    """V = k * frictional energy; k [m^3/J]."""

    def __init__(self, k: float = 1e-13):
        if not (k > 0 and math.isfinite(k)):
            raise InputError(f"frictional-power k = {k!r}: expected a wear coefficient > 0 m^3/J")
        self.k = k

    def rate(self, normal, tang, velocity):
        return self.k * _energy_density(tang)


@register("usfd")
class USFD:
    """Sheffield T gamma / A wear function; density rho [kg/m^3]."""

    def __init__(self, density: float = 7850.0):
        if not density > 0:
            raise InputError(f"usfd density {density!r}: expected a value > 0 kg/m^3")
        self.rho = density

    @staticmethod
    def wear_rate(I):
        """K [ug/(m mm^2)] for I = T gamma / A [N/mm^2], as published."""
        I = np.asarray(I, dtype=float)
        return np.where(I < 10.4, 5.3 * I, np.where(I <= 77.2, 55.0, 61.9 * I - 4778.7))

    def rate(self, normal, tang, velocity):
        I = _energy_density(tang) * 1e-6                 # N/mm^2
        K = self.wear_rate(I) * 1e-3                      # ug/(m mm^2) -> kg/(m m^2)
        return np.where(tang.contact, np.maximum(K, 0.0) / self.rho, 0.0)


@register("archard")
class Archard:
    """Archard's law with Jendel's wear map; hardness H [Pa]."""

    def __init__(self, hardness: float = 2.75e9, k1: float = 350e-4, k2: float = 5.5e-4,
                 k3: float = 35e-4, k4: float = 5.5e-4):
        if not hardness > 0:
            raise InputError(f"archard hardness {hardness!r}: expected a value > 0 Pa")
        self.H, self.k = hardness, (k1, k2, k3, k4)

    def rate(self, normal, tang, velocity):
        k1, k2, k3, k4 = self.k
        p = normal.pressure
        if tang.options.get("local_fields", True):
            slip = np.hypot(tang.slip_x, tang.slip_y)
        else:
            xi, eta, _ = tang.creepage
            slip = np.where(tang.contact, math.hypot(xi, eta), 0.0)
        v = slip * velocity
        k = np.where(p > 0.8 * self.H, k1, np.where(v < 0.2, k2, np.where(v <= 0.7, k3, k4)))
        return np.where(tang.contact, k * p * slip / self.H, 0.0)
