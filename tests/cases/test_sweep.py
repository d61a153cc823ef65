"""railcontact.cases.sweep: parameter sweeps and their scheduler."""

from pathlib import Path

import pytest

import railcontact as rc

EX = Path(__file__).resolve().parents[2] / "examples"


def test_sweep_threads_equals_sync():
    case = rc.load_case(EX / "bodies.toml")
    vary = {"creepage.longitudinal": [0.0, 1e-3, 2e-3], "bodies.normal_force": [5e4, 1e5]}
    a = rc.sweep(case, vary, scheduler="sync", progress=False)
    b = rc.sweep(case, vary, scheduler="threads", progress=False)
    assert len(a["cases"]) == 6
    assert [c["patches"][0]["Fx"] for c in a["cases"]] == [c["patches"][0]["Fx"] for c in b["cases"]]


def test_auto_scheduler_uses_processes_for_long_sweeps_only(monkeypatch):
    """"auto" starts worker processes only where the sweep is expected to take longer
    than their start-up is worth (PROCESSES_FROM seconds in one process)."""
    import dask

    import railcontact.cases.sweep as sw
    case = rc.load_case(EX / "wheel_rail.toml")
    assert sw._expected_seconds(case, 100, "exact", "exact") == pytest.approx(2.0)
    assert sw._expected_seconds(case, 100, "hertz", "fastsim") == pytest.approx(0.5)
    assert sw._expected_seconds(case, 100, "hertz", "exact") == pytest.approx(2.0)
    used = []
    real = dask.compute

    def spy(*tasks, **kw):
        used.append(kw.get("scheduler"))
        return real(*tasks, scheduler="sync")

    monkeypatch.setattr(dask, "compute", spy)
    vary = {"wheelset.lateral_shift": [0.0, 1e-3]}
    sw.sweep(case, vary, "hertz", "fastsim", progress=False)
    monkeypatch.setattr(sw, "PROCESSES_FROM", 0.001)
    monkeypatch.setattr(sw.os, "cpu_count", lambda: 2)
    sw.sweep(case, vary, "hertz", "fastsim", progress=False)
    assert used == ["sync", "processes"]
