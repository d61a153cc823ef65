"""Time integration of a vehicle model on a route, linear stability analysis, and
batches of runs on Dask."""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from tqdm.auto import tqdm

from ..core.errors import InputError, RailContactError
from ..geometry.validity import nadal_limit
from ..core.materials import Material, STEEL
from ..tangential import get_tangential_model
from ..tangential.polach import PRESETS
from .equations_of_motion import (EXTERNAL, NORMAL_PASSES, ContactTables, Outputs, System,
                                  Track, Vehicle, rhs_core, rk4_run)
from ..geometry.wheel_pass import P_CONTACT_ANGLE, P_Y_RAIL
from .online_contact import (C_FLANGE, C_FX, C_FY, C_MZ, C_RATIO, C_SIDE, C_TOL, C_YRAIL,
                             G_MATCH, MAX_ROWS, NPF, OFF_RAIL, ON_FLANGE_TIP, R_FX, R_FY,
                             R_MZ, R_SFX, R_SFY, R_SMZ, R_SPRING, OnlineWheelRail,
                             matches, rhs_online, rk4_online)
from .route import Route
from .vehicle import VehicleModel
from .wheel_rail import WheelRailTable, online_law, python_patch_forces

log = logging.getLogger(__name__)


def _per_wheelset(table, nw: int) -> list:
    """One contact table per wheelset: ``table`` is one :class:`WheelRailTable` for
    all or a sequence of ``nw`` (e.g. worn wheelsets) on one shift grid and nominal
    radius."""
    tables = [table] * nw if isinstance(table, WheelRailTable) else list(table)
    if len(tables) != nw or not all(isinstance(t, WheelRailTable) for t in tables):
        raise InputError(f"contact tables: expected one WheelRailTable or {nw} (one per "
                         f"wheelset), got {len(tables)}")
    t0 = tables[0]
    for t in tables[1:]:
        if (t.shift.shape != t0.shift.shape or not np.allclose(t.shift, t0.shift, atol=1e-12)
                or t.nominal_radius != t0.nominal_radius or t.data.shape != t0.data.shape):
            raise InputError("contact tables of the wheelsets: expected one shift grid and "
                             "one nominal radius")
    return tables


