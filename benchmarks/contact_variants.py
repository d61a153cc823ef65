"""Variants of CONTACT's testbank inputs that railcontact has not seen, run by
CONTACT and by railcontact.

Each variant is built at run time from an input of ``../shared/contact_testbank``
(never copied into the repository) by changing loads, creepages, velocities or
positions on the input's own lines (found by the labels CONTACT prints after the
values, e.g. ``FN, CKSI, CETA, CPHI``), optionally keeping only the first cases.
One or two variants per physics family: steady wheel-rail (Manchester A-2.2),
transient wheel-rail (``t1_*``), Cattaneo and Cattaneo-to-Carter, conformal
contact, roller rigs, viscoelastic rolling, the plastic interface layer, the flash
temperature, velocity-dependent and varying friction, the wheel flat, switches and
crossings.

    python benchmarks/contact_variants.py --contact EXE   # run CONTACT, write the CSV, compare
    python benchmarks/contact_variants.py --contact EXE --contact-only   # CONTACT's CSV only
    python benchmarks/contact_variants.py                 # compare with the committed CSV
    python benchmarks/contact_variants.py NAME ...        # only these variants
    python benchmarks/contact_variants.py --keep DIR      # leave the variant inputs in DIR

With ``--contact`` CONTACT's output is digested per case and patch (F_n, F_x,
F_y or F_s, mu, elements in contact, p_max, the largest surface temperature; by
the testbank's parsers: ``contact_inputs.parse_ref_out`` for wheel-rail output,
``railcontact.contact_inp.outfile.read_out`` for module 3) into
``benchmarks/contact_variants.csv``.  Then every variant runs through
``railcontact.contact_inp.solve_inp`` and is compared at the issue's tolerances
with the deviation rules of ``benchmarks/contact_testbank.py``; the table goes to
``benchmarks/contact_variants.md``.
"""

from __future__ import annotations

import csv
import os
import re
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

HERE = Path(__file__).resolve().parent
SHARED = HERE.parent.parent / "shared"
BANK = Path(os.environ.get("RAILCONTACT_TESTBANK", SHARED / "contact_testbank"))
REF = Path(os.environ.get("RAILCONTACT_REFERENCE", SHARED / "reference"))
CSV_PATH = HERE / "contact_variants.csv"
MD_PATH = HERE / "contact_variants.md"
COLUMNS = ("variant", "module", "case", "patch", "fn_N", "fx_N", "fy_N", "fs_N", "mu",
           "ncon", "pmax_MPa", "tmax_C")

_VALUE = re.compile(r"^(?:'[^']*'|[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?[dr]?)$")
_MODULE = re.compile(r"^\s*(\d+)\s+MODULE\b")


@dataclass(frozen=True)
class Edit:
    """One change: the value labelled ``label`` becomes ``value * arg`` (``op`` =
    "scale"), ``value + arg`` ("add") or ``arg`` ("set"), in the cases ``cases``
    (CONTACT's case numbers; all kept cases when None)."""

    label: str
    op: str
    arg: float
    cases: tuple | None = None

    def describe(self) -> str:
        where = "" if self.cases is None else f" (case {','.join(map(str, self.cases))})"
        val = {"scale": f"×{self.arg:.6g}", "add": f"{self.arg:+g}".replace("-", "−"),
               "set": f"= {self.arg:g}".replace("-", "−")}[self.op]
        return f"{self.label} {val}{where}"


@dataclass(frozen=True)
class Variant:
    """A variant of ``source`` (relative to the testbank): the first ``keep``
    cases (all when None) with ``edits`` applied."""

    name: str
    family: str
    source: str
    edits: tuple
    keep: int | None = None
    note: str = ""
    fields: dict = field(default_factory=dict)


