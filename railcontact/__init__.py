"""railcontact: wheel-rail rolling contact and wear.

Layers (one sub-package each): :mod:`~railcontact.profiles`, :mod:`~railcontact.geometry`,
:mod:`~railcontact.normal`, :mod:`~railcontact.tangential`.  Above them:
:func:`solve` (one case), :func:`sweep` (many cases) and the ``railcontact`` command.
All quantities are in SI units; conventions in ``docs/conventions.md``.
"""

import logging
import os
import sys


def _numba_cache_dir() -> None:
    """Numba's on-disk cache where ``make`` keeps it (``.venv/numba-cache/<hash of
    the sources>``, see the Makefile) also for commands run outside ``make``, so that
    they load the compiled kernels instead of compiling them again; only for a
    source checkout run from a virtual environment, and where NUMBA_CACHE_DIR is
    not set."""
    if "NUMBA_CACHE_DIR" in os.environ or sys.prefix == sys.base_prefix:
        return
    import hashlib
    from pathlib import Path
    here = Path(__file__).resolve().parent
    root = here.parent
    if not (root / "Makefile").is_file() or Path(sys.prefix).resolve() != root / ".venv":
        return
    files = sorted(str(p.relative_to(root)) for p in here.rglob("*.py"))
    digest = hashlib.sha1()
    for name in sorted(files, key=lambda s: s.encode()):
        digest.update((root / name).read_bytes())
    os.environ["NUMBA_CACHE_DIR"] = str(root / ".venv" / "numba-cache" / digest.hexdigest()[:12])


_numba_cache_dir()


def _quiet_interrupt_at_start() -> None:
    """The ``railcontact`` command: Ctrl-C while Python still imports the package
    ends it at once, exit status 130 and one line (no traceback);
    :func:`railcontact.cli.console_main` takes the signal over once it runs."""
    if not sys.argv or os.path.basename(sys.argv[0]) != "railcontact":
        return
    import signal

    def stop(signum, frame):
        sys.stderr.write("railcontact: interrupted\n")
        sys.stderr.flush()
        os._exit(130)
    try:
        signal.signal(signal.SIGINT, stop)
    except ValueError:                      # not the main thread
        pass


_quiet_interrupt_at_start()

from .cases.case import Case, case_from_dict, load_case
from .core.errors import (CaseFileError, ContactNotFoundError, ConvergenceError, InputError,
                     ProfileError, RailContactError, UnknownModelError)
from .core.materials import Material
from .cases.solve import solve
from .cases.equilibrium import VerticalBalance
from .cases.results import PatchResult, SolveResult
from .cases.sweep import sweep

__version__ = "0.1.0"
logging.getLogger(__name__).addHandler(logging.NullHandler())

__all__ = ["solve", "sweep", "load_case", "case_from_dict", "Case", "Material", "SolveResult",
           "VerticalBalance", "PatchResult", "RailContactError", "InputError", "ProfileError",
           "CaseFileError", "UnknownModelError", "ContactNotFoundError", "ConvergenceError",
           "__version__"]
