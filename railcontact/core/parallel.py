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
    callback : dask.callbacks.Callback, optional
        Active during the run (a progress bar, :mod:`railcontact.core.progress`).
    what : str
        The input's name in the error for an unknown scheduler.
    """
    import dask
    if scheduler.startswith(ADDRESS):
        from distributed import Client
        with Client(scheduler) as client, callback or nullcontext():
            return list(dask.compute(*tasks, scheduler=client.get))
    if scheduler not in LOCAL:
        raise InputError(f"{what} = {scheduler!r}: expected 'threads', 'processes', 'sync' "
                         "or a Dask scheduler address tcp://host:port")
    with callback or nullcontext():
        return list(dask.compute(*tasks, scheduler=scheduler))
