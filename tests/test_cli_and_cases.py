"""Case files, the JSON contract, the command line, and bad input."""

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

import railcontact as rc
from railcontact.cli import main
from railcontact.errors import CaseFileError, UnknownModelError

EX = Path(__file__).resolve().parents[1] / "examples"
CONTRACT_KEYS = {"side", "area", "pmax", "penetration", "Fn", "Fx", "Fy", "Mz", "contact_angle",
                 "rolling_radius", "y_rail", "y_wheel", "creepage"}


def run_cli(args, capsys):
    code = main(args)
    out = capsys.readouterr()
    return code, out.out, out.err


def test_bodies_case_json(capsys):
    code, out, err = run_cli(["solve", str(EX / "bodies.toml"), "--json"], capsys)
    assert code == 0, err
    d = json.loads(out)
    assert d["normal"] == "hertz" and d["tangential"] == "fastsim" and d["cpu_time"] > 0
    (p,) = d["patches"]
    assert CONTRACT_KEYS <= set(p)
    assert p["side"] is None
    # Hertz: A = 1/(2 * 0.46), B = 1/(2 * 0.3)
    h = rc.normal.hertz_ellipse(1 / 0.92, 1 / 0.6, rc.Material().contact_modulus, force=111.5e3)
    assert p["area"] == pytest.approx(math.pi * h.a * h.b, rel=1e-12)
    assert p["pmax"] == pytest.approx(h.p0, rel=1e-12)
    assert p["Fn"] == pytest.approx(111.5e3)
    # positive longitudinal creepage (rail faster than wheel) pulls the wheel forward
    assert p["Fx"] > 0


def test_wheel_rail_case_json(capsys):
    code, out, err = run_cli(["solve", str(EX / "wheel_rail.toml"), "--json"], capsys)
    assert code == 0, err
    d = json.loads(out)
    assert d["patches"] and all(p["side"] == "right" for p in d["patches"])
    p = d["patches"][0]
    assert CONTRACT_KEYS <= set(p)
    assert p["creepage"]["longitudinal"] == -0.001        # overridden by [creepage]
    assert p["Fx"] < 0                                      # braking
    fz = sum(q["Fn"] * math.cos(q["contact_angle"]) - q["Fy"] * math.sin(q["contact_angle"])
             for q in d["patches"])
    assert fz == pytest.approx(70e3, rel=2e-4)              # vertical load met


def test_model_override_and_geometry(capsys):
    code, out, _ = run_cli(["solve", str(EX / "wheel_rail.toml"), "--json", "--tangential",
                            "none"], capsys)
    assert code == 0 and json.loads(out)["patches"][0]["Fx"] == 0.0
    code, out, _ = run_cli(["geometry", str(EX / "wheel_rail.toml"), "--json"], capsys)
    d = json.loads(out)
    assert code == 0 and {"roll", "vertical", "patches"} <= set(d)
    assert all(p["side"] == "right" for p in d["patches"])


def test_sweep_cli(capsys):
    code, out, err = run_cli(["sweep", str(EX / "wheel_rail.toml"), "--vary",
                              "wheelset.lateral_shift=0:0.002:0.001", "--json",
                              "--scheduler", "sync"], capsys)
    assert code == 0, err
    d = json.loads(out)
    assert [c["params"]["wheelset.lateral_shift"] for c in d["cases"]] == [0.0, 0.001, 0.002]
    assert all(c["patches"] for c in d["cases"])
    # the vertical balance of each wheel-rail case, met to the force tolerance here
    assert all(abs(r) <= 1e-4 for c in d["cases"] for r in c["vertical_residual"].values())


def test_sweep_threads_equals_sync():
    case = rc.load_case(EX / "bodies.toml")
    vary = {"creepage.longitudinal": [0.0, 1e-3, 2e-3], "bodies.normal_force": [5e4, 1e5]}
    a = rc.sweep(case, vary, scheduler="sync", progress=False)
    b = rc.sweep(case, vary, scheduler="threads", progress=False)
    assert len(a["cases"]) == 6
    assert [c["patches"][0]["Fx"] for c in a["cases"]] == [c["patches"][0]["Fx"] for c in b["cases"]]


