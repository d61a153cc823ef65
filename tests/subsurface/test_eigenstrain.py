"""Eigenstrain influence in a half-space against closed forms: the cuboid
potentials against the point-source derivatives far away, Eshelby's interior
strain of a (voxelised) sphere, and the free-surface uplift of a centre of
dilatation (Mindlin & Cheng 1950; Mogi)."""

import math

import numpy as np
import pytest

from railcontact.core.errors import InputError
from railcontact.subsurface.eigenstrain import (EigenstrainInfluence, VolumeGrid,
                                                cuboid_potentials)

NU, E = 0.3, 2.0e11


def test_cuboid_potentials_far_field_and_laplacian():
    # far from a small cube, phi_,ij -> V d_ij (1/R), psi_,xxyz -> V d^4 R / dx^2 dy dz
    d = 0.1
    phi, psi = cuboid_potentials(np.array([5.0]), np.array([3.0]), np.array([-4.0]), d, d, d)
    V, R = d ** 3, math.sqrt(50.0)
    x, y, z = 5.0, 3.0, -4.0
    assert phi["xy"][0, 0, 0] == pytest.approx(V * 3 * x * y / R ** 5, rel=1e-3)
    assert phi["xx"][0, 0, 0] == pytest.approx(V * (3 * x * x / R ** 5 - 1 / R ** 3), rel=1e-3)
    # d^4 R / dx^2 dy dz = 3 y z (1 - 5 x^2 / R^2) / R^5
    assert psi["xxyz"][0, 0, 0] == pytest.approx(V * 3 * y * z * (1 - 5 * x * x / R ** 2) / R ** 5,
                                                 rel=1e-3)
    # lap phi = -4 pi inside the cell, 0 outside
    o = np.arange(-2, 3) * 1.0
    phi, _ = cuboid_potentials(o, o, o, 1.0, 1.0, 1.0)
    lap = phi["xx"] + phi["yy"] + phi["zz"]
    assert lap[2, 2, 2] == pytest.approx(-4 * math.pi, rel=1e-12)
    assert abs(lap[2, 2, 4]) < 1e-12


@pytest.fixture(scope="module")
def sphere():
    n, nz, d = 32, 24, 1e-4
    x = (np.arange(n) - n / 2 + 0.5) * d
    grid = VolumeGrid(x=x, y=x, dz=d, nz=nz)
    X, Y, Z = np.meshgrid(x, x, grid.z, indexing="ij")
    inside = X ** 2 + Y ** 2 + (Z - 12 * d) ** 2 < (4.3 * d) ** 2
    return EigenstrainInfluence(grid, E, NU), inside, grid


def test_eshelby_interior_strain(sphere):
    # Eshelby (1957): inside a sphere eps = S eps*; dilatation (1+nu)/(3(1-nu)),
    # shear 2 (4 - 5 nu) / (15 (1 - nu)); the voxel sphere (radius 4.3 cells, measured
    # 0.5 % and 1.2 % off) and its image 24 cells away: 2 %
    inf, inside, _ = sphere
    eps = np.zeros((6,) + inside.shape)
    eps[0][inside] = eps[1][inside] = eps[2][inside] = 1e-3
    st = inf.full_space(eps)
    c = st[:, 15:17, 15:17, 11:13].mean(axis=(1, 2, 3))
    assert c[0] == pytest.approx((1 + NU) / (3 * (1 - NU)) * 1e-3, rel=0.02)
    assert c[2] == pytest.approx((1 + NU) / (3 * (1 - NU)) * 1e-3, rel=0.02)
    eps = np.zeros((6,) + inside.shape)
    eps[3][inside] = 1e-3
    st = inf.full_space(eps)
    assert st[3, 15:17, 15:17, 11:13].mean() == pytest.approx(
        2 * (4 - 5 * NU) / (15 * (1 - NU)) * 1e-3, rel=0.02)


def test_free_surface_pressure_and_uplift_of_a_centre_of_dilatation(sphere):
    # the infinite-space sigma_zz on z = 0 of the sphere and its image, 4 mu C
    # (1/R^3 - 3 d^2/R^5) (C = eps* V (1 + nu) / (4 pi (1 - nu))), to 0.5 %; the
    # surface uplift above it, Mogi's (1 + nu) eps* V d / (pi R^3), to 12 %: the
    # pressure that frees the surface is cut at the grid's edge (16 cells, d = 12)
    inf, inside, grid = sphere
    eps = np.zeros((6,) + inside.shape)
    eps[0][inside] = eps[1][inside] = eps[2][inside] = 1e-3
    V = inside.sum() * 1e-12
    d, x = 12e-4, grid.x
    mu = E / (2 * (1 + NU))
    C = 1e-3 * (1 + NU) * V / (4 * math.pi * (1 - NU))
    p = inf.surface_pressure(eps)
    for i in (16, 24, 30):
        R2 = x[i] ** 2 + x[16] ** 2 + d * d
        assert p[i, 16] == pytest.approx(4 * mu * C * (R2 ** -1.5 - 3 * d * d * R2 ** -2.5),
                                         rel=5e-3)
    sigma, uz = inf(eps)
    R = math.hypot(x[16], math.hypot(x[16], d))
    assert -uz[16, 16] == pytest.approx((1 + NU) * 1e-3 * V * d / (math.pi * R ** 3), rel=0.12)
    # the traction-free surface: sigma_zz, sigma_xz vanish as z -> 0 (top cell at dz/2)
    assert np.abs(sigma[2, :, :, 0]).max() < 0.01 * np.abs(sigma[2]).max()


def test_bad_grid():
    with pytest.raises(InputError, match="eigenstrain grid"):
        EigenstrainInfluence(VolumeGrid(x=np.array([0.0]), y=np.zeros(3), dz=1e-4, nz=2), E, NU)
