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
    """A solved patch state: its strips, the wear depth per passage on them [m] and
    the values recorded per patch (:data:`RECORDS`)."""

    strips: _Strips
    depth_y: np.ndarray
    values: tuple


#: the local model's values recorded per sample, wheelset, side and patch slot
RECORDS = ("Fn", "Fx", "Fy", "area", "pmax", "frictional_power")


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
    grids, friction), the sums of the wear depths, the records and the caches
    (solved states and their mapped depths by reuse key; each wheel slot's last
    solution for warm starts)."""

    samples: _Samples
    tables: list
    wheels: list
    rails: tuple
    wheel_grids: list
    rail_grids: list
    friction: float
    wheel: list = field(default_factory=list)
    rail: list = field(default_factory=list)
    records: dict = field(default_factory=dict)
    energy: float = 0.0
    solved: dict = field(default_factory=dict)
    mapped: dict = field(default_factory=dict)
    last: dict = field(default_factory=dict)
    stats: PostProcessStats = field(default_factory=PostProcessStats)

    def __post_init__(self):
        self.wheel = [[np.zeros_like(g) for g in pair] for pair in self.wheel_grids]
        self.rail = [np.zeros_like(g) for g in self.rail_grids]
        self.records = {k: np.full(self.samples.N.shape, np.nan) for k in RECORDS}

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
        for name, v in zip(RECORDS, hit.values):
            self.records[name][i, w, j, k] = v
        self.energy += hit.values[-1] / self.samples.velocity
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

    def result(self, cpu_time: float) -> dict:
        """The means over the samples (per metre of track) and the records."""
        n = max(self.samples.time.size, 1)
        self.stats.samples = int(self.samples.time.size)
        self.stats.cpu_time = cpu_time
        return {"wheel": [[d / n for d in pair] for pair in self.wheel],
                "rail": [d / n for d in self.rail], "energy": self.energy / n,
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
    """

    def __init__(self, normal: str, tangential: str, law, material: Material, grid=None,
                 element_size=None, normal_options=None, tangential_options=None,
                 reuse_tolerance: float = 1e-3, warm: bool = True):
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
        model's F_n, F_x, F_y, area, p_max and frictional power), ``stats``
        (:class:`PostProcessStats`).
        """
        t0 = time.thread_time()
        run = _Run(_Samples.read(ds, tables[0].shift, stride), tables, wheels, rails,
                   wheel_grids, rail_grids, friction)
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
        return _Solved(_Strips(ns.y, ns.dy), depth_y, values), ns, ts
