"""Elastic material data (SI units)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import InputError


@dataclass(frozen=True)
class Material:
    """Linear elastic, isotropic material, identical for wheel and rail.

    Parameters
    ----------
    young_modulus : float
        Young's modulus E [Pa]. Default: steel, 2.1e11 Pa.
    poisson_ratio : float
        Poisson's ratio nu [-]. Default 0.28.
    """

    young_modulus: float = 2.1e11
    poisson_ratio: float = 0.28

    def __post_init__(self) -> None:
        E, nu = self.young_modulus, self.poisson_ratio
        if not (isinstance(E, (int, float)) and math.isfinite(E) and 1e6 <= E <= 1e13):
            raise InputError(
                f"material.young_modulus = {E!r}: expected a Young's modulus in Pa "
                "between 1e6 and 1e13 (steel: 2.1e11)")
        if not (isinstance(nu, (int, float)) and math.isfinite(nu) and 0.0 <= nu < 0.5):
            raise InputError(
                f"material.poisson_ratio = {nu!r}: expected a value in [0, 0.5)")

    @property
    def shear_modulus(self) -> float:
        """Shear modulus G = E / (2 (1 + nu)) [Pa]."""
        return self.young_modulus / (2.0 * (1.0 + self.poisson_ratio))

    @property
    def contact_modulus(self) -> float:
        """Plane-strain contact modulus E* of the pair [Pa].

        1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2, here with identical bodies.
        """
        return self.young_modulus / (2.0 * (1.0 - self.poisson_ratio ** 2))

    @classmethod
    def from_shear_modulus(cls, shear_modulus: float, poisson_ratio: float) -> "Material":
        """Build from G [Pa] and nu, as CONTACT inputs are given."""
        return cls(2.0 * shear_modulus * (1.0 + poisson_ratio), poisson_ratio)


STEEL = Material()
