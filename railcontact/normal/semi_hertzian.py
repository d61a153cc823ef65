"""Semi-Hertzian (strip) normal models on a patch's grid: ``kik-piotrowski``,
``kpec``, ``stripes``, ``analyn``.

The models' equations are in :mod:`railcontact.normal.strip_theory` (shared with the
batch path :mod:`railcontact.normal.strip_batch`); here they run on the undeformed
distance h(x, y) of the geometry layer on a grid of the tangent plane, as the exact
model does: every grid column is a strip, its smallest gap, position and curvatures
come from :func:`strip_minima`, and the strips' semi-elliptic pressures are laid on
the grid, which the tangential models (exact, FASTSIM, FaStrip) then use.

A given normal force is met by Brent's method on the approach.
"""

from __future__ import annotations

import math
import time

import numpy as np
from scipy.interpolate import RegularGridInterpolator
from scipy.optimize import brentq, root_scalar

from ..core.errors import InputError
from ..core.materials import STEEL, Material
from ..core.status import SolverStatus
from .base import NormalSolution, make_grid, register, resized_elements
from .exact import ExactNormalModel
from .potential_area import own_gap
from ..core.hertz_theory import hertz_ellipse
from .strip_theory import MIN_CURVATURE, parabolic_minima, strip_pressures

__all__ = ["strip_minima", "KikPiotrowskiModel", "KPECModel", "AnalynModel",
           "StripesModel", "MIN_CURVATURE"]


def strip_minima(h, x, dx: float, dy: float):
    """Per strip (column of h): position x_m(y) and value g(y) of the gap's minimum
    along x, and the relative curvatures A(y), B(y) [1/m] there.

    A parabola through the grid row of the smallest gap and its two neighbours gives
    x_m, g and A (:func:`~railcontact.normal.strip_theory.parabolic_minima`, as the
    batch path's three samples per strip); B is the second difference across the
    neighbouring strips at x_m, each strip's values taken from its parabola on the
    same rows.  All four are continuous in the gap: where two rows either side of
    the minimum hold equal gaps (a gap symmetric in x on a grid without a row at
    x = 0), which of the two the rounding of h makes the smaller does not change
    the result.  Curvatures below ``MIN_CURVATURE`` are raised to it.  Needs a grid
    of at least 3 x 3.
    """
    mx, my = h.shape
    ixm = np.clip(np.argmin(h, axis=0), 1, mx - 2)
    cols = np.arange(my)

    def rows(j):
        return h[ixm - 1, j], h[ixm, j], h[ixm + 1, j]

    t, c1, c2, g = parabolic_minima(*rows(cols), dx, dx)

    def at(j):
        _, n1, n2, _ = parabolic_minima(*rows(j), dx, dx)
        return h[ixm, j] + n1 * t + n2 * t * t

    jc = np.clip(cols, 1, my - 2)
    B = 0.5 * (at(jc + 1) - 2.0 * at(jc) + at(jc - 1)) / dy ** 2
    return x[ixm] + t, g, np.maximum(c2, MIN_CURVATURE), np.maximum(B, MIN_CURVATURE)


