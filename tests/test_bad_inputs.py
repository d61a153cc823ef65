"""A corpus of bad inputs: each one gives its exact exit status and a one-line error
naming the input, before any work (nothing written, no traceback).

Each row: an id, the command line (``{d}`` is the test's folder, ``{ref}`` the
CONTACT reference folder), the files to write first (name -> text), the exit status
and a piece of the message.  Run in-process through :func:`railcontact.cli.main`
in the test's folder.
"""

import json
import sys
from pathlib import Path

import numpy as np
import pytest

import railcontact as rc
from railcontact.cli import main

ROOT = Path(__file__).resolve().parents[1]
EX = ROOT / "examples"

WR = "[wheel]\nprofile='S1002'\n[rail]\nprofile='60E1'\n"
BODIES = ("[bodies]\nradii={wheel_rolling=0.46, rail_lateral=0.3}\nnormal_force=1e4\n"
          "[solver]\nnormal='hertz'\ntangential='fastsim'\n")
WEAR = (EX / "wear_demo.toml").read_text()
DYN = (EX / "dynamics_demo.toml").read_text()


def _case(extra):
    return {"c.toml": WR + extra}


def _inp():
    """The first three cases of CONTACT's 10 kN sweep (profiles in the reference
    folder), as text to corrupt."""
    from tests.conftest import reference_dir
    ref = reference_dir()
    if ref is None:
        return None
    text = (ref / "mbench_sweep_10kN.inp").read_text()
    parts = text.split("  1 MODULE")
    return "  1 MODULE".join(parts[:4]).replace("'profiles/", f"'{ref}/profiles/")


INP = _inp()


def _inp_with(old, new, case=1, count=1):
    """The .inp text with ``old`` replaced by ``new`` in case ``case`` (1-based)."""
    if INP is None:
        return None
    parts = INP.split("  1 MODULE")
    assert old in parts[case], old
    parts[case] = parts[case].replace(old, new, count)
    return "  1 MODULE".join(parts)


def _line_of(text, needle):
    return next(i for i, ln in enumerate(text.splitlines(), 1) if needle in ln)


