"""The tasks of one closed-loop wear step, as Dask runs them: a contact table of a
wheel pair on a rail pair (:func:`build_table`), one route's dynamics run with its
measures and post-processing (:func:`run_route`), and where a step's contact skips
positions (:func:`away_from_contact_jumps`).  The loop that drives them is
:mod:`railcontact.wear.closed_loop`.
"""

from __future__ import annotations

import time

import numpy as np

from ..dynamics.simulation import Integration, simulate_vehicle
from ..dynamics.wheel_rail import F_SHARE, F_YWHEEL, WheelRailTable
from ..geometry.track import Track, Wheelset
from .laws import get_wear_law
from .postprocess import PatchPostProcessor


def build_table(wheel_left, wheel_right, rail_left, rail_right, rail_offsets, settings):
    """A contact table of one wheel pair on one rail pair, keeping the patches'
    geometry (a Dask task)."""
    t0 = time.thread_time()
    ws = Wheelset(wheel_right, wheel_left, nominal_radius=settings["nominal_radius"],
                  flange_back_distance=settings["flange_back_distance"],
                  flange_back_position=settings["flange_back_position"])
    tr = Track(rail_right, rail_left, gauge=settings["gauge"],
               gauge_height=settings["gauge_height"], rail_offsets=rail_offsets)
    table = WheelRailTable.build(ws, tr, settings["reference_load"], settings["material"],
                                 settings["table_range"], settings["table_step"],
                                 keep_geometry=True)
    table.cpu_time = time.thread_time() - t0
    return table


def away_from_contact_jumps(tables, y, gap: float = 1e-3, margin: float = 2e-3):
    """Where a wheel profile lies away from the contact jumps of some tables.

    The contact skips the parts of the wheel between neighbouring contact positions
    more than ``gap`` apart over the tables' lateral shifts (both sides, every patch
    slot); the edges of a wear band lie there and move with the step size.

    Parameters
    ----------
    tables : sequence of WheelRailTable
        E.g. the tables of the new and of the final profiles.
    y : ndarray
        Lateral positions on the wheel profile [m].
    gap, margin : float
        Smallest skipped width, and the width added on either side of it [m].

    Returns
    -------
    ndarray of bool
        True at the positions ``y`` farther than ``margin`` from every skipped part.
    """
    pos = np.sort(np.concatenate([t.data[..., F_YWHEEL][t.data[..., F_SHARE] > 0]
                                  for t in tables]))
    keep = np.ones(np.shape(y), dtype=bool)
    for a, b in zip(pos[:-1][np.diff(pos) > gap], pos[1:][np.diff(pos) > gap]):
        keep &= (y < a - margin) | (y > b + margin)
    return keep


def run_route(item, model, tables, dyn, material, wheels, rails, wheel_grids, rail_grids,
              post) -> dict:
    """One route of a wear step (a Dask task): the dynamics run on the tables, its
    measures and the post-processing with the local model (``post``:
    :class:`PatchPostProcessor` settings)."""
    t0 = time.thread_time()
    ds = simulate_vehicle(model, item.route, tables, item.speed, item.duration,
                          dyn["tangential"], item.friction, material,
                          dyn["initial_lateral_shift"], dyn["tangential_options"],
                          dyn["fastsim_grid"],
                          Integration(dyn["integrator"], dyn["sample_rate"], dyn["rtol"],
                                      step=dyn["step"]))
    t_dyn = time.thread_time() - t0
    pp = PatchPostProcessor(post["normal"], post["tangential"],
                            get_wear_law(post["law"], **post["parameters"]), material,
                            post["grid"], post["element_size"], post["normal_options"],
                            post["tangential_options"], post["reuse_tolerance"])
    stride = max(1, int(round(post["sample_distance"] * dyn["sample_rate"] / item.speed)))
    res = pp.run(ds, tables, wheels, rails, wheel_grids, rail_grids, item.friction, stride)
    res["measures"] = route_measures(ds, item, model)
    res["records"] = _records(ds, res, stride)
    res["dynamics_time"] = t_dyn
    res["stride"] = stride
    res["warnings"] = ds.attrs.get("warnings", "")
    res["outside_table"] = int(ds.attrs.get("outside_table", 0))
    return res


def route_measures(ds, item, model) -> dict:
    """Per wheelset (and side, patch) over a run: the mean lateral displacement and
    contact positions on the route's full-curvature section (the whole run on
    tangent track), the largest |Y/Q| and the mean Tγ."""
    wi = [w[0] for w in model.wheelsets]
    x = np.array([model.bodies[b].x for b in wi])
    s = ds["distance"].values[:, None] - (x[0] - x)[None, :]         # each wheelset's s
    kappa = np.abs(item.route.at(s)[0])
    kmax = float(np.max(np.abs(item.route.curvature)))
    steady = kappa >= 0.99 * kmax if kmax > 0 else np.ones_like(kappa, dtype=bool)
    nsteady = steady.sum(axis=0)

    def mean_over(v):              # v (time, wheelset, ...): mean over each's steady part
        m = steady.reshape(steady.shape + (1,) * (v.ndim - 2))
        vv = np.where(m & np.isfinite(v), v, 0.0)
        cnt = (m & np.isfinite(v)).sum(axis=0)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(cnt > 0, vv.sum(axis=0) / np.maximum(cnt, 1), np.nan)

    yq = np.abs(ds["Y_over_Q"].values)
    return {"lateral_position": mean_over(ds["lateral_displacement"].values),
            "yaw": mean_over(ds["yaw"].values),
            "max_Y_over_Q": np.where(np.isfinite(yq), yq, 0.0).max(axis=0),
            "Tgamma": ds["Tgamma"].values.mean(axis=0),
            "contact_y_wheel": mean_over(ds["y_wheel"].values),
            "contact_y_rail": mean_over(ds["y_rail"].values),
            "steady_samples": nsteady.astype(float)}


def _records(ds, res, stride):
    """The post-processed samples of a run: the dynamics' inputs per patch and the
    local model's results (an xarray Dataset)."""
    sub = ds.isel(time=slice(0, None, stride))
    keep = ["relative_shift", "lateral_displacement", "yaw", "patch_normal_force",
            "creepage_longitudinal", "creepage_lateral", "creepage_spin", "contact_angle",
            "y_rail", "y_wheel", "semi_axis_a", "semi_axis_b", "patch_Fx", "patch_Fy",
            "distance", "curvature"]
    out = sub[keep]
    units = {"Fn": "N", "Fx": "N", "Fy": "N", "area": "m2", "pmax": "Pa",
             "frictional_power": "W"}
    for name, arr in res["records"].items():
        out[f"local_{name}"] = (("time", "wheelset", "side", "patch"), arr,
                                {"units": units[name],
                                 "long_name": f"{name} of the local contact model"})
    out.attrs = {k: v for k, v in ds.attrs.items() if isinstance(v, (int, float, str))}
    return out