class _System:
    """A vehicle on a route at speed V with a tangential law: the right-hand side.

    ``table``: one :class:`WheelRailTable` for every wheelset, or one per wheelset."""

    def __init__(self, model: VehicleModel, route: Route, table: WheelRailTable,
                 velocity: float, tangential: str = "fastsim", friction: float = 0.3,
                 material: Material = STEEL, tangential_options: dict | None = None,
                 fastsim_grid=(12, 12), polach_preset: str | None = None):
        if not (isinstance(velocity, (int, float)) and math.isfinite(velocity)
                and 0.1 <= velocity <= 200):
            raise InputError(f"simulation velocity {velocity!r} m/s: expected 0.1 to 200 m/s")
        if not (math.isfinite(friction) and 0 < friction <= 2):
            raise InputError(f"friction coefficient {friction!r}: expected a value in (0, 2]")
        self.model, self.route = model, route
        self.V = float(velocity)
        self.s0 = -min(b.x for b in model.bodies)
        nw = len(model.wheelsets)
        self.wheel_rail = table if isinstance(table, OnlineWheelRail) else None
        if self.wheel_rail is not None:           # online: a placeholder table
            self.tables = []
            self.table = None
            self.flange_angle = self.wheel_rail.flange_angle
            self.contact = ContactTables(np.array([-1.0, 1.0]), np.zeros((nw, 2, 2, 2, 13)),
                                         np.ones(nw), self.wheel_rail.nominal_radius)
        else:
            self.tables = _per_wheelset(table, nw)
            self.table = self.tables[0]
            angles = [t.flange_angle for t in self.tables if math.isfinite(t.flange_angle)]
            self.flange_angle = min(angles) if angles else math.nan
            self.contact = ContactTables(
                self.table.shift, np.ascontiguousarray(np.stack([tb.data for tb in self.tables])),
                np.array([tb.reference_load for tb in self.tables], dtype=float),
                float(self.table.nominal_radius))
        self.out = Outputs.empty(nw)
        self.fext = np.zeros((nw, 2, 2), EXTERNAL)
        self.tangential = tangential
        opts = dict(tangential_options or {})
        mu = friction
        kA = kS = 1.0
        fall = (1.0, 0.0)
        if tangential == "polach" and (polach_preset or opts.get("preset")):
            name = polach_preset or opts.get("preset")
            if name not in PRESETS:
                raise InputError(f"polach preset {name!r}: expected one of {sorted(PRESETS)}")
            kA, kS, mu, A, B = PRESETS[name]
            fall = (A, B)
        nx, ny = (int(v) for v in fastsim_grid)
        if not (2 <= nx <= 200 and 2 <= ny <= 200):
            raise InputError(f"fastsim grid {fastsim_grid!r}: expected two integers in [2, 200]")
        self.tp = np.array([mu, material.shear_modulus, nx, ny, kA, kS, fall[0], fall[1]])
        law = online_law(tangential)
        strips = (self.wheel_rail is not None and not opts
                  and self.wheel_rail.compiled_strips(tangential))
        if law is not None or strips:
            # (a strip model with fastsim-strips: the strip march in compiled code; the
            # law's code is FASTSIM's, unused)
            self.law, self.py_model = (law if law is not None else online_law("fastsim")), None
        else:
            self.law = -1
            self.py_model = get_tangential_model(tangential, **opts)
        self.material, self.friction = material, mu
        self.system = System(self.V, self.s0, Vehicle(*model.packed()), Track(*route.packed()),
                             self.contact, max(self.law, 0), self.tp)
        self.calls = 0
        self.online = None
        if self.wheel_rail is not None:
            ws_inertia = model.bodies[model.wheelsets[0][0]].yaw_inertia
            # (a model in Python: FASTSIM compiled is the stand-in of its tangential
            # problems at the steps' inner stages, _online_python_forces)
            self.online = self.wheel_rail.compiled(
                nw, max(self.law, 0) if self.py_model is None else online_law("fastsim"),
                self.tp, ws_inertia, tangential if strips else None)
            self.fext_rows = np.zeros((nw, MAX_ROWS), EXTERNAL)
            self.warm = {}
            self.batch = False
            self.stand_in = "none"
            self.fastsim_grid = (nx, ny)
            if self.py_model is not None:
                from ..normal import get_normal_model, normal_supports
                from ..tangential import tangential_supports
                self.py_normal = get_normal_model(self.wheel_rail.normal)
                self.batch = (normal_supports(self.wheel_rail.normal, "batch")
                              and tangential_supports(tangential, "strip-march"))
                if not self.batch:
                    self.stand_in = self.wheel_rail.stand_in

    @property
    def n_states(self) -> int:
        """Length of the state: (q, q') and, online, each wheelset's (z, z')."""
        n = 6 * len(self.model.bodies)
        return n + (2 * len(self.model.wheelsets) if self.online is not None else 0)

    @property
    def pin(self) -> np.ndarray:
        """The last evaluation's per-patch inputs (:data:`~.equations_of_motion.PATCH_IN`)."""
        return self.out.patch_in

    @property
    def pout(self) -> np.ndarray:
        """The last evaluation's per-patch outputs (:data:`~.equations_of_motion.PATCH_OUT`)."""
        return self.out.patch_out

    @property
    def wout(self) -> np.ndarray:
        """The last evaluation's per-wheelset values (:data:`~.equations_of_motion.WHEELSET_OUT`)."""
        return self.out.wheelset_out

    def rhs(self, t, u, stage: bool = False):
        """The time derivative of the state u at t [s].  ``stage``: an evaluation at
        an inner stage of a Runge-Kutta step: the online contact's Python path
        (per patch in Python) then takes the compiled stand-ins corrected at the
        step's first evaluation where its :class:`OnlineWheelRail` asks for them
        (``stand_in``) and the patches are the same (mode 4 or 3 of
        :func:`rhs_online`), and else solves its models (mode 1, the corrections
        kept: :meth:`_keep_corrections`); with both stand-ins, on the wheelsets
        whose patches are not the same alone (mode 5, the others' stand-ins kept:
        solving every wheelset's there cost 2.27 against 2.10 solves per
        evaluation in flange contact, benchmarks/dynamics_online.md)."""
        self.calls += 1
        if self.online is not None:
            on, fr = self.online, self.fext_rows
            if self.law >= 0:
                return rhs_online(t, u, self.system, on, 0, fr, self.out)
            if stage and self.stand_in == "both":
                du = rhs_online(t, u, self.system, on, 4, fr, self.out)
                if on.frame[G_MATCH] > 0.0:
                    return du
                # only the wheelsets whose patches are not their corrections' solved
                # (a patch of one wheelset appearing or moving on its rail had all
                # the wheelsets solved; benchmarks/dynamics_online.md), the others'
                # stand-ins kept
                solve = np.array([not matches(on, w, int(on.count[w]))
                                  for w in range(on.count.size)])
                rhs_online(t, u, self.system, on, 2, fr, self.out)
                self._online_python_forces(False, solve)
                du = rhs_online(t, u, self.system, on, 5, fr, self.out)
                self._keep_corrections(solve)
                return du
            rhs_online(t, u, self.system, on, 2, fr, self.out)
            lazy = stage and self.stand_in == "tangential" and on.frame[G_MATCH] > 0.0
            mode = self._online_python_forces(lazy)
            du = rhs_online(t, u, self.system, on, mode, fr, self.out)
            if mode == 1 and self.stand_in != "none":
                self._keep_corrections()
            return du
        if self.law >= 0:
            return rhs_core(t, u, self.system, 0, self.fext, self.out)
        self.fext[:] = 0.0
        rhs_core(t, u, self.system, 1, self.fext, self.out)
        for idx in np.ndindex(self.pin.shape):
            p = self.pin[idx]
            N = p["normal_force"]
            if N <= 0:
                continue
            f = python_patch_forces(self.py_model, self.material, self.friction, N, p["A"],
                                    p["B"], p["xi"], p["eta"], p["phi"], p["velocity"], (20, 20))
            sd, cd = math.sin(p["contact_angle"]), math.cos(p["contact_angle"])
            for _ in range(NORMAL_PASSES if abs(sd) >= 0.05 else 0):
                # N cos d - Fy sin d = table share
                N = max(p["normal_force"] + f[1] * sd / cd, 0.0)
                f = python_patch_forces(self.py_model, self.material, self.friction, N, p["A"],
                                        p["B"], p["xi"], p["eta"], p["phi"], p["velocity"],
                                        (20, 20))
            self.fext[idx] = (*f, N)
        return rhs_core(t, u, self.system, 1, self.fext, self.out)

    def _online_keys(self, wheelsets=None):
        """The rows of the last search: (wheelset, row, key, geometry) with the key
        (wheelset, side, flange slot, the row's rank in that slot) that follows a
        patch from one evaluation to the next (``wheelsets``: a boolean per
        wheelset, those alone)."""
        from ..geometry.track import WheelsetPose
        from ..geometry.wheel_pass import patch_geometry, row_territories
        from .online_contact import FLANGE_ANGLE
        on = self.online
        rows = []
        for w in range(on.count.size):
            if wheelsets is not None and not wheelsets[w]:
                continue
            shift, z, roll, yaw = on.poses[w]
            pose = WheelsetPose(float(shift), float(z), float(roll), float(yaw))
            seen = {}
            m = int(on.count[w])
            # each patch's territory halfway to its side's neighbours: a patch
            # solved on a grid of its own (exact) loads its own region alone (a
            # small region beside a loaded one had the neighbour's load again,
            # and the stand-ins that ratio: issue 30's spikes, docs/dynamics.md)
            lands = row_territories([on.rows[w, i] for i in range(m)])
            for i in range(m):
                row = on.rows[w, i]
                slot = (w, int(row[0]), abs(float(row[P_CONTACT_ANGLE])) > FLANGE_ANGLE)
                seen[slot] = seen.get(slot, -1) + 1
                rows.append((w, i, slot + (seen[slot],),
                             patch_geometry(row[:NPF], self.wheel_rail.wheelset,
                                            self.wheel_rail.track, pose, lands[i])))
        return rows

    def _online_python_forces(self, lazy: bool = False, wheelsets=None) -> int:
        """The creep forces and normal forces of every row of the last search with
        the registered models at the row's approach and creepages, into
        ``fext_rows``; returns the mode of :func:`rhs_online` that takes them.

        A strip model with a strip-marching tangential model (``fastsim-strips``,
        ``fastrip``): all patches together in compiled code
        (:func:`railcontact.cases.batch.solve_patches`; mode 1).  Any other pair per
        patch through its Python ``solve``: the normal problem at the row's approach
        (displacement-controlled: no balance), warm-started from the same patch's
        solution of the last evaluation and on its grid where the patch's
        potential area still fits it (``reuse_grid``: the influence coefficients
        and the pressure are then exact starts); the tangential problem
        warm-started from the same patch's last tangential solution (mode 1).
        ``lazy``: the tangential problems not solved; FASTSIM compiled at the
        normal forces stands in, corrected by the difference of the last
        solutions from it (mode 3, :func:`~.online_contact.row_forces`).
        ``wheelsets``: a boolean per wheelset, the patches of those alone solved
        (the others' rows left as they are: mode 5 takes their stand-ins)."""
        from .online_contact import R_DDOT
        on = self.online
        self.fext_rows[:] = 0.0
        nmodel, tmodel = self.py_normal, self.py_model
        damping = self.wheel_rail.damping
        self._rows = rows = self._online_keys(wheelsets)
        if self.batch and rows:
            # the strip models on all patches together, compiled
            # (railcontact.cases.batch.solve_patches)
            from ..cases.batch import solve_patches
            r = solve_patches([g for *_, g in rows], self.wheel_rail.normal, self.tangential,
                              self.material, self.friction, self.fastsim_grid)
            for k, (w, i, _, _) in enumerate(rows):
                N = max(float(r.normal_force[k]) + damping * float(on.rows[w, i, R_DDOT]),
                        1e-9)
                self.fext_rows[w, i] = (r.Fx[k], r.Fy[k], r.Mz[k], N)
            return 1
        nwarm = "warm-start" in nmodel.capabilities
        nkeep = "grid-reuse" in nmodel.capabilities
        twarm = "warm-start" in tmodel.capabilities
        warm = {}
        for w, i, key, geo in rows:
            prev = self.warm.get(key, (None, None))
            nkw = {"warm_start": prev[0]} if (prev[0] is not None and nwarm) else {}
            if nkw and nkeep:
                nkw["reuse_grid"] = prev[0]
            ns = nmodel.solve(geo, self.material, penetration=geo.approach, **nkw)
            N = max(float(ns.normal_force) + damping * float(on.rows[w, i, R_DDOT]), 1e-9)
            if lazy:
                self.fext_rows[w, i] = (0.0, 0.0, 0.0, N)
                warm[key] = (ns, prev[1])
                continue
            tkw = {"warm_start": prev[1]} if (prev[1] is not None and twarm) else {}
            ts = tmodel.solve(ns, geo, self.material, geo.creepage, self.friction,
                              geo.velocity, **tkw)
            warm[key] = (ns, ts)
            self.fext_rows[w, i] = (ts.fx, ts.fy, ts.mz, N)
        self.warm.update(warm)
        return 3 if lazy else 1

    def _keep_corrections(self, wheelsets=None):
        """After an evaluation with the models solved (mode 1): each patch's
        corrections of the stand-ins into the online contact's
        (:data:`~.online_contact.CORRECTION_FIELDS`): the normal solution's force
        over Hertz's spring's at the same approach, the tangential solution's creep
        forces less the stand-in's at the same normal force, with where the patch
        lay on the rail [m] and its grid's element across [m] (the stages that
        follow take the corrections while the patch stays within it; none for a
        patch that the spring did not load).  ``wheelsets``: a boolean per
        wheelset, those alone (the others' corrections kept)."""
        on = self.online
        keep = np.ones(on.count.size, bool) if wheelsets is None else np.asarray(wheelsets)
        on.corrected[keep] = on.count[keep]
        for w, i, key, _ in self._rows:        # (the rows of those wheelsets alone)
            row, c = on.rows[w, i], on.corrections[w, i]
            ns = self.warm[key][0]
            spring = float(row[R_SPRING])
            c[C_SIDE], c[C_FLANGE], c[C_YRAIL] = row[0], float(key[2]), row[P_Y_RAIL]
            # (a patch unloaded here has no correction: a stage that loads it is
            # solved; the tolerance -1 matches no row)
            c[C_TOL] = float(ns.y[1] - ns.y[0]) if ns.y.size > 1 and spring > 0.0 else -1.0
            c[C_RATIO] = float(ns.normal_force) / spring if spring > 0.0 else 1.0
            c[C_FX] = row[R_FX] - row[R_SFX]
            c[C_FY] = row[R_FY] - row[R_SFY]
            c[C_MZ] = row[R_MZ] - row[R_SMZ]

    def active(self) -> np.ndarray:
        """Indices of the states that are degrees of freedom (roll only where given;
        online, the wheelsets' roll and vertical position)."""
        nb = len(self.model.bodies)
        online = self.online is not None
        wsb = {w[0] for w in self.model.wheelsets}
        act = [3 * b + k for b in range(nb) for k in range(3)
               if k < 2 or self.model.bodies[b].roll or (online and b in wsb)]
        nd = 3 * nb
        act = act + [nd + i for i in act]
        if online:
            nw = len(self.model.wheelsets)
            act += list(range(2 * nd, 2 * nd + 2 * nw))
        return np.array(act)


