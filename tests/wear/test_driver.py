"""The one wear driver (railcontact.wear.driver): its checkpoint (NetCDF with the
scenario's hash) resumes only the scenario it belongs to, and a checkpoint it
cannot read is a clear error, never a traceback."""

import shutil

import numpy as np
import pytest
import xarray as xr

from railcontact.core.errors import InputError
from railcontact.wear.driver import CHECKPOINT
from railcontact.wear.simulation import WearSimulation
from tests.wear.test_simulation import SYMMETRIC, scenario


@pytest.fixture(scope="module")
def one_step(tmp_path_factory):
    """The output folder of one open-loop step (its checkpoint and wear.nc)."""
    out = tmp_path_factory.mktemp("one_step")
    WearSimulation(scenario(SYMMETRIC, steps=1), out, progress=False).run(resume=False)
    return out


def _copy(one_step, tmp_path):
    out = tmp_path / "run"
    shutil.copytree(one_step, out)
    return out


def test_checkpoint_is_netcdf_with_the_scenario_hash(one_step):
    sim = WearSimulation(scenario(SYMMETRIC, steps=1), one_step, progress=False)
    with xr.open_dataset(one_step / CHECKPOINT, engine="h5netcdf") as ck:
        assert ck.attrs["scenario_hash"] == sim.scenario_hash()
        assert ck.sizes["step"] == 1
    assert not (one_step / "checkpoint.npz").exists()
    # more steps, another scheduler: the same scenario (it resumes)
    more = scenario(SYMMETRIC, steps=3, scheduler="sync")
    assert WearSimulation(more, None, progress=False).scenario_hash() == sim.scenario_hash()
    # an integer written for a float is the same value
    ints = [dict(c, weight=1) for c in SYMMETRIC]
    assert WearSimulation(scenario(ints, steps=1), None,
                          progress=False).scenario_hash() == sim.scenario_hash()


def test_resume_is_bit_identical(one_step, tmp_path):
    full = WearSimulation(scenario(SYMMETRIC, steps=2), progress=False).run(resume=False)
    out = _copy(one_step, tmp_path)
    again = WearSimulation(scenario(SYMMETRIC, steps=2), out, progress=False)
    assert again.load_checkpoint() and again.step == 1
    ds = again.run(resume=True)
    for name in ("distance", "energy", "profile_z_wheel_left", "wear_depth_wheel_right",
                 "law_area_wheel_left"):
        np.testing.assert_array_equal(ds[name].values, full[name].values)


@pytest.mark.parametrize("change, named", [
    ({"parameters": {"k": 2e-13}}, "parameters.k"),
    ({"law": "usfd", "parameters": {}}, "law"),
    ({"max_depth_per_step": 2e-4}, "max_depth_per_step"),
    ({"body": "both"}, "body"),
])
def test_another_scenarios_checkpoint_is_refused(one_step, tmp_path, change, named):
    out = _copy(one_step, tmp_path)
    sim = WearSimulation(scenario(SYMMETRIC, steps=2, **change), out, progress=False)
    with pytest.raises(InputError, match=f"another scenario: .*{named}") as err:
        sim.run()
    assert str(out / CHECKPOINT) in str(err.value) and "--restart" in str(err.value)
    before = xr.open_dataset(out / "wear.nc", engine="h5netcdf").load()
    assert before.sizes["step"] == 1                    # nothing rewritten


def test_changed_conditions_are_refused(one_step, tmp_path):
    out = _copy(one_step, tmp_path)
    cond = [dict(c, yaw=0.004) for c in SYMMETRIC]
    with pytest.raises(InputError, match="another scenario: conditions"):
        WearSimulation(scenario(cond, steps=2), out, progress=False).run()


def _damage(path, how):
    data = path.read_bytes()
    if how == "empty":
        path.write_bytes(b"")
    elif how == "truncated":
        path.write_bytes(data[:len(data) // 2])
    elif how == "corrupted":
        path.write_bytes(data[:64] + bytes(range(256)) * 8 + data[64 + 2048:])
    elif how == "text":
        path.write_text("not a checkpoint\n")


@pytest.mark.parametrize("how", ["empty", "truncated", "corrupted", "text"])
def test_unreadable_checkpoint(one_step, tmp_path, how):
    out = _copy(one_step, tmp_path)
    _damage(out / CHECKPOINT, how)
    with pytest.raises(InputError, match="(cannot read|incomplete|damaged).*--restart"):
        WearSimulation(scenario(SYMMETRIC, steps=2), out, progress=False).run()


def test_foreign_netcdf(one_step, tmp_path):
    out = _copy(one_step, tmp_path)
    shutil.copy(out / "wear.nc", out / CHECKPOINT)         # results, not a checkpoint
    with pytest.raises(InputError, match="not a railcontact wear checkpoint"):
        WearSimulation(scenario(SYMMETRIC, steps=2), out, progress=False).run()


def test_restart_ignores_a_bad_checkpoint(one_step, tmp_path):
    out = _copy(one_step, tmp_path)
    _damage(out / CHECKPOINT, "text")
    ds = WearSimulation(scenario(SYMMETRIC, steps=1), out, progress=False).run(resume=False)
    assert ds.sizes["step"] == 1


def test_cli_reports_a_bad_checkpoint(one_step, tmp_path, capsys):
    """The command line: one line on stderr, exit 2, no traceback."""
    from railcontact.cli import main
    out = _copy(one_step, tmp_path)
    _damage(out / CHECKPOINT, "truncated")
    path = tmp_path / "demo.toml"
    path.write_text('[wheel]\nprofile = "S1002"\n[rail]\nprofile = "60E1"\n'
                    "[wheelset]\nvertical_force = 75e3\n"
                    '[wear]\nsteps = 2\nparameters = { k = 1e-13 }\n'
                    "[[condition]]\nlateral_shift = 0.0\nyaw = 0.002\n")
    assert main(["wear", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert "checkpoint" in err and "Traceback" not in err


def test_driver_by_scenario_type():
    from railcontact.wear.closed_loop import ClosedLoopWear
    from tests.wear.test_closed_loop import tiny
    assert isinstance(scenario(SYMMETRIC).driver(progress=False), WearSimulation)
    assert isinstance(tiny(steps=1).driver(progress=False), ClosedLoopWear)
