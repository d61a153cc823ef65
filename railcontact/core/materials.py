"""Elastic material data of the contacting pair (SI units)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from .checks import shown
from .errors import InputError


def _check(name, E, nu):
    if not (isinstance(E, (int, float)) and math.isfinite(E) and 1e6 <= E <= 1e13):
        raise InputError(f"material.{name}young_modulus = {shown(E)}: expected a Young's modulus "
                         "in Pa between 1e6 and 1e13 (steel: 2.1e11)")
    if not (isinstance(nu, (int, float)) and math.isfinite(nu) and 0.0 <= nu < 0.5):
        raise InputError(f"material.{name}poisson_ratio = {shown(nu)}: expected a value in [0, 0.5)")


@dataclass(frozen=True)
class Material:
    """Linear elastic, isotropic materials of rail (body 1) and wheel (body 2).

    Parameters
    ----------
    young_modulus : float
        Young's modulus E [Pa] of the rail, and of the wheel unless given.  Default:
        steel, 2.1e11 Pa.
    poisson_ratio : float
        Poisson's ratio nu [-] of the rail, and of the wheel unless given.  Default 0.28.
    wheel_young_modulus, wheel_poisson_ratio : float, optional
        The wheel's values for dissimilar materials.

    The models use the pair's combined constants (Kalker 1990, section 1.5):
    1/G = (1/G1 + 1/G2)/2, nu = G (nu1/G1 + nu2/G2)/2, 1/E* = (1 - nu1^2)/E1 +
    (1 - nu2^2)/E2, and the difference parameter
    K = G [(1 - 2 nu1)/G1 - (1 - 2 nu2)/G2] / 4, which couples normal and tangential
    problems (0 for quasi-identical bodies).
    """

    young_modulus: float = 2.1e11
    poisson_ratio: float = 0.28
    wheel_young_modulus: float | None = None
    wheel_poisson_ratio: float | None = None

    def __post_init__(self) -> None:
        _check("", self.young_modulus, self.poisson_ratio)
        _check("wheel_", self.wheel_young_modulus if self.wheel_young_modulus is not None
               else self.young_modulus,
               self.wheel_poisson_ratio if self.wheel_poisson_ratio is not None
               else self.poisson_ratio)

    @property
    def bodies(self):
        """((E1, nu1), (E2, nu2)): rail, wheel."""
        E2 = self.young_modulus if self.wheel_young_modulus is None else self.wheel_young_modulus
        n2 = self.poisson_ratio if self.wheel_poisson_ratio is None else self.wheel_poisson_ratio
        return (self.young_modulus, self.poisson_ratio), (E2, n2)

    @property
    def shear_modulus(self) -> float:
        """Combined shear modulus G [Pa], 1/G = (1/G1 + 1/G2)/2 (G = E/(2(1 + nu)))."""
        (E1, n1), (E2, n2) = self.bodies
        return 2.0 / (2.0 * (1.0 + n1) / E1 + 2.0 * (1.0 + n2) / E2)

    @property
    def nu(self) -> float:
        """Combined Poisson's ratio nu = G (nu1/G1 + nu2/G2) / 2."""
        (E1, n1), (E2, n2) = self.bodies
        G1, G2 = E1 / (2.0 * (1.0 + n1)), E2 / (2.0 * (1.0 + n2))
        return 0.5 * self.shear_modulus * (n1 / G1 + n2 / G2)

    @property
    def contact_modulus(self) -> float:
        """Plane-strain contact modulus E* of the pair [Pa]:
        1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2."""
        (E1, n1), (E2, n2) = self.bodies
        return 1.0 / ((1.0 - n1 * n1) / E1 + (1.0 - n2 * n2) / E2)

    @property
    def difference_parameter(self) -> float:
        """Kalker's K = G [(1 - 2 nu1)/G1 - (1 - 2 nu2)/G2] / 4 (rail 1, wheel 2)."""
        (E1, n1), (E2, n2) = self.bodies
        G1, G2 = E1 / (2.0 * (1.0 + n1)), E2 / (2.0 * (1.0 + n2))
        return 0.25 * self.shear_modulus * ((1 - 2 * n1) / G1 - (1 - 2 * n2) / G2)

    @property
    def is_dissimilar(self) -> bool:
        """True when the normal and tangential problems are coupled (K != 0)."""
        return abs(self.difference_parameter) > 1e-12

    @classmethod
    def from_shear_modulus(cls, shear_modulus: float, poisson_ratio: float) -> "Material":
        """Build from G [Pa] and nu, as CONTACT inputs are given."""
        return cls(2.0 * shear_modulus * (1.0 + poisson_ratio), poisson_ratio)


