"""Checks of the user's inputs made before any work: values named in errors cut to
a readable length, output paths that can be written, and the size of a job
against documented limits.

Every command of ``railcontact`` and the public API check their inputs here
before they compute: an output that cannot be written or a job too large for the
machine is an :class:`~railcontact.core.errors.InputError` naming the input, its
value (cut to :data:`SHOWN_CHARACTERS`) and what is expected, raised before the
first case is solved.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

from .errors import InputError, ResourceError

#: at most this many characters of a value are shown in an error message
SHOWN_CHARACTERS = 80

#: the largest exact boundary-element grid accepted without ``allow_large``:
#: 250 000 elements (500 x 500).  The exact normal solver's FFT products need about
#: 200 bytes per element of the doubled grid (0.2 GB here) and, measured on one
#: core, about 1 s per conjugate-gradient iteration at this size; 2000 x 2000
#: (4 million elements) would need 3 GB and minutes per case.
MAX_GRID_ELEMENTS = 250_000

#: the most cases of one sweep or positions of one ``track`` run accepted without
#: ``allow_large``
MAX_JOB_CASES = 100_000


def shown(value, limit: int = SHOWN_CHARACTERS) -> str:
    """``repr(value)`` cut to ``limit`` characters (with its length or shape said
    when cut), for error messages: never a whole 50 MB array in one line."""
    shape = getattr(value, "shape", None)
    try:
        text = repr(value) if shape is None or getattr(value, "size", 0) <= 16 else \
            f"array of shape {tuple(shape)}"
    except Exception:                                  # a repr that fails: its type
        text = f"<{type(value).__name__}>"
    text = " ".join(text.split())
    if len(text) > limit:
        n = len(value) if hasattr(value, "__len__") else None
        unit = "characters" if isinstance(value, (str, bytes)) else "items"
        text = text[:limit - 3] + "..." + (f" ({n} {unit})" if n is not None else "")
    return text


def check_output(path, what: str = "--out", folder: bool = False) -> Path:
    """``path`` as a place to write an output to, checked before any work.

    Parameters
    ----------
    path : str or Path
        A file (``folder=False``: its parent folder must exist and be writable, and
        the path must not be a folder) or a folder (``folder=True``: it may exist,
        as a folder, or be created in a writable parent; a folder's missing parents
        are created as ``mkdir -p`` does, so the nearest existing one must be a
        writable folder).
    what : str
        The input's name in the error.

    Returns the path; raises :class:`InputError` naming ``what``.
    """
    p = Path(path)
    if str(path).strip() == "":
        raise InputError(f"{what} = '': expected a {'folder' if folder else 'file'} name")
    if folder:
        if p.exists() and not p.is_dir():
            raise InputError(f"{what} {shown(str(path))}: an existing file; expected a folder "
                             "(new or existing) for the outputs")
        probe = p
        while not probe.exists():
            if probe.parent == probe:
                break
            probe = probe.parent
        if not probe.is_dir():
            raise InputError(f"{what} {shown(str(path))}: {str(probe)!r} is a file; expected "
                             "a folder")
        if not _writable(probe):
            raise InputError(f"{what} {shown(str(path))}: the folder {str(probe)!r} is not "
                             "writable")
        return p
    if p.is_dir():
        raise InputError(f"{what} {shown(str(path))}: an existing folder; expected a file name")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise InputError(f"{what} {shown(str(path))}: the folder {str(parent)!r} does not "
                         "exist; expected a file in an existing folder")
    if not _writable(parent) or (p.exists() and not os.access(p, os.W_OK)):
        raise InputError(f"{what} {shown(str(path))}: not writable (folder {str(parent)!r})")
    return p


def _writable(folder: Path) -> bool:
    """Whether a file can be created in ``folder``: tried (a read-only file system
    or a folder such as /proc refuses even root), the probe removed at once."""
    if not os.access(folder, os.W_OK | os.X_OK):
        return False
    import tempfile
    try:
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".railcontact-probe-"):
            pass
    except OSError:
        return False
    return True


def check_job_size(count: int, what: str, limit: int = MAX_JOB_CASES,
                   allow_large: bool = False, seconds_each: float | None = None) -> None:
    """Refuse a job of ``count`` cases or positions above ``limit`` unless
    ``allow_large``; the error estimates its time from ``seconds_each``."""
    if count <= limit or allow_large:
        return
    eta = ""
    if seconds_each:
        hours = count * seconds_each / 3600.0
        eta = f" (about {hours:.3g} h at {seconds_each:g} s each)"
    raise ResourceError(f"{what}: {count} cases{eta}; the limit is {limit} (give fewer, or "
                        "--allow-large to run it anyway)")


def check_grid_size(shape, what: str = "solver.grid", allow_large: bool = False) -> None:
    """Refuse an exact boundary-element grid of more than :data:`MAX_GRID_ELEMENTS`
    elements unless ``allow_large``, with its memory estimate."""
    n = int(math.prod(int(s) for s in shape))
    if n <= MAX_GRID_ELEMENTS or allow_large:
        return
    gb = 200.0 * 4 * n / 1e9
    raise ResourceError(f"{what} = {shown(list(shape))}: {n} elements (about {gb:.1f} GB and "
                        f"minutes per solve); the limit is {MAX_GRID_ELEMENTS} elements (give a "
                        "coarser grid or a larger solver.element_size, or solver.allow_large = "
                        "true / --allow-large)")