def test_auto_scheduler_uses_processes_for_long_sweeps_only(monkeypatch):
    """"auto" starts worker processes only where the sweep is expected to take longer
    than their start-up is worth (PROCESSES_FROM seconds in one process)."""
    import dask

    import railcontact.case_sweep as sw
    case = rc.load_case(EX / "wheel_rail.toml")
    assert sw._expected_seconds(case, 100, "exact", "exact") == pytest.approx(2.0)
    assert sw._expected_seconds(case, 100, "hertz", "fastsim") == pytest.approx(0.5)
    assert sw._expected_seconds(case, 100, "hertz", "exact") == pytest.approx(2.0)
    used = []
    real = dask.compute

    def spy(*tasks, **kw):
        used.append(kw.get("scheduler"))
        return real(*tasks, scheduler="sync")

    monkeypatch.setattr(dask, "compute", spy)
    vary = {"wheelset.lateral_shift": [0.0, 1e-3]}
    sw.sweep(case, vary, "hertz", "fastsim", progress=False)
    monkeypatch.setattr(sw, "PROCESSES_FROM", 0.001)
    monkeypatch.setattr(sw.os, "cpu_count", lambda: 2)
    sw.sweep(case, vary, "hertz", "fastsim", progress=False)
    assert used == ["sync", "processes"]


@pytest.mark.parametrize("text, msg", [
    ("[wheel]\nprofile='S1002'\n[rail]\nprofile='60E1'\n[solver]\nnormal='hurtz'\n", "hurtz"),
    ("[wheel]\nprofile='S1003'\n[rail]\nprofile='60E1'\n", "S1003"),
    ("[wheel]\nprofile='S1002'\n[rail]\nprofile='60E1'\n[wheelset]\nvertical_force=-5\n",
     "vertical_force"),
    ("[wheel]\nprofile='S1002'\n[rail]\nprofile='60E1'\n[wheelset]\nlateral_shift=3\n",
     "lateral_shift"),
    ("[wheel]\nprofile='S1002'\n[rail]\nprofile='60E1'\n[wheelset]\nlateral_shift=nan\n",
     "lateral_shift"),
    ("[wheel]\nprofile='S1002'\n[rail]\nprofile='60E1'\n[wheelset]\nlateral_shft=0.0\n",
     "lateral_shft"),
    ("[bodies]\nradii={wheel_rolling=0.46, rail_lateral=-0.3}\nnormal_force=1e4\n", "curvatures"),
    ("[wheel]\nprofile='S1002'\n[rail]\nprofile='60E1'\n[wheelset]\ncombine_distance=0.008\n"
     "full_interaction_distance=0.01\n", "full_interaction_distance"),
    ("title = 'x'\n", "missing"),
    ("[wheel\nprofile='S1002'\n", "not valid TOML"),
])
def test_bad_case_files_one_line_error(tmp_path, capsys, text, msg):
    f = tmp_path / "bad.toml"
    f.write_text(text)
    out_file = tmp_path / "res.nc"
    code, out, err = run_cli(["solve", str(f), "--json", "--out", str(out_file)], capsys)
    assert code == 2
    assert err.startswith("railcontact: error:") and msg in err
    assert len(err.strip().splitlines()) == 1
    assert out == "" and not out_file.exists()


def test_missing_case_file_and_bad_profile_file(tmp_path, capsys):
    code, _, err = run_cli(["solve", str(tmp_path / "nope.toml")], capsys)
    assert code == 2 and "does not exist" in err
    prof = tmp_path / "w.csv"
    prof.write_text("y,z\n1,2\n2,1\n1.5,3\n")
    case = tmp_path / "c.toml"
    case.write_text(f"[wheel]\nprofile='{prof}'\n[rail]\nprofile='60E1'\n")
    code, _, err = run_cli(["solve", str(case)], capsys)
    assert code == 2 and "profile" in err


def test_api_errors():
    with pytest.raises(CaseFileError):
        rc.case_from_dict({"wheel": {"profile": "S1002"}})
    with pytest.raises(UnknownModelError):
        rc.solve(rc.load_case(EX / "bodies.toml"), normal="nope")


def test_profile_cli(tmp_path, capsys):
    out = tmp_path / "s1002.prw"
    code, _, err = run_cli(["profile", "export", "S1002", "--out", str(out)], capsys)
    assert code == 0, err
    assert rc.profiles.read_profile(out).kind == "wheel"
    png = tmp_path / "r.png"
    code, _, err = run_cli(["profile", "plot", "60E1", "--out", str(png)], capsys)
    assert code == 0 and png.stat().st_size > 1000


