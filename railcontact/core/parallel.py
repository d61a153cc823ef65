"""Dask tasks run on a scheduler chosen by name: the one way the sweeps, the wear
runs and the closed loop compute in parallel."""

from __future__ import annotations

from contextlib import nullcontext

from .checks import shown
from .errors import InputError

#: local Dask schedulers by name
LOCAL = ("threads", "processes", "sync", "synchronous")
#: prefixes of the address of a dask.distributed scheduler
ADDRESS = ("tcp://", "tls://", "inproc://")


def check_scheduler(scheduler, what: str = "--scheduler", auto: bool = False) -> str:
    """``scheduler`` checked before any work: a local scheduler's name, or the
    address of a dask.distributed scheduler with the ``distributed`` package
    installed (else the error names the extra to install); ``auto``: "auto" (the
    sweeps' choice between sync and processes) accepted too."""
    if not isinstance(scheduler, str) or not (scheduler in LOCAL + (("auto",) if auto else ())
                                              or scheduler.startswith(ADDRESS)):
        raise InputError(f"{what} = {shown(scheduler)}: expected 'threads', 'processes', "
                         f"'sync'{', auto' if auto else ''} or a Dask scheduler address "
                         "tcp://host:port")
    if scheduler.startswith(ADDRESS):
        try:
            import distributed  # noqa: F401
        except ImportError:
            raise InputError(f"{what} = {scheduler!r}: a Dask cluster needs the package "
                             "'distributed'; install it with: pip install railcontact[cluster]"
                             ) from None
    return scheduler


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
    check_scheduler(scheduler, what)
    if scheduler.startswith(ADDRESS):
        from distributed import Client
        with Client(scheduler) as client:
            futures = client.compute(list(tasks))
            if callback is None:
                return list(client.gather(futures))
            # a cluster runs no local Dask callbacks: the bar follows the futures
            done = callback.follow(futures)
            return [done[f.key] for f in futures]
    with callback or nullcontext():
        return list(dask.compute(*tasks, scheduler=scheduler))
