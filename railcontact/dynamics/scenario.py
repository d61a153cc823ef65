"""``railcontact simulate``: scenario files for the dynamics layer (single wheelset)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..case import case_from_dict, read_toml
from ..errors import CaseFileError
from .wheelset import WheelsetModel, critical_speed, simulate

_VEHICLE = {"model", "mass", "yaw_inertia", "k_y", "k_psi", "wheel_load"}
_SIM = {"velocity", "duration", "initial_lateral_shift", "initial_yaw", "sample_rate",
        "table_range", "table_step"}


def write_history(ds, path, wheel_load: float):
    """Write a run as a time history in the format of ``wear.history``
    (see docs/wear.md): time, lateral_shift, yaw, wheel loads, velocity."""
    path = Path(path)
    v = float(ds.attrs["velocity_m_s"])
    rows = ["time,lateral_shift,yaw,vertical_force_left,vertical_force_right,velocity"]
    for t, y, psi in zip(ds["time"].values, ds["lateral_displacement"].values,
                         ds["yaw"].values):
        rows.append(f"{t:.6g},{y:.9g},{psi:.9g},{wheel_load:.6g},{wheel_load:.6g},{v:.6g}")
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text("\n".join(rows) + "\n")
    tmp.replace(path)
    return path


def run_scenario(path, out=None):
    """Run a dynamics scenario; returns the dataset (written to ``out/simulation.nc``)."""
    path = Path(path)
    raw = read_toml(path, "dynamics scenario")
    veh = raw.pop("vehicle", {})
    sim = raw.pop("simulation", {})
    for sec, allowed, name in ((veh, _VEHICLE, "vehicle"), (sim, _SIM, "simulation")):
        bad = set(sec) - allowed
        if bad:
            raise CaseFileError(f"unknown key(s) {name}.{sorted(bad)}; expected {sorted(allowed)}")
    if veh.get("model", "wheelset") != "wheelset":
        raise CaseFileError(f"vehicle.model = {veh.get('model')!r}: only 'wheelset' is available")

    def num(sec, name, key, default, lo, hi):
        v = sec.get(key, default)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not lo <= v <= hi:
            raise CaseFileError(f"{name}.{key} = {v!r}: expected a value in [{lo:g}, {hi:g}]")
        return float(v)

    load = num(veh, "vehicle", "wheel_load", 75e3, 1.0, 1e7)
    raw.setdefault("wheelset", {})["vertical_force"] = load
    case = case_from_dict(raw, path.parent)
    from ..geometry import contact_table
    from ..solve import build_wheelset_track
    ws, tr = build_wheelset_track(case)
    rng = num(sim, "simulation", "table_range", 0.008, 1e-3, 0.02)
    step = num(sim, "simulation", "table_step", 2.5e-4, 1e-5, 1e-3)
    table = contact_table(ws, tr, np.arange(-rng, rng + 0.5 * step, step), vertical_force=load,
                          material=case.material, progress=True)
    model = WheelsetModel.from_table(
        table, case.material,
        mass=num(veh, "vehicle", "mass", 1813.0, 1.0, 1e6),
        yaw_inertia=num(veh, "vehicle", "yaw_inertia", 1120.0, 1e-3, 1e6),
        k_y=num(veh, "vehicle", "k_y", 0.0, 0.0, 1e10),
        k_psi=num(veh, "vehicle", "k_psi", 0.0, 0.0, 1e10))
    v = num(sim, "simulation", "velocity", 30.0, 0.1, 200.0)
    ds = simulate(model, v, num(sim, "simulation", "duration", 5.0, 1e-3, 1e5),
                  y0=num(sim, "simulation", "initial_lateral_shift", 3e-3, -0.02, 0.02),
                  psi0=num(sim, "simulation", "initial_yaw", 0.0, -0.1, 0.1),
                  sample_rate=num(sim, "simulation", "sample_rate", 200.0, 1.0, 1e5))
    try:
        ds.attrs["critical_speed_m_s"] = critical_speed(model)
    except Exception:                                   # not a bounded crossing
        ds.attrs["critical_speed_m_s"] = math.nan
    ds.attrs.update(title=str(raw.get("title", "")), f11_N=model.f11, f22_N=model.f22)
    if out is not None:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        tmp = out / "simulation.nc.tmp"
        ds.to_netcdf(tmp, engine="h5netcdf")
        tmp.replace(out / "simulation.nc")
        write_history(ds, out / "history.csv", load)
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, axes = plt.subplots(2, 1, figsize=(9, 5), sharex=True)
        axes[0].plot(ds["distance"], ds["lateral_displacement"] * 1e3)
        axes[0].set_ylabel("y [mm]")
        axes[1].plot(ds["distance"], ds["yaw"] * 1e3)
        axes[1].set_ylabel("yaw [mrad]")
        axes[1].set_xlabel("distance [m]")
        fig.suptitle(f"single wheelset at {v:g} m/s (linear critical speed "
                     f"{ds.attrs['critical_speed_m_s']:.1f} m/s)")
        fig.tight_layout()
        fig.savefig(out / "simulation.png", dpi=110)
        plt.close(fig)
    return ds
