"""Exact steady rolling against Kalker's table, CONTACT, Carter and Coulomb."""

import math

import numpy as np
import pytest

from railcontact.core.materials import Material
from railcontact.normal.base import NormalSolution
from railcontact.normal.polonsky_keer import polonsky_keer
from railcontact.normal.influence import normal_operator
from railcontact.tangential import get_tangential_model, kalker_coefficients
from railcontact.tangential.exact import steady_rolling
from tests.conftest import read_csv

G = 82e9


def hertz_on_grid(a, b, mx, my, dx, dy, fn, mat):
    """Discrete normal solution for the Hertz gap of semi-axes (a, b), on CONTACT's grid
    (potential area centred, mx x my elements of dx x dy)."""
    from scipy.special import ellipe, ellipk
    Es = mat.contact_modulus
    p0 = 3 * fn / (2 * math.pi * a * b)
    if abs(a - b) < 1e-15:
        A = B = math.pi * p0 / (4 * Es * a)
    else:
        big, small = max(a, b), min(a, b)
        k = small / big
        m = 1 - k * k
        K, E = ellipk(m), ellipe(m)
        As = p0 * k / (Es * big) * (K - E) / m
        Al = p0 * k / (Es * big) * (E / k ** 2 - K) / m
        A, B = (As, Al) if a >= b else (Al, As)
    x = (np.arange(mx) + 0.5) * dx - mx * dx / 2
    y = (np.arange(my) + 0.5) * dy - my * dy / 2
    h = A * x[:, None] ** 2 + B * y[None, :] ** 2
    p, app, it, ok = polonsky_keer(normal_operator(mx, my, dx, dy, Es), h, dx * dy, force=fn,
                                   tol=1e-10)
    assert ok
    return NormalSolution("exact", x, y, p, p > 0, 0.0, float(p.max()), app, fn)


def coefficients(ns, mat, c, e=1e-6, mu=0.3):
    ex = get_tangential_model("exact")
    tx = ex.solve(ns, None, mat, (e, 0, 0), mu)
    ty = ex.solve(ns, None, mat, (0, e, 0), mu)
    tp = ex.solve(ns, None, mat, (0, 0, e / c), mu)
    return {"C11": tx.fx / (G * c * c * e), "C22": ty.fy / (G * c * c * e),
            "C23_eta": -ty.mz / (G * c ** 3 * e), "C23_phi": tp.fy / (G * c * c * e),
            "C33": tp.mz / (G * c ** 3 * e),
            "nslip": [int((t.contact & ~t.stick).sum()) for t in (tx, ty)]}


def test_against_contact_same_grid(refdir):
    """Same grid and discrete contact area as CONTACT: C11, C22 and C23 (from lateral
    creepage and from spin) agree to 0.1 % (measured 0.04 %), the lateral rigid slip
    of spin taken where CONTACT takes it (SPIN_OFFSET); at the element centres C23
    from spin is 1-4 % lower, O(dx).  The elements in slip at the trailing edge are
    CONTACT's, element for element in number (0-32 per run)."""
    rows = [r for r in read_csv(refdir / "kalker_coefficients_contact.csv")
            if float(r["mu"]) < 1 and int(r["mx"]) * int(r["my"]) <= 6400
            and float(r["creepage"]) == 1e-5 and float(r["nu"]) == 0.28]
    assert len(rows) >= 6
    for r in rows:
        mat = Material.from_shear_modulus(G, float(r["nu"]))
        a, b = float(r["a_mm"]) * 1e-3, float(r["b_mm"]) * 1e-3
        ns = hertz_on_grid(a, b, int(r["mx"]), int(r["my"]), float(r["dx_mm"]) * 1e-3,
                           float(r["dy_mm"]) * 1e-3, float(r["fn_N"]), mat)
        assert int(ns.contact.sum()) == int(r["ncon"])
        e_run = float(r["creepage"])
        c = coefficients(ns, mat, math.sqrt(a * b), e=e_run)
        for k in ("C11", "C22", "C23_eta", "C23_phi"):
            assert c[k] == pytest.approx(float(r[k]), rel=1e-3), (k, r["a_over_b"], r["mx"])
        # CONTACT's spin run has CPHI = creepage per mm
        tp = get_tangential_model("exact").solve(ns, None, mat, (0, 0, 1e3 * e_run), 0.3)
        nslip = c["nslip"] + [int((tp.contact & ~tp.stick).sum())]
        assert nslip == [int(r[k]) for k in ("nslip_xi", "nslip_eta", "nslip_phi")]


def test_partial_slip_elements_as_contact_40x40(refdir):
    """CONTACT's 40 x 40 timing problems (Hertzian, F_n = 52.36 kN, mu = 0.3,
    circle a = b = 5 mm and ellipse a = 3.5355, b = 7.0711 mm, potential area 1.1
    times the ellipse): with creepages (-1e-3, 2e-4) and spin 0.1 1/m together, the
    contact and slip elements are CONTACT's in number (1044; 307 and 278 in slip),
    and no slip without creepage but a longitudinal one of -1e-5."""
    rows = [r for r in read_csv(refdir / "contact_timing.csv")
            if r["workload"] == "module3_hertz_40x40" and r["build"] == "mkl_fft"
            and r["omp_threads"] == "1" and r["eps"] == "1e-05"]
    assert len(rows) == 3
    semi = {"circ_partial_slip": (5e-3, 5e-3), "circ_adhesion": (5e-3, 5e-3),
            "ellip_partial_slip": (3.5355e-3, 7.0711e-3)}
    creep = {"circ_adhesion": (-1e-5, 0.0, 0.0)}
    mat = Material.from_shear_modulus(G, 0.28)
    for r in rows:
        a, b = semi[r["case"]]
        ns = hertz_on_grid(a, b, 40, 40, 2.2 * a / 40, 2.2 * b / 40, 52360.0, mat)
        ts = get_tangential_model("exact").solve(ns, None, mat,
                                                 creep.get(r["case"], (-1e-3, 2e-4, 0.1)), 0.3)
        assert int(ns.contact.sum()) == int(r["ncon"])
        assert int((ts.contact & ~ts.stick).sum()) == int(r["nslip"]), r["case"]


