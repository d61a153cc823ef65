"""Input files read into typed configurations, where they enter the package.

The front ends (the ``railcontact`` command, the demo) and users read files
through here; below, every layer takes the parsed, validated objects.  A
multibody contact element is built from names by :func:`contact_element`.  A case file
is :func:`railcontact.cases.case.load_case`'s; a dynamics scenario's case sections
(``[wheel]``, ``[rail]``, ``[track]``, ``[material]``, ``[friction]``) are parsed
as a case's and its own sections by :mod:`railcontact.dynamics.scenario`.
"""

from __future__ import annotations

from pathlib import Path

from .cases.bodies import build_wheelset_track
from .cases.case import case_from_dict
from .core.files import read_toml
from .dynamics.contact_element import ContactElement
from .dynamics.scenario import DynamicsScenario, scenario_from_sections

#: the sections of a dynamics scenario that are not a case's
DYNAMICS_SECTIONS = ("title", "vehicle", "simulation", "route")


def load_dynamics_scenario(path) -> DynamicsScenario:
    """Read and validate a dynamics scenario file (``docs/dynamics.md``): its case
    sections give the wheelset and track, its ``[vehicle]``, ``[route]`` and
    ``[simulation]`` the rest.  Nothing is computed; a bad key is a
    :class:`~railcontact.core.errors.CaseFileError` naming it."""
    path = Path(path)
    raw = read_toml(path, "dynamics scenario")
    sections = {k: raw.pop(k) for k in DYNAMICS_SECTIONS if k in raw}

    def bodies():
        case = case_from_dict(raw, path.parent)
        return (*build_wheelset_track(case), case.material, case.friction)

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
