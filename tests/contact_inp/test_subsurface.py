"""Subsurface stresses of CONTACT's input files (STRESS = 1, 2, 3) through
``solve_inp(..., subsurface=True)``: CONTACT's subsurf.inp against its
``subsurf.ref_subs`` and printed maxima, spence35.inp (dissimilar bodies, a
sequence of shifts) against the stresses CONTACT prints for its last stage, and
the Manchester A-2.2 wheel-rail case of mbench_a22_varfric.inp (module 1) against
its printed maxima."""

import re

import numpy as np
import pytest

from railcontact.contact_inp import InpError, read_inp, solve_inp
from railcontact.contact_inp.subsurface import (CSV_COLUMNS, MAXIMA, block_stresses,
                                                derived, to_csv, to_dataset)
from railcontact.subsurface import stresses_on_grid


def _ref_subs(path):
    """The blocks of a CONTACT .subs file: arrays of rows X Y Z UX UY UZ SIGHYD SIGVM
    SIGXX SIGXY SIGXZ SIGYY SIGYZ SIGZZ."""
    blocks, lines = [], [ln for ln in open(path) if ln.strip()]
    i = 0
    while i < len(lines):
        if lines[i].lstrip().startswith("%   NX"):
            nx, ny, nz = (int(float(v)) for v in lines[i + 1].split()[:3])
            n = nx * ny * nz
            blocks.append(np.array([[float(v) for v in ln.split()]
                                    for ln in lines[i + 3:i + 3 + n]]))
            i += 3 + n
        else:
            i += 1
    return blocks


def _printed_maxima(text):
    """CONTACT's printed maxima per block, in file order: lists of (name, value,
    (x, y, z))."""
    out = []
    for part in text.split("SUBSURFACE STRESSES BLOCK")[1:]:
        rows = re.findall(r"^ (ABSMAX|MAX|MIN)\s+(\w+) =\s*(\S+) AT \(X,Y,Z\) = \(\s*(\S+),"
                          r"\s*(\S+),\s*(\S+)\)", part, flags=re.M)[:len(MAXIMA)]
        out.append([(f"{a} {b}", float(v), (float(x), float(y), float(z)))
                    for a, b, v, x, y, z in rows])
    return out


def _check_maxima(block, printed, rel, absolute):
    """Each printed maximum within ``rel`` (or ``absolute`` N/mm^2, CONTACT's printed
    digits) of ours, and ours at CONTACT's point as large (a tie of equal values may
    be printed at another of the points).  Returns the largest relative deviation."""
    from railcontact.contact_inp.subsurface import quantity
    worst = 0.0
    names = {m[0].split()[-1]: m for m in MAXIMA}
    for (name, value, point), ours in zip(printed, block["maxima"]):
        assert ours[0].split()[-1] == name.split()[-1]
        assert ours[1] == pytest.approx(value, rel=rel, abs=absolute), (name, ours, value)
        worst = max(worst, abs(ours[1] - value) / max(abs(value), 1e-300))
        k = np.argmin((block["x"] - point[0]) ** 2 + (block["y"] - point[1]) ** 2
                      + (block["z"] - point[2]) ** 2)
        at = quantity(block, names[name.split()[-1]][1])[k]
        assert at == pytest.approx(value, rel=rel, abs=absolute), (name, at, value, point)
    return worst


def test_subsurf_reference(testbank):
    """subsurf.inp: a unit pressure (case 1) and a traction 0.999 (case 2: steady
    rolling, FX prescribed) on one element, two blocks of points (ISUBS = 9).  Case
    2's stresses within 1 % of subsurf.ref_subs (floor 1e-4 of the largest; measured
    2.6e-6 of the largest), von Mises and the mean stress likewise; every printed
    maximum of both cases within CONTACT's 3 decimals."""
    path = testbank / "examples_basic" / "subsurf.inp"
    rows = solve_inp(path, subsurface=True)
    blocks = {(r["case"], b["block"]): b for r in rows for b in r.get("subsurface", [])}
    assert sorted(blocks) == [(1, 1), (1, 2), (2, 1), (2, 2)]
    ref = _ref_subs(path.with_suffix(".ref_subs"))
    worst = 0.0
    for k, r in enumerate(ref, 1):
        b = blocks[(2, k)]
        np.testing.assert_allclose(np.c_[b["x"], b["y"], b["z"]], r[:, :3], atol=1e-4)
        scale = np.abs(r[:, 8:]).max()
        np.testing.assert_allclose(b["sigma"], r[:, 8:], rtol=0.01, atol=1e-4 * scale)
        np.testing.assert_allclose(b["sigvm"], r[:, 7], rtol=0.01, atol=1e-4 * scale)
        np.testing.assert_allclose(b["sighyd"], r[:, 6], rtol=0.01, atol=1e-4 * scale)
        worst = max(worst, np.abs(b["sigma"] - r[:, 8:]).max() / scale)
    assert worst < 1e-5
    printed = _printed_maxima(path.with_suffix(".ref_out").read_text())
    for (case, k), p in zip(sorted(blocks), printed):
        _check_maxima(blocks[(case, k)], p, rel=0.0, absolute=6e-4)


