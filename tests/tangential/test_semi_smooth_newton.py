"""The compiled semi-smooth Newton iteration of the exact tangential model
(railcontact.tangential.semi_smooth_newton): the local friction problem of one
element against its closed form, and the compiled slip operator against the
NumPy/SciPy one.  The whole solver is tested against Kalker's and Carter's
solutions in test_exact.py."""

import math

import numpy as np
import pytest

from railcontact.tangential.exact import _operators
from railcontact.tangential.semi_smooth_newton import (SlipOperator, _c_of, _local_slip,
                                                      bound_at)


def test_local_problem_sticks_within_the_bound():
    """|D^-1 r| <= g: the element sticks with p = -D^-1 r and zero slip."""
    px, py, ex, ey, stick = _local_slip(0.3, -0.4, 0.5, 2.0, 1.0)
    assert stick and (px, py) == pytest.approx((-0.6, 0.2)) and (ex, ey) == (0.0, 0.0)


def test_local_problem_slips_on_the_bound():
    """Equal flexibilities d: the slip |s| = |r| - g d along r, the traction -g r/|r|
    (r = (3, 4), d = 1, g = 2: |s| = 3).  Unequal ones: the traction lies on the bound
    against the slip s = r + D p that it leaves."""
    px, py, ex, ey, stick = _local_slip(3.0, 4.0, 1.0, 1.0, 2.0)
    assert not stick
    assert (px, py) == pytest.approx((-1.2, -1.6), rel=1e-12)
    assert (ex, ey) == pytest.approx((0.6, 0.8), rel=1e-12)
    rx, ry, dxx, dyy, g = 3.0, -1.0, 0.4, 1.7, 2.5
    px, py, ex, ey, stick = _local_slip(rx, ry, dxx, dyy, g)
    sx, sy = rx + dxx * px, ry + dyy * py
    assert not stick and math.hypot(px, py) == pytest.approx(g, rel=1e-12)
    assert (ex, ey) == pytest.approx((sx / math.hypot(sx, sy), sy / math.hypot(sx, sy)),
                                     rel=1e-10)
    assert (px, py) == pytest.approx((-g * ex, -g * ey), rel=1e-12)


def test_compiled_slip_operator_equals_the_fft_operator():
    """The compiled linear part of the slip (FFT products by rocket-fft in Numba)
    equals the NumPy/SciPy tangential operator: rolling -(u_I+ - u_I)/dx, shift u_I."""
    mx, my, dx, dy = 13, 9, 2e-4, 3e-4
    op, _ = _operators(mx, my, dx, dy, 8e10, 0.28)
    rng = np.random.default_rng(5)
    px, py = rng.normal(size=(mx, my)), rng.normal(size=(mx, my))
    ux, uy = op(px, py)
    for shift, (ex, ey) in ((False, (-(ux[1:] - ux[:-1]) / dx, -(uy[1:] - uy[:-1]) / dx)),
                            (True, (ux[:-1], uy[:-1]))):
        sop = SlipOperator(op.kxx, op.kxy, op.kyy, op.shape, dx, shift, 0.0)
        cx, cy = _c_of(px, py, sop, np.zeros(op.shape), np.zeros(op.shape))
        scale = np.abs(ex).max() + np.abs(ey).max()
        assert np.abs(cx - ex).max() <= 1e-12 * scale
        assert np.abs(cy - ey).max() <= 1e-12 * scale


def test_layer_flexibility_in_the_slip_operator():
    """An interfacial layer (CONTACT's M = 4) adds its own displacement f p to the
    bodies' u = B p: shift u_I + f p_I, rolling -(U_I+ - U_I)/dx with U = u + f p."""
    mx, my, dx, dy, f = 13, 9, 2e-4, 3e-4, 3.7e-15
    op, _ = _operators(mx, my, dx, dy, 8e10, 0.28)
    rng = np.random.default_rng(7)
    px, py = rng.normal(size=(mx, my)), rng.normal(size=(mx, my))
    ux, uy = op(px, py)                                   # mx + 1 rows
    zero = np.zeros((1, my))
    Ux, Uy = ux + f * np.vstack([px, zero]), uy + f * np.vstack([py, zero])
    for shift, (ex, ey) in ((False, (-(Ux[1:] - Ux[:-1]) / dx, -(Uy[1:] - Uy[:-1]) / dx)),
                            (True, (Ux[:-1], Uy[:-1]))):
        sop = SlipOperator(op.kxx, op.kxy, op.kyy, op.shape, dx, shift, f)
        cx, cy = _c_of(px, py, sop, np.zeros(op.shape), np.zeros(op.shape))
        scale = np.abs(ex).max() + np.abs(ey).max()
        assert np.abs(cx - ex).max() <= 1e-12 * scale
        assert np.abs(cy - ey).max() <= 1e-12 * scale


