"""The demo (``make demo``) writes its outputs."""

import xarray as xr

from railcontact.demo import run_demo


def test_demo_outputs(tmp_path):
    run_demo(tmp_path)
    ds = xr.open_dataset(tmp_path / "contact_table.nc", engine="h5netcdf")
    assert {"delta_r", "contact_angle", "Fn", "Fx"} <= set(ds.variables)
    assert ds["delta_r"].attrs["units"] == "m"
    assert 0.1 < ds.attrs["equivalent_conicity_3mm"] < 0.25
    for f in ("contact_positions.png", "patches.png"):
        assert (tmp_path / f).stat().st_size > 10_000
