"""Tangential contact layer: creep forces, traction, slip.

Models are chosen by name (:func:`get_tangential_model`): ``"fastsim"``, ``"fastsim-strips"``,
``"fastrip"``, ``"exact"``, ``"polach"``, ``"linear"``; what each can do is declared
in its ``capabilities`` (:class:`~railcontact.tangential.base.TangentialModel`).
"""

from . import exact, fastrip, fastsim, fastsim_strips, linear, polach  # noqa: F401  (register the models)
from .base import (TangentialModel, TangentialSolution, get_tangential_model,
                   tangential_model_class, tangential_models, tangential_supports)
from .kalker import flexibilities, kalker_coefficients

__all__ = ["TangentialModel", "TangentialSolution", "get_tangential_model", "tangential_models",
           "tangential_model_class", "tangential_supports",
           "kalker_coefficients", "flexibilities"]
