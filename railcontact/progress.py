"""Progress bars (tqdm) for Dask computations and loops."""

from __future__ import annotations

import sys

from dask.callbacks import Callback
from tqdm.auto import tqdm


class TqdmCallback(Callback):
    """Dask callback that advances a tqdm bar by the cases of each finished sweep
    task (a chain of consecutive cases)."""

    def __init__(self, total: int, desc: str = "", prefix: str = "_solve"):
        super().__init__()
        self.total, self.desc, self.prefix = total, desc, prefix

    def _start(self, dsk):
        self.bar = tqdm(total=self.total, desc=self.desc, file=sys.stderr,
                        disable=not sys.stderr.isatty() and None)

    def _posttask(self, key, result, dsk, state, worker_id):
        name = key[0] if isinstance(key, tuple) else key
        if str(name).startswith(self.prefix) and isinstance(result, list):
            self.bar.update(len(result))

    def _finish(self, dsk, state, errored):
        self.bar.close()
