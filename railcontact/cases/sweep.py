"""Many cases at once: parameter sweeps, in parallel with Dask."""

from __future__ import annotations

import functools
import itertools
import math
import logging
import os
import time

import numpy as np

from .case import Case, case_from_dict
from .solve import solve
from ..core.checks import check_job_size, shown
from ..core.errors import InputError, RailContactError
from ..core.parallel import check_scheduler, compute

log = logging.getLogger(__name__)


def parse_vary(spec: str, allow_large: bool = False):
    """Parse ``KEY=START:STOP:STEP`` (inclusive stop) or ``KEY=v1,v2,...``; more
    than :data:`~railcontact.core.checks.MAX_JOB_CASES` values only with
    ``allow_large``."""
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
            if not all(np.isfinite(parts)):
                raise ValueError
            n = int(np.floor((stop - start) / step + 1e-9)) + 1
            if n < 1:
                raise ValueError
            values = None
        else:
            values = [float(v) for v in rng.split(",")]
            if not all(np.isfinite(values)):
                raise ValueError
    except (ValueError, OverflowError):
        raise InputError(f"--vary {shown(spec)}: expected KEY=START:STOP:STEP with a non-zero "
                         "step that reaches STOP, or KEY=v1,v2,... (finite numbers)") from None
    if values is None:
        check_job_size(n, f"--vary {shown(spec)}", allow_large=allow_large)
        values = [start + i * step for i in range(n)]
    return key, [round(v, 12) for v in values]


def _solve_chain(raws, base_dir, normal, tangential, warm):
    """Solve consecutive cases in order; with ``warm`` each starts from the previous
    case's solution (:func:`railcontact.solve`'s ``warm_start``)."""
    out, prev = [], None
    for raw in raws:
        try:
            res = solve(case_from_dict(raw, base_dir), normal, tangential,
                        warm_start=prev if warm else None)
            prev = res
            d = res.to_dict()
            out.append({k: d[k] for k in ("patches", "converged", "message", "warnings",
                                          "vertical_residual") if k in d})
        except RailContactError as exc:
            prev = None
            out.append({"patches": [], "error": str(exc)})
    return out


#: estimated time [s] of one wheel-rail case by the heavier of its models, for the
#: "auto" scheduler (docs/tuning.md, section "Sweeps")
CASE_SECONDS = {"exact": 0.02}
OTHER_CASE_SECONDS = 0.005

#: "auto" runs a sweep in worker processes when it is expected to take longer than this
#: [s] in one process (each worker imports railcontact and loads the compiled kernels;
#: docs/tuning.md, section "Sweeps")
PROCESSES_FROM = 8.0
#: cases per warm chain by default: the chains, and so a warm sweep's results (each
#: chain's first case starts cold), do not depend on the machine's cores or the
#: scheduler
CHAIN_LENGTH = 64


def _expected_seconds(case: Case, n: int, normal, tangential) -> float:
    """Rough time [s] of n cases of this case's models in one process."""
    names = {str(normal or case.normal).lower(), str(tangential or case.tangential).lower()}
    return n * max([CASE_SECONDS.get(m, OTHER_CASE_SECONDS) for m in names])