VARIANTS = (
    Variant("a22_left_load_pos", "steady wheel-rail", "examples_basic/mbench_a22_left.inp",
            (Edit("FZ", "scale", 1.4), Edit("Y", "add", 0.3)), keep=8),
    Variant("a22_right_creep_vel", "steady wheel-rail", "examples_basic/mbench_a22_right.inp",
            (Edit("VS", "scale", 1.5), Edit("VPITCH", "scale", 1.5 * 1.0015)), keep=8),
    Variant("t1_force_cp_load_pos", "transient wheel-rail", "examples_trans/t1_force_cp.inp",
            (Edit("FZ", "scale", 0.8), Edit("Y", "add", -0.5))),
    Variant("t1_zws_pos", "transient wheel-rail", "examples_trans/t1_zws.inp",
            (Edit("Y", "add", 0.1),), keep=3,
            note="position control (Z prescribed): the load follows the position"),
    Variant("cattaneo_load_shift", "Cattaneo", "examples_basic/cattaneo.inp",
            (Edit("FN", "scale", 1.5), Edit("FX", "set", -0.6))),
    Variant("catt_to_cart_load_creep", "Cattaneo to Carter", "examples_basic/catt_to_cart.inp",
            (Edit("FN", "scale", 1.3), Edit("FX", "scale", 0.8))),
    Variant("mbench_conf_pos", "conformal", "examples_conformal/mbench_conf.inp",
            (Edit("FZ", "add", 0.003), Edit("VPITCH", "scale", 1.001)),
            note="position control: FZ is the vertical position z_ws [mm]"),
    Variant("rollers2_load_creep", "roller rig", "examples_conformal/test-rollers2.inp",
            (Edit("Z_WS", "scale", 0.8), Edit("VPITCH_WS", "scale", 1.002)), keep=6),
    Variant("rollers3_load_creep", "roller rig", "examples_conformal/test-rollers3.inp",
            (Edit("Z_WS", "scale", 1.2), Edit("VPITCH_WS", "scale", 0.998)), keep=6),
    Variant("visc_load_vel", "viscoelastic", "examples_basic/visc_cylindr.inp",
            (Edit("FN", "scale", 0.75), Edit("VELOC", "scale", 1.5)),
            note="VELOC x2 or x0.5 stops CONTACT in case 2 (numerical integration of an "
                 "influence coefficient)"),
    Variant("carter_plast_load_creep", "plasticity", "examples_plast/carter_plast.inp",
            (Edit("FN", "scale", 0.8), Edit("CKSI", "scale", 1.5))),
    Variant("catt3d_plast_load", "plasticity", "examples_plast/catt3d_plast.inp",
            (Edit("FN", "scale", 1.2),), keep=12),
    Variant("ertz_load_creep_vel", "temperature", "examples_basic/ertz_temperature.inp",
            (Edit("FN", "scale", 0.8), Edit("CKSI", "scale", 1.5), Edit("VELOC", "scale", 0.6))),
    Variant("veldep_vel_load", "velocity-dependent friction", "examples_basic/veldep_fric.inp",
            (Edit("VELOC", "scale", 2.0 / 3.0), Edit("FN", "scale", 0.9)), keep=12),
    Variant("varfric_load_pos", "varying friction", "examples_basic/mbench_a22_varfric.inp",
            (Edit("FZ", "scale", 1.2), Edit("Y", "add", 0.3)), keep=4),
    Variant("wheelflat_pos_load", "wheel flat", "examples_basic/wheelflat.inp",
            (Edit("PITCH", "add", 0.5), Edit("FZ", "scale", 0.8), Edit("Z", "scale", 0.8)),
            keep=5, note="force control throughout: the later cases label the force Z"),
    Variant("cross_wing_pos", "switches and crossings", "examples_s+c/cross+wing.inp",
            (Edit("Y", "add", 0.5), Edit("VPITCH", "scale", 1.001))),
    Variant("wing_locus_pos", "switches and crossings", "examples_s+c/wing_locus.inp",
            (Edit("Y", "add", 1.0), Edit("Z", "add", -0.01))),
)


def _labels(line: str):
    """The value tokens of an input line and the labels printed after them."""
    toks = line.split()
    n = 0
    while n < len(toks) and _VALUE.match(toks[n]):
        n += 1
    labels = [t for t in re.split(r"[,\s]+", " ".join(toks[n:]).replace("%", " ")) if t]
    return toks[:n], labels


def _fmt_value(v: float) -> str:
    s = f"{v:.10g}"
    return s if any(c in s for c in ".eE") else s + "."


def _apply(token: str, edit: Edit) -> str:
    suffix = token[-1] if token[-1] in "dr" else ""
    v = float(token[: len(token) - len(suffix)].replace("D", "E").replace("d", "e"))
    new = {"scale": v * edit.arg, "add": v + edit.arg, "set": edit.arg}[edit.op]
    return _fmt_value(new) + suffix


