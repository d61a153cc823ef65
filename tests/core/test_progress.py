"""railcontact.core.progress: a tqdm bar advanced by the cases of finished Dask tasks."""

import dask
import pytest

from railcontact.core import progress


class _Bar:
    made = []

    def __init__(self, total, desc, file, disable):
        self.total, self.desc, self.n, self.closed = total, desc, 0, False
        _Bar.made.append(self)

    def update(self, k):
        self.n += k

    def close(self):
        self.closed = True


def test_bar_counts_the_cases_of_solve_tasks_only(monkeypatch):
    monkeypatch.setattr(progress, "tqdm", _Bar)
    _Bar.made.clear()
    chains = [dask.delayed(lambda n: list(range(n)))(n, dask_key_name=f"_solve-{n}")
              for n in (3, 4)]
    other = dask.delayed(lambda: [0] * 10)(dask_key_name="_prepare-0")     # not counted
    with progress.TqdmCallback(total=7, desc="sweep"):
        out = dask.compute(chains, other, scheduler="sync")
    assert [len(c) for c in out[0]] == [3, 4]
    (bar,) = _Bar.made
    assert (bar.total, bar.desc, bar.n, bar.closed) == (7, "sweep", 7, True)


def test_bar_follows_a_cluster(monkeypatch):
    """Under a dask.distributed scheduler (no local callbacks run there) the bar
    follows the futures: it counts the cases of the counted tasks (a LocalCluster
    in this process, 2 workers; skipped without the ``cluster`` extra)."""
    pytest.importorskip("distributed")
    from distributed import LocalCluster
    from railcontact.core.parallel import compute
    monkeypatch.setattr(progress, "tqdm", _Bar)
    _Bar.made.clear()
    chains = [dask.delayed(_cases)(n, dask_key_name=f"_solve-{n}") for n in (3, 4)]
    other = dask.delayed(_cases)(10, dask_key_name="_prepare-0")
    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None,
                      processes=False) as cluster:
        out = compute(chains + [other], cluster.scheduler_address,
                      progress.TqdmCallback(total=7, desc="sweep"))
    assert [len(c) for c in out] == [3, 4, 10]
    (bar,) = _Bar.made
    assert (bar.n, bar.closed) == (7, True)


def _cases(n):
    return list(range(n))
