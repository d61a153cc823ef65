"""Progress bars (tqdm) for Dask computations and loops.

tqdm's own Dask callback (``tqdm.dask.TqdmCallback``) counts every task of a graph
(a sweep's chain of cases counts one, a wear step's tables count with its routes),
and neither it nor any local Dask callback is called under a dask.distributed
scheduler; :class:`TqdmCallback` counts the cases of the tasks it is asked to and
follows a cluster's futures (:meth:`TqdmCallback.follow`).
"""

from __future__ import annotations

import sys

from dask.callbacks import Callback
from tqdm.auto import tqdm


class TqdmCallback(Callback):
    """Dask callback that advances a tqdm bar as the tasks whose key starts with
    ``prefix`` finish: by the cases of a task that returns a list (a sweep's chain
    of consecutive cases), by one otherwise (e.g. a wear step's route).

    Parameters
    ----------
    total : int
        Length of the bar.
    desc : str
    prefix : str
        Key prefix of the counted tasks (Dask names a delayed call after its
        function).
    **bar
        More options of the tqdm bar (``unit``, ``leave``, ``disable``).
    """

    def __init__(self, total: int, desc: str = "", prefix: str = "_solve", **bar):
        super().__init__()
        self.total, self.desc, self.prefix, self.options = total, desc, prefix, bar

    def _start(self, dsk):
        options = {"file": sys.stderr, "disable": not sys.stderr.isatty() and None}
        options.update(self.options)
        self.bar = tqdm(total=self.total, desc=self.desc, **options)

    def _posttask(self, key, result, dsk, state, worker_id):
        name = key[0] if isinstance(key, tuple) else key
        if str(name).startswith(self.prefix):
            self.bar.update(len(result) if isinstance(result, list) else 1)

    def _finish(self, dsk, state, errored):
        self.bar.close()

    def follow(self, futures) -> dict:
        """Advance the bar as the dask.distributed ``futures`` finish; returns their
        results by key (an error of a task is raised)."""
        from distributed import as_completed
        self._start(None)
        done = {}
        try:
            for fut, result in as_completed(futures, with_results=True):
                done[fut.key] = result
                self._posttask(fut.key, result, None, None, None)
        finally:
            self._finish(None, None, False)
        return done
