"""Every CONTACT input of ``../shared/contact_testbank`` and ``../shared/reference``
through ``railcontact solve``: which run, which stop (and with what line), and how
close the ones that run come to CONTACT's printed output (``.ref_out``).

Per file the largest deviation over its cases and patches, against the issue's
tolerances: F_n, F_x, F_y within 1 % (tangential forces also relative to mu F_n,
which decides where the force is small), p_max and the contact area (elements in
contact) within 3 %; patches are matched by number (CONTACT's: field side to gauge
side).  The files of ``../shared/reference`` have CSV references instead, compared
case by case in ``benchmarks/contact_inputs.py``; here they are run and counted.

    python benchmarks/contact_testbank.py            # every file (long: module 1 files)
    python benchmarks/contact_testbank.py --quick    # read and map only; module 3 solved
    python benchmarks/contact_testbank.py FILTER     # files whose path contains FILTER

Writes ``benchmarks/contact_testbank.md`` and, run whole, the same table into
``docs/contact_users.md`` between its markers (:data:`DOC_BEGIN`, :data:`DOC_END`;
``tests/test_contact_testbank_doc.py`` checks that the two agree).
"""

from __future__ import annotations

import math
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SHARED = HERE.parent.parent / "shared"
REF = Path(os.environ.get("RAILCONTACT_REFERENCE", SHARED / "reference"))
BANK = SHARED / "contact_testbank"
TABLE_HEADER = "| input | status | against CONTACT |"
TOL = {"fn": 0.01, "ft": 0.01, "pmax": 0.03, "area": 0.03, "temp": 0.03}

lines: list = []
#: the user guide's copy of the table lies between these lines
DOC = HERE.parent / "docs" / "contact_users.md"
DOC_BEGIN = ("<!-- testbank table: written by `python benchmarks/contact_testbank.py` (its "
             "table in benchmarks/contact_testbank.md); tests/test_contact_testbank_doc.py "
             "checks that the two agree -->")
DOC_END = "<!-- end of the testbank table -->"


def out(s=""):
    print(s, flush=True)
    lines.append(s)


def _module3_deviations(rows, ref):
    """Largest deviations of module 3 rows against read_out's cases."""
    worst = {"fn": 0.0, "ft": 0.0, "pmax": 0.0, "area": 0.0}
    n = 0
    for r in rows:
        f = ref.get(r["case"])
        if f is None or not r.get("npatch"):
            continue
        n += 1
        mu = float(r.get("mu") or 0.0)
        scale = max(mu * f["fn_N"], 1e-12)
        worst["fn"] = max(worst["fn"], abs(r["fn_N"] / f["fn_N"] - 1) if f["fn_N"] else 0.0)
        if mu:
            # tangential: relative to CONTACT's force, or to mu F_n where that is larger
            for a, b in ((r["fx_N"], f["fx_N"]), (r["fs_N"], f["fy_N"])):
                worst["ft"] = max(worst["ft"], abs(a - b) / max(abs(b), scale))
        if f.get("pmax_MPa"):
            worst["pmax"] = max(worst["pmax"], abs(r["pmax_MPa"] / f["pmax_MPa"] - 1))
        if f.get("ncon"):
            worst["area"] = max(worst["area"], abs(r["ncon"] / f["ncon"] - 1))
        if f.get("tmax_C") is not None and r.get("tmax_C") is not None:
            # temperatures: the rise above 0 C in deg C, relative
            worst["temp"] = max(worst.get("temp", 0.0),
                                abs(r["tmax_C"] / f["tmax_C"] - 1) if f["tmax_C"] else 0.0)
    return n, worst


