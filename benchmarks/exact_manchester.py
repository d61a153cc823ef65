"""The Manchester 10 kN sweep (right wheel, roll 0, 0.25 mm elements) with the exact
models: our CPU time per case against CONTACT's reference timing
(``../shared/reference/contact_timing.csv``), also in FFT-convolution units, and
the passes of the (scalar) vertical balance.  Prints; issue 30's figure
(``benchmarks/exact_case.md`` quotes it).

``python benchmarks/exact_manchester.py``
"""

from __future__ import annotations

import csv
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import railcontact as rc                                   # noqa: E402
from exact_case import unit_cpu                            # noqa: E402
from run_all import REF, mbench_case                       # noqa: E402


def main(repeat=3):
    rows = list(csv.DictReader(open(REF / "mbench_sweep_10kN.csv")))
    timing = {float(r["y_ws_mm"]): float(r["ms_per_case"])
              for r in csv.DictReader(open(REF / "contact_timing.csv"))
              if r["workload"] == "mbench_sweep_10kN"}
    cases = [mbench_case(REF / "profiles", float(r["y_ws_mm"]), float(r["vpitch_rad_s"]),
                         {"roll": 0.0}, {"normal": "exact", "tangential": "exact",
                                         "element_size": [0.25e-3, 0.25e-3]}) for r in rows]
    rc.solve(cases[0])
    unit = unit_cpu()
    ms, ratio, passes = [], [], []
    for r, c in zip(rows, cases):
        best = float("inf")
        for _ in range(repeat):
            t0 = time.process_time()
            res = rc.solve(c)
            best = min(best, time.process_time() - t0)
        ms.append(best * 1e3)
        ratio.append(best * 1e3 / timing[float(r["y_ws_mm"])])
        passes.append(res.balance.passes)
    med = statistics.median(ms)
    lines = [f"* Manchester 10 kN sweep, exact + exact, 0.25 mm elements (CPU, best of "
             f"{repeat} per case): median {med:.2f} ms = {med * 1e-3 / unit:.0f} FFT "
             f"convolutions of the 80 x 80 grid ({unit * 1e6:.1f} µs in this run); ours / "
             f"CONTACT's reference timing median {statistics.median(ratio):.2f} (min "
             f"{min(ratio):.2f}, max {max(ratio):.2f}; target 0.1); balance passes "
             f"{statistics.mean(passes):.2f} per case (max {max(passes)})"]
    # the same sweep warm-started along it (each case from the previous one's
    # result, as a sweep with --warm runs it), best of ``repeat`` chains per case
    wms = [float("inf")] * len(cases)
    wpasses, dev = [0] * len(cases), [0.0] * len(cases)
    cold = [rc.solve(c) for c in cases]
    for _ in range(repeat):
        prev = None
        for k, c in enumerate(cases):
            t0 = time.process_time()
            prev = rc.solve(c, warm_start=prev)
            wms[k] = min(wms[k], (time.process_time() - t0) * 1e3)
            wpasses[k] = prev.balance.passes
            fn = sum(p.normal.normal_force for p in cold[k].patches)
            dev[k] = max(abs(sum(p.tangential.fx for p in prev.patches)
                             - sum(p.tangential.fx for p in cold[k].patches)),
                         abs(sum(p.tangential.fy for p in prev.patches)
                             - sum(p.tangential.fy for p in cold[k].patches))) / (0.3 * fn)
    wratio = [w / timing[float(r["y_ws_mm"])] for w, r in zip(wms, rows)]
    wmed = statistics.median(wms)
    lines.append(f"* the same, warm-started along the sweep (each case from the previous "
                 f"one's result): median {wmed:.2f} ms = {wmed * 1e-3 / unit:.0f} "
                 f"convolutions, ours / CONTACT's median {statistics.median(wratio):.2f} "
                 f"(min {min(wratio):.2f}, max {max(wratio):.2f}); balance passes "
                 f"{statistics.mean(wpasses):.2f} per case (max {max(wpasses)}); F_x, F_y "
                 f"within {max(dev) * 100:.3f} % of mu F_n of the cold results")
    print("\n".join(lines))
    return lines


if __name__ == "__main__":
    main()