def test_spence_stresses(testbank):
    """spence35.inp, the last of 35 stages (dissimilar bodies, a sequence of shifts):
    the stresses just below the surface (z = 1e-6 mm) at the 45 element centres of
    the row y = 0 that CONTACT prints with 4 digits, every component within 1 %
    (floor 1e-3 of the largest; measured: 0.05 % of each component above 1 % of the
    largest, 2.1e-4 of the largest in all); the printed maxima within their 3
    decimals; the elements in contact and adhesion CONTACT's (921, 225)."""
    path = testbank / "examples_basic" / "spence35.inp"
    rows = solve_inp(path, subsurface=True)
    last = rows[-1]
    assert last["case"] == 35 and (last["ncon"], last["nadh"]) == (921, 225)
    text = path.with_suffix(".ref_out").read_text().split(" Case    35")[1]
    num = r"\s+(\S+)"
    pts = re.findall(r"Position \(X,Y,Z\):" + num * 3 + r"\s*\n.*\n"
                     + (r"\s*\d\s+\S+;" + num * 3 + r"\s*\n") * 3, text)
    ref = np.array(pts, float)
    assert ref.shape == (45, 12)
    b, = last["subsurface"]
    np.testing.assert_allclose(b["x"], ref[:, 0], atol=2e-4)
    s = b["sigma"]                              # xx, xy, xz, yy, yz, zz
    full = s[:, [0, 1, 2, 1, 3, 4, 2, 4, 5]]
    scale = np.abs(ref[:, 3:]).max()
    np.testing.assert_allclose(full, ref[:, 3:], rtol=0.01, atol=1e-3 * scale)
    assert np.abs(full - ref[:, 3:]).max() < 5e-4 * scale
    _check_maxima(b, _printed_maxima(text)[0], rel=0.0, absolute=6e-4)
    # the stages with S = 1, 2 and 3 all have the stresses of the block kept
    assert all(len(r.get("subsurface", [])) == 1 for r in rows)


def test_wheel_rail_case(testbank):
    """mbench_a22_varfric.inp, case 1 (module 1, the Manchester A-2.2 wheel centred,
    friction 0.3 on the tread): the rail's stresses at every element centre at 11
    depths (ISUBS = 1), below the patch on CONTACT's lattice.  CONTACT's printed
    maxima within 0.1 % and at its points (measured: 0.04 %, SIGMA3 -386.76 against
    -386.84 N/mm^2); the surface results as CONTACT's (F_n 9997 N, F_s -253.6 N,
    p_max 338.4 MPa)."""
    path = testbank / "examples_basic" / "mbench_a22_varfric.inp"
    r, = solve_inp(path, cases=[1], subsurface=True)
    assert r["fn_N"] == pytest.approx(9997, rel=1e-3)
    assert r["fs_N"] == pytest.approx(-253.6, abs=0.01 * 0.3 * 9997)
    assert r["pmax_MPa"] == pytest.approx(338.3, rel=0.003)
    b, = r["subsurface"]
    assert b["shape"][2] == 11 and b["z"].max() == pytest.approx(5.0 + 1e-6)
    printed = _printed_maxima(path.with_suffix(".ref_out").read_text())[0]
    worst = _check_maxima(b, printed, rel=1e-3, absolute=0.0)
    assert worst < 1e-3


def test_blocks_of_element_centres():
    """ISUBS = 2 and 3 pick columns and rows of the grid (numbers outside it ignored)
    from the FFT convolution of the whole grid; ISUBS = 9 sums the loaded elements
    at any point: the two agree at element centres.  The derived measures."""
    x, y = np.arange(6) * 0.5 - 1.25, np.arange(5) * 0.4 - 0.8
    X, Y = np.meshgrid(x, y, indexing="ij")
    p = np.clip(1 - X ** 2 - Y ** 2, 0, None)
    q = (p * 0.3, p * -0.1, p)
    loads = (p, q[0], q[1])
    z = [0.0, 0.3]
    reg = block_stresses(x, y, (0.5, 0.4), loads, {"isubs": 2, "ix": [2, 4, 6, 8],
                                                   "iy": [1, 3], "z": z}, 0.3)
    assert reg["shape"] == (3, 2, 2)
    full = stresses_on_grid(x, y, p, q[0], q[1], [0.3], 0.3)
    k = -1                        # the last point: x[5], y[2], z = 0.3
    assert (reg["x"][k], reg["y"][k], reg["z"][k]) == (x[5], y[2], 0.3)
    np.testing.assert_allclose(reg["sigma"][k], full[[0, 3, 4, 1, 5, 2], 5, 2, 0])
    pts = block_stresses(x, y, (0.5, 0.4), loads, {"isubs": 9, "x": [x[5], x[1]],
                                                   "y": [y[2], y[0]], "z": z}, 0.3)
    assert pts["shape"] == (2, 2, 2)
    np.testing.assert_allclose(pts["sigma"][-1], reg["sigma"][-1], rtol=1e-9, atol=1e-12)
    d = derived(np.array([[1.0, 0.0, 0.0, 2.0, 0.0, 3.0]]))
    assert d["sigma1"][0] == 3.0 and d["sigma3"][0] == 1.0 and d["sigtr"][0] == 2.0
    assert d["sighyd"][0] == 2.0 and d["sigvm"][0] == pytest.approx(np.sqrt(3.0))
    reg.update(case=1, patch=1, block=1)
    text = to_csv([reg])
    lines = text.splitlines()
    assert lines[0].split(",") == list(CSV_COLUMNS) and len(lines) == 13
    ds = to_dataset([reg])
    assert ds.sizes["point"] == 12 and ds["sigvm"].attrs["units"] == "N/mm^2"


def test_points_without_a_block(testbank, tmp_path):
    """S = 1 (the points kept) in a file's first case stops with the line naming it."""
    text = (testbank / "examples_basic" / "subsurf.inp").read_text()
    bad = tmp_path / "bad.inp"
    bad.write_text(text.replace("  200103     P-B-T-N-F-S", "  200101     P-B-T-N-F-S", 1))
    with pytest.raises(InpError, match=r"bad.inp, case 1 \(line \d+\): STRESS = 1"):
        read_inp(bad)
