"""Kalker's creep coefficients C11, C22, C23 of linear rolling-contact theory.

Values: Kalker (1990), *Three-Dimensional Elastic Bodies in Rolling Contact*,
Table E.3, for nu = 0, 0.25, 0.5 and g = a/b (a <= b) or b/a (a > b) from 0.1 to 1
(transcription checked in ``REFERENCES.md`` section 4.2; C23 at a/b = 0.8, nu = 0.25
is 1.25).  Interpolation as in CONTACT: linear in g, a parabola in 1/C through the
three values of nu.  Below g = 0.1, Kalker's asymptotic expressions for slender
ellipses are used.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import NamedTuple

import numpy as np
from numba import njit

from ..core.errors import InputError

# rows: g = 0.1 ... 1.0; columns: nu = 0, 0.25, 0.5
_C11_AB = np.array([[2.51, 3.31, 4.85], [2.59, 3.37, 4.81], [2.68, 3.44, 4.80],
                    [2.78, 3.53, 4.82], [2.88, 3.62, 4.83], [2.98, 3.72, 4.91],
                    [3.09, 3.81, 4.97], [3.19, 3.91, 5.05], [3.29, 4.01, 5.12],
                    [3.40, 4.12, 5.20]])
_C22_AB = np.array([[2.51, 2.52, 2.53], [2.59, 2.63, 2.66], [2.68, 2.75, 2.81],
                    [2.78, 2.88, 2.98], [2.88, 3.01, 3.14], [2.98, 3.14, 3.31],
                    [3.09, 3.28, 3.48], [3.19, 3.41, 3.65], [3.29, 3.54, 3.82],
                    [3.40, 3.67, 3.98]])
_C23_AB = np.array([[0.334, 0.473, 0.731], [0.483, 0.603, 0.809], [0.607, 0.715, 0.889],
                    [0.720, 0.823, 0.977], [0.827, 0.929, 1.07], [0.930, 1.03, 1.18],
                    [1.03, 1.14, 1.29], [1.13, 1.25, 1.40], [1.23, 1.36, 1.51],
                    [1.33, 1.47, 1.63]])
# b/a rows g = b/a = 0.1 ... 1.0 (a > b)
_C11_BA = np.array([[10.7, 11.7, 12.9], [6.96, 7.78, 8.82], [5.57, 6.34, 7.34],
                    [4.84, 5.57, 6.57], [4.37, 5.10, 6.11], [4.06, 4.78, 5.80],
                    [3.82, 4.54, 5.58], [3.65, 4.36, 5.42], [3.51, 4.22, 5.30],
                    [3.40, 4.12, 5.20]])
_C22_BA = np.array([[10.7, 12.8, 16.0], [6.96, 8.14, 9.79], [5.57, 6.40, 7.51],
                    [4.84, 5.48, 6.31], [4.37, 4.90, 5.56], [4.06, 4.50, 5.04],
                    [3.82, 4.21, 4.67], [3.65, 3.99, 4.39], [3.51, 3.81, 4.16],
                    [3.40, 3.67, 3.98]])
_C23_BA = np.array([[12.2, 14.6, 18.0], [5.72, 6.63, 7.89], [3.79, 4.32, 5.01],
                    [2.88, 3.24, 3.70], [2.35, 2.62, 2.96], [2.01, 2.23, 2.50],
                    [1.76, 1.95, 2.18], [1.58, 1.75, 1.94], [1.44, 1.59, 1.77],
                    [1.33, 1.47, 1.63]])


class Creepage(NamedTuple):
    """The creepages of a patch (CONTACT's convention: rigid slip of the rail
    relative to the wheel over V), as compiled kernels take them; each a value, or
    an array (e.g. the spin per strip)."""

    #: longitudinal creepage ξ [-]
    xi: float
    #: lateral creepage η [-]
    eta: float
    #: spin creepage φ [1/m]
    phi: float


class KalkerCoefficients(NamedTuple):
    """Kalker's creep coefficients of an ellipse [-] (:func:`kalker_coefficients`)."""

    C11: float
    C22: float
    C23: float


class Flexibilities(NamedTuple):
    """FASTSIM's flexibilities [m/Pa] (:func:`flexibilities`): longitudinal, lateral
    and spin; each a value, or an array (per strip)."""

    L1: float
    L2: float
    L3: float


_TAB_AB = np.stack([_C11_AB, _C22_AB, _C23_AB])      # (3 coefficients, 10 ratios, 3 nu)
_TAB_BA = np.stack([_C11_BA, _C22_BA, _C23_BA])


@lru_cache(maxsize=4096)
def _coefficients(a_over_b: float, nu: float):
    out = np.empty((3, 1))
    _coefficients_kernel(np.array([a_over_b]), nu, _TAB_AB, _TAB_BA, out)
    return tuple(float(c) for c in out[:, 0])


def kalker_coefficients(a_over_b: float, nu: float):
    """Creep coefficients (C11, C22, C23) for semi-axis ratio a/b and Poisson's ratio.

    Parameters
    ----------
    a_over_b : float
        Ratio of the semi-axis in the rolling direction to the lateral one.
    nu : float
        Poisson's ratio in [0, 0.5].
    """
    if not (math.isfinite(a_over_b) and a_over_b > 0):
        raise InputError(f"semi-axis ratio a/b = {a_over_b!r}: expected a value > 0")
    if not 0.0 <= nu <= 0.5:
        raise InputError(f"poisson_ratio = {nu!r}: expected a value in [0, 0.5]")
    return _coefficients(float(a_over_b), float(nu))


