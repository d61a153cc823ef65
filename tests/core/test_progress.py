"""railcontact.core.progress: a tqdm bar advanced by the cases of finished Dask tasks."""

import dask

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