class _StripModel(ExactNormalModel):
    """A strip model on a patch's grid: the grid's columns are its strips; grid,
    approach iteration and result are common, the model's rules are
    :func:`~railcontact.normal.strip_theory.strip_pressures`'s."""

    capabilities = frozenset({"force-control", "batch", "strips"})
    #: Kik-Piotrowski's constant scaling (used by ``kik-piotrowski`` only)
    eps = 0.55

    def __init__(self, margin: float = 0.25):
        super().__init__(margin=margin)

    def _pressure(self, hstar, x, y, dx, dy, material):
        """Pressure on the grid, contact mask and strip edges (x_lead, x_trail)
        for the interpenetration ``hstar = h - delta``."""
        xm, g, A, B = strip_minima(hstar, x, dx, dy)
        half, peak = strip_pressures(self.name, y[None, :], np.array([dy]), xm[None, :],
                                     g[None, :], A[None, :], B[None, :],
                                     material.contact_modulus, eps=self.eps,
                                     elements=hstar.shape[0])
        half, peak = half[0], peak[0]
        on = half > 0
        with np.errstate(divide="ignore", invalid="ignore"):
            r = (x[:, None] - xm[None, :]) / np.where(on, half, 1.0)[None, :]
        inside = on[None, :] & (np.abs(r) < 1)
        p = np.where(inside, peak[None, :] * np.sqrt(np.clip(1 - r * r, 0, None)), 0.0)
        return p, p > 0, (np.where(on, xm + half, 0.0), np.where(on, xm - half, 0.0))

    @staticmethod
    def _secant_log(f, guess: float, force: float):
        """The approach at which ``f`` (the force minus ``force``) vanishes, by secant
        steps on log F against log approach (F grows about as the approach^1.5, so
        that a few steps reach 1e-10; docs/tuning.md, section "Strip models and the
        Hertz formulas").  None
        where a step leaves the contact or does not converge (the caller brackets)."""
        def g(s):
            F = f(math.exp(s)) + force
            return math.log(F / force) if F > 0 else math.nan

        try:
            r = root_scalar(g, method="secant", x0=math.log(guess),
                            x1=math.log(guess) + 0.1, xtol=1e-11, rtol=1e-11, maxiter=20)
        except (ValueError, ArithmeticError):
            return None
        if not (r.converged and math.isfinite(r.root)):
            return None
        return math.exp(r.root)

    def solve(self, geometry, material: Material = STEEL, normal_force: float | None = None,
              penetration: float | None = None, grid=None, element_size=None) -> NormalSolution:
        """Solve for a given normal force [N] or approach [m] on the geometry's gap."""
        t0 = time.perf_counter()
        if (normal_force is None) == (penetration is None):
            raise InputError("give exactly one of normal force and penetration")
        for name, v in (("normal force", normal_force), ("penetration", penetration)):
            if v is not None and not (math.isfinite(v) and v >= 0):
                raise InputError(f"{name} {v!r}: expected a finite value >= 0")
        guess = penetration
        if guess is None:
            A, B = geometry.curvatures
            guess = hertz_ellipse(max(A, MIN_CURVATURE), max(B, MIN_CURVATURE),
                                  material.contact_modulus, force=normal_force).penetration
        (cx, cy), (ex, ey) = self._potential_area(geometry, material, None, 1.5 * guess)
        x, y = make_grid(ex, ey, grid, element_size, center=(cx, cy))
        dx, dy = float(x[1] - x[0]), float(y[1] - y[0])
        h0 = own_gap(geometry, x, y) + geometry.approach

        def at(delta):
            return self._pressure(h0 - delta, x, y, dx, dy, material)

        if penetration is not None:
            p, contact, strips = at(penetration)
            delta = penetration
        else:
            seen = {}

            def f(d):
                seen[d] = at(d)
                return float(seen[d][0].sum() * dx * dy) - normal_force

            delta = self._secant_log(f, guess, normal_force) if normal_force > 0 else None
            if delta is None:
                lo, hi = 0.2 * guess, 2.0 * guess
                while f(hi) < 0:
                    hi *= 2
                if f(lo) > 0:
                    # down to the approach at which no element interpenetrates (F = 0):
                    # below 0 where the grid's deepest point lies below the search's
                    delta = min(float(h0.min()), 0.0)
                    lo = delta
                delta = brentq(f, lo, hi, rtol=1e-10, xtol=1e-15)
            p, contact, strips = seen[delta] if delta in seen else at(delta)
        interp = RegularGridInterpolator((x, y), p, bounds_error=False, fill_value=0.0)

        def pressure_at(xq, yq, interp=interp):
            xq, yq = np.broadcast_arrays(np.asarray(xq, float), np.asarray(yq, float))
            return np.maximum(interp(np.stack([xq.ravel(), yq.ravel()], -1)), 0.0).reshape(xq.shape)

        dA = dx * dy
        return NormalSolution(model=self.name, x=x, y=y, pressure=p, contact=contact,
                              area=float(contact.sum() * dA), pmax=float(p.max(initial=0.0)),
                              penetration=float(delta), normal_force=float(p.sum() * dA),
                              semi_axes=None, strips=strips, pressure_at=pressure_at,
                              cpu_time=time.perf_counter() - t0, gap=h0,
                              **_resized_status(element_size, dx, dy))


def _resized_status(element_size, dx, dy) -> dict:
    """``status`` with the warning of elements changed from the request, if any."""
    w = resized_elements(element_size, dx, dy)
    return {"status": SolverStatus().with_warnings(w)} if w else {}


@register("kik-piotrowski")
class KikPiotrowskiModel(_StripModel):
    """Kik-Piotrowski with a constant virtual-penetration scaling ``eps`` (0.55)."""

    def __init__(self, eps: float = 0.55, margin: float = 0.25):
        if not 0 < eps <= 1:
            raise InputError(f"kik-piotrowski eps {eps!r}: expected a value in (0, 1]")
        super().__init__(margin=margin)
        self.eps = eps


@register("kpec")
class KPECModel(_StripModel):
    """Kik-Piotrowski with ellipse correction (variable scaling per strip)."""


@register("analyn")
class AnalynModel(_StripModel):
    """ANALYN: strip-wise Hertzian pressure from local curvatures and approach."""


@register("stripes")
class StripesModel(_StripModel):
    """STRIPES (Ayasse & Chollet): Hertz strips with constant longitudinal and
    corrected local lateral curvature."""
