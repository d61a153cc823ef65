"""Dask tasks on a scheduler chosen by name (railcontact.core.parallel)."""

import copy
import io

import dask
import numpy as np
import pytest

from railcontact.core.errors import InputError
from railcontact.core.parallel import compute
from railcontact.core.progress import TqdmCallback


@pytest.mark.parametrize("scheduler", ["sync", "threads"])
def test_results_in_the_order_of_the_tasks(scheduler):
    tasks = [dask.delayed(lambda k: k * k)(k) for k in range(6)]
    assert compute(tasks, scheduler) == [0, 1, 4, 9, 16, 25]


def test_the_callback_runs_during_the_computation():
    bar = TqdmCallback(3, "t", prefix="square", disable=False, file=io.StringIO())
    tasks = [dask.delayed(lambda k: k * k)(k, dask_key_name=f"square-{k}") for k in range(3)]
    assert compute(tasks, "sync", bar) == [0, 1, 4]
    assert bar.bar.n == 3


def test_an_unknown_scheduler_names_the_input():
    with pytest.raises(InputError, match="wear.scheduler = 'gpu'"):
        compute([], "gpu", what="wear.scheduler")


def test_a_cluster_without_distributed_names_the_extra(monkeypatch):
    import sys
    monkeypatch.setitem(sys.modules, "distributed", None)         # not installed
    with pytest.raises(InputError, match="railcontact\\[cluster\\]"):
        compute([], "tcp://127.0.0.1:8786", what="wear.scheduler")


# ---- a real dask.distributed cluster (loopback, two workers in this process) ----

distributed = pytest.importorskip("distributed")


@pytest.fixture(scope="module")
def cluster():
    """A LocalCluster on the loopback interface: two workers, one thread each, TCP
    between scheduler, workers and client (the path of --scheduler tcp://...)."""
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                  protocol="tcp", host="127.0.0.1", dashboard_address=None
                                  ) as c:
        yield c.scheduler_address


class _Recorded:
    """A tqdm stand-in recording how far each bar moved."""
    bars: list = []

    def __init__(self, total=None, desc="", **options):
        self.total, self.n = total, 0
        _Recorded.bars.append(self)

    def update(self, k=1):
        self.n += k

    def close(self):
        pass


@pytest.fixture
def recorded(monkeypatch):
    import railcontact.core.progress as progress
    _Recorded.bars = []
    monkeypatch.setattr(progress, "tqdm", _Recorded)
    return _Recorded.bars


def test_tasks_on_a_cluster(cluster):
    assert cluster.startswith("tcp://127.0.0.1:")
    bar = TqdmCallback(10, "t", prefix="rep", disable=False, file=io.StringIO())
    tasks = [dask.delayed(lambda k: [k] * k)(k, dask_key_name=f"rep-{k}") for k in range(1, 5)]
    assert compute(tasks, cluster, bar) == [[1], [2, 2], [3, 3, 3], [4, 4, 4, 4]]
    assert bar.bar.n == 10                       # advanced by the cases of each task


def test_a_sweep_on_a_cluster_equals_the_sequential_one(cluster, recorded):
    from pathlib import Path

    import railcontact as rc
    case = rc.load_case(Path(__file__).resolve().parents[2] / "examples" / "bodies.toml")
    vary = {"bodies.normal_force": [5e4, 7e4, 9e4, 1.1e5, 1.3e5, 1.5e5]}
    seq = rc.sweep(case, vary, scheduler="sync", progress=False)
    par = rc.sweep(case, vary, scheduler=cluster, progress=True)
    assert [c["patches"] for c in par["cases"]] == [c["patches"] for c in seq["cases"]]
    assert [b.n for b in recorded] == [6]          # the bar reached every case


def test_an_open_loop_wear_step_on_a_cluster(cluster, recorded):
    from railcontact.wear import WearSimulation
    from tests.wear.test_simulation import SYMMETRIC, scenario
    seq = WearSimulation(scenario(SYMMETRIC, steps=1, scheduler="sync"),
                         progress=False).run(resume=False)
    par = WearSimulation(scenario(SYMMETRIC, steps=1, scheduler=cluster),
                         progress=True).run(resume=False)
    for name in ("wear_depth_wheel_left", "wear_depth_wheel_right"):
        np.testing.assert_array_equal(par[name].values, seq[name].values)
    assert recorded and all(b.n == b.total for b in recorded if b.total)


def test_a_closed_loop_route_mix_on_a_cluster(cluster, recorded, monkeypatch):
    from railcontact.wear.closed_loop import ClosedLoopWear
    from tests.wear import test_closed_loop as tcl
    small = copy.deepcopy(tcl.TINY)              # the tiny route mix, shorter
    small["dynamics"] = {"table_range": 0.008, "table_step": 1e-3}
    for route in small["route"]:
        route["length"] = 20.0
    monkeypatch.setattr(tcl, "TINY", small)
    seq = ClosedLoopWear(tcl.tiny(steps=1), None, progress=False).run(resume=False)
    sc = tcl.tiny(steps=1)
    sc.scheduler = cluster
    par = ClosedLoopWear(sc, None, progress=True).run(resume=False)
    np.testing.assert_array_equal(par["wear_depth_wheel"].values, seq["wear_depth_wheel"].values)
    assert recorded and all(b.n == b.total for b in recorded if b.total)
