"""Closed-loop wear: a vehicle on a route mix, the dynamics on the worn profiles at
every step, any local contact model in the post-processing."""

import copy

import numpy as np
import pytest

from railcontact.core.errors import CaseFileError, InputError
from railcontact.inputs import wear_scenario_from_dict
from railcontact.wear.closed_loop import ClosedLoopWear

# a bogie on a short tight curve and a short irregular tangent: seconds per step
TINY = {
    "title": "tiny closed loop",
    "wheel": {"profile": "S1002"}, "rail": {"profile": "60E1", "inclination": 0.025},
    "solver": {"normal": "hertz", "tangential": "fastsim", "grid": [20, 20]},
    "vehicle": {"model": "bogie"},
    "dynamics": {"table_range": 0.010, "table_step": 5e-4},
    "wear": {"law": "usfd", "steps": 2, "wheels": "individual", "max_depth_per_step": 1e-4},
    "route": [{"name": "R300", "radius": 300.0, "cant": 0.1, "speed": 20.0, "length": 40.0,
               "weight": 1.0, "lead": 5.0},
              {"name": "tangent", "speed": 30.0, "length": 40.0, "weight": 1.0,
               "irregularities": {"spectrum": "ERRI-high", "seed": 3}}],
}


def tiny(**wear):
    raw = copy.deepcopy(TINY)
    raw["wear"].update(wear)
    sc = wear_scenario_from_dict(raw)
    sc.scheduler = "sync"
    return sc


@pytest.fixture(scope="module")
def two_steps():
    """The tiny scenario, wheels and rails worn, step by step: the simulation, the
    wheel and rail profile objects before each step and the tables each step used."""
    sim = ClosedLoopWear(tiny(body="both"), progress=False)
    seen = []
    for _ in range(2):
        before = ([list(p) for p in sim.wheels], [list(p) for p in sim.rails])
        tables, _ = sim._compute({id(p): np.arange(0.0, 0.2, 1e-4)
                                  for pair in sim.wheels + sim.rails for p in pair})
        seen.append((before, tables))
        sim.run_step()
    return sim, seen


def test_loop_is_closed(two_steps):
    """The contact tables of step k come from step k's worn profiles."""
    sim, seen = two_steps
    for k, ((wheels, rails), tables) in enumerate(seen):
        for r in range(sim.nr):
            for w in range(sim.nw):
                geo = [g for row in tables[r][w].geometry for side in row for g in side
                       if g is not None]
                assert geo
                for g in geo:
                    j = 0 if g.side == "left" else 1
                    assert g.gap_function.wheel is wheels[w][j]
                    assert g.gap_function.rail is rails[r][j]
        if k:                                    # worn profiles are new objects
            assert all(wheels[w][j] is not seen[0][0][0][w][j] for w in range(sim.nw)
                       for j in range(2))
    # the worn profiles change the contact geometry: delta_r(y) of the tight curve
    d0, d1 = (seen[k][1][0][0].delta_r for k in (0, 1))
    assert np.max(np.abs(d1 - d0)) > 1e-6


def test_conservation_wheels_and_rails(two_steps):
    """The removed cross-section area equals the law's total within 0.5 %."""
    ds = two_steps[0].to_xarray()
    for kind in ("wheel", "rail"):
        law = ds[f"law_area_{kind}"].values
        removed = ds[f"removed_area_{kind}"].values
        assert law.max() > 0
        worn = law > 1e-3 * law.max()
        assert np.all(np.abs(removed[worn] / law[worn] - 1.0) < 5e-3)
    # the step control: the largest depth of any worn body is max_depth_per_step
    top = max(float(ds["wear_depth_wheel"].isel(step=0).max()),
              float(ds["wear_depth_rail"].isel(step=0).max()))
    assert top == pytest.approx(1e-4, rel=0.02)


