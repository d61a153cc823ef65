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
  the peak follows from the elastic displacement at the deepest point
  (between strips: :func:`deepest_point`), ``u(p) = -h*_min`` (Love's half-space influence of the strips' semi-ellipses,
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
from typing import NamedTuple

import numpy as np
from numba import njit

from ..core.errors import InputError
from ..core.hertz_theory import _axes_table, axes_at

#: smallest curvature used where the fitted one is not positive [1/m] (CONTACT: 1e-4/mm)
MIN_CURVATURE = 0.1

#: the strip models, by their registered names
STRIP_MODELS = ("kik-piotrowski", "kpec", "stripes", "analyn")


@njit(cache=True, nogil=True)
def parabola_min(hm, h0, hp, d, reach):
    """:func:`parabolic_minima` of one strip: (t, c1, c2, g)."""
    c1 = (hp - hm) / (2.0 * d)
    c2 = (hp - 2.0 * h0 + hm) / (2.0 * d * d)
    t = 0.0
    if c2 > 0:
        t = min(max(-c1 / (2.0 * c2), -reach), reach)
    return t, c1, c2, h0 + c1 * t + c2 * t * t


@njit(cache=True, nogil=True)
def _parabolic_minima_kernel(hm, h0, hp, d, reach, out):
    for i in range(hm.size):
        out[0, i], out[1, i], out[2, i], out[3, i] = parabola_min(hm[i], h0[i], hp[i], d[i],
                                                                  reach[i])


def parabolic_minima(hm, h0, hp, d, reach):
    """Minimum of the parabola through three samples per strip, at -d, 0, +d
    along x (arrays of shape (..., strips); d broadcasts against them).

    Returns the offset t of the minimum (clipped to ±reach, 0 where the parabola
    is not convex), the coefficients (c1, c2) of ``h0 + c1 t + c2 t^2``, and the
    minimum g.  Continuous in the samples, so that which of two nearly equal
    samples is the smaller cannot move the strips (issue 21).  One compiled rule
    (:func:`parabola_min`) with the compiled pass.
    """
    arrs = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (hm, h0, hp, d, reach)))
    shape = arrs[0].shape
    flat = [np.ascontiguousarray(a).ravel() for a in arrs]
    out = np.empty((4, flat[0].size))
    _parabolic_minima_kernel(*flat, out)
    return tuple(o.reshape(shape) for o in out)


@njit(cache=True, nogil=True)
def corrected_row(g, beta, k, out, ds):
    """:func:`corrected_gap` of one row (``ds``: work array of my - 1)."""
    my = g.size
    n = my - 1
    for j in range(my):
        out[j] = g[j]
    if n == 0:
        return
    jr = min(k, n - 1)                          # first difference to the right of j0
    ds[jr] = beta[k] * (g[jr + 1] - g[jr])
    for j in range(jr + 1, n):                  # march right
        ds[j] = ds[j - 1] + beta[j] * (g[j + 1] - 2.0 * g[j] + g[j - 1])
    if jr >= 1:                                 # march left
        ds[jr - 1] = beta[k] * (g[jr] - g[jr - 1])
        for j in range(jr - 2, -1, -1):
            ds[j] = ds[j + 1] - beta[j + 1] * (g[j + 2] - 2.0 * g[j + 1] + g[j])
    acc = 0.0
    gk = 0.0
    for j in range(my):
        if j > 0:
            acc += ds[j - 1]
        if j == k:
            gk = acc
    acc = 0.0
    gkk = g[k]
    for j in range(my):
        if j > 0:
            acc += ds[j - 1]
        out[j] = acc - gk + gkk


