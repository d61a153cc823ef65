"""Where an exact + exact wheel-rail case spends its FFT convolutions, and the same
against the code of a git ref (issue 30); ``benchmarks/exact_case.md``.

The 1000-case sweep of ``run_all.sweep_raws`` (S1002 on 60E1 1:40, 70 kN per
wheel, shift -4..9 mm, yaw 0..6 mrad, creepages varying, 40 x 40 grid), solved
cold and warm-started along the sweep with the package's defaults, each tree in
a worker process of its own: this checkout ("after") and, with ``--before REF``,
the ref checked out as a temporary worktree beside it ("before";
``before_after.ref_tree``: its own library, this script's sweep and counting), the
two interleaved in blocks of 50 cases (each worker keeps its warm chain across
its blocks); CPU time per case (the shared machine's pauses out).  The library
keeps no switch for a "before": e.g. the start before the compiled Hertz +
FASTSIM start is the commit before it (``--before c632828^``).

The stages are counted by wrapping their functions: the balance's passes
(provisional, or final: the tangential problems solved), the contact searches,
the exact normal solves (Polonsky-Keer iterations: one FFT convolution A t each,
and A p refreshed at least every 10, counted as it + ceil(it / 10)), the exact
tangential solves (semi-smooth Newton iterations and products with the Jacobian:
each product two real 2-D transforms and two inverse ones of the contact box's
padded grid, i.e. two convolutions of at most the 80 x 80 size, counted as 2 (1 +
products)), FASTSIM (the stand-ins of the provisional passes).  Every time is also
given in units of one FFT convolution of the 80 x 80 padded grid
(``polonsky_keer._convolve``), its CPU time measured between the blocks.

``python benchmarks/exact_case.py [--cases 1000] [--before REF] [--out benchmarks/exact_case.md]``
"""

from __future__ import annotations

import argparse
import functools
import importlib
import json
import os
import subprocess
import sys
import time
from collections import defaultdict
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import railcontact as rc                                   # noqa: E402
from md_report import write_report                         # noqa: E402
from run_all import sweep_raws                             # noqa: E402

ROOT = HERE.parent
#: the line a worker prefixes its block's results with (JSON)
TAG = "@exact_case "


class Counter:
    """Calls, CPU time, iterations and counted convolutions of the wrapped stages."""

    def __init__(self):
        self.calls = defaultdict(int)
        self.cpu = defaultdict(float)
        self.iters = defaultdict(int)
        self.conv = defaultdict(int)
        self.saved = []

    def wrap(self, mod, attr, label, count=None, skip=None):
        """Count ``mod.attr`` under ``label``; a stage the code does not have (an
        older tree's) is left out."""
        owner = importlib.import_module(mod)
        *path, name = attr.split(".")
        for p in path:
            owner = getattr(owner, p, None)
        real = getattr(owner, name, None)
        if real is None:
            return
        me = self

        @functools.wraps(real)
        def timed(*a, **k):
            if skip is not None and skip(*a, **k):
                return real(*a, **k)
            t0 = time.process_time()
            res = real(*a, **k)
            me.cpu[label] += time.process_time() - t0
            me.calls[label] += 1
            if count is not None:
                it, conv = count(res)
                me.iters[label] += it
                me.conv[label] += conv
            return res
        self.saved.append((owner, name, real))
        setattr(owner, name, timed)

    def restore(self):
        for owner, name, real in reversed(self.saved):
            setattr(owner, name, real)
        self.saved = []

    def state(self) -> dict:
        """The counts, for a worker's JSON line."""
        return {k: dict(getattr(self, k)) for k in ("calls", "cpu", "iters", "conv")}

    def add(self, state: dict) -> None:
        """Add a worker's counts (:meth:`state`)."""
        for k, d in state.items():
            mine = getattr(self, k)
            for label, v in d.items():
                mine[label] += v


def _pk(res):
    it = res[2]
    return it, it + (it + 9) // 10


def _ssn(res):
    return res[5], 2 * (res[6] + 1)


def _pass(res):
    return int(res.final), 0


def _reused(evaluate, d, final=False):
    """Whether a call of the contact evaluation returns its last evaluation as it
    is (a warm case's first evaluation, made before its restart check, asked again
    by the balance): not counted as a pass."""
    last = evaluate.last
    return last is not None and last.interpenetration == d and (last.final or not final)


