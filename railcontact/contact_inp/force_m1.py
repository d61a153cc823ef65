"""CONTACT's module 1 with the total longitudinal force prescribed (F = 1): the
pitch velocity that gives it.

CONTACT's user guide ("F1 - FORCE", "Total forces"): with F = 1 the sixth value of
the velocity line is FX_WS [N], the total force on the rail along the wheelset's
longitudinal axis x_ws, in place of the pitch velocity VPITCH, which CONTACT
determines.  Here the mapped case (:func:`railcontact.contact_inp.mapping.map_case`,
its pitch velocity started at -VS/NOMRAD) is solved for pitch velocities found by
Brent's method on FX_WS(omega) - FX_WS, each solve warm-started from the last
(the vertical problem, N = 0 or 1, solved in each).  FX_WS of the rows' totals
on the rail in the track frame, turned by the wheelset's yaw:
FX_WS = FX_TR cos(yaw) + FY_TR sin(yaw).

Units: CONTACT's N at the boundary; the pitch velocity in rad/s.
"""

from __future__ import annotations

import copy
import logging
import math

from scipy.optimize import brentq

from ..core.errors import ConvergenceError
from .mapping import MappedCase
from .table import rows

log = logging.getLogger(__name__)

#: relative tolerance on the pitch velocity (a creepage of about 1e-11; with 1e-10
#: and CONTACT's conformal wheel samples groove_li case 4 met FX_WS = 0 to 3.8e-3 N
#: only, dF_x/d(omega) being some 4e7 N s there)
PITCH_RTOL = 1e-11
#: the vertical balance's relative tolerance inside the search (a tenth of the case
#: default 1e-4): FX_WS follows the balance's load to its tolerance, so that a
#: balance met to 1e-4 leaves FX_WS(omega) rough at 1e-4 and the root 1e-4 off
#: (groove_li case 1: 599.937 N for 600; with 1e-5, 599.99994 N)
BALANCE_RTOL = 1e-5
#: the first bracket: the nominal pitch velocity times 1 -/+ this (creepages of
#: about +-1 %, rolling radii 1 % from NOMRAD), widened by doubling
BRACKET = 0.01
MAX_WIDEN = 6


def wheelset_fx(table) -> float:
    """FX_WS [N] of a case's rows (:func:`railcontact.contact_inp.table.rows`): the
    total force on the rail along the wheelset's longitudinal axis."""
    r = table[0]
    yaw = r.get("yaw_rad") or 0.0
    return r["fx_tr_N"] * math.cos(yaw) + r["fy_tr_N"] * math.sin(yaw)


def solve_for_force(mapped: MappedCase, solve_raw):
    """Solve a mapped module 1 case with ``meta["fx_ws"]`` prescribed: returns the
    result at the pitch velocity found and the mapped case with it (its raw
    ``wheelset.pitch_velocity``).  ``solve_raw(raw, warm)`` solves a case
    dictionary (``warm`` a previous result or None) and returns its SolveResult."""
    target = float(mapped.meta["fx_ws"])
    omega0 = float(mapped.raw["wheelset"]["pitch_velocity"])
    state = {"warm": None}

    def at(omega):
        raw = copy.deepcopy(mapped.raw)
        raw["wheelset"]["pitch_velocity"] = float(omega)
        sol = raw.setdefault("solver", {})
        sol["force_tolerance"] = min(float(sol.get("force_tolerance", 1e-4)), BALANCE_RTOL)
        m = MappedCase(mapped.number, mapped.module, raw, mapped.meta)
        res = solve_raw(raw, state["warm"])
        state.update(warm=res, res=res, mapped=m)
        if not res.patches:
            raise ConvergenceError(f"{mapped.raw.get('title', 'case')}: FX_WS = {target:g} N "
                                   "prescribed without contact; expected a loaded wheel")
        return wheelset_fx(rows(res, m)) - target

    lo, hi = omega0 * (1.0 - BRACKET), omega0 * (1.0 + BRACKET)
    f_lo, f_hi = at(lo), at(hi)
    for _ in range(MAX_WIDEN):
        if f_lo * f_hi <= 0:
            break
        width = hi - lo
        lo, hi = lo - width / 2, hi + width / 2
        f_lo, f_hi = at(lo), at(hi)
    else:
        if f_lo * f_hi > 0:
            raise ConvergenceError(f"{mapped.raw.get('title', 'case')}: FX_WS = {target:g} N not "
                                   f"reached by pitch velocities {lo:.6g} to {hi:.6g} rad/s "
                                   f"(FX_WS - target {f_lo:.4g}, {f_hi:.4g} N); expected "
                                   "|FX_WS| below the friction bound")
    omega = brentq(at, lo, hi, xtol=PITCH_RTOL * abs(omega0), rtol=1e-14, maxiter=60)
    if state["mapped"].raw["wheelset"]["pitch_velocity"] != omega:
        at(omega)
    log.info("FX_WS = %g N: pitch velocity %.10g rad/s", target, omega)
    return state["res"], state["mapped"]
