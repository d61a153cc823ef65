"""Every CONTACT input of ../shared/reference through ``railcontact solve``.

The wheel-rail files are compared case by case in tests/test_exact_wheel_rail.py
and tests/normal/test_semi_hertzian.py (selected cases; all of them in
benchmarks/contact_inputs.py); here: that every file is read and mapped, the
module 3 (Hertzian) files against their CSV, and the command line."""

import json
import subprocess
import sys

import pytest

from railcontact.cli import main
from railcontact.contact_inp import load_inp, solve_inp
from tests.conftest import read_csv

FILES = ["mbench_a22/mbench_a22_left.inp", "mbench_a22/mbench_a22_right.inp",
         "mbench_a22/mbench_a22_kpec.inp", "mbench_sweep_10kN.inp",
         "mbench_sweep_10kN_dx0125.inp", "kalker_example.inp", "timing_m3_40x40_example.inp"]


def test_every_reference_input_is_read(refdir):
    assert sorted(str(p.relative_to(refdir)) for p in refdir.rglob("*.inp")) == sorted(FILES)
    counts = {f: len(load_inp(refdir / f, profile_dirs=[refdir / "profiles"])) for f in FILES}
    assert counts == {FILES[0]: 21, FILES[1]: 21, FILES[2]: 9, FILES[3]: 25, FILES[4]: 25,
                      FILES[5]: 1, FILES[6]: 1}


def test_kalker_example(refdir):
    """Module 3, Hertzian circle (IPOTCN = -3) on 80 x 80 elements, CKSI = 1e-5:
    F_x and the elements in contact and in slip are CONTACT's (measured F_x -87.02
    N, CONTACT's -87.02 N)."""
    (r,) = solve_inp(refdir / "kalker_example.inp")
    (ref,) = [x for x in read_csv(refdir / "kalker_coefficients_contact.csv")
              if x["nu"] == "0.28" and x["a_over_b"] == "1.0" and x["mx"] == "80"
              and x["creepage"] == "1e-05" and x["mu"] == "0.3"]
    assert r["module"] == 3 and (r["mx"], r["my"]) == (80, 80)
    assert r["dx_mm"] == pytest.approx(float(ref["dx_mm"]))
    assert r["fx_N"] == pytest.approx(float(ref["fx_xi_N"]), rel=1e-3)
    assert r["fn_N"] == pytest.approx(float(ref["fn_N"]), rel=1e-9)
    assert (r["ncon"], r["nslip"]) == (int(ref["ncon"]), int(ref["nslip_xi"]))


def test_timing_example(refdir):
    (r,) = solve_inp(refdir / "timing_m3_40x40_example.inp")
    (ref,) = [x for x in read_csv(refdir / "contact_timing.csv")
              if x["case"] == "circ_partial_slip" and x["eps"] == "1e-06"
              and x["omp_threads"] == "1" and x["build"] == "mkl_fft"]
    assert (r["ncon"], r["nslip"]) == (int(ref["ncon"]), int(ref["nslip"]))


def test_command_line(refdir, tmp_path, capsys):
    inp = str(refdir / "mbench_sweep_10kN.inp")
    prof = str(refdir / "profiles")
    out = tmp_path / "t.csv"
    assert main(["solve", inp, "--case", "3,11", "--profiles", prof, "--out", str(out)]) == 0
    rows = read_csv(out)
    assert [r["case"] for r in rows] == ["3", "11"]
    ref = read_csv(refdir / "mbench_sweep_10kN.csv")
    assert float(rows[1]["ycp_tr_mm"]) == pytest.approx(float(ref[10]["ycp_tr_mm"]), abs=0.01)
    capsys.readouterr()
    assert main(["sweep", inp, "--case", "3-4", "--profiles", prof, "--scheduler", "sync",
                 "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert [r["case"] for r in d["rows"]] == [3, 4] and d["units"].startswith("CONTACT")
    # errors: one line, exit status 2, nothing written
    bad = tmp_path / "bad.csv"
    assert main(["solve", str(refdir / "mbench_a22" / "mbench_a22_right.inp"),
                 "--out", str(bad)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "not found" in err and "--profiles" in err
    assert not bad.exists()
    assert main(["sweep", inp, "--vary", "wheelset.yaw=0:0.001:0.001"]) == 2
    assert main(["solve", inp, "--case", "x"]) == 2


def test_console_script(refdir, tmp_path):
    """``railcontact`` as installed: a module 3 file, JSON on stdout."""
    r = subprocess.run([sys.executable, "-m", "railcontact.cli", "solve",
                        str(refdir / "timing_m3_40x40_example.inp"), "--json"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    (row,) = json.loads(r.stdout)["rows"]
    assert row["ncon"] == 1044
