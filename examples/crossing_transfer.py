"""A wheel passing a crossing: the load moves from the wing rail to the nose.

An artificial common crossing (``railcontact.profiles.slices.artificial_crossing``:
a 60E1 wing rail diverging at 1:9, a nose rising at 1:60 from 6 mm below the
running level) is written as CONTACT slices files with a case file that names the
wing rail and the nose as two rails, each with its own placement; an S1002 wheel
under 80 kN is then solved at wheelset positions s through the transfer
(``railcontact.cases.crossing.sweep_along_track``): vertical force on each rail, where
along the track each contact lies (the nose's ahead of the axle), p_max and area.

Run:  python examples/crossing_transfer.py [OUTPUT_DIR]
Writes crossing.toml, the slices, crossing_sweep.nc and crossing_sweep.png.
"""

import sys
import tempfile
from pathlib import Path

import numpy as np

import railcontact as rc
from railcontact.cases.crossing import plot_track_sweep, sweep_along_track, transfer_range
from railcontact.core.files import write_netcdf
from railcontact.profiles.slices import artificial_crossing, write_slices

CASE = """title = "S1002 through an artificial 1:9 crossing, 80 kN"

[wheel]
profile = "S1002"
nominal_radius = 0.46

[[rails]]
name = "wing rail"
slices = "wing.slcs"
lateral_position = 0.75      # rail-profile origin at the wheel's tape circle [m]

[[rails]]
name = "nose"
slices = "nose.slcs"
lateral_position = 0.75

[wheelset]
side = "right"
position = 0.0               # s [m]; the sweep varies it
vertical_force = 80e3        # N
velocity = 30.0              # m/s

[solver]
normal = "exact"
tangential = "fastsim"
element_size = [0.5e-3, 0.5e-3]
"""


def main(out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    nose, wing = artificial_crossing()
    write_slices(nose, out / "nose.slcs")
    write_slices(wing, out / "wing.slcs")
    (out / "crossing.toml").write_text(CASE)
    case = rc.load_case(out / "crossing.toml")
    positions = np.arange(0.090, 0.1001, 0.002)
    ds = sweep_along_track(case, positions, progress=False)
    write_netcdf(ds, out / "crossing_sweep.nc")
    plot_track_sweep(ds, out / "crossing_sweep.png")
    print(f"{'s mm':>7} {'wing kN':>8} {'nose kN':>8} {'x wing mm':>10} {'x nose mm':>10} "
          f"{'pmax MPa':>9}")
    for i, s in enumerate(ds["s"].values):
        fz = ds["Fz"].isel(s=i).fillna(0.0).values / 1e3
        x = ds["x"].isel(s=i).values * 1e3
        pmax = np.nanmax(ds["pmax"].isel(s=i).values) / 1e6
        print(f"{s * 1e3:7.1f} {fz[0]:8.2f} {fz[1]:8.2f} {x[0]:10.2f} {x[1]:10.2f} {pmax:9.0f}")
    rng = transfer_range(ds, "wing rail", "nose")
    if rng is not None:
        print(f"load passes from the wing rail to the nose over s = {rng[0] * 1e3:.1f} to "
              f"{rng[1] * 1e3:.1f} mm; written to {out}")


if __name__ == "__main__":
    if len(sys.argv) > 1:
        main(Path(sys.argv[1]))
    else:
        with tempfile.TemporaryDirectory() as d:
            main(Path(d))
