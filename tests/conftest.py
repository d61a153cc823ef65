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
    from railcontact.inputs import load_wear_scenario
    from railcontact.wear.closed_loop import ClosedLoopWear
    from railcontact.wear.plots import plot_closed_loop
    out = tmp_path_factory.mktemp("wear_vehicle")
    ds = ClosedLoopWear(load_wear_scenario(ROOT / "examples" / "wear_vehicle.toml"), out,
                        progress=False).run(resume=False)
    plot_closed_loop(ds, out)
    return out, ds


def testbank_dir() -> Path | None:
    """CONTACT's testbank (inputs and reference outputs): ../shared/contact_testbank."""
    env = os.environ.get("RAILCONTACT_TESTBANK")
    for cand in ([Path(env)] if env else []) + [ROOT.parent / "shared" / "contact_testbank",
                                                 ROOT / "shared" / "contact_testbank"]:
        if (cand / "README.md").is_file():
            return cand
    return None


@pytest.fixture(scope="session")
def testbank() -> Path:
    d = testbank_dir()
    if d is None:
        pytest.skip("CONTACT testbank not found (set RAILCONTACT_TESTBANK)")
    return d


def read_ref_out(path):
    """The cases of a CONTACT ``.ref_out`` file (wheel-rail output): per case the
    wheelset position (s, y, z [mm]) and per patch its reference point (xcp, ycp,
    zcp [mm]), contact angle, FN, FX, FS [N], APPROACH [mm], PMAX [MPa], NCON and
    the creepages, in CONTACT's units and sign conventions."""
    import re
    cases, cur, p = [], None, None
    lines = Path(path).read_text().splitlines()
    for i, line in enumerate(lines):
        m = re.match(r"\s*Case\s+(\d+)", line)
        if m:
            cur = {"case": int(m.group(1)), "patches": []}
            cases.append(cur)
        nxt = lines[i + 1].split() if i + 1 < len(lines) else []
        if "S_WS        Y_WS" in line or "X_WS        Y_WS" in line:
            cur["s"], cur["y"], cur["z"] = (float(v) for v in nxt[:3])
        elif "DATA FOR CONTACT PATCH" in line:
            p = {}
            cur["patches"].append(p)
        elif "XCP(TR)     YCP(TR)" in line:
            p["xcp"], p["ycp"], p["zcp"], p["delta"] = (float(v) for v in nxt[:4])
        elif line.strip().startswith("CHI") and "CKSI" in line:
            p["veloc"], p["cksi"], p["ceta"], p["cphi"] = (float(v) for v in nxt[2:6])
        elif line.strip().startswith("FN ") and "FX" in line:
            p["fn"], p["fx"], p["fs"], p["mn"] = (float(v) for v in nxt[:4])
        elif "APPROACH     PMAX" in line:
            p["approach"], p["pmax"] = float(nxt[3]), float(nxt[4])
        elif "NPOT   NCON" in line:
            p["ncon"] = int(nxt[1])
    return cases