def test_individual_wheels_in_the_tight_curve(two_steps):
    """Right-hand curve: the leading wheelset's outer (left) wheel wears on the flange
    (flange root and flank of S1002: y from -40 to -22 mm), its inner wheel on the
    field side of the tread; every wheel keeps its own profile."""
    ds = two_steps[0].to_xarray()
    y = ds["y_wheel"].values
    rate = ds["wear_rate_wheel"].sel(route="R300", wheelset=1).isel(step=0)
    outer, inner = rate.sel(side="left").values, rate.sel(side="right").values
    assert -0.040 < y[np.argmax(outer)] < -0.022
    assert y[np.argmax(inner)] > 0.005
    assert outer.max() > 3 * inner.max()
    prof = {id(p) for pair in two_steps[0].wheels for p in pair}
    assert len(prof) == 4


def test_wheel_groups():
    sc = tiny(steps=1, wheels="vehicle")
    sim = ClosedLoopWear(sc, progress=False)
    ds = sim.run(resume=False)
    assert len({id(p) for pair in sim.wheels for p in pair}) == 1
    d = ds["wear_depth_wheel"].values
    assert np.array_equal(d[:, 0, 0], d[:, 1, 1]) and d.max() > 0
    sim = ClosedLoopWear(tiny(steps=1, wheels="side"), progress=False)
    sim.run(resume=False)
    assert len({id(p) for pair in sim.wheels for p in pair}) == 2
    assert sim.wheels[0][0] is sim.wheels[1][0] and sim.wheels[0][0] is not sim.wheels[0][1]


def test_local_model_meets_the_dynamics(tmp_path):
    """Force-controlled post-processing: the local model carries the dynamics'
    normal force; Hertz + FASTSIM on the table's patches gives the creep forces of
    the online FASTSIM (same creepage conventions) to a median of 1 % of mu N."""
    import xarray as xr
    ClosedLoopWear(tiny(steps=1, records=True), tmp_path, progress=False).run(resume=False)
    for route in ("R300", "tangent"):
        rec = xr.open_dataset(tmp_path / "records" / f"step001_{route}.nc")
        N = rec["patch_normal_force"].values
        on = N > 0
        assert np.max(np.abs(rec["local_Fn"].values[on] / N[on] - 1)) < 1e-3
        for a, b in (("patch_Fx", "local_Fx"), ("patch_Fy", "local_Fy")):
            d = np.abs(rec[a].values - rec[b].values)[on] / (0.3 * N[on])
            assert np.median(d) < 0.01


def test_resume_gives_the_same_result(tmp_path):
    full = ClosedLoopWear(tiny(steps=2), None, progress=False).run(resume=False)
    ClosedLoopWear(tiny(steps=1), tmp_path, progress=False).run(resume=False)
    again = ClosedLoopWear(tiny(steps=2), tmp_path, progress=False)
    assert again.load_checkpoint() and again.step == 1
    ds = again.run(resume=True)
    assert ds.sizes["step"] == 2
    np.testing.assert_array_equal(ds["profile_z_wheel"].values, full["profile_z_wheel"].values)
    np.testing.assert_array_equal(ds["distance"].values, full["distance"].values)
    with pytest.raises(InputError, match="another scenario"):
        ClosedLoopWear(tiny(steps=2, wheels="vehicle"), tmp_path, progress=False).run()


def test_threads_equal_sync():
    a = ClosedLoopWear(tiny(steps=1), None, progress=False).run(resume=False)
    sc = tiny(steps=1)
    sc.scheduler = "threads"
    b = ClosedLoopWear(sc, None, progress=False).run(resume=False)
    np.testing.assert_array_equal(a["wear_depth_wheel"].values, b["wear_depth_wheel"].values)


@pytest.mark.parametrize("patch, match", [
    ({"route": []}, "missing \\[\\[route\\]\\]"),
    ({"route": [{"name": "a", "speed": 10.0, "weight": 0.0}]}, "weight"),
    ({"route": [{"name": "a", "speed": 10.0, "colour": 1}]}, "unknown key"),
    ({"route": [{"name": "a", "speed": 10.0}, {"name": "a", "speed": 10.0}]}, "distinct"),
    ({"route": [{"name": "a", "radius": 5.0}]}, "radius"),
    ({"route": [{"name": "a", "cant": 0.1}]}, "give radius"),
    ({"wear": {"wheels": "pairs"}}, "wear.wheels"),
    ({"wear": {"sample_distance": 0.0}}, "wear.sample_distance"),
    ({"wear": {"records": 1}}, "wear.records"),
    ({"wear": {"bogus": 1}}, "unknown key"),
    ({"dynamics": {"duration": 3.0}}, "unknown key"),
    ({"dynamics": {"tangential": "nonsense"}}, "dynamics.tangential"),
    ({"condition": [{"lateral_shift": 0.0}]}, "\\[\\[condition\\]\\]"),
    ({"vehicle": {"preset": "tgv"}}, "vehicle.preset"),
    ({"solver": {"normal": "nonsense"}}, "nonsense"),
])
def test_bad_scenarios(patch, match):
    raw = copy.deepcopy(TINY)
    for key, value in patch.items():
        if isinstance(value, dict) and key in raw:
            raw[key] = {**raw[key], **value}
        else:
            raw[key] = value
    with pytest.raises(InputError, match=match):
        wear_scenario_from_dict(raw)


