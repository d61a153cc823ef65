"""One scenario with several contact-model combinations (``railcontact wear-compare``)."""

from __future__ import annotations

import copy
import csv
from pathlib import Path

import numpy as np

from ..errors import InputError
from .simulation import WearSimulation


def parse_models(spec: str):
    """``"hertz+fastsim,kpec+fastsim"`` -> [("hertz", "fastsim"), ("kpec", "fastsim")]."""
    out = []
    for item in spec.split(","):
        parts = [p.strip() for p in item.split("+")]
        if len(parts) != 2 or not all(parts):
            raise InputError(f"--models {spec!r}: expected NORMAL+TANGENTIAL pairs, e.g. "
                             "hertz+fastsim,kpec+fastsim")
        out.append(tuple(parts))
    return out


def compare_wear(scenario, models, out=None, progress=True):
    """Run ``scenario`` for each (normal, tangential) pair; returns {label: dataset}."""
    results = {}
    for normal, tang in models:
        sc = copy.deepcopy(scenario)
        sc.base.setdefault("solver", {})
        sc.base["solver"] = {**sc.base["solver"], "normal": normal, "tangential": tang}
        label = f"{normal}+{tang}"
        sub = Path(out) / label if out else None
        if sub:
            sub.mkdir(parents=True, exist_ok=True)
        results[label] = WearSimulation(sc, sub, progress=progress).run(resume=False)
    if out:
        _write(results, Path(out))
    return results


def _write(results, out: Path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    bodies = [b for b in ("wheel_right", "wheel_left", "rail_right", "rail_left")
              if any(float(ds[f"wear_depth_{b}"].max()) > 0 for ds in results.values())]
    fig, axes = plt.subplots(len(bodies), 1, figsize=(9, 3.2 * len(bodies)), squeeze=False)
    rows = []
    for ax, b in zip(axes[:, 0], bodies):
        for label, ds in results.items():
            total = ds[f"wear_depth_{b}"].values.sum(axis=0)
            y = ds[f"y_{b}"].values
            # normalised to the distance of the first run so that shapes compare
            ax.plot(y * 1e3, total / ds.attrs["total_distance_m"] * 1e9, label=label)
            rows.append({"models": label, "body": b,
                         "distance_km": ds.attrs["total_distance_m"] / 1e3,
                         "max_wear_mm": float(total.max()) * 1e3,
                         "y_max_mm": float(y[np.argmax(total)]) * 1e3,
                         "area_mm2": float(np.trapezoid(total, y)) * 1e6})
        ax.set_xlabel(f"y [mm] ({b})")
        ax.set_ylabel("wear depth per distance [mm per 1000 km]")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "wear_comparison.png", dpi=110)
    plt.close(fig)
    with open(out / "wear_comparison.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    return rows
