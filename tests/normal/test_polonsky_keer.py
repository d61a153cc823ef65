"""The constrained conjugate gradient of Polonsky & Keer
(railcontact.normal.polonsky_keer): a Hertz circle on a grid, the pressure limit,
the direct corrections of its products, and its convergence flag (a solution's
contact conditions; a missed surface's gap left out of the gap scale)."""

import math

import numpy as np
import pytest

from railcontact.core.errors import InputError
from railcontact.core.materials import Material
from railcontact.normal.influence import normal_operator
from railcontact.normal import polonsky_keer as pk
from railcontact.normal.polonsky_keer import MISSED_GAP, gap_scale, polonsky_keer

MAT = Material(2.1e11, 0.28)
R, F = 0.3, 1e4                       # sphere on a plane (equal curvatures 1/R)


@pytest.fixture(scope="module")
def sphere():
    E = MAT.contact_modulus
    a = (3 * F * R / (4 * E)) ** (1 / 3)
    n = 41
    x = np.linspace(-1.5 * a, 1.5 * a, n)
    dx = x[1] - x[0]
    X, Y = np.meshgrid(x, x, indexing="ij")
    h = (X ** 2 + Y ** 2) / (2 * R)
    return a, dx, h, normal_operator(n, n, dx, dx, E)


def test_hertz_circle_force_controlled(sphere):
    """Hertz: a = (3 F R / 4 E*)^(1/3), p0 = 3 F / (2 pi a^2), approach a^2 / R; on a
    41 x 41 grid over 3a (27 elements across the contact)."""
    a, dx, h, op = sphere
    p, approach, it, ok = polonsky_keer(op, h, dx * dx, force=F)
    assert ok and it < 100
    assert p.sum() * dx * dx == pytest.approx(F, rel=1e-9)
    assert p.max() == pytest.approx(3 * F / (2 * math.pi * a * a), rel=2e-3)
    assert approach == pytest.approx(a * a / R, rel=1e-3)
    assert (p > 0).sum() * dx * dx == pytest.approx(math.pi * a * a, rel=0.03)  # O(dx)
    assert p.min() >= 0.0


def test_displacement_controlled_and_pressure_limit(sphere):
    a, dx, h, op = sphere
    p0, delta = 3 * F / (2 * math.pi * a * a), a * a / R
    p, approach, _, ok = polonsky_keer(op, h - delta, dx * dx)
    assert ok and approach == 0.0
    assert p.sum() * dx * dx == pytest.approx(F, rel=2e-3)
    limit = 0.8 * p0
    pl, _, _, ok = polonsky_keer(op, h - delta, dx * dx, pressure_limit=limit)
    assert ok
    assert pl.max() == pytest.approx(limit, rel=1e-12)
    assert (pl >= limit * (1 - 1e-12)).sum() > 100          # a plastic core
    # the capped contact carries less at the same approach, but more than the cap
    # removes on the elastic solution alone (the contact widens)
    assert pl.sum() < p.sum()
    assert pl.sum() > np.minimum(p, limit).sum()
    with pytest.raises(InputError, match="pressure limit"):
        polonsky_keer(op, h - delta, dx * dx, pressure_limit=0.0)
    with pytest.raises(InputError, match="approach given"):
        polonsky_keer(op, h, dx * dx, force=F, pressure_limit=limit)
    with pytest.raises(InputError, match="regions"):
        polonsky_keer(op, h, dx * dx, force=F, regions=(np.zeros(3), np.ones((1, 1))))


def test_direct_displacements_of_a_few_elements_equal_the_convolution():
    """Polonsky-Keer adds the displacements of the few elements clipped or loaded in
    a step by a direct sum over the kernel: equal to the FFT product of those
    changes, on a block smaller than its operator's (whose kernel it uses)."""
    from railcontact.normal.polonsky_keer import _add_direct
    from railcontact.normal.influence import normal_operator_block
    mx, my, dx, dy, E = 30, 26, 1e-4, 1.5e-4, MAT.contact_modulus
    op = normal_operator_block(mx, my, dx, dy, E, 11, 9)      # serves 11 x 9 in a 12 x 9
    assert op.kernel.shape == (2 * op.mx - 1, 2 * op.my - 1)
    rng = np.random.default_rng(5)
    u = rng.random((11, 9))
    idx = np.array([0, 17, 50, 98])                           # corners and inside
    dq = rng.normal(size=idx.size) * 1e8
    d = np.zeros(11 * 9)
    d[idx] = dq
    u0 = u.copy()
    expected = u + 0.7 * op(d.reshape(11, 9))
    cols, fm = np.zeros(9, dtype=np.int64), np.ones((1, 1))
    _add_direct(u, 0.7, idx, dq, op.kernel, cols, fm, np.zeros((0, 9)))
    assert np.abs(u - expected).max() <= 1e-12 * np.abs(expected).max()
    # with Blanco's column modulation (cos, sin of each column's inclination) the
    # direct sum equals the modulated FFT product
    from railcontact.normal.conformal_influence import blanco_normal_operator
    mop = blanco_normal_operator(op, np.linspace(-0.8, 0.5, 9))
    expected = u0 + 0.7 * mop(d.reshape(11, 9))
    _add_direct(u0, 0.7, idx, dq, op.kernel, cols, fm, mop.modulation)
    assert np.abs(u0 - expected).max() <= 1e-12 * np.abs(expected).max()


