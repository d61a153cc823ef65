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

from ..core.errors import InputError, RailContactError

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

#: (load, component) pairs whose kernels are those of others (the potentials'
#: identities: sigma_zz of q_x is sigma_xz of p, sigma_zz of q_y sigma_yz of p,
#: sigma_xz of q_y sigma_yz of q_x): their spectra are shared, not transformed
DUPLICATES = (((1, 2), (0, 4)), ((2, 2), (0, 5)), ((2, 4), (1, 5)))
_UNIQUE = np.array([ld * 6 + c for ld in range(3) for c in range(6)
                    if (ld, c) not in {d for d, _ in DUPLICATES}])


def _static_tables():
    """(parities (2, 15) in x and y of the distinct kernels; per (load, component)
    the row of its spectrum among them (3, 6); the sign (+1, -1) and whether the
    factor is -i (3, 6) of FACTOR = sign * (1 or -i))."""
    par = PARITY.reshape(18, 2)[_UNIQUE].T.astype(float)
    src = np.arange(18)
    for (ld, c), (ld0, c0) in DUPLICATES:
        src[ld * 6 + c] = ld0 * 6 + c0
    slot = np.full(18, -1)
    slot[_UNIQUE] = np.arange(_UNIQUE.size)
    odd = (PARITY[..., 0] < 0).astype(int) + (PARITY[..., 1] < 0)
    return (np.ascontiguousarray(par), slot[src].reshape(3, 6),
            np.where(odd == 2, -1.0, 1.0), odd == 1)


_PAR, _SLOT, _SIGN, _IMAG = _static_tables()


@njit(cache=True, nogil=True)
def _corner_arguments(grid, z, buf):
    """buf[0] = rho and buf[1:] the arguments of the corner functions' transcendental
    parts at the element corners ((i - 1/2) dx, (j - 1/2) dy), i <= mx, j <= my, of
    depth z, stored [., j, i] (grid = (dx, dy, nu); buf (7, my + 1, mx + 1)): ln of
    buf[1] = v + rho, buf[2] = u + rho (in their cancellation-free forms for v < 0,
    u < 0), buf[3] = rho + z; atan2 of (buf[4], buf[5]) = (u v, z rho); atan of
    buf[6] = u v (rho - z) / (u^2 rho + z v^2).  No corner lies on u = 0 or v = 0."""
    dx, dy = grid[0], grid[1]
    z2 = z * z
    for j in range(buf.shape[1]):
        v = (j - 0.5) * dy
        v2 = v * v
        for i in range(buf.shape[2]):
            u = (i - 0.5) * dx
            u2 = u * u
            r = math.sqrt(u2 + v2 + z2)
            rpz = r + z
            buf[0, j, i] = r
            buf[1, j, i] = v + r if v >= 0.0 else (u2 + z2) / (r - v)
            buf[2, j, i] = u + r if u >= 0.0 else (v2 + z2) / (r - u)
            buf[3, j, i] = rpz
            buf[4, j, i] = u * v
            buf[5, j, i] = z * r
            buf[6, j, i] = u * v * ((u2 + v2) / rpz) / (u2 * r + z * v2)


def _corner_transcendentals(grid, z, buf):
    """:func:`_corner_arguments` and their logarithms and arctangents by NumPy's
    vectorised (SIMD) functions, in place: buf[1:4] the logarithms, buf[4] atan2,
    buf[6] atan."""
    _corner_arguments(grid, z, buf)
    np.log(buf[1:4], out=buf[1:4])
    np.arctan2(buf[4], buf[5], out=buf[4])
    np.arctan(buf[6], out=buf[6])


