"""The load on a crossing nose: vertical dynamics of a wheel passing a crossing.

The artificial 1:9 crossing of ``crossing_transfer.py`` (the wheel runs down the
diverging wing rail and is lifted by the nose rising at 1:60: its vertical path
kinks by 23 mrad at the transfer) is tabulated once with the 3-D contact search
(``railcontact.dynamics.crossing.contact_table``), and a wheel under 80 kN with
900 kg unsprung mass runs through it at 10, 20 and 30 m/s on a track of 240 kg,
70 MN/m and 60 kN s/m (``simulate_crossing``): the contact force on the wing rail
and on the nose against s, its peak ('P1', the impact) and Jenkins's 'P2'.

Run:  python examples/crossing_dynamics.py [OUTPUT.png]
"""

import sys

import numpy as np

from railcontact.cases.case import case_from_dict
from railcontact.cases.surfaces import build_surface_case
from railcontact.dynamics.crossing import (CrossingTrack, contact_table, jenkins_p2,
                                           simulate_crossing)
from railcontact.profiles.slices import artificial_crossing

Q = 80e3


def main(png=None):
    nose, wing = artificial_crossing()
    rails = [{"name": name, "lateral_position": 0.75,
              "slices": [{"s": float(s), "profile": p} for s, p in zip(sl.s, sl.profiles)]}
             for name, sl in (("wing rail", wing), ("nose", nose))]
    case = case_from_dict({"wheel": {"profile": "S1002", "nominal_radius": 0.46},
                           "rails": rails,
                           "wheelset": {"side": "right", "vertical_force": Q, "position": 0.0},
                           "solver": {"normal": "hertz", "tangential": "none"}})
    table = contact_table(build_surface_case(case), np.arange(0.0, 0.2001, 0.002),
                          case.material)
    k = int(np.argmax(table.z_touch))
    slope = lambda a, b: np.polyfit(table.s[a:b], table.z_touch[a:b], 1)[0]   # noqa: E731
    dip = slope(k - 15, k - 2) - slope(k + 2, k + 15)
    print(f"quasi-static path: down {table.z_touch[k] - table.z_touch[0]:.2e} m on the wing "
          f"rail, transfer to the nose at s = {table.s[k] * 1e3:.0f} mm, kink {dip * 1e3:.1f} mrad")
    runs = {}
    for V in (10.0, 20.0, 30.0):
        ds = simulate_crossing(table, V, Q, start=0.02, end=0.2)
        runs[V] = ds
        p2 = jenkins_p2(Q, V, dip, 900.0, CrossingTrack())
        print(f"V = {V:4.0f} m/s: peak {ds.attrs['peak_force_N'] / 1e3:6.1f} kN "
              f"({ds.attrs['peak_load_factor']:.2f} Q) at s = "
              f"{ds.attrs['peak_position_m'] * 1e3:5.1f} mm; Jenkins's P2 {p2 / 1e3:6.1f} kN")
    if png:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(2, 1, sharex=True, figsize=(7, 6))
        for V, ds in runs.items():
            s = ds["s"].values * 1e3
            for name, style in (("wing rail", "--"), ("nose", "-")):
                ax[0].plot(s, ds["force"].sel(rail=name).values / 1e3, style,
                           label=f"{name}, {V:.0f} m/s")
        ax[0].axhline(Q / 1e3, color="k", lw=0.5)
        ax[0].set_ylabel("vertical contact force [kN]")
        ax[0].legend(fontsize="x-small", ncol=2)
        ax[1].plot(table.s * 1e3, table.z_touch * 1e3, "k")
        ax[1].set_ylabel("quasi-static wheel path [mm, down]")
        ax[1].set_xlabel("wheelset position s [mm]")
        fig.tight_layout()
        fig.savefig(png, dpi=120)
        print(f"wrote {png}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
