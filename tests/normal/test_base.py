"""Grid helpers shared by the normal models (railcontact.normal.base)."""

import numpy as np
from scipy.ndimage import map_coordinates

from railcontact.normal.base import bilinear, make_grid, same_grid


def test_bilinear_equals_scipy_map_coordinates():
    """The compiled interpolation equals scipy's order-1, mode="constant" one: bilinear
    between the element centres, zero outside them (edges and points a rounding
    error outside included)."""
    rng = np.random.default_rng(3)
    x, y = make_grid(2e-3, 1e-3, (40, 37))
    f = rng.random((40, 37))
    xq = rng.uniform(x[0] - 3e-4, x[-1] + 3e-4, 5000)
    yq = rng.uniform(y[0] - 3e-4, y[-1] + 3e-4, 5000)
    xq[:40], yq[40:80], xq[80:120] = x[0], y[-1], x[-1] * (1 + 1e-15)
    u, v = (xq - x[0]) / (x[1] - x[0]), (yq - y[0]) / (y[1] - y[0])
    ref = map_coordinates(f, np.stack([u, v]), order=1, mode="constant", cval=0.0)
    np.testing.assert_allclose(bilinear(x, y, f, xq, yq), ref, rtol=0, atol=1e-14)
    # on the centres it returns the values; a (n, 1) x (1, m) query keeps its shape
    np.testing.assert_allclose(bilinear(x, y, f, x[:, None], y[None, :]), f, atol=1e-14)
    assert bilinear(x, y, f, x[:5, None], y[None, :3]).shape == (5, 3)
    assert not bilinear(x, y, f, np.array([x[0] - 1e-6]), np.array([y[3]])).any()


def test_same_grid():
    x, y = make_grid(2e-3, 1e-3, (40, 30))
    assert same_grid(x, y, x, y) and same_grid(x, y, x.copy() + 1e-15, y.copy())
    x2, y2 = make_grid(2e-3 * (1 + 1e-4), 1e-3, (40, 30))
    assert not same_grid(x, y, x2, y2)                    # 1e-4 of the extent apart
    assert not same_grid(x, y, x[:-1], y)                 # one element fewer
    assert not same_grid(x, y, x, y + 1e-8)               # shifted by 1e-4 elements


def test_an_element_size_changed_from_the_request_is_a_warning_of_the_result():
    """1e-7 m elements over a Hertzian patch of about 10 mm would need 10^5 per
    direction: the grid is coarsened to MAX_ELEMENTS per direction and the solution
    says so; the requested size itself gives no warning."""
    import railcontact as rc
    from railcontact.geometry import ContactGeometry
    from railcontact.normal import get_normal_model
    from railcontact.normal.base import MAX_ELEMENTS, resized_elements
    assert resized_elements(None, 1e-4, 1e-4) == ""
    assert resized_elements((1e-4, 1e-4), 1e-4, 1e-4) == ""
    assert "changed from the requested 0.0001 x 0.0001 mm to 0.06 x 0.03 mm" in \
        resized_elements((1e-7, 1e-7), 6e-5, 3e-5)
    g = ContactGeometry(curvatures=(1.0, 4.0))
    for model in ("exact", "kpec"):
        ns = get_normal_model(model).solve(g, rc.Material(), normal_force=1e5,
                                           element_size=(1e-7, 1e-7))
        (w,) = [w for w in ns.status.warnings if "element size" in w]
        assert "changed from the requested 0.0001 x 0.0001 mm" in w
        assert max(ns.x.size, ns.y.size) <= MAX_ELEMENTS + 2
        ok = get_normal_model(model).solve(g, rc.Material(), normal_force=1e5,
                                           element_size=(5e-4, 5e-4))
        assert not any("element size" in w for w in ok.status.warnings)


def test_element_lattice_through_a_given_origin():
    """make_grid with an element size and an origin (a transient CONTACT grid):
    the element centres lie on origin + (i dx, j dy) and cover the area."""
    x, y = make_grid(1e-3, 2e-3, element_size=(4e-4, 2.5e-4), origin=(1e-4, -3e-5))
    assert np.allclose(np.remainder(x - 1e-4 + 1e-9, 4e-4), 1e-9, atol=1e-12)
    assert np.allclose(np.remainder(y + 3e-5 + 1e-9, 2.5e-4), 1e-9, atol=1e-12)
    assert x[0] <= -1e-3 and x[-1] >= 1e-3 and y[0] <= -2e-3 and y[-1] >= 2e-3
    x0, _ = make_grid(1e-3, 2e-3, element_size=(4e-4, 2.5e-4))
    assert np.any(np.abs(x0) < 1e-15)                   # default: through the reference


def test_bilinear_on_lines_equals_the_points_exactly():
    """Another grid's lines (an (n, 1) x (1, m) query, the warm start's) give the
    point-by-point interpolation bit for bit, lines outside the grid zero."""
    rng = np.random.default_rng(4)
    x, y = make_grid(2e-3, 1e-3, (40, 37))
    f = rng.random((40, 37))
    xl = np.linspace(x[0] - 4e-4, x[-1] + 4e-4, 43)
    yl = np.linspace(y[0] - 2e-4, y[-1] + 3e-4, 31)
    xl[5], yl[7] = x[-1], y[0]
    lines = bilinear(x, y, f, xl[:, None], yl[None, :])
    X, Y = np.broadcast_arrays(xl[:, None], yl[None, :])
    points = bilinear(x, y, f, X.ravel(), Y.ravel()).reshape(X.shape)
    assert np.array_equal(lines, points)
    assert not lines[0].any() and not lines[:, -1].any() and lines[5].any()
