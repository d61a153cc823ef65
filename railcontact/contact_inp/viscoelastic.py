"""CONTACT's viscoelastic materials (M = 1) on module 3's grid.

The input (user guide, "Viscoelastic materials"): GG1, GG2 the initial (glassy)
shear moduli [N/mm^2], POISS1, POISS2, and per body FG (the spring ratio
C_v / C_g = (E_g - E_r) / E_r) and TC (the creep relaxation time [s], read as VT1,
VT2); steady rolling (T = 3, or T = 0 with the normal problem only) towards +x
(CHI = 0) at VELOC [mm/s].  The kernels are :mod:`railcontact.normal.viscoelastic`'s.
"""

from __future__ import annotations

import math

from ..normal.viscoelastic import (Viscoelastic, ViscoelasticBody, active_set_normal,
                                   viscoelastic_normal_operator)
from .reader import InpCase, InpError

__all__ = ["active_set_normal", "check_viscoelastic", "viscoelastic_pair",
           "viscoelastic_normal_operator"]

MM = 1e-3


def _value(case, name):
    v = case.values.get(name)
    if v is None:
        raise InpError(f"{case.where()}: {name} is not set (no earlier case gave it)")
    return v


def check_viscoelastic(case: InpCase) -> None:
    """The one-line InpError of a viscoelastic case that is not steady rolling towards
    +x of quasi-identical bodies (what CONTACT supports with M = 1)."""
    d = case.digits
    if d["T"] not in (0, 3):
        raise InpError(f"{case.where()}: MATER = 1 (viscoelastic) with TANG = {d['T']} is not "
                       "supported; expected steady rolling (T = 3) or T = 0, as in CONTACT")
    if d["T"] == 3 and abs(_value(case, "CHI")) > 1e-9:
        raise InpError(f"{case.where()}: MATER = 1 (viscoelastic) with CHI = "
                       f"{_value(case, 'CHI'):g} rad is not supported; expected rolling "
                       "towards +x (CHI = 0), as in CONTACT")
    g1, g2 = _value(case, "GG1"), _value(case, "GG2")
    n1, n2 = _value(case, "POISS1"), _value(case, "POISS2")
    if abs((1 - 2 * n1) / g1 - (1 - 2 * n2) / g2) > 1e-9 * (1 / g1 + 1 / g2):
        raise InpError(f"{case.where()}: MATER = 1 (viscoelastic) with dissimilar materials "
                       "(K != 0) is not supported; expected (1 - 2 nu)/G equal for both bodies")
    viscoelastic_pair(case)


def viscoelastic_pair(case: InpCase) -> Viscoelastic:
    """The case's viscoelastic pair in SI (hashable: its kernels are cached)."""
    bodies = []
    for a in (1, 2):
        bodies.append(ViscoelasticBody(_value(case, f"GG{a}") * 1e6, _value(case, f"POISS{a}"),
                                       _value(case, f"FG{a}"), _value(case, f"VT{a}")))
    veloc = case.values.get("VELOC")
    if veloc is None or not (math.isfinite(veloc) and veloc > 0):
        raise InpError(f"{case.where()}: MATER = 1 (viscoelastic) needs the rolling velocity "
                       f"VELOC > 0 (got {veloc!r} mm/s)")
    return Viscoelastic(bodies[0], bodies[1], veloc * MM)
