"""railcontact: wheel-rail rolling contact and wear.

Layers (one sub-package each): :mod:`~railcontact.profiles`, :mod:`~railcontact.geometry`,
:mod:`~railcontact.normal`, :mod:`~railcontact.tangential`.  Above them:
:func:`solve` (one case), :func:`sweep` (many cases) and the ``railcontact`` command.
All quantities are in SI units; conventions in ``docs/conventions.md``.
"""

import logging

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
