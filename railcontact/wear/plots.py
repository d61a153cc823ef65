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


def _wheel_panels(ds):
    """(label, wheelset, side) of the distinct wheel profiles of a closed-loop run."""
    mode = ds.attrs.get("wheels", "individual")
    if mode == "vehicle":
        return [("all wheels", 1, "right")]
    if mode == "side":
        return [(f"{s} wheels", 1, s) for s in ("left", "right")]
    return [(f"wheelset {int(w)}, {s}", int(w), s) for w in ds["wheelset"].values
            for s in ("left", "right")]


def plot_closed_loop(ds, out: Path):
    """Plots of a closed-loop run (:class:`railcontact.wear.closed_loop.ClosedLoopWear`):

    * ``wear.png``: profile evolution (accumulated wear depth and the profiles at
      every state) of each worn wheel profile and rail;
    * ``measures.png``: flange height, flange thickness, qR, equivalent conicity and
      per route the leading wheelset's mean lateral position, max Y/Q and Tγ against
      the distance run;
    * ``rcf.png``: rolling contact fatigue (:func:`plot_rcf`).
    """
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    out = Path(out)
    km = ds["cumulative_distance"].values / 1e3
    panels = []
    if ds.attrs.get("worn_body") in ("wheel", "both"):
        panels += [("wheel", label, {"wheelset": w, "side": s})
                   for label, w, s in _wheel_panels(ds)]
    if ds.attrs.get("worn_body") in ("rail", "both"):
        panels += [("rail", f"rail {s}, route {r}", {"route": r, "side": s})
                   for r in ds["route"].values for s in ("left", "right")]
    fig, axes = plt.subplots(len(panels), 2, figsize=(11, 3.2 * len(panels)), squeeze=False)
    cmap = plt.get_cmap("viridis")
    nstate = ds.sizes["state"]
    for row, (kind, label, sel) in zip(axes, panels):
        y = ds[f"y_{kind}"].values * 1e3
        depth = np.cumsum(ds[f"wear_depth_{kind}"].sel(**sel).values, axis=0) * 1e3
        z = ds[f"profile_z_{kind}"].sel(**sel).values * 1e3
        for k in range(depth.shape[0]):
            row[0].plot(y, depth[k], color=cmap((k + 1) / max(nstate - 1, 1)), lw=1,
                        label=f"{km[k + 1]:.0f} km")
        for k in range(nstate):
            row[1].plot(y, z[k] - z[0] if k else 0 * z[0], color=cmap(k / max(nstate - 1, 1)),
                        lw=1)
        row[0].set_xlabel(f"y [mm] ({label})")
        row[0].set_ylabel("accumulated wear [mm]")
        row[0].legend(fontsize=7, ncol=2)
        ax2 = row[1].twinx()
        ax2.plot(y, z[0], "k-", lw=0.8, alpha=0.5)
        ax2.invert_yaxis()
        ax2.set_ylabel("new profile z [mm]", fontsize=8)
        row[1].set_xlabel("y [mm]")
        row[1].set_ylabel("z - z_new [mm] (z down)")
    fig.suptitle(f"closed-loop wear: {ds.attrs['normal']} + {ds.attrs['tangential']}, "
                 f"{ds.attrs['law']}, {ds.attrs['total_distance_m'] / 1e3:.0f} km")
    fig.tight_layout()
    fig.savefig(out / "wear.png", dpi=110)
    plt.close(fig)

    fig, axes = plt.subplots(3, 3, figsize=(13, 9))
    ax = axes.ravel()
    for label, w, s in _wheel_panels(ds):
        for i, (key, name) in enumerate((("flange_height", "flange height Sh [mm]"),
                                         ("flange_thickness", "flange thickness Sd [mm]"),
                                         ("qR", "qR [mm]"))):
            ax[i].plot(km, ds[key].sel(wheelset=w, side=s).values * 1e3, "o-", ms=3,
                       label=label)
            ax[i].set_ylabel(name)
    routes = ds["route"].values
    for r in routes:
        ax[3].plot(km, ds["equivalent_conicity"].sel(route=r, wheelset=1).values, "o-", ms=3,
                   label=r)
    ax[3].set_ylabel("equivalent conicity (3 mm)")
    km_step = km[:-1][:ds.sizes["step"]]          # each step ran on the state before it
    for r in routes:
        sel = ds.sel(route=r, wheelset=1)
        ax[4].plot(km_step, sel["lateral_position"].values * 1e3, "o-", ms=3, label=r)
        ax[5].plot(km_step, sel["max_Y_over_Q"].max("side").values, "o-", ms=3, label=r)
        ax[6].plot(km_step, sel["Tgamma"].max("side").values, "o-", ms=3, label=r)
        ax[7].plot(km_step, ds["energy"].sel(route=r).values, "o-", ms=3, label=r)
    ax[4].set_ylabel("wheelset 1 mean lateral\nposition (curve) [mm]")
    ax[5].set_ylabel("wheelset 1 max |Y/Q|")
    ax[6].set_ylabel("wheelset 1 mean Tγ [N]\n(larger side)")
    ax[7].set_ylabel("frictional energy [J/m]")
    if "delta_r" in ds:
        sh = ds["lateral_shift"].values * 1e3
        for k in range(nstate):
            ax[8].plot(sh, ds["delta_r"].isel(state=k, route=0, wheelset=0).values * 1e3,
                       color=cmap(k / max(nstate - 1, 1)), lw=1, label=f"{km[k]:.0f} km")
        ax[8].set_xlabel("lateral shift [mm]")
        ax[8].set_ylabel(f"Δr [mm], route {routes[0]}")
    for a in ax[:8]:
        a.set_xlabel("distance [km]")
        a.grid(alpha=0.3)
    for a in ax:
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "measures.png", dpi=110)
    plt.close(fig)
    if "rcf_damage_wheel" in ds:
        plot_rcf(ds, out)