@pytest.mark.parametrize("ab, mx, my", [(1.0, 80, 80), (0.5, 40, 80), (2.0, 80, 40)])
def test_kalker_table_80(ab, mx, my):
    """C11, C22, C23 within 2 % of Kalker's table (nu = 0.25) on 80-element grids."""
    mat = Material.from_shear_modulus(G, 0.25)
    c = 5e-3
    a, b = c * math.sqrt(ab), c / math.sqrt(ab)
    d = 2 * 1.1 * max(a, b) / max(mx, my)
    ns = hertz_on_grid(a, b, mx, my, d, d, 52359.88, mat)
    k = coefficients(ns, mat, c)
    C11, C22, C23 = kalker_coefficients(ab, 0.25)
    assert k["C11"] == pytest.approx(C11, rel=0.02)
    assert k["C22"] == pytest.approx(C22, rel=0.02)
    assert k["C23_phi"] == pytest.approx(C23, rel=0.02)
    assert k["C23_eta"] == pytest.approx(C23, rel=0.02)


def test_converges_with_refinement():
    mat = Material.from_shear_modulus(G, 0.25)
    c = 5e-3
    errs = []
    for n in (20, 40, 80):
        d = 2.2 * c / n
        ns = hertz_on_grid(c, c, n, n, d, d, 52359.88, mat)
        errs.append(abs(coefficients(ns, mat, c)["C22"] / 3.67 - 1))
    assert errs[0] > errs[1] > errs[2]


@pytest.mark.parametrize("stick_fraction", [0.2, 0.5, 0.8])
def test_carter_2d(stick_fraction):
    """Carter (1926): cylinder rolling with longitudinal creepage.  A row of very long
    strip elements gives the plane-strain kernel.  Force and adhesion length to 1 %."""
    mat = Material(2.1e11, 0.28)
    R, P, mu = 0.3, 1e6, 0.3              # relative radius [m], load per length [N/m]
    a = math.sqrt(4 * P * R / (math.pi * mat.contact_modulus))
    p0 = 2 * P / (math.pi * a)
    mx = 200
    dx = 2.2 * a / mx
    x = (np.arange(mx) + 0.5) * dx - 1.1 * a
    y = np.array([0.0, 50.0])             # one loaded strip, 50 m long elements
    p = np.where(np.abs(x) < a, p0 * np.sqrt(np.clip(1 - (x / a) ** 2, 0, None)), 0.0)
    p = np.c_[p, np.zeros(mx)]
    s = stick_fraction
    xi = -(mu * a / R) * (1 - s)          # Carter: a'/a = 1 - R |xi| / (mu a)
    px, py, sx, sy, st, it, ok = steady_rolling(x, y, p > 0, mu * p, (xi, 0, 0),
                                                mat.shear_modulus, mat.poisson_ratio, 1e-8)
    assert ok
    Q = px[:, 0].sum() * dx               # on the rail; xi < 0 drags the rail forward
    assert Q == pytest.approx(mu * P * (1 - s * s), rel=0.01)
    assert st[:, 0].sum() * dx / (2 * a) == pytest.approx(s, abs=0.01)
    # the adhesion zone lies at the leading edge: x in [a - 2 a', a]
    xs = x[st[:, 0]]
    assert xs.min() >= a - 2 * s * a - 2 * dx and xs.max() <= a


def test_saturation_and_signs():
    mat = Material(2.1e11, 0.28)
    d = 2.2 * 5e-3 / 30
    ns = hertz_on_grid(5e-3, 5e-3, 30, 30, d, d, 5e4, mat)
    ex = get_tangential_model("exact")
    t = ex.solve(ns, None, mat, (-0.02, 0.01, 0.0), 0.3)
    assert math.hypot(t.fx, t.fy) == pytest.approx(0.3 * 5e4, rel=0.01)
    assert t.fx < 0 and t.fy > 0
    assert t.stick_fraction == 0.0
    assert t.converged
    # partial slip: between the linear and the saturated values
    t2 = ex.solve(ns, None, mat, (-1e-3, 0, 0), 0.3)
    assert -0.3 * 5e4 < t2.fx < 0 and 0 < t2.stick_fraction < 1


