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


def _chain_starts(items, warm):
    """One output per item: the first item of the item's chain."""
    return [items[0]] * len(items)


def test_warm_chains_do_not_depend_on_the_scheduler_or_the_cores(monkeypatch):
    """A warm sweep's chains (where its cases start cold) are CHAIN_LENGTH cases
    long whatever the scheduler and the machine's cores."""
    from railcontact.cases import sweep as sweep_module
    items = list(range(130))
    got = {}
    for cores in (1, 2, 16):
        monkeypatch.setattr(sweep_module.os, "cpu_count", lambda cores=cores: cores)
        for scheduler in ("sync", "threads"):
            got[cores, scheduler] = sweep_module.run_chains(
                _chain_starts, items, scheduler=scheduler, progress=False, warm=True)
    first = next(iter(got.values()))
    assert all(v == first for v in got.values())
    assert sorted(set(first)) == [0, 43, 87]      # 130 cases in ceil(130 / 64) = 3 chains