# (id, argv, files, exit status, message piece)
CASES = [
    # ---- case files: models, profiles, loads, positions ----
    ("normal-model", "solve c.toml", _case("[solver]\nnormal='hurtz'\n"), 2,
     "unknown normal model 'hurtz'"),
    ("tangential-model", "solve c.toml", _case("[solver]\ntangential='fastism'\n"), 2,
     "unknown tangential model 'fastism'"),
    ("wheel-profile", "solve c.toml", {"c.toml": "[wheel]\nprofile='S1003'\n[rail]\n"
                                                 "profile='60E1'\n"}, 2,
     "wheel profile 'S1003': neither a built-in name"),
    ("rail-profile-as-wheel-name", "solve c.toml",
     {"c.toml": "[wheel]\nprofile='60E1'\n[rail]\nprofile='60E1'\n"}, 2,
     "wheel profile '60E1': neither a built-in name (S1002)"),
    ("wheel-profile-as-rail", "solve c.toml",
     {"c.toml": "[wheel]\nprofile='S1002'\n[rail]\nprofile='S1002'\n"}, 2,
     "rail profile 'S1002': neither a built-in name"),
    ("load-negative", "solve c.toml", _case("[wheelset]\nvertical_force=-5\n"), 2,
     "wheelset.vertical_force = -5: expected loads in [1, 1e7] N"),
    ("load-huge", "solve c.toml", _case("[wheelset]\nvertical_force=1e9\n"), 2,
     "wheelset.vertical_force = 1000000000.0: expected loads in [1, 1e7] N"),
    ("load-three", "solve c.toml", _case("[wheelset]\nvertical_force=[1e4, 1e4, 1e4]\n"), 2,
     "expected one load or [left, right] in N"),
    ("load-string", "solve c.toml", _case("[wheelset]\nvertical_force='70kN'\n"), 2,
     "wheelset.vertical_force = '70kN': expected loads in"),
    ("load-bool", "solve c.toml", _case("[wheelset]\nvertical_force=true\n"), 2,
     "wheelset.vertical_force = True"),
    ("load-long-list", "solve c.toml",
     _case("[wheelset]\nvertical_force=[" + ",".join(["1e4"] * 20000) + "]\n"), 2,
     "... (20000 items): expected one load or [left, right] in N"),
    ("shift-large", "solve c.toml", _case("[wheelset]\nlateral_shift=3\n"), 2,
     "wheelset.lateral_shift = 3"),
    ("shift-nan", "solve c.toml", _case("[wheelset]\nlateral_shift=nan\n"), 2,
     "wheelset.lateral_shift = nan"),
    ("shift-inf", "solve c.toml", _case("[wheelset]\nlateral_shift=inf\n"), 2,
     "wheelset.lateral_shift = inf"),
    ("shift-string", "solve c.toml", _case("[wheelset]\nlateral_shift='3mm'\n"), 2,
     "wheelset.lateral_shift = '3mm': expected a number in m"),
    ("yaw-large", "solve c.toml", _case("[wheelset]\nyaw=2.0\n"), 2, "wheelset.yaw = 2.0"),
    ("unknown-key", "solve c.toml", _case("[wheelset]\nlateral_shft=0.0\n"), 2,
     "unknown key wheelset.lateral_shft"),
    ("unknown-section", "solve c.toml", _case("[wheels]\nx=1\n"), 2,
     "unknown section or key [wheels]"),
    ("section-not-table", "solve c.toml", {"c.toml": "wheel='S1002'\n[rail]\nprofile='60E1'\n"},
     2, "[wheel] must be a table"),
    ("missing-rail", "solve c.toml", {"c.toml": "[wheel]\nprofile='S1002'\n"}, 2,
     "missing [wheel] and [rail] (or [bodies])"),
    ("bodies-and-wheel", "solve c.toml", {"c.toml": BODIES + WR}, 2,
     "a case has either [bodies] or [wheel]"),
    ("bodies-no-radii", "solve c.toml", {"c.toml": "[bodies]\nnormal_force=1e4\n"}, 2,
     "bodies.radii = None: expected a table"),
    ("bodies-concave", "solve c.toml",
     {"c.toml": "[bodies]\nradii={wheel_rolling=0.46, rail_lateral=-0.3}\nnormal_force=1e4\n"},
     2, "relative curvatures A = "),
    ("bodies-zero-radius", "solve c.toml",
     {"c.toml": "[bodies]\nradii={wheel_rolling=0, rail_lateral=0.3}\nnormal_force=1e4\n"},
     2, "bodies.radii.wheel_rolling = 0"),
    ("bodies-negative-force", "solve c.toml",
     {"c.toml": BODIES.replace("normal_force=1e4", "normal_force=-1e4")}, 2,
     "bodies.normal_force = -10000.0"),
    ("friction-large", "solve c.toml", _case("[friction]\ncoefficient=7\n"), 2,
     "friction.coefficient = 7: expected a value in [0, 5]"),
    ("friction-string", "solve c.toml", _case("[friction]\ncoefficient='high'\n"), 2,
     "friction.coefficient = 'high'"),
    ("friction-variation", "solve c.toml", _case("[friction]\nvariation={angle=[0.1]}\n"), 2,
     "friction.variation = {'angle': [0.1]}"),
    ("modulus-string", "solve c.toml", _case("[material]\nyoung_modulus='steel'\n"), 2,
     "material.young_modulus = 'steel': expected a number in Pa"),
    ("poisson", "solve c.toml", _case("[material]\npoisson_ratio=0.6\n"), 2,
     "material.poisson_ratio = 0.6"),
    ("yield-stress", "solve c.toml", _case("[material]\nyield_stress=-1\n"), 2,
     "material.yield_stress = -1"),
    ("grid-zero", "solve c.toml", _case("[solver]\ngrid=[0, 40]\n"), 2,
     "solver.grid = [0, 40]: expected two positive finite numbers"),
    ("grid-fraction", "solve c.toml", _case("[solver]\ngrid=[40.5, 40]\n"), 2,
     "solver.grid = [40.5, 40]: expected two integers in [2, 2000]"),
    ("grid-huge", "solve c.toml", _case("[solver]\nnormal='exact'\ngrid=[2000, 2000]\n"), 2,
     "solver.grid = [2000, 2000]: 4000000 elements (about 3.2 GB"),
    ("grid-allow-string", "solve c.toml", _case("[solver]\nallow_large='yes'\n"), 2,
     "solver.allow_large = 'yes': expected true or false"),
    ("grid-and-size", "solve c.toml",
     _case("[solver]\ngrid=[40, 40]\nelement_size=[1e-4, 1e-4]\n"), 2,
     "give either grid or element_size, not both"),
    ("element-size-negative", "solve c.toml", _case("[solver]\nelement_size=[-1e-4, 1e-4]\n"),
     2, "solver.element_size = [-0.0001, 0.0001]"),
    ("force-tolerance", "solve c.toml", _case("[solver]\nforce_tolerance=0.5\n"), 2,
     "solver.force_tolerance = 0.5"),
    ("creepage", "solve c.toml", _case("[creepage]\nlongitudinal=2\n"), 2,
     "creepage.longitudinal = 2"),
    ("force-on-wheel-rail", "solve c.toml", _case("[force]\nlongitudinal=1.0\n"), 2,
     "[force] (prescribed tangential forces) needs a [bodies] case"),
    ("plasticity-hertz", "solve c.toml", _case("[plasticity]\nyield_stress=5e8\n"), 2,
     "[plasticity] bounds the pressure of the exact normal model"),
    ("plasticity-both", "solve c.toml",
     _case("[solver]\nnormal='exact'\n[plasticity]\nyield_stress=5e8\npressure_limit=1e9\n"),
     2, "give pressure_limit, or yield_stress"),
    ("side", "solve c.toml", _case("[wheelset]\nside='middle'\n"), 2,
     "wheelset.side = 'middle': expected 'left', 'right' or 'both'"),
    ("combine-distance", "solve c.toml",
     _case("[wheelset]\ncombine_distance=0.008\nfull_interaction_distance=0.01\n"), 2,
     "full_interaction_distance"),
    ("gauge", "solve c.toml", _case("[track]\ngauge=10\n"), 2, "track.gauge = 10"),
    ("nominal-radius", "solve c.toml",
     {"c.toml": "[wheel]\nprofile='S1002'\nnominal_radius=5\n[rail]\nprofile='60E1'\n"}, 2,
     "wheel.nominal_radius = 5"),
    ("not-toml", "solve c.toml", {"c.toml": "[wheel\nprofile='S1002'\n"}, 2, "not valid TOML"),
    ("empty-file", "solve c.toml", {"c.toml": ""}, 2, "missing [wheel] and [rail]"),
    ("binary-file", "solve c.toml", {"c.toml": "\x00\x01\x02\xff"}, 2, "c.toml: not valid TOML"),
    ("missing-file", "solve nope.toml", {}, 2, "case file 'nope.toml' does not exist"),
    ("folder-as-case", "solve sub", {"sub/x": ""}, 2, "case file 'sub' does not exist"),
    ("profile-file-bad", "solve c.toml",
     {"w.csv": "y,z\n1,2\n2,1\n1.5,3\n", "c.toml": "[wheel]\nprofile='w.csv'\n[rail]\n"
                                                   "profile='60E1'\n"}, 2, "w.csv"),
    ("profile-file-empty", "solve c.toml",
     {"w.csv": "", "c.toml": "[wheel]\nprofile='w.csv'\n[rail]\nprofile='60E1'\n"}, 2, "w.csv"),
    # ---- command-line options ----
    ("out-missing-folder", "solve c.toml --out nodir/r.nc", {"c.toml": BODIES}, 2,
     "--out 'nodir/r.nc': the folder 'nodir' does not exist"),
    ("out-read-only-place", "solve c.toml --out /proc/r.nc", {"c.toml": BODIES}, 2,
     "--out '/proc/r.nc': not writable (folder '/proc')"),
    ("out-folder-read-only-place", "wear w.toml --out /proc/w", {"w.toml": WEAR}, 2,
     "--out '/proc/w': the folder '/proc' is not writable"),
    ("out-is-folder", "solve c.toml --out sub", {"c.toml": BODIES, "sub/x": ""}, 2,
     "--out 'sub': an existing folder; expected a file name"),
    ("solve-normal-option", "solve c.toml --normal hurtz", {"c.toml": BODIES}, 2,
     "unknown normal model 'hurtz'"),
    ("solve-tangential-option", "solve c.toml --tangential bogus", {"c.toml": BODIES}, 2,
     "unknown tangential model 'bogus'"),
    ("solve-case-option", "solve c.toml --case 1", {"c.toml": BODIES}, 2,
     "--case and --profiles apply to CONTACT input files"),
    ("sweep-no-vary", "sweep c.toml", {"c.toml": BODIES}, 2, "sweep: give --vary"),
    ("sweep-vary-spec", "sweep c.toml --vary x", {"c.toml": BODIES}, 2,
     "--vary 'x': expected KEY=START:STOP:STEP"),
    ("sweep-vary-zero-step", "sweep c.toml --vary bodies.normal_force=1:2:0", {"c.toml": BODIES},
     2, "expected KEY=START:STOP:STEP with a non-zero step"),
    ("sweep-vary-wrong-sign", "sweep c.toml --vary bodies.normal_force=1:2:-1",
     {"c.toml": BODIES}, 2, "step that reaches STOP"),
    ("sweep-vary-nan", "sweep c.toml --vary bodies.normal_force=nan:2:1", {"c.toml": BODIES}, 2,
     "(finite numbers)"),
    ("sweep-vary-huge", "sweep c.toml --vary bodies.normal_force=1:2:1e-9", {"c.toml": BODIES},
     2, "1000000000 cases; the limit is 100000 (give fewer, or --allow-large"),
    ("sweep-vary-value", "sweep c.toml --vary bodies.normal_force=1e4,-5", {"c.toml": BODIES}, 2,
     "bodies.normal_force = -5.0"),
    ("sweep-vary-key", "sweep c.toml --vary bodies.force=1,2", {"c.toml": BODIES}, 2,
     "bodies.force"),
    ("sweep-scheduler", "sweep c.toml --vary bodies.normal_force=1e4,2e4 --scheduler gpu",
     {"c.toml": BODIES}, 2, "--scheduler = 'gpu': expected 'threads', 'processes', 'sync'"),
    ("sweep-out-case", "sweep c.toml --vary bodies.normal_force=1e4,2e4 --out x.csv",
     {"c.toml": BODIES}, 2, "--case, --profiles and --out apply to CONTACT input files"),
    ("compare-model", "compare c.toml --models hertz,hurtz", {"c.toml": BODIES}, 2,
     "unknown normal model 'hurtz'"),
    ("compare-tangential", "compare c.toml --tangential bogus", {"c.toml": BODIES}, 2,
     "unknown tangential model 'bogus'"),
    ("compare-out-file", "compare c.toml --out f", {"c.toml": BODIES, "f": "x"}, 2,
     "--out 'f': an existing file; expected a folder"),
    ("wear-out-file", "wear w.toml --out f", {"w.toml": WEAR, "f": "x"}, 2,
     "--out 'f': an existing file; expected a folder"),
    ("wear-out-under-file", "wear w.toml --out f/sub", {"w.toml": WEAR, "f": "x"}, 2,
     "--out 'f/sub': 'f' is a file; expected a folder"),
    ("wear-scheduler", "wear w.toml --scheduler gpu", {"w.toml": WEAR}, 2,
     "--scheduler = 'gpu'"),
    ("wear-normal", "wear w.toml --normal hurtz", {"w.toml": WEAR}, 2,
     "unknown normal model 'hurtz'"),
    ("wear-missing", "wear nope.toml", {}, 2, "nope.toml"),
    ("wear-both-steps", "wear w.toml",
     {"w.toml": WEAR.replace("max_depth_per_step = 1e-4", "max_depth_per_step = 1e-4\n"
                                                           "step_distance = 1000.0")}, 2,
     "give max_depth_per_step (the step chosen by the depth) or step_distance"),
    ("wear-scheduler-key", "wear w.toml",
     {"w.toml": WEAR.replace("[wear]", "[wear]\nscheduler = 'gpu'")}, 2,
     "wear.scheduler = 'gpu'"),
    ("wear-law", "wear w.toml",
     {"w.toml": WEAR.replace('law = "frictional-power"', 'law = "magic"')}, 2, "magic"),
    ("wear-compare-model", "wear-compare w.toml --models hertz+fastsim,hurtz+fastsim",
     {"w.toml": WEAR}, 2, "unknown normal model 'hurtz'"),
    ("wear-compare-tangential", "wear-compare w.toml --models hertz+fastism",
     {"w.toml": WEAR}, 2, "unknown tangential model 'fastism'"),
    ("wear-compare-pair", "wear-compare w.toml --models hertz", {"w.toml": WEAR}, 2,
     "--models 'hertz': expected NORMAL+TANGENTIAL pairs"),
    ("wear-compare-out-file", "wear-compare w.toml --out f", {"w.toml": WEAR, "f": "x"}, 2,
     "--out 'f': an existing file"),
    ("simulate-out-file", "simulate d.toml --out f", {"d.toml": DYN, "f": "x"}, 2,
     "--out 'f': an existing file"),
    ("simulate-missing", "simulate nope.toml --out o", {}, 2, "nope.toml"),
    ("simulate-batch-scheduler", "simulate a.toml b.toml --out o --scheduler gpu",
     {"a.toml": DYN, "b.toml": DYN}, 2, "--scheduler = 'gpu'"),
    ("profile-export-no-out", "profile export S1002", {}, 2,
     "profile export needs --out FILE"),
    ("profile-export-missing-folder", "profile export S1002 --out nodir/s.prw", {}, 2,
     "the folder 'nodir' does not exist"),
    ("profile-export-folder", "profile export S1002 --out sub", {"sub/x": ""}, 2,
     "an existing folder"),
    ("profile-unknown", "profile plot S1003 --out s.png", {}, 2, "S1003"),
    ("track-zero-step", "track c.toml --from 0 --to 1 --step 0", {"c.toml": WR}, 2,
     "expected start <= stop and a step > 0"),
    ("track-reversed", "track c.toml --from 1 --to 0 --step 0.1", {"c.toml": WR}, 2,
     "expected start <= stop"),
    ("track-nan", "track c.toml --from 0 --to nan --step 0.1", {"c.toml": WR}, 2,
     "expected start <= stop and a step > 0"),
    ("track-tiny-step", "track c.toml --from 0.09 --to 0.1 --step 1e-9", {"c.toml": WR}, 2,
     "10000001 cases (about 1.39e+03 h at 0.5 s each); the limit is 100000"),
    ("track-out-file", "track c.toml --from 0 --to 0.01 --step 0.001 --out f",
     {"c.toml": WR, "f": "x"}, 2, "--out 'f': an existing file"),
    ("geometry-bodies", "geometry c.toml", {"c.toml": BODIES}, 2,
     "geometry needs a wheel-rail case"),
    ("demo-out-file", "demo --out f", {"f": "x"}, 2, "--out 'f': an existing file"),
    ("inp-out-suffix", "solve x.inp --out r.txt", {"x.inp": "1 MODULE\n"}, 2,
     "expected a .csv or .json file"),
    ("inp-vary", "sweep x.inp --vary a=1,2", {"x.inp": "1 MODULE\n"}, 2,
     "--vary applies to case files"),
    ("inp-case-spec", "solve x.inp --case 1,x", {"x.inp": "1 MODULE\n"}, 2,
     "--case '1,x': expected case numbers"),
    ("inp-out-missing-folder", "solve x.inp --out nodir/r.csv", {"x.inp": "1 MODULE\n"}, 2,
     "the folder 'nodir' does not exist"),
    # ---- CONTACT input files ----
    ("inp-missing", "solve nope.inp", {}, 2, "CONTACT input file 'nope.inp' does not exist"),
    ("inp-empty", "solve x.inp", {"x.inp": "% nothing\n"}, 2, "x.inp: no case found"),
    ("inp-module", "solve x.inp", {"x.inp": "\n\n 2 MODULE\n"}, 2,
     "x.inp, line 3: MODULE = 2: expected 1 (wheel-rail), 3 (basic contact) or 0"),
    ("inp-module-text", "solve x.inp", {"x.inp": "one MODULE\n"}, 2,
     "x.inp, line 1: MODULE = 'one': expected an integer"),
    ("inp-binary", "solve x.inp", {"x.inp": "\x00\xff\x10"}, 2, "x.inp, line 1: MODULE"),
    ("inp-end-of-file", "solve x.inp", {"x.inp": "1 MODULE\n 1203100\n"}, 2,
     "x.inp, line 2: unexpected end of file reading VLDCMZE"),
]

