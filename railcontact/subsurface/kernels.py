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
    C[L_xx] = atan(u v (rho - z) / (u^2 rho + z v^2)),  C[L_yy] = -C[I_z] - C[L_xx]
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

from ..core.errors import InputError

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
    lyy = -iz - lxx                  # L_xx + L_yy = -L_zz = -I_z
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
#: the DFT of a kernel is FACTOR times its real spectrum: (-i)^(number of odd axes)
FACTOR = (-1j) ** ((PARITY[..., 0] < 0).astype(int) + (PARITY[..., 1] < 0))


@njit(cache=True, nogil=True)
def _quadrant_kernels(mx, my, dx, dy, zs, nu):
    """The element kernels K[depth, load, comp, a, b] at the non-negative offsets
    a < mx, b < my only (the others follow from :data:`PARITY`): corners at
    ((i - 1/2) dx, (j - 1/2) dy), i <= mx, j <= my, a quarter of the full set."""
    C = np.empty((mx + 1, my + 1, 3, 6))
    K = np.empty((zs.size, 3, 6, mx, my))
    s = 1.0 / (2.0 * math.pi)
    for k in range(zs.size):
        for i in range(mx + 1):
            u = (i - 0.5) * dx
            for j in range(my + 1):
                _corner(u, (j - 0.5) * dy, zs[k], nu, C[i, j])
        for ld in range(3):
            for c in range(6):
                for a in range(mx):
                    for b in range(my):
                        K[k, ld, c, a, b] = s * (C[a + 1, b + 1, ld, c] - C[a, b + 1, ld, c]
                                                 - C[a + 1, b, ld, c] + C[a, b, ld, c])
    return K


#: (load, component) pairs whose kernels are those of others (the potentials'
#: identities: sigma_zz of q_x is sigma_xz of p, sigma_zz of q_y sigma_yz of p,
#: sigma_xz of q_y sigma_yz of q_x): their spectra are copied, not transformed
DUPLICATES = (((1, 2), (0, 4)), ((2, 2), (0, 5)), ((2, 4), (1, 5)))
_UNIQUE = np.array([ld * 6 + c for ld in range(3) for c in range(6)
                    if (ld, c) not in {d for d, _ in DUPLICATES}])


def _static_tables():
    """Parities of the distinct kernels and, per kernel, the row of its original
    among them (:func:`_spectra_depth`'s tables)."""
    par = PARITY.reshape(18, 2)[_UNIQUE].astype(float)
    src = np.arange(18)
    for (ld, c), (ld0, c0) in DUPLICATES:
        src[ld * 6 + c] = ld0 * 6 + c0
    slot = np.full(18, -1)
    slot[_UNIQUE] = np.arange(_UNIQUE.size)
    return par[:, 0].copy(), par[:, 1].copy(), slot[src]


_PX, _PY, _SLOT = _static_tables()


@njit(cache=True, nogil=True)
def _spectra_depth(Kq, unique, px, py, slot, N1, N2, T):
    """T[i] (N1, N2 // 2 + 1): the real spectrum of kernel i of one depth, from the
    kernels Kq (18, mx, my) at the non-negative offsets.  Per distinct kernel u
    (``unique``): its rows a >= 0 mirrored along y with the parity py[u] on N2 points
    and transformed (real FFT; the rows a < 0 are px[u] times them), the real or
    imaginary part ((-i)^odd_y R) mirrored along x on N1 points and transformed
    again, whose real or imaginary part ((-i)^odd_x T) gives the wave numbers up to
    N1 / 2 and, mirrored with px[u], the others.  Kernels that are copies of others
    (``slot[i]``: the row of their original in ``unique``) are copied."""
    n, mx, my = Kq.shape
    m2 = N2 // 2 + 1
    h = N1 // 2 + 1
    rows = np.zeros((mx, N2))
    cols = np.zeros((N1, m2))
    spec = np.empty((unique.size, N1, m2))
    for u in range(unique.size):
        kk = unique[u]
        rows[:, :] = 0.0
        for a in range(mx):
            for b in range(my):
                v = Kq[kk, a, b]
                rows[a, b] = v
                if b > 0:
                    rows[a, N2 - b] = py[u] * v
        Y = np.fft.rfft(rows, axis=1)
        cols[:, :] = 0.0
        for a in range(mx):
            for b in range(m2):
                v = Y[a, b].real if py[u] > 0 else -Y[a, b].imag
                cols[a, b] = v
                if a > 0:
                    cols[N1 - a, b] = px[u] * v
        X = np.fft.rfft(cols, axis=0)
        for r in range(N1):
            src = r if r < h else N1 - r
            sgn = 1.0 if r < h else px[u]
            for b in range(m2):
                d = X[src, b]
                spec[u, r, b] = sgn * (d.real if px[u] > 0 else -d.imag)
    for i in range(n):
        T[i] = spec[slot[i]]


