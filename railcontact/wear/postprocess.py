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

from ..core.errors import InputError
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


@dataclass
class _Strips:
    """What the wear mapping needs of a normal solution: its strips' lateral
    coordinates [m] and width [m]."""

    y: np.ndarray
    dy: float


@dataclass
class _Solved:
    """A solved patch state: its strips, the wear depth per passage on them [m],
    the values recorded per patch (:data:`RECORDS`) and its rolling contact fatigue
    measures (:mod:`railcontact.wear.rcf`): FI_surf [-], T gamma [N], the WLRM damage
    per passage [-], the strips with contact (1.0, else 0.0) and FI_sub [Pa] (NaN
    without ``rcf.subsurface``)."""

    strips: _Strips
    depth_y: np.ndarray
    values: tuple
    fi_surf: float
    tgamma: float
    damage: float
    covered: np.ndarray
    fi_sub: float

    def rcf_values(self, subsurface: bool) -> tuple:
        """The RCF values recorded per patch (:data:`RCF_RECORDS`)."""
        return (self.fi_surf, self.tgamma, self.damage) + ((self.fi_sub,) if subsurface
                                                           else ())


#: the local model's values recorded per sample, wheelset, side and patch slot
RECORDS = ("Fn", "Fx", "Fy", "area", "pmax", "frictional_power")
#: the RCF measures recorded likewise (FI_sub with ``rcf.subsurface`` only)
RCF_RECORDS = ("fi_surf", "tgamma", "rcf_damage", "fi_sub")


def _covered(window, damage, exceedance):
    """(slice of the positions a patch covers, their mask within it, the WLRM damage
    and the FI_surf exceedance on them): the RCF measures of a patch placed on a
    profile grid, from its coverage there (:func:`~railcontact.wear.rcf.profile_window`
    of 1 on its strips)."""
    sl, c = window
    return sl, c > 0.5, damage * c, exceedance * c


def _envelope(v):
    """A running maximum with NaN where no patch came."""
    return np.where(np.isfinite(v), v, np.nan)


@dataclass
class _Samples:
    """The post-processed samples of a dynamics run: per sample, wheelset, side and
    patch slot the normal force N [N], the creepages (ξ, η [-], φ [1/m]) and the
    semi-axes [m]; per sample and wheelset the nearest table shift and its neighbour
    on the sample's side (the slot's geometry where the nearest has none)."""

    N: np.ndarray
    creep: np.ndarray
    semi_a: np.ndarray
    semi_b: np.ndarray
    near: np.ndarray
    other: np.ndarray
    velocity: float
    time: np.ndarray

    @classmethod
    def read(cls, ds, shift, stride: int) -> "_Samples":
        """Every ``stride``-th sample of the run ``ds`` on the table shifts ``shift``."""
        idx = np.arange(0, ds.sizes["time"], max(int(stride), 1))
        yrel = ds["relative_shift"].values[idx]
        h = shift[1] - shift[0]
        near = np.clip(np.rint((yrel - shift[0]) / h).astype(int), 0, shift.size - 1)
        other = np.clip(np.where(yrel - shift[0] >= near * h, near + 1, near - 1), 0,
                        shift.size - 1)
        creep = np.stack([ds[f"creepage_{c}"].values[idx]
                          for c in ("longitudinal", "lateral", "spin")], axis=-1)
        return cls(ds["patch_normal_force"].values[idx], creep,
                   ds["semi_axis_a"].values[idx], ds["semi_axis_b"].values[idx], near, other,
                   float(ds.attrs["velocity_m_s"]), ds["time"].values[idx])

    def loaded(self):
        """(sample, wheelset, side, slot) of every loaded patch, in sample order."""
        return np.argwhere(self.N > 0)