@pytest.mark.parametrize("q", [0.2, 0.5, 0.8])
def test_cattaneo_mindlin_shift(q):
    """Transient shift of two spheres (Mindlin 1949; Johnson 1985, eq. 7.42):
    delta = 3 mu P (2 - nu) / (8 G a) [1 - (1 - Q / mu P)^(2/3)], stick radius
    c = a (1 - Q / mu P)^(1/3)."""
    from railcontact.geometry import ContactGeometry
    from railcontact.normal import get_normal_model
    mat = Material(2.1e11, 0.28)
    R, P, mu = 0.1, 2e4, 0.3
    ns = get_normal_model("hertz", margin=0.05).solve(
        ContactGeometry(curvatures=(1 / (2 * R), 1 / (2 * R))), mat, normal_force=P,
        grid=(60, 60))
    a = ns.semi_axes[0]
    delta = 3 * mu * P * (2 - mat.poisson_ratio) / (8 * mat.shear_modulus * a) * \
        (1 - (1 - q) ** (2 / 3))
    t = get_tangential_model("exact", mode="shift").solve(ns, None, mat, (delta, 0, 0), mu)
    assert t.converged
    assert t.fx / (mu * P) == pytest.approx(q, rel=2e-3)      # the rail drags the wheel along
    c = math.sqrt(t.stick.sum() * ns.dx * ns.dy / math.pi)
    assert c / a == pytest.approx((1 - q) ** (1 / 3), rel=0.015)


def test_block_operator_equals_the_grid_operator_on_the_block():
    """The tangential solver works on the contact's bounding box: the operator of a
    block, cut from the grid's kernels, gives the grid operator's displacements
    (the extra row included) for tractions that vanish outside the block; the
    operator is that of the largest block with the same FFT size (12 x 8 for
    11 x 7), which serves the smaller one."""
    from railcontact.tangential.exact import _operators, _sub_operator
    mx, my, dx, dy, G, nu = 17, 12, 2e-4, 3e-4, 8e10, 0.28
    full, _ = _operators(mx, my, dx, dy, G, nu)
    i0, j0, ms, ns = 4, 3, 11, 7
    block = _sub_operator(mx, my, dx, dy, G, nu, ms, ns)
    assert (block.mx, block.my) == (12, 8)
    assert block is _sub_operator(mx, my, dx, dy, G, nu, 12, 8)
    rng = np.random.default_rng(8)
    qx, qy = rng.normal(size=(ms, ns)), rng.normal(size=(ms, ns))
    px, py = np.zeros((mx, my)), np.zeros((mx, my))
    px[i0:i0 + ms, j0:j0 + ns], py[i0:i0 + ms, j0:j0 + ns] = qx, qy
    ux, uy = full(px, py)
    bx, by = block(qx, qy)
    for u, b in ((ux, bx), (uy, by)):
        ref = u[i0:i0 + ms + 1, j0:j0 + ns]
        assert np.abs(b - ref).max() <= 1e-12 * np.abs(ref).max()


def test_compiled_block_operator_equals_the_grid_kernels_cut_to_the_block():
    """A new grid's set-up (issue 30): the compiled block operator (its kernels'
    spectra from the grid's element integrals, over the block's offsets alone) and
    the self terms of the rolling difference are those of the whole grid's kernels
    cut to the block, bit for bit, on grids and blocks of several sizes."""
    from railcontact.normal.influence import block_size
    from railcontact.tangential.exact import _block_operator, _elastic_block, _kernels
    rng = np.random.default_rng(30)
    for mx, my, ms, ns in ((17, 12, 11, 7), (40, 40, 22, 17), (9, 30, 9, 30), (5, 3, 1, 1)):
        dx, dy = rng.uniform(0.5e-4, 3e-4, 2)
        G, nu = 8e10 * rng.uniform(0.5, 1.5), rng.uniform(0.2, 0.4)
        bs = block_size(ms, ns, mx, my, extra_rows=1)
        ref = _block_operator(mx, my, dx, dy, G, nu, *bs)
        op, selfs = _elastic_block(mx, my, dx, dy, G, nu, *bs)
        assert op.shape == ref.shape and (op.mx, op.my, op.rows) == (ref.mx, ref.my, 1)
        for k in ("kxx", "kxy", "kyy"):
            assert np.array_equal(getattr(op, k), getattr(ref, k))
        assert selfs == _kernels(mx, my, dx, dy, G, nu)[1]


def test_warm_start_on_another_grid_is_the_bilinear_interpolation_bounded():
    """A warm start from a solution on another grid (a neighbouring case's): its
    tractions bilinear at this grid's centres (zero outside its own), inside the
    contact and scaled onto the bound where they exceed it, in one compiled loop:
    bit for bit the NumPy composition of ``bilinear`` and the bounding."""
    from types import SimpleNamespace
    from railcontact.normal.base import bilinear
    from railcontact.tangential.exact import _initial_tractions
    rng = np.random.default_rng(31)
    wx, wy = np.linspace(-4e-3, 4e-3, 30), np.linspace(-3e-3, 3.2e-3, 25)
    warm = SimpleNamespace(x=wx, y=wy, traction_x=rng.normal(size=(30, 25)) * 1e8,
                           traction_y=rng.normal(size=(30, 25)) * 1e8)
    x, y = np.linspace(-4.3e-3, 3.9e-3, 28) + 1e-5, np.linspace(-3.1e-3, 3.3e-3, 27)
    contact = rng.random((28, 27)) < 0.7
    bound = rng.random((28, 27)) * 1.5e8
    px, py = _initial_tractions(warm, x, y, contact, bound)
    tx = -bilinear(wx, wy, warm.traction_x, x[:, None], y[None, :])
    ty = -bilinear(wx, wy, warm.traction_y, x[:, None], y[None, :])
    mag = np.hypot(tx, ty)
    scale = np.where(mag > bound, bound / np.where(mag > 0, mag, 1.0), 1.0)
    assert np.array_equal(px, np.where(contact, tx * scale, 0.0))
    assert np.array_equal(py, np.where(contact, ty * scale, 0.0))
    assert (np.hypot(px, py) <= bound * (1 + 1e-15)).all()
    assert np.count_nonzero(px) > 0.5 * contact.sum()


