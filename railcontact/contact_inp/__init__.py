"""CONTACT's input files (``.inp``) in railcontact.

``railcontact solve FILE.inp`` and ``railcontact sweep FILE.inp`` read the cases of
a CONTACT input file (module 1, wheel-rail; module 3, basic Hertzian contact),
map each onto a railcontact case (:mod:`.mapping`; CONTACT's mm and N converted
to SI), solve them with :func:`railcontact.solve`, and return one row per contact
patch in CONTACT's units and frames (:mod:`.table`), so that results compare line
by line with CONTACT's output.  An option railcontact does not support stops the
run before any work with one line naming it (:class:`InpError`).

>>> from railcontact.contact_inp import solve_inp
>>> rows = solve_inp("mbench_sweep_10kN.inp", cases=[1, 2])       # doctest: +SKIP
"""

from __future__ import annotations

import functools
from pathlib import Path

from ..cases.case import case_from_dict
from ..cases.solve import solve
from ..cases.sweep import CASE_SECONDS, OTHER_CASE_SECONDS, run_chains
from ..core.errors import RailContactError
from . import force_m1, module3, subsurface as _subs, transient_m1
from .mapping import MappedCase, map_case
from .reader import InpCase, InpError, read_inp
from .table import COLUMNS, rows, to_csv, to_json, to_text

__all__ = ["read_inp", "load_inp", "solve_inp", "map_case", "InpCase", "MappedCase",
           "InpError", "COLUMNS", "rows", "to_csv", "to_json", "to_text"]


def load_inp(path, cases=None, profile_dirs=()) -> list:
    """The railcontact cases of a CONTACT input file, every one checked before any
    is solved.

    Parameters
    ----------
    path : str or Path
        The ``.inp`` file.
    cases : iterable of int, optional
        Case numbers (1-based, in file order, as CONTACT counts them) to keep;
        default all.
    profile_dirs : iterable of str or Path
        More folders where profile files are looked for (after the input file's
        folder and the working directory).

    Returns a list of :class:`MappedCase`.
    """
    read = read_inp(path)
    if cases is not None:
        want = sorted(set(int(c) for c in cases))
        have = {c.number for c in read}
        missing = [c for c in want if c not in have]
        if missing:
            raise InpError(f"{Path(path).name}: no case {missing[0]} (the file holds cases "
                           f"1-{max(have)})")
        read = [c for c in read if c.number in want]
    mapped = [_map(c, tuple(profile_dirs)) for c in read]
    for c, m in zip(read, mapped):            # every case valid before any is solved
        if m.raw is not None:
            check_mapped(c, m)
    return mapped


#: the CONTACT inputs behind the keys of a mapped case, for the line of an error
INP_NAMES = {"wheelset.vertical_force": "FZ_WS", "wheelset.vertical_position": "Z_WS",
             "wheelset.lateral_shift": "Y_WS", "wheelset.yaw": "YAW", "wheelset.roll": "ROLL",
             "wheelset.velocity": "VS_WS", "wheelset.pitch_velocity": "VPITCH",
             "wheelset.lateral_velocity": "VY_WS", "wheelset.yaw_rate": "VYAW",
             "wheelset.flange_back_distance": "FBDIST",
             "wheelset.flange_back_position": "FBPOS", "wheel.nominal_radius": "NOMRADW",
             "rail.inclination": "CANT", "track.gauge": "GAUGWD", "friction": "FSTAT",
             "material": "GG1", "solver.element_size": "DX", "bodies.normal_force": "FN",
             "bodies.velocity": "VELOC", "bodies.radii": "A1", "creepage": "CKSI",
             "wheel.": "W_FNAME", "rail.": "R_FNAME"}


def check_mapped(case: InpCase, mapped: MappedCase):
    """The railcontact case of a mapped CONTACT case, validated; an invalid value is
    an :class:`InpError` naming the file, the case and the line of the CONTACT input
    behind it."""
    try:
        return case_from_dict(mapped.raw, case.path.parent)
    except RailContactError as exc:
        text = str(exc)
        name = next((n for key, n in INP_NAMES.items() if text.startswith(key)), None)
        raise InpError(f"{case.where(name)}: {text}") from None


