"""Hertz's theory of elliptic contact, with complete elliptic integrals.

For an undeformed gap h = A x^2 + B y^2 (A, B > 0, relative curvatures) between two
elastic half-spaces with contact modulus E* (1/E* = sum (1 - nu^2)/E), the contact
area is an ellipse with semi-axes a (along x) and b (along y), and the pressure is
p = p0 sqrt(1 - x^2/a^2 - y^2/b^2), p0 = 3 F / (2 pi a b).

With the major semi-axis along the smaller curvature, k = minor/major, e^2 = 1 - k^2,
and K = K(e), E = E(e) the complete elliptic integrals of the first and second kind
(Johnson, *Contact Mechanics*, 1985, section 4.2):

    A_small = (p0 k / (E* a_major)) (K - E) / e^2
    A_large = (p0 k / (E* a_major)) (E / k^2 - K) / e^2
    delta   =  p0 a_minor K / E*

so the curvature ratio fixes e, and the force (or the penetration) the size.
No curve fits are used.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numba import njit
from scipy.optimize import brentq
from scipy.special import ellipe, ellipk

from .errors import InputError


def _k_minus_e_over_m(m: float) -> float:
    """(K(m) - E(m)) / m, accurate also for small m."""
    if m < 1e-6:
        return math.pi / 4.0 * (1.0 + 3.0 * m / 8.0 + 45.0 * m * m / 256.0)
    return (ellipk(m) - ellipe(m)) / m


def _k_minus_e_over_m_array(m: np.ndarray) -> np.ndarray:
    """Vectorised :func:`_k_minus_e_over_m`."""
    mm = np.where(m < 1e-6, 0.5, m)
    return np.where(m < 1e-6, math.pi / 4.0 * (1.0 + 3.0 * m / 8.0 + 45.0 * m * m / 256.0),
                    (ellipk(mm) - ellipe(mm)) / mm)


def _checked_arrays(A, B, penetration):
    """Curvatures [1/m] and approaches [m] broadcast together, curvatures checked."""
    A, B, d = np.broadcast_arrays(np.asarray(A, float), np.asarray(B, float),
                                  np.asarray(penetration, float))
    if not (np.all(np.isfinite(A)) and np.all(np.isfinite(B)) and np.all(A > 0)
            and np.all(B > 0)):
        raise InputError("relative curvatures A, B: expected finite values > 0 1/m")
    return A, B, d


#: Taylor coefficients of the curvature ratio (E/(1-m) - K)/(K - E) in m, from the
#: series of K and E; used below SERIES_M, where the closed form loses digits to
#: cancellation (docs/tuning.md, section "Strip models and the Hertz formulas").
_RATIO_SERIES = (1.0, 3 / 4, 21 / 32, 309 / 512, 291 / 512, 17781 / 32768)
SERIES_M = 3e-3


def _ratio_series(m):
    out = 0.0
    for c in reversed(_RATIO_SERIES):
        out = out * m + c
    return out


def _ratio(m: float) -> float:
    """Curvature ratio A_large / A_small of an ellipse with e^2 = m."""
    if m < SERIES_M:
        return _ratio_series(m)
    K, E = ellipk(m), ellipe(m)
    return (E / (1.0 - m) - K) / (K - E)


def eccentricity_from_ratio(ratio: float) -> float:
    """e^2 of the Hertz ellipse for a curvature ratio A_large/A_small >= 1."""
    if ratio < 1.0:
        raise InputError(f"curvature ratio {ratio}: expected >= 1")
    if ratio - 1.0 < 1e-12:
        return 0.0
    hi = 1.0 - 1e-15
    if _ratio(hi) < ratio:
        raise InputError(f"curvature ratio {ratio:.4g} is beyond the range of Hertz theory "
                         "handled here (semi-axis ratio above 1e7)")
    return brentq(lambda m: _ratio(m) - ratio, 0.0, hi, xtol=1e-17, rtol=1e-15, maxiter=400)


@dataclass(frozen=True)
class HertzEllipse:
    """Hertz solution: semi-axes a (x), b (y) [m], p0 [Pa], penetration [m], force [N]."""

    a: float
    b: float
    p0: float
    penetration: float
    force: float

    @property
    def area(self) -> float:
        return math.pi * self.a * self.b


def hertz_ellipse(A: float, B: float, contact_modulus: float, force: float | None = None,
                  penetration: float | None = None) -> HertzEllipse:
    """Solve Hertz's elliptic contact for a given force or penetration.

    Parameters
    ----------
    A, B : float
        Relative curvatures [1/m] in the gap h = A x^2 + B y^2 (x rolling, y lateral);
        a concave body enters with its negative curvature, the sum must stay > 0.
    contact_modulus : float
        E* [Pa].
    force, penetration : float
        Exactly one: normal force F [N] >= 0 or approach delta [m] >= 0.
    """
    for name, v in (("A", A), ("B", B)):
        if isinstance(v, float) and math.isnan(v):
            raise InputError(f"relative curvature {name} = nan 1/m: the wheel and rail "
                             "surfaces do not meet in a patch (is a rail profile given as the "
                             "wheel, or a wheel profile as the rail?)")
        if not (math.isfinite(v) and v > 0.0):
            raise InputError(f"relative curvature {name} = {v!r} 1/m: expected > 0 (the surfaces "
                             "must form a point contact; for conformal or flat geometry use a "
                             "non-Hertzian model)")
    if (force is None) == (penetration is None):
        raise InputError("give exactly one of normal force and penetration")
    small, large = min(A, B), max(A, B)
    m = eccentricity_from_ratio(large / small)
    k = math.sqrt(1.0 - m)
    K = math.pi / 2.0 if m == 0.0 else float(ellipk(m))
    kme = _k_minus_e_over_m(m)
    Es = contact_modulus
    if force is not None:
        if not (math.isfinite(force) and force >= 0.0):
            raise InputError(f"normal force {force!r} N: expected a finite value >= 0")
        a_major = (3.0 * force * kme / (2.0 * math.pi * Es * small)) ** (1.0 / 3.0)
        a_minor = k * a_major
        p0 = 3.0 * force / (2.0 * math.pi * a_major * a_minor) if force > 0 else 0.0
        delta = p0 * a_minor * K / Es
        F = force
    else:
        if not (math.isfinite(penetration) and penetration >= 0.0):
            raise InputError(f"penetration {penetration!r} m: expected a finite value >= 0")
        a_major = math.sqrt(penetration * kme / (K * small))
        a_minor = k * a_major
        F = 2.0 * math.pi * a_major * penetration * Es / (3.0 * K)
        p0 = 3.0 * F / (2.0 * math.pi * a_major * a_minor) if F > 0 else 0.0
        delta = penetration
    a, b = (a_major, a_minor) if A <= B else (a_minor, a_major)
    return HertzEllipse(a, b, p0, delta, F)


def hertz_curvatures(a: float, b: float, contact_modulus: float, force: float):
    """Relative curvatures (A, B) [1/m] of the Hertzian contact with semi-axes a
    (x, rolling) and b (y, lateral) [m] under the normal force [N]: the inverse of
    :func:`hertz_ellipse` (CONTACT's module 3 with the semi-axes prescribed,
    IPOTCN = -3).  With p0 = 3 F / (2 pi a b), k = minor / major and m = 1 - k^2,
    the curvature along the major axis is p0 k (K - E) / (E* a_major m), along the
    minor axis p0 k (E / k^2 - K) / (E* a_major m) (Johnson 1985, section 4.2)."""
    for name, v in (("a", a), ("b", b), ("force", force)):
        if not (math.isfinite(v) and v > 0.0):
            raise InputError(f"Hertzian {name} = {v!r}: expected a value > 0")
    p0 = 3.0 * force / (2.0 * math.pi * a * b)
    major, minor = max(a, b), min(a, b)
    k = minor / major
    m = 1.0 - k * k
    if m < 1e-12:
        A = B = math.pi * p0 / (4.0 * contact_modulus * a)
        return A, B
    K, E = float(ellipk(m)), float(ellipe(m))
    along_major = p0 * k * (K - E) / (contact_modulus * major * m)
    along_minor = p0 * k * (E / k ** 2 - K) / (contact_modulus * major * m)
    return (along_major, along_minor) if a >= b else (along_minor, along_major)


def _ratio_array(m: np.ndarray) -> np.ndarray:
    """Vectorised :func:`_ratio`."""
    small = m < SERIES_M
    ms = np.where(small, 0.5, m)
    K, E = ellipk(ms), ellipe(ms)
    return np.where(small, _ratio_series(m), (E / (1.0 - ms) - K) / (K - E))


@lru_cache(maxsize=1)
def _ratio_table():
    u = np.linspace(-15.0, -1e-9, 16001)
    return u, np.log(_ratio_array(1.0 - 10.0 ** u))


def _m_from_ratio_array(ratio: np.ndarray) -> np.ndarray:
    """e^2 for an array of curvature ratios >= 1 (vectorised
    :func:`eccentricity_from_ratio`)."""
    u_tab, lr_tab = _ratio_table()
    target = np.log(ratio)
    if np.any(target > lr_tab[0]):
        raise InputError("curvature ratio beyond the range of Hertz theory handled here "
                         "(semi-axis ratio above 1e7)")
    u = np.interp(target, lr_tab[::-1], u_tab[::-1])
    # one Newton step: the table is dense enough (tested against the scalar solver)
    h = 1e-7
    f0 = np.log(_ratio_array(1.0 - 10.0 ** u)) - target
    f1 = np.log(_ratio_array(1.0 - 10.0 ** (u + h))) - target
    slope = (f1 - f0) / h
    u = np.clip(np.where(slope != 0, u - f0 / np.where(slope != 0, slope, 1.0), u), -15.0, 0.0)
    return np.where(ratio - 1.0 < 1e-9, 0.0, 1.0 - 10.0 ** u)


def hertz_ellipses(A, B, contact_modulus: float, penetration):
    """Hertz semi-axes and forces for arrays of curvatures at given approaches.

    Vectorised form of :func:`hertz_ellipse` (given penetration) for the strip
    models, which need one Hertz solution per strip.  The eccentricity is found by
    interpolation in a table of log(ratio) against u = log10(1 - e^2) (16001
    points), refined by one Newton step on u (agrees with the scalar solver to
    5e-13 in e^2).

    Parameters
    ----------
    A, B : array_like   relative curvatures [1/m], > 0
    penetration : array_like   approach [m] (entries <= 0 give zero-size ellipses)

    Returns
    -------
    a, b, force : ndarray   semi-axes along x, y [m] and normal force [N]
    """
    A, B, d = _checked_arrays(A, B, penetration)
    small, large = np.minimum(A, B), np.maximum(A, B)
    ratio = large / small
    m = _m_from_ratio_array(ratio)
    k = np.sqrt(1.0 - m)
    K = ellipk(m)
    kme = _k_minus_e_over_m_array(m)
    dpos = np.maximum(d, 0.0)
    a_major = np.sqrt(dpos * kme / (K * small))
    a_minor = k * a_major
    force = 2.0 * math.pi * a_major * dpos * contact_modulus / (3.0 * K)
    a = np.where(A <= B, a_major, a_minor)
    b = np.where(A <= B, a_minor, a_major)
    return a, b, force


#: points of the table of :func:`hertz_ellipses_table`, uniform in log(ratio) up to
#: the ratio table's end
AXES_TABLE_POINTS = 32001


@lru_cache(maxsize=1)
def _axes_table():
    """Uniform table in t = log(A_large/A_small): sqrt((K - E)/(m K)), k = sqrt(1 - m)
    and 1/K, with m from :func:`_m_from_ratio_array`; returns (dt, table (3, n))."""
    _, lr_tab = _ratio_table()
    t = np.linspace(0.0, lr_tab[0], AXES_TABLE_POINTS)
    m = _m_from_ratio_array(np.exp(t))
    K = ellipk(m)
    return float(t[1] - t[0]), np.ascontiguousarray(
        [np.sqrt(_k_minus_e_over_m_array(m) / K), np.sqrt(1.0 - m), 1.0 / K])


@njit(cache=True, nogil=True)
def axes_at(A, B, d, Es, dt, tab):
    """Hertz's semi-axes a (along A), b [m] and force [N] of curvatures (A, B)
    [1/m] at the approach d [m] from the table of :func:`_axes_table` (``dt``,
    ``tab``), for compiled callers: the one scalar form of
    :func:`hertz_ellipses_table`."""
    n = tab.shape[1]
    small = min(A, B)
    t = math.log(max(A, B) / small) / dt
    j = min(int(t), n - 2)
    w = t - j
    dp = max(d, 0.0)
    major = math.sqrt(dp / small) * ((1.0 - w) * tab[0, j] + w * tab[0, j + 1])
    minor = ((1.0 - w) * tab[1, j] + w * tab[1, j + 1]) * major
    F = 2.0 * math.pi * major * dp * Es / 3.0 * ((1.0 - w) * tab[2, j] + w * tab[2, j + 1])
    if A <= B:
        return major, minor, F
    return minor, major, F


@njit(cache=True, nogil=True)
def _axes_kernel(A, B, d, Es, dt, tab, a, b, F):
    for i in range(A.size):
        a[i], b[i], F[i] = axes_at(A[i], B[i], d[i], Es, dt, tab)


def hertz_ellipses_table(A, B, contact_modulus: float, penetration):
    """:func:`hertz_ellipses` interpolated linearly in a table uniform in the log of
    the curvature ratio (relative error below 1e-7; docs/tuning.md, section "Strip
    models and the Hertz formulas"): for the strip models and FASTSIM's local
    ellipses, one Hertz solution per strip.

    Returns a, b [m] and the force [N], arrays of the broadcast shape.
    """
    A, B, d = _checked_arrays(A, B, penetration)
    shape = A.shape
    A, B, d = (np.ascontiguousarray(v).ravel() for v in (A, B, d))
    dt, tab = _axes_table()
    if np.any(np.maximum(A, B) / np.minimum(A, B) > math.exp(dt * (tab.shape[1] - 1))):
        raise InputError("curvature ratio beyond the range of Hertz theory handled here "
                         "(semi-axis ratio above 1e7)")
    a, b, F = np.empty(A.size), np.empty(A.size), np.empty(A.size)
    _axes_kernel(A, B, d, float(contact_modulus), dt, tab, a, b, F)
    return a.reshape(shape), b.reshape(shape), F.reshape(shape)
