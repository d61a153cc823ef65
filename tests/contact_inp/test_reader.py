"""Reading CONTACT's input format (railcontact.contact_inp.reader)."""

import math

import pytest

from railcontact.contact_inp import InpError, read_inp

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


SUBS_CASE = """
 3  MODULE
  200103     P-B-T-N-F-S
  022020     L-D-C-M-Z-E
 0001541   H-G-I-A-O-W-R
      80         100      30       1  1e-6       MAX_GS,_IN,_NR,_OUT, EPS
   1.000       0.000       0.000      0.000      FN, CKSI, CETA, CPHI
   1.000       1.000                             FSTAT, FKIN
   0.280       0.280       1.000      1.000      POISS 1,2, GG 1,2
    1                                            IPOTCN
    4    3   -2.0  -1.5   1.000    1.000   MX,MY,XL,YL,DX,DY
    1    1                                       IBASE, IPLAN
  0.5   0.    0.5    0.     0.     0.       B(I), I=1, 6
   2   1        MATFIL, OUTPUT
   1            ISUBS
   3  0.0  0.5      NZ, ZL, DZ
   6            ISUBS
   1 2 4   1 1 3     IXL, IXINC, IXH, IYL, IYINC, IYH
   2                 NZ
   0.25  1.0
   3            ISUBS
   2  1              NX, NY
   1 3
   2
   2  0.1 0.2   NZ, ZL, DZ
   9            ISUBS
   2  1  1    NX, NY, NZ
   0.5 -0.5
   0.0
   0.3
   0            ISUBS
 0  MODULE
"""


def test_subsurface_blocks(tmp_path):
    """The subsurface points of a case with S = 3: ISUBS 1 (all elements, NZ layers
    from ZL by DZ), 6 (a regular selection, listed depths), 3 (listed columns and
    rows, layers from ZL by DZ) and 9 (explicit
    coordinates)."""
    path = tmp_path / "subs.inp"
    path.write_text(SUBS_CASE)
    case, = read_inp(path)
    assert case.values["B"] == [0.5, 0.0, 0.5, 0.0, 0.0, 0.0]
    b = case.values["SUBSURFACE_BLOCKS"]
    assert [x["isubs"] for x in b] == [1, 6, 3, 9]
    assert b[0]["ix"] is None and b[0]["z"] == [0.0, 0.5, 1.0]
    assert b[1]["ix"] == [1, 3] and b[1]["iy"] == [1, 2, 3] and b[1]["z"] == [0.25, 1.0]
    assert b[2]["ix"] == [1, 3] and b[2]["iy"] == [2] and b[2]["z"] == pytest.approx([0.1, 0.3])
    assert b[3]["x"] == [0.5, -0.5] and b[3]["y"] == [0.0] and b[3]["z"] == [0.3]
    bad = tmp_path / "bad.inp"
    bad.write_text(SUBS_CASE.replace("   6            ISUBS", "   4            ISUBS"))
    with pytest.raises(InpError, match=r"ISUBS = 4: expected"):
        read_inp(bad)