def test_solution_on_the_contact_box_equals_the_whole_grid_solution():
    """Solving on the contact's bounding box gives the solution of the whole grid:
    the same problem placed in a grid twice as large (zero bound outside) has the
    same tractions and slip, to rounding."""
    from railcontact.tangential.exact import steady_rolling
    n, dx = 16, 1e-3 / 8
    x = (np.arange(n) - (n - 1) / 2) * dx
    X, Y = np.meshgrid(x, x, indexing="ij")
    contact = X ** 2 + (Y / 0.8) ** 2 < (0.95e-3) ** 2
    bound = 0.3 * 1e9 * np.sqrt(np.clip(1 - (X / 1e-3) ** 2 - (Y / 0.8e-3) ** 2, 0, None))
    bound = np.where(contact, bound, 0.0)
    args = ((1e-3, -5e-4, 0.3), 8e10, 0.28, 1e-9)
    px, py, sx, sy, stick, it, ok = steady_rolling(x, x, contact, bound, *args)
    # the larger grid's elements 5.. and 3.. lie where the small grid's do (the spin
    # enters through the coordinates)
    bx, by = x[0] + (np.arange(2 * n) - 5) * dx, x[0] + (np.arange(2 * n) - 3) * dx
    pad = ((5, n - 5), (3, n - 3))
    r = steady_rolling(bx, by, np.pad(contact, pad), np.pad(bound, pad), *args)
    assert ok and r[-1]
    box = (slice(5, 5 + n), slice(3, 3 + n))
    scale = bound.max()
    assert np.abs(r[0][box] - px).max() <= 1e-8 * scale
    assert np.abs(r[1][box] - py).max() <= 1e-8 * scale
    assert np.array_equal(r[4][box], stick)


def _mindlin_shift(q, mu, P, nu, G, a):
    """Mindlin's shift of two identical spheres at a tangential force q mu P [m]."""
    return 3 * mu * P * (2 - nu) / (8 * G * a) * (1 - (1 - q) ** (2 / 3))


def test_transient_shift_loading_and_unloading():
    """Cattaneo's shift curve step by step (T = 1, each step from the last one's
    tractions): loading to Q* = 0.8 mu P in four steps follows Mindlin's curve
    (Johnson 1985, eq. 7.42) and its stick radius c/a = (1 - Q/mu P)^(1/3); unloading
    from it follows Mindlin & Deresiewicz, delta = delta* - 2 delta_M((Q* - Q)/2)
    (Johnson eq. 7.49), which a solve from the unloaded state cannot give.
    Measured on 40 x 40 elements: forces within 0.4 % of mu P, stick radius 2.5 %."""
    from railcontact.tangential.exact import previous_displacement, transient_step
    mat = Material(2.1e11, 0.28)
    G, nu = mat.shear_modulus, mat.poisson_ratio
    a, P, mu, n = 5e-3, 5e4, 0.3, 40
    d = 2.2 * a / n
    ns = hertz_on_grid(a, a, n, n, d, d, P, mat)
    contact, bound = ns.contact, mu * ns.pressure
    zero = np.zeros(contact.shape)
    prev = None

    total = [0.0]

    def step(delta):
        """To the total shift delta: the rigid shift of the step is the increment."""
        nonlocal prev
        inc, total[0] = delta - total[0], delta
        if prev is None:
            u, p0 = (zero, zero), None
        else:
            u = previous_displacement(prev[0], prev[1], (0, 0), contact.shape, d, d, G, nu)
            p0 = prev
        px, py, sx, sy, st, it, ok = transient_step(ns.x, ns.y, contact, bound,
                                                    (inc, 0.0), u, G, nu, 1e-9, 100, p0=p0)
        assert ok
        prev = (px, py)
        return -px.sum() * d * d / (mu * P), st

    for q in (0.2, 0.4, 0.6, 0.8):
        f, st = step(_mindlin_shift(q, mu, P, nu, G, a))
        assert f == pytest.approx(q, abs=4e-3)
        c = math.sqrt(st.sum() * d * d / math.pi)
        assert c / a == pytest.approx((1 - q) ** (1 / 3), rel=0.025)
    top = _mindlin_shift(0.8, mu, P, nu, G, a)
    totals = []
    for q in (0.4, 0.0, -0.4):
        totals.append(top - 2 * _mindlin_shift((0.8 - q) / 2, mu, P, nu, G, a))
        f, _ = step(totals[-1])
        assert f == pytest.approx(q, abs=4e-3)
    # a solve from the unloaded state at the first unloading step's total shift has
    # the loading curve's force, 0.513 mu P against the unloading curve's 0.4
    px, *_ = transient_step(ns.x, ns.y, contact, bound, (totals[0], 0.0), (zero, zero), G,
                            nu, 1e-9, 100)
    assert -px.sum() * d * d / (mu * P) == pytest.approx(0.513, abs=5e-3)