def test_blanco_lateral_displacement_in_the_slip_operator():
    """Blanco's coefficients (variant 3) in the compiled operator: u_x as on the
    half-space, u_s = sum_J cos(a_J - a_I) (A_sx p_x + A_ss p_s)(I - J), against
    the dense sum of the kernels (the shift's u and the rolling difference); a
    constant inclination gives the half-space's operator."""
    from railcontact.normal.influence import tangential_kernels
    mx, my, dx, dy = 7, 6, 2e-4, 3e-4
    op, _ = _operators(mx, my, dx, dy, 8e10, 0.28)
    kxx, kxy, kyy = tangential_kernels(mx, my, dx, dy, 8e10, 0.28, extra_rows=1)
    rng = np.random.default_rng(11)
    px, py = rng.normal(size=(mx, my)), rng.normal(size=(mx, my))
    a = np.array([-0.9, -0.5, -0.1, 0.2, 0.6, 1.0])
    ux, uy = np.zeros((mx + 1, my)), np.zeros((mx + 1, my))
    for i in range(mx + 1):
        for j in range(my):
            for k in range(mx):
                for m in range(my):
                    o = (i - k + mx - 1, j - m + my - 1)
                    ux[i, j] += kxx[o] * px[k, m] + kxy[o] * py[k, m]
                    uy[i, j] += math.cos(a[m] - a[j]) * (kxy[o] * px[k, m] + kyy[o] * py[k, m])
    for shift, (ex, ey) in ((False, (-(ux[1:] - ux[:-1]) / dx, -(uy[1:] - uy[:-1]) / dx)),
                            (True, (ux[:-1], uy[:-1]))):
        sop = SlipOperator(op.kxx, op.kxy, op.kyy, op.shape, dx, shift, 0.0,
                           np.cos(a), np.sin(a))
        cx, cy = _c_of(px, py, sop, np.zeros(op.shape), np.zeros(op.shape))
        scale = np.abs(ex).max() + np.abs(ey).max()
        assert np.abs(cx - ex).max() <= 1e-11 * scale
        assert np.abs(cy - ey).max() <= 1e-11 * scale
    flat = SlipOperator(op.kxx, op.kxy, op.kyy, op.shape, dx, True, 0.0,
                        np.full(my, math.cos(0.4)), np.full(my, math.sin(0.4)))
    plain = SlipOperator(op.kxx, op.kxy, op.kyy, op.shape, dx, True, 0.0)
    cf = _c_of(px, py, flat, np.zeros(op.shape), np.zeros(op.shape))
    cp = _c_of(px, py, plain, np.zeros(op.shape), np.zeros(op.shape))
    assert np.allclose(cf[1], cp[1], rtol=1e-12, atol=1e-12 * np.abs(cp[1]).max())


def test_traction_bound_of_a_yielding_layer():
    """bound(S) = min(g, max(0, tau + k S)) where the yield limit tau lies under the
    friction bound g, with its slope k; g (slope 0) elsewhere."""
    assert bound_at(5.0, 7.0, 3.0, 0.4) == (5.0, 0.0)          # friction: tau >= g
    assert bound_at(5.0, 2.0, 3.0, 0.5) == (3.5, 3.0)          # hardening flow
    assert bound_at(5.0, 2.0, 3.0, 2.0) == (5.0, 0.0)          # hardened up to g: slides
    assert bound_at(5.0, 2.0, -3.0, 0.5) == (0.5, -3.0)        # softening
    assert bound_at(5.0, 2.0, -3.0, 1.0) == (0.0, 0.0)         # softened to nothing
    assert bound_at(5.0, 2.0, 0.0, 9.0) == (2.0, 0.0)          # perfectly plastic
