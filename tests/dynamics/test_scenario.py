"""Scenario files: ``railcontact simulate``, its outputs, bad input, the wear feed."""

import pytest

from railcontact.core.errors import CaseFileError

SHORT = """
[wheel]
profile = "S1002"
[rail]
profile = "60E1"
[vehicle]
model = "{model}"
[[route.segment]]
type = "tangent"
length = 10.0
[[route.segment]]
type = "transition"
length = 30.0
[[route.segment]]
type = "curve"
radius = 500.0
cant = 0.05
length = 200.0
[route.irregularities]
spectrum = "ERRI-high"
seed = 2
[simulation]
velocity = 20.0
duration = {duration}
sample_rate = 50
table_step = 5e-4
history_wheelset = {hw}
"""


def _write(tmp_path, text, name="s.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_vehicle_scenario_outputs(tmp_path):
    import xarray as xr

    from railcontact.dynamics.scenario import run_scenario
    from railcontact.inputs import load_dynamics_scenario
    p = _write(tmp_path, SHORT.format(model="vehicle", duration=2.0, hw=3))
    run_scenario(load_dynamics_scenario(p), tmp_path / "out", progress=False)
    ds = xr.open_dataset(tmp_path / "out" / "simulation.nc", engine="h5netcdf")
    assert ds.sizes == {"time": 101, "wheelset": 4, "side": 2, "patch": 2, "body": 7}
    for var in ("lateral_displacement", "yaw", "normal_force", "longitudinal_force",
                "lateral_creep_force", "creepage_longitudinal", "creepage_lateral",
                "creepage_spin", "Y_over_Q", "Tgamma"):
        assert var in ds and "units" in ds[var].attrs
    # normal forces carry the wheel loads (vertical force = load, within the creep part)
    assert float(abs(ds["Q"] - ds[["load_left", "load_right"]].to_array("side")
                     .assign_coords(side=["left", "right"])).max()) < 0.05 * 60e3
    assert (tmp_path / "out" / "simulation.png").is_file()
    hist = (tmp_path / "out" / "history.csv").read_text().splitlines()
    assert len(hist) == 102 and hist[0].startswith("time,lateral_shift,yaw")
    ds.close()


def test_simulation_history_feeds_wear(tmp_path):
    """A recorded bogie run drives the wear loop end to end (short track)."""
    from railcontact.dynamics.scenario import run_scenario
    from railcontact.inputs import load_dynamics_scenario
    from railcontact.inputs import wear_scenario_from_dict
    from railcontact.wear import WearSimulation
    p = _write(tmp_path, SHORT.format(model="bogie", duration=1.0, hw=1))
    run_scenario(load_dynamics_scenario(p), tmp_path, progress=False)
    raw = {"wheel": {"profile": "S1002"}, "rail": {"profile": "60E1"},
           "solver": {"normal": "hertz", "tangential": "fastsim", "grid": [20, 20]},
           "wear": {"law": "frictional-power", "steps": 1, "history": "history.csv",
                    "history_stride": 10}}
    sc = wear_scenario_from_dict(raw, tmp_path)
    assert len(sc.conditions) == 6
    (tmp_path / "wear").mkdir()
    ds = WearSimulation(sc, tmp_path / "wear", progress=False).run(resume=False)
    depth = [float(ds[f"wear_depth_wheel_{s}"].max()) for s in ("left", "right")]
    # the step is scaled to 0.1 mm of wear on the worst profile: the outer (left) wheel
    assert max(depth) == pytest.approx(1e-4, rel=0.02) and depth[0] > depth[1] > 0


@pytest.mark.parametrize("edit, word", [
    (("model = \"vehicle\"", "model = \"tram\""), "vehicle.model"),
    (("velocity = 20.0", "velocity = -20.0"), "simulation.velocity"),
    (("velocity = 20.0", "velocity = 20.0\ntangential = \"magic\""), "simulation.tangential"),
    (("radius = 500.0", "radius = 5.0"), "radius"),
    (("seed = 2", "seed = 2\ncolour = 1"), "colour"),
    (("[vehicle]", "[vehicle]\nmass = 3.0"), "model = 'wheelset'"),
    (("[vehicle]", "[vehicle.parameters]\nprimary_kx = -1.0\n[vehicle2]"), "primary_kx"),
])
def test_bad_scenarios(tmp_path, edit, word):
    from railcontact.dynamics.scenario import run_scenario
    from railcontact.inputs import load_dynamics_scenario
    text = SHORT.format(model="vehicle", duration=1.0, hw=1).replace(*edit)
    p = _write(tmp_path, text)
    with pytest.raises(CaseFileError, match=word):
        run_scenario(load_dynamics_scenario(p), tmp_path / "out", progress=False)
    assert not (tmp_path / "out").exists()


def test_cli_batch(tmp_path):
    """Several scenarios run as one Dask batch from the command line."""
    from railcontact.cli import main
    a = _write(tmp_path, SHORT.format(model="wheelset", duration=0.5, hw=1), "a.toml")
    b = _write(tmp_path, SHORT.format(model="bogie", duration=0.5, hw=2), "b.toml")
    main(["simulate", str(a), str(b), "--out", str(tmp_path / "runs"),
          "--scheduler", "synchronous"])
    assert (tmp_path / "runs" / "a" / "simulation.nc").is_file()
    assert (tmp_path / "runs" / "b" / "simulation.nc").is_file()


def test_parameter_file(tmp_path):
    """Vehicle parameters from a data file, overridden by [vehicle.parameters]."""
    from railcontact.dynamics.scenario import vehicle_from_section
    (tmp_path / "veh.toml").write_text("carbody_mass = 40000.0\nframe_mass = 3000.0\n")
    m = vehicle_from_section({"model": "vehicle", "parameter_file": "veh.toml",
                              "parameters": {"frame_mass": 2800.0}}, tmp_path)
    assert m.bodies[0].mass == 40000.0 and m.bodies[1].mass == 2800.0
    assert m.total_mass == pytest.approx(40000 + 2 * 2800 + 4 * 1813)
    (tmp_path / "bad.toml").write_text("carbody_mas = 1.0\n")
    with pytest.raises(CaseFileError, match="carbody_mas"):
        vehicle_from_section({"parameter_file": "bad.toml"}, tmp_path)
    with pytest.raises(CaseFileError, match="does not exist"):
        vehicle_from_section({"parameter_file": "none.toml"}, tmp_path)


def test_quasi_elastic_scenario(tmp_path):
    """``simulation.contact = "quasi-elastic"``: the wheelset runs on Arnold's contact
    (one point per wheel: the flange slot carries nothing)."""
    from railcontact.dynamics.scenario import run_scenario
    from railcontact.inputs import load_dynamics_scenario
    text = SHORT.format(model="wheelset", duration=0.5, hw=1).replace(
        "table_step = 5e-4", "table_step = 5e-4\ncontact = \"quasi-elastic\"\nalpha = 3e-5")
    ds = run_scenario(load_dynamics_scenario(_write(tmp_path, text)), progress=False)
    assert ds.attrs["contact"] == "quasi-elastic" and ds.attrs["alpha_m"] == 3e-5
    assert float(abs(ds["patch_normal_force"].sel(patch="flange")).max()) == 0.0
    assert float(ds["patch_normal_force"].sel(patch="tread").min()) > 0.5 * 9.81 * 1000
    bad = SHORT.format(model="wheelset", duration=0.5, hw=1).replace(
        "table_step = 5e-4", "table_step = 5e-4\ncontact = \"rigid\"")
    with pytest.raises(CaseFileError, match="simulation.contact"):
        load_dynamics_scenario(_write(tmp_path, bad, "b.toml"))