def padded_shape(mx: int, my: int) -> tuple:
    """The FFT sizes (N1, N2) >= (2 mx - 1, 2 my - 1) of the zero-padded convolution."""
    return (fft.next_fast_len(2 * mx - 1, real=True), fft.next_fast_len(2 * my - 1, real=True))


def kernel_spectra(mx, my, dx, dy, depths, poisson) -> np.ndarray:
    """Real spectra (nz, 3, 6, N1, N2 // 2 + 1) of the stress kernels of a grid at the
    depths (the DFT on the :func:`padded_shape` grid is :data:`FACTOR` times them),
    the kernels evaluated at the non-negative offsets (a quarter of the element
    corners), the 15 distinct ones (:data:`DUPLICATES`) transformed along y for the
    rows of non-negative offsets only, mirrored by parity, then along x by real
    transforms (half the work of a full real 2-D FFT per kernel)."""
    zs = np.ascontiguousarray(np.atleast_1d(np.asarray(depths, float)))
    for z in zs:
        _check(z, poisson)
    N1, N2 = padded_shape(mx, my)
    nz = zs.size
    T = np.empty((nz, 18, N1, N2 // 2 + 1))
    for k in range(nz):          # depth by depth: a fine grid's kernels are large
        Kq = _quadrant_kernels(int(mx), int(my), float(dx), float(dy), zs[k:k + 1],
                               float(poisson))
        _spectra_depth(Kq.reshape(18, mx, my), _UNIQUE, _PX, _PY, _SLOT, N1, N2, T[k])
    return T.reshape(nz, 3, 6, N1, N2 // 2 + 1)


@njit(cache=True, nogil=True)
def _depth_stresses(T, factor, L, active, shape, out, k):
    """out[c, :, :, k] = the inverse real FFT of the sum over the active loads ld of
    factor[ld, c] T[ld, c] L[ld] (one depth; compiled, numpy.fft by rocket-fft)."""
    n1, n2 = L.shape[1], L.shape[2]
    mx, my = out.shape[1], out.shape[2]
    acc = np.empty((n1, n2), dtype=np.complex128)
    for c in range(6):
        acc[:, :] = 0.0
        for ld in range(3):
            if not active[ld]:
                continue
            f = factor[ld, c]
            for i in range(n1):
                for j in range(n2):
                    acc[i, j] += (f * T[ld, c, i, j]) * L[ld, i, j]
        r = np.fft.irfft2(acc, s=shape)
        for i in range(mx):
            for j in range(my):
                out[c, i, j, k] = r[i, j]


class _Cache:
    """Kernel spectra by (grid, depth, Poisson's ratio), least recently used first
    out, within a memory budget (a fine grid's spectra are large: 46 MB per depth on
    400 x 400 elements)."""

    def __init__(self, budget_bytes: int = 256 * 2 ** 20):
        from collections import OrderedDict
        self.budget = budget_bytes
        self.items = OrderedDict()
        self.size = 0

    def get(self, mx, my, dx, dy, depth, poisson) -> np.ndarray:
        """The spectra (3, 6, N1, N2 // 2 + 1) of one depth, built when missing; the
        least recently used ones beyond the budget forgotten (the one returned kept)."""
        key = (mx, my, dx, dy, float(depth), poisson)
        T = self.items.get(key)
        if T is not None:
            self.items.move_to_end(key)
            return T
        T = kernel_spectra(mx, my, dx, dy, [key[4]], poisson)[0]
        self.items[key] = T
        self.size += T.nbytes
        while self.size > self.budget and len(self.items) > 1:
            _, old = self.items.popitem(last=False)
            self.size -= old.nbytes
        return T

    def clear(self):
        self.items.clear()
        self.size = 0


_CACHE = _Cache()


def convolve_depths(loads, dx, dy, depths, poisson) -> np.ndarray:
    """Stresses (6, mx, my, nz) [Pa] at the element centres of a uniform grid and the
    depths from piecewise constant loads (3, mx, my) = (p, q_x, q_y) [Pa]: the loads'
    3 spectra, per depth the sum of their products with the 18 kernel spectra (cached
    per grid, depth and Poisson's ratio; at most 256 MiB kept) and the inverse
    transforms of the 6 components."""
    loads = np.asarray(loads, float)
    _, mx, my = loads.shape
    zs = np.atleast_1d(np.asarray(depths, float))
    key = (int(mx), int(my), float(dx), float(dy))
    for z in zs:
        _check(z, poisson)
    N1, N2 = padded_shape(mx, my)
    active = np.array([bool(np.any(v)) for v in loads], dtype=np.bool_)
    if not active.any():
        return np.zeros((6, mx, my, zs.size))
    L = fft.rfft2(loads, s=(N1, N2), axes=(-2, -1))
    out = np.empty((6, mx, my, zs.size))
    for k, z in enumerate(zs):
        T = _CACHE.get(*key, float(z), float(poisson))
        _depth_stresses(T, FACTOR, L, active, (N1, N2), out, k)
    return out


def clear_cache() -> None:
    """Forget the cached kernel spectra."""
    _CACHE.clear()
