"""A wheel passing a crossing quasi-statically: a sweep along the track.

:func:`sweep_along_track` solves a case on rail surfaces
(:mod:`railcontact.cases.surfaces`) at a series of wheelset positions s, each
from the last (its vertical position and patch solutions as warm starts), and
gathers per rail the vertical force, the position of its contact along the track
and on its profile, p_max and the contact area: where the load passes from the
wing rail to the nose, both rails carry it over a stretch of s.
:func:`plot_track_sweep` draws them against s.

Name the rails of one slices file that holds several side by side (a crossing's
wing rail and nose) with ``[[rails]]`` entries on the same file, each with its
``lateral_range``.
"""

from __future__ import annotations

import dataclasses
import logging
from pathlib import Path

import numpy as np

from .case import Case
from ..core.checks import shown
from ..core.errors import ContactNotFoundError, InputError
from ..core.files import written_whole
from .surfaces import build_surface_case, solve_on_surfaces

log = logging.getLogger(__name__)

#: per rail: variable, units, long name
RAIL_VARS = (("Fz", "N", "vertical force on the rail"),
             ("Fn", "N", "normal force, sum over the rail's patches"),
             ("x", "m", "position along the track of the rail's largest patch, from the axle"),
             ("y_rail", "m", "lateral position of that patch on the rail profile"),
             ("pmax", "Pa", "largest pressure on the rail"),
             ("area", "m2", "contact area on the rail"),
             ("n_patches", "1", "number of patches on the rail"))


def sweep_along_track(case: Case, positions, normal: str | None = None,
                      tangential: str | None = None, progress: bool = True):
    """Solve ``case`` at the wheelset positions ``positions`` [m] along the track.

    Returns
    -------
    xarray.Dataset
        Over (``s``, ``rail``): the variables of :data:`RAIL_VARS` (NaN where a rail
        carries nothing); over ``s``: the wheel's vertical position
        ``vertical_position`` [m], ``converged`` and the ``total_Fz`` [N].  The
        attribute ``results`` is not kept; each case's :class:`SurfaceResult` is
        returned by :func:`solve_along_track`.
    """
    s, results = solve_along_track(case, positions, normal, tangential, progress)
    return to_dataset(s, results, case)


def solve_along_track(case: Case, positions, normal=None, tangential=None,
                      progress: bool = True):
    """The :class:`SurfaceResult` at each position (None where no contact was
    found), each case warm-started from the last."""
    from tqdm.auto import tqdm
    s = np.asarray(positions, dtype=float)
    if s.ndim != 1 or s.size < 1 or not np.all(np.isfinite(s)):
        raise InputError(f"positions = {shown(positions)}: expected positions along the track [m]")
    setup = build_surface_case(case)
    out, prev = [], None
    for si in tqdm(s, desc="along the track", disable=not progress):
        st = dataclasses.replace(setup, pose=dataclasses.replace(setup.pose, s=float(si)))
        try:
            res = solve_on_surfaces(case, normal, tangential, setup=st, warm_start=prev)
        except ContactNotFoundError as exc:
            log.warning("s = %.4f m: %s", si, exc)
            out.append(None)
            prev = None
            continue
        out.append(res)
        prev = res
    return s, out


def to_dataset(s, results, case: Case | None = None):
    """The sweep's results as an :class:`xarray.Dataset` (see
    :func:`sweep_along_track`)."""
    import xarray as xr
    names = []
    for r in results:
        for p in (r.patches if r is not None else ()):
            if p.geometry.rail not in names:
                names.append(p.geometry.rail)
    data = {k: np.full((s.size, len(names)), np.nan) for k, _, _ in RAIL_VARS}
    data["n_patches"] = np.zeros((s.size, len(names)), dtype=int)
    z = np.full(s.size, np.nan)
    conv = np.zeros(s.size, dtype=bool)
    for i, r in enumerate(results):
        if r is None:
            continue
        z[i] = r.pose.vertical
        conv[i] = r.converged
        forces = r.rail_forces()
        for j, name in enumerate(names):
            ps = [p for p in r.patches if p.geometry.rail == name]
            if not ps:
                continue
            big = max(ps, key=lambda p: p.normal.normal_force)
            data["Fz"][i, j] = forces[name]
            data["Fn"][i, j] = sum(p.normal.normal_force for p in ps)
            data["x"][i, j] = big.geometry.position[0]
            data["y_rail"][i, j] = big.geometry.y_rail
            data["pmax"][i, j] = max(p.normal.pmax for p in ps)
            data["area"][i, j] = sum(p.normal.area for p in ps)
            data["n_patches"][i, j] = len(ps)
    units = {k: (u, n) for k, u, n in RAIL_VARS}
    ds = xr.Dataset(
        {k: (("s", "rail"), v, {"units": units[k][0], "long_name": units[k][1]})
         for k, v in data.items()},
        coords={"s": ("s", s, {"units": "m", "long_name": "wheelset position along the track"}),
                "rail": ("rail", names)})
    ds["vertical_position"] = ("s", z, {"units": "m", "long_name":
                                        "vertical position of the wheelset (down)"})
    ds["converged"] = ("s", conv)
    ds["total_Fz"] = ds["Fz"].fillna(0.0).sum("rail").assign_attrs(
        units="N", long_name="vertical force on all rails")
    ds.attrs["title"] = case.title if case is not None else ""
    return ds


def transfer_range(ds, source: str, target: str, share: float = 0.02):
    """(s_start, s_end) [m]: the stretch over which ``target`` takes the load from
    ``source``, from where it first carries ``share`` of the total to where the
    source last does; None where no such stretch lies in the sweep."""
    fz = ds["Fz"].fillna(0.0)
    tot = ds["total_Fz"].where(ds["total_Fz"] > 0)
    a = (fz.sel(rail=target) / tot).values
    b = (fz.sel(rail=source) / tot).values
    s = ds["s"].values
    on_t = np.flatnonzero(a > share)
    on_s = np.flatnonzero(b > share)
    if not on_t.size or not on_s.size:
        return None
    return float(s[on_t[0]]), float(s[on_s[-1]])


def plot_track_sweep(ds, path=None):
    """Vertical force, position along the track, p_max and contact area of each
    rail against the wheelset position (one figure, four panels); written to
    ``path`` (PNG, PDF, ...) when given.  Returns the figure."""
    import matplotlib
    if path is not None:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(4, 1, sharex=True, figsize=(7, 9))
    s = ds["s"].values * 1e3
    panels = (("Fz", 1e-3, "vertical force [kN]"), ("x", 1e3, "contact x from the axle [mm]"),
              ("pmax", 1e-6, "p_max [MPa]"), ("area", 1e6, "area [mm$^2$]"))
    for a, (var, f, label) in zip(ax, panels):
        for name in ds["rail"].values:
            a.plot(s, ds[var].sel(rail=name).values * f, ".-", label=str(name))
        a.set_ylabel(label)
        a.grid(alpha=0.3)
    ax[0].plot(s, ds["total_Fz"].values * 1e-3, "k:", label="total")
    ax[0].legend(loc="best", fontsize="small")
    ax[-1].set_xlabel("wheelset position s [mm]")
    title = ds.attrs.get("title", "")
    fig.suptitle(title or "wheel passing along the track")
    fig.tight_layout()
    if path is not None:
        path = Path(path)
        with written_whole(path) as tmp:
            fig.savefig(tmp, dpi=120, format=path.suffix.lstrip(".") or None)
    return fig
