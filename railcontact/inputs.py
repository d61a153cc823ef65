"""Input files read into typed configurations, where they enter the package.

The front ends (the ``railcontact`` command, the demo) and users read files
through here; below, every layer takes the parsed, validated objects: a
:class:`~railcontact.cases.case.Case`, a dynamics scenario, a wear scenario.  A
multibody contact element is built from names by :func:`contact_element`.  A case file
is :func:`railcontact.cases.case.load_case`'s; a dynamics scenario's case sections
(``[wheel]``, ``[rail]``, ``[track]``, ``[material]``, ``[friction]``) are parsed
as a case's and its own sections by :mod:`railcontact.dynamics.scenario`.
"""

from __future__ import annotations

from pathlib import Path

from .cases.bodies import build_wheelset_track
from .cases.case import case_from_dict
from .core.errors import CaseFileError
from .core.files import read_toml
from .dynamics.contact_element import ContactElement
from .dynamics.roller_rig import RIG_SECTIONS, RigScenario, rig_scenario_from_sections
from .dynamics.scenario import DynamicsScenario, scenario_from_sections
from .wear import simulation as open_loop
from .wear import vehicle_scenario as closed_loop

#: the sections of a dynamics scenario that are not a case's
DYNAMICS_SECTIONS = ("title", "vehicle", "simulation", "route", "contact")


def load_dynamics_scenario(path) -> DynamicsScenario | RigScenario:
    """Read and validate a dynamics scenario file (``docs/dynamics.md``): its case
    sections give the wheelset and track, its ``[vehicle]``, ``[route]`` and
    ``[simulation]`` the rest; a file with ``[roller_rig]`` is a wheelset on a
    roller rig (:class:`~railcontact.dynamics.roller_rig.RigScenario`: its
    ``[roller_rig]``, ``[vehicle]``, ``[excitation]`` and ``[simulation]``).
    Nothing is computed; a bad key is a
    :class:`~railcontact.core.errors.CaseFileError` naming it."""
    path = Path(path)
    raw = read_toml(path, "dynamics scenario")
    rig = "roller_rig" in raw
    sections = {k: raw.pop(k) for k in (RIG_SECTIONS if rig else DYNAMICS_SECTIONS)
                if k in raw}

    def bodies():
        case = case_from_dict(raw, path.parent)
        return (*build_wheelset_track(case), case.material, case.friction)

    if rig:
        return rig_scenario_from_sections(sections, bodies)
    return scenario_from_sections(sections, path.parent, bodies)


def contact_element(wheel: str = "S1002", rail: str = "60E1", normal: str = "hertz",
                    tangential: str = "fastsim", friction: float = 0.3, mode: str = "position",
                    extra: dict | None = None) -> ContactElement:
    """A multibody contact element (:class:`~railcontact.dynamics.contact_element.
    ContactElement`) from profile and model names; ``extra``: further case keys, e.g.
    ``{"wheel": {"nominal_radius": 0.45}}``, merged into the case before it is
    parsed and checked."""
    raw = {"wheel": {"profile": wheel}, "rail": {"profile": rail},
           "friction": {"coefficient": friction},
           "solver": {"normal": normal, "tangential": tangential}}
    for key, table in (extra or {}).items():
        if isinstance(table, dict):
            raw.setdefault(key, {}).update(table)
        else:
            raw[key] = table
    return ContactElement(case_from_dict(raw), mode=mode)


def load_wear_scenario(path):
    """Read and validate a wear scenario file (``docs/wear.md``): an open-loop
    :class:`~railcontact.wear.simulation.WearScenario` (operating conditions or a
    time history) or, with ``[vehicle]`` and ``[[route]]``, a closed-loop
    :class:`~railcontact.wear.vehicle_scenario.VehicleWearScenario`.  Nothing is
    computed; a bad key is a :class:`~railcontact.core.errors.CaseFileError`."""
    path = Path(path)
    return wear_scenario_from_dict(read_toml(path, "wear scenario"), path.parent)


def wear_scenario_from_dict(raw: dict, base_dir=None):
    """:func:`load_wear_scenario` of a parsed TOML table (``base_dir``: where its
    files are; default the working folder)."""
    if not isinstance(raw, dict):
        raise CaseFileError("wear scenario: expected a TOML table")
    raw = dict(raw)
    if closed_loop.is_vehicle_scenario(raw):
        names = closed_loop.VEHICLE_SCENARIO_SECTIONS
        sections = {k: raw.pop(k) for k in names if k in raw}
        sections["title"] = raw.get("title", "")
        return closed_loop.vehicle_scenario_from_sections(
            sections, base_dir, lambda: case_from_dict(raw, base_dir))
    sections = {k: raw.pop(k) for k in open_loop.WEAR_SCENARIO_SECTIONS if k in raw}
    return open_loop.scenario_from_sections(sections, base_dir,
                                            lambda: case_from_dict(raw, base_dir))
