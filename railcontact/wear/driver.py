"""The wear driver: one loop, one step, one output writer and one checkpoint for
every wear scenario (a scenario's ``driver()`` gives its own).

A wear run is a sequence of steps.  In each step the loads on the current profiles
give every worn profile its wear depth per metre run (:meth:`WearDriver.loads`,
the one part a kind of scenario provides):

* **fixed operating conditions** (:class:`~railcontact.wear.simulation.WearSimulation`):
  given wheelset positions, loads and creepages, or a recorded time history,
  solved on the current profiles; they do not respond to the wear;
* **closed loop** (:class:`~railcontact.wear.closed_loop.ClosedLoopWear`): a vehicle
  on a route mix, its dynamics run on the current profiles and post-processed with
  the local contact model.

The rest is one step function (:meth:`WearDriver.run_step`): the depth is smoothed
(Gaussian, area conserved), the step distance is imposed (``distances``), fixed
(``step_distance``) or chosen so that the largest depth is ``max_depth_per_step``,
and each worn profile moves along its inward normal.  After every step the driver
writes the checkpoint (``checkpoint.nc``: the results of
:meth:`WearDriver.to_xarray` from the kind's table of :class:`Variable`, the
current profiles and the scenario's hash) and, at most every
:data:`RESULTS_INTERVAL` and at the end, the results (``wear.nc``); a run started again
resumes from it, bit-identical to an uninterrupted run, and refuses a checkpoint of
another scenario or one it cannot read, naming what differs.
"""

from __future__ import annotations

import hashlib
import json
import logging
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..core.errors import InputError, RailContactError
from ..core.files import write_netcdf
from ..profiles.profile import Profile
from .mapping import arc_length_grid, removed_area, smooth_depth, wear_profile

log = logging.getLogger(__name__)

#: file name of the checkpoint in the output folder
CHECKPOINT = "checkpoint.nc"
#: the attribute that marks a checkpoint (its value: the format's version)
CHECKPOINT_MARK = "railcontact_wear_checkpoint"
CHECKPOINT_VERSION = 1
#: scenario settings that a run may change on resume: how far it runs and where
RESUMABLE = ("steps", "scheduler", "base_dir", "records")
#: wear.nc is rewritten after a step when this long [s] has passed since it was last
#: written, and at the end of a run; the checkpoint after every step (a NetCDF
#: write costs about 0.4 s, more than a step of a few fixed conditions)
RESULTS_INTERVAL = 10.0


@dataclass(frozen=True)
class Variable:
    """One variable of a wear run's results: where its values lie in the step (or
    state) records and how it is written.

    Attributes
    ----------
    name : str          the record key and the dataset's variable name
    dims : tuple        its dimensions after the leading ``over`` dimension
    units, long_name : str
    over : str          "step" (one value per step) or "state" (per profile state)
    """

    name: str
    dims: tuple
    units: str
    long_name: str
    over: str = "step"


@dataclass
class WornBody:
    """A worn profile in a step: what it is, its profile before the step, the wear
    per metre run on its arc-length grid (before smoothing), where its wear depth
    is recorded and which slots take the new profile.

    Attributes
    ----------
    kind : str              "wheel" or "rail"
    profile : Profile       before the step
    grid : ndarray          its arc-length grid [m]
    rate : ndarray          wear depth per metre run on ``grid`` [m/m]
    y : ndarray             lateral positions where the step's depth is recorded [m]
    slots : list            the kind's slots that take the worn profile
    """

    kind: str
    profile: Profile
    grid: np.ndarray
    rate: np.ndarray
    y: np.ndarray
    slots: list


@dataclass
class WornProfile:
    """A worn profile after the step: the new profile, the step's depth on the
    body's ``y`` [m], the worn area given by the law and the area between the
    profiles [m²]."""

    body: WornBody
    new: Profile
    depth_on_y: np.ndarray
    law_area: float
    removed_area: float


@dataclass
class StepLoads:
    """What a kind of scenario gives for one step: the worn bodies and the entries
    of the step's record that belong to the kind (energies, measures, counts)."""

    bodies: list
    record: dict = field(default_factory=dict)


