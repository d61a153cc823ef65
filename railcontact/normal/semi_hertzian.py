"""Semi-Hertzian (strip) normal models: ``kik-piotrowski``, ``kpec``, ``stripes``,
``analyn``.

All four work on the undeformed distance h(x, y) of the geometry layer on a grid
of the tangent plane (as the exact model) and give a semi-elliptic pressure in the
rolling direction on every strip.  With ``h* = h - delta`` (delta the approach,
negative h* = interpenetration) and ``h_min`` its minimum:

* **Kik-Piotrowski** (Kik & Piotrowski 1996; Piotrowski & Kik, VSD 46, 2008): the
  contact area is the virtual interpenetration region h* <= (1 - eps) h_min with a
  constant scaling eps (0.55 by default); each strip carries
  p = p0 sqrt((l/2)^2 - (x - x_m)^2) / (l_max/2) between its trailing and leading
  edges, and p0 follows from the elastic displacement at the point of deepest
  interpenetration, A p = -h_min (exact half-space influence coefficients).
* **KPEC** (Kik-Piotrowski with ellipse correction, as in CONTACT): eps varies per
  strip so that an elliptic (Hertzian) gap gives the Hertz ellipse:
  eps(y) = max(0, (A a^2 - (A a^2 - B b^2) ((y - y_m)/b)^2) / delta), with A, B the
  curvatures of an equivalent ellipse fitted to h* (A from a parabola along the
  row of the minimum through the KP (eps = 0.5) region, B from the lateral extent
  of that region) and a, b its Hertz semi-axes at the approach.
* **ANALYN** (Sichani, Enblom & Berg, VSD 52, 2014; CONTACT's "modified ANALYN"):
  per strip, local curvatures A(y), B(y) at the strip's minimum x_lc(y), the Hertz
  semi-axes for the total approach, shape factors alpha1 = delta/(A a^2),
  beta1 = delta/(B b^2), local approach delta_l = delta - beta1 g(y), half-length
  sqrt(delta_l/(alpha1 A)) and maximum pressure 3 F_H/(2 pi a b) of the Hertz
  solution for delta_l.
* **STRIPES** (Ayasse & Chollet, VSD 43, 2005; correction strategy 3 as used by
  Tao et al., CM2015): constant longitudinal curvature A (that of the first-contact
  strip), local lateral curvature per strip; both curvatures of every strip are
  corrected by the shape factors of its local Hertz ellipse (A* = alpha1(y) A,
  B* = beta1(y) B(y)), the corrected lateral gap g*(y) is the double integral of
  the corrected curvature from the first-contact point, and each strip is a Hertz
  strip: local approach delta - g*(y), half-length sqrt((delta - g*)/A*) and
  maximum pressure of the Hertz solution (A, B(y)) at that approach.  The
  equations are our reading of the method as described in the literature; the
  original paper was not available to check them.  On a Hertzian gap
  g* = beta1 B y^2 and the result is the Hertz solution.

A given normal force is met by a secant iteration on the approach.
"""

from __future__ import annotations

import math
import time

import numpy as np
from scipy.interpolate import RegularGridInterpolator
from numba import njit
from scipy.optimize import brentq

from ..errors import InputError
from ..materials import STEEL, Material
from .base import NormalSolution, make_grid, register
from .exact import ExactNormalModel, own_gap
from .hertz_theory import hertz_ellipse, hertz_ellipses
from .influence import normal_displacement_at

#: smallest curvature used where the fitted one is not positive [1/m] (CONTACT: 1e-4/mm)
MIN_CURVATURE = 0.1


