"""A dynamics scenario as a typed configuration (:class:`DynamicsScenario`) and its
run (``railcontact simulate``, see docs/dynamics.md).

The scenario's own sections, ``[vehicle]``, ``[route]`` and ``[simulation]``, are
parsed here, once, into typed values (:func:`scenario_from_sections`); the wheel
and rail sections are a case's, parsed by the case layer where the file enters
(:func:`railcontact.inputs.load_dynamics_scenario`), and arrive as the built
wheelset and track.  :func:`run_scenario` and :func:`simulate_batch` take parsed
scenarios, never a path.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from ..core.errors import CaseFileError, InputError, RailContactError
from ..core.files import read_toml, write_netcdf, write_text
from ..core.materials import Material
from ..core.parallel import compute
from ..geometry.track import Track, Wheelset
from ..tangential import tangential_models
from .online_contact import DEFAULT_DAMPING, STAND_IN, OnlineWheelRail
from .route import Irregularities, Route
from .simulation import Integration, critical_speed, simulate_vehicle
from .vehicle import G_ACC, MANCHESTER, VehicleModel
from .wheel_rail import WheelRailTable

_VEHICLE = {"model", "preset", "parameters", "parameter_file", "mass", "yaw_inertia", "k_y", "k_psi",
            "wheel_load"}
_SIM = {"velocity", "duration", "initial_lateral_shift", "sample_rate", "table_range",
        "table_step", "tangential", "tangential_options", "fastsim_grid", "rtol",
        "history_wheelset", "integrator", "step", "contact", "alpha"}
_IRR = {"spectrum", "seed", "wavelengths", "step", "file"}
_CONTACT = {"mode", "damping", "normal", "roll_inertia", "stand_in"}
#: how the dynamics finds the wheel-rail contact (``contact.mode``): a table over the
#: lateral shift built before the run, or a search at every evaluation
CONTACT_MODES = ("table", "online")


def _num(sec, name, key, default, lo, hi):
    v = sec.get(key, default)
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not lo <= v <= hi:
        raise CaseFileError(f"{name}.{key} = {v!r}: expected a value in [{lo:g}, {hi:g}]")
    return float(v)


def write_history(ds, path, wheelset: int = 1):
    """Write one wheelset of a run as a time history in the format of
    ``wear.history`` (docs/wear.md): time, lateral_shift (relative to the rails),
    yaw, the wheel loads and the velocity."""
    path = Path(path)
    v = float(ds.attrs["velocity_m_s"])
    w = ds.sel(wheelset=wheelset)
    rows = ["time,lateral_shift,yaw,vertical_force_left,vertical_force_right,velocity"]
    for t, y, psi, ql, qr in zip(ds["time"].values, w["relative_shift"].values,
                                 w["yaw"].values, w["load_left"].values, w["load_right"].values):
        rows.append(f"{t:.6g},{y:.9g},{psi:.9g},{ql:.6g},{qr:.6g},{v:.6g}")
    return write_text(path, "\n".join(rows) + "\n")


def creep_law_settings(section: dict, name: str) -> tuple:
    """The dynamics' creep-law settings of a section (``[simulation]`` of a dynamics
    scenario, ``[dynamics]`` of a wear scenario), checked: the tangential model
    (compiled online or per patch), FASTSIM's grid [nx, ny] and the integrator."""
    tang = section.get("tangential", "fastsim")
    if tang not in tangential_models():
        raise CaseFileError(f"{name}.tangential = {tang!r}: expected one of "
                            f"{tangential_models()}")
    grid = section.get("fastsim_grid", [12, 12])
    if not (isinstance(grid, list) and len(grid) == 2 and all(isinstance(g, int) for g in grid)):
        raise CaseFileError(f"{name}.fastsim_grid = {grid!r}: expected [nx, ny] integers")
    integ = section.get("integrator", "auto")
    if integ not in ("auto", "rk4", "lsoda"):
        raise CaseFileError(f"{name}.integrator = {integ!r}: expected 'auto', 'rk4' or "
                            "'lsoda'")
    return tang, grid, integ


def vehicle_length(model: VehicleModel) -> float:
    """Distance [m] from the vehicle's last body to its first along the track."""
    return max(b.x for b in model.bodies) - min(b.x for b in model.bodies)