@njit(cache=True, nogil=True)
def coefficients_at(ri, nu, tab_ab, tab_ba):
    """(C11, C22, C23) of the ratio a/b = ``ri``: the table rows g = 0.1 ... 1.0
    interpolated linearly, a parabola in 1/C through nu = 0, 0.25, 0.5, and the
    asymptotic expressions below g = 0.1 (the scalar form of
    :func:`_coefficients_kernel`, for compiled callers)."""
    x0, x1, x2 = 0.0, 0.25, 0.5
    l0 = (nu - x1) * (nu - x2) / ((x0 - x1) * (x0 - x2))
    l1 = (nu - x0) * (nu - x2) / ((x1 - x0) * (x1 - x2))
    l2 = (nu - x0) * (nu - x1) / ((x2 - x0) * (x2 - x1))
    g = ri if ri <= 1.0 else 1.0 / ri
    if g < 0.1:
        if ri < 1.0:
            return (math.pi ** 2 / (4 * (1 - nu)), math.pi ** 2 / 4,
                    (math.pi * math.sqrt(g) / (3 * (1 - nu))
                     * (1 + nu * (math.log(16 / g) - 5))))
        lam = math.log(16 / g ** 2)
        return ((2 * math.pi / ((lam - 2 * nu) * g)
                 * (1 + (3 - math.log(4)) / (lam - 2 * nu))),
                ((2 * math.pi / g)
                 * (1 + (1 - nu) * (3 - math.log(4)) / ((1 - nu) * lam + 2 * nu))
                 / ((1 - nu) * lam + 2 * nu)),
                2 * math.pi / (3 * g ** 1.5 * ((1 - nu) * lam - 2 + 4 * nu)))
    tab = tab_ab if ri <= 1.0 else tab_ba
    k = min(int((g - 0.1) / 0.1 + 1e-12), 8)
    t = (g - (0.1 + 0.1 * k)) / 0.1
    return (_table_row(tab, 0, k, t, l0, l1, l2), _table_row(tab, 1, k, t, l0, l1, l2),
            _table_row(tab, 2, k, t, l0, l1, l2))


@njit(cache=True, nogil=True, inline="always")
def _table_row(tab, m, k, t, l0, l1, l2):
    r0 = (1 - t) * tab[m, k, 0] + t * tab[m, k + 1, 0]
    r1 = (1 - t) * tab[m, k, 1] + t * tab[m, k + 1, 1]
    r2 = (1 - t) * tab[m, k, 2] + t * tab[m, k + 1, 2]
    return 1.0 / (l0 / r0 + l1 / r1 + l2 / r2)


@njit(cache=True)
def _coefficients_kernel(r, nu, tab_ab, tab_ba, out):
    """(C11, C22, C23) for every ratio a/b in ``r`` into ``out`` (3, n)
    (:func:`coefficients_at`)."""
    for i in range(r.size):
        out[0, i], out[1, i], out[2, i] = coefficients_at(r[i], nu, tab_ab, tab_ba)


def kalker_coefficients_array(a_over_b, nu: float):
    """:func:`kalker_coefficients` for an array of ratios a/b (compiled loop)."""
    r = np.asarray(a_over_b, dtype=float)
    if not np.all(np.isfinite(r) & (r > 0)):
        raise InputError("semi-axis ratios a/b: expected finite values > 0")
    if not 0.0 <= nu <= 0.5:
        raise InputError(f"poisson_ratio = {nu!r}: expected a value in [0, 0.5]")
    out = np.empty((3, r.size))
    _coefficients_kernel(np.ascontiguousarray(r.ravel()), float(nu), _TAB_AB, _TAB_BA, out)
    return tuple(o.reshape(r.shape) for o in out)


def flexibilities(a: float, b: float, shear_modulus: float, nu: float):
    """FASTSIM flexibilities L1, L2, L3 [m/Pa] of Kalker (1982).

    L1 = 8a / (3 C11 G),  L2 = 8a / (3 C22 G),  L3 = pi a sqrt(a/b) / (4 G C23).
    """
    c11, c22, c23 = kalker_coefficients(a / b, nu)
    G = shear_modulus
    return (8 * a / (3 * c11 * G), 8 * a / (3 * c22 * G),
            math.pi * a * math.sqrt(a / b) / (4 * G * c23))


def flexibilities_array(a, b, shear_modulus: float, nu: float):
    """:func:`flexibilities` for arrays of semi-axes (vectorised)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return flexibilities_from_coefficients(a, b, *kalker_coefficients_array(a / b, nu),
                                           shear_modulus)


def flexibilities_from_coefficients(a, b, c11, c22, c23, shear_modulus: float):
    """FASTSIM's L1, L2, L3 [m/Pa] of ellipses (a, b) [m] with Kalker's coefficients
    (arrays)."""
    G = shear_modulus
    return (8 * a / (3 * c11 * G), 8 * a / (3 * c22 * G),
            math.pi * a * np.sqrt(a / b) / (4 * G * c23))


@njit(cache=True, nogil=True)
def linear_forces(G, a, b, C11, C22, C23, xi, eta, phi):
    """Kalker's linear theory: creep forces (F_x, F_y) [N] of an ellipse with semi-axes
    a, b [m], shear modulus G [Pa] and coefficients C_ij for creepages xi, eta [-] and
    spin phi [1/m]: F_x = G c^2 C11 xi, F_y = G c^2 C22 eta + G c^3 C23 phi, c = sqrt(a b)."""
    c = math.sqrt(a * b)
    return G * c * c * C11 * xi, G * c * c * C22 * eta + G * c * c * c * C23 * phi
