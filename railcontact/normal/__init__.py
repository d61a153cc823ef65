"""Normal contact layer: models that give the pressure in a contact patch.

Models are chosen by name (:func:`get_normal_model`): ``"hertz"``, ``"exact"``,
``"kik-piotrowski"``, ``"kpec"``, ``"analyn"``, ``"stripes"``; what each can do is
declared in its ``capabilities`` (:class:`~railcontact.normal.base.NormalModel`).
"""

from . import exact, hertz, semi_hertzian  # noqa: F401  (register the models)
from .base import (NormalModel, NormalSolution, get_normal_model, make_grid,
                   normal_model_class, normal_models, normal_supports)
from ..core.hertz_theory import HertzEllipse, hertz_ellipse

__all__ = ["NormalModel", "NormalSolution", "get_normal_model", "normal_models", "make_grid",
           "normal_model_class", "normal_supports",
           "hertz_ellipse", "HertzEllipse"]
