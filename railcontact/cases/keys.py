"""Reading a case's keys with validation: :class:`CaseKeys`.

The parsed TOML of a case (or a scenario) as nested tables, read by dotted key
(``"wheelset.lateral_shift"``) with its range and unit checked once, where the
input enters.  :class:`~railcontact.cases.case.Case` is one; the parsers of a
case's parts (:mod:`railcontact.cases.wheel_rail_setup`,
:mod:`railcontact.cases.surface_setup`) read through it and return typed values.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..core.checks import shown
from ..core.errors import CaseFileError, RailContactError
from ..profiles.processing import ProfileOptions

#: a profile file's processing (:class:`railcontact.profiles.ProfileOptions`)
PROFILE_OPTIONS = {"mirror_y", "mirror_z", "scale", "smoothing", "zigzag", "kinks"}


@dataclass(frozen=True)
class CaseKeys:
    """The parsed TOML tables ``raw`` of a case, read by dotted key with validation;
    every error is a :class:`~railcontact.core.errors.CaseFileError` naming the key,
    its value and what was expected."""

    raw: dict

    def get(self, dotted: str, default=None):
        """The value at ``dotted`` (``"wheelset.yaw"``), or ``default`` where absent."""
        node = self.raw
        for part in dotted.split("."):
            if not isinstance(node, dict) or part not in node:
                return default
            node = node[part]
        return node

    def number(self, dotted: str, default=None, lo=-math.inf, hi=math.inf, unit=""):
        """The number at ``dotted`` (``default`` where absent) as a float, checked to lie
        in [``lo``, ``hi``] in ``unit``; a missing number without default, a non-number,
        NaN or a value out of range is a :class:`CaseFileError`."""
        v = self.get(dotted, default)
        if v is None:
            raise CaseFileError(f"{dotted}: missing; expected a number in {unit or 'SI units'}")
        if isinstance(v, bool) or not isinstance(v, (int, float)) or math.isnan(v):
            raise CaseFileError(f"{dotted} = {shown(v)}: expected a number in {unit or 'SI units'}")
        if not lo <= v <= hi:
            raise CaseFileError(f"{dotted} = {shown(v)}: expected a value in [{lo:g}, {hi:g}] {unit}")
        return float(v)

    def profile_options(self, body: str):
        """The profile-file options of ``[wheel]`` or ``[rail]`` as
        :class:`~railcontact.profiles.ProfileOptions` (None where none is given) and
        the file's length unit."""
        table = self.raw.get(body, {})
        units = table.get("units", "auto")
        if units not in ("auto", "mm", "m"):
            raise CaseFileError(f"{body}.units = {shown(units)}: expected 'auto', 'mm' or 'm'")
        if not PROFILE_OPTIONS & set(table):
            return None, units
        try:
            return ProfileOptions.from_table(table, body), units
        except RailContactError as exc:
            raise CaseFileError(str(exc)) from None

    def wheel_loads(self) -> dict:
        """Vertical wheel loads [N] per side: ``vertical_force`` is one value for both
        wheels or [left, right]."""
        v = self.get("wheelset.vertical_force", 70e3)
        if isinstance(v, list):
            if len(v) != 2:
                raise CaseFileError(f"wheelset.vertical_force = {shown(v)}: expected one load or "
                                    "[left, right] in N")
            vals = v
        else:
            vals = [v, v]
        out = {}
        for side, x in zip(("left", "right"), vals):
            if isinstance(x, bool) or not isinstance(x, (int, float)) or not 1.0 <= x <= 1e7:
                raise CaseFileError(f"wheelset.vertical_force = {shown(v)}: expected loads in "
                                    "[1, 1e7] N")
            out[side] = float(x)
        return out