INP_CASES = [
    # (id, old, new, case, message piece, the line's needle in the corrupted text)
    ("inp-control-word-letters", " 0111002 ", " 01110x2 ", 2,
     "VLDCMZE = '01110x2': expected an integer", "01110x2"),
    ("inp-control-word-negative", " 0111002 ", " -111002 ", 2,
     "control word VLDCMZE = -111002: expected a non-negative integer", "-111002"),
    ("inp-control-word-long", " 0111002 ", " 111111002 ", 2,
     "control word VLDCMZE = 111111002: expected at most 7 digits", "111111002"),
    ("inp-negative-fz", "10000.0", "-10000.0", 3,
     "case 3 (line {line}): wheelset.vertical_force = -10000.0", "-10000.0"),
    ("inp-huge-fz", "10000.0", "1e12", 2,
     "case 2 (line {line}): wheelset.vertical_force = 1000000000000.0", "1e12"),
    ("inp-bad-real", "0.300   0.300", "0.300   abc", 1, "FKIN = 'abc': expected a real number",
     "abc"),
    ("inp-friction-law", " 0022033 ", " 0922033 ", 1, "FRCLAW = 9: expected 0 .. 6", "0922033"),
    ("inp-integer", "    999     100", "    9x9     100", 1, "MAXGS = '9x9': expected an integer",
     "9x9"),
    ("inp-stresses", " 1203100 ", " 1203101 ", 1, "STRESS = 1 (subsurface stresses at the "
     "points kept) without points", "1203101"),
    ("inp-profile-missing", "MBench_UIC60_v3.prr", "nope.prr", 1,
     "profile file", "nope.prr"),
    ("inp-module-two", "", "", 0, None, None),
]
INP_CASES = [c for c in INP_CASES if c[0] != "inp-module-two"]