def test_transient_rolling_reaches_the_steady_state():
    """Transient rolling (T = 2) of a sphere from rest at a prescribed creepage: the
    tractions of each step enter the next one's slip at the material points one
    step DQ = dx upstream.  The force grows from Cattaneo's shift of xi dx in the
    first step to the steady rolling force of the same grid
    (:func:`steady_rolling`), which it reaches as the material passes the contact
    (the creepage prescribed, the bodies' bulk displacement builds up over several
    contact lengths).  Measured on 30 x 30 elements, xi = -1e-3: F_x 0.4931 mu F_n
    steady; after 4 contact lengths 3.6e-4 mu F_n below it, after 6 9e-6."""
    from railcontact.tangential.exact import previous_displacement, transient_step
    mat = Material(2.1e11, 0.28)
    Gm, nu = mat.shear_modulus, mat.poisson_ratio
    a, P, mu, n = 5e-3, 5e4, 0.3, 30
    d = 2.2 * a / n
    ns = hertz_on_grid(a, a, n, n, d, d, P, mat)
    contact, bound = ns.contact, mu * ns.pressure
    xi = -1e-3
    steady = steady_rolling(ns.x, ns.y, contact, bound, (xi, 0, 0), Gm, nu, 1e-9)
    q_steady = steady[0].sum() * d * d / (mu * P)
    zero = np.zeros(contact.shape)
    prev, q = None, []
    for _ in range(int(6 * 2 * a / d)):
        u = (zero, zero) if prev is None else previous_displacement(
            prev[0], prev[1], (1, 0), contact.shape, d, d, Gm, nu)
        px, py, *_, ok = transient_step(ns.x, ns.y, contact, bound, (xi * d, 0.0), u, Gm, nu,
                                        1e-9, 100, p0=prev)
        assert ok
        prev = (px, py)
        q.append(px.sum() * d * d / (mu * P))
    assert q_steady == pytest.approx(0.4931, abs=1e-3)
    assert 0 < q[0] < 0.05 and all(b > c for b, c in zip(q[1:], q[:-1]))
    assert q[-1] == pytest.approx(q_steady, abs=1e-4)


def test_previous_displacement_on_the_same_grid_is_the_operator():
    """u' on the same grid (offset 0) and one row upstream (offset 1) equals the
    steady solver's FFT operator (rows 0 .. mx-1 and 1 .. mx)."""
    from railcontact.normal.influence import TangentialOperator, tangential_kernels
    from railcontact.tangential.exact import grid_offset, previous_displacement
    rng = np.random.default_rng(3)
    mx, my, dx, dy = 9, 7, 1e-4, 1.5e-4
    px, py = rng.normal(size=(mx, my)), rng.normal(size=(mx, my))
    op = TangentialOperator(tangential_kernels(mx, my, dx, dy, G, 0.3, extra_rows=1), mx, my)
    ux, uy = op(px, py)
    for off in (0, 1):
        vx, vy = previous_displacement(px, py, (off, 0), (mx, my), dx, dy, G, 0.3)
        assert np.allclose(vx, ux[off:off + mx], rtol=1e-10, atol=1e-12 * abs(ux).max())
        assert np.allclose(vy, uy[off:off + mx], rtol=1e-10, atol=1e-12 * abs(uy).max())
    assert grid_offset((0.0, 0.0), (2.5e-4, -1e-4), (1e-4, 1e-4), (0.5e-4, 0.0)) == (3, -1)
    with pytest.raises(Exception, match="whole elements"):
        grid_offset((0.0, 0.0), (0.25e-4, 0.0), (1e-4, 1e-4))


def test_transient_mode_of_the_model():
    """``get_tangential_model("exact", mode="transient", step=...)`` with
    ``solve(..., previous=...)``: Cattaneo's loading in two steps of shift (step 0)
    lands on Mindlin's curve as the one-shot shift does; shifting back to the first
    step's position gives the unloading curve's 0.272 mu P (Mindlin & Deresiewicz),
    not the loading curve's 0.4; rolling steps (step = dx) from rest raise the
    force towards the steady one.  Measured on 30 x 30 elements: 0.4 and 0.8 within
    0.4 % of mu P, unloading 0.2724 against 0.2724."""
    from railcontact.core.errors import InputError
    mat = Material(2.1e11, 0.28)
    a, P, mu, n = 5e-3, 5e4, 0.3, 30
    d = 2.2 * a / n
    ns = hertz_on_grid(a, a, n, n, d, d, P, mat)
    G, nu = mat.shear_modulus, mat.poisson_ratio
    shift = get_tangential_model("exact", mode="transient", tol=1e-8)
    half, full = (_mindlin_shift(q, mu, P, nu, G, a) for q in (0.4, 0.8))
    s1 = shift.solve(ns, None, mat, (half, 0, 0), mu)
    s2 = shift.solve(ns, None, mat, (full - half, 0, 0), mu, previous=s1)
    assert s1.fx / (mu * P) == pytest.approx(0.4, abs=4e-3)
    assert s2.fx / (mu * P) == pytest.approx(0.8, abs=4e-3)
    # the shift back to half the total: the unloading curve, 0.8 - 2 q((delta* - delta)/2)
    s3 = shift.solve(ns, None, mat, (half - full, 0, 0), mu, previous=s2)
    c = _mindlin_shift(1.0, mu, P, nu, G, a)            # the shift scale C
    q_half = 1 - (1 - (full - half) / (2 * c)) ** 1.5    # delta_M(q_half) = (full - half)/2
    q_back = 0.8 - 2 * q_half                             # 0.272
    assert s3.fx / (mu * P) < s1.fx / (mu * P) - 0.05
    assert s3.fx / (mu * P) == pytest.approx(q_back, abs=6e-3)
    roll = get_tangential_model("exact", mode="transient", step=d, tol=1e-8)
    r, forces = None, []
    for _ in range(3):
        r = roll.solve(ns, None, mat, (-1e-3, 0, 0), mu, previous=r)
        forces.append(r.fx)
    # on the wheel: xi < 0 pulls it back
    assert 0 > forces[0] > forces[1] > forces[2] and r.options["step"] == d
    with pytest.raises(InputError, match="'transient' mode"):
        get_tangential_model("exact").solve(ns, None, mat, (1e-3, 0, 0), mu, previous=r)
    with pytest.raises(InputError, match="step"):
        get_tangential_model("exact", mode="transient", step=-1.0)


