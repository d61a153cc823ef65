"""Stresses and surface displacement of eigenstrains (plastic strains) in a half-space.

A volume grid of mx x my x nz equal cuboids (cells dx x dy x dz) lies below the
surface z = 0 of the half-space z >= 0; each cell carries a uniform eigenstrain
eps* (six components xx, yy, zz, xy, xz, yz; tensor shears, not engineering).
The residual stress and the normal displacement of the surface that they cause are
found as in the semi-analytical method of Jacq, Nelias, Lormand & Girodin (J.
Tribol. 124, 2002), with the decomposition of Chiu (J. Appl. Mech. 45, 1978) and
Liu & Wang (J. Tribol. 127, 2005):

1. **Infinite space** (Mura, *Micromechanics of Defects in Solids*, 1987, eq.
   11.30).  The displacement gradient of an eigenstrain eps* in a region Omega is

       u_i,j = [psi_,ijkl eps*_kl - 2 nu phi_,ij eps*_mm
                - 4 (1 - nu) phi_,jl eps*_il] / (8 pi (1 - nu)),

   with the potentials phi = int_Omega 1/R dV' and psi = int_Omega R dV'.  For a
   cuboid the second derivatives of phi and fourth of psi are sums over its eight
   corners (signs alternating) of closed-form *corner functions* of the offsets
   (X, Y, Z) from the corner (R^2 = X^2 + Y^2 + Z^2, L_c = ln(R + c)):

       phi_,aa: -atan(b c / (a R))        phi_,ab: L_c
       psi_,aaab: L_c + a^2 / (R (R + c)) psi_,aabb: a b / (R (R + c))
       psi_,aabc: a / R                  psi_,aaaa = 2 phi_,aa - psi_,aabb - psi_,aacc

   ({a, b, c} a permutation of {X, Y, Z}; the last from lap R = 2 / R).  Targets
   are the cell centres, so no corner offset is zero.  Stresses follow by Hooke's
   law from the strain minus the eigenstrain in the cell itself.
2. **Mirror image**: the eigenstrain mirrored about z = 0 (eps*_xz, eps*_yz
   change sign) in the infinite space makes the shear stresses on z = 0 and the
   normal displacement there vanish (the field is symmetric).
3. **Free surface**: the normal stress sigma_zz(0) that remains is removed by
   the surface pressure p = sigma_zz(0) of Boussinesq
   (:func:`~railcontact.subsurface.kernels.convolve_depths` for its stresses, the
   influence of :mod:`railcontact.normal.influence` for its displacement): the
   surface normal displacement of the eigenstrains is that of p alone.

Convolutions: the cuboid kernels depend on the offsets between cells (in z on
z - z' for the body, z + z' for its image: one lattice of 2 nz layers, image and
body), so the infinite-space part is one zero-padded 3-D real FFT convolution
(2 mx x 2 my x 4 nz) of the six eigenstrain components with 21 kernel spectra,
built once per grid.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import fft

from ..core.errors import InputError
from ..normal.influence import normal_operator
from .kernels import COMPONENTS, convolve_depths

#: the fourth derivatives of psi held (sorted index strings); the others by symmetry
_PSI = ("xxxx", "yyyy", "zzzz", "xxxy", "xyyy", "xxyy", "xxxz", "xzzz", "xxzz",
        "yyyz", "yzzz", "yyzz", "xxyz", "xyyz", "xyzz")
_PHI = ("xx", "yy", "zz", "xy", "xz", "yz")
#: the surface target lies this fraction of dz below z = 0 (inside the top layer;
#: sigma_zz is continuous across the face)
_ETA = 1e-9


def _corner_functions(X, Y, Z):
    """The 6 + 15 corner functions of phi_,ij and psi_,ijkl (:data:`_PHI`,
    :data:`_PSI`; psi_,aaaa left zero here: from the trace after the corner sums)
    at offsets X, Y, Z (arrays, broadcast), none zero."""
    R = np.sqrt(X * X + Y * Y + Z * Z)

    def r_plus(c, a, b):                      # R + c without cancellation for c < 0
        return np.where(c >= 0, R + c, (a * a + b * b) / (R - c))

    RX, RY, RZ = r_plus(X, Y, Z), r_plus(Y, X, Z), r_plus(Z, X, Y)
    LX, LY, LZ = np.log(RX), np.log(RY), np.log(RZ)
    phi = {"xx": -np.arctan(Y * Z / (X * R)), "yy": -np.arctan(X * Z / (Y * R)),
           "zz": -np.arctan(X * Y / (Z * R)), "xy": LZ, "xz": LY, "yz": LX}
    zero = np.zeros(np.broadcast(X, Y, Z).shape)
    psi = {"xxxx": zero, "yyyy": zero, "zzzz": zero,
           "xxxy": LZ + X * X / (R * RZ), "xyyy": LZ + Y * Y / (R * RZ), "xxyy": X * Y / (R * RZ),
           "xxxz": LY + X * X / (R * RY), "xzzz": LY + Z * Z / (R * RY), "xxzz": X * Z / (R * RY),
           "yyyz": LX + Y * Y / (R * RX), "yzzz": LX + Z * Z / (R * RX), "yyzz": Y * Z / (R * RX),
           "xxyz": X / R, "xyyz": Y / R, "xyzz": Z / R}
    return phi, psi


def _box_sums(G):
    """Alternating corner sums of a corner function sampled at the half-integer
    lattice points: G(o + 1/2) - G(o - 1/2) along each of the three axes."""
    return np.diff(np.diff(np.diff(G, axis=0), axis=1), axis=2)


def _trace_fill(phi, psi):
    """psi_,aaaa = 2 phi_,aa - psi_,aabb - psi_,aacc (lap R = 2 / R)."""
    psi["xxxx"] = 2.0 * phi["xx"] - psi["xxyy"] - psi["xxzz"]
    psi["yyyy"] = 2.0 * phi["yy"] - psi["xxyy"] - psi["yyzz"]
    psi["zzzz"] = 2.0 * phi["zz"] - psi["xxzz"] - psi["yyzz"]


def _key(*idx) -> str:
    return "".join(sorted(idx))


def cuboid_potentials(offsets_x, offsets_y, offsets_z, dx, dy, dz):
    """phi_,ij and psi_,ijkl (integrals over the cell, dimensionless and in m^-1 ...)
    of one cell dx x dy x dz centred at the origin, at the targets offsets_x x
    offsets_y x offsets_z [m] (1-D arrays of increasing offsets spaced by the cell
    size): dicts keyed by
    :data:`_PHI` and :data:`_PSI`, arrays of shape (nx, ny, nz)."""
    hx = np.concatenate([offsets_x - 0.5 * dx, offsets_x[-1:] + 0.5 * dx])
    hy = np.concatenate([offsets_y - 0.5 * dy, offsets_y[-1:] + 0.5 * dy])
    hz = np.concatenate([offsets_z - 0.5 * dz, offsets_z[-1:] + 0.5 * dz])
    X, Y, Z = np.meshgrid(hx, hy, hz, indexing="ij", sparse=True)
    phi, psi = _corner_functions(X, Y, Z)
    # the cell [-d/2, d/2] seen from offset o: int f(X) dX over [o - d/2, o + d/2]
    phi = {k: _box_sums(v) for k, v in phi.items()}
    psi = {k: _box_sums(v) for k, v in psi.items()}
    _trace_fill(phi, psi)
    return phi, psi


def _strains(phi, psi, E, nu):
    """Strains (6 arrays) of eigenstrains E (dict of the 6 components, tensor shears)
    from the potentials' (spectra or values) phi, psi, by Mura's formula."""
    c = 1.0 / (8.0 * math.pi * (1.0 - nu))
    full = {}
    for a in "xyz":
        for b in "xyz":
            full[a + b] = E[_key(a, b)]
    T = E["xx"] + E["yy"] + E["zz"]
    out = {}
    for ij in _PHI:
        i, j = ij
        s = -2.0 * nu * phi[ij] * T
        for k in "xyz":
            for m in "xyz":
                s = s + psi[_key(i, j, k, m)] * full[k + m]
            s = s - 2.0 * (1.0 - nu) * (phi[_key(j, k)] * full[i + k]
                                        + phi[_key(i, k)] * full[j + k])
        out[ij] = c * s
    return out


def hooke(strain, E_mod, nu):
    """Stress (6, ...) [Pa] of strains (6, ...) (tensor shears) by Hooke's law."""
    lam = E_mod * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    mu = 0.5 * E_mod / (1.0 + nu)
    tr = strain[0] + strain[1] + strain[2]
    s = 2.0 * mu * strain
    s[:3] += lam * tr
    return s


