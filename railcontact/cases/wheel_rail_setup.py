"""The wheel-rail part of a case, parsed once into typed values (SI units).

:func:`parse_wheel_rail` reads and validates the ``[wheel]``, ``[rail]``, ``[track]``
and ``[wheelset]`` keys of a wheel-rail case (``docs/case_files.md``) into a
:class:`WheelRailSetup`: the profiles with their processing, the wheelset's and
track's dimensions, and the wheelset's state (position, motion, loads, patch
rules).  :mod:`railcontact.cases.bodies` builds the wheelset and track from it, and the
contact search takes its state; nothing downstream reads the dotted keys again.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..core.checks import shown
from ..core.errors import CaseFileError, InputError
from ..geometry.conformal import ConformalInfluence
from .keys import CaseKeys
from ..profiles.processing import ProfileOptions

SIDES_OR_BOTH = ("left", "right", "both")


@dataclass(frozen=True)
class ProfileSource:
    """A profile of a case: a built-in name, a file (relative to the case file) or a
    :class:`~railcontact.profiles.Profile` (a worn profile of a wear run).

    ``left``: another profile for the left side (None: the right one mirrored);
    ``options``: CONTACT's processing of a profile file (mirroring, scale,
    smoothing, kinks) or None; ``units``: the file's length unit ("auto", "mm",
    "m"); ``inclination``: a rail's inclination [rad] (None: the profile's default,
    1:40 for the built-in rails)."""

    name: object
    left: object | None = None
    options: ProfileOptions | None = None
    units: str = "auto"
    inclination: float | None = None


@dataclass(frozen=True)
class WheelRailSetup:
    """Bodies and wheelset state of a wheel-rail case (SI units: m, rad, N, m/s).

    Bodies: ``wheel``, ``rail`` (:class:`ProfileSource`), ``nominal_radius``,
    ``flange_back_distance`` and ``flange_back_position`` of the wheelset,
    ``gauge``, ``gauge_height`` and ``rail_offset`` (None: from the gauge) of the
    track.

    State: ``lateral_shift``, ``yaw``; ``roll`` and ``side`` (a prescribed roll
    solves one wheel, ``side``); ``loads`` per side [N], or ``vertical_position``
    (CONTACT's NORM = 0); ``velocity``, ``pitch_velocity`` (None: rolling),
    ``lateral_velocity``, ``yaw_rate``.

    Patch rules: ``combine_distance``, ``full_interaction_distance`` (None: full
    interaction in a combined patch), ``turn_distance`` (0: no turning of nearby
    patches' angles) and ``separation_angle``.  The contact locus and the gauge
    point's rule are the case's :class:`~railcontact.cases.rules.ContactRules`
    (``Case.rules``).
    """

    wheel: ProfileSource
    rail: ProfileSource
    nominal_radius: float
    flange_back_distance: float
    flange_back_position: float
    gauge: float
    gauge_height: float
    rail_offset: float | None
    lateral_shift: float
    yaw: float
    roll: float | None
    side: str
    loads: dict
    vertical_position: float | None
    velocity: float
    pitch_velocity: float | None
    lateral_velocity: float
    yaw_rate: float
    combine_distance: float
    full_interaction_distance: float | None
    turn_distance: float
    separation_angle: float
    #: an out-of-round wheel: its slices file (``wheel.slices``, ``.slcw``; None:
    #: round) and the wheelset's pitch angle [rad] (``wheelset.pitch``)
    wheel_slices: str | None = None
    pitch: float = 0.0
    #: ``solver.contact_surface = "conformal"``: each patch on its curved reference
    #: surface (:mod:`railcontact.cases.conformal`; CONTACT's DISCNS = 4)
    conformal: bool = False
    #: ``solver.influence = "blanco"``: Blanco's corrected influence coefficients on
    #: the conformal patches (CONTACT's INFLCF = 4; None: the half-space's)
    influence: ConformalInfluence | None = None

    @property
    def balanced_sides(self) -> tuple:
        """The sides whose vertical balance is solved: both wheels of a wheelset
        free to roll (``side`` only selects the patches reported), the one wheel of
        a prescribed roll."""
        return ("left", "right") if self.roll is None else (self.side,)


def _optional(case: CaseKeys, key: str, lo: float, hi: float, unit: str):
    return None if case.get(key) is None else case.number(key, None, lo, hi, unit)


def parse_wheel_rail(case: CaseKeys) -> WheelRailSetup:
    """The validated :class:`WheelRailSetup` of a wheel-rail case; a
    :class:`~railcontact.core.errors.CaseFileError` names the first key that is wrong."""
    side = case.get("wheelset.side", "both")
    if side not in SIDES_OR_BOTH:
        raise CaseFileError(f"wheelset.side = {shown(side)}: expected 'left', 'right' or 'both'")
    roll = _optional(case, "wheelset.roll", -0.1, 0.1, "rad")
    if roll is not None and side == "both":
        raise CaseFileError("wheelset.roll is prescribed: give wheelset.side = 'left' or "
                            "'right' (with a given roll only one wheel is in equilibrium)")
    z = _optional(case, "wheelset.vertical_position", -0.05, 0.05, "m")
    if z is not None:
        if roll is None:
            raise CaseFileError("wheelset.vertical_position is prescribed: give wheelset.roll "
                                "and wheelset.side = 'left' or 'right' too (one wheel at a "
                                "given position, CONTACT's NORM = 0)")
        if "vertical_force" in case.raw.get("wheelset", {}):
            raise CaseFileError("wheelset: give either vertical_force or vertical_position, "
                                "not both")
    combine = case.number("wheelset.combine_distance", 0.0, 0.0, 0.1, "m")
    turn = case.number("wheelset.turn_distance", 0.0, 0.0, 0.2, "m")
    if 0 < turn <= combine:
        raise CaseFileError(f"wheelset.turn_distance = {shown(turn)}: expected 0 (no turning) or "
                            f"a distance beyond wheelset.combine_distance ({shown(combine)} m)")
    profiles = {}
    for body, default in (("wheel", "S1002"), ("rail", "60E1")):
        options, units = case.profile_options(body)
        profiles[body] = ProfileSource(
            case.get(f"{body}.profile", default), case.get(f"{body}.profile_left"),
            options, units,
            _optional(case, "rail.inclination", -0.1, 0.1, "rad") if body == "rail" else None)
    surface = case.get("solver.contact_surface", "planar")
    if surface not in ("planar", "conformal"):
        raise CaseFileError(f"solver.contact_surface = {shown(surface)}: expected 'planar' (a "
                            "tangent plane per patch) or 'conformal' (a curved reference "
                            "surface, CONTACT's DISCNS = 4)")
    return WheelRailSetup(
        conformal=surface == "conformal", influence=_influence(case, surface),
        wheel=profiles["wheel"], rail=profiles["rail"],
        nominal_radius=case.number("wheel.nominal_radius", 0.46, 0.02, 1.5, "m"),
        flange_back_distance=case.number("wheelset.flange_back_distance", 1.360, 0.1, 2.5, "m"),
        flange_back_position=case.number("wheelset.flange_back_position", -0.070, -0.2, 0.2,
                                         "m"),
        gauge=case.number("track.gauge", 1.435, 0.1, 2.0, "m"),   # as Track checks it
        gauge_height=case.number("track.gauge_height", 0.014, 0.0, 0.05, "m"),
        rail_offset=_optional(case, "track.rail_offset", 0.05, 1.0, "m"),
        lateral_shift=case.number("wheelset.lateral_shift", 0.0, -0.05, 0.05, "m"),
        yaw=case.number("wheelset.yaw", 0.0, -0.1, 0.1, "rad"),
        roll=roll, side=side, loads=case.wheel_loads(), vertical_position=z,
        velocity=case.number("wheelset.velocity", 30.0, 1e-3, 200.0, "m/s"),
        pitch_velocity=_optional(case, "wheelset.pitch_velocity", -1e4, 1e4, "rad/s"),
        lateral_velocity=case.number("wheelset.lateral_velocity", 0.0, -10.0, 10.0, "m/s"),
        yaw_rate=case.number("wheelset.yaw_rate", 0.0, -10.0, 10.0, "rad/s"),
        combine_distance=combine,
        full_interaction_distance=_optional(case, "wheelset.full_interaction_distance", 0.0,
                                            combine, "m (at most wheelset.combine_distance)"),
        turn_distance=turn,
        separation_angle=case.number("wheelset.separation_angle", math.pi / 2, 0.0, math.pi,
                                     "rad"),
        wheel_slices=_wheel_slices(case),
        pitch=case.number("wheelset.pitch", 0.0, -100.0, 100.0, "rad"))


def _influence(case: CaseKeys, surface: str):
    """``solver.influence`` ("half-space" or "blanco") and
    ``solver.influence_options`` (``method``, ``variant``): Blanco's corrected
    coefficients (:class:`~railcontact.geometry.conformal.ConformalInfluence`) for
    a conformal surface, or None."""
    kind = case.get("solver.influence", "half-space")
    opts = case.get("solver.influence_options", {})
    if kind not in ("half-space", "blanco"):
        raise CaseFileError(f"solver.influence = {shown(kind)}: expected 'half-space' or "
                            "'blanco' (Blanco's coefficients of a conformal surface, CONTACT's "
                            "INFLCF = 4)")
    if not isinstance(opts, dict):
        raise CaseFileError(f"solver.influence_options = {shown(opts)}: expected a table "
                            "(method, variant)")
    if kind == "half-space":
        if opts:
            raise CaseFileError("solver.influence_options: given for the half-space "
                                "coefficients; expected them with solver.influence = 'blanco'")
        return None
    if surface != "conformal":
        raise CaseFileError("solver.influence = 'blanco': Blanco's coefficients are for a "
                            "curved surface; expected solver.contact_surface = 'conformal'")
    unknown = set(opts) - {"method", "variant"}
    if unknown:
        raise CaseFileError(f"solver.influence_options keys {sorted(unknown)}: expected "
                            "'method' and 'variant'")
    try:
        return ConformalInfluence(**opts)
    except InputError as exc:
        raise CaseFileError(f"solver.influence_options: {exc}") from None


def _wheel_slices(case: CaseKeys):
    """``wheel.slices``: a wheel slices file (``.slcw``) of an out-of-round wheel."""
    v = case.get("wheel.slices")
    if v is None:
        return None
    if not (isinstance(v, str) and v.lower().endswith(".slcw")):
        raise CaseFileError(f"wheel.slices = {shown(v)}: expected a wheel slices file "
                            "(.slcw, CONTACT's format)")
    return v
