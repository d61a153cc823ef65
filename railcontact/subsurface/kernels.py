"""Stresses in an elastic half-space under uniform loads on rectangles.

The half-space is z >= 0 (z the depth), loaded on its surface by a pressure p
(pushing into the body, +z) and shear tractions q_x, q_y (acting on the body, in
+x, +y).  Stresses are positive in tension.  With the potentials of Love (1929) and
Johnson (*Contact Mechanics*, 1985, section 3.2, eqs. 3.18-3.20)

    Omega = z ln(rho + z) - rho,   L = d Omega / dz = ln(rho + z),   I = dL/dz = 1/rho,

(rho the distance to the load point; all three harmonic), a unit load on an element
gives stresses that are combinations of derivatives of the integrals of Omega, L
and I over the element.  For an element [x1, x2] x [y1, y2] each such integral is
the sum over the corners of a *corner function* C(u, v, z) of the offsets
u = x - x_k, v = y - y_k:

    C(u1, v1) - C(u2, v1) - C(u1, v2) + C(u2, v2),   u1 = x - x1, u2 = x - x2, ...

with C a double antiderivative in (u, v); an x-derivative of the potential is a
u-derivative of C.  The corner functions used here (rho^2 = u^2 + v^2 + z^2):

    C[I_x]  = ln(v + rho)          C[I_y]  = ln(u + rho)          C[I_xy] = 1/rho
    C[I_xx] = u / (rho (v + rho))  C[I_yy] = v / (rho (u + rho))
    C[I_z]  = -atan(u v / (z rho))
    C[I_xz] = -z v / ((u^2 + z^2) rho)     C[I_yz] = -z u / ((v^2 + z^2) rho)
    C[I_zz] = u v (rho^2 + z^2) / (rho (u^2 + z^2) (v^2 + z^2))
    C[L_xx] = atan(u v (rho - z) / (u^2 rho + z v^2))  (C[L_yy]: u, v swapped)
    C[L_xy] = ln(rho + z)     C[L_xxy] = u / (rho (rho + z))    C[L_xyy] = v / (rho (rho + z))
    C[Omega_xxy] = -u / (rho + z)       C[Omega_xyy] = -v / (rho + z)

and, the potentials being harmonic (Omega_zz = I, L_zz = I_z),
L_xxx = -L_xyy - I_xz and Omega_xxx = -Omega_xyy - I_x.  The stresses follow from
Johnson's displacements by Hooke's law (2 pi sigma per unit load):

    pressure p:   xx = 2 nu I_z - z I_xx - (1 - 2 nu) L_xx,   zz = I_z - z I_zz,
                  xy = -(1 - 2 nu) L_xy - z I_xy,   xz = -z I_xz,   yz = -z I_yz
    traction q_x: xx = 2 (1 + nu) I_x + 2 nu Omega_xxx - z L_xxx,
                  yy = 2 nu (Omega_xyy + I_x) - z L_xyy,   zz = -z I_xz,
                  xy = I_y + 2 nu Omega_xxy - z L_xxy,   xz = I_z - z I_xx,   yz = -z I_xy

(yy of p and the stresses of q_y by exchanging x and y).  At the surface they give
sigma_zz = -p, sigma_xz = -q_x, sigma_yz = -q_y inside the element.

Two uses: the element kernels on a uniform grid of element centres at one depth
(:func:`grid_kernels`, convolved by FFT in :mod:`railcontact.subsurface.stresses`),
and stresses at arbitrary points by direct summation (:func:`stresses_at_points`).
"""

from __future__ import annotations

import math
import numpy as np
from numba import njit
from scipy import fft

from ..errors import InputError

#: order of the six stress components in every array of this package
COMPONENTS = ("xx", "yy", "zz", "xy", "xz", "yz")
#: order of the three loads
LOADS = ("p", "qx", "qy")


@njit(cache=True, nogil=True)
def _log_plus(a, b2, r):
    """ln(a + r) with r = sqrt(a^2 + b2), accurate for a < 0 (a + r = b2 / (r - a))."""
    if a >= 0.0:
        return math.log(a + r)
    return math.log(b2 / (r - a))


