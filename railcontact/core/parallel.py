"""Dask tasks run on a scheduler chosen by name: the one way the sweeps, the wear
runs and the closed loop compute in parallel."""

from __future__ import annotations

from contextlib import nullcontext

from .errors import InputError

#: local Dask schedulers by name
LOCAL = ("threads", "processes", "sync", "synchronous")
#: prefixes of the address of a dask.distributed scheduler
ADDRESS = ("tcp://", "tls://", "inproc://")


def compute(tasks: list, scheduler: str, callback=None, what: str = "scheduler") -> list:
    """The results of the Dask ``tasks`` in their order.

    Parameters
    ----------
    tasks : list of dask.delayed
    scheduler : str
        ``"threads"``, ``"processes"`` (one worker per core), ``"sync"``, or the
        address of a dask.distributed scheduler (``tcp://host:port``: a client is
        opened for the run and closed after it).
    callback : railcontact.core.progress.TqdmCallback, optional
        A progress bar: a Dask callback on the local schedulers; on a cluster it
        follows the tasks' futures as they finish (a cluster calls no local
        callbacks).
    what : str
        The input's name in the error for an unknown scheduler.
    """
    import dask
    if scheduler.startswith(ADDRESS):
        try:
            from distributed import Client
        except ImportError:
            raise InputError(f"{what} = {scheduler!r}: a Dask cluster needs the "
                             "dask.distributed package (pip install 'railcontact[cluster]')"
                             ) from None
        with Client(scheduler) as client:
            futures = client.compute(list(tasks))
            if callback is None:
                return list(client.gather(futures))
            # a cluster runs no local Dask callbacks: the bar follows the futures
            done = callback.follow(futures)
            return [done[f.key] for f in futures]
    if scheduler not in LOCAL:
        raise InputError(f"{what} = {scheduler!r}: expected 'threads', 'processes', 'sync' "
                         "or a Dask scheduler address tcp://host:port")
    with callback or nullcontext():
        return list(dask.compute(*tasks, scheduler=scheduler))
