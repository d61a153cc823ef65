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
from numba import njit
from scipy.interpolate import RegularGridInterpolator
from scipy.optimize import brentq, root_scalar

from ..core.errors import InputError
from ..core.materials import STEEL, Material
from ..core.status import SolverStatus
from .base import NormalSolution, make_grid, register, resized_elements
from .exact import ExactNormalModel
from .influence import normal_displacement_at
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


@njit(cache=True, nogil=True)
def _kpec_fit(hs, x, y, dx, dy):
    """CONTACT's equivalent ellipse of KPEC on the grid's interpenetration ``hs``
    (mx, my; negative inside): the deepest element (i, j), its depth h_min < 0, the
    longitudinal curvature A from the parabola through the deepest element and the
    two elements of its row, symmetric about it, just outside the half-depth region
    h <= h_min/2, the region's lateral ends y_sta, y_end (interpolated between the
    first/last rows in it and their outer neighbours at each row's deepest element)
    and B = (h_min/2)/(y_end - y_mid)^2.  Returns (i, j, h_min, A, B, y_mid, single
    row)."""
    mx, my = hs.shape
    im, jm, hmin = 0, 0, hs[0, 0]
    for i in range(mx):
        for j in range(my):
            if hs[i, j] < hmin:
                im, jm, hmin = i, j, hs[i, j]
    thr = 0.5 * hmin
    i0, i1 = im - 1, im + 1
    while not (i0 <= 0 or i1 >= mx - 1 or max(hs[i0, jm], hs[i1, jm]) > thr):
        i0 -= 1
        i1 += 1
    i0, i1 = max(i0, 0), min(i1, mx - 1)
    A = (hs[i1, jm] - 2.0 * hmin + hs[i0, jm]) / (2.0 * (x[i1] - x[im]) ** 2)
    j0, j1 = my, -1
    for j in range(my):
        for i in range(mx):
            if hs[i, j] <= thr:
                j0 = min(j0, j)
                j1 = max(j1, j)
                break
    single = j0 >= j1
    j0 = max(j0, 1)
    j1 = min(j1, my - 2)
    r = np.argmin(hs[:, j0])
    ysta = y[j0] - (thr - hs[r, j0]) * dy / (hs[r, j0 - 1] - hs[r, j0])
    r = np.argmin(hs[:, j1])
    yend = y[j1] + (thr - hs[r, j1]) * dy / (hs[r, j1 + 1] - hs[r, j1])
    ymid = 0.5 * (ysta + yend)
    B = max(MIN_CURVATURE, (thr - hmin) / (yend - ymid) ** 2)
    return im, jm, hmin, A, B, ymid, single


@njit(cache=True, nogil=True)
def _kpec_rows(hs, x, dx, thr, thr_len, p, contact, x_lead, x_trail):
    """CONTACT's KPEC per row of elements (fixed y_j): the elements in contact are
    those with h <= ``thr[j]``; the row's edges are where h crosses ``thr_len[j]``,
    interpolated linearly between the first (last) element in contact and its
    outer neighbour (the grid's edge where there is none); every element from the
    first to the last in contact gets the semi-ellipse sqrt(l_j^2 - (x - x_c,j)^2)
    of the row's half-length l_j and centre x_c,j, divided by half the longest
    row's length in whole elements (a common factor: the caller scales)."""
    mx, my = hs.shape
    first = np.full(my, -1)
    last = np.full(my, -1)
    nmax = 0
    for j in range(my):
        for i in range(mx):
            c = hs[i, j] <= thr[j]
            contact[i, j] = c
            if c:
                if first[j] < 0:
                    first[j] = i
                last[j] = i
        if first[j] >= 0:
            nmax = max(nmax, last[j] - first[j] + 1)
    half_max = 0.5 * nmax * dx
    for j in range(my):
        x_lead[j] = 0.0
        x_trail[j] = 0.0
        if first[j] < 0:
            continue
        t = thr_len[j]
        i = first[j]
        if i == 0:
            xt = x[i] - 0.5 * dx
        else:
            xt = x[i - 1] + dx * (t - hs[i - 1, j]) / (hs[i, j] - hs[i - 1, j])
        xt = min(xt, x[i])
        i = last[j]
        if i == mx - 1:
            xl = x[i] + 0.5 * dx
        else:
            xl = x[i] + dx * (t - hs[i, j]) / (hs[i + 1, j] - hs[i, j])
        xl = max(xl, x[i])
        half = 0.5 * (xl - xt)
        xc = 0.5 * (xl + xt)
        for i in range(first[j], last[j] + 1):
            p[i, j] = math.sqrt(max(0.0, half * half - (x[i] - xc) ** 2)) / half_max
        x_lead[j] = xl
        x_trail[j] = xt


