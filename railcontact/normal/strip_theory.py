"""The equations of the strip (semi-Hertzian) normal models, once for all paths.

Every strip model describes the contact on strips across the patch (lateral
position y_j, width dy): on strip j the pressure is a semi-ellipse in the rolling
direction, ``p_j sqrt(1 - ((x - x_m,j) / l_j)^2)``, with half-length l_j and peak
p_j.  The models differ only in the rules that give (l_j, p_j) from the strip
quantities of the gap; they are data of one function, :func:`strip_pressures`,
which both the per-patch models (:mod:`railcontact.normal.semi_hertzian`, strips =
the columns of a grid) and the batch path (:mod:`railcontact.normal.strip_batch`,
strips sampled on three lines) call.

Strip quantities, arrays of shape (patches, strips): the strip's smallest
interpenetration ``h*_j = min_x (h - delta)`` (negative: interpenetration), its
position x_m,j, and the gap's relative curvatures A_j along x and B_j across the
strips [1/m] (:func:`parabolic_minima`).

The two families:

* **Kik-Piotrowski** (Kik & Piotrowski 1996; Piotrowski & Kik, VSD 46, 2008) and
  **KPEC** (with CONTACT's ellipse correction): the virtual interpenetration region
  ``h* <= (1 - eps_j) h*_min`` gives l_j = sqrt(((1 - eps_j) h*_min - h*_j) / A_j);
  the peak follows from the elastic displacement at the deepest point,
  ``u(p) = -h*_min`` (Love's half-space influence of the strips' semi-ellipses,
  :func:`kp_displacements`).  Kik-Piotrowski's eps is a constant (0.55), KPEC's
  varies per strip so that an elliptic gap gives the Hertz ellipse
  (:func:`kpec_scaling`).
* **Hertz strips**: ANALYN (Sichani, Enblom & Berg, VSD 52, 2014; CONTACT's
  "modified ANALYN") and STRIPES (Ayasse & Chollet, VSD 43, 2005; correction
  strategy 3 of Tao et al., CM2015).  Each strip is cut from the Hertz solution of
  its own curvatures (A_j, B_j) at the total approach d: shape factors
  alpha_j = d / (A_j a_j^2), beta_j = d / (B_j b_j^2); the local approach is
  d - g*_j with the lateral gap g_j = h*_j + d corrected, l_j =
  sqrt((d - g*_j) / (alpha_j A_j)) and p_j the Hertz peak pressure at the local
  approach.  ANALYN: local A_j, g* = beta g.  STRIPES: the longitudinal curvature
  of the first-contact strip for all strips, g* the double integral of beta_j g''
  from the first-contact strip (:func:`corrected_gap`).  STRIPES' equations are our
  reading of the method as described in the literature (the original paper was
  not available); on a Hertzian gap g* = beta B y^2 and both give Hertz.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..core.errors import InputError
from ..core.hertz_theory import hertz_ellipses_table

#: smallest curvature used where the fitted one is not positive [1/m] (CONTACT: 1e-4/mm)
MIN_CURVATURE = 0.1

#: the strip models, by their registered names
STRIP_MODELS = ("kik-piotrowski", "kpec", "stripes", "analyn")


def parabolic_minima(hm, h0, hp, d, reach):
    """Minimum of the parabola through three samples per strip, at -d, 0, +d
    along x (arrays of shape (..., strips); d broadcasts against them).

    Returns the offset t of the minimum (clipped to ±reach, 0 where the parabola
    is not convex), the coefficients (c1, c2) of ``h0 + c1 t + c2 t^2``, and the
    minimum g.  Continuous in the samples, so that which of two nearly equal
    samples is the smaller cannot move the strips (issue 21).
    """
    c1 = (hp - hm) / (2.0 * d)
    c2 = (hp - 2.0 * h0 + hm) / (2.0 * d * d)
    curved = c2 > 0
    t = np.where(curved, np.clip(-c1 / np.where(curved, 2.0 * c2, 1.0), -reach, reach), 0.0)
    return t, c1, c2, h0 + c1 * t + c2 * t * t


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
def kp_displacements(y, dy, xm, half, j0, nx, Es, out):
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


def kpec_scaling(y, dy, hstar, A, Es):
    """KPEC's virtual-penetration scaling eps per strip (patches, strips).

    An equivalent ellipse is fitted to the original Kik-Piotrowski region
    ``h* <= h*_min / 2``: A is the longitudinal curvature at the deepest strip, B
    follows from the region's lateral extent (y_sta, y_end, interpolated) as
    ``(h*_min / 2) / (y_end - y_mid)^2``; with (a, b) its Hertz semi-axes at the
    approach, ``eps(y) = max(0, (A a^2 - (A a^2 - B b^2) ((y - y_mid)/b)^2) / d)``.
    """
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


def _kik_piotrowski(y, dy, xm, hstar, A, eps, Es, nx):
    """Half-lengths and peaks of the Kik-Piotrowski strips for a scaling ``eps``
    per strip."""
    hmin = hstar.min(axis=1)
    thr = (1.0 - eps) * hmin[:, None]
    half = np.sqrt(np.maximum(thr - hstar, 0.0) / A)
    half = np.where(hmin[:, None] < 0, half, 0.0)
    j0 = np.argmin(hstar, axis=1)
    u = np.empty(y.shape[0])
    kp_displacements(y, dy, xm, half, j0, int(nx), Es, u)
    lmax = half.max(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        p0 = np.where((u > 0) & (lmax > 0), -hmin / u, 0.0)
        pm = np.where(lmax[:, None] > 0, p0[:, None] * half / lmax[:, None], 0.0)
    return half, pm


def _hertz_strips(model, hstar, A, B, Es):
    """Half-lengths and peaks of ANALYN's or STRIPES' Hertz strips."""
    n = hstar.shape[0]
    depth = np.maximum(-hstar.min(axis=1), 0.0)               # total approach
    glat = hstar + depth[:, None]                              # lateral gap >= 0
    if model == "stripes":
        j0 = np.argmin(glat, axis=1)
        A = np.broadcast_to(A[np.arange(n), j0][:, None], A.shape)
    dep = np.broadcast_to(depth[:, None], A.shape)
    a, b, force = hertz_ellipses_table(A, B, Es, dep)
    with np.errstate(divide="ignore", invalid="ignore"):
        alpha1 = np.where(a > 0, dep / (A * a * a), 1.0)
        beta1 = np.where(b > 0, dep / (B * b * b), 1.0)
    if model == "stripes":
        glat = corrected_gap(np.ascontiguousarray(glat), np.ascontiguousarray(beta1), j0)
    else:
        glat = beta1 * glat
    # at fixed curvatures the semi-axes scale with sqrt(approach) and the force with
    # approach^(3/2): the peak at the local approach is p_max(d) sqrt(d_loc / d)
    local = dep - glat
    ok = (local > 0) & (a > 0)
    pl = np.where(ok, local, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        half = np.where(ok, np.sqrt(pl / (alpha1 * A)), 0.0)
        pm = np.where(ok, 1.5 * force / (math.pi * a * b) * np.sqrt(pl / dep), 0.0)
    return half, pm


def strip_pressures(model: str, y, dy, xm, hstar, A, B, contact_modulus: float,
                    eps: float = 0.55, elements: int = 20):
    """Half-lengths l_j [m] and peak pressures p_j [Pa] of one strip model.

    Parameters
    ----------
    model : {"kik-piotrowski", "kpec", "stripes", "analyn"}
    y, xm : ndarray (patches, strips)
        Strip centres [m] across and along the rolling direction (x_m: the strip's
        smallest gap).
    dy : ndarray (patches,)
        Strip width [m].
    hstar : ndarray (patches, strips)
        Smallest gap minus approach per strip [m] (negative: interpenetration).
    A, B : ndarray (patches, strips)
        Relative curvatures of the gap along x and across the strips [1/m].
    contact_modulus : float
        E* [Pa].
    eps : float
        Kik-Piotrowski's constant scaling.
    elements : int
        Elements per strip of Kik-Piotrowski's and KPEC's displacement sum.

    Returns
    -------
    half, peak : ndarray (patches, strips)
        Zero where a strip is out of contact.
    """
    if model in ("kik-piotrowski", "kpec"):
        e = (np.full(hstar.shape, float(eps)) if model == "kik-piotrowski"
             else kpec_scaling(y, dy, hstar, A, contact_modulus))
        return _kik_piotrowski(y, dy, xm, hstar, A, e, contact_modulus, elements)
    if model in ("stripes", "analyn"):
        return _hertz_strips(model, hstar, A, B, contact_modulus)
    raise InputError(f"strip model {model!r}: expected one of {', '.join(STRIP_MODELS)}")