def plot_rcf(ds, out: Path):
    """``rcf.png`` of a closed-loop run: per route the largest surface fatigue index
    FI_surf (Ekberg) along the leading wheelset's left and right wheel profiles in
    the first and last step, and the accumulated WLRM damage and FI_surf exceedance
    along the wheel profiles after every step (wear removal included)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    out = Path(out)
    y = ds["y_wheel"].values * 1e3
    panels = [("rcf_damage_wheel", "accumulated WLRM damage")]
    if "rcf_surface_wheel" in ds:
        panels.append(("rcf_surface_wheel", "accumulated FI_surf exceedance"))
    fig, axes = plt.subplots(1, 2 + len(panels), figsize=(5 * (2 + len(panels)), 4))
    for ax, side in zip(axes[:2], ("left", "right")):
        for r in ds["route"].values:
            fi = ds["fi_surf_wheel"].sel(route=r, wheelset=1, side=side)
            line, = ax.plot(y, fi.isel(step=0).values, lw=1, label=f"{r}, step 1")
            ax.plot(y, fi.isel(step=-1).values, lw=1, ls="--", color=line.get_color(),
                    label=f"{r}, step {ds.sizes['step']}")
        ax.axhline(0.0, color="k", lw=0.6)
        ax.set_xlabel(f"y on the wheel [mm], wheelset 1 {side}")
        ax.set_ylabel("largest FI_surf (> 0: surface RCF)")
        ax.legend(fontsize=7)
    cmap = plt.get_cmap("viridis")
    n = ds.sizes["step"]
    for ax, (name, label) in zip(axes[2:], panels):
        for side, ls in (("left", "-"), ("right", "--")):
            d = ds[name].sel(wheelset=1, side=side).values
            for k in range(n):
                ax.plot(y, d[k], color=cmap((k + 1) / n), ls=ls, lw=1,
                        label=f"{side}, step {k + 1}" if k in (0, n - 1) else None)
        ax.set_xlabel("y on the wheel [mm], wheelset 1")
        ax.set_ylabel(label)
        ax.legend(fontsize=7)
    for a in axes:
        a.grid(alpha=0.3)
    fig.suptitle("rolling contact fatigue beside wear")
    fig.tight_layout()
    fig.savefig(out / "rcf.png", dpi=110)
    plt.close(fig)