def _write_tiny(tmp_path, steps=1):
    lines = ['title = "tiny"', "[wheel]", 'profile = "S1002"', "[rail]", 'profile = "60E1"',
             "inclination = 0.025", "[solver]", 'normal = "hertz"', 'tangential = "fastsim"',
             "grid = [20, 20]", "[vehicle]", 'model = "bogie"', "[dynamics]",
             "table_range = 0.010", "table_step = 5e-4", "[wear]", 'law = "usfd"',
             f"steps = {steps}", 'scheduler = "sync"', "records = true", "[[route]]",
             'name = "R300"',
             "radius = 300.0", "cant = 0.1", "speed = 20.0", "length = 30.0", "lead = 5.0"]
    p = tmp_path / "tiny.toml"
    p.write_text("\n".join(lines) + "\n")
    return p


def test_cli_wear_exact_exact(tmp_path, capsys):
    from railcontact.cli import main
    path = _write_tiny(tmp_path)
    out = tmp_path / "out"
    assert main(["wear", str(path), "--normal", "exact", "--tangential", "exact",
                 "--out", str(out)]) == 0
    import xarray as xr
    ds = xr.open_dataset(out / "wear.nc")
    assert ds.attrs["normal"] == "exact" and ds.attrs["tangential"] == "exact"
    assert float(ds["wear_depth_wheel"].max()) == pytest.approx(1e-4, rel=0.02)
    for f in ("wear.png", "measures.png", "checkpoint.nc", "records/step001_R300.nc"):
        assert (out / f).is_file()
    assert main(["wear", str(path), "--normal", "nonsense", "--out", str(out)]) == 2
    assert "nonsense" in capsys.readouterr().err


def test_wear_compare_closed_loop(tmp_path, capsys):
    """Seed 001's study on a scenario: every model over the first model's distances;
    a figure and a table of worn area, maximum depth and CPU time per model."""
    import csv
    from railcontact.cli import main
    path = _write_tiny(tmp_path)
    out = tmp_path / "cmp"
    assert main(["wear-compare", str(path), "--models", "hertz+fastsim,kpec+fastsim",
                 "--out", str(out)]) in (0, None)
    rows = list(csv.DictReader(open(out / "wear_comparison.csv")))
    assert [r["models"] for r in rows] == ["hertz+fastsim", "kpec+fastsim"]
    assert rows[0]["distance_km"] == rows[1]["distance_km"]
    for r in rows:
        assert float(r["worn_area_mm2"]) > 0 and float(r["max_depth_mm"]) > 0
        assert float(r["cpu_time_s"]) > 0 and float(r["solve_ms_per_patch"]) > 0
    assert (out / "wear_comparison.png").stat().st_size > 10000
    assert "area mm2" in capsys.readouterr().out


# ---------------------------------------------------------------- on the example
def test_example_loop_is_closed(wear_vehicle_example):
    """examples/wear_vehicle.toml: between the first and the last step the leading
    wheelset's mean lateral position in the tight curve and its contact positions
    move (measured: about 0.07 mm and 1.5 mm on the outer wheel's flange)."""
    _, ds = wear_vehicle_example
    s = ds.sel(route="R300", wheelset=1)
    first, last = s.isel(step=0), s.isel(step=-1)
    assert abs(float(last["lateral_position"] - first["lateral_position"])) > 3e-5
    flange = s["contact_y_wheel"].sel(side="left", patch="flange")
    assert float(flange.isel(step=-1) - flange.isel(step=0)) < -5e-4      # up the flank
    assert float(first["lateral_position"]) < -4e-3                 # towards the outer rail


