"""Where an exact normal solve of a wheel-rail case spends its time (issue 30);
``benchmarks/exact_normal.md``.

The 1000-case sweep of ``run_all.sweep_raws`` (S1002 on 60E1 1:40, 70 kN per
wheel, 40 x 40 grid), its first ``--cases`` cases solved exact + exact, cold and
warm-started along the sweep, interleaved in blocks of 50; the stages of every
``ExactNormalModel.solve`` timed (CPU) by wrapping the functions it calls:

* the Polonsky-Keer iteration (``polonsky_keer``: the compiled iteration and the
  final check of the contact conditions, one more convolution);
* the potential area's coarse sampling of the gap (``_area_from_gap``: 49 x 49
  points, where the grid is not kept);
* the undeformed distance on the grid (``own_gap``: 40 x 40 points);
* the influence operator of the solved block (``_operator``: cached per grid,
  element size, block size and material; computed where the grid is new);
* the rest: Python around them (grid lines, boxes, warm start, result objects).

The Polonsky-Keer iterations are counted per start: the previous pass's pressure
on the same grid (a kept grid), a neighbouring case's interpolated onto a new
grid, none (o / (2 A_ii) of the overlap o).  Runs on any checkout (the stages'
functions are those of main since dd22a81), so that a ref can be timed
interleaved with this one: ``benchmarks/before_after.py`` or by hand.

``python benchmarks/exact_normal.py [--cases 200] [--out benchmarks/exact_normal.md]``
"""

from __future__ import annotations

import argparse
import functools
import sys
import time
from collections import defaultdict
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import railcontact as rc                                   # noqa: E402
from railcontact.normal import exact                       # noqa: E402
from md_report import write_report                         # noqa: E402
from run_all import sweep_raws                             # noqa: E402

#: (attribute of railcontact.normal.exact, label): the stages timed
STAGES = (("ExactNormalModel.solve", "normal solve"),
          ("polonsky_keer", "Polonsky-Keer (iteration and check)"),
          ("ExactNormalModel._area_from_gap", "potential area (coarse gap sampling)"),
          ("own_gap", "gap on the grid"),
          ("_operator", "influence operator (lookup, or built)"))


class Stages:
    """CPU time and calls of the wrapped stages; Polonsky-Keer iterations per start."""

    def __init__(self):
        self.cpu = defaultdict(float)
        self.calls = defaultdict(int)
        self.iters = defaultdict(list)
        self.start = None
        self.saved = []

    def wrap(self):
        for attr, label in STAGES:
            owner = exact
            *path, name = attr.split(".")
            for p in path:
                owner = getattr(owner, p)
            real = getattr(owner, name)
            setattr(owner, name, self._timed(real, label))
            self.saved.append((owner, name, real))
        real_same = exact.same_grid

        def same(*a):
            r = real_same(*a)
            self.start = "same grid" if r else "interpolated"
            return r
        exact.same_grid = same
        self.saved.append((exact, "same_grid", real_same))

    def _timed(self, real, label):
        me = self

        @functools.wraps(real)
        def timed(*a, **k):
            if label == "normal solve":
                me.start = None
            t0 = time.process_time()
            res = real(*a, **k)
            me.cpu[label] += time.process_time() - t0
            me.calls[label] += 1
            if label.startswith("Polonsky"):
                start = "none" if k.get("p0") is None else (me.start or "interpolated")
                me.iters[start].append(int(res[2]))
                me.start = None
            return res
        return timed

    def restore(self):
        for owner, name, real in reversed(self.saved):
            setattr(owner, name, real)
        self.saved = []


def run(n_cases=200, block=50):
    """Cold and warm, interleaved in blocks; returns the per-case CPU times and the
    stages of each."""
    from railcontact.cases.case import case_from_dict
    cases = [case_from_dict(r) for r in sweep_raws()][:n_cases]
    rc.solve(cases[0], "exact", "exact")                    # compile / load
    t = {w: np.zeros(len(cases)) for w in ("cold", "warm")}
    stages = {w: Stages() for w in t}
    prev = None
    for b0 in range(0, len(cases), block):
        for w in t:
            stages[w].wrap()
            try:
                for i in range(b0, min(b0 + block, len(cases))):
                    t0 = time.process_time()
                    res = rc.solve(cases[i], "exact", "exact",
                                   warm_start=prev if w == "warm" else None)
                    t[w][i] = time.process_time() - t0
                    if w == "warm":
                        prev = res
            finally:
                stages[w].restore()
    return t, stages


def report(t, stages, n):
    from exact_case import unit_cpu
    unit = unit_cpu()
    lines = []
    out = lines.append
    out(f"* the unit: one FFT convolution of the 80 x 80 padded grid, {unit * 1e6:.1f} µs "
        "of CPU in this run")
    for w, st in stages.items():
        solves = st.calls["normal solve"]
        out("")
        per = st.cpu["normal solve"] / solves
        out(f"{w}: {t[w].mean() * 1e3:.2f} ms per case, {solves / n:.2f} normal solves per "
            f"case, {per * 1e3:.3f} ms = {per / unit:.1f} convolutions per solve")
        out("")
        out("| stage | calls per solve | CPU per solve | = convolutions | share of the solve |")
        out("|---|---|---|---|---|")
        inner = 0.0
        for _, label in STAGES[1:]:
            ms = st.cpu[label] / solves
            inner += ms
            out(f"| {label} | {st.calls[label] / solves:.2f} | {ms * 1e3:.3f} ms | "
                f"{ms / unit:.1f} | {ms / (st.cpu['normal solve'] / solves) * 100:.0f} % |")
        rest = st.cpu["normal solve"] / solves - inner
        out(f"| the rest (Python: grid lines, boxes, warm start, results) | | "
            f"{rest * 1e3:.3f} ms | {rest / unit:.1f} | "
            f"{rest / (st.cpu['normal solve'] / solves) * 100:.0f} % |")
        out("")
        for start, its in sorted(st.iters.items()):
            its = np.array(its)
            out(f"* Polonsky-Keer from {start}: {its.size} solves, {its.mean():.1f} iterations "
                f"(median {np.median(its):.0f}, {its.min()}..{its.max()})")
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--cases", type=int, default=200)
    ap.add_argument("--out", default=str(HERE / "exact_normal.md"))
    args = ap.parse_args(argv)
    t, stages = run(args.cases)
    return write_report(
        "The exact normal solve of a wheel-rail case: where its time goes (issue 30)",
        f"`python benchmarks/exact_normal.py --cases {args.cases}`: the first {args.cases} "
        "cases of the 1000-case sweep, exact + exact, cold and warm-started along the sweep, "
        "interleaved in blocks of 50; CPU time of each stage of `ExactNormalModel.solve` per "
        "solve.", report(t, stages, args.cases), args.out)


if __name__ == "__main__":
    main()