def vehicle_from_section(veh: dict, base_dir: Path | None = None) -> VehicleModel:
    """The ``[vehicle]`` table: model, preset, a parameter file and overrides (in
    that order of precedence, the last winning)."""
    bad = set(veh) - _VEHICLE
    if bad:
        raise CaseFileError(f"unknown key(s) vehicle.{sorted(bad)}; expected {sorted(_VEHICLE)}")
    model = veh.get("model", "vehicle")
    if model not in ("wheelset", "bogie", "vehicle"):
        raise CaseFileError(f"vehicle.model = {model!r}: expected 'wheelset', 'bogie' or "
                            "'vehicle'")
    preset = veh.get("preset", "manchester")
    if preset != "manchester":
        raise CaseFileError(f"vehicle.preset = {preset!r}: expected 'manchester'")
    params = {}
    if "parameter_file" in veh:
        pf = Path(base_dir or Path.cwd()) / str(veh["parameter_file"])
        params = read_toml(pf, "vehicle parameter file")
        if not all(isinstance(v, (int, float, list)) for v in params.values()):
            raise CaseFileError(f"{pf}: expected a flat table of parameter = value (SI units)")
    over = veh.get("parameters", {})
    if not isinstance(over, dict):
        raise CaseFileError("vehicle.parameters: expected a table of parameter = value")
    params.update(over)
    unknown = set(params) - set(MANCHESTER)
    if unknown:
        raise CaseFileError(f"unknown vehicle parameters {sorted(unknown)}; expected some of "
                            f"{sorted(MANCHESTER)}")
    legacy = {"mass", "yaw_inertia", "k_y", "k_psi", "wheel_load"} & set(veh)
    try:
        if model == "wheelset" and legacy:
            return VehicleModel.single_wheelset(
                _num(veh, "vehicle", "mass", 1813.0, 1.0, 1e6),
                _num(veh, "vehicle", "yaw_inertia", 1120.0, 1e-3, 1e6),
                _num(veh, "vehicle", "k_y", 0.0, 0.0, 1e10),
                _num(veh, "vehicle", "k_psi", 0.0, 0.0, 1e10),
                wheel_load=_num(veh, "vehicle", "wheel_load", 75e3, 1.0, 1e7))
        if legacy:
            raise CaseFileError(f"vehicle keys {sorted(legacy)} belong to model = 'wheelset'; "
                                "give the others under [vehicle.parameters]")
        return VehicleModel.from_parameters(model, params)
    except InputError as exc:
        if isinstance(exc, CaseFileError):
            raise
        raise CaseFileError(str(exc)) from None


def route_from_section(route: dict, base_dir: Path, length: float) -> Route:
    """The ``[route]`` table: ``[[route.segment]]`` and ``[route.irregularities]``."""
    bad = set(route) - {"segment", "irregularities"}
    if bad:
        raise CaseFileError(f"unknown key(s) route.{sorted(bad)}; expected segment, "
                            "irregularities")
    segs = route.get("segment", [{"type": "tangent", "length": max(length, 1.0)}])
    irr = route.get("irregularities")
    irregularities = None
    if irr is not None:
        bad = set(irr) - _IRR
        if bad:
            raise CaseFileError(f"unknown key(s) route.irregularities.{sorted(bad)}; expected "
                                f"{sorted(_IRR)}")
        if "file" in irr:
            irregularities = Irregularities.from_file(Path(base_dir) / str(irr["file"]))
        else:
            wl = irr.get("wavelengths", [3.0, 120.0])
            if not (isinstance(wl, list) and len(wl) == 2):
                raise CaseFileError(f"route.irregularities.wavelengths = {wl!r}: expected "
                                    "[shortest, longest] in m")
            seed = irr.get("seed", 0)
            if isinstance(seed, bool) or not isinstance(seed, int):
                raise CaseFileError(f"route.irregularities.seed = {seed!r}: expected an integer")
            try:
                irregularities = Irregularities.from_psd(
                    length, str(irr.get("spectrum", "ERRI-low")), seed, wl,
                    _num(irr, "route.irregularities", "step", 0.25, 0.01, 5.0))
            except InputError as exc:
                raise CaseFileError(str(exc)) from None
    try:
        return Route.from_segments(segs, irregularities)
    except CaseFileError:
        raise
    except InputError as exc:
        raise CaseFileError(str(exc)) from None


