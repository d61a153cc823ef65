"""A short tour of the Python API: profiles, geometry, Hertz + FASTSIM, tables.

Run with ``python examples/api_tour.py``; it prints a few numbers and writes nothing.
"""

import math

import numpy as np

import railcontact as rc
from railcontact.geometry import Track, Wheelset, contact_table, equivalent_conicity, find_contact
from railcontact.normal import get_normal_model
from railcontact.profiles import rail_profile, s1002, wheel_measures
from railcontact.tangential import get_tangential_model

# 1. profiles (SI units)
wheel, rail = s1002(), rail_profile("60E1", inclination=math.atan(1 / 40))
m = wheel_measures(wheel)
print(f"S1002: flange height {m['flange_height'] * 1e3:.2f} mm, "
      f"thickness {m['flange_thickness'] * 1e3:.2f} mm, qR {m['qR'] * 1e3:.2f} mm")

# 2. geometry: wheelset 4 mm to the right, 75 kN per wheel
ws, track = Wheelset(wheel), Track(rail)
contact = find_contact(ws, track, lateral_shift=4e-3, vertical_force=75e3)
for p in contact.patches:
    print(f"{p.side:>5}: y_rail {p.y_rail * 1e3:7.2f} mm, angle {math.degrees(p.contact_angle):6.2f}"
          f" deg, r {p.rolling_radius * 1e3:7.2f} mm, creepage {np.round(p.creepage, 6)}")

# 3. Hertz + FASTSIM on the right patch, with a braking creepage
patch = contact.side_patches("right")[0]
material = rc.Material()
normal = get_normal_model("hertz").solve(patch, material, penetration=patch.approach)
tang = get_tangential_model("fastsim").solve(normal, patch, material, (-1e-3, 0.0, 0.0), 0.3,
                                            velocity=30.0)
print(f"Fn = {normal.normal_force / 1e3:.1f} kN, pmax = {normal.pmax / 1e6:.0f} MPa, "
      f"Fx = {tang.fx / 1e3:.2f} kN, stick {tang.stick_fraction:.0%}")

# 4. contact table and equivalent conicity
table = contact_table(ws, track, np.arange(-6e-3, 6.01e-3, 0.5e-3), vertical_force=75e3)
print(f"equivalent conicity (3 mm): {equivalent_conicity(table, 3e-3):.3f}")

# 5. a case file, solved as the CLI does
case = rc.case_from_dict({"wheel": {"profile": "S1002"}, "rail": {"profile": "60E1"},
                          "wheelset": {"lateral_shift": 0.002, "vertical_force": 75e3}})
print(rc.solve(case).to_json(indent=None)[:120], "...")

# 6. many patches at once: every strip model with FASTSIM on a lateral sweep, compiled
from railcontact.cases.batch import solve_patches

contacts = [find_contact(ws, track, lateral_shift=y, vertical_force=75e3)
            for y in np.linspace(0.0, 8e-3, 40)]
patches = [p for c in contacts for p in c.patches if p.approach > 0]
for name in ("hertz", "kik-piotrowski", "kpec", "stripes", "analyn"):
    res = solve_patches(patches, normal=name, tangential="fastsim", material=material)
    print(f"{name:>14}: {len(patches)} patches in {res.cpu_time * 1e3:5.1f} ms, "
          f"largest pmax {res.pmax.max() / 1e6:5.0f} MPa, largest |Fy| {abs(res.Fy).max() / 1e3:5.2f} kN")