def test_flat_punch_stiffness_of_a_circle_is_twice_e_star_a():
    """A rigid flat circular punch of radius a: K = 2 E* a (Boussinesq; Johnson
    1985, eq. 3.36); on 41 x 41 elements with the circle's staircase edge, within
    3 %, and the CG residual met."""
    from railcontact.normal.polonsky_keer import flat_punch_stiffness
    E = MAT.contact_modulus
    a, n = 1e-3, 41
    x = np.linspace(-1.2 * a, 1.2 * a, n)
    dx = x[1] - x[0]
    X, Y = np.meshgrid(x, x, indexing="ij")
    mask = X ** 2 + Y ** 2 <= a ** 2
    # the staircase's own area as the circle's: a_eq = sqrt(area / pi)
    a_eq = math.sqrt(mask.sum() * dx * dx / math.pi)
    K, it, ok = flat_punch_stiffness(normal_operator(n, n, dx, dx, E), mask, dx * dx)
    assert ok and 0 < it < 200
    assert K == pytest.approx(2 * E * a_eq, rel=0.03)


def test_flat_punch_stiffness_is_the_derivative_of_the_load(sphere):
    """On the sphere's converged contact, the stiffness equals dF/d(delta) of
    displacement-controlled solves on the same grid (central difference of 1e-4 of
    the approach: the contact set unchanged) to 1e-5, and Hertz's 3/2 F/delta to
    1 %."""
    from railcontact.normal.polonsky_keer import flat_punch_stiffness
    a, dx, h, op = sphere
    p, delta, _, ok = polonsky_keer(op, h, dx * dx, force=F, tol=1e-10)
    assert ok
    K, _, ok = flat_punch_stiffness(op, p > 0, dx * dx)
    assert ok
    e = 1e-4 * delta
    loads = [polonsky_keer(op, h - (delta + s * e), dx * dx, tol=1e-12, p0=p)[0].sum() * dx * dx
             for s in (1, -1)]
    assert K == pytest.approx((loads[0] - loads[1]) / (2 * e), rel=1e-5)
    assert K == pytest.approx(1.5 * F / delta, rel=0.01)


def _lifted_start(sphere):
    """The solution of the sphere with the grid beyond 0.6 a lifted away: a
    pressure that meets the contact conditions there but not on the sphere (its
    annulus 0.6 a < r < a overlaps unloaded)."""
    a, dx, h, op = sphere
    delta = a * a / R
    n = h.shape[0]
    x = (np.arange(n) - (n - 1) / 2) * dx
    r = np.hypot(x[:, None], x[None, :])
    lifted = np.where(r > 0.6 * a, 1e-3, h - delta)
    p, _, _, ok = polonsky_keer(op, lifted, dx * dx)
    assert ok
    return p, h - delta


def test_a_pressure_that_is_no_solution_is_never_converged(sphere, monkeypatch):
    """Whatever the iteration's own test says, the result is flagged converged only
    where the final pressure meets the contact conditions (t1_zws_pos, case 1: a
    collapsed pressure was flagged converged).  The iteration is replaced by one
    that claims convergence at once and leaves its start: a start that is no
    solution is reported as not converged, a solution as converged."""
    a, dx, h, op = sphere
    wrong, gap = _lifted_start(sphere)
    right, _, _, ok = polonsky_keer(op, gap, dx * dx, tol=1e-9)
    assert ok
    monkeypatch.setattr(pk, "_pk_kernel", lambda *args: (0.0, 1, True))
    assert not polonsky_keer(op, gap, dx * dx, p0=wrong, tol=1e-5)[3]
    assert not polonsky_keer(op, gap, dx * dx, p0=np.zeros_like(gap), tol=1e-5)[3]
    assert polonsky_keer(op, gap, dx * dx, p0=right, tol=1e-5)[3]
    # force-controlled: the approach is the mean gap over the loaded elements
    assert polonsky_keer(op, h, dx * dx, force=right.sum() * dx * dx, p0=right, tol=1e-5)[3]
    assert not polonsky_keer(op, h, dx * dx, force=wrong.sum() * dx * dx, p0=wrong,
                             tol=1e-5)[3]


def test_a_missed_surface_leaves_the_gap_scale(sphere):
    """A grid column where a surface was missed (the geometry layer's 1 m gap) does
    not set the gap scale of the iteration's test (it would loosen it a
    million-fold): the solution is that of the grid without the column, to the
    tolerance."""
    a, dx, h, op = sphere
    gap = h - a * a / R
    missed = gap.copy()
    missed[:, 0] = 1.0
    assert MISSED_GAP <= 1.0
    assert gap_scale(missed) == pytest.approx(float(np.max(np.abs(gap[:, 1:]))), rel=1e-12)
    p, _, _, ok = polonsky_keer(op, gap, dx * dx, tol=1e-6)
    q, _, _, ok2 = polonsky_keer(op, missed, dx * dx, tol=1e-6)
    assert ok and ok2
    assert q.sum() == pytest.approx(p.sum(), rel=1e-5)


def test_gap_scale_is_the_largest_found_gap():
    """The compiled gap scale: the largest |h| where both surfaces were found
    (h < MISSED_GAP), or the largest |h| where none was."""
    rng = np.random.default_rng(2)
    for _ in range(20):
        h = rng.normal(0.0, 1e-3, (9, 11))
        h[rng.random(h.shape) < 0.2] = 1.0
        found = np.abs(h[h < MISSED_GAP])
        assert gap_scale(h) == float(found.max())
    assert gap_scale(np.full((3, 3), 1.0)) == 1.0
    assert gap_scale(np.array([[-2.0, 0.7]])) == 2.0
