"""Wear under several model pairs (railcontact.wear.compare)."""

import pytest

from railcontact.core.errors import InputError
from tests.wear.test_simulation import SYMMETRIC, scenario

def test_wear_compare(tmp_path):
    from railcontact.wear.compare import compare_wear, parse_models
    res = compare_wear(scenario(SYMMETRIC, steps=1), parse_models("hertz+fastsim,kpec+fastsim"),
                       tmp_path, progress=False)
    assert set(res) == {"hertz+fastsim", "kpec+fastsim"}
    assert (tmp_path / "wear_comparison.png").stat().st_size > 10000
    import csv
    rows = list(csv.DictReader(open(tmp_path / "wear_comparison.csv")))
    assert {r["models"] for r in rows} == {"hertz+fastsim", "kpec+fastsim"}
    with pytest.raises(InputError):
        parse_models("hertz")