def variant_text(v: Variant, bank: Path = BANK) -> str:
    """The variant's input text: the source's first ``v.keep`` cases with the
    edits applied (each edit must apply at least once)."""
    src = (bank / v.source).read_text(errors="replace").splitlines()
    out, case, hits = [], 0, {e: 0 for e in v.edits}
    for line in src:
        m = _MODULE.match(line)
        if m:
            if int(m.group(1)) == 0:
                break
            case += 1
            if v.keep is not None and case > v.keep:
                break
        if line.lstrip().startswith("%"):
            out.append(line)
            continue
        values, labels = _labels(line)
        for e in v.edits:
            if e.cases is not None and case not in e.cases:
                continue
            if e.label in labels[: len(values)]:
                k = labels.index(e.label)
                values[k] = _apply(values[k], e)
                hits[e] += 1
                lead = line[: len(line) - len(line.lstrip())]
                # the rest of the line (labels, comments) as it was
                rest = line.split(None, len(values))[len(values)] if len(line.split()) > len(values) else ""
                line = lead + "  ".join(values) + ("    " + rest if rest else "")
        out.append(line)
    missing = [e.describe() for e, n in hits.items() if n == 0]
    if missing:
        raise ValueError(f"variant {v.name}: {', '.join(missing)} not found in {v.source}")
    out.append(" 0  MODULE")
    return "\n".join(out) + "\n"


def write_variant(v: Variant, root: Path, bank: Path = BANK) -> Path:
    """Write the variant into ``root`` in the testbank's layout (the source's
    folder and ``profiles`` linked, so that relative file names resolve) and
    return its path."""
    folder = root / Path(v.source).parent
    folder.mkdir(parents=True, exist_ok=True)
    for entry in (bank / Path(v.source).parent).iterdir():
        if entry.suffix in (".inp", ".ref_out", ".out"):
            continue
        link = folder / entry.name
        if not link.exists():
            link.symlink_to(entry)
    prof = root / "profiles"
    if not prof.exists():
        prof.symlink_to(bank / "profiles")
    path = folder / f"{v.name}.inp"
    path.write_text(variant_text(v, bank))
    return path


def _testbank_helpers():
    sys.path.insert(0, str(HERE))
    import contact_testbank as tb
    from contact_inputs import parse_ref_out
    return tb, parse_ref_out


def digest_contact_out(v: Variant, out_path: Path) -> list:
    """CSV rows of one CONTACT output file (per case and patch)."""
    from railcontact.contact_inp.outfile import read_out
    _, parse_ref_out = _testbank_helpers()
    rows = []
    for case, c in sorted(parse_ref_out(out_path).items()):
        for k, p in enumerate(c["patches"], 1):
            if "fn_N" not in p:
                continue
            rows.append({"variant": v.name, "module": 1, "case": case, "patch": k,
                         "fn_N": p["fn_N"], "fx_N": p["fx_N"], "fs_N": p["fs_N"],
                         "mu": p.get("mu"), "ncon": p.get("ncon"), "pmax_MPa": p.get("pmax_MPa")})
    for case, c in sorted(read_out(out_path).items()):
        rows.append({"variant": v.name, "module": 3, "case": case, "patch": 1,
                     "fn_N": c["fn_N"], "fx_N": c["fx_N"], "fy_N": c["fy_N"],
                     "ncon": c.get("ncon"), "pmax_MPa": c.get("pmax_MPa"),
                     "tmax_C": c.get("tmax_C")})
    return rows


def run_contact(exe: str, v: Variant, root: Path, timeout: float = 1800.0) -> tuple:
    """Run CONTACT on the variant (in its folder under ``root``); its rows and time."""
    path = write_variant(v, root)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    t = time.perf_counter()
    subprocess.run([exe, "2", path.stem], cwd=path.parent, env=env, timeout=timeout,
                   stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT, check=False)
    t = time.perf_counter() - t
    out_path = path.with_suffix(".out")
    if not out_path.is_file():
        raise RuntimeError(f"CONTACT wrote no output for {v.name}")
    return digest_contact_out(v, out_path), t


def write_csv(rows: list, label: str, path: Path = CSV_PATH) -> None:
    with open(path, "w", newline="") as f:
        f.write(f"# CONTACT's results on the variants of benchmarks/contact_variants.py; {label}\n")
        f.write("# module 1: forces per patch (fs_N: F_s in the tangent plane); module 3: totals "
                "(fy_N); N, MPa, deg C\n")
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        for r in rows:
            w.writerow({k: ("" if r.get(k) is None else r.get(k)) for k in COLUMNS})


def read_csv(path: Path = CSV_PATH) -> dict:
    """CONTACT's rows per variant, in the shapes of the testbank parsers:
    {variant: (module, {case: ...})}."""
    out: dict = {}
    with open(path) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))

    def num(x):
        return None if x in ("", None) else float(x)
    for r in rows:
        module = int(r["module"])
        mod, cases = out.setdefault(r["variant"], (module, {}))
        case = int(r["case"])
        if module == 1:
            p = {"fn_N": num(r["fn_N"]), "fx_N": num(r["fx_N"]), "fs_N": num(r["fs_N"]),
                 "pmax_MPa": num(r["pmax_MPa"])}
            if r["mu"]:
                p["mu"] = num(r["mu"])
            if r["ncon"]:
                p["ncon"] = int(float(r["ncon"]))
            cases.setdefault(case, {"patches": []})["patches"].append(p)
        else:
            cases[case] = {"fn_N": num(r["fn_N"]), "fx_N": num(r["fx_N"]),
                           "fy_N": num(r["fy_N"]), "pmax_MPa": num(r["pmax_MPa"]),
                           "ncon": None if not r["ncon"] else int(float(r["ncon"])),
                           "tmax_C": num(r["tmax_C"])}
    return out


