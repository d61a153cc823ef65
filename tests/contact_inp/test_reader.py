"""Reading CONTACT's input format, and the one-line errors for what is not supported."""

import math

import pytest

from railcontact.contact_inp import InpError, load_inp, read_inp

CASE1 = """
% a wheel-rail case written by hand
  1 MODULE
 1203100    C-P-B-T-N-F-S   comment text is ignored
 0022033    V-L-D-C-M-Z-E
 0000321    H-G-I-A-O-W-R
    999     100    30    1     1d-5         MAXGS, MAXIN, MAXNR, MAXOUT, EPS
  0.300   0.300                                 FSTAT, FKIN
  0.280   0.280   82000.  82000.                POISS 1,2,  GG 1,2
  0.200   0.250   1.000   90d   8.0   4.0      DX, DS, DQREL, A_SEP, D_SEP, D_COMB
   14.0     0    1435.0   0.000                GAUGHT, GAUGSQ, GAUGWD, CANT
  'rail.prr'   0     1.0   0.0       RFNAME, MIRRORY, SCALE, SMOOTH
     0.0    0.0   0.000          % DY, DZ, ROLL: three on this line,
     0.0    0.0   0.000                          VY, VZ, VROLL  % three on the next
  1360.0  -70.0   460.0                         FBDIST, FBPOS, NOMRAD
  'wheel.prw'   1     1.0   10.0  -1  1       WFNAME, MIRRORY, SCALE, SMOOTH, MIRRORZ, PRFOPT
   1  150d   30d   6d   2.0                     ISMOOTH, ZIGTRS, KNKHGH, KNKLOW, KNKWID
  0.0  1.5  10000.  0.0001 0.0024  0.0      S, Y, FZ, ROLL, YAW, PITCH
 2000. 0.0    0.0   0.0        0.0  -4.348  VS,VY,VZ, VROLL,VYAW,VPITCH

  1 MODULE
 1203100    C-P-B-T-N-F-S
 0111002    V-L-D-C-M-Z-E  everything kept but the position and velocity
 0100321    H-G-I-A-O-W-R
  0.0  2.5  10000. 0.0 0.0060  0.0      S, Y, FZ, ROLL, YAW, PITCH
 2000. 0.0    0.0   0.0        0.0  -4.3455 VS,VY,VZ, VROLL,VYAW,VPITCH

  1 MODULE
 1203100
 0111002
 0100323    R = 3: preprocessing only, left out
  0.0  3.0  10000. 0.0 0.0  0.0
 2000. 0.0    0.0   0.0        0.0  -4.34
 0 MODULE
  1 MODULE   after the stop: never read
"""


@pytest.fixture
def files(tmp_path, refdir):
    import shutil
    for name in ("MBench_UIC60_v3.prr", "MBench_S1002_v3.prw"):
        shutil.copy(refdir / "profiles" / name,
                    tmp_path / ("rail.prr" if "UIC" in name else "wheel.prw"))
    return tmp_path


def _write(tmp_path, text, name="x.inp"):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_values_digits_and_kept_inputs(tmp_path):
    cases = read_inp(_write(tmp_path, CASE1))
    assert [c.number for c in cases] == [1, 2]            # case 3 only preprocesses
    c1, c2 = cases
    assert c1.digits["C"] == 1 and c1.digits["T"] == 3 and c1.digits["C3"] == 2
    assert c1.digits["X"] == 0 and c1.digits["O"] == 3 and c1.digits["R"] == 1
    v = c1.values
    assert v["EPS"] == pytest.approx(1e-5)                 # Fortran exponent 1d-5
    assert v["A_SEP"] == pytest.approx(math.pi / 2)        # 90d in degrees
    assert v["DS"] == 0.25 and v["D_TURN"] is None
    assert v["VY"] if "VY" in v else v["VYRAIL"] == 0.0   # the group spans two lines
    assert v["W_FNAME"] == "wheel.prw" and v["W_MIRRORY"] == 1 and v["W_MIRRORZ"] == -1
    assert v["W_ISMOOTH"] == 1 and v["W_KINKHIGH"] == pytest.approx(math.radians(30))
    assert v["R_PRFOPT"] == 0 and v["R_MIRRORZ"] == 0
    # case 2 keeps the friction, grid, track and wheel of case 1
    assert c2.values["FKIN"] == 0.3 and c2.values["DX"] == 0.2
    assert c2.values["W_SMOOTH"] == 10.0 and c2.values["Y_WS"] == 2.5
    assert "FKIN" not in c2.read and "Y_WS" in c2.read


