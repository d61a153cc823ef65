"""Why railcontact's gauge-corner patches carry less normal force than CONTACT's at
the same wheelset position (issue 34): CONTACT's planar undeformed distance takes
the wheel surface piecewise linear between profile samples.

railcontact's undeformed distance h(x, y) of a planar patch is the exact distance
between the rail's cylinder and the wheel's surface of revolution along the plane's
normal (:mod:`railcontact.geometry.gap`).  CONTACT's (module 1, planar contact,
``m_wr_undefdist``: the wheel profile resampled every DS of its arc length from the
wheel point at the contact reference, revolved into slices every DX, and the wheel's
normal coordinate interpolated linearly onto the grid points; the rail evaluated
exactly on its spline) takes the wheel surface as chords between samples DS apart.
On the concave flange root of a worn wheel (lateral radius of 10-20 mm) a chord lies
on the rail side of the arc by up to DS^2 / (8 R) (0.4 mm elements: about 1 um), so
that CONTACT's interpenetration is deeper between the samples; on the tread
(R of hundreds of mm) the chords coincide with the arc.

How much deeper depends on where the grid points fall between the wheel samples:
in steady rolling (T = 3) the grid runs through the contact reference, near the
samples (the offset: the wheel point at the reference's wheel coordinate lies
approach * tan(delta) off the contact, and the yaw shifts the samples by
psi * x across the patch); in transient cases (T = 1) the grid is based at the rail
profile's s_r = 0 and a fixed super-grid in x, so the samples can lie anywhere
between grid points, and the force of a gauge-corner patch changes by up to 5 %.

This script measures it on ``examples_trans/iestim_site_b.inp`` (the measured
site_b rail and a high-mileage worn wheel, wheelset height given, T = 3): per case
the gauge-corner patch's F_n, elements in contact and p_max from railcontact's exact
h, from the same h with the wheel taken piecewise linear between CONTACT's samples,
and CONTACT's (``.ref_out``); then case 18 with the grid shifted against the
samples (the spread of a T = 1 grid).

    python benchmarks/gauge_corner_sampling.py

Measured (2026-11-27): the exact h misses CONTACT's F_n by -0.7 to -1.3 % from
2.8 kN on (-2.3 % at 330 N) on the same elements in contact; with CONTACT's wheel
sampling within 0.06 % from 6 kN on (-0.13 % at 2.8 kN, -0.47 % at 330 N), the
elements in contact CONTACT's, p_max within 0.15 %; the grid offset spreads case
18's F_n over -0.05 to +3.8 %.  (.inp files take CONTACT's sampling since
2026-11-27, with CONTACT's gauge point and, in transient cases, its super-grid:
docs/contact_users.md, "The undeformed distance: CONTACT's planar rule"; this
script compares the two undeformed distances on railcontact's patches.)
"""

from __future__ import annotations

import dataclasses
import re
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from railcontact import solve  # noqa: E402
from railcontact.cases.case import case_from_dict  # noqa: E402
from railcontact.contact_inp import load_inp  # noqa: E402
from railcontact.geometry.gap import SampledWheelGap  # noqa: E402
from railcontact.normal.exact import ExactNormalModel  # noqa: E402

BANK = HERE.parent.parent / "shared" / "contact_testbank"
FILE = BANK / "examples_trans" / "iestim_site_b.inp"
_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


