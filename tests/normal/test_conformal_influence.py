"""Blanco's influence coefficients of a conformal patch
(railcontact.normal.conformal_influence, CONTACT's INFLCF = 4, variant 3): their
definition against the rotation of the half-space's displacement into each
element's frame, the FFT products against the dense sum of the coefficients, the
flat-surface limit (exactly the half-space's) and the symmetry of the normal
block."""

import numpy as np
import pytest

from railcontact.core.materials import Material
from railcontact.normal.conformal_influence import (BlancoCoupling, blanco_coefficients,
                                                    blanco_normal_operator)
from railcontact.normal.influence import rect_integrals, normal_operator, tangential_kernels
from railcontact.normal.polonsky_keer import polonsky_keer

MAT = Material(2.0 * 8e10 * 1.28, 0.28)
MX, MY, DX, DY = 5, 6, 1e-4, 2.5e-4


def _dense(angles, extra_rows=0):
    """The dense coefficients B[i, j, k, l, a, b] (displacement a at (i, j) of a unit
    traction b at (k, l); components x, s, n) from the half-space kernels and
    :func:`blanco_coefficients`, output rows up to MX + extra_rows."""
    G, nu = MAT.shear_modulus, MAT.nu
    kxx, kxy, kyy = tangential_kernels(MX, MY, DX, DY, G, nu, extra_rows=1)
    Lx, Ly, _ = rect_integrals(MX, MY, DX, DY)
    knn = (Lx + Ly) / (np.pi * MAT.contact_modulus)
    nout = MX + extra_rows
    B = np.zeros((nout, MY, MX, MY, 3, 3))
    for i in range(nout):
        for j in range(MY):
            for k in range(MX):
                for m in range(MY):
                    o = (i - k + MX - 1, j - m + MY - 1)
                    A = np.array([[kxx[o], kxy[o], 0.0], [kxy[o], kyy[o], 0.0],
                                  [0.0, 0.0, knn[o]]])
                    B[i, j, k, m] = blanco_coefficients(A, angles[m] - angles[j])
    return B


ANGLES = np.array([-0.7, -0.4, -0.15, 0.05, 0.3, 0.8])
RNG = np.random.default_rng(34)
P = RNG.uniform(0.0, 1e9, (MX, MY))
TX, TY = RNG.uniform(-3e8, 3e8, (2, MX, MY))


def test_coefficients_turn_the_half_space_displacement():
    """Each column (the displacement of one traction component) of B is the
    half-space's turned by alpha_J - alpha_I about x: x unchanged, (s, n)
    rotated, lengths kept; the flat surface gives A exactly."""
    A = RNG.normal(size=(7, 3, 3))
    d = RNG.uniform(-1.0, 1.0, 7)
    B = blanco_coefficients(A, d)
    assert np.array_equal(B[:, 0, :], A[:, 0, :])
    assert np.allclose(np.hypot(B[:, 1, :], B[:, 2, :]), np.hypot(A[:, 1, :], A[:, 2, :]),
                       rtol=1e-14)
    ang = np.arctan2(B[:, 2, :], B[:, 1, :]) - np.arctan2(A[:, 2, :], A[:, 1, :])
    assert np.allclose(np.angle(np.exp(1j * ang)), d[:, None], atol=1e-12)
    assert np.array_equal(blanco_coefficients(A, 0.0), A)


def test_normal_product_equals_the_dense_sum_and_is_symmetric():
    """u_n = B_nn p by four FFT convolutions equals the dense sum of
    cos(alpha_J - alpha_I) A_nn(I - J) p_J to rounding; B_nn is symmetric
    (v . B w = w . B v) and its diagonal is A's."""
    B = _dense(ANGLES)
    op = blanco_normal_operator(normal_operator(MX, MY, DX, DY, MAT.contact_modulus), ANGLES)
    dense = np.einsum("ijkl,kl->ij", B[..., 2, 2], P)
    assert np.allclose(op(P), dense, rtol=1e-11, atol=0)
    v, w = RNG.random((2, MX, MY))
    assert np.sum(v * op(w)) == pytest.approx(np.sum(w * op(v)), rel=1e-12)
    assert op.diag == B[0, 0, 0, 0, 2, 2]


