"""Input files read with a clear error, and result files written whole or not at all.

:func:`read_toml` reads a TOML input (a case, a scenario, a parameter file); a
missing, undecodable or invalid file is a :class:`~railcontact.core.errors.CaseFileError`
naming what the file was meant to be.

Every file railcontact writes (results, tables, profiles, checkpoints) is first
written under a temporary name beside its destination (``NAME.tmp``) and then
renamed onto it, so that an interrupted or failed write never leaves a
half-written file under the real name; on an error the temporary file is removed.
"""

from __future__ import annotations

import tomllib
from contextlib import contextmanager
from pathlib import Path

from .errors import CaseFileError


def read_toml(path, what: str = "case file") -> dict:
    """Parse a TOML input file; a missing or unreadable file is a
    :class:`~railcontact.core.errors.CaseFileError` naming ``what`` the file was
    meant to be."""
    path = Path(path)
    if not path.is_file():
        raise CaseFileError(f"{what} {str(path)!r} does not exist")
    try:
        return tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as exc:
        raise CaseFileError(f"{path}: not valid TOML: {exc}") from None
    except UnicodeError as exc:
        raise CaseFileError(f"{path}: cannot decode: {exc}") from None


@contextmanager
def written_whole(path):
    """The temporary path to write ``path``'s new content to: renamed onto ``path``
    when the block ends without an error, removed otherwise.

    Examples
    --------
    >>> with written_whole(out / "table.csv") as tmp:      # doctest: +SKIP
    ...     tmp.write_text(text)
    """
    path = Path(path)
    tmp = path.with_name(path.name + ".tmp")
    try:
        yield tmp
        tmp.replace(path)
    finally:
        tmp.unlink(missing_ok=True)


def write_text(path, text: str) -> Path:
    """Write ``text`` to ``path`` whole (:func:`written_whole`); returns the path."""
    with written_whole(path) as tmp:
        tmp.write_text(text)
    return Path(path)


def write_netcdf(ds, path) -> Path:
    """Write the xarray Dataset ``ds`` to ``path`` as NetCDF-4 (h5netcdf) whole;
    returns the path."""
    with written_whole(path) as tmp:
        ds.to_netcdf(tmp, engine="h5netcdf")
    return Path(path)
