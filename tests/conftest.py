"""Shared fixtures: location of the CONTACT reference data (../shared/reference)."""

import csv
import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def reference_dir() -> Path | None:
    env = os.environ.get("RAILCONTACT_REFERENCE")
    for cand in ([Path(env)] if env else []) + [ROOT.parent / "shared" / "reference",
                                                 ROOT / "shared" / "reference"]:
        if (cand / "README.md").is_file():
            return cand
    return None


@pytest.fixture(scope="session")
def refdir() -> Path:
    d = reference_dir()
    if d is None:
        pytest.skip("CONTACT reference data not found (set RAILCONTACT_REFERENCE)")
    return d


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.fixture(scope="session")
def testbank() -> Path:
    """CONTACT's testbank inputs and outputs (../shared/contact_testbank)."""
    ref = reference_dir()
    for cand in ([ref.parent / "contact_testbank"] if ref else []) + \
            [ROOT.parent / "shared" / "contact_testbank"]:
        if (cand / "README.md").is_file():
            return cand
    pytest.skip("CONTACT testbank not found (../shared/contact_testbank)")
