"""Seed 003 (Wiest et al., Wear 265, 2008): the crossing nose elastic-plastic, and
repeated passes of a rolling load (shakedown or ratchetting).

1. The crossing-nose case (``examples/crossing_nose_elastoplastic.toml``: 111.5 kN,
   Mn13 of yield stress 360 MPa) solved by the semi-analytical elastic-plastic
   model (:mod:`railcontact.subsurface.elastoplastic`) on several grids and
   hardening laws, against the paper's Table 2 (elastic-plastic FE: 128 mm2,
   1085 MPa, 0.1710 mm; elastic FE 70 mm2, 2561 MPa, 0.1431 mm) and the pressure
   cap (``examples/crossing_nose_plastic.toml``).
2. A circular Hertzian contact rolled (frictionless) over the volume grid N times
   at p0 / Y between first yield (1.61) and beyond the shakedown limit of a
   perfectly plastic half-space (2.70 = 4.68 k with k = Y / sqrt 3; Ponter, Hearle
   & Johnson, J. Mech. Phys. Solids 33, 1985; Johnson 1985, ch. 9): the increment
   of the equivalent plastic strain per pass.

Run alone (``python benchmarks/seed003_plastic.py``, writes
``benchmarks/seed003_plastic.md``) or from ``benchmarks/run_all.py``.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
EXAMPLES = HERE.parent / "examples"
#: Table 2 of the paper: area [mm2], p_max [MPa], penetration [mm]
FE_PLASTIC = (128.0, 1085.0, 0.1710)
FE_ELASTIC = (70.0, 2561.0, 0.1431)

lines: list = []


def out(s=""):
    print(s, flush=True)
    lines.append(s)


def _row(label, area, pmax, pen, extra=""):
    a, p, d = FE_PLASTIC
    out(f"| {label} | {area * 1e6:.1f} ({area * 1e6 / a - 1:+.0%}) | {pmax / 1e6:.0f} "
        f"({pmax / 1e6 / p - 1:+.0%}) | {pen * 1e3:.4f} ({pen * 1e3 / d - 1:+.0%}) | {extra} |")


def crossing_nose():
    import railcontact as rc
    from railcontact.core.materials import Material
    from railcontact.subsurface.elastoplastic import (MN13, ElasticPlasticOptions, Hardening,
                                                      solve_elastic_plastic)
    out("## Seed 003: the crossing nose, 111.5 kN, Mn13 (yield 360 MPa)\n")
    out("Against the elastic-plastic FE of the paper's Table 2 "
        f"({FE_PLASTIC[0]:.0f} mm2, {FE_PLASTIC[1]:.0f} MPa, {FE_PLASTIC[2]:.4f} mm; "
        "relative differences in brackets).  Mn13's hardening is railcontact's estimate "
        f"(MN13: Y = {MN13.yield_stress / 1e6:.0f} MPa, linear H = {MN13.modulus / 1e9:.1f} GPa): "
        "no published Mn13 hardening law could be read (docs/subsurface.md, \"Mn13\").\n")
    out("| model | area [mm2] | p_max [MPa] | penetration [mm] | notes |")
    out("|---|---|---|---|---|")
    case = rc.load_case(EXAMPLES / "crossing_nose_plastic.toml")
    t0 = time.perf_counter()
    cap = rc.solve(case).patches[0].normal
    _row("pressure cap 3 Y (exact normal)", cap.area, cap.pmax, cap.penetration,
         f"{time.perf_counter() - t0:.1f} s")
    case = rc.load_case(EXAMPLES / "crossing_nose_elastoplastic.toml")
    t0 = time.perf_counter()
    patch = rc.solve(case).patches[0]
    el, ep = patch.normal, patch.elastic_plastic
    _row("elastic (exact normal, the case's grid)", el.area, el.pmax, el.penetration,
         f"elastic FE {FE_ELASTIC[0]:.0f} mm2, {FE_ELASTIC[1]:.0f} MPa, {FE_ELASTIC[2]} mm")
    _row("elastic-plastic, the example (32 x 32 x 16, Mn13)", ep.normal.area, ep.normal.pmax,
         ep.normal.penetration,
         f"{time.perf_counter() - t0:.1f} s; alpha_max {ep.equivalent_plastic_strain.max():.3f}, "
         f"zone {ep.plastic_zone_depth * 1e3:.1f} mm deep, dent "
         f"{ep.residual_displacement.max() * 1e3:.3f} mm")
    geom = patch.geometry
    mat = case.material
    variants = [
        ("perfectly plastic (H = 0)", mat, ElasticPlasticOptions(hardening=Hardening(360e6))),
        ("Mn13, grid 32 x 32 x 32", mat, ElasticPlasticOptions(layers=32)),
        ("Mn13, volume 4.5 radii deep", mat, ElasticPlasticOptions(depth=4.5, layers=24)),
        ("Mn13, grid 48 x 48 x 16", mat, ElasticPlasticOptions(grid=(48, 48))),
        ("Mn13, E = 190 GPa (Mn13) / 210 GPa (wheel)",
         Material(young_modulus=1.9e11, poisson_ratio=0.3, wheel_young_modulus=2.1e11,
                  wheel_poisson_ratio=0.3), ElasticPlasticOptions()),
        ("Mn13, 8 load steps", mat, ElasticPlasticOptions(load_steps=8)),
    ]
    for label, m, opt in variants:
        t0 = time.perf_counter()
        r = solve_elastic_plastic(geom, m, 111.5e3, opt)
        _row(label, r.normal.area, r.normal.pmax, r.normal.penetration,
             f"{time.perf_counter() - t0:.1f} s; alpha_max "
             f"{r.equivalent_plastic_strain.max():.3f}, zone "
             f"{r.plastic_zone_depth * 1e3:.1f} mm"
             + ("" if r.status.converged else "; NOT converged"))
    el_same = solve_elastic_plastic(geom, mat, 111.5e3,
                                    ElasticPlasticOptions(hardening=Hardening(1e11)))
    _row("elastic limit on the elastic-plastic grid", el_same.normal.area, el_same.normal.pmax,
         el_same.normal.penetration, "yield stress 1e11 Pa")
    del MN13


def rolling_passes(passes=6):
    from railcontact.core.hertz_theory import hertz_ellipse
    from railcontact.core.materials import Material
    from railcontact.subsurface.elastoplastic import ElasticPlasticContact, Hardening
    out("\n## Repeated rolling passes: shakedown or ratchetting\n")
    mat = Material(young_modulus=2e11, poisson_ratio=0.3)
    A = B = 5.0
    F = 1e4
    hz = hertz_ellipse(A, B, mat.contact_modulus, force=F)
    a = hz.a
    out(f"A circular Hertzian contact (a = {a * 1e3:.2f} mm, p0 = {hz.p0 / 1e6:.0f} MPa, "
        "frictionless) rolled along x over a volume grid of 32 x 16 x 8 cells (8 a x 3 a x "
        f"1.2 a), the load moved by a/4 from -2.5 a to 2.5 a and removed, {passes} times; "
        "per pass the largest and the mean (over the cells that yielded in pass 1) "
        "increment of the equivalent plastic strain alpha, and the mean there of the "
        "pass's net plastic strain (its von Mises equivalent): net = alpha increment is "
        "ratchetting, net << alpha increment closed cycles (alternating plasticity).  "
        "The yield stress sets p0 / Y; perfectly plastic (H = 0) and hardening "
        "(H = 2.4 GPa, Mn13's modulus).\n")
    x = (np.arange(32) - 15.5) * (a / 4)
    y = (np.arange(16) - 7.5) * (3 * a / 16)
    shifts = np.arange(-10, 11) * (a / 4)
    out("| p0 / Y | H [GPa] | alpha increment per pass, max (mean) | last / first "
        "(mean) | net / alpha increment, last pass | time [s] |")
    out("|---|---|---|---|---|---|")
    for ratio in (2.0, 2.5, 3.5):
        for H in (0.0, 2.4e9):
            c = ElasticPlasticContact(x, y, lambda X, Y: A * X * X + B * Y * Y, mat,
                                      Hardening(hz.p0 / ratio, H), depth=1.2 * a, nz=8)
            t0 = time.perf_counter()
            c.run_passes(F, passes, shifts=shifts, steps=2)
            inc, mean = c.passes["plastic_increment"], c.passes["mean_increment"]
            net = c.passes["net_increment"]
            seq = ", ".join(f"{v:.2e} ({m:.1e})" for v, m in zip(inc, mean))
            last = mean[-1] / mean[0] if mean[0] > 0 else float("nan")
            ratch = net[-1] / mean[-1] if mean[-1] > 0 else float("nan")
            out(f"| {ratio:.1f} | {H / 1e9:.1f} | {seq} | {last:.4f} | {ratch:.2f} | "
                f"{time.perf_counter() - t0:.0f} |")


def main(parts=("crossing", "passes")):
    out(f"# Seed 003: elastic-plastic contact ({time.strftime('%Y-%m-%d')})\n")
    if "crossing" in parts:
        crossing_nose()
    if "passes" in parts:
        rolling_passes()
    (HERE / "seed003_plastic.md").write_text("\n".join(lines) + "\n")
    return lines


if __name__ == "__main__":
    import sys
    main(tuple(sys.argv[1:]) or ("crossing", "passes"))