def _map(case, profile_dirs):
    """A module 3 case on CONTACT's own grid or a transient one is solved by
    :mod:`.module3` (its ``raw`` is None, ``meta["inp"]`` the case, checked here);
    every other one through a railcontact case file (:func:`map_case`)."""
    if module3.handles(case):
        module3.check(case)
        return MappedCase(case.number, 3, None, {"module": 3, "inp": case})
    if transient_m1.handles(case):
        # module 1, transient (T = 1, 2): :mod:`.transient_m1`
        transient_m1.check(case, profile_dirs)
        return MappedCase(case.number, 1, None, {"module": 1, "inp": case,
                                                 "profile_dirs": profile_dirs})
    return map_case(case, profile_dirs)


def _solve_inp_chain(items, warm=False, normal=None, tangential=None, subsurface=False):
    """Solve mapped cases in order (each warm-started from the previous one where
    ``warm``); returns each case's rows, or its one-line error.  ``subsurface``:
    the first row of a case with S >= 1 gets its blocks of subsurface stresses
    (``row["subsurface"]``, :mod:`.subsurface`)."""
    out, prev = [], None
    seq = module3.Sequence()        # the transient state of module 3 cases
    seq1 = transient_m1.WheelRailSequence()     # ... and of module 1 cases
    for m in items:
        try:
            if m.raw is None and m.module == 1:
                out.append(seq1.run(m.meta["inp"], m.meta["profile_dirs"]))
                continue
            if m.raw is None:
                case_rows = [seq.run(m.meta["inp"])]
                if subsurface and _subs.wanted(m.meta["inp"]):
                    case_rows[0]["subsurface"] = _subs.case_blocks(
                        m.meta["inp"], [_subs.grid_loads(seq.last)])
                out.append(case_rows)
                continue
            if m.module == 3:
                seq.reset()
            if m.meta.get("fx_ws") is not None:
                # F = 1: the pitch velocity that gives FX_WS (:mod:`.force_m1`)
                res, m = force_m1.solve_for_force(m, lambda raw, w: solve(
                    case_from_dict(raw), normal, tangential, warm_start=w))
            else:
                res = solve(case_from_dict(m.raw), normal, tangential,
                            warm_start=prev if warm else None)
            prev = res
            case_rows = rows(res, m)
            inp = m.meta.get("inp")
            if subsurface and inp is not None and _subs.wanted(inp) and res.patches:
                case_rows[0]["subsurface"] = _subs.case_blocks(
                    inp, [_subs.patch_loads(p) for p in res.patches])
            out.append(case_rows)
            if m.module == 1:
                # a steady case's tractions: a following transient case's start
                seq1.remember(inp, m.raw, res)
        except RailContactError as exc:
            prev = None
            seq.reset()
            seq1.reset()
            out.append([{"case": m.number, "module": m.module, "patch": 0, "npatch": 0,
                         "converged": False, "message": f"error: {exc}"}])
    return out


def solve_inp(path, cases=None, profile_dirs=(), scheduler: str = "sync",
              progress: bool = False, warm: bool = False, normal: str | None = None,
              tangential: str | None = None, subsurface: bool = False) -> list:
    """Solve the cases of a CONTACT input file; returns the rows of
    :mod:`.table` (one per contact patch, CONTACT's units and frames), cases in
    file order.

    ``scheduler``: "sync" solves the cases one after the other (``railcontact
    solve``), "auto", "processes", "threads" or a Dask address in parallel
    (``railcontact sweep``; see :func:`railcontact.sweep`).  ``warm``: chains of
    consecutive cases, each warm-started from the previous one.  ``normal``,
    ``tangential``: models overriding the file's.  ``subsurface``: the cases with
    STRESS S >= 1 get their subsurface stresses, a list of blocks in the first
    row's ``"subsurface"`` (:func:`railcontact.contact_inp.subsurface.case_blocks`;
    written by :func:`~railcontact.contact_inp.subsurface.to_csv`).
    """
    mapped = load_inp(path, cases, profile_dirs)
    case_files = [m for m in mapped if m.raw is not None]
    names = {m.raw["solver"]["normal"] for m in case_files} | \
        {m.raw["solver"]["tangential"] for m in case_files} | {"exact"}
    expected = len(mapped) * max(CASE_SECONDS.get(n, OTHER_CASE_SECONDS) for n in names)
    chain = functools.partial(_solve_inp_chain, normal=normal, tangential=tangential,
                              subsurface=subsurface)
    # module 3 cases on their own grid carry state from case to case (transient
    # problems): the file is then solved as one chain, in order
    sequential = len(case_files) < len(mapped)
    out = run_chains(chain, mapped, scheduler=scheduler, progress=progress, warm=warm,
                     chains=1 if sequential else None,
                     expected_seconds=expected, desc=Path(path).name)
    return [r for case_rows in out for r in case_rows]