def _run(tmp_path, monkeypatch, capsys, argv, files):
    for name, text in files.items():
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    before = sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*"))
    monkeypatch.chdir(tmp_path)
    code = main(argv)
    out = capsys.readouterr()
    after = sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*"))
    return code, out.out, out.err, before, after


@pytest.mark.parametrize("name, args, files, code, message", CASES, ids=[c[0] for c in CASES])
def test_bad_input(tmp_path, monkeypatch, capsys, name, args, files, code, message):
    got, out, err, before, after = _run(tmp_path, monkeypatch, capsys, args.split(), files)
    assert got == code, err
    assert err.startswith("railcontact: error: "), err
    assert message in err, err
    assert len(err.strip().splitlines()) == 1 and len(err) < 600, err
    assert "Traceback" not in err and out == ""
    assert after == before                           # nothing written


@pytest.mark.skipif(INP is None, reason="../shared/reference not found")
@pytest.mark.parametrize("name, old, new, case, message, needle", INP_CASES,
                         ids=[c[0] for c in INP_CASES])
def test_bad_inp(tmp_path, monkeypatch, capsys, name, old, new, case, message, needle):
    """A bad value in any case of a CONTACT input stops the run before the first case
    is solved, with the line of that value."""
    text = _inp_with(old, new, case)
    line = _line_of(text, needle)
    got, out, err, before, after = _run(tmp_path, monkeypatch, capsys,
                                        ["solve", "x.inp", "--out", "r.csv"], {"x.inp": text})
    assert got == 2, err
    assert err.startswith("railcontact: error: x.inp"), err
    assert message.format(line=line) in err, err
    if "(line" not in message:
        assert f"line {line}" in err, err
    assert out == "" and after == before and len(err.strip().splitlines()) == 1