@njit(cache=True, nogil=True)
def _unique_kernels(grid, z, buf, C, K):
    """K[u, b, a] (15, >= my, mx; stored y offset first): the distinct element
    kernels (:data:`_UNIQUE`) at the non-negative offsets (a, b) of one depth z, from
    the corner functions of :func:`_corner` with their transcendental parts
    precomputed in buf (:func:`_corner_transcendentals`); grid = (dx, dy, nu);
    C (15, my + 1, mx + 1) work space.  K[:, my:] is left as it is."""
    dx, dy, nu = grid[0], grid[1], grid[2]
    n2, n1 = buf.shape[1], buf.shape[2]
    mx, my = n1 - 1, n2 - 1
    a = 1.0 - 2.0 * nu
    z2 = z * z
    for j in range(n2):
        v = (j - 0.5) * dy
        v2 = v * v
        for i in range(n1):
            u = (i - 0.5) * dx
            u2 = u * u
            r = buf[0, j, i]
            ix, iy, lxy = buf[1, j, i], buf[2, j, i], buf[3, j, i]
            iz = -buf[4, j, i]
            lxx = buf[6, j, i]
            ixy = 1.0 / r
            ixx = u / (r * (v + r)) if v >= 0.0 else u * (r - v) / (r * (u2 + z2))
            iyy = v / (r * (u + r)) if u >= 0.0 else v * (r - u) / (r * (v2 + z2))
            # u, v != 0 at the corners: these are 0 at z = 0 as they should
            ixz = -z * v / ((u2 + z2) * r)
            iyz = -z * u / ((v2 + z2) * r)
            zizz = z * u * v * (r * r + z2) / (r * (u2 + z2) * (v2 + z2))
            lyy = -iz - lxx
            rpz = r + z
            lxxy = u / (r * rpz)
            lxyy = v / (r * rpz)
            lxxx = -lxyy - ixz
            lyyy = -lxxy - iyz
            oxxy = -u / rpz
            oxyy = -v / rpz
            oxxx = -ix - oxyy
            oyyy = -iy - oxxy
            # pressure: xx, yy, zz, xy, xz, yz
            C[0, j, i] = 2.0 * nu * iz - z * ixx - a * lxx
            C[1, j, i] = 2.0 * nu * iz - z * iyy - a * lyy
            C[2, j, i] = iz - zizz
            C[3, j, i] = -a * lxy - z * ixy
            C[4, j, i] = -z * ixz
            C[5, j, i] = -z * iyz
            # traction x: xx, yy, xy, xz, yz (zz = p's xz)
            C[6, j, i] = 2.0 * (1.0 + nu) * ix + 2.0 * nu * oxxx - z * lxxx
            C[7, j, i] = 2.0 * nu * (oxyy + ix) - z * lxyy
            C[8, j, i] = iy + 2.0 * nu * oxxy - z * lxxy
            C[9, j, i] = iz - z * ixx
            C[10, j, i] = -z * ixy
            # traction y: xx, yy, xy, yz (zz = p's yz, xz = q_x's yz)
            C[11, j, i] = 2.0 * nu * (oxxy + iy) - z * lxxy
            C[12, j, i] = 2.0 * (1.0 + nu) * iy + 2.0 * nu * oyyy - z * lyyy
            C[13, j, i] = ix + 2.0 * nu * oxyy - z * lxyy
            C[14, j, i] = iz - z * iyy
    s = 1.0 / (2.0 * math.pi)
    for q in range(15):
        for j in range(my):
            for i in range(mx):
                K[q, j, i] = s * (C[q, j + 1, i + 1] - C[q, j + 1, i] - C[q, j, i + 1]
                                  + C[q, j, i])


@njit(cache=True, nogil=True)
def _trig(M):
    """(sin, cos) of pi j / M, j < M."""
    t = np.empty((2, M))
    for j in range(M):
        t[0, j] = math.sin(math.pi * j / M)
        t[1, j] = math.cos(math.pi * j / M)
    return t


@njit(cache=True, nogil=True)
def _half_pre(x, even, sn, y):
    """y[j, q], j < M: the half-length sequences of :func:`_spectra`'s reduction of
    the sequences x[0 .. M, q] (x[M] the middle value) of period 2 M (sn: sin(pi j /
    M))."""
    M, nq = y.shape
    for j in range(M):
        w = sn[j]
        for q in range(nq):
            s = x[j, q] + x[M - j, q]
            d = x[j, q] - x[M - j, q]
            y[j, q] = 0.5 * s - w * d if even else w * s + 0.5 * d