@dataclass(frozen=True)
class DynamicsScenario:
    """A dynamics scenario, validated, in SI units.

    Bodies: ``model`` (the vehicle), ``route``, ``wheelset`` and ``track`` (the
    profiles as placed), ``material`` and ``friction``.  Run: ``velocity`` [m/s],
    ``duration`` [s], ``initial_lateral_shift`` [m], ``sample_rate`` [Hz]; the creep
    law: ``tangential`` (a registered model), ``tangential_options``,
    ``fastsim_grid`` [nx, ny], ``integrator`` ("auto", "rk4", "lsoda"), ``step`` [s]
    of the fixed-step integrator and ``rtol`` of LSODA; the contact table:
    ``table_range`` and ``table_step`` [m] of lateral shift, ``contact``
    ("multi-hertz" or "quasi-elastic": Arnold's, regularisation ``alpha`` [m]).  Output:
    ``history_wheelset``, the wheelset (1-based) whose time history is written.
    Online contact (``[contact]``): ``contact_mode`` ("table" or "online": the
    contact searched at every evaluation, :mod:`railcontact.dynamics.online_contact`),
    ``contact_damping`` [N s/m] per patch, ``contact_normal`` (the normal model of
    a tangential model without a compiled law), ``wheelset_roll_inertia``
    [kg m²] (0: the wheelset's yaw inertia) and ``contact_stand_in`` (what the
    compiled stand-ins take over from such models at the inner stages of each rk4
    step: "both", "tangential" or "none";
    :class:`~railcontact.dynamics.online_contact.OnlineWheelRail`).
    """

    model: VehicleModel
    route: Route
    wheelset: Wheelset
    track: Track
    material: Material
    friction: float
    velocity: float = 30.0
    duration: float = 5.0
    tangential: str = "fastsim"
    tangential_options: dict = field(default_factory=dict)
    fastsim_grid: tuple = (12, 12)
    integrator: str = "auto"
    step: float = 1e-3
    rtol: float = 1e-6
    initial_lateral_shift: float = 0.0
    sample_rate: float = 100.0
    table_range: float = 0.012
    table_step: float = 2e-4
    history_wheelset: int = 1
    title: str = ""
    contact: str = "multi-hertz"
    alpha: float = 3e-5
    contact_mode: str = "table"
    contact_damping: float = DEFAULT_DAMPING
    contact_normal: str = "hertz"
    wheelset_roll_inertia: float = 0.0
    contact_stand_in: str = "both"


def scenario_from_sections(sections: dict, base_dir: Path, bodies) -> DynamicsScenario:
    """The :class:`DynamicsScenario` of a scenario file's ``[vehicle]``, ``[route]``
    and ``[simulation]`` tables (``sections``, with ``title``), its parameter and
    irregularity files relative to ``base_dir``.

    ``bodies()`` gives (Wheelset, Track, Material, friction coefficient) from the
    file's case sections; it is called once these sections are valid.  A
    :class:`~railcontact.core.errors.CaseFileError` names the first key that is
    wrong; nothing is computed."""
    sim = sections.get("simulation", {})
    bad = set(sim) - _SIM
    if bad:
        raise CaseFileError(f"unknown key(s) simulation.{sorted(bad)}; expected {sorted(_SIM)}")
    model = vehicle_from_section(sections.get("vehicle", {}), base_dir)
    v = _num(sim, "simulation", "velocity", 30.0, 0.1, 200.0)
    duration = _num(sim, "simulation", "duration", 5.0, 1e-3, 1e5)
    rt = route_from_section(sections.get("route", {}), base_dir,
                            v * duration + vehicle_length(model) + 10.0)
    tang, grid, integ = creep_law_settings(sim, "simulation")
    hw = sim.get("history_wheelset", 1)
    if isinstance(hw, bool) or not isinstance(hw, int) or not 1 <= hw <= len(model.wheelsets):
        raise CaseFileError(f"simulation.history_wheelset = {hw!r}: expected 1 to "
                            f"{len(model.wheelsets)}")
    options = sim.get("tangential_options", {})
    if not isinstance(options, dict):
        raise CaseFileError(f"simulation.tangential_options = {options!r}: expected a table")
    cmode, cdamp, cnormal, croll, cstand = _contact_section(sections.get("contact", {}))
    wheelset, track, material, friction = bodies()
    return DynamicsScenario(
        model=model, route=rt, wheelset=wheelset, track=track, material=material,
        friction=float(friction), velocity=v, duration=duration, tangential=tang,
        tangential_options=dict(options), fastsim_grid=tuple(grid), integrator=integ,
        step=_num(sim, "simulation", "step", 1e-3, 1e-6, 1e-2),
        rtol=_num(sim, "simulation", "rtol", 1e-6, 1e-12, 1e-2),
        initial_lateral_shift=_num(sim, "simulation", "initial_lateral_shift", 0.0,
                                   -0.015, 0.015),
        sample_rate=_num(sim, "simulation", "sample_rate", 100.0, 1.0, 1e5),
        table_range=_num(sim, "simulation", "table_range", 0.012, 1e-3, 0.03),
        table_step=_num(sim, "simulation", "table_step", 2e-4, 1e-5, 1e-3),
        history_wheelset=hw, title=str(sections.get("title", "")),
        contact=_contact_model(sim),
        alpha=_num(sim, "simulation", "alpha", 3e-5, 1e-7, 1e-3),
        contact_mode=cmode, contact_damping=cdamp, contact_normal=cnormal,
        wheelset_roll_inertia=croll, contact_stand_in=cstand)