@dataclass(frozen=True)
class Integration:
    """How a run of :func:`simulate_vehicle` is stepped, sampled and shown.

    Attributes
    ----------
    method : {"auto", "rk4", "lsoda"}
        ``"lsoda"``: SciPy's stiff-capable LSODA (switching between Adams and BDF)
        with error control (``rtol``), one Python call of the compiled right-hand
        side per evaluation.  ``"rk4"``: a compiled fixed-step Runge-Kutta loop
        (compiled laws only) whose step is bounded by the stiffness: dt <= 1 / rho
        with rho the spectral radius of the linearised model at this speed (RK4 is
        stable up to 2.78 / rho), by 1 ms and by the sampling interval.
        ``"auto"``: rk4 for compiled laws.
    sample_rate : float
        Output samples per second [Hz].
    rtol : float
        Relative tolerance of LSODA.
    max_step : float, optional
        Upper bound of LSODA's step [s].
    step : float, optional
        Upper bound of the rk4 step [s].
    progress : bool
        Show a progress bar.
    """

    method: str = "auto"
    sample_rate: float = 100.0
    rtol: float = 1e-6
    max_step: float | None = None
    step: float | None = None
    progress: bool = False

    def __post_init__(self):
        if self.method not in ("auto", "rk4", "lsoda"):
            raise InputError(f"integrator {self.method!r}: expected 'auto', 'rk4' or 'lsoda'")
        if not (isinstance(self.sample_rate, (int, float)) and 0 < self.sample_rate <= 1e5):
            raise InputError(f"simulation sample_rate {self.sample_rate!r} Hz: expected "
                             "(0, 1e5]")