def test_transient_mode_extra_slip_is_read_as_the_creepages():
    """The ``"transient"`` mode's ``extra_slip`` (a conformal patch's part of the
    rigid slip) is read as its creepages: in a shift (step 0) a shift [m] per
    element, in rolling times the step.  A uniform extra slip equals the same
    creepage added: the forces agree to 1e-9 of mu P."""
    mat = Material(2.1e11, 0.28)
    a, P, mu, n = 5e-3, 5e4, 0.3, 16
    d = 2.2 * a / n
    ns = hertz_on_grid(a, a, n, n, d, d, P, mat)
    ones = np.ones((n, n))
    for step, c in ((0.0, 2e-6), (d, 4e-4)):
        m = get_tangential_model("exact", mode="transient", step=step, tol=1e-10)
        ref = m.solve(ns, None, mat, (c, c / 2, 0.0), mu)
        got = m.solve(ns, None, mat, (0.0, c / 2, 0.0), mu, extra_slip=(c * ones, 0.0 * ones))
        assert (got.fx, got.fy) == pytest.approx((ref.fx, ref.fy), abs=1e-9 * mu * P)
        assert abs(ref.fx) > 0.01 * mu * P


def test_friction_varying_across_the_patch():
    """``friction_scale``: each element's coefficient friction times the array.
    Ones give the uniform solution; in full sliding each element carries its own
    mu p, so that a coefficient rising along x (0.2 at the rear to 0.3 at the front
    of the patch) gives F = sum mu_i p_i dA; a bad array is refused."""
    from railcontact.core.errors import InputError
    mat = Material(2.1e11, 0.28)
    d = 2.2 * 5e-3 / 30
    ns = hertz_on_grid(5e-3, 5e-3, 30, 30, d, d, 5e4, mat)
    ex = get_tangential_model("exact")
    assert "friction-field" in ex.capabilities
    plain = ex.solve(ns, None, mat, (-1e-3, 0, 0), 0.3)
    ones = ex.solve(ns, None, mat, (-1e-3, 0, 0), 0.3, friction_scale=np.ones_like(ns.pressure))
    assert ones.fx == pytest.approx(plain.fx, rel=1e-9)
    scale = np.broadcast_to(np.interp(ns.x, [ns.x[0], ns.x[-1]], [0.2, 0.3])[:, None] / 0.25,
                            ns.pressure.shape)
    slid = ex.solve(ns, None, mat, (-0.05, 0, 0), 0.25, friction_scale=scale)
    dA = (ns.x[1] - ns.x[0]) * (ns.y[1] - ns.y[0])
    assert slid.fx == pytest.approx(-(0.25 * scale * ns.pressure).sum() * dA, rel=1e-4)
    assert slid.friction == 0.25
    with pytest.raises(InputError, match="friction_scale of shape"):
        ex.solve(ns, None, mat, (-1e-3, 0, 0), 0.3, friction_scale=np.ones(3))


# ------------------------------------------ interfacial layer (CONTACT's M = 4)
def _one_element(mu_pn=1e9):
    """A 3 x 3 grid of 1 mm elements with only the centre one in contact, its
    friction bound ``mu_pn`` [Pa], and its own flexibility c [m/Pa] (shift)."""
    from railcontact.tangential.exact import _self_terms
    d = 1e-3
    x = (np.arange(3) - 1.0) * d
    contact = np.zeros((3, 3), bool)
    contact[1, 1] = True
    bound = np.where(contact, mu_pn, 0.0)
    c = _self_terms(3, 3, d, d, G, 0.28)[0]
    return x, contact, bound, c


def test_layer_of_zero_thickness_without_yield_is_the_elastic_solution():
    """A layer of zero thickness that never yields changes nothing: the tractions
    equal the elastic solver's to the last bit (steady rolling, 24 x 24 Hertz)."""
    from railcontact.core.materials import InterfaceLayer
    mat = Material(2.1e11, 0.28)
    ns = hertz_on_grid(4e-3, 3e-3, 24, 24, 3.6e-4, 2.7e-4, 3e4, mat)
    plain = get_tangential_model("exact").solve(ns, None, mat, (1e-3, 5e-4, 0.2), 0.3)
    layered = get_tangential_model("exact", layer=InterfaceLayer()).solve(
        ns, None, mat, (1e-3, 5e-4, 0.2), 0.3)
    assert np.array_equal(plain.traction_x, layered.traction_x)
    assert np.array_equal(plain.traction_y, layered.traction_y)