def contact_kpec(hs, x, y, dx, dy, contact_modulus):
    """CONTACT's KPEC (BOUND = 5) on the elements of a grid, for the
    interpenetration ``hs`` = h - delta (mx, my) [m] at the element centres ``x``,
    ``y`` [m] (element sizes ``dx``, ``dy``) and E* [Pa]
    (``KPECModel(rule="contact")``; Piotrowski & Kik 2008 with CONTACT's ellipse
    correction, user guide "KPEC" and Vollebregt's implementation, whose rules
    these are):

    * the equivalent ellipse (:func:`_kpec_fit`): Hertz's semi-axes (a, b) of the
      curvatures (A, B) at the approach -h_min (b at least 1.1 |y_deepest - y_mid|
      where the half-depth region holds one row);
    * eps(y) = (A a^2 - (A a^2 - B b^2) ((y - y_mid)/b)^2) / (-h_min): the elements
      with h <= (1 - eps) h_min are in contact (eps clipped to [0, 1]), the rows'
      lengths from h = (1 - eps) h_min with eps only kept >= 0 (:func:`_kpec_rows`);
    * the semi-elliptic rows scaled so that the normal displacement at the deepest
      element (Love's influence coefficients of the elements,
      :func:`~railcontact.normal.influence.normal_displacement_at`) equals -h_min.

    Differs from the strip rule (``rule="strips"``, :mod:`.strip_theory`) in taking
    the rows' lengths from the gap on the grid (not a parabola per strip), the
    contact from the elements' gap, A from a wide parabola and the displacement of
    the pressures at the element centres.  Returns (pressure, contact, (x_lead,
    x_trail))."""
    mx, my = hs.shape
    p = np.zeros((mx, my))
    contact = np.zeros((mx, my), dtype=np.bool_)
    x_lead, x_trail = np.zeros(my), np.zeros(my)
    if mx < 3 or my < 3 or not hs.min() < 0:
        return p, contact, (x_lead, x_trail)
    hs = np.ascontiguousarray(hs, dtype=float)
    x, y = np.ascontiguousarray(x, dtype=float), np.ascontiguousarray(y, dtype=float)
    im, jm, hmin, A, B, ymid, single = _kpec_fit(hs, x, y, dx, dy)
    h = hertz_ellipse(max(A, MIN_CURVATURE), B, contact_modulus, penetration=-hmin)
    a, b = h.a, h.b
    if single:
        b = max(b, 1.1 * abs(y[jm] - ymid))
    eps = (A * a * a - (A * a * a - B * b * b) * ((y - ymid) / b) ** 2) / (-hmin)
    _kpec_rows(hs, x, float(dx), (1.0 - np.clip(eps, 0.0, 1.0)) * hmin,
               (1.0 - np.maximum(eps, 0.0)) * hmin, p, contact, x_lead, x_trail)
    u = normal_displacement_at(p, dx, dy, int(im), int(jm), contact_modulus)
    if u > 0:
        p *= -hmin / u
    else:
        p[:] = 0.0
        contact[:] = False
    return p, contact, (x_lead, x_trail)


@register("kpec")
class KPECModel(_StripModel):
    """Kik-Piotrowski with ellipse correction (variable scaling per strip).

    Parameters
    ----------
    rule : {"strips", "contact"}
        ``"strips"`` (default): the strip formulation of :mod:`.strip_theory`
        (each strip's length from a parabola of its gap, the batch path's
        equations).  ``"contact"``: CONTACT's KPEC on the grid's elements
        (:func:`contact_kpec`), the ``.inp`` path's choice (BOUND = 5): on the
        two-lobed patch of mbench_a22_kpec.inp case 1 the strip rule gives p_max
        346 MPa and 1345 elements against CONTACT's 442.6 MPa and 1282, this one
        442.5 MPa and 1286.
    margin : float
        Margin of the potential contact area (as the exact model's).
    """

    def __init__(self, rule: str = "strips", margin: float = 0.25):
        if rule not in ("strips", "contact"):
            raise InputError(f"kpec rule {rule!r}: expected 'strips' or 'contact'")
        super().__init__(margin=margin)
        self.rule = rule

    def _pressure(self, hstar, x, y, dx, dy, material):
        if self.rule == "contact":
            return contact_kpec(hstar, x, y, dx, dy, material.contact_modulus)
        return super()._pressure(hstar, x, y, dx, dy, material)


@register("analyn")
class AnalynModel(_StripModel):
    """ANALYN: strip-wise Hertzian pressure from local curvatures and approach."""


@register("stripes")
class StripesModel(_StripModel):
    """STRIPES (Ayasse & Chollet): Hertz strips with constant longitudinal and
    corrected local lateral curvature."""