@dataclass(frozen=True)
class VolumeGrid:
    """The cells of the plastic zone: centres x (mx), y (my) [m] of the surface grid
    and depths z = (k + 1/2) dz, k = 0 .. nz - 1 [m]."""

    x: np.ndarray
    y: np.ndarray
    dz: float
    nz: int

    @property
    def z(self) -> np.ndarray:
        return (np.arange(self.nz) + 0.5) * self.dz

    @property
    def shape(self):
        return (self.x.size, self.y.size, self.nz)


class EigenstrainInfluence:
    """Residual stress and surface displacement of eigenstrains on a volume grid
    (module notes).  Builds the kernel spectra once (21 real 3-D FFTs of
    2 mx x 2 my x 4 nz points); :meth:`__call__` costs 6 forward and 6 inverse
    3-D FFTs plus one Boussinesq convolution per depth.

    Parameters
    ----------
    grid : VolumeGrid       cells (uniform in x, y and z)
    young_modulus : float   E [Pa] of the body
    poisson : float         nu [-]
    """

    def __init__(self, grid: VolumeGrid, young_modulus: float, poisson: float):
        mx, my, nz = grid.shape
        if mx < 2 or my < 2 or nz < 1 or not grid.dz > 0:
            raise InputError(f"eigenstrain grid {grid.shape} with dz = {grid.dz!r} m: "
                             "expected at least 2 x 2 x 1 cells and dz > 0")
        if not (young_modulus > 0 and -1.0 < poisson < 0.5):
            raise InputError(f"eigenstrain material E = {young_modulus!r} Pa, nu = "
                             f"{poisson!r}: expected E > 0 and -1 < nu < 0.5")
        self.grid, self.E, self.nu = grid, float(young_modulus), float(poisson)
        dx, dy, dz = float(grid.x[1] - grid.x[0]), float(grid.y[1] - grid.y[0]), grid.dz
        self.dx, self.dy = dx, dy
        self.shape3 = (2 * mx, 2 * my, 4 * nz)
        ox = np.arange(-(mx - 1), mx) * dx
        oy = np.arange(-(my - 1), my) * dy
        oz = np.arange(-(nz - 1), 2 * nz) * dz          # target - source, body and image
        phi, psi = cuboid_potentials(ox, oy, oz, dx, dy, dz)
        self._phi = {k: self._spectrum3(v, ox, oy, oz) for k, v in phi.items()}
        self._psi = {k: self._spectrum3(v, ox, oy, oz) for k, v in psi.items()}
        # the surface (z = eta dz, just inside the top layer) from the 2 nz layers
        oz_s = _ETA * dz - (np.arange(2 * nz)[::-1] - nz + 0.5) * dz      # increasing
        phs, pss = cuboid_potentials(ox, oy, oz_s, dx, dy, dz)
        phs = {k: v[:, :, ::-1] for k, v in phs.items()}          # layer order
        pss = {k: v[:, :, ::-1] for k, v in pss.items()}
        self._phi_s = {k: self._spectrum2(phs[k]) for k in ("xx", "yy", "zz", "xy", "xz", "yz")}
        self._psi_s = {k: self._spectrum2(v) for k, v in pss.items()}
        self._boussinesq_u = normal_operator(mx, my, dx, dy, self.E / (1.0 - self.nu ** 2))

    def _spectrum3(self, K, ox, oy, oz):
        """Kernel values at the offsets placed on the circular lattice, transformed."""
        N1, N2, N3 = self.shape3
        A = np.zeros(self.shape3)
        ix = np.round(ox / self.dx).astype(int) % N1
        iy = np.round(oy / self.dy).astype(int) % N2
        iz = np.round(oz / self.grid.dz).astype(int) % N3
        A[np.ix_(ix, iy, iz)] = K
        return fft.rfftn(A)

    def _spectrum2(self, K):
        """Per layer (last axis) 2-D spectra of in-plane kernels."""
        mx, my, _ = self.grid.shape
        N1, N2, _ = self.shape3
        A = np.zeros((N1, N2, K.shape[2]))
        ix = np.arange(-(mx - 1), mx) % N1
        iy = np.arange(-(my - 1), my) % N2
        A[np.ix_(ix, iy, np.arange(K.shape[2]))] = K
        return fft.rfft2(A, axes=(0, 1))

    def _sources(self, eps):
        """The body's eigenstrain and its mirror image on the 2 nz-layer lattice
        (image layers first, in increasing z), zero-padded."""
        mx, my, nz = self.grid.shape
        S = np.zeros((6,) + self.shape3)
        S[:, :mx, :my, nz:2 * nz] = eps
        img = eps[:, :, :, ::-1].copy()
        img[4:6] *= -1.0                               # xz, yz change sign
        S[:, :mx, :my, :nz] = img
        return S

    def full_space(self, eps: np.ndarray) -> np.ndarray:
        """Strains (6, mx, my, nz) of the eigenstrain and its mirror image in the
        infinite space at the cell centres (step 1 and 2 of the module notes)."""
        mx, my, nz = self.grid.shape
        S = self._sources(eps)
        Eh = dict(zip(_PHI, fft.rfftn(S, axes=(1, 2, 3))))
        st = _strains(self._phi, self._psi, Eh, self.nu)
        out = np.empty((6, mx, my, nz))
        for n, c in enumerate(_PHI):
            out[n] = fft.irfftn(st[c], s=self.shape3)[:mx, :my, nz:2 * nz]
        return out

    def surface_pressure(self, eps: np.ndarray) -> np.ndarray:
        """sigma_zz [Pa] on z = 0 of the eigenstrain and its image in the infinite
        space: the pressure that frees the surface (step 3)."""
        mx, my, nz = self.grid.shape
        S = self._sources(eps)[..., :2 * nz]
        Eh = dict(zip(_PHI, fft.rfft2(S, axes=(1, 2))))
        strain = {}
        st = _strains(self._phi_s, self._psi_s, Eh, self.nu)
        for k in ("xx", "yy", "zz"):
            strain[k] = fft.irfft2(st[k].sum(axis=-1), s=self.shape3[:2])[:mx, :my]
        lam = self.E * self.nu / ((1.0 + self.nu) * (1.0 - 2.0 * self.nu))
        mu = 0.5 * self.E / (1.0 + self.nu)
        tr = strain["xx"] + strain["yy"] + strain["zz"]
        top = eps[:, :, :, 0]                        # the eigenstrain where the target lies
        return lam * (tr - top[:3].sum(axis=0)) + 2.0 * mu * (strain["zz"] - top[2])

    def __call__(self, eps: np.ndarray):
        """Residual stress (6, mx, my, nz) [Pa] at the cell centres and normal
        displacement (mx, my) [m] of the surface, positive into the body, of the
        eigenstrains ``eps`` (6, mx, my, nz) (:data:`COMPONENTS` order, tensor shears)."""
        eps = np.asarray(eps, float)
        if eps.shape != (6,) + self.grid.shape:
            raise InputError(f"eigenstrain of shape {eps.shape}: expected "
                             f"{(6,) + self.grid.shape}")
        strain = self.full_space(eps)
        sigma = hooke(strain - eps, self.E, self.nu)
        p = self.surface_pressure(eps)
        sigma += convolve_depths(np.stack([p, np.zeros_like(p), np.zeros_like(p)]),
                                 _round(self.dx), _round(self.dy),
                                 [_round(v) for v in self.grid.z], self.nu)
        return sigma, self._boussinesq_u(p)


def _round(v: float) -> float:
    return float(f"{v:.12g}")


__all__ = ["EigenstrainInfluence", "VolumeGrid", "cuboid_potentials", "hooke", "COMPONENTS"]
