"""Elastic-perfectly-plastic normal contact: the exact solver with a pressure limit."""

import math

import numpy as np
import pytest

import railcontact as rc
from railcontact.core.errors import CaseFileError, InputError
from railcontact.geometry import ContactGeometry
from railcontact.core.materials import Material
from railcontact.normal import get_normal_model, hertz_ellipse
from railcontact.normal.polonsky_keer import polonsky_keer
from railcontact.normal.influence import normal_operator
from railcontact.normal.plasticity import HARDNESS_FACTOR, pressure_limit

EX = rc.__file__.rsplit("/", 2)[0] + "/examples"
#: seed 003 (Wiest et al. 2008): E = 200 GPa, nu = 0.3 for both bodies in its Hertz
#: calculation; wheel flange root -18 mm, nose 13 mm, 111.5 kN; rolling radius 0.49 m
#: (see examples/crossing_nose_plastic.toml)
NOSE = ContactGeometry(curvatures=(0.5 / 0.49, 0.5 * (1 / 0.013 - 1 / 0.018)))
MAT = Material(2.0e11, 0.3)
FN = 111.5e3
LIMIT = pressure_limit(360e6)


def _solve(limit, **kw):
    kw.setdefault("element_size", (2.5e-4, 1e-4))
    return get_normal_model("exact", pressure_limit=limit).solve(NOSE, MAT, normal_force=FN,
                                                                 **kw)


def test_limit_is_tabors_hardness():
    assert HARDNESS_FACTOR == 3.0
    assert pressure_limit(360e6) == pytest.approx(1.08e9)
    assert pressure_limit(360e6, 1.6) == pytest.approx(5.76e8)
    for bad in (-1.0, 0.0, math.nan, 1e12, True):
        with pytest.raises(InputError, match="yield_stress"):
            pressure_limit(bad)
    with pytest.raises(InputError, match="pressure_factor"):
        pressure_limit(360e6, 0.5)
    with pytest.raises(InputError, match="pressure_limit"):
        get_normal_model("exact", pressure_limit=-1.0)


def test_seed003_hertz_values():
    """The paper's Hertz values (65 mm2, 2566 MPa, 0.1447 mm) with its materials (its
    radii are "about" 13 and 18 mm and its rolling radius is not given: 0.49 m gives
    65.0 mm2, 2573 MPa, 0.1456 mm)."""
    hz = hertz_ellipse(*NOSE.curvatures, MAT.contact_modulus, force=FN)
    assert hz.area * 1e6 == pytest.approx(65, rel=0.01)
    assert hz.p0 / 1e6 == pytest.approx(2566, rel=0.005)
    assert hz.penetration * 1e3 == pytest.approx(0.1447, rel=0.01)


def test_no_pressure_exceeds_the_limit_and_the_load_is_carried():
    el = _solve(None)
    pl = _solve(LIMIT)
    assert el.converged and pl.converged
    # elastic: CONTACT in the paper 67 mm2, 2555 MPa, 0.1421 mm (its grid 0.5 x 0.2 mm)
    assert el.pmax / 1e6 == pytest.approx(2555, rel=0.02)
    assert el.area * 1e6 == pytest.approx(67, rel=0.04)
    # plastic: every element at or below the limit, the force met
    assert pl.pressure.max() <= LIMIT * (1 + 1e-12)
    assert pl.pmax == pytest.approx(LIMIT, rel=1e-9)
    assert pl.normal_force == pytest.approx(FN, rel=1e-6)
    # a larger area carries it: at least force / limit, and the elastic rim on top
    assert pl.area > 1.5 * el.area
    assert FN / LIMIT < pl.area < 1.1 * FN / LIMIT
    assert pl.plastic_area > 0.9 * pl.area
    assert pl.penetration > el.penetration
    # measured: 105.0 mm2 (FE 128), 0.1741 mm (FE 0.1710) on this grid
    assert pl.area * 1e6 == pytest.approx(105.0, rel=0.01)
    assert pl.penetration * 1e3 == pytest.approx(0.1741, rel=0.01)


def test_complementarity_at_the_solution():
    """p = 0 with a gap, 0 < p < limit closed, p = limit overlapping (plastic)."""
    pl = _solve(LIMIT, grid=(50, 50), element_size=None)
    x, y = pl.x, pl.y
    dx, dy = x[1] - x[0], y[1] - y[0]
    h = NOSE.gap(x[:, None], y[None, :])
    u = normal_operator(x.size, y.size, dx, dy, MAT.contact_modulus)(pl.pressure)
    e = h + u - pl.penetration                     # deformed distance
    scale = pl.penetration
    free = (pl.pressure > 0) & ~pl.plastic
    assert np.all(e[pl.pressure == 0] > -1e-4 * scale)
    assert np.all(np.abs(e[free]) < 1e-3 * scale)
    assert np.all(e[pl.plastic] < 1e-4 * scale)
    assert e[pl.plastic].min() < -0.05 * scale     # the plastic elements overlap


