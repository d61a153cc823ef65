"""Influence coefficients of the half-space and their FFT products
(railcontact.normal.influence): against the dense sum, quadrature and Love's
closed form for a uniformly loaded rectangle."""

import math

import numpy as np
import pytest

from railcontact.core.materials import Material
from railcontact.normal.influence import (Convolution, normal_displacement_at, normal_kernel,
                                          normal_operator)

MAT = Material(2.1e11, 0.28)


def test_fft_product_equals_dense_matrix():
    mx, my, dx, dy = 6, 5, 1e-3, 1.5e-3
    K = normal_kernel(mx, my, dx, dy, MAT.contact_modulus)
    p = np.random.default_rng(2).random((mx, my))
    dense = np.zeros((mx, my))
    for i in range(mx):
        for j in range(my):
            dense[i, j] = sum(K[i - k + mx - 1, j - m + my - 1] * p[k, m]
                              for k in range(mx) for m in range(my))
    assert np.allclose(Convolution(K, mx, my)(p), dense, rtol=1e-12, atol=0)
    # centre of a square element of side 2c: 8 c ln(1 + sqrt 2) / (pi E*)
    K1 = normal_kernel(1, 1, 2e-3, 2e-3, MAT.contact_modulus)
    assert K1[0, 0] == pytest.approx(8e-3 * math.log(1 + math.sqrt(2)) /
                                     (math.pi * MAT.contact_modulus), rel=1e-12)


def test_displacement_at_one_point_equals_the_fft_product():
    from railcontact.normal.influence import normal_displacement_at, normal_operator
    rng = np.random.default_rng(3)
    p = rng.uniform(0, 1e9, (23, 17))
    u = normal_operator(23, 17, 1e-4, 2.5e-4, 1.1e11)(p)
    for i0, j0 in [(0, 0), (11, 8), (22, 3)]:
        assert normal_displacement_at(p, 1e-4, 2.5e-4, i0, j0, 1.1e11) \
            == pytest.approx(u[i0, j0], rel=1e-12)


def test_influence_kernels_against_quadrature_at_negative_offsets():
    """The kernels, evaluated for non-negative offsets and mirrored by parity, equal
    a direct quadrature of the Boussinesq and Cerruti kernels over the element at
    negative offsets too (normal 1/r, tangential xy/r^3 odd in both offsets)."""
    from scipy.integrate import dblquad
    from railcontact.normal.influence import tangential_kernels
    mx, my, dx, dy = 4, 3, 1e-3, 2e-3
    K = normal_kernel(mx, my, dx, dy, MAT.contact_modulus)
    G, nu = 8e10, 0.28
    kxx, kxy, kyy = tangential_kernels(mx, my, dx, dy, G, nu)
    for i, j in ((-3, -2), (2, -1), (-1, 2), (3, 2)):
        x0, y0 = i * dx, j * dy
        n = dblquad(lambda y, x: 1 / np.hypot(x, y), x0 - dx / 2, x0 + dx / 2,
                    y0 - dy / 2, y0 + dy / 2, epsabs=1e-14)[0]
        assert K[i + mx - 1, j + my - 1] == pytest.approx(n / (np.pi * MAT.contact_modulus),
                                                         rel=1e-8)
        c = dblquad(lambda y, x: x * y / np.hypot(x, y) ** 3, x0 - dx / 2, x0 + dx / 2,
                    y0 - dy / 2, y0 + dy / 2, epsabs=1e-14)[0]
        assert kxy[i + mx - 1, j + my - 1] == pytest.approx(nu * c / (np.pi * G), rel=1e-8)


def love_corner(a, b):
    """Integral of 1/r over an a x b rectangle seen from its corner (Love 1929;
    Johnson, Contact Mechanics, 3.2): a ln((b + r)/a) + b ln((a + r)/b)."""
    r = math.hypot(a, b)
    return a * math.log((b + r) / a) + b * math.log((a + r) / b)


def test_uniform_rectangle_against_loves_closed_form():
    """A uniform pressure q on 7 x 5 elements: the displacement at the centre is
    four corner rectangles of Love's formula, q / (pi E*) * 4 corner(L/2, W/2); at an
    element centre outside, the difference of corner rectangles."""
    mx, my, dx, dy, q, E = 7, 5, 1e-4, 3e-4, 1e9, MAT.contact_modulus
    p = np.full((mx, my), q)
    L, W = mx * dx, my * dy
    centre = 4 * love_corner(L / 2, W / 2) * q / (math.pi * E)
    assert normal_displacement_at(p, dx, dy, 3, 2, E) == pytest.approx(centre, rel=1e-12)
    # outside: the loaded rectangle in the lower-left 3 x 2 elements of a 7 x 5 grid,
    # the point at element (5, 3): offsets from the rectangle's sides
    p = np.zeros((mx, my))
    p[:3, :2] = q
    x1, x2 = 5 * dx - (-0.5 * dx), 5 * dx - 2.5 * dx         # to the far and near edges
    y1, y2 = 3 * dy - (-0.5 * dy), 3 * dy - 1.5 * dy
    outside = (love_corner(x1, y1) - love_corner(x2, y1) - love_corner(x1, y2)
               + love_corner(x2, y2)) * q / (math.pi * E)
    u = normal_operator(mx, my, dx, dy, E)(p)
    assert u[5, 3] == pytest.approx(outside, rel=1e-10)
    assert u[5, 3] < 0.5 * u[1, 0]                            # decays away from the load


