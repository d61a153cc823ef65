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
def wear_vehicle_example(tmp_path_factory):
    """examples/wear_vehicle.toml run once (closed-loop wear, Hertz + FASTSIM):
    its output folder and dataset."""
    from railcontact.wear import load_scenario
    from railcontact.wear.closed_loop import ClosedLoopWear
    from railcontact.wear.plots import plot_closed_loop
    out = tmp_path_factory.mktemp("wear_vehicle")
    ds = ClosedLoopWear(load_scenario(ROOT / "examples" / "wear_vehicle.toml"), out,
                        progress=False).run(resume=False)
    plot_closed_loop(ds, out)
    return out, ds