def compare(v: Variant, rows: list, module: int, ref: dict) -> tuple:
    """(cases compared, largest deviations, notes) of railcontact's rows against
    CONTACT's, with benchmarks/contact_testbank.py's rules."""
    tb, _ = _testbank_helpers()
    if module == 3:
        n, worst = tb._module3_deviations(rows, ref)
        return n, worst, ""
    n, worst, diff, small = tb._module1_deviations(rows, ref)
    notes = []
    if small:
        notes.append(f"patches under a tenth of the load: F_n {100 * small:.1f} %")
    if diff:
        notes.append(f"patch count differs in cases {diff}")
    return n, worst, "; ".join(notes)


def solve_variant(v: Variant, root: Path) -> tuple:
    from railcontact.contact_inp import solve_inp
    path = write_variant(v, root)
    t = time.perf_counter()
    rows = solve_inp(path, profile_dirs=[REF / "profiles", BANK / "profiles"])
    return rows, time.perf_counter() - t


def main(argv=None):
    argv = list(sys.argv[1:] if argv is None else argv)
    exe = label = keep = None
    only = "--contact-only" in argv
    argv = [a for a in argv if a != "--contact-only"]
    names = []
    while argv:
        a = argv.pop(0)
        if a == "--contact":
            exe = argv.pop(0)
        elif a == "--label":
            label = argv.pop(0)
        elif a == "--keep":
            keep = Path(argv.pop(0))
        else:
            names.append(a)
    chosen = [v for v in VARIANTS if not names or v.name in names]
    root = keep or Path(tempfile.mkdtemp(prefix="contact_variants_"))
    tb, _ = _testbank_helpers()
    lines = []

    def out(s=""):
        print(s, flush=True)
        lines.append(s)

    if exe:
        rows, times = [], {}
        for v in chosen:
            r, t = run_contact(exe, v, root / "contact")
            rows += r
            times[v.name] = t
            print(f"CONTACT {v.name}: {len(r)} rows, {t:.1f} s", flush=True)
        if not names:
            write_csv(rows, label or f"CONTACT executable {exe}")
        if only:
            return
    ref = read_csv()
    out(f"# Variants of the testbank inputs, CONTACT against railcontact "
        f"({time.strftime('%Y-%m-%d')}, {os.cpu_count()} cores)\n")
    with open(CSV_PATH) as f:
        head = f.readline().lstrip("# ").strip()
    out(f"CONTACT's figures: `benchmarks/contact_variants.csv` ({head}).\n")
    out("Largest deviation over each variant's cases (and patches carrying at least a "
        "tenth of the load): F_n; F_x and F_y/F_s (`ft`: relative to CONTACT's force or "
        "mu F_n, the larger); p_max; elements in contact (`area`); largest surface "
        "temperature (`temp`). Tolerances 1, 1, 3, 3, 3 %.\n")
    out("| variant | family | from | changed | railcontact | against CONTACT |")
    out("|---|---|---|---|---|---|")
    ok = 0
    for v in chosen:
        changed = "; ".join(e.describe() for e in v.edits)
        if v.keep:
            changed += f"; first {v.keep} cases"
        if v.name not in ref:
            out(f"| `{v.name}` | {v.family} | `{v.source}` | {changed} | | no CONTACT rows |")
            continue
        module, cases = ref[v.name]
        rows, t = solve_variant(v, root / "railcontact")
        n, worst, notes = compare(v, rows, module, cases)
        bad = sum(1 for r in rows if not r.get("converged", True))
        within = all(val <= tb.TOL[k] for k, val in worst.items())
        ok += within
        status = f"{len(cases)} cases, {t:.1f} s" + (f", {bad} rows not converged" if bad else "")
        out(f"| `{v.name}` | {v.family} | `{v.source}` | {changed} | {status} | {n} cases: "
            f"{tb._fmt(worst)}{'; ' + notes if notes else ''} |")
    out(f"\n{ok} of {len(chosen)} variants within every tolerance.")
    notes = [v for v in chosen if v.note]
    if notes:
        out("")
        for v in notes:
            out(f"* `{v.name}`: {v.note}.")
    if not names:
        MD_PATH.write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