STEEL = Material()


#: a softening interfacial layer's yield limit stays above this fraction of its
#: initial value tau_c0 (CONTACT's lower limit)
YIELD_FLOOR = 0.1


@dataclass(frozen=True)
class InterfaceLayer:
    """An interfacial (third-body) layer between rail and wheel with a plastic
    yield limit that hardens or softens with the accumulated plastic flow
    (CONTACT's material model M = 4; Vollebregt, CONTACT user guide, "Interfacial
    layer of contaminants", after the rheometer data of Hou et al. 1997).

    The layer shears elastically, u_el = (h3 / G3) p_t, adding the flexibility
    h3/G3 [m/Pa] to each element's own displacement; where the tangential
    traction reaches the yield limit

        tau_c = tau_c0 + k_tau u*_pl,    u*_pl = integral of |du_pl|,

    it flows plastically (u*_pl the plastic displacement accumulated by the
    material on its way through the contact, fresh material entering with 0).
    The traction is bounded by min(mu p_n, tau_c); a softening limit (k_tau < 0)
    that the material carries on falls no lower than :data:`YIELD_FLOOR` tau_c0
    (as in CONTACT: the flow of the step itself may take the traction lower).

    Parameters
    ----------
    thickness : float
        Layer thickness h3 [m], >= 0 (0: no layer flexibility; the yield limit
        then acts at the surface of the softer body).
    shear_modulus : float
        Shear modulus G3 [Pa] of the layer, > 0.
    yield_stress : float
        Initial yield limit tau_c0 [Pa]; ``math.inf`` (or <= 0 in CONTACT's
        input) for none: an elastic layer.
    hardening : float
        Rate k_tau [Pa/m] of the yield limit with the accumulated plastic
        displacement: > 0 work-hardening, < 0 softening, 0 perfectly plastic.
    """

    thickness: float = 0.0
    shear_modulus: float = 1e9
    yield_stress: float = math.inf
    hardening: float = 0.0

    def __post_init__(self) -> None:
        for name, v, ok, want in (
                ("thickness", self.thickness, lambda v: math.isfinite(v) and v >= 0,
                 "a layer thickness in m >= 0"),
                ("shear_modulus", self.shear_modulus, lambda v: math.isfinite(v) and v > 0,
                 "a shear modulus in Pa > 0"),
                ("yield_stress", self.yield_stress, lambda v: not math.isnan(v) and v > 0,
                 "a yield limit in Pa > 0 (inf: none)"),
                ("hardening", self.hardening, math.isfinite,
                 "a finite hardening rate in Pa/m")):
            if not (isinstance(v, (int, float)) and not isinstance(v, bool) and ok(v)):
                raise InputError(f"layer.{name} = {shown(v)}: expected {want}")

    @property
    def flexibility(self) -> float:
        """The layer's tangential flexibility h3/G3 [m/Pa]."""
        return self.thickness / self.shear_modulus

    @property
    def yield_floor(self) -> float:
        """The lowest yield limit [Pa] a softening layer (k_tau < 0) carries from one
        step (element) to the next: a tenth of tau_c0, as CONTACT bounds it (0
        without plasticity)."""
        return YIELD_FLOOR * self.yield_stress if self.plastic else 0.0

    @property
    def plastic(self) -> bool:
        """Whether the layer yields (a finite yield limit)."""
        return math.isfinite(self.yield_stress)
