"""Reading CONTACT's printed module 3 output (railcontact.contact_inp.outfile)."""

import pytest

from railcontact.contact_inp import InpError
from railcontact.contact_inp.outfile import read_out


def test_cattaneo_ref_out(testbank):
    """Both cases of cattaneo.ref_out: the totals, the second block's labelled
    columns and the element counts, as printed."""
    out = read_out(testbank / "examples_basic" / "cattaneo.ref_out")
    assert sorted(out) == [1, 2]
    c = out[2]
    assert (c["fn_N"], c["fx_N"], c["fy_N"]) == (9.195, -3.218, 0.0)
    assert (c["x_label"], c["x_value"]) == ("SHIFT X", pytest.approx(8.155e-3))
    assert (c["approach_mm"], c["pmax_MPa"]) == (pytest.approx(1.998e-2), 4.393)
    assert (c["npot"], c["ncon"], c["nadh"], c["nslip"]) == (361, 177, 45, 132)
    assert out[1]["x_label"] == "FX/FSTAT/FN"


def test_short_output_and_missing_file(testbank, tmp_path):
    """At output level 1 CONTACT prints the totals only (no element counts);
    module 1 cases (no module 3 totals) are left out; a missing file is an
    InpError."""
    out = read_out(testbank / "examples_basic" / "catt_to_cart.ref_out")
    assert len(out) == 171 and "ncon" not in out[3]
    assert (out[3]["x_label"], out[3]["x_value"]) == ("CREEP X", pytest.approx(1.882e-3))
    assert read_out(testbank / "examples_trans" / "force_site_b.ref_out") == {}
    with pytest.raises(InpError, match="cannot read"):
        read_out(tmp_path / "none.ref_out")
