"""Dissimilar materials: combined constants, coupling kernels, coupled solution."""

import math

import numpy as np
import pytest

import railcontact as rc
from railcontact.cases.coupling import normal_gap_from_tractions, slip_from_pressure, solve_coupled
from railcontact.core.errors import CaseFileError, InputError
from railcontact.geometry.contact import ContactGeometry
from railcontact.core.materials import Material
from railcontact.normal import get_normal_model
from railcontact.core.hertz_theory import hertz_ellipse
from railcontact.normal.influence import coupling_kernels
from railcontact.tangential import get_tangential_model

SOFT = Material(2.1e11, 0.28, 2.1e10, 0.45)       # steel rail, a softer, nearly incompressible wheel
GEO = ContactGeometry(curvatures=(1 / 0.92, 1 / 0.6))


def test_combined_constants():
    E1, n1, E2, n2 = 2.1e11, 0.28, 2.1e10, 0.45
    G1, G2 = E1 / (2 * (1 + n1)), E2 / (2 * (1 + n2))
    assert SOFT.contact_modulus == pytest.approx(1 / ((1 - n1 ** 2) / E1 + (1 - n2 ** 2) / E2))
    G = 2 / (1 / G1 + 1 / G2)
    assert SOFT.shear_modulus == pytest.approx(G)
    assert SOFT.nu == pytest.approx(G / 2 * (n1 / G1 + n2 / G2))
    assert SOFT.difference_parameter == pytest.approx(G / 4 * ((1 - 2 * n1) / G1
                                                               - (1 - 2 * n2) / G2))
    same = Material(2.1e11, 0.28)
    assert same.difference_parameter == 0 and not same.is_dissimilar
    assert same.shear_modulus == pytest.approx(2.1e11 / 2.56) and same.nu == pytest.approx(0.28)
    swapped = Material(2.1e10, 0.45, 2.1e11, 0.28)
    assert swapped.difference_parameter == pytest.approx(-SOFT.difference_parameter)
    with pytest.raises(InputError, match="wheel_poisson_ratio"):
        Material(2.1e11, 0.28, 2.1e11, 0.6)


def test_coupling_kernels_against_point_loads():
    """Far from the element the integrals are the point-load fields x/r^2, y/r^2
    (Johnson 1985, eqs. 3.19, 3.21); the element on itself has none (odd)."""
    n, h = 11, 1e-3
    kx, ky = coupling_kernels(n, n, h, h, 1.0)
    c = n - 1
    for di, dj in ((6, 2), (-5, 7), (8, -8), (0, 9)):
        X, Y = di * h, dj * h
        r2 = X * X + Y * Y
        assert kx[c + di, c + dj] == pytest.approx(h * h * X / r2, rel=2e-3, abs=1e-12)
        assert ky[c + di, c + dj] == pytest.approx(h * h * Y / r2, rel=2e-3, abs=1e-12)
    assert kx[c, c] == 0 and ky[c, c] == 0
    np.testing.assert_allclose(kx, -kx[::-1, :], atol=1e-18)
    np.testing.assert_allclose(ky, ky[::-1, :], atol=1e-18)


def test_quasi_identical_bodies_are_decoupled():
    nm, tm = get_normal_model("exact"), get_tangential_model("exact")
    mat = Material(2.1e11, 0.28)
    ns, ts = solve_coupled(nm, tm, GEO, mat, (-1e-3, 5e-4, 0.1), 0.3, 30.0,
                           normal_force=50e3, grid=(30, 30))
    ns0 = nm.solve(GEO, mat, normal_force=50e3, grid=(30, 30))
    ts0 = tm.solve(ns0, GEO, mat, (-1e-3, 5e-4, 0.1), 0.3, 30.0)
    assert ts.options["coupling_iterations"] == 1
    np.testing.assert_allclose(ns.pressure, ns0.pressure, rtol=1e-12)
    assert ts.fx == pytest.approx(ts0.fx, rel=1e-9) and ts.fy == pytest.approx(ts0.fy, rel=1e-9)


def test_frictionless_limit_is_hertz_with_the_combined_modulus():
    nm, tm = get_normal_model("exact"), get_tangential_model("exact")
    ns, ts = solve_coupled(nm, tm, GEO, SOFT, (-1e-3, 0.0, 0.0), 1e-6, 30.0,
                           normal_force=50e3, grid=(40, 40))
    hz = hertz_ellipse(*GEO.curvatures, SOFT.contact_modulus, force=50e3)
    assert ns.area == pytest.approx(math.pi * hz.a * hz.b, rel=0.02)
    assert ns.pmax == pytest.approx(hz.p0, rel=0.02)


