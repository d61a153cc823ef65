"""A case given by curvatures (``[bodies]``, with ``[force]``), parsed once into
typed values (SI units): :class:`BodiesSetup`."""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..core.checks import shown
from ..core.errors import CaseFileError
from .keys import CaseKeys

#: the radii of a ``[bodies]`` case
RADII = ("wheel_rolling", "wheel_lateral", "rail_rolling", "rail_lateral")


@dataclass(frozen=True)
class BodiesSetup:
    """Two bodies given by their principal radii of curvature.

    ``radii`` [m] by name (:data:`RADII`; negative = concave, ``inf`` = flat),
    ``curvatures`` (A, B) [1/m] the relative curvatures in the rolling and lateral
    directions, ``normal_force`` [N], ``velocity`` [m/s] and ``forces`` (F_x, F_y)
    [N], the prescribed tangential forces of ``[force]`` (None: creepages given).
    """

    radii: dict
    curvatures: tuple
    normal_force: float
    velocity: float = 1.0
    forces: tuple | None = None

    @property
    def rolling_radius(self) -> float:
        """The wheel's rolling radius [m] (NaN where not given)."""
        return float(self.radii.get("wheel_rolling", math.nan))

    def smallest_radius(self, *names) -> float:
        """The smallest absolute radius [m] among ``names``."""
        return min(abs(self.radii.get(k, math.inf)) for k in names)


def parse_bodies(case: CaseKeys) -> BodiesSetup:
    """The validated :class:`BodiesSetup` of a case's ``[bodies]`` and ``[force]``; a
    :class:`~railcontact.core.errors.CaseFileError` names the first key that is
    wrong."""
    given = case.get("bodies.radii")
    radii, curv = {}, {}
    for k in RADII:
        r = given.get(k, math.inf)
        if isinstance(r, bool) or not isinstance(r, (int, float)) or r == 0 or math.isnan(r):
            raise CaseFileError(f"bodies.radii.{k} = {shown(r)}: expected a radius in m (non-zero; "
                                "negative = concave, inf = flat)")
        radii[k] = float(r)
        curv[k] = 0.0 if math.isinf(r) else 1.0 / r
    A = 0.5 * (curv["wheel_rolling"] + curv["rail_rolling"])
    B = 0.5 * (curv["wheel_lateral"] + curv["rail_lateral"])
    if A <= 0 or B <= 0:
        raise CaseFileError(f"bodies.radii give relative curvatures A = {A:.4g}, B = {B:.4g} 1/m; "
                            "expected both > 0 (a concave body must have the larger radius)")
    forces = None
    if "force" in case.raw:
        forces = (case.number("force.longitudinal", 0.0, -1e8, 1e8, "N"),
                  case.number("force.lateral", 0.0, -1e8, 1e8, "N"))
    return BodiesSetup({k: v for k, v in radii.items() if k in given}, (A, B),
                       case.number("bodies.normal_force", None, 0.0, 1e8, "N"),
                       case.number("bodies.velocity", 1.0, 1e-6, 1e3, "m/s"), forces)