def _numbers(obj):
    """``obj`` with its integers as floats (``k = 1`` and ``k = 1.0`` are one value)."""
    if isinstance(obj, dict):
        return {str(k): _numbers(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_numbers(v) for v in obj]
    if isinstance(obj, (int, np.integer)) and not isinstance(obj, bool):
        return float(obj)
    if isinstance(obj, np.floating):
        return float(obj)
    return obj


def _canonical(obj) -> str:
    """Sorted, compact JSON of ``obj`` (numbers as floats, other objects as text)."""
    return json.dumps(_numbers(obj), sort_keys=True, default=str, separators=(",", ":"))


def _flat(obj, prefix="") -> dict:
    if isinstance(obj, dict):
        out = {}
        for k, v in obj.items():
            out.update(_flat(v, f"{prefix}{k}."))
        return out
    return {prefix[:-1]: obj}


def _cut(value, n: int = 60) -> str:
    text = _canonical(value)
    return text if len(text) <= n else text[:n - 3] + "..."


def profiles_hash(profiles) -> str:
    """SHA-256 of the points of ``profiles`` (the new profiles of a scenario)."""
    h = hashlib.sha256()
    for p in profiles:
        h.update(np.ascontiguousarray(p.y, dtype=float).tobytes())
        h.update(np.ascontiguousarray(p.z, dtype=float).tobytes())
    return h.hexdigest()


class WearDriver:
    """The loop of a wear run (see the module docstring); a kind of scenario gives
    its profiles (:meth:`profiles`, :meth:`set_profile`), its loads per step
    (:meth:`loads`), its results' variables, coordinates and attributes.

    Parameters
    ----------
    scenario : WearScenario or VehicleWearScenario
    out_dir : path, optional
        Folder of ``wear.nc`` and ``checkpoint.nc`` (nothing written without it).
    progress : bool
        Progress bars over the steps (and within a step).
    """

    def __init__(self, scenario, out_dir=None, progress: bool = True):
        self.sc = scenario
        self.out = Path(out_dir) if out_dir else None
        self.progress = progress
        self.steps: list = []        # per step: dict of the record
        self.states: list = []       # per profile state (0 = new profiles)
        self.step = 0
        self.distance = 0.0
        self.cpu_time = 0.0
        self._written = time.perf_counter()       # when wear.nc was last written

    # ------------------------------------------------- what a kind provides
    def slots(self) -> list:
        """The keys of the kind's profile slots, in a fixed order."""
        raise NotImplementedError

    def profile(self, slot) -> Profile:
        """The current profile in ``slot``."""
        raise NotImplementedError

    def set_profile(self, slot, profile: Profile) -> None:
        """Put ``profile`` into ``slot``."""
        raise NotImplementedError

    def initial_profiles(self) -> list:
        """The scenario's new profiles (part of its identity)."""
        raise NotImplementedError

    def loads(self, grid_of: dict) -> StepLoads:
        """The worn bodies of the step on the current profiles (``grid_of``: the
        arc-length grid of each distinct profile by ``id``)."""
        raise NotImplementedError

    def record(self, rec: dict, worn: list) -> None:
        """Store the worn profiles' depths and areas in the step's record."""
        raise NotImplementedError

    def variables(self) -> tuple:
        """The :class:`Variable` table of the results."""
        raise NotImplementedError

    def coords(self) -> dict:
        raise NotImplementedError

    def attrs(self) -> dict:
        raise NotImplementedError

    def finish(self) -> None:
        """Work after the last step (e.g. the measures of the final profiles)."""

    # ------------------------------------------------------------ one step
    def grids(self) -> dict:
        """The arc-length grid of every distinct current profile, by ``id``."""
        out: dict = {}
        for slot in self.slots():
            p = self.profile(slot)
            if id(p) not in out:
                out[id(p)] = arc_length_grid(p, self.sc.grid_step)
        return out

    def step_distance(self, smoothed: list) -> float:
        """The distance of this step [m]: imposed, fixed, or by the largest depth."""
        sc = self.sc
        if sc.distances is not None and self.step < len(sc.distances):
            return float(sc.distances[self.step])
        if sc.step_distance:
            return sc.step_distance
        peak = max((float(d.max()) for d in smoothed), default=0.0)
        if not peak > 0:
            raise RailContactError("no wear in this step (no frictional work on the worn "
                                   "bodies); check the operating conditions or routes and "
                                   "the wear law")
        return sc.max_depth_per_step / peak

    def wear(self, body: WornBody, smoothed, dist: float) -> WornProfile:
        """One body worn over ``dist``: its profile moved along the inward normal."""
        depth = smoothed * dist
        new = wear_profile(body.profile, body.grid, depth, body.kind)
        if self.sc.profile_smoothing > 0:
            new = new.smoothed(self.sc.profile_smoothing)
        on_y = np.interp(body.profile.arc_length(body.y), body.grid, depth, left=0.0,
                         right=0.0)
        return WornProfile(body, new, on_y, float(np.trapezoid(body.rate, body.grid)) * dist,
                           removed_area(body.profile, new, body.kind))

    def run_step(self) -> dict:
        """One wear step (see the module docstring); returns its record."""
        t0 = time.perf_counter()
        sc = self.sc
        loads = self.loads(self.grids())
        smoothed = [smooth_depth(b.rate, sc.grid_step, sc.smoothing) for b in loads.bodies]
        dist = self.step_distance(smoothed)
        worn = [self.wear(b, s, dist) for b, s in zip(loads.bodies, smoothed)]
        for w in worn:
            for slot in w.body.slots:
                self.set_profile(slot, w.new)
        rec = {"distance": dist, **loads.record}
        self.record(rec, worn)
        rec["wall_time"] = time.perf_counter() - t0
        self.step += 1
        self.distance += dist
        self.steps.append(rec)
        if self.out:
            self.write(results=time.perf_counter() - self._written >= RESULTS_INTERVAL)
        return rec

    def run(self, resume: bool = True):
        """Run the remaining steps (from the checkpoint when ``resume``); returns the
        results (:meth:`to_xarray`)."""
        from tqdm.auto import tqdm
        if resume:
            self.load_checkpoint()
        t0 = time.perf_counter()
        for _ in tqdm(range(self.step, self.sc.steps), desc="wear", unit="step",
                      disable=not self.progress, file=sys.stderr):
            self.run_step()
        self.finish()
        self.cpu_time += time.perf_counter() - t0
        if self.out:
            return self.write()
        return self.to_xarray()

    # ------------------------------------------------------------ outputs
    def to_xarray(self):
        """The run's results as an :class:`xarray.Dataset` (see docs/wear.md)."""
        import xarray as xr
        coords = {"step": ("step", np.arange(1, len(self.steps) + 1)),
                  "state": ("state", np.arange(len(self.states)))}
        coords.update(self.coords())
        data = {}
        for v in self.variables():
            rows = self.steps if v.over == "step" else self.states
            if rows and v.name in rows[0]:
                data[v.name] = ((v.over,) + v.dims,
                                np.array([r[v.name] for r in rows], dtype=float),
                                {"units": v.units, "long_name": v.long_name})
        attrs = {"total_distance_m": float(self.distance), "cpu_time_s": float(self.cpu_time),
                 **self.attrs()}
        ds = xr.Dataset(data, coords=coords, attrs=attrs)
        if not self.states:
            ds = ds.drop_vars("state")
        return ds

    def write(self, results: bool = True):
        """Write the checkpoint and (``results``) ``wear.nc`` into the output folder;
        returns the results."""
        ds = self.to_xarray()
        write_netcdf(self._checkpoint_dataset(ds), self.out / CHECKPOINT)
        if results:
            write_netcdf(ds, self.out / "wear.nc")
            self._written = time.perf_counter()
        return ds

    # ------------------------------------------------------------ checkpoint
    def identity(self) -> dict:
        """What a checkpoint must match to be resumed: the scenario's settings
        (but how many steps and on which scheduler) and its new profiles."""
        ident = {k: v for k, v in self.sc.identity().items() if k not in RESUMABLE}
        ident["initial_profiles"] = profiles_hash(self.initial_profiles())
        ident["driver"] = type(self).__name__
        return ident

    def scenario_hash(self) -> str:
        """SHA-256 of the canonical JSON of :meth:`identity`."""
        return hashlib.sha256(_canonical(self.identity()).encode()).hexdigest()

    def _checkpoint_dataset(self, ds):
        """The results plus the current profiles, the counters and the hash."""
        uniq, index = [], {}
        for slot in self.slots():
            p = self.profile(slot)
            if id(p) not in index:
                index[id(p)] = len(uniq)
                uniq.append(p)
        ck = ds.copy()
        for k, p in enumerate(uniq):
            ck[f"checkpoint_profile{k}_y"] = (f"checkpoint_point{k}", p.y)
            ck[f"checkpoint_profile{k}_z"] = (f"checkpoint_point{k}", p.z)
        meta = {"step": self.step, "distance": self.distance, "cpu_time": self.cpu_time,
                "steps": len(self.steps), "states": len(self.states),
                "slots": [index[id(self.profile(s))] for s in self.slots()],
                "kinds": [p.kind for p in uniq], "names": [p.name for p in uniq],
                "smoothing": [p.smoothing for p in uniq]}
        ck.attrs = {CHECKPOINT_MARK: CHECKPOINT_VERSION, "scenario_hash": self.scenario_hash(),
                    "scenario": _canonical(self.identity()), "meta": json.dumps(meta)}
        return ck

    def checkpoint_path(self):
        return self.out / CHECKPOINT if self.out else None

    def _read_checkpoint(self, path: Path):
        """The checkpoint's dataset, loaded and closed; InputError if it is not one."""
        import xarray as xr
        hint = "remove it or run with --restart"
        try:
            with xr.open_dataset(path, engine="h5netcdf") as ds:
                ds = ds.load()
        except Exception as exc:         # h5py/h5netcdf raise many kinds on bad files
            raise InputError(f"{path}: cannot read the wear checkpoint "
                             f"({type(exc).__name__}: {str(exc)[:120]}); {hint}") from None
        if ds.attrs.get(CHECKPOINT_MARK) != CHECKPOINT_VERSION:
            raise InputError(f"{path}: not a railcontact wear checkpoint (no "
                             f"{CHECKPOINT_MARK!r} = {CHECKPOINT_VERSION} attribute); {hint}")
        try:
            meta = json.loads(ds.attrs["meta"])
            theirs = json.loads(ds.attrs["scenario"])
            stored_hash = str(ds.attrs["scenario_hash"])
        except (KeyError, ValueError, TypeError) as exc:
            raise InputError(f"{path}: the wear checkpoint's attributes are damaged "
                             f"({exc!s:.80}); {hint}") from None
        if stored_hash != self.scenario_hash():
            mine = self.identity()
            a, b = _flat(theirs), _flat(json.loads(_canonical(mine)))
            diff = [k for k in sorted(set(a) | set(b)) if a.get(k) != b.get(k)]
            text = "; ".join(f"{k}: {_cut(a[k]) if k in a else 'absent'} in the checkpoint, "
                             f"{_cut(b[k]) if k in b else 'absent'} now"
                             for k in diff[:4]) or "its hash differs"
            more = f" (and {len(diff) - 4} more)" if len(diff) > 4 else ""
            raise InputError(f"{path}: the checkpoint belongs to another scenario: {text}"
                             f"{more}; {hint}")
        return ds, meta

    def load_checkpoint(self) -> bool:
        """Resume from the checkpoint of the output folder (False: none there)."""
        p = self.checkpoint_path()
        if p is None:
            return False
        old = p.with_name("checkpoint.npz")
        if old.is_file() and not p.is_file():
            log.warning("%s: a checkpoint of an earlier version is not resumed; the run "
                        "starts from the new profiles", old)
        if not p.is_file():
            return False
        ds, meta = self._read_checkpoint(p)
        hint = "remove it or run with --restart"
        try:
            uniq = [Profile(ds[f"checkpoint_profile{k}_y"].values,
                            ds[f"checkpoint_profile{k}_z"].values, kind=kind, name=name,
                            smoothing=sm)
                    for k, (kind, name, sm) in enumerate(zip(meta["kinds"], meta["names"],
                                                             meta["smoothing"]))]
            slots = self.slots()
            if len(meta["slots"]) != len(slots):
                raise ValueError(f"{len(meta['slots'])} profile slots, expected {len(slots)}")
            steps = self._records(ds, "step", meta["steps"])
            states = self._records(ds, "state", meta["states"])
        except (KeyError, ValueError, IndexError, TypeError, RailContactError) as exc:
            raise InputError(f"{p}: the wear checkpoint is incomplete ({exc!s:.100}); "
                             f"{hint}") from None
        for slot, k in zip(slots, meta["slots"]):
            self.set_profile(slot, uniq[k])
        self.steps, self.states = steps, states
        self.step, self.distance = int(meta["step"]), float(meta["distance"])
        self.cpu_time = float(meta.get("cpu_time", 0.0))
        log.info("resumed from %s at step %d", p, self.step)
        return True

    def _records(self, ds, over: str, n: int) -> list:
        """The step (or state) records of the results held in a checkpoint."""
        names = [v.name for v in self.variables() if v.over == over and v.name in ds]
        rows = []
        for k in range(n):
            rec = {}
            for name in names:
                v = ds[name].values[k]
                rec[name] = float(v) if np.ndim(v) == 0 else np.array(v)
            rows.append(rec)
        return rows

