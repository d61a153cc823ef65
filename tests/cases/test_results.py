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
    units = {"area": "m2", "pmax": "Pa", "Fn": "N", "Fx": "N", "Mz": "N m",
             "contact_angle": "rad", "creepage_spin": "m-1", "creepage_longitudinal": "1"}
    for name, unit in units.items():
        assert ds[name].attrs["units"] == unit
    assert ds.sizes["patch"] == 1
    assert float(ds["Fn"][0]) == p["Fn"] and float(ds["area"][0]) == p["area"]
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
