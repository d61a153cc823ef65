"""Tables 1 and 2 of seed 001 (Tao et al., CM2015): contact area and maximum pressure
per normal model at wheelset shifts of 0, 3, 5 and 8 mm, each against the exact
model, next to the paper's ratios against CONTACT.

The paper's inputs are the LM wheel on CHN60 rail (1:40), which railcontact has
not got; S1002 on 60E1 (1:40) stand in, with the paper's other inputs: axle load
14 t, E = 206 GPa, nu = 0.28, back-to-back 1353 mm, rolling radius 420 mm, gauge
1435 mm.  Per shift the right wheel's patches (the one that moves towards its
flange) are summed (area) or maximised (p_max).

Run alone (``python benchmarks/seed001_tables.py``, writes
``benchmarks/seed001_tables.md``) or from ``benchmarks/run_all.py``.
"""

from __future__ import annotations

import time
from pathlib import Path

HERE = Path(__file__).resolve().parent

#: Tables 1 and 2 of the paper: shift [mm] -> (CONTACT, Hertz, Kik, Ayasse, Sichani)
PAPER_AREA = {0: (67.2, 60.5, 75.1, 63.8, 58.9), 3: (75.1, 60.4, 85.9, 68.2, 72.4),
              5: (103.9, 102.6, 109.9, 100.6, 100.0), 8: (41.5, 26.5, 62.6, 31.8, 48.4)}
PAPER_PMAX = {0: (1689, 1697, 1399, 1754, 1696), 3: (1580, 1697, 1233, 1753, 1694),
              5: (1007, 989, 924, 989, 989), 8: (3296, 3738, 1675, 3779, 3732)}
MODELS = ("hertz", "kik-piotrowski", "stripes", "analyn")

lines: list = []


def out(s=""):
    print(s, flush=True)
    lines.append(s)


def solve(shift_mm, normal):
    import railcontact as rc
    raw = {"material": {"young_modulus": 206e9, "poisson_ratio": 0.28},
           "friction": {"coefficient": 0.3},
           "wheel": {"profile": "S1002", "nominal_radius": 0.42},
           "rail": {"profile": "60E1", "inclination": 0.025},
           "track": {"gauge": 1.435},
           "wheelset": {"lateral_shift": shift_mm * 1e-3, "vertical_force": 14e3 * 9.81 / 2,
                        "flange_back_distance": 1.353, "velocity": 20.0},
           "solver": {"normal": normal, "tangential": "none"}}
    if normal == "exact":
        raw["solver"]["element_size"] = [0.2e-3, 0.2e-3]
    res = rc.solve(rc.case_from_dict(raw))
    right = [p for p in res.patches if p.geometry.side == "right"]
    return (sum(p.normal.area for p in right) * 1e6, max(p.normal.pmax for p in right) * 1e-6,
            len(right))


def main():
    out(f"# Seed 001, Tables 1 and 2, on S1002/60E1 ({time.strftime('%Y-%m-%d')})\n")
    out("Ratios to the exact model (railcontact, S1002/60E1) and to CONTACT (paper, "
        "LM/CHN60); the sign of (ratio - 1) agrees where both are above or below 1.\n")
    for name, paper, col in (("area [mm²]", PAPER_AREA, 0), ("p_max [MPa]", PAPER_PMAX, 1)):
        out(f"## {name}\n")
        out("| shift | exact | " + " | ".join(f"{m} (paper)" for m in MODELS)
            + " | signs agree |")
        out("|---|---|" + "---|" * len(MODELS) + "---|")
        for shift, ref in paper.items():
            ex = solve(shift, "exact")
            cells, agree = [], 0
            for k, m in enumerate(MODELS):
                v = solve(shift, m)
                r, rp = v[col] / ex[col], ref[k + 1] / ref[0]
                agree += (r - 1) * (rp - 1) > 0
                cells.append(f"{r:.3f} ({rp:.3f})")
            out(f"| {shift} mm | {ex[col]:.1f} ({ex[2]} patch{'es' if ex[2] > 1 else ''}; "
                f"paper CONTACT {ref[0]}) | " + " | ".join(cells) + f" | {agree}/4 |")
        out()
    (HERE / "seed001_tables.md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
