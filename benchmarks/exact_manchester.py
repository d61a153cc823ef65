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
    print("\n".join(lines))
    return lines


if __name__ == "__main__":
    main()
