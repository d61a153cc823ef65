"""Many cases at once: parameter sweeps, in parallel with Dask."""

from __future__ import annotations

import itertools
import logging
import time

import numpy as np

from .case import Case
from .errors import InputError, RailContactError

log = logging.getLogger(__name__)


def parse_vary(spec: str):
    """Parse ``KEY=START:STOP:STEP`` (inclusive stop) or ``KEY=v1,v2,...``."""
    if "=" not in spec:
        raise InputError(f"--vary {spec!r}: expected KEY=START:STOP:STEP or KEY=v1,v2,...")
    key, rng = spec.split("=", 1)
    key = key.strip()
    try:
        if ":" in rng:
            parts = [float(p) for p in rng.split(":")]
            if len(parts) != 3 or parts[2] == 0:
                raise ValueError
            start, stop, step = parts
            n = int(np.floor((stop - start) / step + 1e-9)) + 1
            if n < 1 or n > 100000:
                raise ValueError
            values = [start + i * step for i in range(n)]
        else:
            values = [float(v) for v in rng.split(",")]
    except ValueError:
        raise InputError(f"--vary {spec!r}: expected KEY=START:STOP:STEP with a non-zero step "
                         "that reaches STOP, or KEY=v1,v2,...") from None
    return key, [round(v, 12) for v in values]


def _solve_one(raw, base_dir, normal, tangential):
    from .case import case_from_dict
    from .solve import solve
    try:
        res = solve(case_from_dict(raw, base_dir), normal, tangential)
        return {"patches": [p.to_dict() for p in res.patches]}
    except RailContactError as exc:
        return {"patches": [], "error": str(exc)}


def sweep(case: Case, vary: dict, normal: str | None = None, tangential: str | None = None,
          scheduler: str = "auto", progress: bool = True) -> dict:
    """Solve every combination of the varied case keys.

    Parameters
    ----------
    case : Case
    vary : dict
        Dotted case key -> list of values, e.g. ``{"wheelset.lateral_shift": [0, 0.001]}``.
    scheduler : str
        Dask scheduler: ``"sync"``, ``"threads"``, ``"processes"``, ``"auto"``
        (processes from 64 cases: worker start-up costs about a second) or the address of a Dask scheduler
        (``tcp://host:8786``) to run on a cluster.
    progress : bool
        Show a progress bar.

    Returns
    -------
    dict ``{"cases": [{"params": {...}, "patches": [...]}], "cpu_time": s}``; a case
    that fails carries an ``"error"`` message instead of patches.
    """
    import dask
    t0 = time.perf_counter()
    keys = list(vary)
    combos = list(itertools.product(*[vary[k] for k in keys]))
    raws = []
    for combo in combos:
        c = case
        for k, v in zip(keys, combo):
            c = c.with_value(k, v)   # validates every combination before any work
        raws.append(c.raw)
    tasks = [dask.delayed(_solve_one)(r, case.base_dir, normal, tangential) for r in raws]
    if scheduler == "auto":
        scheduler = "processes" if len(tasks) >= 64 else "sync"
    kwargs = {}
    if scheduler.startswith(("tcp://", "tls://", "inproc://")):
        from distributed import Client
        client = Client(scheduler)
        kwargs["scheduler"] = client.get
    else:
        kwargs["scheduler"] = scheduler
        if scheduler == "processes":
            kwargs["num_workers"] = None
    if progress:
        from .progress import TqdmCallback
        with TqdmCallback(total=len(tasks), desc="sweep"):
            out = dask.compute(*tasks, **kwargs)
    else:
        out = dask.compute(*tasks, **kwargs)
    cases = [{"params": dict(zip(keys, combo)), **o} for combo, o in zip(combos, out)]
    return {"cases": cases, "cpu_time": time.perf_counter() - t0}
