"""The strip models for many patches at once: forces, area and p_max only.

The per-patch models of :mod:`railcontact.normal.semi_hertzian` evaluate the exact
gap on a full grid and build a :class:`~railcontact.normal.base.NormalSolution` for
every patch.  For sweeps, wear loops and dynamics, where only the patch results
are needed, this module solves the same models (``kik-piotrowski``, ``kpec``,
``stripes``, ``analyn``; same equations, see that module) on all patches together:

* the gap of every patch is sampled at three points along x on each of ``strips``
  strips, in one compiled loop per profile pair
  (:func:`railcontact.geometry.search.sample_gap_lines`); a parabola through the three
  samples gives each strip's minimum g(y), its position x_m(y) and the longitudinal
  curvature A(y); the lateral curvature B(y) is the second difference across the
  strips at x_m(y);
* the models work on arrays of shape (patches, strips); the semi-elliptic pressure
  of strip j has half-length l_j around x_m(y_j) and maximum p_j, so that
  F_n = sum (pi/2) p_j l_j dy and the area is sum 2 l_j dy;
* Kik-Piotrowski's displacement at the deepest point is summed over the elements
  of the strips in a compiled loop over the patches.

The results agree with the per-patch models within their grid resolution (tested in
``tests/normal/test_strip_batch.py``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from ..errors import InputError
from .hertz_theory import hertz_ellipses, hertz_ellipses_table
from .semi_hertzian import MIN_CURVATURE, corrected_gap

#: the strip models that have a batch solution
BATCH_MODELS = ("kik-piotrowski", "kpec", "stripes", "analyn")


@dataclass
class StripSolution:
    """Strip-wise semi-elliptic pressures of many patches (SI units).

    Arrays of shape (patches, strips): ``y`` strip centres, ``x_mid`` strip centres
    along x, ``half`` half-lengths (0: no contact), ``p_strip`` maximum pressure
    per strip and ``A``, ``B`` the gap's local relative curvatures [1/m] (along x at
    the strip's minimum, and across the strips); per patch: ``dy`` strip width,
    ``normal_force``, ``area``, ``pmax``, ``penetration``.
    """

    y: np.ndarray
    dy: np.ndarray
    x_mid: np.ndarray
    half: np.ndarray
    p_strip: np.ndarray
    penetration: np.ndarray
    A: np.ndarray
    B: np.ndarray
    #: (a, b) [m] per patch where the patches are ellipses cut in strips
    #: (:func:`hertz_ellipse_strips`): area, p_max and the equivalent ellipse are then
    #: the ellipse's own
    semi_axes: tuple | None = None

    @property
    def normal_force(self) -> np.ndarray:
        return 0.5 * math.pi * np.sum(self.p_strip * self.half, axis=1) * self.dy

    @property
    def area(self) -> np.ndarray:
        if self.semi_axes is not None:
            return math.pi * self.semi_axes[0] * self.semi_axes[1]
        return 2.0 * np.sum(self.half, axis=1) * self.dy

    @property
    def pmax(self) -> np.ndarray:
        if self.semi_axes is not None:
            area = self.area
            with np.errstate(divide="ignore", invalid="ignore"):
                return np.where(area > 0, 1.5 * self.normal_force / area, 0.0)
        return self.p_strip.max(axis=1, initial=0.0)

    def equivalent_ellipses(self):
        """Semi-axes (a, b) [m] of the equivalent ellipse of every patch (area and
        length/width ratio of the contact, as :func:`~railcontact.tangential.fastsim.
        equivalent_ellipse`); zero where there is no contact."""
        if self.semi_axes is not None:
            return self.semi_axes
        on = self.half > 0
        anyc = on.any(axis=1)
        lead = np.where(on, self.x_mid + self.half, -np.inf).max(axis=1)
        trail = np.where(on, self.x_mid - self.half, np.inf).min(axis=1)
        my = on.shape[1]
        first = np.argmax(on, axis=1)
        last = my - 1 - np.argmax(on[:, ::-1], axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            L = np.where(anyc, lead - trail, 1.0)
            W = np.where(anyc, (last - first + 1) * self.dy, 1.0)
            r = np.sqrt(self.area / math.pi)
            return (np.where(anyc, r * np.sqrt(L / W), 0.0),
                    np.where(anyc, r * np.sqrt(W / L), 0.0))


def strip_geometry(patches, strips: int = 40, penetration=None, margin: float = 0.15,
                   widen: int = 4):
    """Strip quantities of many patches from their exact gaps.

    Returns ``y`` (patches, strips) [m], ``dy`` (patches,), ``x_m``, ``g`` (the
    smallest gap + approach per strip, ~0 at the deepest point), ``A``, ``B``
    [1/m].  The lateral window covers the interpenetration region of each patch
    at ``penetration`` [m] (default: the geometry's approach), from the geometry's
    extent, widened until the outer strips are free.  The patch is the run of
    interpenetrating strips through the deepest strip within the extent; strips
    outside it get g = penetration + 1 m (no contact).
    """
    from ..geometry.search import sample_gap_lines
    n = len(patches)
    if strips < 5:
        raise InputError(f"strips {strips!r}: expected at least 5")
    app = np.array([p.approach for p in patches], float)
    pen = app if penetration is None else np.asarray(penetration, float)
    A0 = np.array([max(p.curvatures[0], MIN_CURVATURE) for p in patches], float)
    B0 = np.array([max(p.curvatures[1], MIN_CURVATURE) for p in patches], float)
    ext = np.array([p.extent if p.extent is not None else (0.0, 0.0, 0.0, 0.0)
                    for p in patches], float).reshape(n, 4)
    dpos = np.maximum(pen, 1e-9)
    xc = 0.5 * (ext[:, 0] + ext[:, 1])
    dx = np.maximum(0.5 * (ext[:, 1] - ext[:, 0]), np.sqrt(dpos / A0))
    yc = 0.5 * (ext[:, 2] + ext[:, 3])
    hy = np.maximum(0.5 * (ext[:, 3] - ext[:, 2]), np.sqrt(dpos / B0)) * (1.0 + margin)
    u = -1.0 + (2.0 * np.arange(strips) + 1.0) / strips
    core = hy / (1.0 + margin)                  # the geometry's extent: the deepest strip lies in it
    idx = np.arange(strips)
    todo = np.arange(n)
    out = [np.empty((n, strips)) for _ in range(5)]
    for _ in range(widen + 1):
        y = yc[todo, None] + hy[todo, None] * u[None, :]
        d = dx[todo, None]
        xs = xc[todo, None] + d * np.array([0.0, -1.0, 1.0])[None, :]
        h = sample_gap_lines([patches[k] for k in todo], xs, y) + app[todo, None, None]
        h0, hm, hp = h[:, 0], h[:, 1], h[:, 2]
        c2 = (hp - 2.0 * h0 + hm) / (2.0 * d * d)
        c1 = (hp - hm) / (2.0 * d)
        curved = c2 > 0
        t = np.where(curved, np.clip(-c1 / np.where(curved, 2.0 * c2, 1.0), -2 * d, 2 * d), 0.0)
        g = h0 + c1 * t + c2 * t * t
        A = np.maximum(c2, MIN_CURVATURE)
        # lateral curvature at fixed x = x_m(y), across the neighbouring strips
        dy = 2.0 * hy[todo, None] / strips
        jc = np.clip(np.arange(strips), 1, strips - 2)

        def at(j):
            return h0[:, j] + c1[:, j] * t + c2[:, j] * t * t
        B = np.maximum(0.5 * (at(jc + 1) - 2.0 * at(jc) + at(jc - 1)) / (dy * dy),
                       MIN_CURVATURE)
        # the patch is the run of interpenetrating strips through the deepest strip of
        # the extent; other regions of the tangent plane (another patch, the flange
        # seen from the tread's plane) are not part of it
        inter = g < pen[todo, None]
        inside = np.abs(y - yc[todo, None]) <= core[todo, None]
        jd = np.argmin(np.where(inside, g, np.inf), axis=1)
        lo = np.where(~inter & (idx < jd[:, None]), idx, -1).max(axis=1) + 1
        hi = np.where(~inter & (idx > jd[:, None]), idx, strips).min(axis=1) - 1
        run = (idx >= lo[:, None]) & (idx <= hi[:, None]) & inter[np.arange(todo.size), jd][:, None]
        g = np.where(run, g, pen[todo, None] + 1.0)     # outside the run: no contact (1 m)
        for arr, val in zip(out, (y, xc[todo, None] + t, g, A, B)):
            arr[todo] = val
        edge = run[:, 0] | run[:, -1]
        if not edge.any():
            break
        todo = todo[edge]
        hy[todo] *= 1.6
    y, xm, g, A, B = out
    return y, 2.0 * hy / strips, xm, g, A, B


def hertz_ellipse_strips(patches, contact_modulus: float, strips: int = 40) -> StripSolution:
    """Hertz's ellipses of many patches (at the geometry's approach) cut in
    ``strips`` strips across: strip j at y_j has half-length a sqrt(1 - (y_j/b)^2)
    and peak pressure p0 sqrt(1 - (y_j/b)^2), scaled so that the strips carry the
    Hertz force exactly; for the strip creep laws (``fastrip``) on Hertz patches."""
    patches = list(patches)
    n = len(patches)
    A = np.fromiter((p.curvatures[0] for p in patches), float, n)
    B = np.fromiter((p.curvatures[1] for p in patches), float, n)
    pen = np.maximum(np.fromiter((p.approach for p in patches), float, n), 0.0)
    a, b, F = hertz_ellipses(A, B, contact_modulus, pen)
    u = -1.0 + (2.0 * np.arange(strips) + 1.0) / strips
    r = np.sqrt(1.0 - u * u)[None, :]
    y = b[:, None] * u[None, :]
    dy = 2.0 * b / strips
    half = a[:, None] * r
    with np.errstate(divide="ignore", invalid="ignore"):
        p0 = np.where(F > 0, F / (0.5 * math.pi * a * dy * np.sum(r * r)), 0.0)
    return StripSolution(y, dy, np.zeros_like(y), half, p0[:, None] * r, pen,
                         np.broadcast_to(A[:, None], y.shape),
                         np.broadcast_to(B[:, None], y.shape), semi_axes=(a, b))


def _hertz_strips(a, b, force, depth, alpha1, A, penloc):
    """Half-length and maximum pressure of Hertz strips at local approach ``penloc``
    (ANALYN, STRIPES; as ``semi_hertzian._hertz_strips``), from the Hertz solution
    (a, b, force) of the same curvatures at the approach ``depth``: at fixed
    curvatures the semi-axes scale with sqrt(approach) and the force with
    approach^(3/2), so p_max(penloc) = p_max(depth) sqrt(penloc / depth)."""
    ok = (penloc > 0) & (a > 0)
    pl = np.where(ok, penloc, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        half = np.where(ok, np.sqrt(pl / (alpha1 * A)), 0.0)
        pm = np.where(ok, 1.5 * force / (math.pi * a * b) * np.sqrt(pl / depth), 0.0)
    return half, pm


@njit(cache=True, nogil=True)
def _rect(X, Y):
    """x ln(y + r) + y ln(x + r), the antiderivative of 1/r (stable for x, y < 0)."""
    r = math.hypot(X, Y)
    v = 0.0
    if X != 0.0:
        s = Y + r if Y >= 0.0 else X * X / (r - Y)
        v += X * math.log(s)
    if Y != 0.0:
        s = X + r if X >= 0.0 else Y * Y / (r - X)
        v += Y * math.log(s)
    return v


#: elements farther than FAR element sizes from the point use the mid-point rule
#: (relative error below (1/FAR)^2 / 12 per element), those between NEAR and FAR
#: sizes the 2 x 2 Gauss rule (below (1/NEAR)^4 / 80), the nearest the exact
#: rectangle integral
FAR = 8.0
NEAR = 2.0
_G = 0.5 / math.sqrt(3.0)          # 2-point Gauss abscissae, in element sizes


@njit(cache=True, nogil=True)
def _kp_displacements(y, dy, xm, half, j0, nx, Es, out):
    """Normal displacement [m] at the deepest point (x_m[j0], y[j0]) of every patch
    due to its unit semi-elliptic strip pressures sqrt(l_j^2 - (x - x_m)^2)/l_max,
    on nx elements per strip (uniform rectangles, Love's influence coefficients;
    elements away from the point by 2 x 2 Gauss or mid-point quadrature)."""
    for k in range(y.shape[0]):
        lmax = 0.0
        for j in range(y.shape[1]):
            lmax = max(lmax, half[k, j])
        if lmax <= 0.0:
            out[k] = 0.0
            continue
        x0 = xm[k, j0[k]]
        y0 = y[k, j0[k]]
        hy = 0.5 * dy[k]
        u = 0.0
        for j in range(y.shape[1]):
            lj = half[k, j]
            if lj <= 0.0:
                continue
            ex = 2.0 * lj / nx
            size2 = max(ex, dy[k]) ** 2
            Y = y[k, j] - y0
            X = xm[k, j] - lj - x0                  # trailing edge of the strip
            gy1 = Y - _G * dy[k]
            gy2 = Y + _G * dy[k]
            exact = False                           # edge integrals below are valid
            top = 0.0
            bot = 0.0
            for i in range(nx):
                s = -1.0 + (2.0 * i + 1.0) / nx
                p = lj * math.sqrt(max(0.0, 1.0 - s * s)) / lmax
                xc = X + 0.5 * ex
                r2 = xc * xc + Y * Y
                if r2 > FAR * FAR * size2:
                    u += p * ex * dy[k] / math.sqrt(r2)
                    exact = False
                elif r2 > NEAR * NEAR * size2:
                    gx1 = xc - _G * ex
                    gx2 = xc + _G * ex
                    u += 0.25 * p * ex * dy[k] * (
                        1.0 / math.sqrt(gx1 * gx1 + gy1 * gy1)
                        + 1.0 / math.sqrt(gx1 * gx1 + gy2 * gy2)
                        + 1.0 / math.sqrt(gx2 * gx2 + gy1 * gy1)
                        + 1.0 / math.sqrt(gx2 * gx2 + gy2 * gy2))
                    exact = False
                else:
                    if not exact:
                        top = _rect(X, Y + hy)      # element edges are shared
                        bot = _rect(X, Y - hy)
                        exact = True
                    t1 = _rect(X + ex, Y + hy)
                    b1 = _rect(X + ex, Y - hy)
                    u += p * (t1 - top - b1 + bot)
                    top = t1
                    bot = b1
                X += ex
        out[k] = u / (math.pi * Es)


def _kp(y, dy, xm, hstar, A, eps, Es, nx):
    """Kik-Piotrowski strips for a scaling ``eps`` per strip (patches, strips)."""
    hmin = hstar.min(axis=1)
    thr = (1.0 - eps) * hmin[:, None]
    half = np.sqrt(np.maximum(thr - hstar, 0.0) / A)
    half = np.where(hmin[:, None] < 0, half, 0.0)
    j0 = np.argmin(hstar, axis=1)
    u = np.empty(y.shape[0])
    _kp_displacements(y, dy, xm, half, j0, nx, Es, u)
    lmax = half.max(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        p0 = np.where((u > 0) & (lmax > 0), -hmin / u, 0.0)
        pm = np.where(lmax[:, None] > 0, p0[:, None] * half / lmax[:, None], 0.0)
    return half, pm


def _kpec_eps(y, dy, hstar, A, Es):
    """KPEC's scaling per strip (``semi_hertzian.KPECModel._eps`` on the strips)."""
    n, my = hstar.shape
    rows = np.arange(n)
    hmin = hstar.min(axis=1)
    jm = np.argmin(hstar, axis=1)
    A0 = A[rows, jm]
    thr = 0.5 * hmin
    inreg = hstar <= thr[:, None]
    j0 = np.clip(np.argmax(inreg, axis=1), 1, my - 2)
    j1 = np.clip(my - 1 - np.argmax(inreg[:, ::-1], axis=1), 1, my - 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        ysta = y[rows, j0] - (thr - hstar[rows, j0]) * dy / (hstar[rows, j0 - 1]
                                                             - hstar[rows, j0])
        yend = y[rows, j1] + (thr - hstar[rows, j1]) * dy / (hstar[rows, j1 + 1]
                                                             - hstar[rows, j1])
    ymid = 0.5 * (ysta + yend)
    ymid = np.where(np.isfinite(ymid), ymid, y[rows, jm])
    with np.errstate(divide="ignore", invalid="ignore"):
        Bf = np.maximum(MIN_CURVATURE, (thr - hmin) / (yend - ymid) ** 2)
    Bf = np.where(np.isfinite(Bf), Bf, MIN_CURVATURE)
    a, b, _ = hertz_ellipses_table(A0, Bf, Es, np.maximum(-hmin, 0.0))
    b = np.where(j0 >= j1, np.maximum(b, 1.1 * np.abs(y[rows, jm] - ymid)), b)
    with np.errstate(divide="ignore", invalid="ignore"):
        q = ((y - ymid[:, None]) / b[:, None]) ** 2
        eps = (A0 * a * a)[:, None] - (A0 * a * a - Bf * b * b)[:, None] * q
        eps = np.maximum(0.0, eps / (-hmin)[:, None])
    return np.where(np.isfinite(eps), eps, 0.0)


def solve_strips(model: str, patches, contact_modulus: float, penetration=None,
                 strips: int = 40, elements: int = 20, eps: float = 0.55) -> StripSolution:
    """One strip model on many patches at given approaches.

    Parameters
    ----------
    model : {"kik-piotrowski", "kpec", "stripes", "analyn"}
    patches : sequence of ContactGeometry
    contact_modulus : float
        E* [Pa].
    penetration : array_like, optional
        Approach per patch [m]; default the geometry's approach.
    strips : int
        Strips across each patch's interpenetration region.
    elements : int
        Elements per strip for Kik-Piotrowski's displacement sum.
    eps : float
        Kik-Piotrowski's scaling factor.
    """
    if model not in BATCH_MODELS:
        raise InputError(f"batch strip model {model!r}: expected one of {', '.join(BATCH_MODELS)}")
    patches = list(patches)
    if not patches:
        raise InputError("solve_strips: no patches given")
    pen = (np.array([p.approach for p in patches], float) if penetration is None
           else np.broadcast_to(np.asarray(penetration, float), (len(patches),)).copy())
    if not np.all(np.isfinite(pen)) or np.any(pen < 0):
        raise InputError("penetration: expected finite values >= 0 m")
    y, dy, xm, g, A, B = strip_geometry(patches, strips, pen)
    Aloc = A
    hstar = g - pen[:, None]
    depth = np.maximum(-hstar.min(axis=1), 0.0)            # total approach of the model
    Es = contact_modulus
    if model in ("kik-piotrowski", "kpec"):
        e = (np.full(hstar.shape, eps) if model == "kik-piotrowski"
             else _kpec_eps(y, dy, hstar, A, Es))
        half, pm = _kp(y, dy, xm, hstar, A, e, Es, elements)
    else:
        glat = hstar + depth[:, None]                         # lateral gap >= 0
        if model == "stripes":
            j0 = np.argmin(glat, axis=1)
            A = np.broadcast_to(A[np.arange(len(patches)), j0][:, None], A.shape)
        dep = np.broadcast_to(depth[:, None], A.shape)
        a, b, fh = hertz_ellipses_table(A, B, Es, dep)
        with np.errstate(divide="ignore", invalid="ignore"):
            alpha1 = np.where(a > 0, depth[:, None] / (A * a * a), 1.0)
            beta1 = np.where(b > 0, depth[:, None] / (B * b * b), 1.0)
        if model == "stripes":
            glat = corrected_gap(np.ascontiguousarray(glat), np.ascontiguousarray(beta1), j0)
        else:
            glat = beta1 * glat
        half, pm = _hertz_strips(a, b, fh, dep, alpha1, A, depth[:, None] - glat)
        none = depth <= 0
        half[none], pm[none] = 0.0, 0.0
    return StripSolution(y, dy, xm, half, pm, pen, Aloc, B)