def test_kernel_is_symmetric_and_decays_like_one_over_r():
    mx, my, dx, dy = 40, 40, 1e-4, 1e-4
    K = normal_kernel(mx, my, dx, dy, MAT.contact_modulus)
    assert np.array_equal(K, K[::-1, :]) and np.array_equal(K, K[:, ::-1])
    # far from the element: A -> dx dy / (pi E* r)
    r = 39 * dx
    assert K[-1, my - 1] == pytest.approx(dx * dy / (math.pi * MAT.contact_modulus * r),
                                          rel=1e-4)


def test_bounding_box_is_that_of_the_true_elements():
    """The compiled scan of ``bounding_box`` gives the slices of NumPy's
    row/column test, and None for a mask without a true element (also on a
    strided view)."""
    from railcontact.normal.influence import bounding_box
    rng = np.random.default_rng(3)
    for shape, density in (((40, 40), 0.01), ((7, 13), 0.2), ((1, 5), 0.5), ((30, 2), 0.05)):
        for _ in range(20):
            mask = rng.random(shape) < density
            rows = np.flatnonzero(mask.any(axis=1))
            cols = np.flatnonzero(mask.any(axis=0))
            want = None if rows.size == 0 else (slice(rows[0], rows[-1] + 1),
                                                slice(cols[0], cols[-1] + 1))
            assert bounding_box(mask) == want
            assert bounding_box(mask.T[::-1]) == bounding_box(np.ascontiguousarray(mask.T[::-1]))
    assert bounding_box(np.zeros((4, 4), bool)) is None


def test_a_block_operator_is_the_grid_kernel_cut_to_the_block():
    """The operator of a block is built from the grid's kernel at the block's
    offsets: the same kernel and spectrum as cutting ``normal_kernel``."""
    from railcontact.normal.influence import normal_operator_block
    for mx, my, ms, ns in ((40, 40, 28, 28), (40, 30, 12, 30), (17, 40, 3, 2)):
        op = normal_operator_block(mx, my, 1.3e-4, 0.9e-4, MAT.contact_modulus, ms, ns)
        K = normal_kernel(mx, my, 1.3e-4, 0.9e-4, MAT.contact_modulus)
        a, b = op.mx, op.my
        ref = Convolution(K[mx - a:mx - 1 + a, my - b:my - 1 + b], a, b)
        assert np.array_equal(op.kernel, ref.kernel)
        assert np.array_equal(op.khat, ref.khat)


def test_the_kernels_share_the_element_integrals_by_the_sum_rule():
    """``normal_kernel`` and ``tangential_kernels`` are combinations of the same
    element integrals (``rect_integrals``): with G = E / (2 (1 + nu)) and
    1/E* = 2 (1 - nu^2) / E, kxx + kyy = (2 - nu) / (1 - nu) A at every offset, the
    extra row of the rolling difference included; that row leaves the grid's rows
    as they are."""
    from railcontact.normal.influence import rect_integrals, tangential_kernels
    mx, my, dx, dy = 7, 5, 1.3e-4, 0.9e-4
    A = normal_kernel(mx, my, dx, dy, MAT.contact_modulus, extra_rows=1)
    assert A.shape == (2 * mx, 2 * my - 1)
    assert np.array_equal(A[:-1], normal_kernel(mx, my, dx, dy, MAT.contact_modulus))
    kxx, _, kyy = tangential_kernels(mx, my, dx, dy, MAT.shear_modulus, MAT.nu, extra_rows=1)
    nu = MAT.nu
    assert np.allclose(kxx + kyy, (2 - nu) / (1 - nu) * A, rtol=1e-13, atol=0)
    Lx, Ly, _ = rect_integrals(mx, my, dx, dy)
    assert np.allclose(A, (Lx + Ly) / (math.pi * MAT.contact_modulus), rtol=1e-15, atol=0)
    from railcontact.core.errors import InputError
    with pytest.raises(InputError, match="extra_rows"):
        normal_kernel(mx, my, dx, dy, MAT.contact_modulus, extra_rows=2)
    with pytest.raises(InputError, match="extra_rows = 1.0: expected the integer"):
        tangential_kernels(mx, my, dx, dy, MAT.shear_modulus, MAT.nu, extra_rows=1.0)
    assert np.array_equal(normal_kernel(mx, my, dx, dy, MAT.contact_modulus,
                                        extra_rows=np.int64(1)), A)
