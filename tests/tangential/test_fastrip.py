"""FaStrip-type model: strip theory for xi, eta and FASTSIM for spin."""

import math

import numpy as np
import pytest

from railcontact.geometry import ContactGeometry
from railcontact.core.materials import Material
from railcontact.normal import get_normal_model
from railcontact.tangential import get_tangential_model, kalker_coefficients

MAT = Material(2 * 82e9 * 1.28, 0.28)
FN = 1e5
MU = 0.3


def _hertz(AB):
    g = ContactGeometry(curvatures=AB)
    return g, get_normal_model("hertz").solve(g, MAT, normal_force=FN, grid=(60, 60))


@pytest.mark.parametrize("AB", [(1.0, 1.0), (1.0, 4.0), (4.0, 1.0), (1.0, 0.3)])
def test_linear_theory(AB):
    """Small creepage: Kalker's C11, C22, C23 (measured within 0.01 %)."""
    g, ns = _hertz(AB)
    a, b = ns.semi_axes
    c = math.sqrt(a * b)
    c11, c22, c23 = kalker_coefficients(a / b, MAT.poisson_ratio)
    G = MAT.shear_modulus
    m = get_tangential_model("fastrip")
    assert m.solve(ns, g, MAT, (1e-7, 0, 0), MU).fx == pytest.approx(G * c * c * c11 * 1e-7,
                                                                       rel=1e-3)
    assert m.solve(ns, g, MAT, (0, 1e-7, 0), MU).fy == pytest.approx(G * c * c * c22 * 1e-7,
                                                                       rel=1e-3)
    assert m.solve(ns, g, MAT, (0, 0, 1e-5), MU).fy == pytest.approx(G * c ** 3 * c23 * 1e-5,
                                                                       rel=1e-3)


@pytest.mark.parametrize("creep", [(0.05, 0.02, 0.0), (-0.1, 0.0, 0.5), (-0.01, 0.0, 0.5)])
def test_saturation(creep):
    """Near and at full sliding: mu F_n along the creepage, and with spin the exact
    solver's forces within 2 % of mu F_n (measured: 0.1 % at xi = -0.1, 1.6 % in Fy
    at xi = -0.01, where FASTSIM is 0.8 % off)."""
    g, ns = _hertz((1.0, 2.0))
    t = get_tangential_model("fastrip").solve(ns, g, MAT, creep, MU)
    ex = get_tangential_model("exact").solve(ns, g, MAT, creep, MU)
    assert t.fx == pytest.approx(ex.fx, abs=0.02 * MU * FN)
    assert t.fy == pytest.approx(ex.fy, abs=0.02 * MU * FN)
    assert math.hypot(t.fx, t.fy) <= MU * FN * 1.002
    if creep[2] == 0.0:                       # full sliding along the creepage
        assert math.hypot(t.fx, t.fy) == pytest.approx(MU * FN, rel=0.005)
        assert math.atan2(t.fy, t.fx) == pytest.approx(math.atan2(creep[1], creep[0]), abs=0.01)


@pytest.mark.parametrize("AB", [(1.0, 1.0), (1.0, 4.0), (4.0, 1.0)])
def test_partial_slip_against_exact(AB):
    """Longitudinal creepage in partial slip (about half the adhesion limit): strip
    theory is close to the exact solution (measured +0.2, 0.0, -0.9 %), closer
    than FASTSIM (+5.0, +5.4, +4.1 %)."""
    g, ns = _hertz(AB)
    creep = (1e-3, 0.0, 0.0)
    fr = get_tangential_model("fastrip").solve(ns, g, MAT, creep, MU)
    ex = get_tangential_model("exact").solve(ns, g, MAT, creep, MU)
    fs = get_tangential_model("fastsim").solve(ns, g, MAT, creep, MU)
    assert fr.fx == pytest.approx(ex.fx, rel=0.015)
    assert abs(fr.fx / ex.fx - 1) < abs(fs.fx / ex.fx - 1)


def test_pure_spin_is_fastsim():
    g, ns = _hertz((1.0, 2.0))
    creep = (0.0, 0.0, 0.3)
    fr = get_tangential_model("fastrip").solve(ns, g, MAT, creep, MU)
    fs = get_tangential_model("fastsim", flexibility="three").solve(ns, g, MAT, creep, MU)
    assert fr.fy == pytest.approx(fs.fy, rel=1e-3)
    assert fr.mz == pytest.approx(fs.mz, rel=1e-3)


def test_lens_shaped_adhesion_area():
    """Strip theory: slip starts at the lateral edges (small p0 per strip), the
    adhesion area touches the leading edge in the middle strips."""
    g, ns = _hertz((1.0, 1.0))
    t = get_tangential_model("fastrip").solve(ns, g, MAT, (1e-3, 0, 0), MU)
    cols = np.flatnonzero(ns.contact.any(axis=0))
    mid, edge = cols[cols.size // 2], cols[1]
    assert t.stick[:, mid].sum() > 0.4 * ns.contact[:, mid].sum()
    assert t.stick[:, edge].sum() < 0.2 * ns.contact[:, edge].sum()
    # slip only outside the adhesion area
    slipping = ns.contact & ~t.stick
    assert np.all(np.hypot(t.slip_x, t.slip_y)[t.stick] == 0)
    assert np.hypot(t.slip_x, t.slip_y)[slipping].max() > 0


def test_falling_friction_lowers_force_at_large_slip():
    """xi = 0.02 at 30 m/s: slip velocity about 0.6 m/s, mu(0.6) = 0.82 mu0 with
    A = 0.4, B = 0.6 s/m (measured: 24.6 kN against 30.0 kN)."""
    g, ns = _hertz((1.0, 2.0))
    creep = (0.02, 0.0, 0.0)
    plain = get_tangential_model("fastrip").solve(ns, g, MAT, creep, MU, velocity=30.0)
    fall = get_tangential_model("fastrip", falling={"A": 0.4, "B": 0.6}).solve(
        ns, g, MAT, creep, MU, velocity=30.0)
    assert fall.fx == pytest.approx(0.82 * plain.fx, rel=0.02)


def test_on_non_elliptic_patch():
    """ANALYN patch of a quartic gap: runs, saturates, linear slope from the
    equivalent ellipse."""
    g = ContactGeometry(curvatures=(1.0, 2.5),
                        gap_function=lambda x, y: x * x + 2.5 * y * y + 4e5 * y ** 4)
    ns = get_normal_model("analyn").solve(g, MAT, normal_force=5e4, grid=(50, 50))
    m = get_tangential_model("fastrip")
    t = m.solve(ns, g, MAT, (0.1, 0.0, 0.0), MU)
    assert t.fx == pytest.approx(MU * 5e4, rel=0.01)
    ex = get_tangential_model("exact").solve(ns, g, MAT, (1e-4, 0.0, 0.0), MU)
    assert m.solve(ns, g, MAT, (1e-4, 0.0, 0.0), MU).fx == pytest.approx(ex.fx, rel=0.05)
