"""Every example in examples/ runs."""

import runpy
from pathlib import Path

import pytest

import railcontact as rc

EX = Path(__file__).resolve().parents[1] / "examples"


@pytest.mark.parametrize("path", sorted(EX.glob("*.py")), ids=lambda p: p.name)
def test_python_examples(path, capsys):
    runpy.run_path(str(path), run_name="__main__")
    assert capsys.readouterr().out.strip()


@pytest.mark.parametrize("path", sorted(EX.glob("*.toml")), ids=lambda p: p.name)
def test_case_examples(path, tmp_path):
    if "[vehicle]" in path.read_text():
        from railcontact.dynamics.scenario import run_scenario
        ds = run_scenario(path, tmp_path)
        assert ds.sizes["time"] > 10 and (tmp_path / "simulation.nc").is_file()
        assert abs(float(ds["lateral_displacement"][-1])) < 3e-3   # below the critical speed
        return
    if "[wear]" in path.read_text():
        from railcontact.wear import WearSimulation, load_scenario
        ds = WearSimulation(load_scenario(path), tmp_path, progress=False).run()
        assert ds.sizes["step"] >= 1 and (tmp_path / "wear.nc").is_file()
        return
    res = rc.solve(rc.load_case(path))
    assert res.patches and all(p.normal.normal_force > 0 for p in res.patches)
