"""railcontact.cases.results: the case result, its combined status, JSON and xarray forms."""

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

import railcontact as rc
from railcontact.core.status import SolverStatus

EX = Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture(scope="module")
def bodies_result():
    return rc.solve(rc.load_case(EX / "bodies.toml"), normal="hertz", tangential="fastsim")


def test_to_xarray_carries_units_and_the_patch_values(bodies_result):
    ds = bodies_result.to_xarray()
    (p,) = bodies_result.to_dict()["patches"]
    units = {"area": "m2", "pmax": "Pa", "Fn": "N", "Fx": "N", "Mz": "N m", "frictional_power": "W",
             "contact_angle": "rad", "creepage_spin": "m-1", "creepage_longitudinal": "1"}
    for name, unit in units.items():
        assert ds[name].attrs["units"] == unit
    assert ds.sizes["patch"] == 1
    assert float(ds["Fn"][0]) == p["Fn"] and float(ds["area"][0]) == p["area"]
    assert float(ds["frictional_power"][0]) == p["frictional_power"] > 0
    assert float(ds["creepage_longitudinal"][0]) == p["creepage"]["longitudinal"]
    assert np.isnan(ds["y_rail"][0]) == (p["y_rail"] is None)      # None becomes NaN
    assert ds.attrs["normal_model"] == "hertz" and ds.attrs["tangential_model"] == "fastsim"


def test_json_round_trip(bodies_result):
    d = json.loads(bodies_result.to_json())
    assert d == bodies_result.to_dict()
    assert d["converged"] is True and d["message"] == "" and "vertical_residual" not in d
    (p,) = d["patches"]
    a, b = p["semi_axes"]
    assert p["area"] == pytest.approx(math.pi * a * b, rel=1e-12)
    assert 0.0 <= p["stick_fraction"] <= 1.0 and p["frictional_power"] >= 0.0


def test_an_unconverged_patch_makes_the_case_unconverged(bodies_result):
    (patch,) = bodies_result.patches
    bad_t = dataclasses.replace(patch.tangential, status=SolverStatus.failed("slip not met", 9))
    bad = dataclasses.replace(bodies_result, patches=[dataclasses.replace(patch, tangential=bad_t)])
    assert bodies_result.converged and not bad.converged
    assert bad.status.message == "patch, fastsim tangential: slip not met"
    assert bad.to_dict()["converged"] is False
    warned = dataclasses.replace(patch, validity=SolverStatus(warnings=("flange climb",)))
    res = dataclasses.replace(bodies_result, patches=[warned])
    assert res.converged and res.warnings == ["flange climb"]


def test_the_status_is_in_the_netcdf_attributes():
    """A result's status travels with its NetCDF: converged (0/1), message and the
    warnings ('; ' between them); here p_max beyond the default limit of 3 GPa."""
    from pathlib import Path

    import railcontact as rc
    case = rc.load_case(Path(__file__).resolve().parents[2] / "examples" / "bodies.toml")
    ok = rc.solve(case).to_xarray().attrs
    assert ok["converged"] == 1 and ok["message"] == "" and ok["warnings"] == ""
    hard = rc.solve(case.with_value("bodies.normal_force", 5e7))
    attrs = hard.to_xarray().attrs
    assert attrs["converged"] == 1 and attrs["warnings"] == "; ".join(hard.warnings)
    assert "plasticity: p_max" in attrs["warnings"] and "[plasticity]" in attrs["warnings"]


def test_flash_temperature_of_a_bodies_case(bodies_result):
    """A solve gives the patch's flash temperature where the case has a
    ``[thermal]`` table (each key defaulting to steel at 20 C): JSON
    ``max_temperature_degC``, NetCDF ``max_temperature`` in degC, the fields on the
    tangential grid, rail and wheel equally hot in the contact (equal steels), above
    the bulk temperature where there is slip.  Without the table, none (and no
    cost)."""
    (p,) = bodies_result.patches
    assert p.temperatures is None and "max_temperature_degC" not in p.to_dict()
    assert "max_temperature" not in bodies_result.to_xarray()
    res = rc.solve(rc.load_case(EX / "bodies.toml").with_values(
        {"thermal": {"rail_temperature": 20.0}}))
    (p,) = res.patches
    d = p.to_dict()
    ds = res.to_xarray()
    assert ds["max_temperature"].attrs["units"] == "degC"
    assert float(ds["max_temperature"][0]) == d["max_temperature_degC"] == p.max_temperature
    t_rail, t_wheel = p.temperatures
    c = p.tangential.contact
    assert t_rail.shape == c.shape
    assert np.allclose(t_rail[c], t_wheel[c], atol=1e-9)
    assert 20.0 < p.max_temperature < 100.0
    assert np.all(t_rail[c] >= 20.0 - 1e-9)


def test_flash_temperature_closed_forms():
    """A [bodies] case against closed forms: without slip (zero creepages) and
    bulk temperatures 0 and 150 C the contact is at their mean, 75 C (equal
    effusivities); in full sliding at creepage 0.3 (rigid slip velocity 9 m/s,
    elastic slip ~1 %) the largest temperature is Jaeger's on the Hertzian centre
    strip, 0.5 mu v_s p0 sqrt(a) 2.1883 / sqrt(pi lambda rho c V) (the integral's
    largest value 2.1883): measured +0.12 % (FASTSIM, 60 x 60 elements)."""
    from railcontact.tangential.temperature import STEEL
    case = rc.load_case(EX / "bodies.toml").with_values({
        "creepage": {"longitudinal": 0.0, "lateral": 0.0, "spin": 0.0},
        "thermal": {"rail_temperature": 0.0, "wheel_temperature": 150.0},
        "solver.grid": [60, 60]})
    (p,) = rc.solve(case, normal="hertz", tangential="fastsim").patches
    assert p.max_temperature == pytest.approx(75.0, abs=1e-9)
    case = case.with_values({"creepage.longitudinal": 0.3, "thermal.wheel_temperature": 0.0})
    (p,) = rc.solve(case, normal="hertz", tangential="fastsim").patches
    a, p0 = p.normal.semi_axes[0], p.normal.pmax
    closed = 0.5 * STEEL.jaeger_factor(30.0) * 0.3 * 9.0 * p0 * math.sqrt(a) * 2.1883
    assert p.max_temperature == pytest.approx(closed, rel=5e-3)


def test_thermal_keys_are_checked():
    from railcontact.core.errors import CaseFileError
    case = rc.load_case(EX / "bodies.toml")
    with pytest.raises(CaseFileError, match="thermal.conductivity"):
        case.with_values({"thermal.conductivity": -1.0})
    with pytest.raises(CaseFileError, match="thermal.colour"):
        case.with_values({"thermal.colour": 1.0})
    with pytest.raises(CaseFileError, match="thermal.scheme"):
        case.with_values({"thermal.scheme": "upwind"})
