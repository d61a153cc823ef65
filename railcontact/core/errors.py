"""Exception hierarchy of railcontact.

Every error raised on purpose by the package derives from :class:`RailContactError`,
so that callers (and the command-line tool) can catch one type.  The message always
names the offending input and what was expected.
"""

from __future__ import annotations


class RailContactError(Exception):
    """Base class of all errors raised by railcontact."""


class InputError(RailContactError, ValueError):
    """A value given by the user is missing, of the wrong type, or out of range."""


class ProfileError(InputError):
    """A profile cannot be read, is implausible, or is not a function of y."""


class CaseFileError(InputError):
    """A case file is missing, malformed or inconsistent."""


class UnknownModelError(InputError, KeyError):
    """A model name is not in the registry of its layer."""

    def __str__(self) -> str:  # KeyError quotes its message; keep it readable
        return str(self.args[0]) if self.args else ""


class ContactNotFoundError(RailContactError):
    """The geometry layer found no contact between wheel and rail."""


class ConvergenceError(RailContactError):
    """An iterative solver did not reach its tolerance."""


class ResourceError(InputError):
    """A job larger than the documented limits (grid elements, cases, positions):
    refused before any work unless the user insists."""
