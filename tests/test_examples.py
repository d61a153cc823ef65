"""Every example in examples/ runs."""

import runpy
import sys
from pathlib import Path

import pytest

import railcontact as rc

EX = Path(__file__).resolve().parents[1] / "examples"


@pytest.mark.parametrize("path", sorted(EX.glob("*.py")), ids=lambda p: p.name)
def test_python_examples(path, capsys, monkeypatch, tmp_path):
    # run as `python examples/NAME.py` from a scratch folder: an example that takes an
    # output folder from its command line must not read pytest's arguments as one
    monkeypatch.setattr(sys, "argv", [str(path)])
    monkeypatch.chdir(tmp_path)
    runpy.run_path(str(path), run_name="__main__")
    assert capsys.readouterr().out.strip()


@pytest.mark.parametrize("path", sorted(EX.glob("*.toml")), ids=lambda p: p.name)
def test_case_examples(path, tmp_path, request):
    text = path.read_text()
    if "[vehicle]" in text and "[wear]" in text:       # closed-loop wear (run once)
        out, ds = request.getfixturevalue("wear_vehicle_example")
        assert ds.sizes["step"] >= 1 and ds.sizes["route"] >= 3
        for f in ("wear.nc", "wear.png", "measures.png", "checkpoint.nc"):
            assert (out / f).is_file()
        return
    if "[roller_rig]" in text:           # a wheelset on a roller rig
        from railcontact.dynamics.roller_rig import run_rig_scenario
        from railcontact.inputs import load_dynamics_scenario
        ds = run_rig_scenario(load_dynamics_scenario(path), tmp_path, progress=False)
        assert ds.sizes["time"] > 10 and (tmp_path / "rig_forces.png").is_file()
        assert ds.attrs["critical_speed_m_s"] < ds.attrs["track_critical_speed_m_s"]
        return
    if "[vehicle]" in text:
        from railcontact.dynamics.scenario import run_scenario
        from railcontact.inputs import load_dynamics_scenario
        ds = run_scenario(load_dynamics_scenario(path), tmp_path, progress=False)
        assert ds.sizes["time"] > 10 and (tmp_path / "simulation.nc").is_file()
        in_curve = ds.where(ds["curvature"] > 0.99 * float(ds["curvature"].max()), drop=True)
        assert in_curve.sizes["time"] > 10
        # towards the outer (left) rail in the right-hand curve, and no flange climbing
        assert float(in_curve["lateral_displacement"].sel(wheelset=1).mean()) < -2e-3
        assert float(abs(ds["Y_over_Q"]).max()) < 0.8
        return
    if "[wear]" in text:
        from railcontact.inputs import load_wear_scenario
        from railcontact.wear import WearSimulation
        ds = WearSimulation(load_wear_scenario(path), tmp_path, progress=False).run()
        assert ds.sizes["step"] >= 1 and (tmp_path / "wear.nc").is_file()
        return
    res = rc.solve(rc.load_case(path))
    assert res.patches and all(p.normal.normal_force > 0 for p in res.patches)