def test_variant_3_is_reciprocal_in_the_normal_block_only():
    """Variant 3 turns the displacements only (the rows), so reciprocity
    B_ab(I, J) = B_ba(J, I) holds for the normal block (cos Delta A_nn) but not
    between the lateral and normal components: B_ns(I, J) = sin Delta A_ss(I - J)
    against B_sn(J, I) = sin Delta A_nn(I - J), their ratio A_ss/A_nn; nor
    between x and s (A_xs against cos Delta A_sx).  CONTACT's variant 4 would
    be the reciprocal one; it is not computed."""
    B = _dense(ANGLES)
    Bt = np.transpose(B, (2, 3, 0, 1, 5, 4))           # B_ba(J, I) at [I, J, a, b]
    assert np.allclose(B[..., 2, 2], Bt[..., 2, 2], rtol=1e-14, atol=0)
    ns, sn = B[..., 2, 1], Bt[..., 2, 1]
    off = np.abs(sn) > 1e-3 * np.abs(sn).max()
    assert off.sum() > 100
    ratio = ns[off] / sn[off]
    assert ratio.min() > 0.1 and abs(np.median(ratio) - 1.0) > 0.05
    assert not np.allclose(B[..., 0, 1], Bt[..., 0, 1], rtol=1e-6, atol=0)


def test_flat_surface_gives_the_half_space():
    """A constant inclination: Blanco's normal operator is the half-space's, and
    the coupling terms vanish (to rounding of the cancelling products)."""
    base = normal_operator(MX, MY, DX, DY, MAT.contact_modulus)
    op = blanco_normal_operator(base, np.full(MY, 0.37))
    assert np.allclose(op(P), base(P), rtol=1e-12, atol=0)
    cpl = BlancoCoupling(lambda s: np.full(s.size, 0.37), MAT)
    x, y = np.arange(MX) * DX, np.arange(MY) * DY
    scale = float(np.max(np.abs(base(P))))
    assert np.max(np.abs(cpl.gap_from_tractions(x, y, TX, TY))) < 1e-12 * scale
    assert np.max(np.abs(cpl.lateral_displacement(x, y, P))) < 1e-12 * scale


def test_coupling_equals_the_dense_sum():
    """The gap's opening from tangential tractions (B_nx t_x + B_ns t_s) and the
    lateral displacement of the pressure (B_sn p, one row beyond the grid for the
    rolling difference) equal the dense sums; the rolling slip is its upstream
    difference."""
    B = _dense(ANGLES, extra_rows=1)
    x, y = np.arange(MX) * DX, np.arange(MY) * DY
    cpl = BlancoCoupling(lambda s: ANGLES, MAT)
    gap = np.einsum("ijkl,kl->ij", B[:MX, :, :, :, 2, 0], TX) + \
        np.einsum("ijkl,kl->ij", B[:MX, :, :, :, 2, 1], TY)
    assert np.allclose(cpl.gap_from_tractions(x, y, TX, TY), gap, rtol=1e-10,
                       atol=1e-12 * np.max(np.abs(gap)))
    us = np.einsum("ijkl,kl->ij", B[..., 1, 2], P)
    assert np.allclose(cpl.lateral_displacement(x, y, P), us, rtol=1e-10,
                       atol=1e-12 * np.max(np.abs(us)))
    sx, sy = cpl.slip_from_pressure(x, y, P)
    assert np.array_equal(sx, np.zeros_like(P))
    assert np.allclose(sy, -(us[1:] - us[:-1]) / DX, rtol=1e-8, atol=1e-10 * np.max(np.abs(sy)))
    assert np.allclose(cpl.slip_from_pressure(x, y, P, "shift")[1], us[:-1], rtol=1e-10,
                       atol=1e-12 * np.max(np.abs(us)))


def test_polonsky_keer_takes_the_modulated_operator():
    """The constrained conjugate gradients with Blanco's normal operator: a
    punch-like overlap solved with the approach given meets B_nn p = delta - h in
    the contact, p = 0 with a non-negative gap outside; the direct updates of a
    few elements (the modulated kernel sum) agree with the FFT products."""
    mx, my = 24, 20
    x = (np.arange(mx) - (mx - 1) / 2) * DX
    y = (np.arange(my) - (my - 1) / 2) * DY
    h = 3.0 * x[:, None] ** 2 + 0.6 * y[None, :] ** 2 - 2e-6
    ang = np.linspace(-0.6, 0.6, my)
    op = blanco_normal_operator(normal_operator(mx, my, DX, DY, MAT.contact_modulus), ang)
    p, _, it, ok = polonsky_keer(op, h, DX * DY, None, tol=1e-10, maxiter=2000)
    assert ok
    gap = h + op(p)
    c = p > 0
    assert c.sum() > 20 and not c[0].any() and not c[:, 0].any()
    assert np.max(np.abs(gap[c])) < 1e-8 * 2e-6
    assert gap[~c].min() > -1e-8 * 2e-6
    # Blanco's coefficients couple distant columns less (cos < 1): at the same
    # approach the pressure carries more load than the half-space's
    q, _, _, _ = polonsky_keer(normal_operator(mx, my, DX, DY, MAT.contact_modulus), h,
                               DX * DY, None, tol=1e-10, maxiter=2000)
    assert p.sum() > q.sum()