def _contact_section(con: dict) -> tuple:
    """The ``[contact]`` table: mode, damping [N s/m], normal model, wheelset roll
    inertia [kg m²] (0: the yaw inertia) and the stand-ins, checked."""
    from ..normal.base import normal_models
    bad = set(con) - _CONTACT
    if bad:
        raise CaseFileError(f"unknown key(s) contact.{sorted(bad)}; expected {sorted(_CONTACT)}")
    mode = con.get("mode", "table")
    if mode not in CONTACT_MODES:
        raise CaseFileError(f"contact.mode = {mode!r}: expected one of {CONTACT_MODES}")
    normal = con.get("normal", "hertz")
    if normal not in normal_models():
        raise CaseFileError(f"contact.normal = {normal!r}: expected one of {normal_models()}")
    stand_in = con.get("stand_in", "both")
    if stand_in not in STAND_IN:
        raise CaseFileError(f"contact.stand_in = {stand_in!r}: expected one of {STAND_IN}")
    return (mode, _num(con, "contact", "damping", DEFAULT_DAMPING, 0.0, 1e8), normal,
            _num(con, "contact", "roll_inertia", 0.0, 0.0, 1e5), stand_in)


#: the contact of the dynamics' tables (``simulation.contact``)
CONTACT_MODELS = ("multi-hertz", "quasi-elastic")


def _contact_model(sim: dict) -> str:
    v = sim.get("contact", "multi-hertz")
    if v not in CONTACT_MODELS:
        raise CaseFileError(f"simulation.contact = {v!r}: expected one of {CONTACT_MODELS}")
    return v


def build_table(sc: DynamicsScenario, progress: bool = False) -> WheelRailTable:
    """Contact table of a scenario at the static wheel load of its first wheelset: the
    multi-Hertzian search, or Arnold's quasi-elastic contact (``simulation.contact``,
    ``simulation.alpha``)."""
    load = sc.model.wheelsets[0][1] * G_ACC / 2
    if sc.contact == "quasi-elastic":
        return WheelRailTable.quasi_elastic(sc.wheelset, sc.track, load, sc.alpha, sc.material,
                                            sc.table_range, sc.table_step)
    return WheelRailTable.build(sc.wheelset, sc.track, load, sc.material, sc.table_range,
                                sc.table_step, progress=progress)