def strip_minima(h, x, dx: float, dy: float):
    """Per strip (column of h): position x_m(y) and value g(y) of the gap's minimum
    along x, and the relative curvatures A(y), B(y) [1/m] there.

    A parabola through the grid row of the smallest gap and its two neighbours gives
    x_m, g and A (as the batch path's three samples per strip); B is the second
    difference across the neighbouring strips at x_m, each strip's values taken
    from its parabola on the same rows.  All four are continuous in the gap: where
    two rows either side of the minimum hold equal gaps (a gap symmetric in x on a
    grid without a row at x = 0), which of the two the rounding of h makes the
    smaller does not change the result.  Curvatures below ``MIN_CURVATURE`` are
    raised to it.  Needs a grid of at least 3 x 3.
    """
    mx, my = h.shape
    ixm = np.clip(np.argmin(h, axis=0), 1, mx - 2)
    cols = np.arange(my)

    def parabola(j):
        """Coefficients (h0, c1, c2) of column(s) j on the rows ixm - 1 .. ixm + 1."""
        hm, h0, hp = h[ixm - 1, j], h[ixm, j], h[ixm + 1, j]
        return h0, (hp - hm) / (2.0 * dx), (hp - 2.0 * h0 + hm) / (2.0 * dx * dx)

    h0, c1, c2 = parabola(cols)
    curved = c2 > 0
    t = np.where(curved, np.clip(-c1 / np.where(curved, 2.0 * c2, 1.0), -dx, dx), 0.0)
    g = h0 + c1 * t + c2 * t * t

    def at(j):
        b0, b1, b2 = parabola(j)
        return b0 + b1 * t + b2 * t * t

    jc = np.clip(cols, 1, my - 2)
    B = 0.5 * (at(jc + 1) - 2.0 * at(jc) + at(jc - 1)) / dy ** 2
    return x[ixm] + t, g, np.maximum(c2, MIN_CURVATURE), np.maximum(B, MIN_CURVATURE)


def _semi_ellipse_rows(h, thr, x, dx):
    """Contact mask h <= thr (thr per row), trailing/leading edges by interpolation,
    and the unit semi-elliptic pressure shape per row."""
    mx, my = h.shape
    mask = h <= thr[None, :]
    anyc = mask.any(axis=0)
    idx = np.arange(mx)[:, None]
    first = np.where(anyc, np.argmax(mask, axis=0), 0)
    last = np.where(anyc, mx - 1 - np.argmax(mask[::-1], axis=0), 0)
    cols = np.arange(my)
    # trailing edge between first-1 and first, leading edge between last and last+1
    i0 = np.clip(first - 1, 0, mx - 1)
    i1 = np.clip(last + 1, 0, mx - 1)
    h0, hf = h[i0, cols], h[first, cols]
    hl, h1 = h[last, cols], h[i1, cols]
    with np.errstate(divide="ignore", invalid="ignore"):
        xtrl = np.where(first > 0, x[i0] + dx * (thr - h0) / (hf - h0), x[first] - dx / 2)
        xled = np.where(last < mx - 1, x[last] + dx * (thr - hl) / (h1 - hl), x[last] + dx / 2)
    xtrl = np.minimum(np.nan_to_num(xtrl, nan=x[first] - dx / 2), x[first])
    xled = np.maximum(np.nan_to_num(xled, nan=x[last] + dx / 2), x[last])
    leny = np.where(anyc, xled - xtrl, 0.0)
    xmid = 0.5 * (xtrl + xled)
    half = 0.5 * leny
    shape = np.sqrt(np.clip(half[None, :] ** 2 - (x[:, None] - xmid[None, :]) ** 2, 0.0, None))
    shape = np.where(mask & (idx >= first[None, :]) & (idx <= last[None, :]), shape, 0.0)
    return mask & (shape > 0), shape, np.where(anyc, xled, 0.0), np.where(anyc, xtrl, 0.0), \
        float(leny.max()) if anyc.any() else 0.0


def _no_contact(hstar):
    """Pressure, contact mask and strip edges of a grid without interpenetration."""
    z = np.zeros_like(hstar)
    my = hstar.shape[1]
    return z, z > 0, (np.zeros(my), np.zeros(my))


def _hertz_strips(x, xlc, penloc, A, B, alpha1, Es):
    """Semi-elliptic pressure of Hertz strips (ANALYN, STRIPES): strip centres xlc,
    local approach penloc (<= 0: no contact), half-length sqrt(penloc/(alpha1 A)) and
    maximum pressure 3 F_H / (2 pi a b) of the Hertz solution (A, B) at penloc.
    Returns the pressure, contact mask and strip edges (x_lead, x_trail)."""
    ok = penloc > 0
    penloc = np.where(ok, penloc, 0.0)
    xl = np.sqrt(penloc / (alpha1 * A))
    al, bl, fl = hertz_ellipses(A, B, Es, penloc)
    with np.errstate(divide="ignore", invalid="ignore"):
        pmax = np.where(ok, 1.5 * fl / (math.pi * al * bl), 0.0)
        r = (x[:, None] - xlc[None, :]) / np.where(ok, xl, 1.0)[None, :]
    inside = ok[None, :] & (np.abs(r) < 1)
    p = np.where(inside, pmax[None, :] * np.sqrt(np.clip(1 - r * r, 0, None)), 0.0)
    return p, p > 0, (np.where(ok, xlc + xl, 0.0), np.where(ok, xlc - xl, 0.0))


