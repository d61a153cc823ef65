"""Plots (matplotlib, non-interactive backend): profiles, contact positions, patches."""

from __future__ import annotations

from pathlib import Path

import numpy as np


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def plot_profile(profile, path, title=None):
    """Plot a wheel or rail profile in mm (z downwards drawn downwards)."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(8, 4))
    ax.plot(profile.y * 1e3, profile.z * 1e3, "-", lw=1.2)
    ax.invert_yaxis()
    ax.set_aspect("equal")
    ax.set_xlabel("y [mm] (field side positive)")
    ax.set_ylabel("z [mm] (down)")
    ax.set_title(title or f"{profile.kind} profile {profile.name}")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return Path(path)


def plot_contact_positions(table, wheel, rail, path):
    """Contact positions on wheel and rail profiles against lateral shift (right side)."""
    plt = _plt()
    fig, axes = plt.subplots(2, 2, figsize=(11, 7))
    shifts = table["lateral_shift"].values * 1e3
    r = table.sel(side="right")
    ax = axes[0, 0]
    ax.plot(wheel.y * 1e3, wheel.z * 1e3, "k-", lw=1)
    yw = r["y_wheel"].values
    ax.scatter(yw * 1e3, wheel.z_at(yw) * 1e3, c=shifts, cmap="viridis", s=18, zorder=3)
    ax.set_title("contact points on the right wheel")
    ax.set_xlabel("y_wheel [mm]")
    ax.set_ylabel("z [mm]")
    ax = axes[0, 1]
    ax.plot(rail.y * 1e3, rail.z * 1e3, "k-", lw=1)
    yr = r["y_rail"].values
    sc = ax.scatter(yr * 1e3, rail.z_at(yr) * 1e3, c=shifts, cmap="viridis", s=18, zorder=3)
    ax.invert_yaxis()
    ax.set_title("contact points on the right rail")
    ax.set_xlabel("y_rail [mm]")
    fig.colorbar(sc, ax=ax, label="lateral shift [mm]")
    ax = axes[1, 0]
    ax.plot(shifts, table["delta_r"].values * 1e3, "o-", ms=3)
    ax.set_xlabel("lateral shift [mm]")
    ax.set_ylabel("r_right - r_left [mm]")
    ax.set_title("rolling radius difference")
    ax = axes[1, 1]
    for side in ("left", "right"):
        ax.plot(shifts, np.degrees(table.sel(side=side)["contact_angle"].values), "o-", ms=3,
                label=side)
    ax.set_xlabel("lateral shift [mm]")
    ax.set_ylabel("contact angle [deg]")
    ax.legend()
    for a in axes.flat:
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return Path(path)


def plot_patches(results, path, title="contact patches"):
    """Pressure maps of patches: one panel per (shift, patch), tractions as arrows."""
    plt = _plt()
    n = len(results)
    cols = min(n, 5)
    rows = int(np.ceil(n / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(3 * cols, 3 * rows), squeeze=False)
    for ax, (label, pr) in zip(axes.flat, results):
        ns = pr.normal
        ext = [ns.y[0] * 1e3, ns.y[-1] * 1e3, ns.x[0] * 1e3, ns.x[-1] * 1e3]
        im = ax.imshow(ns.pressure / 1e6, origin="lower", extent=ext, aspect="equal",
                       cmap="magma")
        if pr.tangential is not None and pr.tangential.stick.any():
            ax.contour(ns.y * 1e3, ns.x * 1e3, pr.tangential.stick.astype(float), levels=[0.5],
                       colors="c", linewidths=0.8)
        ax.set_title(label, fontsize=8)
        ax.set_xlabel("y [mm]", fontsize=7)
        ax.set_ylabel("x [mm]", fontsize=7)
        fig.colorbar(im, ax=ax, shrink=0.7, label="p [MPa]")
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return Path(path)