def reference(path: Path) -> dict:
    """Per case the patches' (y_tr [mm], F_n [N], NCON, p_max [MPa]) of a ``.ref_out``."""
    text = path.with_suffix(".ref_out").read_text()
    parts = re.split(r"\n Case +(\d+)\n", text)
    out = {}
    for num, body in zip(parts[1::2], parts[2::2]):
        ps = []
        for pb in body.split("----- DATA FOR CONTACT PATCH")[1:]:
            y = float(re.search(r"XCP\(TR\).*\n\s*" + r"\s+".join([f"({_NUM})"] * 2), pb)[2])
            fn = float(re.search(r"FN\s+FX\s+FS\s+MN.*\n\s*(" + _NUM + ")", pb)[1])
            pm = float(re.search(r"APPROACH\s+PMAX\s*\n\s*" + r"\s+".join([f"({_NUM})"] * 5),
                                 pb)[5])
            nc = int(re.search(r"NPOT\s+NCON.*\n\s*\d+\s+(\d+)", pb)[1])
            ps.append((y, fn, nc, pm))
        out[int(num)] = ps
    return out


def normal(geometry, material, element_size, gap=None):
    """F_n [N], elements in contact and p_max [MPa] at the patch's approach
    (``gap``: another undeformed distance than the patch's exact one)."""
    g = geometry if gap is None else dataclasses.replace(geometry, gap_function=gap)
    s = ExactNormalModel(wheel_sampling="exact").solve(
        g, material, penetration=geometry.approach, element_size=element_size)
    return s.normal_force, int(np.count_nonzero(s.pressure > 0)), float(s.pressure.max()) * 1e-6


class Shifted:
    """A gap evaluated on a grid moved laterally by ``dy`` [m] against the surfaces."""

    def __init__(self, gap, dy):
        self.gap, self.dy = gap, dy

    def __getattr__(self, name):
        return getattr(self.gap, name)

    def __call__(self, x, y):
        return self.gap(x, np.asarray(y, dtype=float) + self.dy)


def main():
    ref = reference(FILE)
    mapped = {m.number: m for m in load_inp(FILE)}
    print("iestim_site_b.inp, gauge-corner patch (|delta| 0.57 rad): F_n [N] (deviation from "
          "CONTACT), elements in contact, p_max [MPa]")
    print(f"{'case':>4} {'CONTACT':>22} {'exact h':>30} {'CONTACT wheel sampling':>30}")
    keep = None
    for case in range(14, 22):
        raw = mapped[case].raw
        raw["solver"]["normal_options"] = {"wheel_sampling": "exact"}
        case_obj = case_from_dict(raw)
        res = solve(case_obj)
        ds = float(mapped[case].raw["solver"]["element_size"][1])
        size = tuple(mapped[case].raw["solver"]["element_size"])
        for p in res.patches:
            g = p.geometry
            if abs(g.contact_angle) < 0.4 or abs(g.contact_angle) > 1.0:
                continue
            y = g.position[1] * 1e3
            _, fn, nc, pm = min(ref[case], key=lambda q: abs(q[0] - y))
            ex = normal(g, case_obj.material, size)
            sm = normal(g, case_obj.material, size,
                        SampledWheelGap(g.gap_function, g.y_wheel, ds))
            print(f"{case:4d} {fn:9.1f} {nc:4d} {pm:7.1f} "
                  f"{ex[0]:9.1f} ({100 * (ex[0] / fn - 1):+5.2f} %) {ex[1]:4d} {ex[2]:7.1f} "
                  f"{sm[0]:9.1f} ({100 * (sm[0] / fn - 1):+5.2f} %) {sm[1]:4d} {sm[2]:7.1f}")
            if case == 18:
                keep = (g, case_obj.material, size, ds, fn)
    g, mat, size, ds, fn = keep
    print("\ncase 18, the grid shifted laterally against the wheel samples (as a T = 1 grid "
          "based at s_r = 0 can be): F_n deviation from CONTACT's steady case")
    for f in np.arange(0.0, 1.0, 0.125):
        sm = normal(g, mat, size, Shifted(SampledWheelGap(g.gap_function, g.y_wheel, ds),
                                          f * ds))
        print(f"  offset {f:5.3f} DS: F_n {sm[0]:9.1f} ({100 * (sm[0] / fn - 1):+5.2f} %), "
              f"{sm[1]} elements")


if __name__ == "__main__":
    main()
