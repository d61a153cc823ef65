"""Hertz normal contact model (``normal="hertz"``).

Hertz (1882); formulas as in Johnson, *Contact Mechanics* (1985), ch. 4, with
complete elliptic integrals (:mod:`railcontact.core.hertz_theory`).  The patch is
the ellipse of the relative curvatures at the first point of contact.
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from ..core.errors import InputError
from ..core.materials import STEEL, Material
from .base import NormalSolution, make_grid, register
from ..core.hertz_theory import hertz_ellipse


@register("hertz")
class HertzModel:
    """Elliptic Hertzian contact.

    Parameters
    ----------
    margin : float
        The potential contact grid covers the ellipse times (1 + margin).
    """

    capabilities = frozenset({"force-control", "ellipse", "batch"})

    def __init__(self, margin: float = 0.05):
        if not 0 <= margin <= 1:
            raise InputError(f"hertz margin {margin!r}: expected a value in [0, 1]")
        self.margin = margin

    def solve(self, geometry, material: Material = STEEL, normal_force: float | None = None,
              penetration: float | None = None, grid=None, element_size=None) -> NormalSolution:
        """Solve for a given normal force [N] or penetration [m].

        Parameters
        ----------
        geometry : ContactGeometry
            Supplies the relative curvatures (A, B).
        """
        t0 = time.perf_counter()
        A, B = geometry.curvatures
        Bf = getattr(geometry, "force_curvature", None)
        if Bf is not None and Bf > 0.0 and Bf != B and (normal_force is not None
                                                         or penetration is not None):
            # the force from the force curvature at the approach, the ellipse from
            # the curvatures at that force (geometry.wheel_pass.force_curvature)
            Es = material.contact_modulus
            if normal_force is None:
                normal_force = hertz_ellipse(A, Bf, Es, penetration=penetration).force
            else:
                penetration = hertz_ellipse(A, Bf, Es, force=normal_force).penetration
            h = hertz_ellipse(A, B, Es, force=normal_force)
            h = replace(h, penetration=penetration)
        else:
            h = hertz_ellipse(A, B, material.contact_modulus, force=normal_force,
                              penetration=penetration)
        a, b, p0 = h.a, h.b, h.p0
        s = 1.0 + self.margin
        x, y = make_grid(s * a, s * b, grid, element_size)
        r2 = (x[:, None] / a) ** 2 + (y[None, :] / b) ** 2 if a > 0 else np.ones((x.size, y.size))
        inside = r2 < 1.0
        p = np.where(inside, p0 * np.sqrt(np.clip(1.0 - r2, 0.0, None)), 0.0)
        half = a * np.sqrt(np.clip(1.0 - (y / b) ** 2, 0.0, None)) if b > 0 else np.zeros_like(y)

        def pressure_at(xq, yq, a=a, b=b, p0=p0):
            rr = (np.asarray(xq) / a) ** 2 + (np.asarray(yq) / b) ** 2
            return p0 * np.sqrt(np.clip(1.0 - rr, 0.0, None))

        return NormalSolution(model="hertz", x=x, y=y, pressure=p, contact=inside,
                              area=h.area, pmax=p0, penetration=h.penetration,
                              normal_force=h.force, semi_axes=(a, b), strips=(half, -half),
                              pressure_at=pressure_at, cpu_time=time.perf_counter() - t0)