STAGES = (("railcontact.cases.balance", "WheelRailContact.__call__",
           "balance passes (of them final)", _pass, _reused),
          ("railcontact.cases.balance", "contact_search", "contact searches", None),
          ("railcontact.normal.exact", "ExactNormalModel.solve", "exact normal solves", None),
          ("railcontact.normal.exact", "polonsky_keer", "  Polonsky-Keer iterations", _pk),
          ("railcontact.tangential.exact", "ExactTangentialModel.solve",
           "exact tangential solves", None),
          ("railcontact.tangential.exact", "ssn_solve", "  semi-smooth Newton (GMRES)", _ssn),
          ("railcontact.tangential.fastsim", "FastsimModel.solve", "FASTSIM stand-ins", None))


def unit_cpu(number=300, repeat=5):
    """CPU time [s] of one FFT convolution of the 40 x 40 grid's 80 x 80 padding,
    the solvers' own compiled product (best of ``repeat``)."""
    from railcontact.normal.influence import normal_operator
    from railcontact.normal.polonsky_keer import _convolve
    op = normal_operator(40, 40, 1e-4, 1e-4, 2.3e11)
    p = np.random.default_rng(1).random((40, 40))
    buf = np.zeros(op.shape)
    _convolve(p, op.khat, op.shape, buf)
    best = np.inf
    for _ in range(repeat):
        t0 = time.process_time()
        for _ in range(number):
            _convolve(p, op.khat, op.shape, buf)
        best = min(best, (time.process_time() - t0) / number)
    return best


def worker(n_cases, offset):
    """``--worker``: the sweep's cases ``offset`` .. ``offset + n_cases`` of the
    library on ``sys.path`` (the tree this process was started in); reads lines
    "i0 i1" on stdin, solves cases i0 .. i1 (indices into those) cold and then
    warm-started along the sweep (the warm chain kept across blocks), and writes a
    line :data:`TAG` + JSON: the unit measured before the block, and per run the
    CPU times, the results' summaries and the stage counts."""
    from railcontact.cases.case import case_from_dict
    cases = [case_from_dict(r) for r in sweep_raws()][offset:offset + n_cases]
    # compile / load every kernel the sweep reaches before timing (with an empty
    # Numba cache a path met first within a timed block, e.g. a two-patch case,
    # took 55x the median in that block): every 25th case, cold and a warm neighbour
    for i in range(0, len(cases) - 1, 25):
        rc.solve(cases[i + 1], "exact", "exact",
                 warm_start=rc.solve(cases[i], "exact", "exact"))
    prev = None
    for line in sys.stdin:
        if not line.strip():
            break
        i0, i1 = map(int, line.split())
        out = {"unit": unit_cpu()}
        for w in ("cold", "warm"):
            c = Counter()
            for st in STAGES:
                c.wrap(*st)
            t, summary = [], []
            try:
                for i in range(i0, i1):
                    t0 = time.process_time()
                    res = rc.solve(cases[i], "exact", "exact",
                                   warm_start=prev if w == "warm" else None)
                    t.append(time.process_time() - t0)
                    if w == "warm":
                        prev = res
                    summary.append((
                        bool(res.converged), int(res.balance.passes),
                        float(sum(p.normal.normal_force for p in res.patches)),
                        float(sum(p.tangential.fx for p in res.patches)),
                        float(sum(p.tangential.fy for p in res.patches))))
            finally:
                c.restore()
            out[w] = {"t": t, "summary": summary, "counts": c.state()}
        print(TAG + json.dumps(out), flush=True)


def _start_worker(tree, n_cases, offset):
    """A :func:`worker` process on the library of ``tree`` (another tree's with a
    Numba cache of its own; this checkout's with the environment's)."""
    env = dict(os.environ, PYTHONPATH=str(tree))
    if Path(tree).resolve() != ROOT:
        env["NUMBA_CACHE_DIR"] = str(Path(tree) / ".venv-bench-numba")
    return subprocess.Popen([sys.executable, str(Path(__file__).resolve()), "--worker",
                             "--cases", str(n_cases), "--offset", str(offset)],
                            cwd=tree, env=env, stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, text=True)


def _ask(proc, i0, i1) -> dict:
    """One block of a worker: its JSON result."""
    proc.stdin.write(f"{i0} {i1}\n")
    proc.stdin.flush()
    for line in proc.stdout:
        if line.startswith(TAG):
            return json.loads(line[len(TAG):])
    raise RuntimeError(f"exact_case worker stopped (exit {proc.wait()})")


