"""Exact (boundary-element) normal contact: ``normal="exact"``.

Kalker's variational formulation of the normal problem for two identical elastic
half-spaces (Kalker 1990, ch. 2 and 5): on a grid of mx x my equal rectangles with
piecewise-constant pressure p, find p >= 0 with the deformed distance
e = h + A p - delta >= 0 and p e = 0, where h is the undeformed distance (from the
geometry layer's exact gap function), A the influence matrix of uniform pressures on
rectangles (:mod:`railcontact.normal.influence`) and delta the approach.

Solver: the constrained conjugate-gradient method of Polonsky & Keer (Wear 231,
1999), in its force-controlled form (the mean gap over the contact area is the
unknown approach) or displacement-controlled form (approach given).  Matrix-vector
products are FFT convolutions, so the cost per iteration is O(N log N); with the
approach given they run on the bounding box of the overlap h < delta, which holds
the contact.  A solution that does not reach the tolerance is flagged
(``converged=False``) and logged.
"""

from __future__ import annotations

import logging
import math
import time

import numpy as np

from ..core.errors import InputError
from ..core.hertz_theory import hertz_ellipse
from ..core.materials import STEEL, Material
from ..core.status import SolverStatus
from ..geometry.conformal import influence_angles
from ..geometry.gap import sampled_wheel_geometry
from .base import NormalSolution, bilinear, make_grid, register, resized_elements, same_grid
from .conformal_influence import blanco_normal_operator
from .influence import box_bounds, bounding_box, normal_operator, normal_operator_block
from .polonsky_keer import flat_punch_stiffness, gap_scale, polonsky_keer
from .viscoelastic import (ViscoelasticOption, active_set_normal, final_material,
                           viscoelastic_normal_operator)
from .potential_area import (AREA_SAMPLES, FORCE_BOX, GROWTH_STEPS, coarse_lines,
                             cut_regions, edge_sides, fits, grown_box, inside_bounds, own_gap,
                             plausible_growth, region_ends,
                             strip_edges, subregions)


log = logging.getLogger(__name__)


def _operator(grid_key, shape=None, cols=slice(None), angles=None):
    """The normal operator of the grid ``grid_key`` (whole, or a block of
    ``shape`` whose columns are ``cols``); with ``angles`` (the inclination [rad]
    of each grid column of a conformal patch) Blanco's corrected coefficients
    (:mod:`railcontact.normal.conformal_influence`)."""
    base = normal_operator(*grid_key) if shape is None else \
        normal_operator_block(*grid_key, *shape)
    if angles is None:
        return base
    return blanco_normal_operator(base, np.asarray(angles)[cols])



