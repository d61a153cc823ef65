"""A wheel-rail case's bodies: its wheelset and track built from the case's
:class:`~railcontact.cases.wheel_rail_setup.WheelRailSetup`, and the geometry layer's
contact search on them."""

from __future__ import annotations

from .case import Case
from .wheel_rail_setup import ProfileSource, WheelRailSetup
from .wheel_slices_setup import out_of_round_wheel
from ..core.errors import CaseFileError
from ..geometry.search import (PatchRules, SearchStart, WheelsetContact, WheelsetMotion,
                               find_contact)
from ..geometry.track import SIDES, Track, Wheelset
from ..profiles.library import get_profile


def wheel_rail_setup(case: Case) -> WheelRailSetup:
    """The case's parsed wheel-rail keys; a clear error for other cases."""
    if case.wheel_rail is None:
        kind = "bodies" if case.is_bodies else "rail-surface"
        raise CaseFileError(f"a {kind} case has no wheelset on a track: expected a wheel-rail "
                            "case ([wheel], [rail], [wheelset])")
    return case.wheel_rail


def load_profiles(source: ProfileSource, kind: str, base_dir):
    """The right and the left (None: the right one mirrored) profile of a case's
    ``[wheel]`` or ``[rail]``, read with the case's units and CONTACT's processing
    options (mirroring, scale, smoothing, kinks)."""
    kw = {"base_dir": base_dir, "units": source.units}
    if source.options is not None:
        kw["options"] = source.options
    if kind == "rail":
        kw["inclination"] = source.inclination
    right = get_profile(source.name, kind, **kw)
    return right, (get_profile(source.left, kind, **kw) if source.left else None)


def build_wheelset_track(case: Case):
    """Wheelset and track of a wheel-rail case."""
    s = wheel_rail_setup(case)
    wheel, wheel_left = load_profiles(s.wheel, "wheel", case.base_dir)
    rail, rail_left = load_profiles(s.rail, "rail", case.base_dir)
    ws = Wheelset(wheel, wheel_left, nominal_radius=s.nominal_radius,
                  flange_back_distance=s.flange_back_distance,
                  flange_back_position=s.flange_back_position,
                  out_of_round=out_of_round_wheel(s.wheel, s.wheel_slices, s.pitch, wheel,
                                                  case.base_dir), locus=case.rules.locus)
    tr = Track(rail, rail_left, gauge=s.gauge, gauge_height=s.gauge_height,
               rail_offsets=None if s.rail_offset is None else {
                   side: s.rail_offset for side in SIDES},
               gauge_rule=case.rules.gauge_point)
    return ws, tr


def contact_search(case: Case, interpenetration: dict | None = None,
                   bodies=None, roll_start: float = 0.0,
                   load_iterations: int = 10) -> WheelsetContact:
    """Geometry layer only: wheelset position and contact patches of a wheel-rail case.

    ``bodies`` = (Wheelset, Track) built once by the caller, else built here;
    ``roll_start`` the roll [rad] where the search starts (an earlier search's);
    ``load_iterations`` as in :func:`railcontact.geometry.find_contact`.
    """
    s = wheel_rail_setup(case)
    ws, tr = bodies or build_wheelset_track(case)
    return find_contact(ws, tr, s.lateral_shift, s.yaw,
                        vertical_force=(s.loads["left"], s.loads["right"]),
                        material=case.material,
                        motion=WheelsetMotion(s.velocity, s.pitch_velocity, s.lateral_velocity,
                                              s.yaw_rate),
                        rules=PatchRules(s.combine_distance, s.full_interaction_distance,
                                         s.turn_distance, s.separation_angle),
                        interpenetration=interpenetration, roll=s.roll,
                        side=s.side if s.roll is not None else "both",
                        start=SearchStart(roll_start if s.roll is None else 0.0,
                                          load_iterations))