def test_a_cluster_without_distributed_names_the_extra(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "distributed", None)          # not installed
    got, out, err, before, after = _run(
        tmp_path, monkeypatch, capsys,
        ["sweep", "c.toml", "--vary", "bodies.normal_force=1e4,2e4", "--scheduler",
         "tcp://127.0.0.1:8786"], {"c.toml": BODIES})
    assert got == 2 and "pip install railcontact[cluster]" in err
    assert err.startswith("railcontact: error: --scheduler = 'tcp://127.0.0.1:8786'")
    got, *_ = _run(tmp_path, monkeypatch, capsys, ["wear", "w.toml", "--scheduler",
                                                   "tcp://127.0.0.1:8786"], {"w.toml": WEAR})
    assert got == 2


BIG = np.zeros(6_000_000)                       # 48 MB


@pytest.mark.parametrize("call, error, message", [
    (lambda: rc.solve([1, 2, 3]), rc.InputError, "case = [1, 2, 3]: expected a Case"),
    (lambda: rc.solve({"wheel": {}}), rc.InputError, "case = {'wheel': {}}: expected a Case"),
    (lambda: rc.solve("examples/wheel_rail.toml"), rc.InputError,
     "case = 'examples/wheel_rail.toml': expected a Case (railcontact.load_case(path)"),
    (lambda: rc.solve(rc.case_from_dict({"bodies": {"radii": {"wheel_rolling": 0.46,
                                                              "rail_lateral": 0.3},
                                                    "normal_force": 1e4}}), normal=3),
     rc.InputError, "normal = 3: expected a model name"),
    (lambda: rc.Material("steel"), rc.InputError, "material.young_modulus = 'steel'"),
    (lambda: rc.Material(BIG), rc.InputError, "young_modulus = array of shape (6000000,)"),
    (lambda: rc.Material(2.1e11, [0.3]), rc.InputError, "material.poisson_ratio = [0.3]"),
    (lambda: rc.case_from_dict([1]), rc.CaseFileError, "case: expected a TOML table"),
    (lambda: rc.case_from_dict({"wheel": {"profile": "S1002"}, "rail": {"profile": "60E1"},
                                "wheelset": {"vertical_force": BIG.tolist()}}),
     rc.CaseFileError, "(6000000 items)"),
    (lambda: rc.sweep({"a": 1}, {}), rc.InputError, "case = {'a': 1}: expected a Case"),
    (lambda: rc.sweep(rc.load_case(EX / "bodies.toml"), [1, 2]), rc.InputError,
     "vary = [1, 2]: expected a dict"),
    (lambda: rc.sweep(rc.load_case(EX / "bodies.toml"), {"bodies.normal_force": 1e4}),
     rc.InputError, "expected a dict of case keys to non-empty lists"),
    (lambda: rc.sweep(rc.load_case(EX / "bodies.toml"), {"bodies.normal_force": [1e4]},
                      scheduler="gpu"), rc.InputError, "scheduler = 'gpu'"),
    (lambda: rc.normal.get_normal_model("hertz").solve([1, 2], rc.Material(),
                                                       normal_force=1e4),
     rc.InputError, "geometry = [1, 2]: expected a ContactGeometry"),
    (lambda: rc.normal.get_normal_model("exact").solve(BIG, rc.Material(), normal_force=1e4),
     rc.InputError, "geometry = array of shape (6000000,)"),
    (lambda: rc.tangential.get_tangential_model("fastsim").solve(None, None, rc.Material(),
                                                                 (0, 0, 0), 0.3),
     rc.InputError, "normal = None: expected the NormalSolution"),
    (lambda: rc.normal.get_normal_model("hurtz"), rc.UnknownModelError,
     "unknown normal model 'hurtz'"),
    (lambda: rc.profiles.read_profile("/nonexistent/w.prw"), rc.ProfileError, "w.prw"),
])
def test_bad_api_input(call, error, message):
    """The public API raises the package's own errors, values cut to a readable
    length."""
    with pytest.raises(error) as info:
        call()
    assert message in str(info.value)
    assert len(str(info.value)) < 400


def test_corpus_size():
    assert len(CASES) + len(INP_CASES) + 18 + 1 >= 100


def test_a_derailed_wheel_on_the_side_not_reported(tmp_path, capsys, monkeypatch):
    """wheelset.side = "right" with the left wheel on its flange tip (lateral shift
    -50 mm): not a solution, said in the JSON and the exit status."""
    text = (EX / "wheel_rail.toml").read_text().replace("lateral_shift = 0.003",
                                                        "lateral_shift = -0.05")
    (tmp_path / "c.toml").write_text(text)
    monkeypatch.chdir(tmp_path)
    code = main(["solve", "c.toml", "--json"])
    d = json.loads(capsys.readouterr().out)
    assert code == 1 and d["converged"] is False
    assert "the left wheel (not reported): derailment" in d["message"]
    assert all(p["side"] == "right" for p in d["patches"])