def sweep(case: Case, vary: dict, normal: str | None = None, tangential: str | None = None,
          scheduler: str = "auto", progress: bool = True, warm: bool = False,
          chains: int | None = None, allow_large: bool = False) -> dict:
    """Solve every combination of the varied case keys.

    Parameters
    ----------
    case : Case
    vary : dict
        Dotted case key -> list of values, e.g. ``{"wheelset.lateral_shift": [0, 0.001]}``.
    scheduler : str
        Dask scheduler: ``"sync"``, ``"threads"``, ``"processes"``, ``"auto"``
        (processes where the sweep is expected to take over ``PROCESSES_FROM``
        seconds in one process, e.g. from 400 exact or 1600 Hertz + FASTSIM cases;
        docs/tuning.md, section "Sweeps") or the address of a Dask scheduler
        (``tcp://host:8786``) to run on a cluster.
    progress : bool
        Show a progress bar.
    warm : bool
        Solve consecutive cases as chains, each case warm-started from the previous
        one (pays for the exact solvers, whose iterations start from the neighbouring
        solution; the last varied key changes fastest).
    allow_large : bool
        Run more than :data:`~railcontact.core.checks.MAX_JOB_CASES` cases.
    chains : int, optional
        Number of chains (parallel tasks) with ``warm``: default one per
        ``CHAIN_LENGTH`` (64) cases, whatever the scheduler and the machine's cores
        (the results of a warm sweep depend on where its chains start).

    Returns
    -------
    dict ``{"cases": [{"params": {...}, "patches": [...]}], "cpu_time": s}``; a case
    that fails carries an ``"error"`` message instead of patches.
    """
    if not isinstance(case, Case):
        raise InputError(f"case = {shown(case)}: expected a Case (railcontact.load_case or "
                         "case_from_dict)")
    t0 = time.perf_counter()
    keys = list(vary) if isinstance(vary, dict) else []
    if not isinstance(vary, dict) or not all(isinstance(v, (list, tuple)) and v
                                             for v in vary.values()):
        raise InputError(f"vary = {shown(vary)}: expected a dict of case keys to non-empty "
                         "lists of values")
    check_scheduler(scheduler, "scheduler", auto=True)
    count = int(np.prod([len(vary[k]) for k in keys], dtype=float))
    check_job_size(count, "sweep", allow_large=allow_large,
                   seconds_each=_expected_seconds(case, 1, normal, tangential))
    combos = list(itertools.product(*[vary[k] for k in keys]))
    raws = []
    for combo in combos:
        c = case
        for k, v in zip(keys, combo):
            c = c.with_value(k, v)   # validates every combination before any work
        raws.append(c.raw)
    chain = functools.partial(_solve_chain, base_dir=case.base_dir, normal=normal,
                              tangential=tangential)
    out = run_chains(chain, raws, scheduler=scheduler, progress=progress, warm=warm,
                     chains=chains,
                     expected_seconds=_expected_seconds(case, len(raws), normal, tangential))
    cases = [{"params": dict(zip(keys, combo)), **o} for combo, o in zip(combos, out)]
    return {"cases": cases, "cpu_time": time.perf_counter() - t0}


def run_chains(chain, items: list, scheduler: str = "auto", progress: bool = True,
               warm: bool = False, chains: int | None = None, expected_seconds: float = 0.0,
               desc: str = "sweep") -> list:
    """``chain(items[a:b], warm)`` over consecutive slices of ``items`` in Dask tasks
    (the machinery of :func:`sweep`; ``chain`` returns one output per item and must
    be picklable for worker processes).  ``scheduler`` and ``chains`` as in
    :func:`sweep`; "auto" runs in processes where ``expected_seconds`` exceeds
    ``PROCESSES_FROM``.  Returns the outputs in the order of ``items``."""
    import dask
    if scheduler == "auto":
        long = expected_seconds > PROCESSES_FROM
        scheduler = "processes" if long and (os.cpu_count() or 1) > 1 else "sync"
    if chains is None:
        chains = len(items) if not warm else max(1, math.ceil(len(items) / CHAIN_LENGTH))
    if not (isinstance(chains, int) and chains >= 1):
        raise InputError(f"chains {chains!r}: expected a positive integer")
    if not items:
        return []
    bounds = np.linspace(0, len(items), min(chains, len(items)) + 1).round().astype(int)
    tasks = [dask.delayed(chain)(items[a:b], warm=warm) for a, b in zip(bounds[:-1], bounds[1:])]
    bar = None
    if progress:
        from ..core.progress import TqdmCallback       # Dask's callbacks: loaded with dask
        bar = TqdmCallback(total=len(items), desc=desc)
    out = compute(tasks, scheduler, bar)
    return [o for chain_out in out for o in chain_out]
