"""One scenario with several contact-model combinations (``railcontact wear-compare``).

For a closed-loop scenario (a vehicle on routes) this is the study of seed 001
(Tao et al., CM2015): the same closed loop with each local contact model, every
model over the step distances of the first, with a figure of the final wear depth
per model and a table of the worn area, maximum depth and CPU time per model.
"""

from __future__ import annotations

import csv
import time
from pathlib import Path

import numpy as np

from ..core.errors import InputError
from .plots import _wheel_panels
from .vehicle_scenario import VehicleWearScenario


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
    """Run ``scenario`` for each (normal, tangential) pair; returns {label: dataset}
    (and writes ``wear_comparison.png`` and ``.csv`` into ``out``).  Every model name
    is checked before the first pair runs."""
    from ..normal import normal_model_class
    from ..tangential import tangential_model_class
    for normal, tang in models:
        normal_model_class(normal)
        tangential_model_class(tang)
    if isinstance(scenario, VehicleWearScenario):
        return _compare_closed_loop(scenario, models, out, progress)
    results = {}
    scenarios = [scenario.with_models(normal, tang) for normal, tang in models]
    for (normal, tang), sc in zip(models, scenarios):
        label = f"{normal}+{tang}"
        sub = Path(out) / label if out else None
        if sub:
            sub.mkdir(parents=True, exist_ok=True)
        results[label] = sc.driver(sub, progress=progress).run(resume=False)
    if out:
        _write(results, Path(out))
    return results


