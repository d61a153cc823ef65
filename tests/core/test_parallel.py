"""Dask tasks on a scheduler chosen by name (railcontact.core.parallel)."""

import io

import dask
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