def run(n_cases=1000, block=50, offset=0, trees=None):
    """The sweep in the worker of each of ``trees`` ({"before": path, "after":
    path}; default this checkout as "after"), the trees alternating block by
    block; returns the per-case CPU times, results' summaries, the stage counters
    and the unit (median of the workers' measurements)."""
    trees = trees or {"after": ROOT}
    procs = {m: _start_worker(tree, n_cases, offset) for m, tree in trees.items()}
    keys = [(m, w) for m in trees for w in ("cold", "warm")]
    t = {k: np.zeros(n_cases) for k in keys}
    summary = {k: [None] * n_cases for k in keys}
    counters = {k: Counter() for k in keys}
    units = []
    try:
        for b0 in range(0, n_cases, block):
            b1 = min(b0 + block, n_cases)
            for m, proc in procs.items():
                res = _ask(proc, b0, b1)
                units.append(res["unit"])
                for w in ("cold", "warm"):
                    t[(m, w)][b0:b1] = res[w]["t"]
                    summary[(m, w)][b0:b1] = [tuple(x) for x in res[w]["summary"]]
                    counters[(m, w)].add(res[w]["counts"])
    finally:
        for proc in procs.values():
            proc.stdin.close()
            proc.wait()
    return t, summary, counters, float(np.median(units))


def _top(v) -> float:
    """The largest of v (0 where empty)."""
    return float(v.max()) if v.size else 0.0


