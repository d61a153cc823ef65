"""Influence coefficients of the elastic half-space and FFT convolution.

Normal surface displacement (difference of two identical half-spaces) at the
centre of element (i, j) due to a unit uniform pressure on element (k, l) of a
uniform grid (Love 1929; Johnson 1985, section 3.9):

    A = 1 / (pi E*) * [F(x + dx/2, y + dy/2) - F(x - dx/2, y + dy/2)
                       - F(x + dx/2, y - dy/2) + F(x - dx/2, y - dy/2)],
    F(x, y) = x ln(y + r) + y ln(x + r),  r = sqrt(x^2 + y^2),

with (x, y) the offset between the element centres and 1/E* = 2 (1 - nu^2) / E.
The matrix is block-Toeplitz, so products A p are computed as zero-padded
convolutions with real FFTs (never as a dense N x N matrix).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numba import njit
from scipy import fft

from ..core.errors import InputError


def _log_sum(a, b, r):
    """ln(a + r) with r = hypot(a, b), accurate when a < 0 (a + r = b^2 / (r - a))."""
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(a >= 0, a + r, b * b / (r - a))
        return np.log(s)


def _F(x, y):
    """Antiderivative of 1/r over a rectangle: x ln(y + r) + y ln(x + r)."""
    r = np.hypot(x, y)
    t1 = np.where(x != 0, x * np.where(x != 0, _log_sum(y, x, r), 0.0), 0.0)
    t2 = np.where(y != 0, y * np.where(y != 0, _log_sum(x, y, r), 0.0), 0.0)
    return t1 + t2


def _element_integrals(mx: int, my: int, dx: float, dy: float, extra_rows: int = 0):
    """``rect(F, parity)``: the integral over an element (dx x dy) of a kernel with
    antiderivative F, at the offsets between element centres, di in
    [-(mx-1), mx-1+extra_rows], dj in [-(my-1), my-1] (array of that shape).

    The kernels are even or odd in each offset (``parity`` +1 or -1 per axis): the
    integrals are evaluated for non-negative offsets only, on the antiderivative at
    the element corners (shared by four elements each), and mirrored."""
    nx = mx + extra_rows
    cx = (np.arange(nx + 1) - 0.5) * dx
    cy = (np.arange(my + 1) - 0.5) * dy
    X, Y = np.meshgrid(cx, cy, indexing="ij")
    di = np.arange(-(mx - 1), nx)
    dj = np.arange(-(my - 1), my)
    ix, jy = np.abs(di), np.abs(dj)
    sx, sy = np.where(di < 0, -1.0, 1.0), np.where(dj < 0, -1.0, 1.0)

    def rect(F, parity=(1, 1)):
        G = F(X, Y)
        Q = G[1:, 1:] - G[:-1, 1:] - G[1:, :-1] + G[:-1, :-1]
        out = Q[np.ix_(ix, jy)]
        if parity[0] < 0:
            out = out * sx[:, None]
        if parity[1] < 0:
            out = out * sy[None, :]
        return out

    return rect


@njit(cache=True, nogil=True)
def _rect_kernel(mx, my, dx, dy):
    """Compiled body of :func:`rect_integrals`: x ln(y + r), y ln(x + r) and -r at
    the element corners ((i - 1/2) dx, (j - 1/2) dy) (r and the logarithms shared;
    ln(a + r) accurate for a < 0 as ln(b^2 / (r - a)), terms with a zero factor 0),
    their differences over the elements at non-negative offsets, mirrored (the
    first two even in both offsets, the third odd)."""
    nx = mx + 1
    Lx = np.zeros((nx + 1, my + 1))
    Ly = np.zeros((nx + 1, my + 1))
    R = np.empty((nx + 1, my + 1))
    for i in range(nx + 1):
        x = (i - 0.5) * dx
        for j in range(my + 1):
            y = (j - 0.5) * dy
            r = math.hypot(x, y)
            R[i, j] = -r
            if x != 0.0:
                Lx[i, j] = x * math.log(y + r if y >= 0 else x * x / (r - y))
            if y != 0.0:
                Ly[i, j] = y * math.log(x + r if x >= 0 else y * y / (r - x))
    out = np.empty((3, mx + nx - 1, 2 * my - 1))
    for a in range(mx + nx - 1):
        di = a - (mx - 1)
        i = abs(di)
        for b in range(2 * my - 1):
            dj = b - (my - 1)
            j = abs(dj)
            out[0, a, b] = Lx[i + 1, j + 1] - Lx[i, j + 1] - Lx[i + 1, j] + Lx[i, j]
            out[1, a, b] = Ly[i + 1, j + 1] - Ly[i, j + 1] - Ly[i + 1, j] + Ly[i, j]
            q = R[i + 1, j + 1] - R[i, j + 1] - R[i + 1, j] + R[i, j]
            out[2, a, b] = -q if (di < 0) != (dj < 0) else q
    return out


@lru_cache(maxsize=64)
def rect_integrals(mx: int, my: int, dx: float, dy: float):
    """The element integrals of the half-space's influence functions on a grid.

    The integrals over one element (dx x dy, centred at the origin) of y^2/r^3,
    x^2/r^3 and xy/r^3 [m], r the distance from the point (x, y), at the offsets
    between element centres di in [-(mx-1), mx], dj in [-(my-1), my-1] (one row
    beyond the grid's offsets, for the rolling difference).  They come from the
    antiderivatives x ln(y + r), y ln(x + r) and -r at the element's corners (Love
    1929; Johnson 1985, sections 3.2 and 3.9: the Boussinesq and Cerruti
    displacements of a uniformly loaded rectangle); 1/r is the sum of the first
    two.  Every influence kernel of the half-space is a combination of them
    (:func:`normal_coefficient`, :func:`tangential_coefficients`).

    Parameters
    ----------
    mx, my : int
        The grid's elements in x and y.
    dx, dy : float
        The element's size [m].

    Returns
    -------
    (Lx, Ly, R) : tuple of ndarray, each of shape (2 mx, 2 my - 1)
        The integrals of y^2/r^3, x^2/r^3 and xy/r^3 [m]; row ``di + mx - 1``,
        column ``dj + my - 1`` the offset (di, dj).  Computed compiled, once per grid
        (cached) for all the kernels.
    """
    out = _rect_kernel(mx, my, float(dx), float(dy))
    return out[0], out[1], out[2]


@njit(cache=True, nogil=True)
def normal_coefficient(lx, ly, contact_modulus):
    """The normal influence coefficient [m/Pa] of one offset: (lx + ly) / (pi E*),
    from the element integrals lx, ly [m] of y^2/r^3 and x^2/r^3
    (:func:`rect_integrals`; their sum the integral of 1/r) and the contact modulus
    E* [Pa] (Boussinesq; Johnson 1985, section 3.9, for two identical bodies)."""
    return (lx + ly) / (math.pi * contact_modulus)


@njit(cache=True, nogil=True)
def tangential_coefficients(lx, ly, r, c, nu):
    """The tangential influence coefficients (xx, xy, yy) [m/Pa] of one offset
    (:func:`tangential_kernels`' formulas), from the element integrals lx, ly, r [m]
    of y^2/r^3, x^2/r^3 and xy/r^3 (:func:`rect_integrals`), c = 1/(pi G) [1/Pa]
    and Poisson's ratio nu (Cerruti; Johnson 1985, eqs. 3.86-3.87)."""
    s = lx + ly
    return c * ((1 - nu) * s + nu * ly), c * nu * r, c * ((1 - nu) * s + nu * lx)


@njit(cache=True, nogil=True)
def _normal_cut(Lx, Ly, first, shape, contact_modulus):
    """The normal kernel (:func:`normal_coefficient`) at the offsets of the grid's
    integrals ``Lx``, ``Ly`` from row, column ``first`` on, ``shape`` of them."""
    out = np.empty(shape)
    for a in range(shape[0]):
        for b in range(shape[1]):
            out[a, b] = normal_coefficient(Lx[first[0] + a, first[1] + b],
                                           Ly[first[0] + a, first[1] + b], contact_modulus)
    return out


@njit(cache=True, nogil=True)
def _tangential_rows(Lx, Ly, R, rows, c, nu):
    """The tangential kernels (:func:`tangential_coefficients`) at the first
    ``rows`` rows of offsets of the grid's integrals ``Lx``, ``Ly``, ``R``."""
    out = np.empty((3, rows, Lx.shape[1]))
    for a in range(rows):
        for b in range(Lx.shape[1]):
            out[0, a, b], out[1, a, b], out[2, a, b] = tangential_coefficients(
                Lx[a, b], Ly[a, b], R[a, b], c, nu)
    return out


def _check_extra_rows(extra_rows) -> int:
    """``extra_rows`` as the int 0 or 1 (the row of the rolling difference), or an
    :class:`InputError` naming it (a float such as 1.0 too: the kernels index by it)."""
    if not isinstance(extra_rows, (int, np.integer)) or extra_rows not in (0, 1):
        raise InputError(f"extra_rows = {extra_rows!r}: expected the integer 0 or 1 (the "
                         "row of the rolling difference)")
    return int(extra_rows)


def normal_kernel(mx: int, my: int, dx: float, dy: float, contact_modulus: float,
                  extra_rows: int = 0) -> np.ndarray:
    """Kernel A[di, dj] for offsets di in [-(mx-1), mx-1+extra_rows], dj in
    [-(my-1), my-1] [m/Pa] (:func:`normal_coefficient` of :func:`rect_integrals`);
    ``extra_rows`` 0 or 1 (the row of the rolling difference)."""
    extra_rows = _check_extra_rows(extra_rows)
    Lx, Ly, _ = rect_integrals(mx, my, float(dx), float(dy))
    return _normal_cut(Lx, Ly, (0, 0), (2 * mx - 1 + extra_rows, 2 * my - 1),
                       float(contact_modulus))


@njit(cache=True, nogil=True)
def _kernel_spectrum(kernel, m, n, N1, N2):
    """Real 2-D FFT of a kernel placed for zero-padded convolution on an N1 x N2
    grid: kernel[a, b] holds the offsets (a - (m-1), b - (n-1)), placed modulo the
    size, so that circular convolution of an m x n field equals the linear one."""
    k = np.zeros((N1, N2))
    for a in range(kernel.shape[0]):
        i = (a - (m - 1)) % N1
        for b in range(kernel.shape[1]):
            k[i, (b - (n - 1)) % N2] = kernel[a, b]
    return np.fft.rfft2(k)


class Convolution:
    """y = A p on an mx x my grid, by zero-padded real FFTs."""

    #: the column weights of a modulated operator (None: the half-space's; Blanco's
    #: :class:`~railcontact.normal.conformal_influence.ModulatedConvolution`)
    modulation = None

    def __init__(self, kernel: np.ndarray, mx: int, my: int):
        self.mx, self.my = mx, my
        self.shape = (fft.next_fast_len(2 * mx - 1, real=True),
                      fft.next_fast_len(2 * my - 1, real=True))
        #: the kernel itself, offsets -(mx-1)..mx-1, -(my-1)..my-1 (the displacements
        #: of a few elements' pressures, summed directly)
        self.kernel = np.ascontiguousarray(kernel, dtype=float)
        self.khat = _kernel_spectrum(self.kernel, mx, my, *self.shape)
        self.diag = float(kernel[mx - 1, my - 1])

    def __call__(self, p: np.ndarray) -> np.ndarray:
        """A p for p on the grid, or on a smaller block (an operator of a block serves
        every smaller one: the kernel's offsets are placed modulo the FFT size)."""
        ph = fft.rfft2(p, s=self.shape)
        return fft.irfft2(ph * self.khat, s=self.shape)[:p.shape[0], :p.shape[1]]


def normal_displacement_at(p: np.ndarray, dx: float, dy: float, i0: int, j0: int,
                           contact_modulus: float) -> float:
    """Normal displacement difference [m] at element (i0, j0) from pressures p [Pa].

    The same sum as ``normal_operator(...)(p)[i0, j0]``, evaluated directly: one row
    of the influence matrix costs O(mx my), without building the kernel and its FFT
    (the strip models need the displacement at one point only, on a grid that
    changes with every patch).
    """
    mx, my = p.shape
    X = ((np.arange(mx) - i0) * dx)[:, None]
    Y = ((np.arange(my) - j0) * dy)[None, :]
    hx, hy = dx / 2, dy / 2
    val = (_F(X + hx, Y + hy) - _F(X - hx, Y + hy)
           - _F(X + hx, Y - hy) + _F(X - hx, Y - hy))
    return float(np.sum(val * p) / (np.pi * contact_modulus))


@lru_cache(maxsize=64)
def normal_operator(mx: int, my: int, dx: float, dy: float, contact_modulus: float) -> Convolution:
    """Cached convolution operator for a grid and material."""
    return Convolution(normal_kernel(mx, my, dx, dy, contact_modulus), mx, my)


@lru_cache(maxsize=4096)
def block_size(m: int, n: int, grid_m: int, grid_n: int, extra_rows: int = 0):
    """The largest block of a grid whose zero-padded FFT has the size of an m x n
    block's (``extra_rows``: output rows below the block, as the rolling difference
    needs): its operator serves every block up to it, so the blocks of successive
    passes (a contact that grows or shrinks by a row) share one."""
    N1 = fft.next_fast_len(2 * m - 1 + extra_rows, real=True)
    N2 = fft.next_fast_len(2 * n - 1, real=True)
    return min(grid_m, (N1 + 1 - extra_rows) // 2), min(grid_n, (N2 + 1) // 2)


def normal_operator_block(mx: int, my: int, dx: float, dy: float, contact_modulus: float,
                          ms: int, ns: int) -> Convolution:
    """Convolution operator for an ms x ns block of the mx x my grid, from the grid's
    kernel cut to the block's offsets (the grid's element integrals are computed
    once, whatever blocks of it are solved on); cached per FFT size
    (:func:`block_size`: it serves the block and every smaller one)."""
    return _normal_block(mx, my, dx, dy, contact_modulus, *block_size(ms, ns, mx, my))


@lru_cache(maxsize=64)
def _normal_block(mx, my, dx, dy, contact_modulus, ms, ns) -> Convolution:
    # the grid's kernel (:func:`normal_kernel`) at the block's offsets only
    Lx, Ly, _ = rect_integrals(mx, my, float(dx), float(dy))
    return Convolution(_normal_cut(Lx, Ly, (mx - ms, my - ns), (2 * ms - 1, 2 * ns - 1),
                                   float(contact_modulus)), ms, ns)


def bounding_box(mask: np.ndarray):
    """Slices of the smallest block of the grid that holds every true element of
    ``mask`` (the block the exact solvers work on), or None where there is none."""
    i0, i1, j0, j1 = box_bounds(np.ascontiguousarray(mask, dtype=np.bool_))
    if i1 < 0:
        return None
    return slice(i0, i1 + 1), slice(j0, j1 + 1)


@njit(cache=True, nogil=True)
def box_bounds(mask):
    """First and last row, first and last column holding a true element of the 2-D
    ``mask`` (-1 each where there is none): :func:`bounding_box`'s scan, compiled
    (a few microseconds of NumPy calls per solve otherwise)."""
    i0, i1, j0, j1 = -1, -1, mask.shape[1], -1
    for i in range(mask.shape[0]):
        for j in range(mask.shape[1]):
            if mask[i, j]:
                if i0 < 0:
                    i0 = i
                i1 = i
                j0 = min(j0, j)
                j1 = max(j1, j)
    if i1 < 0:
        j0 = -1
    return i0, i1, j0, j1


def tangential_kernels(mx: int, my: int, dx: float, dy: float, shear_modulus: float,
                       poisson_ratio: float, extra_rows: int = 0):
    """Tangential influence kernels (xx, xy, yy) [m/Pa] for identical bodies.

    Displacement difference at offset (x, y) from a unit uniform traction on an
    element (Cerruti; Johnson 1985, eq. 3.86-3.87, doubled for two bodies):

        u_x = 1/(pi G) [ (1 - nu) I(1/r) + nu I(x^2/r^3) ] t_x + nu/(pi G) I(xy/r^3) t_y
        u_y = nu/(pi G) I(xy/r^3) t_x + 1/(pi G) [ (1 - nu) I(1/r) + nu I(y^2/r^3) ] t_y

    with the rectangle integrals (:func:`rect_integrals`) from the antiderivatives
    I(y^2/r^3) = x ln(y + r), I(x^2/r^3) = y ln(x + r), I(xy/r^3) = -r
    (:func:`tangential_coefficients`, element by element).  Offsets in x run over
    [-(mx-1), mx-1+extra_rows], ``extra_rows`` 0 or 1 (the row of the rolling
    difference).
    """
    extra_rows = _check_extra_rows(extra_rows)
    Lx, Ly, Rr = rect_integrals(mx, my, float(dx), float(dy))
    k = _tangential_rows(Lx, Ly, Rr, 2 * mx - 1 + extra_rows, 1.0 / (np.pi * shear_modulus),
                         float(poisson_ratio))
    return k[0], k[1], k[2]


def _Cx(x, y):
    """Antiderivative of x/r^2 over a rectangle: (y/2) ln(x^2 + y^2) + x atan(y/x)
    (terms linear in one variable, which cancel over a rectangle, dropped)."""
    r2 = x * x + y * y
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = np.where(r2 > 0, 0.5 * y * np.log(np.where(r2 > 0, r2, 1.0)), 0.0)
        t2 = np.where(x != 0, x * np.arctan(y / np.where(x != 0, x, 1.0)), 0.0)
    return t1 + t2


def coupling_kernels(mx: int, my: int, dx: float, dy: float, D: float, extra_rows: int = 0):
    """Kernels (k_x, k_y) [m/Pa] coupling normal and tangential problems of dissimilar
    bodies: D times the integrals of x/r^2 and y/r^2 over an element (Boussinesq
    and Cerruti; Johnson 1985, eqs. 3.19, 3.21), D = [(1 - 2 nu1)/G1 - (1 - 2 nu2)/G2]
    / (4 pi) = K / (pi G).  The normal displacement difference from tractions
    (t_x, t_y) on body 1 is k_x * t_x + k_y * t_y; the tangential displacement
    difference from the pressure p is -(k_x, k_y) * p.  Offsets in x run over
    [-(mx-1), mx-1+extra_rows]."""
    rect = _element_integrals(mx, my, dx, dy, extra_rows)
    kx = rect(_Cx, parity=(-1, 1))
    ky = rect(lambda a, b: _Cx(b, a), parity=(1, -1))
    return D * kx, D * ky


class ShiftedConvolution:
    """u = K p on an (mx + rows) x my output grid for p on mx x my (rows above)."""

    def __init__(self, kernel: np.ndarray, mx: int, my: int, rows: int = 1):
        self.mx, self.my, self.rows = mx, my, rows
        mo = mx + rows
        self.shape = (fft.next_fast_len(mx + mo - 1, real=True),
                      fft.next_fast_len(2 * my - 1, real=True))
        # kernel offsets di in [-(mx-1), mo-1], dj in [-(my-1), my-1]
        self.khat = _kernel_spectrum(np.ascontiguousarray(kernel, dtype=float), mx, my,
                                     *self.shape)

    def __call__(self, p: np.ndarray) -> np.ndarray:
        return fft.irfft2(fft.rfft2(p, s=self.shape) * self.khat,
                          s=self.shape)[:self.mx + self.rows, :self.my]


def rigid_slip_of(ux: np.ndarray, uy: np.ndarray, dx: float, mode: str = "rolling"):
    """The rigid slip that a tangential displacement difference (u_x, u_y) [m] on a
    grid and one row of x beyond it (a :class:`ShiftedConvolution`'s output) adds
    to the tangential problem: in steady rolling -(u(I+) - u(I))/dx [-] (``dx``
    the grid's step [m]), in a shift (``mode = "shift"``) u(I) itself [m].  The
    pressure's share in the coupled normal and tangential problems: dissimilar
    materials (:mod:`railcontact.cases.coupling`) and Blanco's conformal
    coefficients (:mod:`railcontact.normal.conformal_influence`)."""
    if mode == "shift":
        return np.ascontiguousarray(ux[:-1]), np.ascontiguousarray(uy[:-1])
    return (np.ascontiguousarray(-(ux[1:] - ux[:-1]) / dx),
            np.ascontiguousarray(-(uy[1:] - uy[:-1]) / dx))


class TangentialOperator:
    """(u_x, u_y) = B (p_x, p_y) on an (mx + rows) x my grid with shared FFTs."""

    def __init__(self, kernels, mx: int, my: int, rows: int = 1):
        convs = [ShiftedConvolution(k, mx, my, rows) for k in kernels]
        self.shape = convs[0].shape
        self.kxx, self.kxy, self.kyy = (c.khat for c in convs)
        self.mx, self.my, self.rows = mx, my, rows

    def __call__(self, px: np.ndarray, py: np.ndarray):
        """Displacements of tractions on the grid or on a smaller block (as
        :meth:`Convolution.__call__`), with the extra rows."""
        fx = fft.rfft2(px, s=self.shape)
        fy = fft.rfft2(py, s=self.shape)
        n, m = px.shape[0] + self.rows, px.shape[1]
        ux = fft.irfft2(self.kxx * fx + self.kxy * fy, s=self.shape)[:n, :m]
        uy = fft.irfft2(self.kxy * fx + self.kyy * fy, s=self.shape)[:n, :m]
        return ux, uy