def _module1_deviations(rows, ref, cases=None):
    """Largest deviations per patch (matched by number) of module 1 rows against
    the parsed ``.ref_out`` (patches carrying at least a tenth of the case's load,
    as in tests/contact_inp/test_testbank.py; the smaller ones' largest F_n
    deviation apart), over ``cases`` (default all); also the cases whose patch
    count differs."""
    worst = {"fn": 0.0, "ft": 0.0, "pmax": 0.0, "area": 0.0}
    n, npatch_diff, small = 0, [], 0.0
    for case in sorted({r["case"] for r in rows}):
        if cases is not None and case not in cases:
            continue
        mine = [r for r in rows if r["case"] == case and r.get("npatch")]
        theirs = ref.get(case, {}).get("patches", [])
        if not theirs:
            continue
        n += 1
        if len(mine) != len(theirs):
            npatch_diff.append(case)
            continue
        load = sum(p.get("fn_N", 0.0) for p in theirs)
        for r, p in zip(mine, theirs):
            if "fn_N" not in p:
                continue
            if p["fn_N"] < 0.1 * load:
                small = max(small, abs(r["fn_N"] / p["fn_N"] - 1))
                continue
            # CONTACT's printed mu; with friction varying across the patch the
            # largest it prints (docs/conventions.md, "The friction coefficient of a
            # patch's figures")
            mu = float(p.get("mu") or r.get("mu") or 0.3)
            scale = mu * p["fn_N"]
            worst["fn"] = max(worst["fn"], abs(r["fn_N"] / p["fn_N"] - 1))
            for k in ("fx_N", "fs_N"):
                worst["ft"] = max(worst["ft"], abs(r[k] - p[k]) / max(abs(p[k]), scale))
            if p.get("pmax_MPa"):
                worst["pmax"] = max(worst["pmax"], abs(r["pmax_MPa"] / p["pmax_MPa"] - 1))
            if p.get("ncon") and r.get("ncon") is not None:
                # elements in contact (railcontact's grid has CONTACT's DX x DS)
                worst["area"] = max(worst["area"], abs(r["ncon"] / p["ncon"] - 1))
    return n, worst, npatch_diff, small


def _ranges(numbers) -> str:
    """Case numbers as CONTACT's --case list: 1-30,61-90,92."""
    out, run = [], []
    for k in numbers:
        if run and k == run[-1] + 1:
            run.append(k)
            continue
        if run:
            out.append(f"{run[0]}-{run[-1]}" if len(run) > 1 else str(run[0]))
        run = [k]
    if run:
        out.append(f"{run[0]}-{run[-1]}" if len(run) > 1 else str(run[0]))
    return ",".join(out)


def _fmt(worst):
    return ", ".join(f"{k} {100 * v:.2f} %" + ("" if v <= TOL[k] else " (over)")
                     for k, v in worst.items())