def _write(results, out: Path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    bodies = _open_bodies(results)
    fig, axes = plt.subplots(len(bodies), 1, figsize=(9, 3.2 * len(bodies)), squeeze=False)
    rows = comparison_rows(results)
    for ax, b in zip(axes[:, 0], bodies):
        for label, ds in results.items():
            total = ds[f"wear_depth_{b}"].values.sum(axis=0)
            # normalised to the distance of the first run so that shapes compare
            ax.plot(ds[f"y_{b}"].values * 1e3, total / ds.attrs["total_distance_m"] * 1e9,
                    label=label)
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


def _compare_closed_loop(scenario, models, out, progress):
    """Each model pair through the closed loop of ``scenario``: the first pair sets
    the step distances (by its step control), the others run over the same."""
    results = {}
    distances = None
    scenarios = [scenario.with_models(normal, tang) for normal, tang in models]
    for (normal, tang), sc in zip(models, scenarios):
        sc.distances = distances
        label = f"{normal}+{tang}"
        sub = Path(out) / label if out else None
        if sub:
            sub.mkdir(parents=True, exist_ok=True)
        c0 = time.process_time()
        ds = sc.driver(sub, progress=progress).run(resume=False)
        ds.attrs["process_cpu_time_s"] = time.process_time() - c0
        if distances is None:
            distances = [float(d) for d in ds["distance"].values]
        results[label] = ds
    if out:
        _write_closed_loop(results, Path(out))
    return results


def _panels(ds):
    """(body, label, selection) of the distinct worn profiles of a closed-loop run."""
    out = []
    if ds.attrs["worn_body"] in ("wheel", "both"):
        out += [("wheel", label, {"wheelset": w, "side": s}) for label, w, s in _wheel_panels(ds)]
    if ds.attrs["worn_body"] in ("rail", "both"):
        out += [("rail", f"rail {s}, route {r}", {"route": r, "side": s})
                for r in ds["route"].values for s in ("left", "right")]
    return out


def _open_bodies(results) -> list:
    return [b for b in ("wheel_right", "wheel_left", "rail_right", "rail_left")
            if any(float(ds[f"wear_depth_{b}"].max()) > 0 for ds in results.values())]


def comparison_rows(results) -> list:
    """Per model and worn profile: distance, worn area, maximum depth and where, and
    for a closed loop the CPU times (whole run, post-processing, per solved patch)."""
    rows = []
    for label, ds in results.items():
        if "route" not in ds.dims:                  # operating conditions / history
            for b in _open_bodies(results):
                total = ds[f"wear_depth_{b}"].values.sum(axis=0)
                y = ds[f"y_{b}"].values
                rows.append({"models": label, "body": b,
                             "distance_km": ds.attrs["total_distance_m"] / 1e3,
                             "max_wear_mm": float(total.max()) * 1e3,
                             "y_max_mm": float(y[np.argmax(total)]) * 1e3,
                             "area_mm2": float(np.trapezoid(total, y)) * 1e6})
            continue
        post = float(ds["postprocess_time"].sum())
        solve = float(ds["solve_time"].sum())
        solved = float(ds["patches_solved"].sum())
        for body, name, sel in _panels(ds):
            total = ds[f"wear_depth_{body}"].sel(**sel).values.sum(axis=0)
            y = ds[f"y_{body}"].values
            rows.append({"models": label, "profile": name,
                         "distance_km": ds.attrs["total_distance_m"] / 1e3,
                         "worn_area_mm2": float(ds[f"removed_area_{body}"].sel(**sel).sum())
                         * 1e6,
                         "max_depth_mm": float(total.max()) * 1e3,
                         "y_max_mm": float(y[np.argmax(total)]) * 1e3,
                         "cpu_time_s": ds.attrs.get("process_cpu_time_s", ds.attrs["cpu_time_s"]),
                         "postprocess_cpu_s": post,
                         "solve_ms_per_patch": 1e3 * solve / solved if solved else float("nan"),
                         "patches_solved": int(solved),
                         "patches_reused": int(ds["patches_reused"].sum())})
    return rows


def format_rows(rows) -> str:
    """The comparison table as text (one line per model and profile)."""
    if not rows:
        return ""
    if "worn_area_mm2" not in rows[0]:
        return "\n".join(f"{r['models']:>24} {r['body']:>12}: {r['distance_km']:10.1f} km, max "
                         f"{r['max_wear_mm']:.4f} mm at {r['y_max_mm']:.1f} mm" for r in rows)
    head = (f"{'models':>24} {'profile':>14} {'km':>8} {'area mm2':>9} {'max mm':>8} "
            f"{'at y mm':>8} {'CPU s':>8} {'post s':>8} {'ms/patch':>9} {'solved':>7} "
            f"{'reused':>7}")
    lines = [head]
    for r in rows:
        lines.append(f"{r['models']:>24} {r['profile']:>14} {r['distance_km']:8.1f} "
                     f"{r['worn_area_mm2']:9.3f} {r['max_depth_mm']:8.4f} {r['y_max_mm']:8.1f} "
                     f"{r['cpu_time_s']:8.1f} {r['postprocess_cpu_s']:8.1f} "
                     f"{r['solve_ms_per_patch']:9.3f} {r['patches_solved']:7d} "
                     f"{r['patches_reused']:7d}")
    return "\n".join(lines)


def _write_closed_loop(results, out: Path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    first = next(iter(results.values()))
    panels = _panels(first)
    fig, axes = plt.subplots(len(panels), 1, figsize=(9, 3.4 * len(panels)), squeeze=False)
    for ax, (body, name, sel) in zip(axes[:, 0], panels):
        for label, ds in results.items():
            total = ds[f"wear_depth_{body}"].sel(**sel).values.sum(axis=0)
            ax.plot(ds[f"y_{body}"].values * 1e3, total * 1e3, label=label)
        ax.set_xlabel(f"y [mm] ({name})")
        ax.set_ylabel(f"wear depth after {first.attrs['total_distance_m'] / 1e3:.0f} km [mm]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("closed-loop wear per local contact model")
    fig.tight_layout()
    fig.savefig(out / "wear_comparison.png", dpi=110)
    plt.close(fig)
    rows = comparison_rows(results)
    with open(out / "wear_comparison.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    return rows
