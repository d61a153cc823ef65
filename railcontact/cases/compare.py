"""Run several normal models on one case and compare them (``railcontact compare``)."""

from __future__ import annotations

import csv
import logging
import time
from pathlib import Path


from .case import Case
from .solve import solve
from ..core.errors import RailContactError
from ..core.files import written_whole
from ..normal import normal_models

log = logging.getLogger(__name__)

DEFAULT_MODELS = ("hertz", "kik-piotrowski", "kpec", "stripes", "analyn", "exact")
COLUMNS = ("model", "side", "patches", "area_mm2", "pmax_MPa", "penetration_mm", "Fn_kN",
           "Fx_kN", "Fy_kN", "Mz_Nm", "cpu_ms")


#: the (normal, tangential) pairs solved once in this process: their compiled
#: kernels are loaded, so that ``cpu_ms`` excludes Numba's compilation
_COMPILED: set = set()


def compare(case: Case, models=DEFAULT_MODELS, tangential: str | None = None):
    """Solve ``case`` with every normal model in ``models``.

    Returns (rows, results): one row per model and side (units in the column names),
    and the :class:`~railcontact.cases.results.SolveResult` of each model.
    ``cpu_ms`` is the time of one solve with the model's kernels compiled: the first
    solve of a model in a process (compiling or loading them) is not timed.
    """
    unknown = [m for m in models if m not in normal_models()]
    if unknown:
        raise RailContactError(f"compare: unknown normal model(s) {unknown}; expected "
                               f"{normal_models()}")
    rows, results = [], {}
    for m in models:
        key = (m, tangential or case.tangential)
        if key not in _COMPILED:              # compile the model's kernels untimed
            solve(case, normal=m, tangential=tangential)
            _COMPILED.add(key)
        t0 = time.perf_counter()
        res = solve(case, normal=m, tangential=tangential)
        dt = time.perf_counter() - t0
        results[m] = res
        sides = sorted({str(p.geometry.side) for p in res.patches})
        for side in sides:
            ps = [p for p in res.patches if str(p.geometry.side) == side]
            rows.append({
                "model": m, "side": side, "patches": len(ps),
                "area_mm2": sum(p.normal.area for p in ps) * 1e6,
                "pmax_MPa": max(p.normal.pmax for p in ps) / 1e6,
                "penetration_mm": max(p.normal.penetration for p in ps) * 1e3,
                "Fn_kN": sum(p.normal.normal_force for p in ps) / 1e3,
                "Fx_kN": sum(p.tangential.fx for p in ps if p.tangential) / 1e3,
                "Fy_kN": sum(p.tangential.fy for p in ps if p.tangential) / 1e3,
                "Mz_Nm": sum(p.tangential.mz for p in ps if p.tangential),
                "cpu_ms": dt * 1e3})
    return rows, results


def format_table(rows) -> str:
    head = " ".join(f"{c:>14}" for c in COLUMNS)
    lines = [head]
    for r in rows:
        lines.append(" ".join(f"{r[c]:>14}" if isinstance(r[c], str) else
                              (f"{r[c]:>14d}" if isinstance(r[c], int) else f"{r[c]:>14.4g}")
                              for c in COLUMNS))
    return "\n".join(lines)


def write_outputs(rows, results, out: Path, side: str | None = None):
    """Write ``comparison.csv``, ``outlines.png`` and ``lateral_pressure.png``."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    with written_whole(out / "comparison.csv") as tmp, open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        w.writerows(rows)
    fig1, ax1 = plt.subplots(figsize=(7, 6))
    fig2, ax2 = plt.subplots(figsize=(8, 4))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, (m, res) in enumerate(results.items()):
        c = colours[k % len(colours)]
        ps = [p for p in res.patches if side is None or p.geometry.side == side]
        if not ps:
            continue
        p = max(ps, key=lambda q: q.normal.normal_force)
        ns = p.normal
        if ns.contact.any():
            ax1.contour(ns.y * 1e3, ns.x * 1e3, ns.contact.astype(float), levels=[0.5],
                        colors=[c])
            ax1.plot([], [], color=c, label=m)
        ax2.plot(ns.y * 1e3, ns.pressure.max(axis=0) / 1e6, color=c, label=m)
    ax1.set_xlabel("y [mm] (lateral)")
    ax1.set_ylabel("x [mm] (rolling)")
    ax1.set_aspect("equal")
    ax1.legend()
    ax1.set_title("contact area outlines")
    ax2.set_xlabel("y [mm] (lateral)")
    ax2.set_ylabel("max pressure along x [MPa]")
    ax2.legend()
    ax2.set_title("pressure along the lateral axis")
    for fig, name in ((fig1, "outlines.png"), (fig2, "lateral_pressure.png")):
        fig.tight_layout()
        fig.savefig(out / name, dpi=120)
        plt.close(fig)
    return out