@njit(cache=True, nogil=True)
def _corner(u, v, z, nu, out):
    """The 18 corner functions (3 loads x 6 components, :data:`LOADS` x
    :data:`COMPONENTS`) of the stresses at offset (u, v) and depth z >= 0, times 2 pi."""
    u2, v2, z2 = u * u, v * v, z * z
    rho = math.sqrt(u2 + v2 + z2)
    ix = _log_plus(v, u2 + z2, rho)                 # C[I_x]
    iy = _log_plus(u, v2 + z2, rho)                 # C[I_y]
    ixy = 1.0 / rho if rho > 0.0 else 0.0           # C[I_xy]
    # C[I_xx] = u / (rho (v + rho)) = u (rho - v) / (rho (u^2 + z^2))
    if u == 0.0:
        ixx = 0.0
    elif v >= 0.0:
        ixx = u / (rho * (v + rho))
    else:
        ixx = u * (rho - v) / (rho * (u2 + z2))
    if v == 0.0:
        iyy = 0.0
    elif u >= 0.0:
        iyy = v / (rho * (u + rho))
    else:
        iyy = v * (rho - u) / (rho * (v2 + z2))
    iz = -math.atan2(u * v, z * rho)
    if z > 0.0:
        ixz = -z * v / ((u2 + z2) * rho)
        iyz = -z * u / ((v2 + z2) * rho)
        zizz = z * u * v * (rho * rho + z2) / (rho * (u2 + z2) * (v2 + z2))
    else:
        ixz = 0.0
        iyz = 0.0
        zizz = 0.0
    # rho - z, without cancellation at depth
    rmz = (u2 + v2) / (rho + z) if rho + z > 0.0 else 0.0
    uv = u * v
    lxx = 0.0 if uv == 0.0 else math.atan(uv * rmz / (u2 * rho + z * v2))
    lyy = 0.0 if uv == 0.0 else math.atan(uv * rmz / (v2 * rho + z * u2))
    rpz = rho + z
    lxy = math.log(rpz) if rpz > 0.0 else 0.0
    lxxy = u / (rho * rpz) if rpz > 0.0 else 0.0
    lxyy = v / (rho * rpz) if rpz > 0.0 else 0.0
    lxxx = -lxyy - ixz
    lyyy = -lxxy - iyz
    oxxy = -u / rpz if rpz > 0.0 else 0.0
    oxyy = -v / rpz if rpz > 0.0 else 0.0
    oxxx = -ix - oxyy
    oyyy = -iy - oxxy
    a = 1.0 - 2.0 * nu
    # pressure
    out[0, 0] = 2.0 * nu * iz - z * ixx - a * lxx
    out[0, 1] = 2.0 * nu * iz - z * iyy - a * lyy
    out[0, 2] = iz - zizz
    out[0, 3] = -a * lxy - z * ixy
    out[0, 4] = -z * ixz
    out[0, 5] = -z * iyz
    # traction x
    out[1, 0] = 2.0 * (1.0 + nu) * ix + 2.0 * nu * oxxx - z * lxxx
    out[1, 1] = 2.0 * nu * (oxyy + ix) - z * lxyy
    out[1, 2] = -z * ixz
    out[1, 3] = iy + 2.0 * nu * oxxy - z * lxxy
    out[1, 4] = iz - z * ixx
    out[1, 5] = -z * ixy
    # traction y (x and y exchanged)
    out[2, 0] = 2.0 * nu * (oxxy + iy) - z * lxxy
    out[2, 1] = 2.0 * (1.0 + nu) * iy + 2.0 * nu * oyyy - z * lyyy
    out[2, 2] = -z * iyz
    out[2, 3] = ix + 2.0 * nu * oxyy - z * lxyy
    out[2, 4] = -z * ixy
    out[2, 5] = iz - z * iyy


@njit(cache=True, nogil=True)
def _grid_kernel(mx, my, dx, dy, z, nu):
    """Element kernels K[load, comp, a, b]: stress at the centre of element
    (i, j) from a unit load on element (k, l), a = i - k + mx - 1, b = j - l + my - 1."""
    nc1, nc2 = 2 * mx, 2 * my
    C = np.empty((nc1, nc2, 3, 6))
    tmp = np.empty((3, 6))
    for i in range(nc1):
        u = (i - mx + 0.5) * dx          # corner offsets -(mx - 1/2) .. (mx - 1/2) dx
        for j in range(nc2):
            v = (j - my + 0.5) * dy
            _corner(u, v, z, nu, tmp)
            C[i, j] = tmp
    K = np.empty((3, 6, nc1 - 1, nc2 - 1))
    s = 1.0 / (2.0 * math.pi)
    for a in range(nc1 - 1):
        for b in range(nc2 - 1):
            # offset a - (mx - 1): u1 = offset + dx/2 -> corner a + 1, u2 -> corner a
            for ld in range(3):
                for c in range(6):
                    K[ld, c, a, b] = s * (C[a + 1, b + 1, ld, c] - C[a, b + 1, ld, c]
                                          - C[a + 1, b, ld, c] + C[a, b, ld, c])
    return K


