"""Post-processing of a dynamics run with a local contact model: the wear of every
wheel and rail along the run.

The dynamics (:func:`railcontact.dynamics.simulate_vehicle`) gives per sample,
wheelset, side and patch slot the normal force N, the creepages (ξ, η, φ) and the
wheelset's shift relative to the rails; the contact table the run used holds the
patches' geometry (:attr:`WheelRailTable.geometry`, the geometry layer's patches at
the table's shifts).  Each loaded patch of a sample is solved again with the chosen
local contact model (any registered normal x tangential pair, ``exact`` + ``exact``
included), without waste:

* **force-controlled:** the normal problem is solved for the normal force the
  dynamics balanced (``normal_force=N``), on the patch of the table's shift nearest
  to the sample's; no vertical-force iteration (the dynamics already met the wheel
  load with this N, :mod:`railcontact.dynamics.vehicle`);
* **warm starts along the time history:** models that accept them start from the
  previous sample's solution of the same wheel and patch slot (exact solvers); the
  exact normal solver keeps that sample's grid (and its influence coefficients)
  while the potential contact area still fits it (``reuse_grid``);
* **samples at a stride:** every ``stride``-th sample of the run (the closed loop
  takes one per ``wear.sample_distance`` metres of track; its convergence is
  measured in ``benchmarks/run_all.py``);
* **repeated states reused:** a patch whose table shift, normal force and creepages
  equal an earlier one's within ``reuse_tolerance`` (relative on N; on ξ, η of
  μN/(G c²) and on φ of μN/(G c³), c = √(ab), the creepage scale at which the creep
  force saturates) takes that patch's wear (steady curving repeats its states).

The wear law gives each patch's wear depth per passage on its strips
(:func:`~railcontact.wear.mapping.strip_depth`), mapped onto the wheel's and the
rail's arc length (:func:`~railcontact.wear.mapping.profile_depth`).  Samples are
equally spaced in distance, so the means over the samples are per metre of track:

* wheel: depth per metre run = mean of (depth per revolution / (2π r_rolling));
* rail: depth per vehicle passage = mean over the samples (the rail's cross-sections
  along the route) of the depths of all wheelsets.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..core.materials import Material
from ..normal import get_normal_model
from ..tangential import get_tangential_model
from .mapping import profile_depth, strip_depth
from .rcf import (RcfParameters, covered_strips, patch_measures, profile_window,
                  subsurface_fatigue_index)


@dataclass
class PostProcessStats:
    """What the post-processing of one run did.

    Attributes
    ----------
    samples : int        samples post-processed
    patches : int        loaded patches in them
    solved : int         patches solved with the local model
    reused : int         patches that took a repeated state's wear
    skipped : int        patches entering between two table shifts (a slot loaded by the
                         interpolated table with no geometry at either shift)
    solve_time : float   CPU time [s] of the normal and tangential solves
    cpu_time : float     CPU time [s] of the whole post-processing
    not_converged : int  solves whose status is not converged
    warnings : dict      warning text -> count
    rcf_time : float     CPU time [s] of the RCF damage measures (included in cpu_time)
    """

    samples: int = 0
    patches: int = 0
    solved: int = 0
    reused: int = 0
    skipped: int = 0
    solve_time: float = 0.0
    cpu_time: float = 0.0
    not_converged: int = 0
    warnings: dict = field(default_factory=dict)
    rcf_time: float = 0.0

    @property
    def time_per_patch(self) -> float:
        """Solve time per solved patch [s]."""
        return self.solve_time / self.solved if self.solved else math.nan


def _covered(window, damage):
    """(slice of the positions a patch covers, their mask within it, the damage on
    them): the RCF measures of a patch placed on a profile grid, from its coverage
    there (:func:`~railcontact.wear.rcf.profile_window` of 1 on its strips)."""
    sl, c = window
    return sl, c > 0.5, damage * c


@dataclass
class _Strips:
    """What the wear mapping needs of a normal solution: its strips' lateral
    coordinates [m] and width [m]."""

    y: np.ndarray
    dy: float


class PatchPostProcessor:
    """Solve the patches of dynamics runs with one local contact model and a wear law.

    Parameters
    ----------
    normal, tangential : str
        Registered model names (``railcontact.normal``, ``railcontact.tangential``).
    law : wear law object (:func:`railcontact.wear.get_wear_law`)
    material : Material
    grid, element_size : the normal models' grid (``[solver]``)
    normal_options, tangential_options : dict
    reuse_tolerance : float
        Width of the bins of repeated states (0: every patch is solved).
    warm : bool
        Warm starts along the time history (for models that accept them).
    rcf : RcfParameters, optional
        Parameters of the rolling contact fatigue measures computed beside the wear
        (:mod:`railcontact.wear.rcf`; defaults when omitted).
    """

    def __init__(self, normal: str, tangential: str, law, material: Material, grid=None,
                 element_size=None, normal_options=None, tangential_options=None,
                 reuse_tolerance: float = 1e-3, warm: bool = True, rcf=None):
        self.nmodel = get_normal_model(normal, **(normal_options or {}))
        self.tmodel = get_tangential_model(tangential, **(tangential_options or {}))
        self.law, self.material = law, material
        self.kw = {"grid": grid, "element_size": element_size}
        self.tol = float(reuse_tolerance)
        self.nwarm = warm and "warm-start" in self.nmodel.capabilities
        self.regrid = warm and getattr(self.nmodel, "reuses_grids", False)
        self.twarm = warm and "warm-start" in self.tmodel.capabilities
        self.rcf = rcf if rcf is not None else RcfParameters()

    def _key(self, w, ti, j, k, N, creep, a, b, mu):
        """Bin of a patch state (None: no reuse)."""
        if not self.tol > 0:
            return None
        G = self.material.shear_modulus
        c2 = max(a * b, 1e-12)
        fs = mu * N / (G * c2)                      # creepage scale of saturation
        scales = (fs, fs, fs / math.sqrt(c2))
        q = tuple(int(round(c / (self.tol * s))) for c, s in zip(creep, scales))
        return (w, ti, j, k, int(round(math.log(N) / self.tol))) + q

    def run(self, ds, tables, wheels, rails, wheel_grids, rail_grids, friction: float,
            stride: int = 1) -> dict:
        """Wear of one dynamics run.

        Parameters
        ----------
        ds : xarray.Dataset
            From :func:`railcontact.dynamics.simulate_vehicle`.
        tables : list of WheelRailTable
            The run's contact table of each wheelset, built with ``keep_geometry``.
        wheels : list of (Profile, Profile)
            Each wheelset's (left, right) wheel profile (those of its table).
        rails : (Profile, Profile)
            The (left, right) rail profiles.
        wheel_grids, rail_grids : arc-length grids [m] of the same shapes.
        friction : float
            Friction coefficient of the run.
        stride : int
            Post-process every ``stride``-th sample of the run.

        Returns
        -------
        dict with ``wheel`` (list per wheelset of (left, right) depth per metre run
        [m/m] on the wheel grids), ``rail`` ((left, right) depth per vehicle passage
        [m] on the rail grids), ``energy`` (frictional energy per metre run [J/m]),
        ``records`` (per post-processed sample, wheelset, side and slot: the local
        model's F_n, F_x, F_y, area, p_max and frictional power, and the RCF
        measures FI_surf, T gamma, WLRM damage and, with ``rcf.subsurface``, FI_sub),
        ``rcf_wheel`` / ``rcf_rail`` (WLRM damage per metre run / per vehicle
        passage on the grids, as the depths), ``fi_surf_wheel`` / ``fi_surf_rail``
        (the largest FI_surf at each grid position, NaN where no patch came),
        ``fi_sub_wheel`` / ``fi_sub_rail`` (likewise FI_sub [Pa], with
        ``rcf.subsurface``; NaN otherwise),
        ``stats`` (:class:`PostProcessStats`).
        """
        t0 = time.thread_time()
        st = PostProcessStats()
        nt = ds.sizes["time"]
        idx = np.arange(0, nt, max(int(stride), 1))
        V = float(ds.attrs["velocity_m_s"])
        N = ds["patch_normal_force"].values[idx]
        creep = np.stack([ds[f"creepage_{c}"].values[idx] for c in ("longitudinal", "lateral",
                                                                    "spin")], axis=-1)
        sa, sb = ds["semi_axis_a"].values[idx], ds["semi_axis_b"].values[idx]
        yrel = ds["relative_shift"].values[idx]
        nw = yrel.shape[1]
        shift = tables[0].shift
        h = shift[1] - shift[0]
        near = np.clip(np.rint((yrel - shift[0]) / h).astype(int), 0, shift.size - 1)
        # the neighbouring table point on the sample's side: the slot's geometry where
        # the nearest point has none (a patch entering between two table points)
        other = np.clip(np.where(yrel - shift[0] >= near * h, near + 1, near - 1), 0,
                        shift.size - 1)
        wheel = [[np.zeros_like(wheel_grids[w][j]) for j in range(2)] for w in range(nw)]
        rail = [np.zeros_like(rail_grids[j]) for j in range(2)]
        rec = {k: np.full(N.shape, np.nan) for k in ("Fn", "Fx", "Fy", "area", "pmax",
                                                      "frictional_power")}
        rcf_names = ("fi_surf", "tgamma", "rcf_damage") + (("fi_sub",) if self.rcf.subsurface
                                                          else ())
        rec.update({k: np.full(N.shape, np.nan) for k in rcf_names})
        dmg_w = [[np.zeros_like(wheel_grids[w][j]) for j in range(2)] for w in range(nw)]
        dmg_r = [np.zeros_like(rail_grids[j]) for j in range(2)]
        fi_w = [[np.full(wheel_grids[w][j].shape, -np.inf) for j in range(2)] for w in range(nw)]
        fi_r = [np.full(rail_grids[j].shape, -np.inf) for j in range(2)]
        sub_w = [[np.full(wheel_grids[w][j].shape, -np.inf) for j in range(2)] for w in range(nw)]
        sub_r = [np.full(rail_grids[j].shape, -np.inf) for j in range(2)]
        rcf_mapped: dict = {}
        energy = 0.0
        cache: dict = {}
        mapped: dict = {}                   # key -> (wheel, rail) depth on the grids
        last: dict = {}
        for i in range(idx.size):
            for w in range(nw):
                geo_tab = tables[w].geometry
                for j in range(2):
                    for k in range(2):
                        n = float(N[i, w, j, k])
                        if not n > 0:
                            continue
                        st.patches += 1
                        ti = int(near[i, w])
                        geom = geo_tab[ti][j][k]
                        if geom is None:
                            ti = int(other[i, w])
                            geom = geo_tab[ti][j][k]
                        if geom is None:            # entering between table points
                            st.skipped += 1
                            continue
                        cr = (float(creep[i, w, j, k, 0]), float(creep[i, w, j, k, 1]),
                              float(creep[i, w, j, k, 2]))
                        key = self._key(w, ti, j, k, n, cr, float(sa[i, w, j, k]),
                                        float(sb[i, w, j, k]), friction)
                        hit = cache.get(key) if key is not None else None
                        if hit is None:
                            hit, ns, ts = self._solve(geom, n, cr, friction, V,
                                                      last.get((w, j, k)), ti, st)
                            last[(w, j, k)] = (ti, ns, ts)
                            if key is not None:
                                cache[key] = hit
                        else:
                            st.reused += 1
                        strips, depth_y, values, rcfv = hit
                        for name, v in zip(rec, values + rcfv[:3] + rcfv[4:]):
                            rec[name][i, w, j, k] = v
                        energy += values[5] / V
                        c0 = time.thread_time()
                        on = rcf_mapped.get(key) if key is not None else None
                        if on is None:              # coverage and damage on the profiles
                            r_w = 2 * math.pi * geom.rolling_radius
                            on = (_covered(profile_window(geom, strips.y, rcfv[3], wheels[w][j],
                                                          "wheel", wheel_grids[w][j]),
                                           rcfv[2] / r_w),
                                  _covered(profile_window(geom, strips.y, rcfv[3], rails[j],
                                                          "rail", rail_grids[j]), rcfv[2]))
                            if key is not None:
                                rcf_mapped[key] = on
                        for (sl, mask, d), dmg, fi, sub in (
                                (on[0], dmg_w[w][j], fi_w[w][j], sub_w[w][j]),
                                (on[1], dmg_r[j], fi_r[j], sub_r[j])):
                            dmg[sl] += d
                            part = fi[sl]
                            part[mask] = np.maximum(part[mask], rcfv[0])
                            if self.rcf.subsurface:
                                part = sub[sl]
                                part[mask] = np.maximum(part[mask], rcfv[4])
                        st.rcf_time += time.thread_time() - c0
                        if not depth_y.any():
                            continue
                        depths = mapped.get(key) if key is not None else None
                        if depths is None:          # the same key maps onto the same profiles
                            depths = (profile_depth(geom, strips, depth_y, wheels[w][j],
                                                    "wheel", wheel_grids[w][j])
                                      / (2 * math.pi * geom.rolling_radius),
                                      profile_depth(geom, strips, depth_y, rails[j], "rail",
                                                    rail_grids[j]))
                            if key is not None:
                                mapped[key] = depths
                        wheel[w][j] += depths[0]
                        rail[j] += depths[1]
        n_s = max(idx.size, 1)
        st.samples = int(idx.size)
        st.cpu_time = time.thread_time() - t0
        def envelope(v):
            return np.where(np.isfinite(v), v, np.nan)
        return {"wheel": [[d / n_s for d in pair] for pair in wheel],
                "rail": [d / n_s for d in rail], "energy": energy / n_s,
                "rcf_wheel": [[d / n_s for d in pair] for pair in dmg_w],
                "rcf_rail": [d / n_s for d in dmg_r],
                "fi_surf_wheel": [[envelope(v) for v in pair] for pair in fi_w],
                "fi_surf_rail": [envelope(v) for v in fi_r],
                "fi_sub_wheel": [[envelope(v) for v in pair] for pair in sub_w],
                "fi_sub_rail": [envelope(v) for v in sub_r],
                "records": rec, "time": ds["time"].values[idx], "stats": st}

    def _solve(self, geom, n, creep, friction, V, previous, ti, st):
        """Normal (force-controlled) and tangential solution of one patch and its wear
        per passage on the strips; ``previous`` = (table index, normal, tangential)
        of the same wheel's slot at the previous sample (warm starts).  Returns the
        cache entry (strips, depth per passage on them, the record values) and the
        solutions."""
        nkw = dict(self.kw)
        tkw = {}
        if previous is not None:
            pti, pns, pts = previous
            if self.nwarm:
                nkw["warm_start"] = pns
                if self.regrid and pti == ti:
                    nkw["reuse_grid"] = pns
            if self.twarm:
                tkw["warm_start"] = pts
        c0 = time.thread_time()
        ns = self.nmodel.solve(geom, self.material, normal_force=n, **nkw)
        ts = self.tmodel.solve(ns, geom, self.material, creep, friction, V, **tkw)
        st.solve_time += time.thread_time() - c0
        st.solved += 1
        for status in (ns.status, ts.status):
            if not status.converged:
                st.not_converged += 1
            for wtext in status.warnings:
                st.warnings[wtext] = st.warnings.get(wtext, 0) + 1
        depth_y = strip_depth(self.law.rate(ns, ts, V), ns)
        values = (ns.normal_force, ts.fx, ts.fy, ns.area, ns.pmax, ts.frictional_power)
        c0 = time.thread_time()
        fi, tg, dmg = patch_measures(ns, ts, V, self.rcf, values[5])
        fi_sub = (subsurface_fatigue_index(ns, ts, self.material, self.rcf)["fi_sub"]
                  if self.rcf.subsurface else math.nan)
        rcfv = (fi, tg, dmg, covered_strips(ns), fi_sub)
        st.rcf_time += time.thread_time() - c0
        return (_Strips(ns.y, ns.dy), depth_y, values, rcfv), ns, ts
