"""Variants of CONTACT's testbank inputs (other loads, creepages, velocities and
positions) that CONTACT ran and railcontact had not seen, against CONTACT's
figures in ``benchmarks/contact_variants.csv``.

The variant inputs are regenerated here from ``../shared/contact_testbank`` by
``benchmarks/contact_variants.py`` (which lists every variant and compares all of
them); a handful of the quick ones run here, at the issue's tolerances: F_n, F_x,
F_y (F_s) within 1 % (the tangential forces relative to CONTACT's force or mu F_n,
the larger), p_max, elements in contact and the surface temperature within 3 %
(patches carrying at least a tenth of the load; benchmarks/contact_testbank.py's
rules).
"""

import importlib.util
import sys
from pathlib import Path

import pytest

from railcontact.contact_inp import solve_inp

ROOT = Path(__file__).resolve().parents[2]
TOL = {"fn": 0.01, "ft": 0.01, "pmax": 0.03, "area": 0.03, "temp": 0.03}


def _variants_module():
    spec = importlib.util.spec_from_file_location(
        "contact_variants", ROOT / "benchmarks" / "contact_variants.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod              # (its dataclasses look their module up)
    spec.loader.exec_module(mod)
    return mod


CV = _variants_module()
REF = CV.read_csv(ROOT / "benchmarks" / "contact_variants.csv")


def _run(name, testbank, tmp_path):
    v = next(v for v in CV.VARIANTS if v.name == name)
    path = CV.write_variant(v, tmp_path, testbank)
    rows = solve_inp(path, profile_dirs=[testbank / "profiles"])
    module, ref = REF[name]
    return CV.compare(v, rows, module, ref), ref


@pytest.mark.parametrize("name", ["cattaneo_load_shift", "visc_load_vel", "ertz_load_creep_vel",
                                  "catt3d_plast_load", "t1_force_cp_load_pos", "varfric_load_pos",
                                  "t1_zws_pos", "rollers3_load_creep"])
def test_variant_within_tolerance(name, testbank, tmp_path):
    (n, worst, notes), ref = _run(name, testbank, tmp_path)
    assert n == len(ref) and n > 0
    assert "patch count differs" not in notes
    over = {k: round(100 * v, 3) for k, v in worst.items() if v > TOL[k]}
    assert not over, (name, over)


def test_temperature_compared(testbank, tmp_path):
    """The flash-temperature variant compares CONTACT's MAX(T1,T2): present in the
    CSV and within 3 %."""
    (n, worst, _), ref = _run("ertz_load_creep_vel", testbank, tmp_path)
    assert any(c.get("tmax_C") for c in ref.values())
    assert "temp" in worst and worst["temp"] <= TOL["temp"]


def test_variant_text_changes_only_the_named_values(testbank):
    """A variant changes the labelled values, keeps the first cases and ends the file."""
    v = next(v for v in CV.VARIANTS if v.name == "a22_left_load_pos")
    text = CV.variant_text(v, testbank)
    src = (testbank / v.source).read_text()
    assert text.count(" MODULE") == v.keep + 1 and text.rstrip().endswith("0  MODULE")
    assert "14000." in text and "10000." in src
    assert "0.3  14000." in text               # S, Y +0.3, FZ x1.4 of case 1
    with pytest.raises(ValueError, match="not found"):
        CV.variant_text(CV.Variant("bad", "", v.source, (CV.Edit("NOSUCH", "add", 1.0),)),
                        testbank)