def grid_kernels(mx: int, my: int, dx: float, dy: float, depth: float, poisson: float) -> np.ndarray:
    """Influence kernels of the stresses at one depth on a uniform grid.

    Parameters
    ----------
    mx, my : int          elements per direction
    dx, dy : float        element size [m]
    depth : float         depth z >= 0 [m] below the surface
    poisson : float       Poisson's ratio of the loaded body [-]

    Returns
    -------
    ndarray (3, 6, 2 mx - 1, 2 my - 1)
        Stress [Pa per Pa of load] at the centre of an element offset by
        (a - (mx - 1), b - (my - 1)) elements from the loaded one, for the loads
        (p, q_x, q_y) and components (xx, yy, zz, xy, xz, yz).
    """
    _check(depth, poisson)
    return _grid_kernel(int(mx), int(my), float(dx), float(dy), float(depth), float(poisson))


def _check(depth, poisson):
    if not (np.isfinite(depth) and depth >= 0):
        raise InputError(f"subsurface depth {depth!r}: expected a depth >= 0 m")
    if not (0.0 <= poisson < 0.5):
        raise InputError(f"poisson_ratio {poisson!r}: expected a value in [0, 0.5)")


@njit(cache=True, nogil=True)
def _point_kernel(px, py, pz, x1, x2, y1, y2, load, nu, out):
    """out[k, c] = stress c at point k from the uniform loads load[e, 3] on the
    rectangles [x1, x2] x [y1, y2] of the elements e (direct summation)."""
    tmp = np.empty((3, 6))
    s = 1.0 / (2.0 * math.pi)
    for k in range(px.size):
        for c in range(6):
            out[k, c] = 0.0
        for e in range(x1.size):
            if load[e, 0] == 0.0 and load[e, 1] == 0.0 and load[e, 2] == 0.0:
                continue
            for corner in range(4):
                u = px[k] - (x1[e] if corner % 2 == 0 else x2[e])
                v = py[k] - (y1[e] if corner < 2 else y2[e])
                sign = 1.0 if (corner == 0 or corner == 3) else -1.0
                _corner(u, v, pz[k], nu, tmp)
                for ld in range(3):
                    f = sign * s * load[e, ld]
                    if f != 0.0:
                        for c in range(6):
                            out[k, c] += f * tmp[ld, c]


def stresses_at_points(points, rectangles, loads, poisson: float) -> np.ndarray:
    """Stresses at arbitrary points from uniform loads on rectangles, summed directly.

    Parameters
    ----------
    points : array (n, 3)
        Points (x, y, z) [m], z >= 0 the depth.  A point on the surface on an edge of a
        loaded rectangle is singular (the stresses of a uniform load jump there).
    rectangles : array (m, 4)
        Loaded rectangles (x1, x2, y1, y2) [m].
    loads : array (m, 3)
        Uniform (p, q_x, q_y) [Pa] on each rectangle (p pushing into the body).
    poisson : float
        Poisson's ratio [-].

    Returns
    -------
    ndarray (n, 6): stresses [Pa] (xx, yy, zz, xy, xz, yz), tension positive.
    """
    pts = np.ascontiguousarray(np.atleast_2d(np.asarray(points, float)))
    rect = np.ascontiguousarray(np.atleast_2d(np.asarray(rectangles, float)))
    ld = np.ascontiguousarray(np.atleast_2d(np.asarray(loads, float)))
    if pts.shape[1] != 3:
        raise InputError(f"points of shape {pts.shape}: expected (n, 3) rows (x, y, z)")
    if rect.shape[1] != 4 or ld.shape != (rect.shape[0], 3):
        raise InputError(f"rectangles {rect.shape} and loads {ld.shape}: expected (m, 4) "
                         "rows (x1, x2, y1, y2) and (m, 3) rows (p, qx, qy)")
    if np.any(pts[:, 2] < 0) or not np.all(np.isfinite(pts)):
        raise InputError("subsurface points: expected finite coordinates with depth z >= 0 m")
    _check(0.0, poisson)
    out = np.empty((pts.shape[0], 6))
    _point_kernel(pts[:, 0].copy(), pts[:, 1].copy(), pts[:, 2].copy(), rect[:, 0].copy(),
                  rect[:, 1].copy(), rect[:, 2].copy(), rect[:, 3].copy(), ld, float(poisson), out)
    return out