def simulate_vehicle(model: VehicleModel, route: Route, table,
                     velocity: float, duration: float, tangential: str = "fastsim",
                     friction: float = 0.3, material: Material = STEEL,
                     initial_lateral_shift: float = 0.0,
                     tangential_options: dict | None = None, fastsim_grid=(12, 12),
                     integration: Integration = Integration()):
    """Run ``model`` over ``route`` at constant ``velocity`` [m/s] for ``duration`` [s].

    The compiled right-hand side is stepped by RK4 (compiled laws) or LSODA, and
    sampled at ``integration.sample_rate`` [Hz].

    Parameters
    ----------
    table : WheelRailTable, sequence of WheelRailTable or OnlineWheelRail
        The contact table of every wheelset, or one per wheelset (worn wheelsets,
        on one shift grid); or the contact searched online
        (:class:`~railcontact.dynamics.online_contact.OnlineWheelRail`: every
        wheelset with vertical and roll freedom, starting from its static
        equilibrium; the run ends where a wheel derails).
    tangential : str
        ``"linear"``, ``"fastsim"``, ``"polach"`` (compiled) or any registered
        tangential model (Python, slow).
    initial_lateral_shift : float
        Lateral displacement [m] of every wheelset at t = 0 (a perturbation).
    integration : Integration
        The integrator, its tolerance and steps, the sampling and the progress bar.

    Returns
    -------
    xarray.Dataset
        See :func:`_dataset` and docs/dynamics.md.
    """
    sample_rate, progress = integration.sample_rate, integration.progress
    if not (isinstance(duration, (int, float)) and 0 < duration <= 1e5):
        raise InputError(f"simulation duration {duration!r} s: expected a value in (0, 1e5]")
    if not (isinstance(initial_lateral_shift, (int, float)) and abs(initial_lateral_shift) < 0.02):
        raise InputError(f"initial_lateral_shift {initial_lateral_shift!r} m: expected |y| < 0.02")
    sysm = _System(model, route, table, velocity, tangential, friction, material,
                   tangential_options, fastsim_grid)
    u0 = np.zeros(sysm.n_states)
    for w in model.wheelsets:
        u0[3 * w[0]] = initial_lateral_shift
    if sysm.online is not None:
        u0 = static_contact(sysm, u0)
    t_eval = np.arange(0.0, duration + 0.5 / sample_rate, 1.0 / sample_rate)
    t_eval = t_eval[t_eval <= duration]
    bar = tqdm(total=round(duration, 3), unit="s", desc=f"simulate {model.name}",
               disable=not progress, bar_format="{l_bar}{bar}| {n:.2f}/{total:.2f} s "
                                                 "[{elapsed}<{remaining}]")
    state = {"shown": 0.0}

    def f(t, u):
        if progress and t - state["shown"] > 0.01 * duration:
            bar.update(round(t - state["shown"], 3))
            state["shown"] = t
        return sysm.rhs(t, u)

    integrator = integration.method
    if integrator == "auto":
        integrator = "rk4" if sysm.law >= 0 or sysm.online is not None else "lsoda"
    if sysm.online is not None:
        if integrator != "rk4":
            raise InputError(f"integrator {integrator!r} with the online contact: expected "
                             "'rk4' (or 'auto'), whose loop stops at a derailment")
        return _run_rk4_online(sysm, u0, duration, sample_rate, integration.step, bar)
    if integrator == "rk4":
        if sysm.law < 0:
            raise InputError(f"integrator 'rk4' needs a compiled creep law (linear, fastsim, "
                             f"polach), not {tangential!r}; use 'lsoda'")
        return _run_rk4(sysm, u0, duration, sample_rate, integration.step, progress, bar)
    wall = time.perf_counter()
    try:
        sol = solve_ivp(f, (0.0, duration), u0, method="LSODA", t_eval=t_eval,
                        rtol=integration.rtol, atol=1e-9, max_step=integration.max_step or np.inf)
    finally:
        bar.update(max(round(duration - state["shown"], 3), 0))
        bar.close()
    wall = time.perf_counter() - wall
    if not sol.success:
        raise RailContactError(f"simulation failed at t = {sol.t[-1]:.4g} s: {sol.message}")
    return _dataset(sysm, sol.t, sol.y, wall)


