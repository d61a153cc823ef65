"""Where ``t3_t2_conformal`` case 3's middle patch F_s comes from (issue 34): the
vertical balance (F_z = 117 kN) and the wheelset height z_ws that sets the patch's
reference angle.

Case 3 (transient rolling after cases 1-2 at 137 kN) splits the large patch in two;
the middle patch's reference angle follows CONTACT's turning rule for nearby patches,
whose patch-end distance moves about 0.54 mm per um of z_ws, so that the patch's bar
F_s moves about 3 N per nm of z_ws.  This script solves case 3 (cases 1-2 first, as
the file has them) three ways with railcontact:

* as given (F_z prescribed), with ``solver.force_tolerance`` 1e-4 (the case default,
  which the ``.inp`` path keeps), 1e-6 (the file's EPS) and 1e-8: the z_ws found, the
  F_z met, the middle patch's reference angle and bar F_s;
* at prescribed wheelset heights (copies of the file with N = 0 and Z_WS in case 3):
  F_z(z_ws), the middle patch's angle and F_s along z_ws.

It prints CONTACT's printed F_s (the ``.ref_out``) beside them.  Figures measured
with CONTACT itself (rev. 2707, built locally; its output with X_FORCE = 3, which
prints the Brent iterations of z_ws to 8 digits) are in docs/contact_users.md (the
paragraph on ``t3_t2_conformal`` below the testbank table); in short: CONTACT's z_ws
is 1.2081357 mm with EPS 1e-6 (the file's), 1e-7, 1e-8 and 1e-10 alike (F_s -2011 N
each time), so its balance is converged; its F_z(z_ws) is not monotone (a dip to
116913 N at 1.20832 mm), so that F_z = 117 kN has three roots (z_ws 1.2081357,
about 1.208258 and 1.208360 mm, middle patch F_s -2011, -1644, -1351 N) of which its
Brent iteration finds the first.

    python benchmarks/t3_t2_conformal_balance.py

Measured (2026-11-27, railcontact): z_ws 1.2081201 mm at the default tolerance
(F_z 117000.9 N, F_s -2107.5 N), 1.2081198 mm at 1e-6 and 1e-8 (F_s -2108.2,
-2108.1 N): the balance's tolerance moves z_ws by 0.3 nm, not the 16 nm to
CONTACT's.  Along z_ws railcontact's F_z is 12 to 206 N above CONTACT's from
1.2081 to 1.20836 mm (+51.6 N at CONTACT's root 1.2081357 mm; 102 N below at
1.2080, 147 N below at 1.2084 mm) and its dip stays above 117 kN (117050 N at
1.20835 mm): one root.  At the same z_ws the middle patch's F_s is 43
to 55 N below CONTACT's (-2108.2 against -2058 N at 1.2081198 mm, -2062.6 against
-2011 N at 1.2081357 mm), its reference angle 0.9 mrad below (-0.52718 against
-0.52628 rad at 1.2081198 mm).
"""

from __future__ import annotations

import re
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

import railcontact.contact_inp.transient_m1 as transient_m1  # noqa: E402
from railcontact.contact_inp import solve_inp  # noqa: E402

BANK = HERE.parent.parent / "shared" / "contact_testbank"
FILE = BANK / "examples_trans" / "t3_t2_conformal.inp"
#: the middle patch's y_tr [mm] in case 3 (CONTACT's 723.3827)
Y_MIDDLE = 723.38
#: wheelset heights [mm] of the scan: below CONTACT's root to past its dip
Z_SCAN = (1.2080, 1.2081, 1.2081198, 1.2081357, 1.2081500, 1.2082, 1.2082582,
          1.2083, 1.2083601, 1.2084)


