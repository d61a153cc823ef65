"""Plots of a wear run: wear depth per step and profile evolution."""

from __future__ import annotations

from pathlib import Path

import numpy as np


def plot_wear(ds, sim, out: Path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    out = Path(out)
    worn = [b for b in ("wheel_left", "wheel_right", "rail_left", "rail_right")
            if float(ds[f"wear_depth_{b}"].max()) > 0]
    fig, axes = plt.subplots(len(worn), 2, figsize=(11, 3.2 * len(worn)), squeeze=False)
    for row, b in zip(axes, worn):
        y = ds[f"y_{b}"].values * 1e3
        cum = np.cumsum(ds[f"wear_depth_{b}"].values, axis=0) * 1e3
        for k in range(cum.shape[0]):
            row[0].plot(y, cum[k], lw=1, label=f"after step {k + 1}" if k in (0, cum.shape[0] - 1)
                        else None)
        row[0].set_xlabel(f"y [mm] ({b})")
        row[0].set_ylabel("accumulated wear [mm]")
        row[0].legend(fontsize=7)
        row[1].plot(y, sim.initial[b].z * 1e3 if sim.initial[b].y.size == y.size else
                    sim.initial[b].z_at(ds[f"y_{b}"].values) * 1e3, "k-", lw=1, label="new")
        row[1].plot(y, ds[f"profile_z_{b}"].values[-1] * 1e3, "r-", lw=1, label="worn")
        row[1].invert_yaxis()
        row[1].set_xlabel("y [mm]")
        row[1].set_ylabel("z [mm]")
        row[1].legend(fontsize=7)
    fig.suptitle(f"wear: {ds.attrs['law']}, {ds.attrs['total_distance_m'] / 1e3:.0f} km")
    fig.tight_layout()
    fig.savefig(out / "wear.png", dpi=110)
    plt.close(fig)