class _StripModel(ExactNormalModel):
    """Common driver: grid, approach iteration and result for the strip models."""

    label = "strip"
    accepts_warm_start = False

    def __init__(self, margin: float = 0.25):
        super().__init__(margin=margin)

    def _pressure(self, hstar, x, y, dx, dy, material):
        raise NotImplementedError

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
            def f(d):
                return float(at(d)[0].sum() * dx * dy) - normal_force
            lo, hi = 0.2 * guess, 2.0 * guess
            while f(hi) < 0:
                hi *= 2
            if f(lo) > 0:
                # down to the approach at which no element interpenetrates (F = 0): below
                # 0 where the grid's deepest point lies below the search's (a small load)
                lo = min(float(h0.min()), 0.0)
            delta = brentq(f, lo, hi, rtol=1e-10, xtol=1e-15)
            p, contact, strips = at(delta)
        interp = RegularGridInterpolator((x, y), p, bounds_error=False, fill_value=0.0)

        def pressure_at(xq, yq, interp=interp):
            xq, yq = np.broadcast_arrays(np.asarray(xq, float), np.asarray(yq, float))
            return np.maximum(interp(np.stack([xq.ravel(), yq.ravel()], -1)), 0.0).reshape(xq.shape)

        dA = dx * dy
        return NormalSolution(model=self.name, x=x, y=y, pressure=p, contact=contact,
                              area=float(contact.sum() * dA), pmax=float(p.max(initial=0.0)),
                              penetration=float(delta), normal_force=float(p.sum() * dA),
                              semi_axes=None, strips=strips, pressure_at=pressure_at,
                              cpu_time=time.perf_counter() - t0, gap=h0)


class _KPBase(_StripModel):
    def _eps(self, hstar, x, y, dx, dy, material, hmin):
        raise NotImplementedError

    def _pressure(self, hstar, x, y, dx, dy, material):
        mx, my = hstar.shape
        imin = np.unravel_index(np.argmin(hstar), hstar.shape)
        hmin = float(hstar[imin])
        if hmin >= 0:
            return _no_contact(hstar)
        eps = self._eps(hstar, x, y, dx, dy, material, hmin)
        thr = (1.0 - eps) * hmin
        contact, shape, xled, xtrl, lenmax = _semi_ellipse_rows(hstar, thr, x, dx)
        shape = shape / (0.5 * lenmax) if lenmax > 0 else shape
        u = normal_displacement_at(shape, dx, dy, imin[0], imin[1], material.contact_modulus)
        p0 = -hmin / u if u > 0 else 0.0
        return p0 * shape, contact, (xled, xtrl)


@register("kik-piotrowski")
class KikPiotrowskiModel(_KPBase):
    """Kik-Piotrowski with a constant virtual-penetration scaling ``eps`` (0.55)."""

    def __init__(self, eps: float = 0.55, margin: float = 0.25):
        if not 0 < eps <= 1:
            raise InputError(f"kik-piotrowski eps {eps!r}: expected a value in (0, 1]")
        super().__init__(margin=margin)
        self.eps = eps

    def _eps(self, hstar, x, y, dx, dy, material, hmin):
        return np.full(hstar.shape[1], self.eps)