def run_file(path: Path, root: Path, quick: bool):
    from railcontact.contact_inp import load_inp, solve_inp
    from railcontact.contact_inp.outfile import read_out
    from railcontact.core.errors import RailContactError

    name = str(path.relative_to(root.parent))
    dirs = [REF / "profiles", BANK / "profiles"]
    subset = None
    try:
        mapped = load_inp(path, profile_dirs=dirs)
    except RailContactError as exc:
        # the cases that map on their own run (`railcontact solve FILE --cases ...`)
        from railcontact.contact_inp import read_inp
        try:
            numbers = [c.number for c in read_inp(path)]
        except RailContactError:
            numbers = []                 # the reader itself stops
        subset = []
        for k in numbers:
            try:
                load_inp(path, cases=[k], profile_dirs=dirs)
                subset.append(k)
            except RailContactError:
                pass
        if not subset:
            out(f"| `{name}` | stops | {str(exc).split(': ', 1)[-1][:160]} |")
            return "stops"
        mapped = load_inp(path, cases=subset, profile_dirs=dirs)
        first = str(exc).split(': ', 1)[-1][:120]
        subset = (subset, len(numbers), first)
    modules = {m.module for m in mapped}
    if quick and modules != {3}:
        out(f"| `{name}` | reads ({len(mapped)} cases, module {sorted(modules)}) | not solved "
            "(--quick) |")
        return "reads"
    t = time.perf_counter()
    try:
        rows = solve_inp(path, cases=None if subset is None else subset[0],
                         profile_dirs=dirs)
    except RailContactError as exc:
        out(f"| `{name}` | fails | {exc} |")
        return "fails"
    t = time.perf_counter() - t
    bad = sum(1 for r in rows if not r.get("converged", True))
    status = f"runs ({len(mapped)} cases, {t:.1f} s" + (f", {bad} rows not converged" if bad
                                                         else "") + ")"
    if subset is not None:
        status = (f"partly: cases {_ranges(subset[0])} of {subset[1]} run (`--case`, {t:.1f} s; the others "
                  "stop, "
                  f"first: {subset[2]})")
    ref_path = path.with_suffix(".ref_out")
    if not ref_path.is_file():
        out(f"| `{name}` | {status} | CSV reference: benchmarks/contact_inputs.py |")
        return "runs"
    if modules == {3}:
        n, worst = _module3_deviations(rows, read_out(ref_path))
        out(f"| `{name}` | {status} | {n} cases: {_fmt(worst)} |")
    else:
        sys.path.insert(0, str(HERE))
        from contact_inputs import parse_ref_out
        ref = parse_ref_out(ref_path)
        approx = {m.number for m in mapped if m.raw is not None
                  and m.raw["solver"]["normal"] != "exact"}
        parts = []
        for label, sel in (("exact", {m.number for m in mapped} - approx),
                           ("KPEC/ANALYN", approx)):
            if not sel:
                continue
            n, worst, diff, small = _module1_deviations(rows, ref, sel)
            txt = f"{n} cases ({label}): {_fmt(worst)}"
            if small:
                txt += f"; patches under a tenth of the load: F_n {100 * small:.1f} %"
            if diff:
                txt += f"; patch count differs in cases {diff}"
            parts.append(txt)
        out(f"| `{name}` | {status} | {'; '.join(parts)} |")
    return "runs" if subset is None else "runs partly"


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    quick = "--quick" in argv
    filters = [a for a in argv if not a.startswith("--")]
    out(f"# Every CONTACT input through railcontact ({time.strftime('%Y-%m-%d')}, "
        f"{os.cpu_count()} cores{', --quick' if quick else ''})\n")
    out("Largest deviation from CONTACT's `.ref_out` over each file's cases: F_n, F_x and "
        "F_y (`ft`: relative to CONTACT's force or mu F_n, the larger), p_max, elements in "
        "contact (`area`), largest surface temperature (`temp`); tolerances 1, 1, 3, 3, 3 %.\n")
    out(TABLE_HEADER)
    out("|---|---|---|")
    counts = {}
    for root in (BANK, REF):
        for path in sorted(root.rglob("*.inp")):
            if filters and not any(f in str(path) for f in filters):
                continue
            s = run_file(path, root, quick)
            counts[s] = counts.get(s, 0) + 1
    out("\n" + ", ".join(f"{v} {k}" for k, v in sorted(counts.items())))
    if not filters:
        (HERE / "contact_testbank.md").write_text("\n".join(lines) + "\n")
        if not quick:
            write_doc_table(table_of(lines))


def table_of(text_lines) -> list:
    """The table's lines (its header, rule and rows) among the lines of
    ``benchmarks/contact_testbank.md``."""
    i = text_lines.index(TABLE_HEADER)
    j = i
    while j + 1 < len(text_lines) and text_lines[j + 1].startswith("|"):
        j += 1
    return list(text_lines[i:j + 1])


def doc_table(doc_lines) -> list:
    """The table's lines between the user guide's markers."""
    i = doc_lines.index(DOC_BEGIN)
    return list(doc_lines[i + 1:doc_lines.index(DOC_END, i)])


def write_doc_table(table) -> None:
    """Replace the user guide's copy of the table (between its markers)."""
    doc = DOC.read_text().split("\n")
    i = doc.index(DOC_BEGIN)
    doc[i + 1:doc.index(DOC_END, i)] = table
    DOC.write_text("\n".join(doc))


if __name__ == "__main__":
    main()
