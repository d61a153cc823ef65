"""``make bench``'s sections before and after a change, interleaved.

Runs sections of ``benchmarks/run_all.py`` on a git ref (checked out as a
temporary worktree beside this checkout, so that ``../shared`` is found the same
way; each tree with its own ``run_all.py`` and Numba cache) and on
this checkout, alternating tree by tree for ROUNDS rounds, so that the machine's
drift (up to 1.4x between runs) falls on both alike; prints each run's result
lines.

    .venv/bin/python benchmarks/before_after.py REF [ROUNDS] [SECTION ...]

SECTION is a ``bench_*`` function of run_all.py without its prefix, e.g.
``hertz_fastsim`` (default: hertz_fastsim, exact_module3, exact_wheel_rail,
dynamics), or a name of :data:`CALLS` (``compiled_sweep``, ``compiled_strips``:
the sweeps of ``benchmarks/compiled_case.py``).  ``benchmarks/exact_case.py --before
REF`` takes its "before" from a ref the same way (:func:`ref_tree`).  Example: ``before_after.py 7dc4656 3 hertz_fastsim`` for issue 29's
layout against the main it started from.
"""

from __future__ import annotations

import contextlib
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DEFAULT = ("hertz_fastsim", "exact_module3", "exact_wheel_rail", "dynamics")
#: sections that take the result of another
CALLS = {"hertz_fastsim": "t = run_all.bench_hertz_fastsim(); run_all.bench_contact_sweep(t)",
         # benchmarks/compiled_case.py's sweeps (the compiled pass), printed
         "compiled_sweep": "import compiled_case as c; "
                           "c.bench_compiled_sweep(print, run_all.conv_time)",
         "compiled_strips": "import compiled_case as c; "
                            "c.bench_strip_sweep(print, run_all.conv_time)"}


def run(tree: Path, section: str) -> tuple[float, str]:
    """One section in ``tree``: wall time [s] and its result lines."""
    code = ("import sys; sys.path.insert(0, 'benchmarks'); import run_all; "
            + CALLS.get(section, f"run_all.bench_{section}()"))
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tree / ".venv-bench-numba"))
    t0 = time.perf_counter()
    p = subprocess.run([sys.executable, "-c", code], cwd=tree, env=env, capture_output=True,
                       text=True)
    lines = [ln for ln in p.stdout.splitlines() if ln.startswith(("*", "|"))]
    if p.returncode:
        lines.append(f"FAILED ({p.returncode}): {p.stderr.strip().splitlines()[-1:]}")
    return time.perf_counter() - t0, "\n".join(lines)


@contextlib.contextmanager
def ref_tree(ref: str):
    """The git ref ``ref`` checked out as a temporary worktree beside this checkout
    (so that ``../shared`` is found the same way), removed on exit; yields its path."""
    with tempfile.TemporaryDirectory(prefix=".railcontact-before-", dir=ROOT.parent) as tmp:
        old = Path(tmp)                 # an empty folder beside this checkout
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "-q", "--detach", str(old),
                        ref], check=True)
        try:
            yield old
        finally:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(old)],
                           check=False)


def main(argv: list) -> None:
    ref = argv[0] if argv else "HEAD"
    rounds = int(argv[1]) if len(argv) > 1 else 2
    sections = argv[2:] or list(DEFAULT)
    with ref_tree(ref) as old:
        for section in sections:
            for r in range(rounds):
                for tag, tree in (("before", old), ("after", ROOT)):
                    wall, text = run(tree, section)
                    name = ref if tag == "before" else "this checkout"
                    print(f"### {section}, round {r + 1}, {tag} ({name}, {wall:.0f} s)\n"
                          f"{text}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
