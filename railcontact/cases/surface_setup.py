"""Case keys of a wheel on rail surfaces: rails along the track (slices), several
rails each placed on its own, a roller (``docs/case_files.md``, "Rails along the
track, several rails, rollers").

Which cases need the 3-D surfaces, and the validation of their keys; the solving
is :mod:`railcontact.cases.surfaces`'s.
"""

from __future__ import annotations


from ..core.checks import shown
from ..core.errors import CaseFileError
from .keys import CaseKeys

#: keys of one rail (``[rail]`` or an entry of ``[[rails]]``) in a surface case
RAIL_KEYS = {"profile", "slices", "inclination", "units", "name", "lateral_position",
             "vertical_position", "slice_spacing", "lateral_range"}
ROLLER_KEYS = {"radius", "angular_velocity", "position"}


def is_surface_case(case: CaseKeys) -> bool:
    """Whether a case needs the 3-D surfaces: slices, several rails, a roller, a rail
    placed by its own position, or a wheelset position along the track.  (A
    prescribed ``wheelset.vertical_position`` alone, on one rail placed by the track's
    gauge, is a profile case: :func:`railcontact.solve`'s position control.)"""
    raw = case.raw
    placed = RAIL_KEYS - {"profile", "inclination", "units"}
    return ("rails" in raw or "roller" in raw or bool(placed & set(raw.get("rail", {})))
            or "position" in raw.get("wheelset", {}))


def check_surface_case(case: CaseKeys) -> None:
    """Validate the surface keys of a case (no files read): a clear
    :class:`CaseFileError` for what is wrong."""
    raw = case.raw
    if "rails" in raw and "slices" in raw.get("rail", {}):
        raise CaseFileError("give the rails either as [[rails]] or as [rail], not both")
    rails = raw.get("rails")
    if rails is not None:
        if not isinstance(rails, list) or not rails or not all(isinstance(r, dict) for r in rails):
            raise CaseFileError("[[rails]]: expected one or more tables, each a rail with "
                                "profile or slices and its placement")
        for k, r in enumerate(rails):
            _check_rail(r, f"rails[{k}]")
    elif "rail" in raw:
        _check_rail(raw["rail"], "rail")
    roller = raw.get("roller")
    if roller is not None:
        if not isinstance(roller, dict) or set(roller) - ROLLER_KEYS or "radius" not in roller:
            raise CaseFileError(f"[roller] = {shown(roller)}: expected radius [m] and optionally "
                                f"{sorted(ROLLER_KEYS - {'radius'})}")
        case.number("roller.radius", None, 0.02, 10.0, "m")
        if rails is not None and len(rails) > 1:
            raise CaseFileError("[roller] replaces one rail; give one rail")
    side = case.get("wheelset.side", "right")
    if side not in ("left", "right"):
        raise CaseFileError(f"wheelset.side = {shown(side)}: a case on rail surfaces solves one "
                            "wheel; expected 'left' or 'right'")
    has_z = case.get("wheelset.vertical_position") is not None
    if has_z:
        case.number("wheelset.vertical_position", None, -0.05, 0.05, "m")
    case.number("wheelset.position", 0.0, -1e5, 1e5, "m")
    case.number("wheelset.roll", 0.0, -0.1, 0.1, "rad")
    inc = case.get("solver.contact_angle", "local")
    if inc not in ("local", "wheelset"):
        raise CaseFileError(f"solver.contact_angle = {shown(inc)}: expected 'local' (the rail's "
                            "inclination at each point of the patch) or 'wheelset' (on its "
                            "cross-section at the wheelset's position, as CONTACT)")
    slip = case.get("solver.rigid_slip", "planar")
    if slip not in ("planar", "surfaces"):
        raise CaseFileError(f"solver.rigid_slip = {shown(slip)}: expected 'planar' (the creepages of "
                            "the reference point) or 'surfaces' (on the actual surfaces)")
    if slip == "surfaces" and case.tangential != "exact":
        raise CaseFileError("solver.rigid_slip = 'surfaces' needs solver.tangential = 'exact'")


def _check_rail(r: dict, where: str) -> None:
    if not isinstance(r, dict):
        raise CaseFileError(f"[{where}] must be a table")
    bad = set(r) - RAIL_KEYS - {"profile_left"}
    if bad:
        raise CaseFileError(f"unknown key {where}.{sorted(bad)[0]}; expected one of "
                            f"{sorted(RAIL_KEYS)}")
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
    for key, lim in (("lateral_position", 2.0), ("vertical_position", 0.5)):
        v = r.get(key)
        if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float))
                              or not abs(v) <= lim):
            raise CaseFileError(f"{where}.{key} = {shown(v)}: expected a position in m, |value| <= "
                                f"{lim}")