def run_scenario(sc: DynamicsScenario, out=None, progress: bool = True):
    """Run a dynamics scenario; returns the dataset (written to ``out/simulation.nc``
    with ``simulation.png`` and ``history.csv`` when ``out`` is given).  With
    ``contact.mode = "online"`` no table is built, and the linear critical speed
    (an analysis of the table) is not computed (NaN)."""
    online = sc.contact_mode == "online"
    if online:
        table = OnlineWheelRail(sc.wheelset, sc.track, sc.material, sc.contact_damping,
                                sc.wheelset_roll_inertia or None, sc.contact_normal,
                                sc.contact_stand_in)
    else:
        table = build_table(sc, progress)
    ds = simulate_vehicle(sc.model, sc.route, table, sc.velocity, sc.duration,
                          sc.tangential, sc.friction, sc.material,
                          sc.initial_lateral_shift, sc.tangential_options, sc.fastsim_grid,
                          Integration(sc.integrator, sc.sample_rate, sc.rtol, step=sc.step,
                                      progress=progress))
    try:
        vc = math.nan if online else critical_speed(sc.model, table, material=sc.material)
    except (InputError, ValueError):           # no crossing in the bracket
        vc = math.nan
    ds.attrs.update(title=sc.title, critical_speed_m_s=vc, contact=sc.contact,
                    alpha_m=sc.alpha if sc.contact == "quasi-elastic" else math.nan,
                    route_segments=str(sc.route.segments),
                    irregularities=sc.route.irregularities.source)
    if out is not None:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        write_netcdf(ds, out / "simulation.nc")
        write_history(ds, out / "history.csv", sc.history_wheelset)
        plot_simulation(ds, out / "simulation.png")
    return ds


def plot_simulation(ds, path):
    """Lateral displacement, wheel lateral forces and contact positions along the track."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    x = ds["distance"].values
    fig, axes = plt.subplots(4, 1, figsize=(10, 9), sharex=True)
    for w in ds["wheelset"].values:
        c = f"C{(w - 1) % 10}"
        axes[0].plot(x, ds["lateral_displacement"].sel(wheelset=w) * 1e3, color=c,
                     label=f"wheelset {w}")
        for side, ls in (("left", "-"), ("right", "--")):
            axes[1].plot(x, ds["Y"].sel(wheelset=w, side=side) / 1e3, ls, color=c, lw=0.8,
                         label=f"{w} {side}")
    axes[0].set_ylabel("y [mm]")
    axes[0].legend(fontsize=7, ncol=4)
    axes[1].set_ylabel("Y [kN]")
    axes[1].legend(fontsize=6, ncol=4)
    w1 = ds.sel(wheelset=1)
    for side, c in (("left", "C0"), ("right", "C1")):
        for patch, mk in (("tread", "."), ("flange", "x")):
            axes[2].plot(x, w1["y_rail"].sel(side=side, patch=patch) * 1e3, mk, color=c, ms=2,
                         label=f"{side} {patch}")
    axes[2].set_ylabel("contact on rail,\nwheelset 1 [mm]")
    axes[2].legend(fontsize=7, ncol=4)
    axes[3].plot(x, ds["curvature"] * 1e3, color="C0")
    axes[3].set_ylabel("curvature [1/km]", color="C0")
    ax2 = axes[3].twinx()
    ax2.plot(x, ds["cant"] * 1e3, color="C1")
    ax2.set_ylabel("cant [mrad]", color="C1")
    axes[3].set_xlabel("distance of wheelset 1 [m]")
    fig.suptitle(f"{ds.attrs['model']} at {ds.attrs['velocity_m_s']:g} m/s, "
                 f"{ds.attrs['tangential']}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


# --------------------------------------------------------------- batches
def _run_one(sc: DynamicsScenario, name: str, out):
    try:
        ds = run_scenario(sc, out, progress=False)
        return {"scenario": name, "out": str(out), "wall_time_s": ds.attrs["wall_time_s"],
                "duration_s": float(ds["time"][-1])}
    except RailContactError as exc:
        return {"scenario": name, "out": str(out), "error": str(exc)}


def simulate_batch(scenarios: dict, out_dirs, scheduler: str = "processes",
                   progress: bool = True) -> list:
    """Run several parsed scenarios (``scenarios``: name -> :class:`DynamicsScenario`,
    in order) as one Dask batch through :func:`railcontact.core.parallel.compute`
    (``scheduler``: "processes", "threads", "sync", or the address of a
    ``dask.distributed`` scheduler).

    Returns one summary dict per run (with ``error`` for runs that failed)."""
    import dask
    names, out_dirs = list(scenarios), list(out_dirs)
    if len(names) != len(out_dirs) or not names:
        raise InputError("simulate_batch: give one output folder per scenario (at least one)")
    tasks = [dask.delayed(_run_one)(scenarios[n], n, str(o)) for n, o in zip(names, out_dirs)]
    callback = None
    if progress:
        from dask.diagnostics import ProgressBar
        callback = ProgressBar()
    return compute(tasks, scheduler, callback, what="simulate --scheduler")