#: parity (in x, in y; +1 even, -1 odd) of the kernel of each load and component
PARITY = np.array([[(1, 1), (1, 1), (1, 1), (-1, -1), (-1, 1), (1, -1)],      # p
                   [(-1, 1), (-1, 1), (-1, 1), (1, -1), (1, 1), (-1, -1)],    # q_x
                   [(1, -1), (1, -1), (1, -1), (-1, 1), (-1, -1), (1, 1)]])   # q_y


@njit(cache=True, nogil=True)
def _quadrant_kernel(mx, my, dx, dy, z, nu):
    """The element kernels K[load, comp, a, b] at the non-negative offsets a < mx,
    b < my only (the others follow from :data:`PARITY`): corners at
    ((i - 1/2) dx, (j - 1/2) dy), i <= mx, j <= my, a quarter of the full set."""
    C = np.empty((mx + 1, my + 1, 3, 6))
    tmp = np.empty((3, 6))
    for i in range(mx + 1):
        u = (i - 0.5) * dx
        for j in range(my + 1):
            _corner(u, (j - 0.5) * dy, z, nu, tmp)
            C[i, j] = tmp
    K = np.empty((3, 6, mx, my))
    s = 1.0 / (2.0 * math.pi)
    for ld in range(3):
        for c in range(6):
            for a in range(mx):
                for b in range(my):
                    K[ld, c, a, b] = s * (C[a + 1, b + 1, ld, c] - C[a, b + 1, ld, c]
                                          - C[a + 1, b, ld, c] + C[a, b, ld, c])
    return K


def _mirrored_spectra(Kq, N1, N2):
    """Real spectra T (18, N1, N2 // 2 + 1) of the kernels Kq (18, mx, my), given at
    the non-negative offsets and mirrored with :data:`PARITY` on the N1 x N2
    periodic grid (N1, N2 even; zero beyond the offsets given): per axis a DCT-I of
    the offsets 0..N/2 (even) or a DST-I of 1..N/2 - 1 (odd, whose DFT is -i times
    it; the factor is left to the caller), the rows past N1/2 mirrored."""
    n, mx, my = Kq.shape
    px, py = PARITY[..., 0].ravel(), PARITY[..., 1].ravel()
    h1, h2 = N1 // 2, N2 // 2
    # along y
    Y = np.zeros((n, mx, h2 + 1))
    ev, od = np.flatnonzero(py > 0), np.flatnonzero(py < 0)
    A = np.zeros((ev.size, mx, h2 + 1))
    A[:, :, :my] = Kq[ev]
    Y[ev] = fft.dct(A, type=1, axis=2)
    B = np.zeros((od.size, mx, h2 - 1))
    B[:, :, :my - 1] = Kq[od, :, 1:]
    Y[od, :, 1:h2] = fft.dst(B, type=1, axis=2)
    # along x
    T = np.empty((n, N1, h2 + 1))
    ev, od = np.flatnonzero(px > 0), np.flatnonzero(px < 0)
    A = np.zeros((ev.size, h1 + 1, h2 + 1))
    A[:, :mx] = Y[ev]
    X = fft.dct(A, type=1, axis=1)
    T[ev, :h1 + 1] = X
    T[ev, h1 + 1:] = X[:, h1 - 1:0:-1]
    B = np.zeros((od.size, h1 - 1, h2 + 1))
    B[:, :mx - 1] = Y[od, 1:]
    X = fft.dst(B, type=1, axis=1)
    T[od, 0] = 0.0
    T[od, h1] = 0.0
    T[od, 1:h1] = X
    T[od, h1 + 1:] = -X[:, ::-1]
    return T


