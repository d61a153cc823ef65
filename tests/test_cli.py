"""The command line (railcontact.cli): case files through the JSON contract, and bad input."""

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

import railcontact as rc
from railcontact.cli import main

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


BIG_EXACT = """[bodies]
radii = {wheel_rolling = 0.46, rail_lateral = 0.3}
normal_force = 1e5
[solver]
normal = "exact"
tangential = "exact"
grid = [500, 500]
"""


def test_ctrl_c_stops_a_compiled_loop_within_a_second(tmp_path):
    """SIGINT (Ctrl-C) while the exact solvers iterate on 250 000 elements in
    compiled code: the command ends within a second with exit status 130 and one
    line, and writes nothing."""
    import os
    import signal
    import time
    case = tmp_path / "big.toml"
    case.write_text(BIG_EXACT)
    from pathlib import Path
    script = Path(sys.executable).parent / "railcontact"      # the console script
    if not script.exists():
        pytest.skip("the railcontact console script is not installed beside Python")
    env = {**os.environ, "PYTHONUNBUFFERED": "1"}
    p = subprocess.Popen([str(script), "-v", "solve", str(case), "--out",
                          str(tmp_path / "r.nc")], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, env=env)
    for line in p.stderr:                   # the case read, the solvers about to run
        if "railcontact: info: solving" in line:
            break
    time.sleep(2.0)                         # inside the exact solvers' iterations
    assert p.poll() is None
    t0 = time.monotonic()
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=20)
    elapsed = time.monotonic() - t0
    assert p.returncode == 130 and elapsed < 1.0, (p.returncode, elapsed, err)
    assert err.strip().splitlines()[-1] == "railcontact: interrupted"
    assert not (tmp_path / "r.nc").exists()


def test_ctrl_c_inside_a_compiled_function_is_an_interruption(monkeypatch, capsys):
    """Ctrl-C while Numba runs a compiled function: its dispatcher returns with the
    KeyboardInterrupt set and Python raises ``SystemError: ... returned a result
    with an exception set`` from it (seen once in the test above, under load).
    That is an interruption too: one line, exit status 130; another SystemError
    stays a bug (raised)."""
    import argparse

    import railcontact.cli as cli

    def run(err):
        def func(args):
            try:
                raise KeyboardInterrupt
            except KeyboardInterrupt:
                raise err
        parser = argparse.ArgumentParser()
        parser.add_argument("-v", "--verbose", action="store_true")
        parser.set_defaults(func=func)
        monkeypatch.setattr(cli, "build_parser", lambda: parser)
        return cli.main([])

    assert run(SystemError("CPUDispatcher returned a result with an exception set")) == 130
    assert capsys.readouterr().err.strip() == "railcontact: interrupted"

    def bug(args):
        raise SystemError("not an interruption")
    parser = argparse.ArgumentParser()
    parser.add_argument("-v", "--verbose", action="store_true")
    parser.set_defaults(func=bug)
    monkeypatch.setattr(cli, "build_parser", lambda: parser)
    with pytest.raises(SystemError):
        cli.main([])


def test_warnings_in_one_format(tmp_path, capsys):
    """Warnings of a result go to stderr as 'railcontact: warning: ...' lines and
    into the JSON; p_max beyond the material's limit is one of them."""
    text = (EX / "bodies.toml").read_text().replace("normal_force = 111.5e3", "normal_force = 5e7")
    f = tmp_path / "hard.toml"
    f.write_text(text)
    code, out, err = run_cli(["solve", str(f), "--json"], capsys)
    d = json.loads(out)
    assert code == 0 and any("plasticity: p_max" in w for w in d["warnings"])
    lines = err.strip().splitlines()
    assert lines and all(ln.startswith("railcontact: warning: ") for ln in lines)
    f.write_text(text.replace("[material]", "[material]\nyield_stress = 5e9"))
    code, out, err = run_cli(["solve", str(f), "--json"], capsys)
    assert code == 0 and not json.loads(out)["warnings"]


def test_inp_subsurface_file(capsys, tmp_path, testbank):
    """``railcontact solve FILE.inp --subsurface out.csv|.nc``: the subsurface
    stresses of the cases with STRESS >= 1 beside the table (subsurf.inp: 2 cases x
    (15 + 6615) points), CONTACT's maxima per block on the terminal; the JSON table
    without them."""
    import xarray as xr
    inp = str(testbank / "examples_basic" / "subsurf.inp")
    out = tmp_path / "subs.csv"
    code, text, err = run_cli(["solve", inp, "--subsurface", str(out)], capsys)
    assert code == 0, err
    assert "SUBSURFACE STRESSES BLOCK  2" in text and "MAX SIGVM =     2.179" in text
    lines = out.read_text().splitlines()
    assert lines[0].startswith("case,patch,block,x_mm,y_mm,z_mm,sighyd,sigvm")
    assert len(lines) == 1 + 2 * (15 + 21 * 21 * 15)
    nc = tmp_path / "subs.nc"
    code, text, err = run_cli(["solve", inp, "--case", "2", "--json", "--subsurface", str(nc)],
                              capsys)
    assert code == 0, err
    assert "subsurface" not in json.loads(text)["rows"][0]
    with xr.open_dataset(nc, engine="h5netcdf") as ds:
        assert ds.sizes["point"] == 15 + 21 * 21 * 15
        assert float(ds["sigzz"][0]) == pytest.approx(-1.0, abs=1e-6)
    code, _, err = run_cli(["solve", inp, "--subsurface", str(tmp_path / "s.txt")], capsys)
    assert code == 2 and "expected a .csv or .nc file" in err
