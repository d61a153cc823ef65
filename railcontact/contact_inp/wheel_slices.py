"""CONTACT's out-of-round wheel in module 1: WFNAME a wheel slices file (``.slcw``).

The case file's wheel is the wheel of revolution of the first slice (CONTACT
reads it as the wheel's profile) with ``wheel.slices`` the file, read with the
same profile options (MIRRORY, SCALE, SMOOTH, MIRRORZ), and ``wheelset.pitch``
the wheelset's pitch angle PITCH (:mod:`railcontact.cases.wheel_slices_setup`).
"""

from __future__ import annotations

from pathlib import Path

from ..profiles.wheel_slices import slice_files


def wheel_table(table: dict) -> dict:
    """The case file's ``[wheel]`` of CONTACT's profile table: unchanged for a
    profile file; for a ``.slcw`` file its first slice as ``profile`` and the file as
    ``slices``."""
    path = Path(str(table["profile"]))
    if path.suffix.lower() != ".slcw":
        return table
    first = slice_files(path)[0]
    out = {**table, "profile": str(first), "slices": str(path)}
    if first.suffix.lower() not in (".prr", ".prw"):
        out["units"] = "mm"                 # plain tables: mm, as CONTACT reads them
    return out