@register("kpec")
class KPECModel(_KPBase):
    """Kik-Piotrowski with ellipse correction (variable scaling per strip)."""

    def _eps(self, hstar, x, y, dx, dy, material, hmin):
        mx, my = hstar.shape
        ix, iy = np.unravel_index(np.argmin(hstar), hstar.shape)
        thr = 0.5 * hmin                              # original KP scaling 0.5
        row = hstar[:, iy]
        k = 1
        while ix - k > 0 and ix + k < mx - 1 and max(row[ix - k], row[ix + k]) <= thr:
            k += 1
        i0, i1 = max(ix - k, 0), min(ix + k, mx - 1)
        A = (row[i1] - 2 * row[ix] + row[i0]) / (2 * (x[i1] - x[ix]) ** 2)
        rows = np.flatnonzero((hstar <= thr).any(axis=0))
        j0, j1 = int(rows[0]), int(rows[-1])
        if j0 == 0:
            j0 = 1
        if j1 >= my - 1:
            j1 = my - 2
        c0 = int(np.argmin(hstar[:, j0]))
        ysta = y[j0] - (thr - hstar[c0, j0]) * dy / (hstar[c0, j0 - 1] - hstar[c0, j0])
        c1 = int(np.argmin(hstar[:, j1]))
        yend = y[j1] + (thr - hstar[c1, j1]) * dy / (hstar[c1, j1 + 1] - hstar[c1, j1])
        ymid = 0.5 * (ysta + yend)
        B = max(MIN_CURVATURE, (thr - hmin) / (yend - ymid) ** 2)
        A = max(A, MIN_CURVATURE)
        hz = hertz_ellipse(A, B, material.contact_modulus, penetration=-hmin)
        a, b = hz.a, hz.b
        if j0 >= j1:
            b = max(b, 1.1 * abs(y[iy] - ymid))
        return np.maximum(0.0, (A * a * a - (A * a * a - B * b * b) * ((y - ymid) / b) ** 2)
                          / (-hmin))


@register("analyn")
class AnalynModel(_StripModel):
    """ANALYN: strip-wise Hertzian pressure from local curvatures and approach."""

    def _pressure(self, hstar, x, y, dx, dy, material):
        my = hstar.shape[1]
        xlc, gmin, A, B = strip_minima(hstar, x, dx, dy)
        pen = -float(gmin.min())
        if pen <= 0:
            return _no_contact(hstar)
        Es = material.contact_modulus
        g = gmin + pen
        a, b, _ = hertz_ellipses(A, B, Es, pen)       # one Hertz solution per strip
        alpha1 = pen / (A * a * a)
        beta1 = pen / (B * b * b)
        return _hertz_strips(x, xlc, pen - beta1 * g, A, B, alpha1, Es)


@njit(cache=True, nogil=True)
def corrected_gap(g, beta, j0):
    """Double integral of the corrected curvature beta(y) g''(y) on the strip grid,
    row by row (g, beta of shape (rows, strips)), starting from strip ``j0[row]``
    with g*(j0) = g(j0) and the slope there scaled by beta(j0).  With a constant
    beta this is beta g (up to g(j0))."""
    rows, my = g.shape
    out = g.copy()
    n = my - 1
    if n == 0:
        return out
    ds = np.empty(n)
    for r in range(rows):
        k = j0[r]
        jr = min(k, n - 1)                          # first difference to the right of j0
        ds[jr] = beta[r, k] * (g[r, jr + 1] - g[r, jr])
        for j in range(jr + 1, n):                  # march right
            ds[j] = ds[j - 1] + beta[r, j] * (g[r, j + 1] - 2.0 * g[r, j] + g[r, j - 1])
        if jr >= 1:                                 # march left
            ds[jr - 1] = beta[r, k] * (g[r, jr] - g[r, jr - 1])
            for j in range(jr - 2, -1, -1):
                ds[j] = ds[j + 1] - beta[r, j + 1] * (g[r, j + 2] - 2.0 * g[r, j + 1]
                                                      + g[r, j])
        acc = 0.0
        gk = 0.0
        for j in range(my):
            if j > 0:
                acc += ds[j - 1]
            if j == k:
                gk = acc
        acc = 0.0
        for j in range(my):
            if j > 0:
                acc += ds[j - 1]
            out[r, j] = acc - gk + g[r, k]
    return out


@register("stripes")
class StripesModel(_StripModel):
    """STRIPES (Ayasse & Chollet): Hertz strips with constant longitudinal and
    corrected local lateral curvature (see the module notes)."""

    def _pressure(self, hstar, x, y, dx, dy, material):
        my = hstar.shape[1]
        xlc, gmin, Aloc, B = strip_minima(hstar, x, dx, dy)
        pen = -float(gmin.min())
        if pen <= 0:
            return _no_contact(hstar)
        Es = material.contact_modulus
        g = gmin + pen                              # lateral gap along the strip minima
        j0 = int(np.argmin(g))
        A = np.full(my, Aloc[j0])                   # constant longitudinal curvature
        a, b, _ = hertz_ellipses(A, B, Es, pen)      # local ellipses: shape factors
        alpha1 = pen / (A * a * a)
        beta1 = pen / (B * b * b)
        gs = corrected_gap(g[None, :], beta1[None, :], np.array([j0]))[0]
        return _hertz_strips(x, xlc, pen - gs, A, B, alpha1, Es)