@njit(cache=True, nogil=True)
def corrected_gap(g, beta, j0):
    """Double integral of the corrected curvature beta(y) g''(y) on the strip grid,
    row by row (g, beta of shape (rows, strips)), starting from strip ``j0[row]``
    with g*(j0) = g(j0) and the slope there scaled by beta(j0).  With a constant
    beta this is beta g (up to g(j0))."""
    rows, my = g.shape
    out = g.copy()
    ds = np.empty(max(my - 1, 1))
    for r in range(rows):
        corrected_row(g[r], beta[r], j0[r], out[r], ds)
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
def kp_displacement(y, dy, xm, half, point, nx, Es):
    """Normal displacement [m] at ``point`` (x0, y0) [m] of one patch due to its
    unit semi-elliptic strip pressures sqrt(l_j^2 - (x - x_m)^2)/l_max, on nx
    elements per strip (uniform rectangles, Love's influence coefficients;
    elements away from the point by 2 x 2 Gauss or mid-point quadrature); arrays
    over the strips, ``dy`` the strip width [m]."""
    lmax = 0.0
    for j in range(y.size):
        lmax = max(lmax, half[j])
    if lmax <= 0.0:
        return 0.0
    x0, y0 = point
    hy = 0.5 * dy
    u = 0.0
    for j in range(y.size):
        lj = half[j]
        if lj <= 0.0:
            continue
        ex = 2.0 * lj / nx
        size2 = max(ex, dy) ** 2
        Y = y[j] - y0
        X = xm[j] - lj - x0                     # trailing edge of the strip
        gy1 = Y - _G * dy
        gy2 = Y + _G * dy
        exact = False                           # edge integrals below are valid
        top = 0.0
        bot = 0.0
        for i in range(nx):
            s = -1.0 + (2.0 * i + 1.0) / nx
            p = lj * math.sqrt(max(0.0, 1.0 - s * s)) / lmax
            xc = X + 0.5 * ex
            r2 = xc * xc + Y * Y
            if r2 > FAR * FAR * size2:
                u += p * ex * dy / math.sqrt(r2)
                exact = False
            elif r2 > NEAR * NEAR * size2:
                gx1 = xc - _G * ex
                gx2 = xc + _G * ex
                u += 0.25 * p * ex * dy * (
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
    return u / (math.pi * Es)


@njit(cache=True, nogil=True)
def kp_displacements(y, dy, xm, half, j0, nx, Es, out):
    """:func:`kp_displacement` of every patch (arrays (patches, strips), ``dy``
    and ``j0`` per patch) into ``out``."""
    for k in range(y.shape[0]):
        out[k] = kp_displacement(y[k], dy[k], xm[k], half[k], (xm[k, j0[k]], y[k, j0[k]]),
                                 nx, Es)


@njit(cache=True, nogil=True)
def deepest_point(y, xm, hs, j0):
    """The deepest point (x, y) [m] of the strips' gap ``hs`` around its deepest
    strip j0: the vertex of the parabola through strips j0 - 1, j0, j0 + 1 across
    the strips (within half a strip of j0; x_m interpolated linearly), j0's centre
    where the three are not convex or j0 is an outer strip.  Continuous where the
    deepest strip changes (two neighbours of equal depth: both give their
    midpoint), so that the strip models' force is continuous in the approach."""
    n = y.size
    if j0 <= 0 or j0 >= n - 1:
        return xm[j0], y[j0]
    c2 = hs[j0 + 1] - 2.0 * hs[j0] + hs[j0 - 1]
    if not c2 > 0.0:
        return xm[j0], y[j0]
    t = min(max(-0.5 * (hs[j0 + 1] - hs[j0 - 1]) / c2, -0.5), 0.5)
    k = j0 + 1 if t > 0.0 else j0 - 1
    w = abs(t)
    return (1.0 - w) * xm[j0] + w * xm[k], (1.0 - w) * y[j0] + w * y[k]


#: the strip models' codes in compiled code (:class:`StripRule`)
KIK_PIOTROWSKI, KPEC, STRIPES, ANALYN = 0, 1, 2, 3
MODEL_CODES = {"kik-piotrowski": KIK_PIOTROWSKI, "kpec": KPEC, "stripes": STRIPES,
               "analyn": ANALYN}


class StripRule(NamedTuple):
    """A strip model's rule for the compiled kernels (:func:`strip_patch`)."""

    #: the model (:data:`MODEL_CODES`)
    code: int
    #: contact modulus E* [Pa]
    Es: float
    #: Kik-Piotrowski's constant scaling eps (``kik-piotrowski`` only)
    eps: float
    #: elements per strip of Kik-Piotrowski's and KPEC's displacement sum
    elements: int
    #: the Hertz table (:func:`railcontact.core.hertz_theory._axes_table`): its step
    dt: float
    #: and its values (3, n)
    table: np.ndarray


def strip_rule(model: str, contact_modulus: float, eps: float = 0.55,
               elements: int = 20) -> StripRule:
    """The :class:`StripRule` of a strip model by its registered name."""
    if model not in MODEL_CODES:
        raise InputError(f"strip model {model!r}: expected one of {', '.join(STRIP_MODELS)}")
    dt, tab = _axes_table()
    return StripRule(MODEL_CODES[model], float(contact_modulus), float(eps), int(elements),
                     dt, tab)


class StripSet(NamedTuple):
    """One patch's strip quantities (arrays over the strips; SI units), the input of
    :func:`strip_patch`."""

    #: strip centres [m] across the rolling direction
    y: np.ndarray
    #: strip width [m]
    dy: float
    #: position of each strip's smallest gap along x [m]
    xm: np.ndarray
    #: smallest gap minus approach per strip [m] (negative: interpenetration)
    hstar: np.ndarray
    #: relative curvatures of the gap along x and across the strips [1/m]
    A: np.ndarray
    B: np.ndarray


@njit(cache=True, nogil=True)
def _argmin(v):
    k = 0
    for j in range(1, v.size):
        if v[j] < v[k]:
            k = j
    return k


@njit(cache=True, nogil=True)
def kpec_eps(st, rule, eps):
    """KPEC's virtual-penetration scaling eps per strip of one patch into ``eps``.

    An equivalent ellipse is fitted to the original Kik-Piotrowski region
    ``h* <= h*_min / 2``: A is the longitudinal curvature at the deepest strip, B
    follows from the region's lateral extent (y_sta, y_end, interpolated) as
    ``(h*_min / 2) / (y_end - y_mid)^2``; with (a, b) its Hertz semi-axes at the
    approach, ``eps(y) = max(0, (A a^2 - (A a^2 - B b^2) ((y - y_mid)/b)^2) / d)``.
    """
    y, hs, dy = st.y, st.hstar, st.dy
    my = y.size
    jm = _argmin(hs)
    hmin = hs[jm]
    A0 = st.A[jm]
    thr = 0.5 * hmin
    first, last = 0, my - 1
    for j in range(my):
        if hs[j] <= thr:
            first = j
            break
    for j in range(my - 1, -1, -1):
        if hs[j] <= thr:
            last = j
            break
    j0 = min(max(first, 1), my - 2)
    j1 = min(max(last, 1), my - 2)
    den = hs[j0 - 1] - hs[j0]
    ysta = y[j0] - (thr - hs[j0]) * dy / den if den != 0.0 else math.nan
    den = hs[j1 + 1] - hs[j1]
    yend = y[j1] + (thr - hs[j1]) * dy / den if den != 0.0 else math.nan
    ymid = 0.5 * (ysta + yend)
    if not math.isfinite(ymid):
        ymid = y[jm]
    w2 = (yend - ymid) ** 2
    Bf = (thr - hmin) / w2 if w2 > 0.0 else math.nan
    Bf = max(MIN_CURVATURE, Bf) if math.isfinite(Bf) else MIN_CURVATURE
    a, b, _ = axes_at(A0, Bf, max(-hmin, 0.0), rule.Es, rule.dt, rule.table)
    if j0 >= j1:
        b = max(b, 1.1 * abs(y[jm] - ymid))
    for j in range(my):
        eps[j] = 0.0
    if not (hmin < 0.0 and b > 0.0):
        return
    c0 = A0 * a * a
    c1 = A0 * a * a - Bf * b * b
    for j in range(my):
        q = ((y[j] - ymid) / b) ** 2
        e = max(0.0, (c0 - c1 * q) / (-hmin))
        eps[j] = e if math.isfinite(e) else 0.0


#: Kik-Piotrowski's peak follows from the displacement at the deepest point; where
#: the gap has several local minima within this fraction of the deepest's depth
#: (S1002/60E1's near-conformal tread: two minima 20 mm apart, 1 um apart at 50 um),
#: the displacements at them are blended, with weights (1 - dh / (TIE_DEPTH h))^2 by
#: their depth above the deepest, so that the force stays continuous where the
#: deepest minimum passes from one to the other (it jumped by 15 % there)
TIE_DEPTH = 0.02


@njit(cache=True, nogil=True)
def normalising_displacement(st, half, j0, rule):
    """The displacement [m] of Kik-Piotrowski's unit strip pressures ``half`` that
    their peak is scaled to: at the deepest point (:func:`deepest_point`), blended
    with those at other local minima of the gap within ``TIE_DEPTH`` of its
    depth."""
    hs = st.hstar
    n = hs.size
    hmin = hs[j0]
    u = kp_displacement(st.y, st.dy, st.xm, half, deepest_point(st.y, st.xm, hs, j0),
                        rule.elements, rule.Es)
    band = TIE_DEPTH * abs(hmin)
    if not band > 0.0:
        return u
    total = u
    weight = 1.0
    for j in range(n):
        if j == j0 or hs[j] - hmin >= band:
            continue
        if abs(j - j0) <= 1 or not ((j == 0 or hs[j] < hs[j - 1])
                                     and (j == n - 1 or hs[j] <= hs[j + 1])):
            continue
        w = (1.0 - (hs[j] - hmin) / band) ** 2
        total += w * kp_displacement(st.y, st.dy, st.xm, half,
                                     deepest_point(st.y, st.xm, hs, j), rule.elements, rule.Es)
        weight += w
    return total / weight


@njit(cache=True, nogil=True)
def _kik_piotrowski(st, rule, eps, half, peak):
    """Half-lengths and peaks of the Kik-Piotrowski strips of one patch for a
    scaling ``eps`` per strip."""
    hs = st.hstar
    j0 = _argmin(hs)
    hmin = hs[j0]
    lmax = 0.0
    for j in range(hs.size):
        half[j] = 0.0
        if hmin < 0.0:
            half[j] = math.sqrt(max((1.0 - eps[j]) * hmin - hs[j], 0.0) / st.A[j])
        lmax = max(lmax, half[j])
    u = normalising_displacement(st, half, j0, rule)
    p0 = -hmin / u if (u > 0.0 and lmax > 0.0) else 0.0
    for j in range(hs.size):
        peak[j] = p0 * half[j] / lmax if lmax > 0.0 else 0.0


@njit(cache=True, nogil=True)
def _hertz_strips(st, rule, half, peak, work):
    """Half-lengths and peaks of ANALYN's or STRIPES' Hertz strips of one patch
    (``work``: (3, strips))."""
    hs, A, B = st.hstar, st.A, st.B
    my = hs.size
    jd = _argmin(hs)
    depth = max(-hs[jd], 0.0)                      # total approach
    glat, beta, gc = work[0], work[1], work[2]
    for j in range(my):
        glat[j] = hs[j] + depth                     # lateral gap >= 0
    stripes = rule.code == STRIPES
    j0 = _argmin(glat)
    A0 = A[j0]
    for j in range(my):
        Aj = A0 if stripes else A[j]
        a, b, force = axes_at(Aj, B[j], depth, rule.Es, rule.dt, rule.table)
        alpha1 = depth / (Aj * a * a) if a > 0.0 else 1.0
        beta[j] = depth / (B[j] * b * b) if b > 0.0 else 1.0
        # (the strip's own Hertz solution, kept for its peak below)
        half[j] = alpha1
        peak[j] = 1.5 * force / (math.pi * a * b) if a > 0.0 else 0.0
    if stripes:
        corrected_row(glat, beta, j0, gc, np.empty(max(my - 1, 1)))
    else:
        for j in range(my):
            gc[j] = beta[j] * glat[j]
    # at fixed curvatures the semi-axes scale with sqrt(approach) and the force with
    # approach^(3/2): the peak at the local approach is p_max(d) sqrt(d_loc / d)
    for j in range(my):
        local = depth - gc[j]
        Aj = A0 if stripes else A[j]
        if local > 0.0 and peak[j] > 0.0:
            peak[j] = peak[j] * math.sqrt(local / depth)
            half[j] = math.sqrt(local / (half[j] * Aj))
        else:
            half[j] = 0.0
            peak[j] = 0.0


@njit(cache=True, nogil=True)
def strip_patch(st, rule, half, peak, work):
    """Half-lengths l_j [m] and peak pressures p_j [Pa] of one patch's strips
    (:class:`StripSet`) by the model of ``rule`` (:class:`StripRule`) into ``half``
    and ``peak`` (zero where a strip is out of contact); ``work``: (3, strips).
    The one implementation of the strip models' equations: the per-patch models,
    the batch path and the compiled case and dynamics call it."""
    if rule.code == KIK_PIOTROWSKI or rule.code == KPEC:
        eps = work[0]
        if rule.code == KPEC:
            kpec_eps(st, rule, eps)
        else:
            for j in range(eps.size):
                eps[j] = rule.eps
        _kik_piotrowski(st, rule, eps, half, peak)
    else:
        _hertz_strips(st, rule, half, peak, work)


@njit(cache=True, nogil=True)
def _strip_pressures_kernel(rule, y, dy, xm, hstar, A, B, half, peak):
    work = np.empty((3, y.shape[1]))
    for k in range(y.shape[0]):
        strip_patch(StripSet(y[k], dy[k], xm[k], hstar[k], A[k], B[k]), rule, half[k],
                    peak[k], work)


def kpec_scaling(y, dy, hstar, A, Es):
    """KPEC's virtual-penetration scaling eps per strip (patches, strips)
    (:func:`kpec_eps` per patch)."""
    y, hstar, A = (np.ascontiguousarray(v, dtype=float) for v in (y, hstar, A))
    dy = np.broadcast_to(np.asarray(dy, dtype=float), (y.shape[0],))
    rule = strip_rule("kpec", Es)
    out = np.empty(y.shape)
    for k in range(y.shape[0]):
        kpec_eps(StripSet(y[k], float(dy[k]), y[k], hstar[k], A[k], A[k]), rule, out[k])
    return out


def strip_pressures(model: str, y, dy, xm, hstar, A, B, contact_modulus: float,
                    eps: float = 0.55, elements: int = 20):
    """Half-lengths l_j [m] and peak pressures p_j [Pa] of one strip model
    (:func:`strip_patch` on every patch, compiled).

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
    rule = strip_rule(model, contact_modulus, eps, elements)
    y, xm, hstar, A, B = (np.ascontiguousarray(np.broadcast_to(np.asarray(v, dtype=float),
                                                                np.shape(hstar)))
                          for v in (y, xm, hstar, A, B))
    dy = np.ascontiguousarray(np.broadcast_to(np.asarray(dy, dtype=float), (hstar.shape[0],)))
    half, peak = np.empty(hstar.shape), np.empty(hstar.shape)
    _strip_pressures_kernel(rule, y, dy, xm, hstar, A, B, half, peak)
    return half, peak