class DepthOperator:
    """The stress tensor at one depth on an mx x my grid from (p, q_x, q_y), by
    zero-padded real FFTs: the loads' spectra (computed once for all depths, see
    :meth:`load_spectra`) times the 18 kernel spectra, summed per component in the
    frequency domain, then one inverse transform per component (6 per depth).

    The kernels are even or odd in each offset (:data:`PARITY`), so they are
    evaluated at the non-negative offsets only and their spectra, real or imaginary,
    are DCT-I / DST-I of that quarter (no full-size FFT of a kernel)."""

    def __init__(self, mx, my, dx, dy, depth, poisson):
        self.mx, self.my = mx, my
        # even sizes (the cosine/sine transforms of the mirrored kernels need them)
        N1 = 2 * fft.next_fast_len(mx, real=True)
        N2 = 2 * fft.next_fast_len(my, real=True)
        self.shape = (N1, N2)
        Kq = _quadrant_kernel(int(mx), int(my), float(dx), float(dy), float(depth),
                              float(poisson))
        #: real spectra T (3, 6, N1, N2 // 2 + 1); the kernel's spectrum is factor * T
        self.spectra = _mirrored_spectra(Kq.reshape(18, mx, my), N1, N2).reshape(
            3, 6, N1, N2 // 2 + 1)
        #: (-i)^(number of odd axes) per kernel: 1, -i or -1
        self.factor = (-1j) ** ((PARITY[..., 0] < 0).astype(int) + (PARITY[..., 1] < 0))

    @property
    def nbytes(self) -> int:
        return self.spectra.nbytes

    def load_spectra(self, loads: np.ndarray) -> np.ndarray:
        """Spectra (3, N1, N2 // 2 + 1) of the loads (3, mx, my) [Pa]."""
        return fft.rfft2(loads, s=self.shape, axes=(-2, -1))

    def __call__(self, spectra: np.ndarray, active=(True, True, True)) -> np.ndarray:
        """Stresses (6, mx, my) [Pa] from the loads' spectra; ``active`` skips loads
        that are zero everywhere."""
        lds = [ld for ld in range(3) if active[ld]]
        if not lds:
            return np.zeros((6, self.mx, self.my))
        acc = _combine(self.spectra, self.factor, spectra, np.array(active, dtype=np.bool_))
        return fft.irfft2(acc, s=self.shape, axes=(-2, -1))[:, :self.mx, :self.my]


@njit(cache=True, nogil=True)
def _combine(T, factor, L, active):
    """acc[c] = sum over the active loads ld of factor[ld, c] T[ld, c] L[ld]."""
    n1, n2 = L.shape[1], L.shape[2]
    acc = np.zeros((6, n1, n2), dtype=np.complex128)
    for ld in range(3):
        if not active[ld]:
            continue
        for c in range(6):
            f = factor[ld, c]
            for i in range(n1):
                for j in range(n2):
                    acc[c, i, j] += (f * T[ld, c, i, j]) * L[ld, i, j]
    return acc


class _Cache:
    """Depth operators by (grid, depth, Poisson's ratio), least recently used first
    out, within a memory budget (a fine grid's operators are large)."""

    def __init__(self, budget_bytes: int = 256 * 2 ** 20):
        from collections import OrderedDict
        self.budget = budget_bytes
        self.items = OrderedDict()
        self.size = 0

    def get(self, key):
        op = self.items.get(key)
        if op is not None:
            self.items.move_to_end(key)
            return op
        op = DepthOperator(*key)
        self.items[key] = op
        self.size += op.nbytes
        while self.size > self.budget and len(self.items) > 1:
            _, old = self.items.popitem(last=False)
            self.size -= old.nbytes
        return op

    def clear(self):
        self.items.clear()
        self.size = 0


_CACHE = _Cache()


def depth_operator(mx: int, my: int, dx: float, dy: float, depth: float,
                   poisson: float) -> DepthOperator:
    """The :class:`DepthOperator` of a grid, depth and Poisson's ratio, cached (patches
    on one grid, as a batch or a wear loop with a fixed element size has them, share
    it; at most 256 MiB of operators are kept)."""
    _check(depth, poisson)
    return _CACHE.get((int(mx), int(my), float(dx), float(dy), float(depth), float(poisson)))


def clear_cache() -> None:
    """Forget the cached depth operators."""
    _CACHE.clear()
