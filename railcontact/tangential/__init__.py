"""Tangential contact layer: creep forces, traction, slip.

Models are chosen by name (:func:`get_tangential_model`): ``"fastsim"``, ``"fastsim-strips"``,
``"fastrip"``, ``"exact"``, ``"polach"``.
"""

from . import exact, fastrip, fastsim, polach  # noqa: F401  (register the models)
from .base import TangentialSolution, get_tangential_model, tangential_models
from .kalker import flexibilities, kalker_coefficients

__all__ = ["TangentialSolution", "get_tangential_model", "tangential_models",
           "kalker_coefficients", "flexibilities"]