def test_netcdf_output(tmp_path, capsys):
    out = tmp_path / "res.nc"
    code, _, err = run_cli(["solve", str(EX / "bodies.toml"), "--out", str(out)], capsys)
    assert code == 0, err
    import xarray as xr
    ds = xr.open_dataset(out, engine="h5netcdf")
    assert ds["Fn"].attrs["units"] == "N" and float(ds["Fn"][0]) == pytest.approx(111.5e3)


def test_console_script_entry_point():
    r = subprocess.run([sys.executable, "-m", "railcontact.cli", "--help"], capture_output=True,
                       text=True)
    assert r.returncode == 0 and "solve" in r.stdout


def test_compare_cli(tmp_path, capsys):
    code, out, err = run_cli(["compare", str(EX / "bodies.toml"), "--models",
                              "hertz,kpec,analyn,exact", "--out", str(tmp_path)], capsys)
    assert code == 0, err
    assert "kpec" in out and "analyn" in out
    import csv
    rows = list(csv.DictReader(open(tmp_path / "comparison.csv")))
    assert [r["model"] for r in rows] == ["hertz", "kpec", "analyn", "exact"]
    # on a Hertzian case all four agree on the contact area within 3 %
    areas = [float(r["area_mm2"]) for r in rows]
    assert max(areas) / min(areas) < 1.03
    for f in ("outlines.png", "lateral_pressure.png"):
        assert (tmp_path / f).stat().st_size > 5000
    code, out, err = run_cli(["compare", str(EX / "bodies.toml"), "--models", "hertz,nope"],
                             capsys)
    assert code == 2 and "nope" in err


def test_per_wheel_loads():
    res = rc.solve(rc.case_from_dict({"wheel": {"profile": "S1002"}, "rail": {"profile": "60E1"},
                                      "wheelset": {"lateral_shift": 0.002,
                                                   "vertical_force": [50e3, 90e3]}}))
    for side, load in (("left", 50e3), ("right", 90e3)):
        fz = sum(p.normal.normal_force * math.cos(p.geometry.contact_angle)
                 - p.tangential.fy * math.sin(p.geometry.contact_angle)
                 for p in res.patches if p.geometry.side == side)
        assert fz == pytest.approx(load, rel=2e-4)
    with pytest.raises(CaseFileError, match="vertical_force"):
        rc.case_from_dict({"wheel": {"profile": "S1002"}, "rail": {"profile": "60E1"},
                           "wheelset": {"vertical_force": [1.0, 2.0, 3.0]}})


def test_prescribed_forces_bodies_case(tmp_path, capsys):
    text = (EX / "bodies.toml").read_text() + "\n[force]\nlongitudinal = 12000.0\nlateral = -3000.0\n"
    f = tmp_path / "forces.toml"
    f.write_text(text)
    code, out, err = run_cli(["solve", str(f), "--json"], capsys)
    assert code == 0, err
    (p,) = json.loads(out)["patches"]
    assert p["Fx"] == pytest.approx(12000.0, abs=1.0)
    assert p["Fy"] == pytest.approx(-3000.0, abs=1.0)
    assert p["creepage"]["longitudinal"] > 0
    bad = tmp_path / "bad.toml"
    bad.write_text((EX / "wheel_rail.toml").read_text() + "\n[force]\nlongitudinal = 1.0\n")
    code, out, err = run_cli(["solve", str(bad)], capsys)
    assert code == 2 and "[force]" in err


def _shifted(tmp_path, shift):
    text = (EX / "wheel_rail.toml").read_text().replace("lateral_shift = 0.003",
                                                        f"lateral_shift = {shift}")
    path = tmp_path / f"shift_{shift}.toml"
    path.write_text(text)
    return path


def test_a_derailed_wheelset_is_not_a_solution(tmp_path, capsys):
    """50 mm lateral shift: the wheel stands on its flange tip (rolling radius 488 mm,
    the tip's).  Such a state has no equilibrium on track: the case says so in the
    result, the JSON, and on the command line (exit status 1), though every solver
    converged."""
    code, out, err = run_cli(["solve", str(_shifted(tmp_path, 0.05)), "--json"], capsys)
    d = json.loads(out)
    (p,) = d["patches"]
    assert p["rolling_radius"] == pytest.approx(0.488, abs=5e-4)
    assert d["converged"] is False and "derailment" in d["message"]
    assert code == 1 and "not converged" in err and "derailment" in err
    res = rc.solve(rc.load_case(_shifted(tmp_path, 0.05)))
    assert not res.converged and res.balance.converged        # the balance itself is met


