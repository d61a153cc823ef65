"""The main job on built-in data (``make demo``): a lateral-shift sweep of S1002 on
60E1 with 1:40 inclination, Hertz + FASTSIM, written as NetCDF and plots."""

from __future__ import annotations

import logging
import math
from pathlib import Path

import numpy as np
from tqdm.auto import tqdm

from .core.files import write_netcdf
from .geometry import Track, Wheelset, contact_table, equivalent_conicity, find_contact
from .core.materials import Material
from .normal import get_normal_model
from .core.plotting import plot_contact_positions, plot_patches
from .profiles import rail_profile, s1002
from .cases.results import PatchResult
from .tangential import get_tangential_model
from .inputs import wear_scenario_from_dict
from .wear import WearSimulation
from .wear.plots import plot_wear

log = logging.getLogger(__name__)


def run_demo(out: Path, load: float = 75e3, velocity: float = 30.0, friction: float = 0.3):
    """Run the demo and write ``contact_table.nc``, ``contact_positions.png``,
    ``patches.png`` into ``out``; returns the dataset."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    wheel, rail = s1002(), rail_profile("60E1", math.atan(1 / 40))
    ws, tr = Wheelset(wheel), Track(rail)
    mat = Material()
    shifts = np.round(np.arange(0.0, 10.0001e-3, 0.5e-3), 6)
    normal, tang = get_normal_model("hertz"), get_tangential_model("fastsim")
    rows, shown = [], []
    for y in tqdm(shifts, desc="Hertz+FASTSIM sweep", unit="case"):
        c = find_contact(ws, tr, float(y), 0.0, vertical_force=load, material=mat,
                         velocity=velocity)
        for g in c.side_patches("right"):
            ns = normal.solve(g, mat, penetration=g.approach)
            ts = tang.solve(ns, g, mat, g.creepage, friction, g.velocity)
            rows.append((y, g, ns, ts))
            if abs(y * 1e3 - round(y * 1e3)) < 1e-9 and int(round(y * 1e3)) % 2 == 0:
                shown.append((f"dy={y * 1e3:.0f} mm, y_r={g.y_rail * 1e3:.1f} mm",
                              PatchResult(g, ns, ts, g.creepage)))
    table = contact_table(ws, tr, np.concatenate((-shifts[:0:-1], shifts)),
                          vertical_force=load, material=mat, progress=True)
    import xarray as xr
    n = len(rows)
    patch = xr.Dataset(
        {"patch_shift": ("patch", [r[0] for r in rows], {"units": "m"}),
         "Fn": ("patch", [r[2].normal_force for r in rows], {"units": "N"}),
         "Fx": ("patch", [r[3].fx for r in rows], {"units": "N"}),
         "Fy": ("patch", [r[3].fy for r in rows], {"units": "N"}),
         "Mz": ("patch", [r[3].mz for r in rows], {"units": "N m"}),
         "area": ("patch", [r[2].area for r in rows], {"units": "m2"}),
         "pmax": ("patch", [r[2].pmax for r in rows], {"units": "Pa"}),
         "patch_y_rail": ("patch", [r[1].y_rail for r in rows], {"units": "m"}),
         "patch_contact_angle": ("patch", [r[1].contact_angle for r in rows], {"units": "rad"}),
         "creepage_longitudinal": ("patch", [r[1].creepage[0] for r in rows], {"units": "1"}),
         "creepage_spin": ("patch", [r[1].creepage[2] for r in rows], {"units": "m-1"})},
        coords={"patch": np.arange(n)})
    ds = xr.merge([table, patch])
    amp = 3e-3
    ds.attrs.update(title="S1002 on 60E1 1:40, right wheel, Hertz + FASTSIM",
                    normal_model="hertz", tangential_model="fastsim", load_N=load,
                    velocity_m_s=velocity, friction=friction,
                    equivalent_conicity_3mm=equivalent_conicity(table, amp))
    write_netcdf(ds, out / "contact_table.nc")
    plot_contact_positions(table, wheel, rail, out / "contact_positions.png")
    plot_patches(shown, out / "patches.png", "S1002 / 60E1 1:40, right wheel: pressure "
                 "(stick area outlined)")
    print(f"equivalent conicity at 3 mm amplitude: {ds.attrs['equivalent_conicity_3mm']:.4f}")
    # a short wear run on the built-in profiles (examples/wear_demo.toml settings)
    wear_raw = {"friction": {"coefficient": friction}, "wheel": {"profile": "S1002"},
                "rail": {"profile": "60E1"},
                "wheelset": {"vertical_force": load, "velocity": velocity},
                "solver": {"normal": "hertz", "tangential": "fastsim", "grid": [30, 30]},
                "wear": {"law": "frictional-power", "parameters": {"k": 1e-13}, "steps": 3,
                         "max_depth_per_step": 1e-4, "smoothing": 2e-3},
                "condition": [{"lateral_shift": 0.0, "yaw": 0.002, "weight": 2.0},
                              {"lateral_shift": 0.004, "yaw": 0.004},
                              {"lateral_shift": -0.004, "yaw": -0.004}]}
    wear_dir = out / "wear"
    wear_dir.mkdir(exist_ok=True)
    sim = WearSimulation(wear_scenario_from_dict(wear_raw), wear_dir)
    wds = sim.run(resume=False)
    plot_wear(wds, sim, wear_dir)
    print(f"wear: {wds.sizes['step']} steps, {wds.attrs['total_distance_m'] / 1e3:.0f} km, "
          f"wrote {wear_dir / 'wear.nc'} and {wear_dir / 'wear.png'}")
    print(f"wrote {out / 'contact_table.nc'}, {out / 'contact_positions.png'}, "
          f"{out / 'patches.png'}")
    return ds