def test_example_trends_and_conservation(wear_vehicle_example):
    """Tight curve: the leading wheelset's outer wheel wears at the flange root and
    flank; the tangent wears the tread; removed area = the law's total (0.5 %)."""
    _, ds = wear_vehicle_example
    y = ds["y_wheel"].values
    for k in range(ds.sizes["step"]):
        tight = ds["wear_rate_wheel"].sel(route="R300", wheelset=1, side="left").isel(step=k)
        assert -0.040 < y[int(np.argmax(tight.values))] < -0.022
        tangent = ds["wear_rate_wheel"].sel(route="tangent").isel(step=k).values
        for rate in tangent.reshape(-1, y.size):
            tread = np.abs(y) < 0.025
            assert np.trapezoid(rate[tread], y[tread]) > 0.95 * np.trapezoid(rate, y)
    law, removed = ds["law_area_wheel"].values, ds["removed_area_wheel"].values
    assert np.all(np.abs(removed / law - 1) < 5e-3)
    assert int(ds["not_converged"].sum()) == 0


def test_conicity_grows_as_the_tread_hollows():
    """A bogie on tangent track without irregularities wears a hollow into the tread
    (its running band, |y| < 15 mm); the equivalent conicity grows step by step
    (measured 0.166, 0.178, 0.187, 0.191)."""
    raw = copy.deepcopy(TINY)
    raw["route"] = [{"name": "tangent", "speed": 40.0, "length": 60.0}]
    raw["wear"].update(steps=3, wheels="vehicle", max_depth_per_step=5e-5)
    raw["dynamics"]["initial_lateral_shift"] = 1e-3
    sc = wear_scenario_from_dict(raw)
    sc.scheduler = "sync"
    ds = ClosedLoopWear(sc, None, progress=False).run(resume=False)
    y = ds["y_wheel"].values
    total = ds["wear_depth_wheel"].sel(wheelset=1, side="right").sum("step").values
    band = np.abs(y) < 0.015
    assert np.trapezoid(total[band], y[band]) > 0.9 * np.trapezoid(total, y)
    gamma = ds["equivalent_conicity"].sel(route="tangent", wheelset=1).values
    assert np.all(np.diff(gamma) > 0) and gamma[-1] > gamma[0] + 0.015


def test_documented_scenario_parses():
    """The closed-loop scenario of docs/wear.md is a valid scenario."""
    import tomllib
    from pathlib import Path
    text = (Path(__file__).resolve().parents[2] / "docs" / "wear.md").read_text()
    block = text.split("## Closed loop")[1].split("```toml")[1].split("```")[0]
    sc = wear_scenario_from_dict(tomllib.loads(block))
    assert [r.name for r in sc.routes] == ["tangent", "R300", "S-curve"]
    assert sc.routes[1].route.curvature.max() == pytest.approx(1 / 300.0)
    assert sc.routes[2].length == pytest.approx(350.0 - 2 * (9.5 + 1.28))   # wheelsets


def test_worn_rails_stay_in_place():
    """A rail worn on its gauge face is not moved back to the gauge: the closed loop
    places worn rails where the new ones were (Track.rail_offsets)."""
    from railcontact.geometry.track import Track
    from railcontact.profiles import rail_profile
    from railcontact.wear.mapping import wear_profile
    new = rail_profile("60E1", 0.025)
    s = np.arange(0.0, float(new.arc_length(new.y_max)) + 1e-4, 1e-4)
    s_gauge = float(new.arc_length(Track(new).gauge_point(new)))
    worn = wear_profile(new, s, 3e-4 * np.exp(-((s - s_gauge) / 6e-3) ** 2), "rail")
    placed = {side: Track(new).rail_offset(side) for side in ("left", "right")}
    by_gauge = Track(worn).rail_offset("right")
    kept = Track(worn, rail_offsets=placed).rail_offset("right")
    assert kept == placed["right"]
    assert kept - by_gauge > 2e-4     # by the gauge the worn rail would move to the track centre
    with pytest.raises(InputError, match="rail_offsets"):
        Track(worn, rail_offsets={"right": 0.7})