@dataclass
class _Run:
    """The bookkeeping of one run's post-processing: its inputs (tables, profiles,
    grids, friction, whether FI_sub is computed), the sums of the wear depths and of
    the WLRM damage, the envelopes of FI_surf and FI_sub on the grids, the records and
    the caches (solved states and their mapped depths and RCF placements by reuse
    key; each wheel slot's last solution for warm starts)."""

    samples: _Samples
    tables: list
    wheels: list
    rails: tuple
    wheel_grids: list
    rail_grids: list
    friction: float
    subsurface: bool = False
    wheel: list = field(default_factory=list)
    rail: list = field(default_factory=list)
    damage_wheel: list = field(default_factory=list)
    damage_rail: list = field(default_factory=list)
    surface_wheel: list = field(default_factory=list)
    surface_rail: list = field(default_factory=list)
    fi_surf_wheel: list = field(default_factory=list)
    fi_surf_rail: list = field(default_factory=list)
    fi_sub_wheel: list = field(default_factory=list)
    fi_sub_rail: list = field(default_factory=list)
    records: dict = field(default_factory=dict)
    energy: float = 0.0
    solved: dict = field(default_factory=dict)
    mapped: dict = field(default_factory=dict)
    rcf_mapped: dict = field(default_factory=dict)
    last: dict = field(default_factory=dict)
    stats: PostProcessStats = field(default_factory=PostProcessStats)

    def __post_init__(self):
        self.wheel = [[np.zeros_like(g) for g in pair] for pair in self.wheel_grids]
        self.rail = [np.zeros_like(g) for g in self.rail_grids]
        self.damage_wheel = [[np.zeros_like(g) for g in pair] for pair in self.wheel_grids]
        self.damage_rail = [np.zeros_like(g) for g in self.rail_grids]
        self.surface_wheel = [[np.zeros_like(g) for g in pair] for pair in self.wheel_grids]
        self.surface_rail = [np.zeros_like(g) for g in self.rail_grids]
        for name in ("fi_surf", "fi_sub"):
            setattr(self, f"{name}_wheel", [[np.full(g.shape, -np.inf) for g in pair]
                                            for pair in self.wheel_grids])
            setattr(self, f"{name}_rail", [np.full(g.shape, -np.inf) for g in self.rail_grids])
        names = RECORDS + (RCF_RECORDS if self.subsurface else RCF_RECORDS[:3])
        self.records = {k: np.full(self.samples.N.shape, np.nan) for k in names}

    def geometry(self, i: int, w: int, j: int, k: int):
        """(table index, patch geometry) of a loaded patch; None where it enters
        between two table shifts (no geometry at either)."""
        for ti in (int(self.samples.near[i, w]), int(self.samples.other[i, w])):
            geom = self.tables[w].geometry[ti][j][k]
            if geom is not None:
                return ti, geom
        return None

    def add(self, at: tuple, key, geom, hit: _Solved) -> None:
        """A patch's records, energy and wear depth on the wheel and rail grids (the
        depths of a reuse key map onto the same profiles: computed once)."""
        i, w, j, k = at
        for name, v in zip(self.records, hit.values + hit.rcf_values(self.subsurface)):
            self.records[name][i, w, j, k] = v
        self.energy += hit.values[-1] / self.samples.velocity
        self.add_rcf(at, key, geom, hit)
        if not hit.depth_y.any():
            return
        depths = self.mapped.get(key) if key is not None else None
        if depths is None:
            depths = (profile_depth(geom, hit.strips, hit.depth_y, self.wheels[w][j], "wheel",
                                    self.wheel_grids[w][j]) / (2 * math.pi * geom.rolling_radius),
                      profile_depth(geom, hit.strips, hit.depth_y, self.rails[j], "rail",
                                    self.rail_grids[j]))
            if key is not None:
                self.mapped[key] = depths
        self.wheel[w][j] += depths[0]
        self.rail[j] += depths[1]

    def add_rcf(self, at: tuple, key, geom, hit: _Solved) -> None:
        """A patch's RCF measures on the wheel and rail grids: the positions its
        strips with contact cover take its WLRM damage and its FI_surf exceedance
        max(FI_surf, 0) (the wheel's per metre run) and raise the FI_surf (and FI_sub)
        envelopes (the placement of a reuse key is computed once)."""
        c0 = time.thread_time()
        i, w, j, k = at
        on = self.rcf_mapped.get(key) if key is not None else None
        if on is None:
            r_w = 2 * math.pi * geom.rolling_radius
            exc = hit.fi_surf if hit.fi_surf > 0 else 0.0           # NaN: 0
            on = (_covered(profile_window(geom, hit.strips.y, hit.covered, self.wheels[w][j],
                                          "wheel", self.wheel_grids[w][j]), hit.damage / r_w,
                           exc / r_w),
                  _covered(profile_window(geom, hit.strips.y, hit.covered, self.rails[j],
                                          "rail", self.rail_grids[j]), hit.damage, exc))
            if key is not None:
                self.rcf_mapped[key] = on
        for (sl, mask, d, e), dmg, srf, fi, sub in (
                (on[0], self.damage_wheel[w][j], self.surface_wheel[w][j],
                 self.fi_surf_wheel[w][j], self.fi_sub_wheel[w][j]),
                (on[1], self.damage_rail[j], self.surface_rail[j], self.fi_surf_rail[j],
                 self.fi_sub_rail[j])):
            dmg[sl] += d
            srf[sl] += e
            part = fi[sl]
            part[mask] = np.maximum(part[mask], hit.fi_surf)
            if self.subsurface:
                part = sub[sl]
                part[mask] = np.maximum(part[mask], hit.fi_sub)
        self.stats.rcf_time += time.thread_time() - c0

    def result(self, cpu_time: float) -> dict:
        """The means over the samples (per metre of track), the FI envelopes and the
        records."""
        n = max(self.samples.time.size, 1)
        self.stats.samples = int(self.samples.time.size)
        self.stats.cpu_time = cpu_time
        return {"wheel": [[d / n for d in pair] for pair in self.wheel],
                "rail": [d / n for d in self.rail], "energy": self.energy / n,
                "rcf_wheel": [[d / n for d in pair] for pair in self.damage_wheel],
                "rcf_rail": [d / n for d in self.damage_rail],
                "rcf_surface_wheel": [[d / n for d in pair] for pair in self.surface_wheel],
                "rcf_surface_rail": [d / n for d in self.surface_rail],
                "fi_surf_wheel": [[_envelope(v) for v in pair] for pair in self.fi_surf_wheel],
                "fi_surf_rail": [_envelope(v) for v in self.fi_surf_rail],
                "fi_sub_wheel": [[_envelope(v) for v in pair] for pair in self.fi_sub_wheel],
                "fi_sub_rail": [_envelope(v) for v in self.fi_sub_rail],
                "records": self.records, "time": self.samples.time, "stats": self.stats}


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
        Warm starts along the time history (models with the ``"warm-start"``
        capability) and grid reuse at the same table shift (``"grid-reuse"``).
    rcf : RcfParameters, optional
        Parameters of the rolling contact fatigue measures computed beside the wear
        (:mod:`railcontact.wear.rcf`; defaults when omitted).
    """

    def __init__(self, normal: str, tangential: str, law, material: Material, grid=None,
                 element_size=None, normal_options=None, tangential_options=None,
                 reuse_tolerance: float = 1e-3, warm: bool = True, rcf=None):
        self.nmodel = get_normal_model(normal, **(normal_options or {}))
        self.tmodel = get_tangential_model(tangential, **(tangential_options or {}))
        if "force-control" not in self.nmodel.capabilities:
            raise InputError(f"normal model {normal!r}: the wear post-processing solves for the "
                             "dynamics' normal force; expected a model with 'force-control'")
        self.law, self.material = law, material
        self.kw = {"grid": grid, "element_size": element_size}
        self.tol = float(reuse_tolerance)
        self.nwarm = warm and "warm-start" in self.nmodel.capabilities
        self.regrid = warm and "grid-reuse" in self.nmodel.capabilities
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
        passage on the grids, as the depths), ``rcf_surface_wheel`` /
        ``rcf_surface_rail`` (likewise the FI_surf exceedance, the sum over the
        passages of max(FI_surf, 0)), ``fi_surf_wheel`` / ``fi_surf_rail``
        (the largest FI_surf at each grid position, NaN where no patch came),
        ``fi_sub_wheel`` / ``fi_sub_rail`` (likewise FI_sub [Pa], with
        ``rcf.subsurface``; NaN otherwise), ``stats`` (:class:`PostProcessStats`).
        """
        t0 = time.thread_time()
        run = _Run(_Samples.read(ds, tables[0].shift, stride), tables, wheels, rails,
                   wheel_grids, rail_grids, friction, self.rcf.subsurface)
        for at in run.samples.loaded():
            self._patch(run, tuple(int(x) for x in at))
        return run.result(time.thread_time() - t0)

    def _patch(self, run: _Run, at: tuple) -> None:
        """One loaded patch (sample, wheelset, side, slot): its geometry, its solution
        (solved, or a repeated state's) and its wear."""
        i, w, j, k = at
        smp = run.samples
        n = float(smp.N[at])
        run.stats.patches += 1
        found = run.geometry(i, w, j, k)
        if found is None:                   # entering between table points
            run.stats.skipped += 1
            return
        ti, geom = found
        cr = tuple(float(c) for c in smp.creep[at])
        key = self._key(w, ti, j, k, n, cr, float(smp.semi_a[at]), float(smp.semi_b[at]),
                        run.friction)
        hit = run.solved.get(key) if key is not None else None
        if hit is None:
            hit, ns, ts = self._solve(geom, n, cr, run.friction, smp.velocity,
                                      run.last.get((w, j, k)), ti, run.stats)
            run.last[(w, j, k)] = (ti, ns, ts)
            if key is not None:
                run.solved[key] = hit
        else:
            run.stats.reused += 1
        run.add(at, key, geom, hit)

    def _solve(self, geom, n, creep, friction, V, previous, ti, st):
        """Normal (force-controlled) and tangential solution of one patch and its wear
        per passage on the strips; ``previous`` = (table index, normal, tangential)
        of the same wheel's slot at the previous sample (warm starts).  Returns the
        cache entry (strips, depth per passage on them, the record values, the RCF
        measures) and the solutions."""
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
        covered = covered_strips(ns)
        st.rcf_time += time.thread_time() - c0
        return (_Solved(_Strips(ns.y, ns.dy), depth_y, values, fi, tg, dmg, covered, fi_sub),
                ns, ts)