def rk4_step(sysm: _System, sample_rate: float, step: float | None = None):
    """The rk4 step [s]: 1 / spectral radius of the linearised model at this speed
    (linear creep, centred on tangent track), at most 1 ms, ``step`` and the
    sampling interval, which it divides exactly.  Returns (step, steps per sample)."""
    J = state_matrix(sysm.model, sysm.tables, sysm.V, material=sysm.material)
    rho = float(np.max(np.abs(np.linalg.eigvals(J))))
    dt = min(1.0 / rho, 1e-3, step or 1.0, 1.0 / sample_rate)
    every = int(math.ceil(1.0 / (sample_rate * dt)))
    return 1.0 / (sample_rate * every), every


def _sample_arrays(u0, duration, sample_rate):
    """The rk4 runs' output: the number of samples, their times [s], the state
    array with ``u0`` in its first row, the working state and the progress chunk."""
    n_samples = int(math.floor(duration * sample_rate + 1e-9))
    t = np.arange(n_samples + 1) / sample_rate
    Y = np.empty((n_samples + 1, u0.size))
    Y[0] = u0
    return n_samples, t, Y, u0.copy(), max(1, n_samples // 100)


def _run_rk4(sysm: _System, u0, duration, sample_rate, step, progress, bar):
    dt, every = rk4_step(sysm, sample_rate, step)
    n_samples, t, Y, u, chunk = _sample_arrays(u0, duration, sample_rate)
    wall = time.perf_counter()
    try:
        for k0 in range(0, n_samples, chunk):
            k1 = min(k0 + chunk, n_samples)
            u = rk4_run(u, t[k0], dt, (k1 - k0) * every, every, sysm.system, sysm.fext, sysm.out,
                        Y[k0 + 1:k1 + 1])
            if not np.all(np.isfinite(u)):
                raise RailContactError(f"simulation diverged before t = {t[k1]:.4g} s (rk4, "
                                       f"step {dt:.3g} s); try integrator = 'lsoda'")
            bar.update(max(min(round(float(t[k1]), 3), bar.total) - bar.n, 0))  # not past it
    finally:
        bar.close()
    wall = time.perf_counter() - wall
    sysm.calls = 4 * n_samples * every
    ds = _dataset(sysm, t, Y.T, wall)
    ds.attrs.update(integrator="rk4", step_s=dt)
    return ds


def static_contact(sysm: _System, u0, passes: int = 8) -> np.ndarray:
    """The state ``u0`` with every wheelset's vertical position and roll set to its
    static equilibrium on the online contact (Newton steps on the vertical and roll
    accelerations at rest, from the pose of the geometry layer's search at the
    static wheel load)."""
    from ..geometry import find_contact
    from ..geometry.wheel_pass import new_memo
    from .vehicle import G_ACC
    model, on = sysm.model, sysm.online
    nb = len(model.bodies)
    nd = 3 * nb
    u = u0.copy()
    wr = sysm.wheel_rail
    zi = [2 * nd + w for w in range(len(model.wheelsets))]
    ri = [3 * w[0] + 2 for w in model.wheelsets]
    trk = sysm.system.track
    for w, ws in enumerate(model.wheelsets):
        s = sysm.s0 + model.bodies[ws[0]].x          # relative to the rails there
        ya = float(np.interp(s, trk.irregularity_s, trk.alignment))
        cl = float(np.interp(s, trk.irregularity_s, trk.cross_level))
        c = find_contact(wr.wheelset, wr.track, float(u0[3 * ws[0]]) - ya, 0.0,
                         vertical_force=ws[1] * G_ACC / 2, material=wr.material)
        u[zi[w]], u[ri[w]] = c.pose.vertical, c.pose.roll + cl
        on.memo[w] = new_memo(c.pose.roll)
    nz = len(zi)
    for _ in range(passes):
        r0 = sysm.rhs(0.0, u)
        res = np.concatenate([r0[[z + nz for z in zi]], r0[[nd + i for i in ri]]])
        log.debug("static contact: residuals %s", res)
        if np.all(np.abs(res) < 1e-6):
            break
        J = np.zeros((2 * nz, 2))
        for c_, (idx, h) in enumerate(((zi, 1e-7), (ri, 1e-7))):
            du = u.copy()
            du[idx] += h
            r1 = sysm.rhs(0.0, du)
            J[:, c_] = (np.concatenate([r1[[z + nz for z in zi]], r1[[nd + i for i in ri]]])
                        - res) / h
        for w in range(nz):        # each wheelset's 2 x 2 block (they do not couple)
            A = np.array([[J[w, 0], J[w, 1]], [J[nz + w, 0], J[nz + w, 1]]])
            try:
                dz, dr = np.linalg.solve(A, [-res[w], -res[nz + w]])
            except np.linalg.LinAlgError:
                continue
            u[zi[w]] += max(min(dz, 1e-4), -1e-4)
            u[ri[w]] += max(min(dr, 1e-3), -1e-3)
    return u


#: the rk4 step [s] of an online run with a compiled strip model at most (None: the
#: step of the Jacobian at the start, as Hertz's).  With the step of the Jacobian
#: (0.71 ms) and no stiffness of the strip springs (their rows' R_STIFF 0, so that
#: no step was divided) the Manchester vehicle's 100 s run with ANALYN +
#: fastsim-strips diverged at 75 s in the curve, and 0.5 ms bounded the step; the
#: strip springs' stiffness divides the steps where the contact stiffens, as
#: Hertz's (benchmarks/dynamics_online.md)
STRIP_ONLINE_STEP = None


def online_step(sysm: _System, u0, sample_rate: float, step: float | None = None):
    """The rk4 step [s] of an online run: 1 / spectral radius of the Jacobian of the
    right-hand side at the start (by central differences over the degrees of
    freedom: the wheel-rail contact's vertical and roll modes, the creep forces),
    at most 1 ms, ``step``, the sampling interval, which it divides exactly, and
    with a compiled strip model ``STRIP_ONLINE_STEP`` (None: no bound).
    Returns (step, steps per sample)."""
    act = sysm.active()
    J = np.empty((act.size, act.size))
    memo = sysm.online.memo.copy()
    for c, i in enumerate(act):
        h = 1e-8 if i < 3 * len(sysm.model.bodies) or i >= 6 * len(sysm.model.bodies) \
            else 1e-6
        du = np.zeros(u0.size)
        du[i] = h
        J[:, c] = (sysm.rhs(0.0, u0 + du)[act] - sysm.rhs(0.0, u0 - du)[act]) / (2 * h)
    sysm.online.memo[:] = memo
    rho = float(np.max(np.abs(np.linalg.eigvals(J))))
    dt = min(1.0 / rho, 1e-3, step or 1.0, 1.0 / sample_rate)
    if sysm.online.model.strips.rule.code >= 0 and STRIP_ONLINE_STEP is not None:
        dt = min(dt, STRIP_ONLINE_STEP)
    every = int(math.ceil(1.0 / (sample_rate * dt)))
    return 1.0 / (sample_rate * every), every


def _run_rk4_online(sysm: _System, u0, duration, sample_rate, step, bar):
    """The rk4 run of the online contact: compiled (:func:`rk4_online`) with a
    compiled law, else a Python loop of the same steps; it ends where a wheel
    derails (the dataset's ``derailment`` attribute says when and which)."""
    dt, every = online_step(sysm, u0, sample_rate, step)
    n_samples, t, Y, u, chunk = _sample_arrays(u0, duration, sample_rate)
    written = n_samples
    wall = time.perf_counter()
    steps = 0
    try:
        for k0 in range(0, n_samples, chunk):
            k1 = min(k0 + chunk, n_samples)
            if sysm.law >= 0:
                u, k, n = rk4_online(u, t[k0], dt, (k1 - k0) * every, every, sysm.system,
                                     sysm.online, sysm.fext_rows, sysm.out,
                                     Y[k0 + 1:k1 + 1])
            else:
                u, k, n = _rk4_python(sysm, u, t[k0], dt, (k1 - k0) * every, every,
                                      Y[k0 + 1:k1 + 1])
            steps += n
            if not np.all(np.isfinite(u)):
                raise RailContactError(f"simulation diverged before t = {t[k1]:.4g} s (rk4 "
                                       f"online, step {dt:.3g} s)")
            if n < (k1 - k0) * every:                    # a wheel derailed
                written = k0 + k
                break
            bar.update(max(min(round(float(t[k1]), 3), bar.total) - bar.n, 0))
    finally:
        bar.close()
    wall = time.perf_counter() - wall
    # (the compiled loop's steps in the contact's substeps: rk4_online)
    made = int(sysm.online.count_substeps[0]) if sysm.law >= 0 else steps
    sysm.calls = 4 * made
    t_der = steps * dt
    status = sysm.online.status.copy()
    ds = _dataset(sysm, t[:written + 1], Y[:written + 1].T, wall)
    ds.attrs.update(integrator="rk4", step_s=dt, contact_mode="online", rk4_steps=made,
                    rk4_substepped=made - steps)
    if written < n_samples:
        w, side = (int(v) for v in np.argwhere(status != 0)[0])
        code = int(status[w, side])
        yq = np.abs(np.nan_to_num(ds["Y_over_Q"].isel(wheelset=w, side=side).values))
        k = int(np.argmax(yq))
        what = ("stands on its flange tip" if code == ON_FLANGE_TIP else
                "runs off the rail" if code == OFF_RAIL else "derails")
        msg = (f"derailment at t = {t_der:.4f} s: wheelset {w + 1}, "
               f"{('left', 'right')[side]} wheel {what} (largest |Y/Q| {yq[k]:.2f} at "
               f"t = {float(t[k]):.3f} s, {yq[-1]:.2f} at the last sample; Nadal's limit "
               f"{ds.attrs['nadal_limit']:.2f}); the run ends there")
        log.warning("%s", msg)
        ds.attrs.update(status="derailed", derailment=msg, derailment_time_s=t_der,
                        derailment_wheelset=w + 1, derailment_side=("left", "right")[side])
        ds.attrs["warnings"] = "; ".join(x for x in (msg, ds.attrs["warnings"]) if x)
    return ds


def _rk4_python(sysm: _System, u, t0, dt, n_steps, every, samples):
    """:func:`rk4_online`'s steps with the right-hand side in Python (a tangential
    model without a compiled law: its ``solve`` per patch, at each step's first
    evaluation or at every one, :class:`~.online_contact.OnlineWheelRail`'s
    ``tangential_solves``; the steps' inner stages marked as such)."""
    k = 0
    for n in range(n_steps):
        t = t0 + n * dt
        k1 = sysm.rhs(t, u)
        if np.any(sysm.online.status != 0):
            return u, k, n
        k2 = sysm.rhs(t + 0.5 * dt, u + 0.5 * dt * k1, stage=True)
        k3 = sysm.rhs(t + 0.5 * dt, u + 0.5 * dt * k2, stage=True)
        k4 = sysm.rhs(t + dt, u + dt * k3, stage=True)
        u = u + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
        if (n + 1) % every == 0 and k < samples.shape[0]:
            samples[k] = u
            k += 1
    return u, k, n_steps


def _dataset(sysm: _System, t, Y, wall):
    import xarray as xr
    model = sysm.model
    calls = sysm.calls
    nt = t.size
    nw = len(model.wheelsets)
    pin = np.zeros((nt,) + sysm.pin.shape, sysm.pin.dtype)
    pout = np.zeros((nt,) + sysm.pout.shape, sysm.pout.dtype)
    wout = np.zeros((nt,) + sysm.wout.shape, sysm.wout.dtype)
    for i in range(nt):
        sysm.rhs(t[i], Y[:, i])
        pin[i], pout[i], wout[i] = sysm.pin, sysm.pout, sysm.wout
    nb = len(model.bodies)
    q = Y[:3 * nb].reshape(nb, 3, nt)
    wi = [w[0] for w in model.wheelsets]
    V = sysm.V
    s_first = sysm.s0 + V * t + model.bodies[wi[0]].x
    kap, cant = sysm.route.at(s_first)
    dims_p = ("time", "wheelset", "side", "patch")
    dims_w = ("time", "wheelset", "side")
    Q = pout["Q"].sum(axis=3)
    Yf = pout["Y"].sum(axis=3)
    with np.errstate(divide="ignore", invalid="ignore"):
        YQ = np.where(Q > 0, Yf / Q, np.nan)
    data = {
        "body_lateral_displacement": (("time", "body"), q[:, 0].T, {"units": "m"}),
        "body_yaw": (("time", "body"), q[:, 1].T, {"units": "rad"}),
        "body_roll": (("time", "body"), q[:, 2].T, {"units": "rad"}),
        "lateral_displacement": (("time", "wheelset"), q[wi, 0].T,
                                 {"units": "m", "long_name": "wheelset lateral displacement "
                                  "relative to the design track"}),
        "yaw": (("time", "wheelset"), q[wi, 1].T,
                {"units": "rad", "long_name": "wheelset yaw relative to the track tangent"}),
        "relative_shift": (("time", "wheelset"), wout["relative_shift"],
                           {"units": "m", "long_name": "wheelset shift relative to the rails"}),
        "load_left": (("time", "wheelset"), wout["load_left"], {"units": "N"}),
        "load_right": (("time", "wheelset"), wout["load_right"], {"units": "N"}),
        "normal_force": (dims_w, pin["normal_force"].sum(axis=3), {"units": "N"}),
        "longitudinal_force": (dims_w, pout["Fx"].sum(axis=3),
                               {"units": "N", "long_name": "creep force Fx on the wheel"}),
        "lateral_creep_force": (dims_w, pout["Fy"].sum(axis=3),
                                {"units": "N", "long_name": "creep force Fy on the wheel, "
                                 "contact plane"}),
        "Y": (dims_w, Yf, {"units": "N", "long_name": "lateral force of the rail on the "
                           "wheel, track plane"}),
        "Q": (dims_w, Q, {"units": "N", "long_name": "vertical force of the rail on the wheel"}),
        "Y_over_Q": (dims_w, YQ, {"units": "1"}),
        "Tgamma": (dims_w, pout["Tgamma"].sum(axis=3), {"units": "N",
                                                      "long_name": "wear number T gamma"}),
        "patch_normal_force": (dims_p, pin["normal_force"], {"units": "N"}),
        "patch_Fx": (dims_p, pout["Fx"], {"units": "N"}),
        "patch_Fy": (dims_p, pout["Fy"], {"units": "N"}),
        "patch_Mz": (dims_p, pout["Mz"], {"units": "N m"}),
        "creepage_longitudinal": (dims_p, pin["xi"], {"units": "1"}),
        "creepage_lateral": (dims_p, pin["eta"], {"units": "1"}),
        "creepage_spin": (dims_p, pin["phi"], {"units": "1/m"}),
        "contact_angle": (dims_p, pin["contact_angle"], {"units": "rad"}),
        "y_rail": (dims_p, np.where(pin["normal_force"] > 0, pin["y_rail"], np.nan),
                   {"units": "m", "long_name": "contact position on the rail profile"}),
        "y_wheel": (dims_p, np.where(pin["normal_force"] > 0, pin["y_wheel"], np.nan),
                    {"units": "m", "long_name": "contact position on the wheel profile"}),
        "semi_axis_a": (dims_p, pin["a"], {"units": "m"}),
        "semi_axis_b": (dims_p, pin["b"], {"units": "m"}),
        "wheelset_vertical": (("time", "wheelset"), wout["vertical"],
                              {"units": "m", "long_name": "wheelset vertical position "
                               "relative to the rails, down (online contact; 0 with a table)"}),
        "wheelset_roll": (("time", "wheelset"), wout["roll"],
                          {"units": "rad", "long_name": "wheelset roll relative to the rails "
                           "(online contact; 0 with a table)"}),
        "distance": ("time", s_first, {"units": "m", "long_name": "position of wheelset 1"}),
        "curvature": ("time", kap, {"units": "1/m"}),
        "cant": ("time", cant, {"units": "rad"}),
    }
    ds = xr.Dataset(data, coords={
        "time": ("time", t, {"units": "s"}),
        "body": ("body", [b.name for b in model.bodies]),
        "wheelset": ("wheelset", np.arange(1, nw + 1)),
        "side": ("side", ["left", "right"]), "patch": ("patch", ["tread", "flange"])},
        attrs={"model": model.name, "velocity_m_s": V, "tangential": sysm.tangential,
               "friction": sysm.friction, "total_mass_kg": model.total_mass,
               "rhs_calls": calls, "wall_time_s": wall,
               "outside_table": int(wout["outside_table"].any()) if nt else 0,
               "contact_mode": "table" if sysm.online is None else "online",
               "status": "completed", "nadal_limit": nadal_limit(sysm.flange_angle,
                                                                 sysm.friction)
               if math.isfinite(sysm.flange_angle) else math.nan,
               "flange_angle_rad": sysm.flange_angle})
    warnings = _validity(sysm, t, YQ, pin["normal_force"][..., 1] > 0)
    if ds.attrs["outside_table"]:
        warnings.insert(0, "a wheelset left the contact table's range: the contact was "
                           "clamped to the table's edge; build the table with a larger range")
    for w in warnings:                 # in the result; the CLI prints them
        log.info("%s", w)
    ds.attrs["warnings"] = "; ".join(warnings)
    return ds


def _validity(sysm: _System, t, YQ, flange_loaded) -> list:
    """Where a run left the range of its models: Y/Q of a wheel in flange contact
    above Nadal's flange-climb limit (the wheels' largest flange angle, the run's
    friction; :func:`railcontact.geometry.validity.nadal_limit`)."""
    angle = sysm.flange_angle
    if not (math.isfinite(angle) and YQ.size):
        return []
    limit = nadal_limit(angle, sysm.friction)
    over = flange_loaded & (np.abs(np.nan_to_num(YQ)) > limit)
    out = []
    for w, j in zip(*np.nonzero(over.any(axis=0))):
        k = int(np.argmax(np.where(over[:, w, j], np.abs(YQ[:, w, j]), -1.0)))
        out.append(f"flange climb: wheelset {w + 1}, {('left', 'right')[j]} wheel: |Y/Q| "
                   f"{abs(YQ[k, w, j]):.2f} at t = {t[k]:.3f} s exceeds Nadal's limit "
                   f"{limit:.2f} (flange angle {math.degrees(angle):.1f} deg, friction "
                   f"{sysm.friction:g})")
    return out


# --------------------------------------------------------------- linear stability
def state_matrix(model: VehicleModel, table: WheelRailTable, velocity: float,
                 tangential: str = "linear", material: Material = STEEL,
                 step: float = 1e-7) -> np.ndarray:
    """State matrix of the model on tangent track about the centred position, by
    central differences of the compiled right-hand side (exact for the ``linear``
    law on a table that is linear in the shift), reduced to the degrees of freedom."""
    sysm = _System(model, Route.tangent(), table, velocity, tangential, 0.3, material)
    act = sysm.active()
    n = 6 * len(model.bodies)
    u0 = np.zeros(n)
    J = np.empty((act.size, act.size))
    for c, i in enumerate(act):
        du = np.zeros(n)
        du[i] = step
        J[:, c] = (sysm.rhs(0.0, u0 + du)[act] - sysm.rhs(0.0, u0 - du)[act]) / (2 * step)
    return J


def critical_speed(model: VehicleModel, table: WheelRailTable, v_min: float = 1.0,
                   v_max: float = 200.0, material: Material = STEEL) -> float:
    """Linear critical speed [m/s]: the speed where the largest real part of the
    eigenvalues of :func:`state_matrix` crosses zero (linear creep law)."""
    def growth(v):
        return float(np.max(np.linalg.eigvals(state_matrix(model, table, v,
                                                           material=material)).real))
    if growth(v_min) > 0:
        raise InputError(f"critical_speed: already unstable at {v_min} m/s")
    if growth(v_max) < 0:
        raise InputError(f"critical_speed: stable up to {v_max} m/s")
    return brentq(growth, v_min, v_max, xtol=1e-4)


def amplitude_growth(model: VehicleModel, table: WheelRailTable, velocity: float,
                     duration: float, y0: float = 1e-4, tangential: str = "linear") -> float:
    """Ratio of the largest wheelset displacement in the last quarter of a run on
    tangent track to that in the first quarter (> 1: unstable)."""
    ds = simulate_vehicle(model, Route.tangent(velocity * duration + 100), table, velocity,
                          duration, tangential, initial_lateral_shift=y0,
                          integration=Integration(sample_rate=200.0, rtol=1e-8))
    y = np.abs(ds["lateral_displacement"].values).max(axis=1)
    n = y.size
    return float(y[-n // 4:].max() / y[:n // 4].max())