def test_layer_flexibility_and_hardening_of_one_element():
    """One element shifted by W (CONTACT's plastic_3bl): without yield its traction
    is W / (c + f), the bodies' own flexibility c and the layer's f = h3/G3 in
    series; past the yield limit tau_c0 it hardens, |p| = (tau_c0 + k W) /
    (1 + k (c + f)) (the flow W - (c + f)|p| raising the limit by k per metre);
    a yield limit above the friction bound leaves Coulomb's mu p_n."""
    from railcontact.core.materials import InterfaceLayer
    from railcontact.tangential.exact import layer_bound, transient_step
    x, contact, bound, c = _one_element()
    zero = np.zeros((3, 3))
    f = 0.02e-3 / 106.25e6                                  # 20 um of clay, G3 = 106 MPa

    def shift(layer, W):
        lb = layer_bound(layer, bound)
        px, *_ , ok = transient_step(x, x, contact, lb, (W, 0.0), (zero, zero), G, 0.28,
                                     1e-12, 100)
        assert ok
        return -px[1, 1]

    W = 5e-6
    assert shift(InterfaceLayer(0.02e-3, 106.25e6), W) == pytest.approx(W / (c + f), rel=1e-9)
    clay = InterfaceLayer(0.02e-3, 106.25e6, 200e6, 435e9)
    W = 60e-6                                                # past the yield at 40 um
    expected = (200e6 + 435e9 * W) / (1 + 435e9 * (c + f))
    assert shift(clay, W) == pytest.approx(expected, rel=1e-9)
    assert shift(InterfaceLayer(0.02e-3, 106.25e6, 2e9, 435e9), 1e-3) == pytest.approx(
        1e9, rel=1e-12)


def test_perfectly_plastic_layer_in_full_sliding():
    """In full sliding the traction lies on min(mu p_n, tau_c0): a perfectly plastic
    layer (k_tau = 0) caps the friction bound where mu p_n exceeds the yield limit,
    and the creep force is the sum of the caps (steady rolling, 24 x 24 Hertz)."""
    from railcontact.core.materials import InterfaceLayer
    mat = Material(2.1e11, 0.28)
    ns = hertz_on_grid(4e-3, 3e-3, 24, 24, 3.6e-4, 2.7e-4, 3e4, mat)
    tau, mu = 150e6, 0.3
    layer = InterfaceLayer(0.0, 1e9, tau, 0.0)
    t = get_tangential_model("exact", layer=layer).solve(ns, None, mat, (0.05, 0, 0), mu)
    cap = np.minimum(mu * ns.pressure, tau) * ns.contact
    dA = (ns.x[1] - ns.x[0]) * (ns.y[1] - ns.y[0])
    assert t.converged and not t.stick[ns.contact].any()
    assert np.abs(np.hypot(t.traction_x, t.traction_y) - cap).max() <= 1e-6 * tau
    # the slip turns from x by the lateral displacements (up to 2.4 mrad here): F_x
    # (on the wheel) within 1e-5 of the caps' sum (measured 1.9e-6)
    assert t.fx == pytest.approx(cap.sum() * dA, rel=1e-5)
    # the cap binds: well under Coulomb's full sliding force
    assert t.fx < 0.8 * mu * ns.pressure.sum() * dA


def test_layer_option_from_a_case_file():
    """``tangential_options = {layer = {...}}`` (a case file's table) builds the
    InterfaceLayer; an unknown key or value stops with one line naming it."""
    from railcontact.core.errors import InputError
    from railcontact.core.materials import InterfaceLayer
    m = get_tangential_model("exact", layer={"thickness": 2e-5, "shear_modulus": 8.2e8,
                                             "yield_stress": 6e7, "hardening": 1e12})
    assert m.layer == InterfaceLayer(2e-5, 8.2e8, 6e7, 1e12)
    with pytest.raises(InputError, match="layer keys.*'yield'"):
        get_tangential_model("exact", layer={"yield": 6e7})
    with pytest.raises(InputError, match="layer.shear_modulus"):
        get_tangential_model("exact", layer={"shear_modulus": -1.0})


def test_transient_mode_carries_the_plastic_displacement():
    """``mode="transient"`` with a hardening layer: the plastic displacement of a
    step comes with its solution (``options["plastic_displacement"]``) and the next
    step's yield limit starts from it, so two shifts W1, W2 in one direction give
    one shift W1 + W2's traction, (tau_c0 + k (W1 + W2)) / (1 + k (c + f))."""
    from railcontact.core.materials import InterfaceLayer
    x, contact, bound, c = _one_element()
    mu = 0.5
    ns = NormalSolution("exact", x, x, bound / mu, contact, 0.0, float(bound.max() / mu),
                        0.0, float(bound.sum() / mu * 1e-6))
    clay = InterfaceLayer(0.02e-3, 106.25e6, 200e6, 435e9)
    model = get_tangential_model("exact", mode="transient", tol=1e-9, layer=clay)
    mat = Material.from_shear_modulus(G, 0.28)
    s1 = model.solve(ns, None, mat, (50e-6, 0, 0), mu)
    s2 = model.solve(ns, None, mat, (30e-6, 0, 0), mu, previous=s1)
    k, ct = 435e9, c + clay.flexibility
    u1 = s1.options["plastic_displacement"][1, 1]
    # (the solution's tractions act on the wheel: + where the rail's are -)
    assert s1.traction_x[1, 1] == pytest.approx((200e6 + k * 50e-6) / (1 + k * ct), rel=1e-9)
    assert u1 == pytest.approx(50e-6 - ct * s1.traction_x[1, 1], rel=1e-9)
    assert s2.traction_x[1, 1] == pytest.approx((200e6 + k * 80e-6) / (1 + k * ct), rel=1e-9)