def test_mapping_to_a_case_in_si_units(files):
    (m1, m2) = load_inp(_write(files, CASE1))
    r = m1.raw
    assert r["material"]["young_modulus"] == pytest.approx(2 * 82e9 * 1.28)
    assert r["solver"] == {"normal": "exact", "tangential": "exact",
                           "element_size": [2e-4, 2.5e-4], "tangential_options": {}}
    ws = r["wheelset"]
    assert ws["side"] == "right" and ws["roll"] == 0.0001 and ws["yaw"] == 0.0024
    assert ws["lateral_shift"] == pytest.approx(1.5e-3) and ws["vertical_force"] == 1e4
    assert ws["velocity"] == 2.0 and ws["pitch_velocity"] == -4.348
    # CONTACT's patch rules: D_SEP, D_COMB and the default D_TURN = 2 D_SEP - D_COMB
    assert (ws["combine_distance"], ws["full_interaction_distance"],
            ws["turn_distance"]) == pytest.approx((8e-3, 4e-3, 12e-3))
    assert r["track"] == {"gauge": pytest.approx(1.435), "gauge_height": pytest.approx(0.014)}
    w = r["wheel"]
    assert w["mirror_y"] is True and w["mirror_z"] is False and w["nominal_radius"] == 0.46
    assert w["smoothing"] == {"method": "weighted", "length": pytest.approx(0.01)}
    assert w["kinks"]["width"] == pytest.approx(2e-3)
    assert r["rail"]["mirror_z"] == "auto" and "smoothing" not in r["rail"]
    assert m2.raw["wheelset"]["lateral_shift"] == pytest.approx(2.5e-3)


def test_format_errors_name_the_line(tmp_path):
    bad = CASE1.replace("0.300   0.300", "0.300   abc")
    with pytest.raises(InpError, match=r"x.inp, line 8: FKIN = 'abc': expected a real number"):
        read_inp(_write(tmp_path, bad))
    with pytest.raises(InpError, match="unexpected end of file"):
        read_inp(_write(tmp_path, CASE1.split("  1 MODULE\n 1203100    C-P-B-T-N-F-S\n")[0]
                        + "  1 MODULE\n 1203100\n 0022033\n"))
    with pytest.raises(InpError, match="MODULE = 2"):
        read_inp(_write(tmp_path, " 2 MODULE\n"))
    with pytest.raises(InpError, match="does not exist"):
        read_inp(tmp_path / "missing.inp")


@pytest.mark.parametrize("old, new, match", [
    ("1203100    C-P-B-T-N-F-S   comment", "1201100    C-P-B-T-N-F-S   comment",
     r"case 1 \(line 3\): TANG = 1 \(transient shift or rolling"),
    ("0022033    V-L-D-C-M-Z-E", "0042033    V-L-D-C-M-Z-E", r"DISCNS = 4 \(conformal contact\)"),
    ("0022033    V-L-D-C-M-Z-E", "0023033    V-L-D-C-M-Z-E", r"INFLCF = 3 \(bilinear"),
    ("1203100    C-P-B-T-N-F-S   comment", "5203100    C-P-B-T-N-F-S   comment",
     r"CONFIG = 5 \(roller rig"),
    ("1435.0   0.000", "1435.0   0.025 1e-5", r"CURV = 1e-05 1/mm \(curved track\)"),
    ("     0.0    0.0   0.000          % DY", "     0.5    0.0   0.000   % DY",
     r"DYRAIL = 0.5 \(rail deviations\)"),
    ("1360.0  -70.0   460.0", "1360.0  -70.0   460.0  -10.0", r"YTAPE = -10 mm"),
])
def test_unsupported_options_stop_with_one_line(files, old, new, match):
    assert old in CASE1
    with pytest.raises(InpError, match=match) as err:
        load_inp(_write(files, CASE1.replace(old, new, 1)))
    assert "\n" not in str(err.value) and "is not supported" in str(err.value)


def test_unsupported_material_after_its_inputs(files):
    text = CASE1.replace("0022033    V-L-D-C-M-Z-E", "0022133    V-L-D-C-M-Z-E", 1).replace(
        "82000.  82000.                POISS 1,2,  GG 1,2",
        "82000.  82000.                POISS 1,2,  GG 1,2\n  1e3 1e3 0.1 0.1  FG, VT", 1)
    with pytest.raises(InpError, match=r"MATER = 1 \(viscoelastic material\) is not supported"):
        load_inp(_write(files, text))


def test_missing_profile_names_where_it_looked(tmp_path):
    with pytest.raises(InpError, match="profile file 'wheel.prw' not found.*--profiles"):
        load_inp(_write(tmp_path, CASE1))
    with pytest.raises(InpError, match="no case 7"):
        load_inp(_write(tmp_path, CASE1), cases=[7])


def test_module3_hertzian_case(refdir):
    (m,) = load_inp(refdir / "kalker_example.inp")
    r = m.raw
    assert m.module == 3 and r["solver"]["grid"] == [80, 80]
    assert r["solver"]["normal_options"] == {"margin": pytest.approx(0.1)}
    assert r["bodies"]["normal_force"] == pytest.approx(52359.8776)
    assert r["creepage"] == {"longitudinal": 1e-5, "lateral": 0.0, "spin": 0.0}
    # the curvatures of the 5 mm circle at that load
    from railcontact import Material
    from railcontact.hertz_theory import hertz_ellipse
    rad = r["bodies"]["radii"]
    h = hertz_ellipse(0.5 / rad["wheel_rolling"], 0.5 / rad["wheel_lateral"],
                      Material(**r["material"]).contact_modulus, force=52359.8776)
    assert (h.a, h.b) == pytest.approx((5e-3, 5e-3), rel=1e-9)