@pytest.mark.parametrize("shift, climbing", [(0.003, False), (0.006, False), (0.009, True)])
def test_flange_climb_is_flagged(tmp_path, capsys, shift, climbing):
    """Flange contact beyond the steepest part of the S1002 flange (70 degrees, up to
    39.8 mm from the tape circle) is flange climb: a warning on a converged result.
    At 9 mm the contact lies at 43.3 mm on the flange, its contact angle 50 degrees."""
    code, out, err = run_cli(["solve", str(_shifted(tmp_path, shift)), "--json"], capsys)
    d = json.loads(out)
    assert code == 0 and d["converged"] is True
    flagged = any("flange climb" in w for w in d["warnings"])
    assert flagged == climbing
    assert ("flange climb" in err) == climbing


# ------------------------------------------------- CONTACT's options in case files
def _mbench_raw(refdir, **wheelset):
    prof = refdir / "profiles"
    return {"material": {"young_modulus": 2 * 82e9 * 1.28, "poisson_ratio": 0.28},
            "friction": {"coefficient": 0.3},
            "wheel": {"profile": str(prof / "MBench_S1002_v3.prw")},
            "rail": {"profile": str(prof / "MBench_UIC60_v3.prr"), "inclination": 0.0},
            "wheelset": {"vertical_force": 1e4, "velocity": 2.0, "side": "right", "roll": 0.0,
                         **wheelset},
            "solver": {"normal": "exact", "tangential": "exact",
                       "element_size": [2.5e-4, 2.5e-4]}}


def test_friction_varying_with_the_rail_inclination(refdir):
    """friction.variation (CONTACT's VARFRC = 1): each patch takes the coefficient
    at its rail surface's inclination, interpolated linearly, constant beyond."""
    from railcontact import case_from_dict, solve
    var = {"angle": [-0.5236, -0.3491], "coefficient": [0.2, 0.35]}
    for y, mu in ((2e-3, 0.35), (9e-3, 0.2)):       # tread, flange flank
        raw = _mbench_raw(refdir, lateral_shift=y)
        raw["friction"]["variation"] = var
        res = solve(case_from_dict(raw))
        (p,) = res.patches
        assert p.tangential.friction == mu
        assert abs(complex(p.tangential.fx, p.tangential.fy)) <= mu * p.normal.normal_force * 1.0001
    case = case_from_dict({**_mbench_raw(refdir), "friction": {"variation": var}})
    assert case.friction_at(-0.4363) == pytest.approx(0.275, abs=1e-3)
    for bad in ({"angle": [0.1, 0.0], "coefficient": [0.2, 0.3]},
                {"angle": [0.0], "coefficient": [0.2, 0.3]}, {"angles": [0.0]}):
        with pytest.raises(CaseFileError, match="friction.variation"):
            case_from_dict({**_mbench_raw(refdir), "friction": {"variation": bad}})


def test_vertical_position_prescribed(refdir):
    """wheelset.vertical_position (CONTACT's NORM = 0): at the height the force
    control found, the same patch and force (to the force tolerance)."""
    from railcontact import case_from_dict, solve
    force = solve(case_from_dict(_mbench_raw(refdir, lateral_shift=3e-3)))
    raw = _mbench_raw(refdir, lateral_shift=3e-3, vertical_position=force.pose.vertical)
    del raw["wheelset"]["vertical_force"]
    pos = solve(case_from_dict(raw))
    assert pos.balance is None and pos.pose.vertical == force.pose.vertical
    assert pos.patches[0].normal.normal_force == pytest.approx(
        force.patches[0].normal.normal_force, rel=2e-4)
    # raised by 1 mm the wheel does not reach the rail: no patch, no error
    raw["wheelset"]["vertical_position"] = force.pose.vertical - 1e-3
    assert solve(case_from_dict(raw)).patches == []
    raw["wheelset"]["vertical_force"] = 1e4
    with pytest.raises(CaseFileError, match="either vertical_force or vertical_position"):
        case_from_dict(raw)
    del raw["wheelset"]["roll"], raw["wheelset"]["vertical_force"]
    with pytest.raises(CaseFileError, match="give wheelset.roll"):
        case_from_dict(raw)