@njit(cache=True, nogil=True)
def _half_post(x, even, cs, Y, out):
    """out[k, q], k = 0 .. M: the real spectra of the sequences x[0 .. M, q] from the
    DFT Y (along the first axis) of their half-length sequences (:func:`_half_pre`;
    cs: cos(pi j / M))."""
    M = cs.size
    nq = x.shape[1]
    for m in range(M // 2 + 1):
        for q in range(nq):
            out[2 * m, q] = 2.0 * Y[m, q].real if even else -2.0 * Y[m, q].imag
    if even:
        for q in range(nq):
            out[1, q] = x[0, q] - x[M, q]
        for j in range(1, M):
            w = 2.0 * cs[j]
            for q in range(nq):
                out[1, q] += w * x[j, q]
    else:
        for q in range(nq):
            out[1, q] = Y[0, q].real
    for m in range(1, (M - 1) // 2 + 1):
        for q in range(nq):
            if even:
                out[2 * m + 1, q] = out[2 * m - 1, q] - 2.0 * Y[m, q].imag
            else:
                out[2 * m + 1, q] = out[2 * m - 1, q] + 2.0 * Y[m, q].real


@njit(cache=True, nogil=True)
def _spectra(K, par, shape, S):
    """S[u] (N1 // 2 + 1, N2 // 2 + 1): the real spectra of the distinct kernels
    K[u] (15, N2 // 2 + 1, mx: the non-negative offsets, y first, zero from my on) on
    the padded grid (N1, N2 even) at the wave numbers r <= N1 / 2 (those above are
    par[0, u] times S[u, N1 - r]).

    Along y the columns a >= 0 are sequences of period N2 and parity par[1, u] (the
    columns a < 0 are par[0, u] times them), then along x the results are sequences
    of period N1 and parity par[0, u]; the DFT of the kernel is (-i)^(odd axes)
    times S.  The real spectrum of an even (DFT X, real) or odd (DFT -i R, R real)
    sequence of period 2 M takes one real FFT of length M instead of 2 M (the
    classical reduction of the DCT-I and DST-I to a half-length FFT, e.g. Press et
    al., Numerical Recipes, cosft1 and sinft): with s_j = x_j + x_{M-j},
    d_j = x_j - x_{M-j} and Y the DFT of

        even: y_j = s_j / 2 - sin(pi j / M) d_j   ->  X[2m] = 2 Re Y[m],
              X[2m + 1] = X[2m - 1] - 2 Im Y[m],  X[1] = x_0 - x_M + 2 sum x_j cos(pi j / M);
        odd:  y_j = sin(pi j / M) s_j + d_j / 2   ->  R[2m] = -2 Im Y[m],
              R[2m + 1] = R[2m - 1] + 2 Re Y[m],  R[1] = Re Y[0]

    (x_0 and x_M of an odd sequence drop out: they are zero).  The sequences of all
    15 kernels go through one batched FFT per direction, the pre- and
    post-processing vectorised across the sequences."""
    n, m2, mx = K.shape
    M1, M2 = shape[0] // 2, m2 - 1
    t1, t2 = _trig(M1), _trig(M2)
    y = np.empty((n, M2, mx))
    for u in range(n):
        _half_pre(K[u], par[1, u] > 0, t2[0], y[u])
    Y = np.fft.rfft(y, axis=1)
    R = np.empty((M2 + 1, mx))
    X = np.zeros((n, M1 + 1, M2 + 1))                  # zero from mx on
    for u in range(n):
        _half_post(K[u], par[1, u] > 0, t2[1], Y[u], R)
        for b in range(M2 + 1):
            for a in range(mx):
                X[u, a, b] = R[b, a]
    y2 = np.empty((n, M1, M2 + 1))
    for u in range(n):
        _half_pre(X[u], par[0, u] > 0, t1[0], y2[u])
    Y2 = np.fft.rfft(y2, axis=1)
    for u in range(n):
        _half_post(X[u], par[0, u] > 0, t1[1], Y2[u], S[u])


def padded_shape(mx: int, my: int) -> tuple:
    """The FFT sizes (N1, N2) >= (2 mx, 2 my) of the zero-padded convolution: even
    (twice a fast length), so that the kernels' spectra take half-length transforms
    (:func:`_spectra`)."""
    return (2 * fft.next_fast_len(mx, real=True), 2 * fft.next_fast_len(my, real=True))


class _Builder:
    """Work space of the kernel spectra of one grid (:meth:`spectra`)."""

    def __init__(self, mx, my, dx, dy, poisson):
        self.mx, self.my = int(mx), int(my)
        self.shape = padded_shape(self.mx, self.my)
        self.grid = np.array([float(dx), float(dy), float(poisson)])
        self.buf = np.empty((7, self.my + 1, self.mx + 1))
        self.C = np.empty((15, self.my + 1, self.mx + 1))
        self.K = np.zeros((15, self.shape[1] // 2 + 1, self.mx))     # zero from my on

    def spectra(self, z: float) -> np.ndarray:
        """The real spectra (15, N1 // 2 + 1, N2 // 2 + 1) of the distinct kernels at
        depth z: the corner functions' logarithms and arctangents by NumPy's
        vectorised functions, the kernels at the non-negative offsets (a quarter of
        the element corners) in compiled code, their spectra by half-length real
        FFTs (:func:`_spectra`)."""
        _corner_transcendentals(self.grid, z, self.buf)
        _unique_kernels(self.grid, z, self.buf, self.C, self.K)
        N1, N2 = self.shape
        S = _CACHE.array((15, N1 // 2 + 1, N2 // 2 + 1))
        _spectra(self.K, _PAR, self.shape, S)
        return S


def unique_spectra(mx, my, dx, dy, depths, poisson) -> list:
    """The real spectra (15, N1 // 2 + 1, N2 // 2 + 1) of the distinct stress kernels
    (:data:`_UNIQUE`; :data:`DUPLICATES` share theirs) of a grid, one array per depth,
    at the wave numbers r <= N1 / 2 along x (the others by parity: S[u, N1 - r] times
    :data:`PARITY`'s x parity of the kernel)."""
    zs = np.atleast_1d(np.asarray(depths, float))
    for z in zs:
        _check(z, poisson)
    b = _Builder(mx, my, dx, dy, poisson)
    return [b.spectra(float(z)) for z in zs]


def kernel_spectra(mx, my, dx, dy, depths, poisson) -> np.ndarray:
    """Real spectra (nz, 3, 6, N1, N2 // 2 + 1) of the stress kernels of a grid at the
    depths (the DFT on the :func:`padded_shape` grid is :data:`FACTOR` times them),
    from :func:`unique_spectra` (the duplicates copied, the wave numbers above
    N1 / 2 mirrored by parity)."""
    N1, _ = padded_shape(int(mx), int(my))
    S = np.stack(unique_spectra(mx, my, dx, dy, depths, poisson))
    r = np.arange(N1)
    src = np.where(r <= N1 // 2, r, N1 - r)
    full = S[:, :, src] * np.where(r <= N1 // 2, 1.0, _PAR[0][:, None])[None, :, :, None]
    return full[:, _SLOT]


#: per (load, component): the x parity of its kernel (PARITY[..., 0])
_PARX = PARITY[..., 0].astype(float)


@njit(cache=True, nogil=True)
def _depth_stresses(S, tables, L, shape, out):
    """out (6, mx, my) = the inverse real FFT of the sum over the active loads ld of
    FACTOR[ld, c] S[slot[ld, c]] L[ld] per component c (one depth; compiled,
    numpy.fft by rocket-fft); L (2, 3, N1, N2 // 2 + 1): the real and imaginary parts
    of the loads' spectra; S holds the wave numbers r <= N1 / 2 (those above: parx
    times S[N1 - r]); tables = (slot, sign, imag, active, parx) as float (3, 6) arrays
    (FACTOR = sign times 1, or times -i where imag).  The inverse transform along x
    first, then along y for the rows i < mx only (the output window)."""
    slot, sign, imag, active, parx = tables[0], tables[1], tables[2], tables[3], tables[4]
    n1, n2 = L.shape[2], L.shape[3]
    h = S.shape[1]
    mx, my = out.shape[1], out.shape[2]
    Lr, Li = L[0], L[1]
    acc = np.zeros((6, n1, n2), dtype=np.complex128)
    for c in range(6):
        for ld in range(3):
            if active[ld, c] == 0.0:
                continue
            T = S[int(slot[ld, c])]
            for i in range(n1):
                if i < h:
                    src, s = i, sign[ld, c]
                else:
                    src, s = n1 - i, sign[ld, c] * parx[ld, c]
                if imag[ld, c] == 0.0:          # factor s: s T L
                    for j in range(n2):
                        t = s * T[src, j]
                        acc[c, i, j] += complex(t * Lr[ld, i, j], t * Li[ld, i, j])
                else:                           # factor -i s: s T (Li - i Lr)
                    for j in range(n2):
                        t = s * T[src, j]
                        acc[c, i, j] += complex(t * Li[ld, i, j], -t * Lr[ld, i, j])
    Z = np.fft.ifft(acc, axis=1)
    r = np.fft.irfft(Z[:, :mx, :], n=shape[1], axis=2)
    for c in range(6):
        for i in range(mx):
            for j in range(my):
                out[c, i, j] = r[c, i, j]


class _Entry:
    """Spectra in the cache (:class:`_Cache`) and the leases held on them: once
    forgotten (``epoch``: the cache's epoch then, None while kept), the array goes
    back for reuse when its last lease is given back (``reuse``)."""

    __slots__ = ("spectra", "leases", "epoch", "reuse")

    def __init__(self, spectra):
        self.spectra = spectra
        self.leases = 0
        self.epoch = None
        self.reuse = False


class _SpectraLease:
    """The right to read the kernel spectra of one key of the cache, held for a
    ``with`` block: ``with _CACHE.lease(key, build) as S:`` gives the spectra
    (those kept, or new ones from ``build(key)``, put in the cache) and gives the
    lease back at the block's end, however it ends.  An array under a lease is
    never handed out for other spectra: the cache may forget the spectra
    meanwhile, but their array goes back for reuse only when the last lease on
    them is given back."""

    __slots__ = ("cache", "key", "build", "entry")

    def __init__(self, cache, key, build):
        self.cache, self.key, self.build = cache, key, build
        self.entry = None

    def __enter__(self) -> np.ndarray:
        if self.entry is not None:
            raise RailContactError("spectra lease entered twice: expected one with-block "
                                   "at a time per lease")
        self.entry = self.cache._acquire(self.key, self.build)
        return self.entry.spectra

    def __exit__(self, *exc) -> bool:
        entry, self.entry = self.entry, None
        self.cache._release(entry)
        return False


class _Cache:
    """Kernel spectra by (grid, depth, Poisson's ratio), least recently used first
    out, within a memory budget (a fine grid's spectra are large: 19 MB per depth on
    400 x 400 elements).  The arrays of forgotten spectra are kept for the next
    spectra of the same shape (up to a quarter of the budget): filling fresh memory
    costs more than building the spectra of a 40 x 40 grid (measured, docs/subsurface.md).
    Safe for threads: one lock around every change, and the spectra are read under
    a lease (:meth:`lease`): an array with a lease held on it is never handed out
    again until the last one is given back."""

    def __init__(self, budget_bytes: int = 256 * 2 ** 20):
        import threading
        from collections import OrderedDict
        self.budget = budget_bytes
        self.items = OrderedDict()          # key -> _Entry
        self.size = 0
        self.free = {}
        self.free_size = 0
        self.epoch = 0                      # + 1 at every clear(release=True)
        self.lock = threading.Lock()

    def lease(self, key, build) -> _SpectraLease:
        """A lease (:class:`_SpectraLease`, a context manager) on the spectra of key =
        (mx, my, dx, dy, depth, poisson): those kept, or ``build(key)``'s (built
        outside the lock) put in the cache."""
        return _SpectraLease(self, key, build)

    def _acquire(self, key, build) -> _Entry:
        """The entry of key with one lease more: the one kept (another thread's,
        where it put the key while this one built its spectra), or a new one."""
        S = None
        while True:
            with self.lock:
                entry = self.items.get(key)
                if entry is not None:
                    self.items.move_to_end(key)
                    entry.leases += 1
                    return entry
                if S is not None:
                    return self._put(key, S)
            S = build(key)

    def _put(self, key, S) -> _Entry:
        """Add the spectra of a key with one lease on them (the lock held); forget
        the least recently used ones beyond the budget (the newest is always kept)."""
        entry = _Entry(S)
        entry.leases = 1
        self.items[key] = entry
        self.size += S.nbytes
        while self.size > self.budget and len(self.items) > 1:
            _, old = self.items.popitem(last=False)
            self.size -= old.spectra.nbytes
            self._forget(old, True)
        return entry

    def _release(self, entry) -> None:
        """Give a lease back: the array of forgotten spectra goes back for reuse
        with the last lease (unless the reusable arrays were released since)."""
        with self.lock:
            entry.leases -= 1
            if entry.leases == 0 and entry.epoch is not None:
                if entry.reuse and entry.epoch == self.epoch:
                    self._recycle(entry.spectra)
                entry.reuse = False

    def _forget(self, entry, reuse: bool) -> None:
        """Spectra out of the cache (the lock held): their array kept for reuse
        (``reuse``) now, or when the last lease on it is given back."""
        entry.epoch, entry.reuse = self.epoch, reuse
        if entry.leases == 0 and reuse:
            self._recycle(entry.spectra)
            entry.reuse = False

    def array(self, shape) -> np.ndarray:
        """An array of this shape for new spectra: a forgotten one, or a new one."""
        with self.lock:
            pool = self.free.get(shape)
            if pool:
                S = pool.pop()
                self.free_size -= S.nbytes
                return S
        return np.empty(shape)

    def _recycle(self, S) -> None:
        """Keep the array of forgotten spectra, under no lease, for reuse (the lock
        held), within a quarter of the budget."""
        if self.free_size + S.nbytes <= self.budget // 4:
            self.free.setdefault(S.shape, []).append(S)
            self.free_size += S.nbytes

    def clear(self, release: bool = False):
        """Forget the spectra (their arrays kept for reuse unless ``release``; those
        under a lease when their last lease is given back)."""
        with self.lock:
            if release:
                self.epoch += 1
            while self.items:
                _, entry = self.items.popitem()
                self._forget(entry, not release)
            self.size = 0
            if release:
                self.free.clear()
                self.free_size = 0


_CACHE = _Cache()


def convolve_depths(loads, dx, dy, depths, poisson) -> np.ndarray:
    """Stresses (6, mx, my, nz) [Pa] at the element centres of a uniform grid and the
    depths from piecewise constant loads (3, mx, my) = (p, q_x, q_y) [Pa] (a view of
    a depth-major array): the loads' 3 spectra, per depth the sum of their products with the kernel spectra (the 15
    distinct ones; cached per grid, depth and Poisson's ratio, at most 256 MiB kept;
    built where missing, right before their use) and the inverse transforms of the 6
    components."""
    loads = np.asarray(loads, float)
    _, mx, my = loads.shape
    zs = np.atleast_1d(np.asarray(depths, float))
    for z in zs:
        _check(z, poisson)
    N1, N2 = padded_shape(mx, my)
    active = np.array([bool(np.any(v)) for v in loads], dtype=np.bool_)
    if not active.any():
        return np.zeros((6, mx, my, zs.size))
    spec = fft.rfft2(loads, s=(N1, N2), axes=(-2, -1))
    L = np.stack([spec.real, spec.imag])
    tables = np.stack([_SLOT.astype(float), _SIGN, _IMAG.astype(float),
                       np.repeat(active[:, None].astype(float), 6, axis=1), _PARX])
    out = np.empty((zs.size, 6, mx, my))        # depth first: each depth's block contiguous
    builder = []

    def build(key):
        if not builder:
            builder.append(_Builder(mx, my, dx, dy, poisson))
        return builder[0].spectra(key[4])
    for k, z in enumerate(zs):
        key = (int(mx), int(my), float(dx), float(dy), float(z), float(poisson))
        with _CACHE.lease(key, build) as S:
            _depth_stresses(S, tables, L, (N1, N2), out[k])
    return out.transpose(1, 2, 3, 0)


def clear_cache(release: bool = False) -> None:
    """Forget the cached kernel spectra (``release``: their memory too; otherwise the
    arrays are reused for the next spectra of the same shape)."""
    _CACHE.clear(release)
