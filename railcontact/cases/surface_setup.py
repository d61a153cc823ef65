"""Case keys of a wheel on rail surfaces: rails along the track (slices), several
rails each placed on its own, a roller (``docs/case_files.md``, "Rails along the
track, several rails, rollers").

Which cases need the 3-D surfaces (:func:`is_surface_case`), and their keys
validated and parsed once into a typed :class:`SurfaceCaseSetup`
(:func:`parse_surface_case`); building the surfaces from it and solving is
:mod:`railcontact.cases.surfaces`'s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..core.checks import shown
from ..core.errors import CaseFileError
from .keys import PROFILE_OPTIONS, CaseKeys
from .rules import ContactRules
from .wheel_rail_setup import ProfileSource

#: keys of one rail (``[rail]`` or an entry of ``[[rails]]``) in a surface case
RAIL_KEYS = {"profile", "slices", "inclination", "units", "name", "lateral_position",
             "vertical_position", "slice_spacing", "lateral_range"}
ROLLER_KEYS = {"radius", "angular_velocity", "position", "profile_deviation", "turn"}


def is_surface_case(case: CaseKeys) -> bool:
    """Whether a case needs the 3-D surfaces: slices, several rails, a roller, a rail
    placed by its own position, or a wheelset position along the track.  (A
    prescribed ``wheelset.vertical_position`` alone, on one rail placed by the track's
    gauge, is a profile case: :func:`railcontact.solve`'s position control.)"""
    raw = case.raw
    placed = RAIL_KEYS - {"profile", "inclination", "units"}
    return ("rails" in raw or "roller" in raw or bool(placed & set(raw.get("rail", {})))
            or bool({"position", "wheel_deviation"} & set(raw.get("wheelset", {}))))


@dataclass(frozen=True)
class RailSpec:
    """One rail of a surface case, parsed (SI units): a ``profile``
    (:class:`ProfileSource`) or ``slices`` (a ``.slcs`` file name or a list of
    ``{s, profile}``), its ``name`` (None: the surface's), ``lateral_position`` [m]
    of its profile origin in the track frame (None: placed by the track's gauge),
    ``vertical_position`` [m], ``slice_spacing`` [m] (None: the slices' default),
    ``lateral_range`` (y_min, y_max) [m] in rail-profile coordinates (None: all),
    the file's length ``units`` and CONTACT's profile processing of every slice
    (``options``: :class:`~railcontact.profiles.ProfileOptions`, None: none);
    ``where`` names it in messages."""

    where: str
    profile: ProfileSource | None = None
    slices: object = None
    name: str | None = None
    lateral_position: float | None = None
    vertical_position: float = 0.0
    slice_spacing: float | None = None
    lateral_range: tuple | None = None
    units: str = "auto"
    options: object = None


@dataclass(frozen=True)
class RollerSpec:
    """A roller in place of the rail: ``radius`` [m], ``angular_velocity`` [rad/s]
    (None: rolling with the wheel) and ``position`` [m] along the track of its
    crown; ``profile_deviation`` (dz [m], roll [rad]) or None: its profile turned
    by roll about +x about the profile origin, then lowered by dz, before it is
    revolved about the roller's axis, which stays (CONTACT's DZRAIL, DROLLR of a
    roller); the undeformed distance's surface is the rule ``roller.turn``
    (``Case.rules.roller_turn``)."""

    radius: float
    angular_velocity: float | None = None
    position: float = 0.0
    profile_deviation: tuple | None = None


@dataclass(frozen=True)
class SurfaceCaseSetup:
    """The keys of a case on rail surfaces, parsed once (SI units: m, rad, N, m/s).

    Bodies: ``wheel`` (:class:`ProfileSource`), ``nominal_radius``,
    ``flange_back_distance`` and ``flange_back_position``; ``rails`` (one
    :class:`RailSpec` each), ``roller`` (:class:`RollerSpec` or None), ``gauge`` and
    ``gauge_height`` (placing a rail without ``lateral_position``).

    State: ``side`` (one wheel), ``position`` s along the track, ``lateral_shift``,
    ``roll``, ``yaw``; ``vertical_position`` (None: the ``load`` [N] is met);
    ``velocity``, ``pitch_velocity`` (None: rolling), ``lateral_velocity``,
    ``yaw_rate``; ``wheel_deviation`` (None, or the wheel's deviation by flexibility
    (dx, dy, dz [m], roll, yaw, pitch [rad]) about its profile origin in wheelset
    coordinates: :class:`~railcontact.geometry.surface_search.SurfaceWheel`).

    Search: ``search_length`` [m] (None: the default), ``rigid_slip`` ("planar" or
    "surfaces") and ``combine_distance`` [m]: interpenetration regions on one rail
    laterally closer than this are one patch (CONTACT's D_SEP; 0: every region its
    own patch).  The search's rules (the contact angle, the reference point's
    weights, the search grid) are the case's
    :class:`~railcontact.cases.rules.ContactRules` (``Case.rules``).
    """

    wheel: ProfileSource
    rails: tuple
    roller: RollerSpec | None
    side: str
    load: float | None
    vertical_position: float | None
    nominal_radius: float = 0.46
    flange_back_distance: float = 1.360
    flange_back_position: float = -0.070
    gauge: float = 1.435
    gauge_height: float = 0.014
    position: float = 0.0
    lateral_shift: float = 0.0
    roll: float = 0.0
    yaw: float = 0.0
    velocity: float = 30.0
    pitch_velocity: float | None = None
    lateral_velocity: float = 0.0
    yaw_rate: float = 0.0
    search_length: float | None = None
    rigid_slip: str = "planar"
    combine_distance: float = 0.0
    wheel_deviation: tuple | None = None


def parse_surface_case(case: CaseKeys, tangential: str,
                       rules: ContactRules = ContactRules()) -> SurfaceCaseSetup:
    """Validate and parse the keys of a case on rail surfaces (no file read); a
    :class:`~railcontact.core.errors.CaseFileError` names the first key that is
    wrong.  ``tangential`` is the case's tangential model (``rigid_slip =
    "surfaces"`` needs the exact one), ``rules`` its CONTACT rules (CONTACT's search
    grid needs ``solver.element_size``)."""
    raw = case.raw
    if "rails" in raw and "slices" in raw.get("rail", {}):
        raise CaseFileError("give the rails either as [[rails]] or as [rail], not both")
    rails = raw.get("rails")
    if rails is not None:
        if not isinstance(rails, list) or not rails or not all(isinstance(r, dict) for r in rails):
            raise CaseFileError("[[rails]]: expected one or more tables, each a rail with "
                                "profile or slices and its placement")
        specs = tuple(_rail_spec(r, f"rails[{k}]") for k, r in enumerate(rails))
    else:
        specs = (_rail_spec(raw.get("rail", {"profile": "60E1"}), "rail"),)
    roller = raw.get("roller")
    if roller is not None:
        if not isinstance(roller, dict) or set(roller) - ROLLER_KEYS or "radius" not in roller:
            raise CaseFileError(f"[roller] = {shown(roller)}: expected radius [m] and optionally "
                                f"{sorted(ROLLER_KEYS - {'radius'})}")
        roller = RollerSpec(case.number("roller.radius", None, 0.02, 10.0, "m"),
                            _optional(case, "roller.angular_velocity", -1e5, 1e5, "rad/s"),
                            case.number("roller.position", 0.0, -1.0, 1.0, "m"),
                            _profile_deviation(case))
        if len(specs) > 1:
            raise CaseFileError("[roller] replaces one rail; give one rail")
        if specs[0].slices is not None:
            raise CaseFileError("[roller]: the roller's profile is a rail profile, not slices")
    side = case.get("wheelset.side", "right")
    if side not in ("left", "right"):
        raise CaseFileError(f"wheelset.side = {shown(side)}: a case on rail surfaces solves one "
                            "wheel; expected 'left' or 'right'")
    z = _optional(case, "wheelset.vertical_position", -0.2, 0.2, "m")
    loads = case.wheel_loads()
    slip = case.get("solver.rigid_slip", "planar")
    if slip not in ("planar", "surfaces"):
        raise CaseFileError(f"solver.rigid_slip = {shown(slip)}: expected 'planar' (the creepages of "
                            "the reference point) or 'surfaces' (on the actual surfaces)")
    if rules.search_grid == "contact" and case.get("solver.element_size") is None:
        raise CaseFileError("solver.search_grid = 'contact' needs solver.element_size")
    if slip == "surfaces" and tangential != "exact":
        raise CaseFileError("solver.rigid_slip = 'surfaces' needs solver.tangential = 'exact'")
    options, units = case.profile_options("wheel")
    return SurfaceCaseSetup(
        wheel=ProfileSource(case.get("wheel.profile", "S1002"), options=options, units=units),
        rails=specs, roller=roller, side=side, load=None if z is not None else loads[side],
        vertical_position=z,
        nominal_radius=case.number("wheel.nominal_radius", 0.46, 0.01, 1.5, "m"),
        flange_back_distance=case.number("wheelset.flange_back_distance", 1.360, -2.0, 2.0, "m"),
        flange_back_position=case.number("wheelset.flange_back_position", -0.070, -0.2, 0.2,
                                         "m"),
        gauge=case.number("track.gauge", 1.435, 0.5, 2.5, "m"),
        gauge_height=case.number("track.gauge_height", 0.014, 0.0, 0.05, "m"),
        position=case.number("wheelset.position", 0.0, -1e5, 1e5, "m"),
        lateral_shift=case.number("wheelset.lateral_shift", 0.0, -0.05, 0.05, "m"),
        roll=case.number("wheelset.roll", 0.0, -0.5, 0.5, "rad"),
        yaw=case.number("wheelset.yaw", 0.0, -0.5, 0.5, "rad"),
        velocity=_speed(case),
        pitch_velocity=_optional(case, "wheelset.pitch_velocity", -1e4, 1e4, "rad/s"),
        lateral_velocity=case.number("wheelset.lateral_velocity", 0.0, -10.0, 10.0, "m/s"),
        yaw_rate=case.number("wheelset.yaw_rate", 0.0, -10.0, 10.0, "rad/s"),
        search_length=_optional(case, "solver.search_length", 1e-3, 1.0, "m"),
        rigid_slip=slip,
        combine_distance=case.number("wheelset.combine_distance", 0.0, 0.0, 0.1, "m"),
        wheel_deviation=_wheel_deviation(case))


def _speed(case: CaseKeys) -> float:
    """``wheelset.velocity`` [m/s] on rail surfaces: negative where the wheel rolls
    towards -x (solved mirrored in x, :mod:`railcontact.cases.surfaces`)."""
    v = case.number("wheelset.velocity", 30.0, -200.0, 200.0, "m/s")
    if abs(v) < 1e-3:
        raise CaseFileError(f"wheelset.velocity = {v!r}: expected a speed of at least 0.001 "
                            "m/s, forwards (> 0) or backwards (< 0)")
    return v


def _profile_deviation(case: CaseKeys):
    """``roller.profile_deviation = [dz, roll]`` (m, rad) or None."""
    dev = case.get("roller.profile_deviation")
    if dev is None:
        return None
    if not (isinstance(dev, list) and len(dev) == 2 and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
            for v in dev)) or abs(dev[0]) > 0.05 or abs(dev[1]) > 0.5:
        raise CaseFileError(f"roller.profile_deviation = {shown(dev)}: expected [dz, roll], "
                            "dz within 0.05 m and roll within 0.5 rad")
    return tuple(float(v) for v in dev)


