"""Writers of the CONTACT-unit result table (railcontact.contact_inp.table) on
hand-made rows."""

import csv
import io
import json
import math

from railcontact.contact_inp.table import COLUMNS, to_csv, to_json, to_text

ROWS = [{"case": 1, "module": 1, "side": "right", "patch": 1, "npatch": 1,
         "ycp_tr_mm": 757.123456789012, "delta_tr_rad": -0.0312, "fn_N": 50123.4,
         "fx_N": -120.5, "fs_N": 33.25, "pmax_MPa": 1023.0, "area_mm2": 101.5,
         "cksi": 1.5e-4, "approach_mm": math.nan, "converged": True, "unknown": 7},
        {"case": 2, "module": 1, "side": "left", "npatch": 0}]


def test_csv_has_the_reference_columns_in_order():
    text = to_csv(ROWS)
    rows = list(csv.DictReader(io.StringIO(text)))
    assert text.splitlines()[0].split(",") == list(COLUMNS)
    assert rows[0]["ycp_tr_mm"] == "757.1234568"            # 10 significant digits
    assert rows[0]["fn_N"] == "50123.4" and rows[0]["converged"] == "True"
    assert rows[1]["fn_N"] == "" and "unknown" not in rows[0]
    assert len(COLUMNS) == len(set(COLUMNS))


def test_json_turns_nan_into_null():
    d = json.loads(to_json(ROWS, source="a.inp"))
    assert d["source"] == "a.inp" and "mm" in d["units"]
    assert d["rows"][0]["approach_mm"] is None and d["rows"][0]["fn_N"] == 50123.4
    assert len(d["rows"]) == 2


def test_text_table():
    lines = to_text(ROWS).splitlines()
    assert lines[0].split()[:4] == ["case", "side", "cp", "ycp_tr"]
    assert lines[1].split()[:6] == ["1", "right", "1", "757.1235", "-0.0312", "50123.4"]
    assert lines[2].split() == ["2", "left", "-", "no", "contact"]
