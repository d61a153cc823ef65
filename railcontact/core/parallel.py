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


def _on_cluster(client, tasks: list, callback=None) -> list:
    """The tasks computed on a dask.distributed ``client``, the progress bar of
    ``callback`` (a :class:`~railcontact.core.progress.TqdmCallback`) advanced as
    each of its counted tasks' result comes back, as the callback counts them
    (Dask's local callbacks do not run there)."""
    from distributed import as_completed
    futures = client.compute(list(tasks))
    index = {}
    for i, f in enumerate(futures):                # equal tasks share one future
        index.setdefault(f.key, []).append(i)
    out = [None] * len(futures)
    bar = callback.open_bar() if callback is not None and hasattr(callback, "open_bar") \
        else None
    try:
        for fut, result in as_completed(futures, with_results=True):
            name = fut.key[0] if isinstance(fut.key, tuple) else fut.key
            counted = bar is not None and str(name).startswith(callback.prefix)
            for i in index[fut.key]:
                out[i] = result
                if counted:
                    bar.update(len(result) if isinstance(result, list) else 1)
    finally:
        if bar is not None:
            bar.close()
    return out


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
    check_scheduler(scheduler, what)
    if scheduler.startswith(ADDRESS):
        from distributed import Client
        with Client(scheduler) as client:
            return _on_cluster(client, tasks, callback)
    with callback or nullcontext():
        return list(dask.compute(*tasks, scheduler=scheduler))