def test_friction_scale_per_column_and_extra_slip():
    """``friction_scale`` per column and ``extra_slip`` (conformal patches): a uniform
    scale of one is the scalar coefficient; full sliding saturates at the field's coefficients column
    by column (0.2 on one half, 0.4 on the other: |F| = 0.3 F_n for a symmetric
    pressure); a uniform extra slip (a, b) is the creepages (xi + a, eta + b)."""
    mat = Material(2.1e11, 0.28)
    d = 2.2 * 5e-3 / 30
    ns = hertz_on_grid(5e-3, 5e-3, 30, 30, d, d, 5e4, mat)
    ex = get_tangential_model("exact")
    ref = ex.solve(ns, None, mat, (-1e-3, 0.0, 0.0), 0.3)
    same = ex.solve(ns, None, mat, (-1e-3, 0.0, 0.0), 0.3,
                    friction_scale=np.full((1, 30), 1.0))
    assert same.fx == pytest.approx(ref.fx, rel=1e-9)
    half = np.where(np.arange(30) < 15, 0.2, 0.4)[None, :] / 0.3
    slide = ex.solve(ns, None, mat, (-0.05, 0.0, 0.0), 0.3, friction_scale=half)
    assert -slide.fx == pytest.approx(0.3 * 5e4, rel=0.01)
    assert slide.traction_x[:, :15].sum() == pytest.approx(0.5 * slide.traction_x[:, 15:].sum(),
                                                           rel=0.01)
    shifted = ex.solve(ns, None, mat, (-1e-3, 0.0, 0.0), 0.3,
                       extra_slip=(np.full((30, 30), 4e-4), np.full((30, 30), -2e-4)))
    moved = ex.solve(ns, None, mat, (-6e-4, -2e-4, 0.0), 0.3)
    assert shifted.fx == pytest.approx(moved.fx, rel=1e-6)
    assert shifted.fy == pytest.approx(moved.fy, rel=1e-6)
    with pytest.raises(Exception, match="friction_scale"):
        ex.solve(ns, None, mat, (-1e-3, 0.0, 0.0), 0.3, friction_scale=np.full((1, 30), -1.0))


def test_leading_edge_fraction_and_boundary_element():
    """CONTACT's leading-edge rule on a row in contact from x index 3 to 10 and a
    step of 4 elements: the last element ahead x_0 = 10, the edge at x_0 + dx; the
    elements 10, 9, 8 were in the contact 1/4, 2/4, 3/4 of the step, the rest all
    of it; their previous displacement is taken at element 11.  Rolling towards -x
    mirrors it; a step of one element changes nothing; the last two columns keep
    f = 1."""
    from railcontact.tangential.exact import leading_edge, leading_edge_slip
    contact = np.zeros((16, 2), bool)
    contact[3:11, 0] = True
    facdt, edge = leading_edge(contact, 1e-3, 4e-3)
    assert facdt[:, 0].tolist() == [1.0] * 8 + [0.75, 0.5, 0.25] + [1.0] * 5
    assert (edge[8:11, 0] == 11).all() and (edge[:8] == -1).all() and (edge[11:] == -1).all()
    assert (facdt[:, 1] == 1.0).all() and (edge[:, 1] == -1).all()
    back, eb = leading_edge(contact, 1e-3, -4e-3)
    assert back[:, 0].tolist() == [1.0] * 3 + [0.25, 0.5, 0.75] + [1.0] * 10
    assert (eb[3:6, 0] == 2).all()
    one = leading_edge(contact, 1e-3, 1e-3)
    assert (one[0] == 1.0).all() and (one[1] == -1).all()
    wide = np.zeros((8, 1), bool)
    wide[2:, 0] = True
    f, e = leading_edge(wide, 1.0, 4.0)
    assert f[:, 0].tolist() == [1.0, 1.0, 1.0, 1.0, 1.0, 0.75, 1.0, 1.0]
    assert e[5, 0] == -2                              # edge beyond the grid: u_b = 0
    w = (np.full(contact.shape, 2.0), np.full(contact.shape, -1.0))
    u = (np.full(contact.shape, 5.0), np.zeros(contact.shape))
    here = (np.arange(16.0)[:, None] * np.ones((1, 2)), np.zeros(contact.shape))
    (wx, wy), (ux, uy) = leading_edge_slip(contact, 1e-3, 4e-3, w, u, here)
    assert wx[8:11, 0].tolist() == [1.5, 1.0, 0.5] and wy[10, 0] == -0.25
    assert ux[8:11, 0].tolist() == [11.0] * 3 and ux[7, 0] == 5.0 and wx[7, 0] == 2.0


def test_rolling_step_from_rest_leading_edge():
    """The first rolling step from rest (no previous tractions): with a step of one
    element every element has been in the contact the whole step, and the force is
    the shift's of the same rigid shift (to 1e-9 of mu P); with a step of 4
    elements the material within the step of the leading edge takes its fraction
    of the shift (CONTACT's m1_trans_dqrel): a smaller force, less traction on the
    leading (+x) half than on the trailing one."""
    mat = Material(2.1e11, 0.28)
    a, P, mu, n = 5e-3, 5e4, 0.3, 30
    d = 2.2 * a / n
    ns = hertz_on_grid(a, a, n, n, d, d, P, mat)
    xi = -1e-3
    shift = get_tangential_model("exact", mode="transient", tol=1e-9)
    for k in (1, 4):
        roll = get_tangential_model("exact", mode="transient", step=k * d, tol=1e-9)
        r = roll.solve(ns, None, mat, (xi, 0, 0), mu)
        s = shift.solve(ns, None, mat, (xi * k * d, 0, 0), mu)
        if k == 1:
            assert r.fx == pytest.approx(s.fx, abs=1e-9 * mu * P)
        else:
            assert abs(r.fx) < abs(s.fx) - 1e-3 * mu * P
            # the leading (+x) half carries less traction than the trailing one
            mid = n // 2
            lead, trail = abs(r.traction_x[mid:].sum()), abs(r.traction_x[:mid].sum())
            assert lead < 0.95 * trail
