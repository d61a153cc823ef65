"""Where an exact + exact wheel-rail case spends its FFT convolutions, before and
after the compiled Hertz + FASTSIM start (issue 30); ``benchmarks/exact_case.md``.

The 1000-case sweep of ``run_all.sweep_raws`` (S1002 on 60E1 1:40, 70 kN per
wheel, shift -4..9 mm, yaw 0..6 mrad, creepages varying, 40 x 40 grid), solved
cold and warm-started along the sweep, "before" (a cold case from the geometry
layer's multi-Hertzian estimate, a warm one from the extrapolation of its two
previous cases alone: ``BalanceOptions(hertz_start=False)``, and
``equilibrium.FINAL_SLOPE`` = 0) and "after" (the
default: a cold case from the compiled pass's Hertz + FASTSIM balance, a warm one
from it where its first evaluation misses the load by more than
``balance.RESTART_MISS``), interleaved in blocks of 50 cases in one process; CPU
time per case (the shared machine's pauses out).

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

``python benchmarks/exact_case.py [--cases 1000] [--out benchmarks/exact_case.md]``
"""

from __future__ import annotations

import argparse
import functools
import os
import importlib
import sys
import time
from collections import defaultdict
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import railcontact as rc                                   # noqa: E402
from railcontact.cases import equilibrium                 # noqa: E402
from railcontact.cases.balance import BalanceOptions      # noqa: E402
from run_all import sweep_raws                             # noqa: E402

#: the balance's options of each run: no compiled Hertz + FASTSIM start (before),
#: the default (after)
MODES = {"before": BalanceOptions(hertz_start=False), "after": BalanceOptions()}

#: ``equilibrium.FINAL_SLOPE`` of each run: before, no floor (0), as main before
#: this change; after, the default
FINAL_SLOPES = {"before": 0.0, "after": equilibrium.FINAL_SLOPE}


class Counter:
    """Calls, CPU time, iterations and counted convolutions of the wrapped stages."""

    def __init__(self):
        self.calls = defaultdict(int)
        self.cpu = defaultdict(float)
        self.iters = defaultdict(int)
        self.conv = defaultdict(int)
        self.saved = []

    def wrap(self, mod, attr, label, count=None, skip=None):
        owner = importlib.import_module(mod)
        *path, name = attr.split(".")
        for p in path:
            owner = getattr(owner, p)
        real = getattr(owner, name)
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


def run(n_cases=1000, block=50, offset=0):
    """Both modes, cold and warm, interleaved in blocks; returns the per-case CPU
    times, results' summaries and the stage counters."""
    from railcontact.cases.case import case_from_dict
    cases = [case_from_dict(r) for r in sweep_raws()][offset:offset + n_cases]
    rc.solve(cases[0], "exact", "exact")                    # compile / load
    keys = [(m, w) for m in MODES for w in ("cold", "warm")]
    t = {k: np.zeros(len(cases)) for k in keys}
    summary = {k: [None] * len(cases) for k in keys}
    counters = {k: Counter() for k in keys}
    prev = {m: None for m in MODES}
    units = []
    for b0 in range(0, len(cases), block):
        units.append(unit_cpu())
        for m, w in keys:
            c = counters[(m, w)]
            for st in STAGES:
                c.wrap(*st)
            equilibrium.FINAL_SLOPE = FINAL_SLOPES[m]
            try:
                for i in range(b0, min(b0 + block, len(cases))):
                    t0 = time.process_time()
                    res = rc.solve(cases[i], "exact", "exact",
                                   warm_start=prev[m] if w == "warm" else None,
                                   options=MODES[m])
                    t[(m, w)][i] = time.process_time() - t0
                    if w == "warm":
                        prev[m] = res
                    summary[(m, w)][i] = (
                        res.converged, res.balance.passes,
                        sum(p.normal.normal_force for p in res.patches),
                        sum(p.tangential.fx for p in res.patches),
                        sum(p.tangential.fy for p in res.patches))
            finally:
                c.restore()
                equilibrium.FINAL_SLOPE = FINAL_SLOPES["after"]
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
        f"of {n // 50 if n >= 50 else 1} measurements between the blocks)")
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
    for w in ("cold", "warm"):
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
            f"{np.median(dfx) * 100:.4f} %), sum F_y within {dfy.max() * 100:.3f} % of mu Q")
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
    ap.add_argument("--no-manchester", dest="manchester", action="store_false",
                    help="leave out the Manchester sweep's timing")
    args = ap.parse_args(argv)
    load0 = os.getloadavg()[0]
    t, summary, counters, unit = run(args.cases, offset=args.offset)
    load1 = os.getloadavg()[0]
    lines = report(t, summary, counters, unit, args.cases, args.offset)
    head = ["# The exact + exact case: where its FFT convolutions go (issue 30)", "",
            f"`python benchmarks/exact_case.py --cases {args.cases}`: the 1000-case sweep "
            "(S1002 on 60E1 1:40, 70 kN per wheel, shift -4..9 mm, yaw 0..6 mrad, creepages "
            "varying, 40 x 40 grid), cold and warm-started along the sweep, before "
            "(`BalanceOptions(hertz_start=False)` and `equilibrium.FINAL_SLOPE` = 0: cold "
            "from the multi-Hertzian estimate, "
            "warm from the extrapolation of the two previous cases) and after (the "
            "default: cold from the compiled Hertz + FASTSIM balance, warm from it where "
            "the first evaluation misses a load by more than `RESTART_MISS`), interleaved "
            "in blocks of 50 cases in one process; CPU time per case.  Machine load "
            f"(1-minute load average, 2 cores shared): {load0:.1f} at the start, "
            f"{load1:.1f} at the end.", ""]
    if args.manchester:
        import exact_manchester
        lines += ["", "The Manchester 10 kN sweep (one wheel, the roll prescribed: the compiled "
                  "pass does not run it, the start is unchanged):", ""] + exact_manchester.main()
    text = "\n".join(head + lines) + "\n"
    print(text)
    if args.out:
        Path(args.out).write_text(text)
    return lines


if __name__ == "__main__":
    main()