def report(t, summary, counters, unit, n, offset=0):
    lines = []
    out = lines.append
    shifts = np.array([r["wheelset"]["lateral_shift"] for r in sweep_raws()])[offset:offset + n]
    out(f"* the unit: one FFT convolution of the 80 x 80 padded grid (40 x 40 elements; "
        f"the solvers' compiled product), {unit * 1e6:.1f} µs of CPU in this run (median "
        f"of the workers' measurements before each block)")
    out("")
    out("| run | mean | median | max / median | cases over 3x the median | balance passes "
        "(mean, max) | load met |")
    out("|---|---|---|---|---|---|---|")
    for (m, w), v in t.items():
        s = summary[(m, w)]
        ok = sum(x[0] for x in s)
        passes = np.array([x[1] for x in s])
        med = float(np.median(v))
        out(f"| {w}, {m} | {v.mean() * 1e3:.2f} ms = {v.mean() / unit:.0f} conv. | "
            f"{med * 1e3:.2f} ms = {med / unit:.0f} conv. | {v.max() / med:.1f} (case "
            f"{offset + int(np.argmax(v))}, {shifts[int(np.argmax(v))] * 1e3:.2f} mm) | "
            f"{int(np.sum(v > 3 * med))} | {passes.mean():.2f}, {passes.max()} | "
            f"{ok} of {n} |")
    for w in ("cold", "warm") if ("before", "cold") in summary else ():
        a = np.array([x[2:] for x in summary[("before", w)]])
        b = np.array([x[2:] for x in summary[("after", w)]])
        mq = 0.3 * 1.4e5
        dfx = np.abs(b[:, 1] - a[:, 1]) / mq
        dfy = np.abs(b[:, 2] - a[:, 2]) / mq
        dfn = np.abs(b[:, 0] - a[:, 0]) / 1.4e5
        tread = shifts < 6.2e-3
        out(f"* {w}, after against before: sum F_n within {dfn.max() * 100:.4f} % of Q "
            f"(median {np.median(dfn) * 100:.5f} %), sum F_x within "
            f"{_top(dfx[tread]) * 100:.3f} % of mu Q below 6.2 mm shift and "
            f"{_top(dfx[~tread]) * 100:.3f} % in flange contact (median "
            f"{np.median(dfx) * 100:.4f} %), sum F_y within {dfy.max() * 100:.3f} % of mu Q; "
            f"sums of F_n, F_x, F_y equal bit for bit in "
            f"{int(np.sum(np.all(a == b, axis=1)))} of {len(a)} cases")
    for (m, w), c in counters.items():
        total = t[(m, w)].sum()
        out("")
        out(f"Where the time goes, {w}, {m} ({n} cases, {total / n * 1e3:.2f} ms = "
            f"{total / n / unit:.0f} convolutions of CPU per case):")
        out("")
        out("| stage | calls per case | iterations per call | FFT convolutions per case "
            "(counted) | CPU per case | = convolutions |")
        out("|---|---|---|---|---|---|")
        inner = 0.0
        for label in (st[2] for st in STAGES):
            if not c.calls[label]:
                continue
            calls = c.calls[label] / n
            if label.startswith("balance"):
                it = f"({c.iters[label] / n:.2f} final)"
            else:
                it = f"{c.iters[label] / c.calls[label]:.1f}" if c.iters[label] else ""
            conv = f"{c.conv[label] / n:.0f}" if c.conv[label] else ""
            ms = c.cpu[label] / n
            out(f"| {label.strip()} | {calls:.2f} | {it} | {conv} | {ms * 1e3:.2f} ms | "
                f"{ms / unit:.0f} |")
            if label in ("contact searches", "exact normal solves",
                         "exact tangential solves", "FASTSIM stand-ins"):
                inner += ms
        rest = total / n - inner
        out(f"| the rest (balance, grids, creepages, results) | | | | {rest * 1e3:.2f} ms | "
            f"{rest / unit:.0f} |")
        counted = (c.conv["  Polonsky-Keer iterations"]
                   + c.conv["  semi-smooth Newton (GMRES)"]) / n
        kernels = (c.cpu["  Polonsky-Keer iterations"] + c.cpu["  semi-smooth Newton (GMRES)"]) / n
        out("")
        out(f"* the solvers' compiled iterations (Polonsky-Keer, semi-smooth Newton) take "
            f"{kernels / (total / n) * 100:.0f} % of the case ({counted:.0f} FFT "
            f"convolutions counted, at most 80 x 80); the contact searches "
            f"{c.cpu['contact searches'] / total * 100:.0f} %, the normal solves' grids, "
            f"gaps and set-up around the iteration "
            f"{(c.cpu['exact normal solves'] - c.cpu['  Polonsky-Keer iterations']) / total * 100:.0f} %, "
            f"the tangential solves' around theirs "
            f"{(c.cpu['exact tangential solves'] - c.cpu['  semi-smooth Newton (GMRES)']) / total * 100:.0f} %")
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--cases", type=int, default=1000)
    ap.add_argument("--out", default=str(HERE / "exact_case.md"))
    ap.add_argument("--offset", type=int, default=0,
                    help="the first case of the sweep to run (a subset: --cases from it)")
    ap.add_argument("--before", default=None, metavar="REF",
                    help="a git ref whose code runs the same sweep as 'before', "
                         "interleaved block by block with this checkout's")
    ap.add_argument("--no-manchester", dest="manchester", action="store_false",
                    help="leave out the Manchester sweep's timing")
    ap.add_argument("--worker", action="store_true",
                    help="(internal) a worker process: see worker()")
    args = ap.parse_args(argv)
    if args.worker:
        return worker(args.cases, args.offset)
    load0 = os.getloadavg()[0]
    if args.before:
        from before_after import ref_tree
        with ref_tree(args.before) as old:
            t, summary, counters, unit = run(args.cases, offset=args.offset,
                                             trees={"before": old, "after": ROOT})
    else:
        t, summary, counters, unit = run(args.cases, offset=args.offset)
    load1 = os.getloadavg()[0]
    lines = report(t, summary, counters, unit, args.cases, args.offset)
    head_ref = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                              capture_output=True, text=True).stdout.strip()
    before = (f"before (the code of `{args.before}`) and after (this checkout, {head_ref}), "
              "each in a worker process of its own, interleaved in blocks of 50 cases"
              if args.before else f"the code of {head_ref}, in blocks of 50 cases")
    intro = (f"`python benchmarks/exact_case.py --cases {args.cases}"
             + (f" --before {args.before}" if args.before else "") + "`: the 1000-case sweep "
             "(S1002 on 60E1 1:40, 70 kN per wheel, shift -4..9 mm, yaw 0..6 mrad, creepages "
             "varying, 40 x 40 grid), cold and warm-started along the sweep with the "
             f"package's defaults, {before}; CPU time per case.  Machine load "
             f"(1-minute load average, 2 cores shared): {load0:.1f} at the start, "
             f"{load1:.1f} at the end.")
    if args.manchester:
        import exact_manchester
        lines += ["", "The Manchester 10 kN sweep (one wheel, the roll prescribed: the compiled "
                  "pass does not run it, the start is unchanged):", ""] + exact_manchester.main()
    return write_report("The exact + exact case: where its FFT convolutions go (issue 30)",
                        intro, lines, args.out)


if __name__ == "__main__":
    main()