@register("exact")
class ExactNormalModel:
    """Kalker's exact theory of the normal contact problem on a boundary-element grid.

    Parameters
    ----------
    tol : float        relative tolerance of the pressure iteration (default 1e-5: the
                       pressure's relative change per iteration, and the rms gap on
                       the contact area relative to the gap's range; what it costs
                       in accuracy: docs/tuning.md, section "Normal: exact")
    maxiter : int      iteration limit
    margin : float     the potential contact area extends the expected contact by
                       this fraction on each side
    pressure_limit : float, optional
                       upper bound [Pa] of the pressure: elastic-perfectly-plastic
                       contact (:mod:`railcontact.normal.plasticity`, e.g.
                       ``pressure_limit(yield_stress)``); default none (elastic).
                       With the force given, the approach that carries it is
                       found by Brent's method on displacement-controlled solves.
    viscoelastic : dict or ViscoelasticOption, optional
                       steady rolling of viscoelastic bodies (the standard linear
                       solid, CONTACT's M = 1; :mod:`railcontact.normal.viscoelastic`):
                       ``spring_ratio``, ``relaxation_time`` [s] (per body or both)
                       and ``velocity`` [m/s]; the material's moduli are the initial
                       ones.  The influence matrix is then not symmetric: the
                       elastic solution with the final moduli is the start of an
                       active-set solve with the viscoelastic operator.
    wheel_sampling : {"exact", "contact"}
                       the wheel surface of a wheel-rail patch: exact (default), or
                       as CONTACT's planar contact takes it, linear across the patch
                       between wheel-profile samples one lateral element size
                       apart along the profile (needs ``element_size``;
                       :class:`railcontact.geometry.gap.SampledWheelGap`: about 1 um
                       deeper interpenetration between the samples on a worn
                       flange root, up to some per cent of a gauge-corner patch's
                       force; the default of a CONTACT input; docs/contact_users.md,
                       "The undeformed distance: CONTACT's planar rule").
    """

    def __init__(self, tol: float = 1e-5, maxiter: int = 3000, margin: float = 0.25,
                 pressure_limit: float | None = None, viscoelastic=None,
                 wheel_sampling: str = "exact"):
        if wheel_sampling not in ("exact", "contact"):
            raise InputError(f"exact wheel_sampling = {wheel_sampling!r}: expected 'exact' or "
                             "'contact'")
        self.wheel_sampling = wheel_sampling
        if not (0 < tol < 1e-2):
            raise InputError(f"exact tol {tol!r}: expected a value in (0, 0.01)")
        self.tol, self.maxiter, self.margin = tol, int(maxiter), margin
        if pressure_limit is None:
            pressure_limit = math.inf
        if isinstance(pressure_limit, bool) or not (isinstance(pressure_limit, (int, float))
                                                    and pressure_limit > 0):
            raise InputError(f"exact pressure_limit = {pressure_limit!r} Pa: expected a "
                             "pressure > 0 (or none: elastic)")
        self.pressure_limit = float(pressure_limit)
        self.viscoelastic = ViscoelasticOption.from_value(viscoelastic)
        if self.viscoelastic is not None and math.isfinite(self.pressure_limit):
            raise InputError("exact normal model: a pressure limit with viscoelastic "
                             "materials is not supported; expected one of them")

    def _potential_area(self, geometry, material, normal_force, penetration,
                        continuous=False):
        """Centre and half-extents [m] of the potential contact area."""
        ext = geometry.extent
        app = geometry.approach
        if ext is not None and app > 0 and geometry.gap_function is not None:
            return self._area_from_gap(geometry, penetration if penetration is not None
                                       else app, continuous)
        A, B = geometry.curvatures
        hz = hertz_ellipse(A, B, material.contact_modulus, force=normal_force,
                           penetration=penetration)
        f = 1.0 + self.margin
        return (0.0, 0.0), (hz.a * f, hz.b * f)

    def _area_from_gap(self, geometry, penetration, continuous=False):
        """Bounding box of the interpenetration region h + approach - penetration < 0
        (which contains the contact area), from a coarse sampling of the exact gap,
        widened by the margin.  ``continuous``: its ends interpolated between the
        samples, so that the box moves continuously with the penetration (the exact
        solver's contact lies in the region; the vertical-force iteration needs a
        force that is continuous in the approach); else one sample beyond the last
        sample inside."""
        x0, x1, y0, y1 = geometry.extent
        cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
        hx, hy = max(0.5 * (x1 - x0), 1e-4), max(0.5 * (y1 - y0), 1e-4)
        for _ in range(6):
            xs, ys = coarse_lines(cx, hx), coarse_lines(cy, hy)
            h = geometry.gap(xs[:, None], ys[None, :]) + geometry.approach - penetration
            i0, i1, j0, j1 = inside_bounds(h, np.ascontiguousarray(geometry.foreign(ys),
                                                                   dtype=np.bool_))
            if i1 < 0:
                break
            if i0 == 0 or i1 == xs.size - 1:
                hx *= 2
            if j0 == 0 or j1 == ys.size - 1:
                hy *= 2
            if 0 < i0 and i1 < xs.size - 1 and 0 < j0 and j1 < ys.size - 1:
                dx, dy = xs[1] - xs[0], ys[1] - ys[0]
                if continuous:
                    return self._region_box(xs, ys, h, (i0, i1, j0, j1), dx, dy)
                lo_x, hi_x = xs[i0] - dx, xs[i1] + dx
                lo_y, hi_y = ys[j0] - dy, ys[j1] + dy
                return self._widened(lo_x, hi_x, lo_y, hi_y)
        return (cx, cy), (hx * (1 + self.margin), hy * (1 + self.margin))

    def _region_box(self, xs, ys, h, bounds, sx, sy):
        """Potential area from the gap h on the lines xs, ys, negative from row
        i0 to i1 and column j0 to j1 (``bounds``, inside the lines): the region's
        ends where the smallest gap along the other axis crosses zero, interpolated
        between the lines, plus 1.5 coarse samples (sx, sy: where the first sample
        outside lies on average), widened by the margin.  Returns its centre and
        half-extents [m]."""
        lo_x, hi_x, lo_y, hi_y = region_ends(xs, ys, h, *bounds)
        return self._widened(lo_x - 1.5 * sx, hi_x + 1.5 * sx, lo_y - 1.5 * sy, hi_y + 1.5 * sy)

    def _widened(self, lo_x, hi_x, lo_y, hi_y):
        """Centre and half-extents [m] of a box widened by the margin."""
        f = 1.0 + self.margin
        return ((0.5 * (lo_x + hi_x), 0.5 * (lo_y + hi_y)),
                (0.5 * (hi_x - lo_x) * f, 0.5 * (hi_y - lo_y) * f))

    def _kept_grid_gap(self, geometry, penetration, sol, grid):
        """The undeformed distance on the grid of ``sol`` (an earlier pass of the same
        patch) where that grid is kept: the potential area of :meth:`_area_from_gap`,
        its ends found on this grid instead of the coarse samples (the same padding:
        1.5 coarse samples, then the margin), fits it by :func:`fits`.  None where
        it does not, or where the interpenetration region reaches the grid's border
        (then the coarse sampling decides)."""
        app = geometry.approach
        if geometry.extent is None or geometry.gap_function is None or not app > 0:
            return None
        x, y = sol.x, sol.y
        if x.size < 3 or y.size < 3:
            return None
        h0 = own_gap(geometry, x, y) + app
        h = h0 - (app if penetration is None else penetration)
        bounds = box_bounds(h < 0)
        i0, i1, j0, j1 = bounds
        if i1 < 0 or i0 == 0 or i1 == x.size - 1 or j0 == 0 or j1 == y.size - 1:
            return None
        x0, x1, y0, y1 = geometry.extent
        sx = 4.0 * max(0.5 * (x1 - x0), 1e-4) / (AREA_SAMPLES - 1)   # the coarse spacing
        sy = 4.0 * max(0.5 * (y1 - y0), 1e-4) / (AREA_SAMPLES - 1)
        (cx, cy), (ex, ey) = self._region_box(x, y, h, bounds, sx, sy)
        return h0 if fits(sol, cx, cy, ex, ey, grid) else None

    def _displacement_controlled(self, grid_key, h, dA, p0, regions=None, angles=None):
        """Polonsky-Keer with the approach given, on the bounding box of the overlap
        h < 0: the contact lies in it (the displacements of a pressure are positive
        everywhere), so outside it the pressure is zero and the iteration is that on
        the whole grid, with smaller FFTs (the convergence test keeps the whole
        grid's gap scale).  Returns p on the grid, iterations, converged."""
        box = bounding_box(h < 0)
        if box is None:                     # no overlap: p = 0 (reported at once)
            p, _, it, ok = polonsky_keer(_operator(grid_key, angles=angles), h, dA, None,
                                         self.tol, self.maxiter, p0=p0)
            return p, it, ok
        op = _operator(grid_key, h[box].shape, box[1], angles)
        q, _, it, ok = polonsky_keer(op, h[box], dA, None, self.tol, self.maxiter,
                                     p0=None if p0 is None else p0[box],
                                     scale=gap_scale(h),
                                     regions=cut_regions(regions, box[1]),
                                     pressure_limit=self.pressure_limit)
        p = np.zeros(h.shape)
        p[box] = q
        return p, it, ok

    def _force_controlled(self, grid_key, h0, dA, force, p0, approach, regions=None,
                          angles=None):
        """Polonsky-Keer with the force given, on the bounding box of h0 <
        FORCE_BOX x ``approach`` (the search's approach): where the solved approach
        is below that, the contact, which lies where h0 is below the solved
        approach, is inside the box and the solution is that of the whole grid (as
        in :meth:`_displacement_controlled`); else the whole grid is solved, from
        the box's solution.  Returns p on the grid, approach, iterations, converged."""
        def scaled(q):              # a start carrying the force, or None
            if q is None or not q.max() > 0:
                return None
            return q * force / max(float(q.sum() * dA), 1e-300)

        scale = gap_scale(h0)
        box = bounding_box(h0 < FORCE_BOX * approach) if approach > 0 else None
        it0 = 0
        if box is not None:
            q0 = None if p0 is None else scaled(np.ascontiguousarray(p0[box]))
            q, app, it0, ok = polonsky_keer(_operator(grid_key, h0[box].shape, box[1], angles),
                                            h0[box], dA, force=force, tol=self.tol,
                                            maxiter=self.maxiter, p0=q0, scale=scale,
                                            regions=cut_regions(regions, box[1]))
            p = np.zeros(h0.shape)
            p[box] = q
            if ok and app <= FORCE_BOX * approach:
                return p, app, it0, ok
            p0 = p if ok and p.max() > 0 else p0
        p, app, it, ok = polonsky_keer(_operator(grid_key, angles=angles), h0, dA, force=force,
                                       tol=self.tol, maxiter=self.maxiter, p0=scaled(p0),
                                       scale=scale, regions=regions)
        return p, app, it0 + it, ok

    def _force_by_approach(self, grid_key, h0, dA, force, p0, regions=None, angles=None):
        """Force-controlled solve with the pressure limit: the approach delta that
        carries ``force`` by Brent's method on displacement-controlled solves (each
        from the last solution), the force F(delta) being continuous and increasing.
        The bracket starts at the elastic approach, which carries less than the
        force once the pressure is capped.  Returns p, approach, iterations,
        converged."""
        from scipy.optimize import brentq

        limit = self.pressure_limit
        p, app, it, ok = self._force_controlled(grid_key, h0, dA, force, p0, 0.0, regions,
                                                angles)
        if not ok or p.max() <= limit:
            return p, app, it, ok                   # the elastic solution holds
        state = {"p": np.minimum(p, limit), "it": it, "ok": True}

        def excess(delta):
            q, k, good = self._displacement_controlled(grid_key, h0 - delta, dA, state["p"],
                                                       regions, angles)
            state["it"] += k
            state["ok"] &= good
            if q.max() > 0:
                state["p"] = q
            return float(q.sum() * dA) / force - 1.0

        lo, hi = app, app * 1.25
        f_hi = excess(hi)
        while f_hi < 0.0:
            lo, hi = hi, hi * 1.5
            f_hi = excess(hi)
            if hi > 1e3 * app:
                return state["p"], hi, state["it"], False
        delta = brentq(excess, lo, hi, xtol=1e-10 * app, rtol=1e-12, maxiter=100)
        excess(delta)                      # the solution at the root (its pressure)
        return state["p"], delta, state["it"], state["ok"]

    def _plastic_extent(self, geometry, material, normal_force, ex, ey):
        """Half-extents of the potential area widened for a pressure limit below
        Hertz's peak: the contact then spreads to about force / limit (with its
        elastic rim), against Hertz's pi a b."""
        if normal_force is None or not math.isfinite(self.pressure_limit):
            return ex, ey
        A, B = geometry.curvatures
        hz = hertz_ellipse(A, B, material.contact_modulus, force=normal_force)
        if hz.p0 <= self.pressure_limit:
            return ex, ey
        k = math.sqrt(1.3 * normal_force / (self.pressure_limit * hz.area))
        return ex * max(k, 1.0), ey * max(k, 1.0)

    capabilities = frozenset({"force-control", "warm-start", "grid-reuse", "coupled",
                              "contact-stiffness"})

    @staticmethod
    def _viscoelastic(grid_key, visc, h0, force, p0):
        """The viscoelastic pressure on the grid (``grid_key``'s sizes) by the active
        set with the steady-rolling operator of ``visc``, from the elastic pressure
        ``p0`` with the final moduli; ``force`` [N] given, or None with ``h0`` less the
        approach.  Returns p, approach (force given), iterations, converged."""
        mx, my, dx, dy, _ = grid_key
        op = viscoelastic_normal_operator(mx, my, dx, dy, visc)
        return active_set_normal(op, h0, dx * dy, force, p0)

    def contact_stiffness(self, solution: NormalSolution, material: Material = STEEL,
                          geometry=None) -> float:
        """dF_n/d(delta) [N/m] of a converged solution: the stiffness of a rigid flat
        punch on its contact area (:func:`~railcontact.normal.polonsky_keer.flat_punch_stiffness`),
        on its own grid and influence coefficients (the sub-regions of a combined
        patch, from ``geometry``, interacting as in the solve).  Hertz's patch:
        3/2 F_n/delta.  0 where the solution carries no load; NaN where the
        iteration does not converge, and under a pressure limit or with viscoelastic
        bodies (where it is not the elastic punch's)."""
        if not isinstance(solution, NormalSolution) or solution.model != "exact":
            raise InputError(f"solution {type(solution).__name__}: expected the exact "
                             "model's NormalSolution")
        if math.isfinite(self.pressure_limit) or self.viscoelastic is not None:
            return math.nan         # the flat punch's stiffness is the elastic one's
        box = bounding_box(solution.contact)
        if box is None:
            return 0.0
        x, y = solution.x, solution.y
        dx, dy = float(x[1] - x[0]), float(y[1] - y[0])
        mask = np.ascontiguousarray(solution.contact[box])
        angles = None if geometry is None else influence_angles(geometry, y)
        op = _operator((x.size, y.size, dx, dy, material.contact_modulus), mask.shape, box[1],
                       angles)
        regions = cut_regions(subregions(geometry, y), box[1]) if geometry is not None \
            else None
        k, it, ok = flat_punch_stiffness(op, mask, dx * dy, regions, tol=1e-8,
                                         maxiter=self.maxiter)
        if not ok:
            log.info("exact contact stiffness: no convergence in %d iterations", it)
            return math.nan
        return k

    def solve(self, geometry, material: Material = STEEL, normal_force: float | None = None,
              penetration: float | None = None, grid=None, element_size=None,
              warm_start: NormalSolution | None = None,
              extra_gap: np.ndarray | None = None,
              reuse_grid: NormalSolution | None = None) -> NormalSolution:
        """Solve for a given normal force [N] or approach [m] (see :meth:`_solve`).

        Where the contact reaches the edge of the potential contact area (the
        interpenetration region's extent, found on a coarse sampling of the gap,
        can miss parts of a rough or conformal patch of measured profiles), the
        area is enlarged by half its width on each side the contact reaches and the
        problem solved again, up to ``GROWTH_STEPS`` times; the warning of a
        truncated contact remains only where that does not suffice (or a kept grid,
        or ``extra_gap`` on it, fixes the area)."""
        t0 = time.perf_counter()
        if self.wheel_sampling == "contact" and element_size is not None:
            geometry = sampled_wheel_geometry(geometry, float(element_size[1]))
        box, sol = None, None
        visc = None
        if self.viscoelastic is not None:
            # the elastic problem with the final (softest) moduli sizes the area and
            # starts the viscoelastic solve (:meth:`_viscoelastic`)
            visc = self.viscoelastic.pair(material)
            material = final_material(visc)
        for _ in range(GROWTH_STEPS + 1):
            new = self._solve(geometry, material, normal_force, penetration, grid,
                              element_size, warm_start, extra_gap, reuse_grid, box, visc)
            if sol is not None and not plausible_growth(sol, new, normal_force is None):
                # the enlarged area reached other parts of the surfaces (the tangent
                # plane's normals meet them far from the patch): keep the last one
                log.info("exact normal solver: an enlarged potential area changes the "
                         "solution implausibly; the area is kept")
                break
            sol = new
            sides = edge_sides(sol.contact)
            if not any(sides) or extra_gap is not None or geometry.gap_function is None:
                break
            box = grown_box(sol.x, sol.y, sides)
            reuse_grid = None
            warm_start = sol if sol.pressure.max() > 0 else warm_start
            log.info("exact normal solver: the contact reaches the edge of its potential area; "
                     "enlarged to %.2f x %.2f mm", 2e3 * box[1][0], 2e3 * box[1][1])
        sides = edge_sides(sol.contact)
        if any(sides):
            log.info("exact normal solver: contact reaches the edge of the potential contact "
                     "area; results may be truncated")
        sol.cpu_time = time.perf_counter() - t0
        return sol

    def _solve(self, geometry, material, normal_force, penetration, grid, element_size,
               warm_start, extra_gap, reuse_grid, box, visc=None) -> NormalSolution:
        """Solve for a given normal force [N] or approach [m] on one potential area.

        ``extra_gap``: a displacement difference [m] added to the undeformed distance
        on the solution grid (the tangential tractions' share for dissimilar
        materials, :mod:`railcontact.cases.coupling`), or a function of the grid's
        (x, y) [m] that gives it (Blanco's coefficients on a conformal patch,
        whose grid may differ from the last solution's).

        ``warm_start``: a previous solution whose pressure is the initial estimate: on
        the same grid (e.g. in the vertical-force iteration) as it is, on another grid
        (a neighbouring case of a sweep) interpolated.

        ``reuse_grid``: a solution of the same patch at a nearby approach (an earlier
        pass of the vertical-force iteration): its grid is kept where the potential
        contact area still lies in it and fills at least ``REUSE_FILL`` of it in
        each direction (with ``grid`` given or by default, not with
        ``element_size``), so that the pressure and the tangential solution of that
        pass are exact starts and the influence coefficients are reused.

        The undeformed distance is taken from ``geometry.gap`` (the exact gap of the
        geometry layer, shifted so that ``penetration`` is measured from the
        search position's approach), or from its curvatures for a bodies case.

        ``box``: centre and half-extents [m] of the potential contact area instead of
        the model's choice (:meth:`solve` enlarging it).

        ``visc``: a :class:`~railcontact.normal.viscoelastic.Viscoelastic` pair
        (``material`` then its final moduli): the elastic solution starts the
        viscoelastic one (:meth:`_viscoelastic`).
        """
        t0 = time.perf_counter()
        if (normal_force is None) == (penetration is None):
            raise InputError("give exactly one of normal force and penetration")
        if normal_force is not None and not (math.isfinite(normal_force) and normal_force >= 0):
            raise InputError(f"normal force {normal_force!r} N: expected a finite value >= 0")
        if penetration is not None and not (math.isfinite(penetration) and penetration >= 0):
            raise InputError(f"penetration {penetration!r} m: expected a finite value >= 0")
        h0 = None
        if reuse_grid is not None and element_size is None:
            h0 = self._kept_grid_gap(geometry, penetration, reuse_grid, grid)
        if h0 is not None:
            x, y = reuse_grid.x, reuse_grid.y
        else:
            (cx, cy), (ex, ey) = box or self._potential_area(geometry, material, normal_force,
                                                             penetration, continuous=True)
            if box is None and (geometry.gap_function is None or geometry.extent is None):
                ex, ey = self._plastic_extent(geometry, material, normal_force, ex, ey)
            if reuse_grid is not None and element_size is None and fits(reuse_grid, cx, cy,
                                                                          ex, ey, grid):
                x, y = reuse_grid.x, reuse_grid.y
            else:
                x, y = make_grid(ex, ey, grid, element_size, center=(cx, cy),
                                 origin=getattr(geometry, "grid_origin", (0.0, 0.0)))
            h0 = own_gap(geometry, x, y) + geometry.approach  # touching: min ~ 0
        dx, dy = x[1] - x[0], y[1] - y[0]
        if callable(extra_gap):
            extra_gap = extra_gap(x, y)          # on the grid this solve takes
        if extra_gap is not None:
            if np.shape(extra_gap) != h0.shape:
                raise InputError(f"extra_gap of shape {np.shape(extra_gap)}: expected the "
                                 f"solution grid's {h0.shape}")
            h0 = h0 + extra_gap
        grid_key = (x.size, y.size, float(dx), float(dy), material.contact_modulus)
        dA = dx * dy
        regions = subregions(geometry, y)
        # Blanco's corrected coefficients on a conformal patch that asks for them
        angles = influence_angles(geometry, y)
        p0 = None
        if warm_start is not None and warm_start.pressure.max() > 0:
            if same_grid(warm_start.x, warm_start.y, x, y):
                p0 = warm_start.pressure
            elif warm_start.pressure_at is not None:
                # another grid (a neighbouring case of a sweep): its pressure there
                p0 = np.maximum(warm_start.pressure_at(x[:, None], y[None, :]), 0.0)
                if not p0.max() > 0:
                    p0 = None
        if normal_force is not None:
            if p0 is None and geometry.approach > 0:
                # Hertz's shape: with the rigid overlap approach - h0, the elastic
                # contact is where it exceeds half the approach, and p ~ its root there
                p0 = np.sqrt(np.maximum(0.5 * geometry.approach - h0, 0.0))
            if math.isfinite(self.pressure_limit):
                p, app, it, ok = self._force_by_approach(grid_key, h0, dA, normal_force, p0,
                                                         regions, angles)
            else:
                p, app, it, ok = self._force_controlled(grid_key, h0, dA, normal_force, p0,
                                                        geometry.approach, regions, angles)
        else:
            p, it, ok = self._displacement_controlled(grid_key, h0 - penetration, dA, p0,
                                                      regions, angles)
            app = penetration
        if visc is not None:
            given = normal_force is not None
            p, app_v, it_v, ok = self._viscoelastic(grid_key, visc, h0 if given else
                                                    h0 - penetration, normal_force, p)
            it, app = it + it_v, app_v if given else app
        status = SolverStatus(True, "", int(it)) if ok else SolverStatus.failed(
            f"exact normal solver: no convergence in {it} iterations", it)
        if not ok:
            log.info("exact normal solver: no convergence in %d iterations", it)
        contact = p > 0
        resized = resized_elements(element_size, dx, dy)
        if resized:
            status = status.with_warnings(resized)
        if any(edge_sides(contact)):
            status = status.with_warnings("the contact reaches the edge of the potential "
                                          "contact area (results may be truncated)")
        F = float(p.sum() * dA)
        x_lead, x_trail = strip_edges(contact, np.ascontiguousarray(x, dtype=float))
        def pressure_at(xq, yq):
            return np.maximum(bilinear(x, y, p, xq, yq), 0.0)

        return NormalSolution(model="exact", x=x, y=y, pressure=p, contact=contact,
                              area=float(contact.sum() * dA), pmax=float(p.max()),
                              penetration=float(app), normal_force=F, semi_axes=None,
                              strips=(x_lead, x_trail), pressure_at=pressure_at, status=status,
                              cpu_time=time.perf_counter() - t0,
                              pressure_limit=self.pressure_limit)
