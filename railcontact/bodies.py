"""A wheel-rail case's bodies: its wheelset and track built from the case keys, and
the geometry layer's contact search on them."""

from __future__ import annotations

import math

from .case import Case
from .geometry.search import WheelsetContact, find_contact
from .geometry.track import SIDES, Track, Wheelset
from .profiles.library import get_profile


def build_wheelset_track(case: Case):
    """Wheelset and track of a wheel-rail case."""
    base = case.base_dir
    kw = {}
    for body in ("wheel", "rail"):
        # a profile file's options (mirroring, scale, smoothing, ...) and length unit
        options, units = case.profile_options(body)
        kw[body] = {"base_dir": base, "units": units,
                    **({"options": options} if options is not None else {})}
    wheel = get_profile(case.get("wheel.profile", "S1002"), "wheel", **kw["wheel"])
    wl = case.get("wheel.profile_left")
    wheel_left = get_profile(wl, "wheel", **kw["wheel"]) if wl else None
    incl = case.get("rail.inclination")
    rail = get_profile(case.get("rail.profile", "60E1"), "rail", inclination=incl, **kw["rail"])
    rl = case.get("rail.profile_left")
    rail_left = get_profile(rl, "rail", inclination=incl, **kw["rail"]) if rl else None
    ws = Wheelset(wheel, wheel_left, nominal_radius=case.number("wheel.nominal_radius", 0.46),
                  flange_back_distance=case.number("wheelset.flange_back_distance", 1.360),
                  flange_back_position=case.number("wheelset.flange_back_position", -0.070))
    offset = case.get("track.rail_offset")
    tr = Track(rail, rail_left, gauge=case.number("track.gauge", 1.435),
               gauge_height=case.number("track.gauge_height", 0.014),
               rail_offsets=None if offset is None else {s: float(offset) for s in SIDES})
    return ws, tr



def contact_search(case: Case, interpenetration: dict | None = None,
                   bodies=None, roll_start: float = 0.0,
                   load_iterations: int = 10) -> WheelsetContact:
    """Geometry layer only: wheelset position and contact patches of a wheel-rail case.

    ``bodies`` = (Wheelset, Track) built once by the caller, else built here;
    ``roll_start`` the roll [rad] where the search starts (an earlier search's);
    ``load_iterations`` as in :func:`railcontact.geometry.find_contact`.
    """
    ws, tr = bodies or build_wheelset_track(case)
    pv = case.get("wheelset.pitch_velocity")
    roll = case.get("wheelset.roll")
    fid = case.get("wheelset.full_interaction_distance")
    combine = case.number("wheelset.combine_distance", 0.0, 0.0, 0.1)
    return find_contact(ws, tr, case.number("wheelset.lateral_shift", 0.0),
                        case.number("wheelset.yaw", 0.0),
                        vertical_force=(case.wheel_loads()["left"], case.wheel_loads()["right"]),
                        material=case.material, velocity=case.number("wheelset.velocity", 30.0),
                        pitch_velocity=None if pv is None else case.number("wheelset.pitch_velocity"),
                        lateral_velocity=case.number("wheelset.lateral_velocity", 0.0),
                        yaw_rate=case.number("wheelset.yaw_rate", 0.0),
                        combine_distance=combine,
                        full_interaction_distance=None if fid is None else case.number(
                            "wheelset.full_interaction_distance", 0.0, 0.0, combine,
                            "m (at most wheelset.combine_distance)"),
                        interpenetration=interpenetration,
                        roll=None if roll is None else case.number("wheelset.roll"),
                        side=case.get("wheelset.side", "both") if roll is not None else "both",
                        roll_start=roll_start if roll is None else 0.0,
                        load_iterations=load_iterations,
                        turn_distance=case.number("wheelset.turn_distance", 0.0),
                        separation_angle=case.number("wheelset.separation_angle", math.pi / 2))