def _cases_1_to_3(folder: Path, z_ws: float | None = None) -> Path:
    """A copy of the file that stops after case 3 (its profile paths absolute); case 3
    at the prescribed wheelset height ``z_ws`` [mm] (N = 0) where given."""
    lines = FILE.read_text().splitlines()
    starts = [i for i, line in enumerate(lines) if line.strip().startswith("1 MODULE")]
    head, c3 = lines[:starts[2]], starts[1]
    if z_ws is not None:
        assert head[c3 + 1].split()[0] == "1002100"
        head[c3 + 1] = head[c3 + 1].replace("1002100", "1002000", 1)
        j = next(k for k in range(c3, len(head)) if "117000." in head[k])
        head[j] = head[j].replace("117000.", f"{z_ws:.9f}", 1)
    text = "\n".join(head) + "\n\n 0  MODULE\n"
    path = folder / f"t3_t2_conformal_{'force' if z_ws is None else f'z{z_ws:.7f}'}.inp"
    path.write_text(text.replace("'../profiles/", f"'{BANK / 'profiles'}/"))
    return path


def _case3(path: Path, tolerance: float | None = None) -> tuple[dict, float]:
    """Case 3's middle-patch row and its F_z [N] (``solver.force_tolerance`` set to
    ``tolerance`` in the mapped cases of the transient path where given)."""
    original = transient_m1.map_case

    def mapped(case, dirs=()):
        m = original(case, dirs)
        if tolerance is not None:
            m.raw.setdefault("solver", {})["force_tolerance"] = tolerance
        return m

    transient_m1.map_case = mapped
    try:
        rows = [r for r in solve_inp(path) if r["case"] == 3]
    finally:
        transient_m1.map_case = original
    mid = min(rows, key=lambda r: abs(r["ycp_tr_mm"] - Y_MIDDLE))
    return mid, rows[0]["fz_tr_N"]


def _contact_fs() -> float:
    """CONTACT's printed bar F_s [N] of case 3's middle patch (the ``.ref_out``)."""
    text = FILE.with_suffix(".ref_out").read_text()
    body = re.split(r"\n Case +\d+\n", text)[3]
    for part in re.split(r"----- DATA FOR CONTACT PATCH", body)[1:]:
        y = float(re.search(r"DELTCP\(TR\).*\n\s+\S+\s+(\S+)", part).group(1))
        if abs(y - Y_MIDDLE) < 0.05:
            return float(re.search(r"BAR_FN\s+BAR_FX\s+BAR_FS.*\n\s+\S+\s+\S+\s+(\S+)",
                                   part).group(1))
    raise LookupError("no middle patch in case 3 of the .ref_out")


def main() -> None:
    if not FILE.is_file():
        print("t3_t2_conformal.inp not found; skipped")
        return
    print("## t3_t2_conformal case 3: the vertical balance and the middle patch's F_s")
    print(f"CONTACT's middle patch bar F_s (.ref_out): {_contact_fs():.0f} N")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        given = _cases_1_to_3(folder)
        print("\nF_z = 117 kN prescribed, railcontact's balance tolerance:")
        for tol in (None, 1e-6, 1e-8):
            mid, fz = _case3(given, tol)
            name = "default" if tol is None else f"{tol:g}"
            print(f"* force_tolerance {name}: z_ws {mid['z_ws_mm']:.7f} mm, F_z {fz:.3f} N, "
                  f"delta {mid['delta_tr_rad']:.5f} rad, F_s {mid['fs_N']:.1f} N")
        print("\nz_ws prescribed (N = 0):")
        print("| z_ws [mm] | F_z [N] | delta [rad] | F_n [N] | F_s [N] | elements |")
        print("|---|---|---|---|---|---|")
        for z in Z_SCAN:
            mid, fz = _case3(_cases_1_to_3(folder, z))
            print(f"| {z:.7f} | {fz:.1f} | {mid['delta_tr_rad']:.5f} | {mid['fn_N']:.1f} | "
                  f"{mid['fs_N']:.1f} | {mid['ncon']} |")


if __name__ == "__main__":
    main()