def _wheel_deviation(case: CaseKeys):
    """``wheelset.wheel_deviation = [dx, dy, dz, roll, yaw, pitch]`` (m, rad): the
    wheel's deviation by flexibility (CONTACT's DXWHL .. DPITCHW), or None."""
    dev = case.get("wheelset.wheel_deviation")
    if dev is None:
        return None
    if not (isinstance(dev, list) and len(dev) == 6 and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
            for v in dev)) or max(abs(v) for v in dev[:3]) > 0.05 or \
            max(abs(v) for v in dev[3:]) > 0.5:
        raise CaseFileError(f"wheelset.wheel_deviation = {shown(dev)}: expected [dx, dy, dz, "
                            "roll, yaw, pitch], displacements within 0.05 m and angles within "
                            "0.5 rad")
    return tuple(float(v) for v in dev)


def _optional(case: CaseKeys, key: str, lo: float, hi: float, unit: str):
    return None if case.get(key) is None else case.number(key, None, lo, hi, unit)


def _rail_spec(r: dict, where: str) -> RailSpec:
    """One rail's keys checked and parsed."""
    if not isinstance(r, dict):
        raise CaseFileError(f"[{where}] must be a table")
    bad = set(r) - RAIL_KEYS - PROFILE_OPTIONS - {"profile_left"}
    if bad:
        raise CaseFileError(f"unknown key {where}.{sorted(bad)[0]}; expected one of "
                            f"{sorted(RAIL_KEYS | PROFILE_OPTIONS)}")
    if ("profile" in r) == ("slices" in r):
        raise CaseFileError(f"[{where}]: give either profile or slices")
    if "slices" in r and "lateral_position" not in r:
        raise CaseFileError(f"[{where}]: a rail given by slices needs lateral_position (y of "
                            "its profile origin in the track frame, m)")
    lr = r.get("lateral_range")
    if lr is not None and not (isinstance(lr, list) and len(lr) == 2 and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and abs(v) < 1 for v in lr)
            and lr[0] < lr[1]):
        raise CaseFileError(f"{where}.lateral_range = {shown(lr)}: expected [y_min, y_max] in m "
                            "(rail-profile coordinates), y_min < y_max")
    units = r.get("units", "auto")
    if units not in ("auto", "mm", "m"):
        raise CaseFileError(f"{where}.units = {shown(units)}: expected 'auto', 'mm' or 'm'")
    sl = r.get("slices")
    if sl is not None and not isinstance(sl, (str, list)):
        raise CaseFileError(f"{where}.slices = {shown(sl)}: expected a .slcs file or a list of "
                            "{s, profile}")
    keys = CaseKeys({where: r})
    options, _ = CaseKeys({"rail": r}).profile_options("rail")
    inc = _optional(keys, f"{where}.inclination", -0.1, 0.1, "rad")
    spacing = _optional(keys, f"{where}.slice_spacing", 1e-5, 10.0, "m")
    return RailSpec(
        where=where,
        profile=None if sl is not None else ProfileSource(r["profile"], units=units,
                                                          inclination=inc, options=options),
        slices=sl, name=None if r.get("name") is None else str(r["name"]),
        lateral_position=_optional(keys, f"{where}.lateral_position", -2.0, 2.0, "m"),
        vertical_position=keys.number(f"{where}.vertical_position", 0.0, -0.5, 0.5, "m"),
        slice_spacing=spacing, lateral_range=None if lr is None else (float(lr[0]), float(lr[1])),
        units=units, options=options)
