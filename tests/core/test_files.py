"""Files written whole or not at all (railcontact.core.files)."""

import pytest
import xarray as xr

from railcontact.core.files import write_netcdf, write_text, written_whole


def test_a_file_appears_only_when_written_whole(tmp_path):
    path = tmp_path / "table.csv"
    with written_whole(path) as tmp:
        tmp.write_text("a,b\n")
        assert not path.exists() and tmp.name == "table.csv.tmp"
    assert path.read_text() == "a,b\n" and not list(tmp_path.glob("*.tmp"))


def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path):
    path = write_text(tmp_path / "profile.csv", "old\n")
    with pytest.raises(RuntimeError):
        with written_whole(path) as tmp:
            tmp.write_text("half")
            raise RuntimeError("interrupted")
    assert path.read_text() == "old\n" and not list(tmp_path.glob("*.tmp"))


def test_netcdf_round_trip(tmp_path):
    ds = xr.Dataset({"fn": ("case", [1.0, 2.5])}, attrs={"units": "N"})
    path = write_netcdf(ds, tmp_path / "r.nc")
    with xr.open_dataset(path, engine="h5netcdf") as back:
        assert back["fn"].values.tolist() == [1.0, 2.5] and back.attrs["units"] == "N"
