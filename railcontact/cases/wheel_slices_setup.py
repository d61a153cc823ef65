"""An out-of-round wheel in a wheel-rail case: ``wheel.slices`` (a ``.slcw`` file,
CONTACT's wheel slices) and ``wheelset.pitch`` (the wheelset's pitch angle
theta_ws [rad]) beside ``wheel.profile`` (the wheel of revolution of the contact
search; CONTACT takes the first slice).  The slices are read with the wheel's
profile options (units, mirroring, smoothing) and become the wheelset's
:class:`~railcontact.geometry.out_of_round.OutOfRoundWheel`."""

from __future__ import annotations

from pathlib import Path

from ..core.errors import CaseFileError, ProfileError
from ..geometry.out_of_round import OutOfRoundWheel
from ..profiles.wheel_slices import read_wheel_slices


def out_of_round_wheel(source, slices: str | None, pitch: float, reference, base_dir):
    """The :class:`OutOfRoundWheel` of a case's ``wheel.slices`` (None where not
    given): ``source`` the wheel's ProfileSource (its units and options),
    ``reference`` the wheel profile read from it, ``base_dir`` the case's folder."""
    if slices is None:
        return None
    p = Path(slices)
    if not p.is_absolute() and base_dir is not None:
        p = Path(base_dir) / p
    kw = {"units": source.units}
    if source.options is not None:
        kw["options"] = source.options
    try:
        ws = read_wheel_slices(p, **kw)
    except ProfileError as exc:
        raise CaseFileError(f"wheel.slices: {exc}") from None
    return OutOfRoundWheel(ws, reference, pitch)