@pytest.fixture(scope="module")
def coupled():
    nm, tm = get_normal_model("exact"), get_tangential_model("exact")
    out = {}
    for name, mat, creep in (("soft", SOFT, (-1e-3, 2e-4, 0.0)),
                             ("swapped", Material(2.1e10, 0.45, 2.1e11, 0.28),
                              (1e-3, -2e-4, 0.0))):
        out[name] = solve_coupled(nm, tm, GEO, mat, creep, 0.3, 30.0, normal_force=50e3,
                                  grid=(30, 30))
    return out


def test_coupled_solution_is_a_fixed_point(coupled):
    """The converged pair solves both coupled problems: re-solving the normal problem
    with the tractions' gap, and the tangential one with the pressure's slip, changes
    nothing."""
    nm, tm = get_normal_model("exact"), get_tangential_model("exact")
    ns, ts = coupled["soft"]
    assert ts.converged and ts.options["coupling_iterations"] > 1
    gap = normal_gap_from_tractions(ns.x, ns.y, -ts.traction_x, -ts.traction_y, SOFT)
    assert np.abs(gap).max() > 1e-8                       # the coupling is not negligible
    ns2 = nm.solve(GEO, SOFT, normal_force=50e3, grid=(30, 30), extra_gap=gap)
    np.testing.assert_allclose(ns2.pressure, ns.pressure, atol=1e-4 * ns.pmax)
    ts2 = tm.solve(ns2, GEO, SOFT, (-1e-3, 2e-4, 0.0), 0.3, 30.0,
                   extra_slip=slip_from_pressure(ns2.x, ns2.y, ns2.pressure, SOFT))
    assert ts2.fx == pytest.approx(ts.fx, abs=1e-4 * 0.3 * 50e3)
    # and the coupling matters: without it the creep force differs
    ts0 = tm.solve(nm.solve(GEO, SOFT, normal_force=50e3, grid=(30, 30)), GEO, SOFT,
                   (-1e-3, 2e-4, 0.0), 0.3, 30.0)
    assert abs(ts0.fx - ts.fx) > 0.05 * abs(ts0.fx)


def test_swapping_the_bodies_mirrors_the_solution(coupled):
    """K -> -K with the creepages reversed: the same pressure, opposite tractions
    (the coupled equations are invariant under this change)."""
    (ns_a, ts_a), (ns_b, ts_b) = coupled["soft"], coupled["swapped"]
    np.testing.assert_allclose(ns_b.pressure, ns_a.pressure, atol=1e-4 * ns_a.pmax)
    assert ts_b.fx == pytest.approx(-ts_a.fx, rel=1e-4)
    assert ts_b.fy == pytest.approx(-ts_a.fy, rel=1e-3, abs=1.0)


def _dissimilar_bodies() -> dict:
    """A bodies case of a steel rail and a wheel ten times softer (exact models)."""
    return {"material": {"young_modulus": 2.1e11, "poisson_ratio": 0.28,
                         "wheel_young_modulus": 2.1e10, "wheel_poisson_ratio": 0.45},
            "bodies": {"radii": {"wheel_rolling": 0.46, "wheel_lateral": 0.3,
                                 "rail_rolling": math.inf, "rail_lateral": 0.3},
                       "normal_force": 5e4, "velocity": 30.0},
            "creepage": {"longitudinal": -1e-3},
            "solver": {"normal": "exact", "tangential": "exact", "grid": [24, 24]}}


def test_case_file_with_dissimilar_materials():
    raw = _dissimilar_bodies()
    res = rc.solve(rc.case_from_dict(raw))
    assert res.patches[0].tangential.converged and res.converged
    raw["solver"] = {"normal": "hertz", "tangential": "fastsim"}
    hz = rc.solve(rc.case_from_dict(raw))          # approximate models: combined constants
    assert hz.patches[0].normal.pmax < 0.5e9
    raw["material"]["wheel_poisson_ratio"] = 0.7
    with pytest.raises(CaseFileError, match="wheel_poisson_ratio"):
        rc.case_from_dict(raw)


def test_unconverged_alternation_makes_the_case_unconverged(monkeypatch):
    """An alternation that stops before the coupled problems agree leaves a result
    whose parts each converged: the case must say it did not, in the result and in
    its JSON, with the reason."""
    import json

    from railcontact.cases import coupling
    monkeypatch.setattr(coupling, "MAX_ALTERNATIONS", 2)
    raw = _dissimilar_bodies()
    res = rc.solve(rc.case_from_dict(raw))
    (p,) = res.patches
    assert p.normal.converged                     # each solve met its own tolerance ...
    assert not p.tangential.converged             # ... the alternation did not
    assert not res.converged
    assert "alternation" in res.status.message
    out = json.loads(res.to_json())
    assert out["converged"] is False and "alternation" in out["message"]