def test_elastic_solution_recovered_for_a_large_yield_stress():
    el = _solve(None, grid=(40, 40), element_size=None)
    big = _solve(pressure_limit(1e10), grid=(40, 40), element_size=None)
    assert np.array_equal(big.pressure, el.pressure)
    assert big.penetration == el.penetration and not big.plastic.any()
    # a limit just above the elastic peak leaves the displacement-controlled
    # solution unchanged too (to the iteration's tolerance: 1e-4 of p_max apart)
    m = get_normal_model("exact", pressure_limit=1.01 * el.pmax)
    d = m.solve(NOSE, MAT, penetration=el.penetration, grid=(40, 40))
    e = get_normal_model("exact").solve(NOSE, MAT, penetration=el.penetration, grid=(40, 40))
    assert not d.plastic.any()
    assert np.allclose(d.pressure, e.pressure, atol=5e-4 * el.pmax)


def test_limit_decreases_pmax_and_increases_area_monotonically():
    areas, apps = [], []
    for y in (1e9, 600e6, 360e6, 250e6):
        s = _solve(pressure_limit(y), grid=(60, 60), element_size=None)
        assert s.pmax <= pressure_limit(y) * (1 + 1e-12)
        assert s.normal_force == pytest.approx(FN, rel=1e-6)
        areas.append(s.area)
        apps.append(s.penetration)
    assert all(a < b for a, b in zip(areas, areas[1:]))
    assert all(a < b for a, b in zip(apps, apps[1:]))


def test_kernel_rejects_a_limit_with_the_force_given():
    op = normal_operator(4, 4, 1e-3, 1e-3, MAT.contact_modulus)
    with pytest.raises(InputError, match="approach given"):
        polonsky_keer(op, np.zeros((4, 4)), 1e-6, force=1.0, pressure_limit=1e9)


def test_tangential_solution_on_the_bounded_pressure():
    case = rc.load_case(f"{EX}/crossing_nose_plastic.toml")
    res = rc.solve(case)
    (p,) = res.patches
    assert res.converged
    assert p.normal.pmax <= LIMIT * (1 + 1e-12)
    t = p.tangential
    mag = np.hypot(t.traction_x, t.traction_y)
    assert np.all(mag <= case.friction * p.normal.pressure * (1 + 1e-6) + 1e-3)
    assert abs(t.fx) < case.friction * p.normal.normal_force
    d = res.to_dict()["patches"][0]
    assert d["pressure_limit"] == pytest.approx(LIMIT) and d["plastic_area"] > 0


def test_case_file_plasticity_section(tmp_path):
    base = rc.load_case(f"{EX}/crossing_nose_plastic.toml").raw
    from railcontact.cases.case import case_from_dict
    raw = dict(base, plasticity={"pressure_limit": 9e8})
    assert case_from_dict(raw).normal_options["pressure_limit"] == 9e8
    raw = dict(base, plasticity={"yield_stress": 3e8, "pressure_factor": 1.6})
    assert case_from_dict(raw).normal_options["pressure_limit"] == pytest.approx(4.8e8)
    for bad, match in (({"yield_stress": -3e8}, "yield_stress"),
                       ({}, "missing yield_stress"),
                       ({"yield_stress": 3e8, "pressure_limit": 9e8}, "not both"),
                       ({"hardness": 3}, "unknown key")):
        with pytest.raises(CaseFileError, match=match):
            case_from_dict(dict(base, plasticity=bad))
    raw = dict(base, solver=dict(base["solver"], normal="hertz"))
    with pytest.raises(CaseFileError, match="expected 'exact'"):
        case_from_dict(raw)


def test_wheel_rail_case_with_a_pressure_limit():
    case = rc.load_case(f"{EX}/wheel_rail.toml")
    from railcontact.cases.case import case_from_dict
    raw = dict(case.raw, plasticity={"pressure_limit": 1e9},
               solver=dict(case.raw["solver"], normal="exact", tangential="fastsim"))
    res = rc.solve(case_from_dict(raw, case.base_dir))
    (p,) = res.patches
    assert res.converged
    assert p.normal.pmax == pytest.approx(1e9, rel=1e-9)
    assert p.normal.plastic_area > 0
    assert abs(res.vertical_residual["right"]) < 1e-4
