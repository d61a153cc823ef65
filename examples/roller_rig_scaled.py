"""A scaled running gear on a roller rig, as the DLR rig of seed 002 (Heckmann et
al.: a 1:5 running gear on rollers of 0.18 m radius, 6 m/s, hunting at 0.5 Hz
with 8 mm lateral amplitude).

The wheel (S1002 scaled 1:5, 92 mm radius) runs on a roller carrying the 60E1
head scaled 1:5 and inclined 1:40, under 2.8 kN (70 kN scaled by 1/25: the same
contact stresses as full scale).  Over one hunting cycle the wheelset moves
y = y_max sin(t) and yaws psi = 2 pi y_max / L cos(t) (kinematic hunting, L =
V / f = 12 m): on the roller the contact leaves its apex, ahead of the axle or
behind it with the yaw ("the wheels leave the apexes of the rollers and slightly
run downhill") by R_r / (R_r + R_w) of the shift on a straight rail, and the
roller's curvature along the track shortens the patch.

Run:  python examples/roller_rig_scaled.py
"""

import math

import numpy as np

import railcontact as rc
from railcontact.cases.case import case_from_dict
from railcontact.geometry.track import Track
from railcontact.profiles.library import get_profile
from railcontact.profiles.profile import Profile

SCALE = 5.0
V = 6.0                        # m/s, the rollers' surface speed
R_ROLLER = 0.18                # m
R_WHEEL = 0.46 / SCALE
LOAD = 70e3 / SCALE ** 2       # N
Y_MAX = 0.008 / SCALE          # m: the paper's 8 mm amplitude at full scale (the scaled
                               # S1002 meets its flange about 1.6 mm out)
PSI_MAX = 2 * math.pi * Y_MAX / (V / 0.5)
#: the rails (rollers) placed by the full-scale gauge, scaled
RAIL_Y = Track(get_profile("60E1", "rail")).rail_offset("right") / SCALE


def scaled(name, kind, **kw):
    p = get_profile(name, kind, **kw)
    return Profile(p.y / SCALE, p.z / SCALE, kind=kind, name=f"{p.name} 1:{SCALE:g}")


def case(y, psi, roller=True):
    raw = {"title": "DLR-like 1:5 roller rig",
           "wheel": {"profile": scaled("S1002", "wheel"), "nominal_radius": R_WHEEL},
           "rail": {"profile": scaled("60E1", "rail", inclination=math.atan(1 / 40)),
                    "lateral_position": RAIL_Y},
           "wheelset": {"side": "right", "position": 0.0,   # on 3-D surfaces
                        "lateral_shift": y, "yaw": psi,
                        "vertical_force": LOAD, "velocity": V,
                        "flange_back_distance": 1.36 / SCALE,
                        "flange_back_position": -0.07 / SCALE},
           "solver": {"normal": "hertz", "tangential": "fastsim", "grid": [30, 30]}}
    if roller:
        raw["roller"] = {"radius": R_ROLLER}           # pure rolling at the wheel's speed
    return case_from_dict(raw)


def main():
    print(f"1:{SCALE:g} rig: wheel radius {R_WHEEL * 1e3:.0f} mm, roller {R_ROLLER * 1e3:.0f} mm, "
          f"{LOAD:.0f} N, yaw amplitude {PSI_MAX * 1e3:.2f} mrad")
    print(f"{'phase':>5} {'y mm':>6} {'yaw mrad':>8} | roller: {'x mm':>6} {'a mm':>5} "
          f"{'b mm':>5} {'pmax MPa':>8} {'xi':>9} {'eta':>9} | rail: {'x mm':>6} {'a mm':>5}")
    for t in np.linspace(0.0, 2 * math.pi, 9)[:-1]:
        y, psi = Y_MAX * math.sin(t), PSI_MAX * math.cos(t)
        (p,) = rc.solve(case(y, psi)).patches
        (q,) = rc.solve(case(y, psi, roller=False)).patches
        a, b = p.normal.semi_axes
        print(f"{math.degrees(t):5.0f} {y * 1e3:6.2f} {psi * 1e3:8.3f} | "
              f"{p.geometry.position[0] * 1e3:14.3f} {a * 1e3:5.2f} {b * 1e3:5.2f} "
              f"{p.normal.pmax / 1e6:8.0f} {p.creepage[0]:9.2e} {p.creepage[1]:9.2e} | "
              f"{q.geometry.position[0] * 1e3:12.3f} {q.normal.semi_axes[0] * 1e3:5.2f}")
    # the exact model on the centred wheel, against Hertz
    c = case(0.0, 0.0)
    raw = dict(c.raw, solver={"normal": "exact", "tangential": "exact",
                              "element_size": [0.05e-3, 0.05e-3]})
    (e,) = rc.solve(case_from_dict(raw)).patches
    (h,) = rc.solve(c).patches
    print(f"centred: Hertz p_max {h.normal.pmax / 1e6:.0f} MPa, area {h.normal.area * 1e6:.2f} mm2;"
          f" exact p_max {e.normal.pmax / 1e6:.0f} MPa, area {e.normal.area * 1e6:.2f} mm2, "
          f"F_x {e.tangential.fx:.1f} N")


if __name__ == "__main__":
    main()
