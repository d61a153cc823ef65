"""Normal contact layer: models that give the pressure in a contact patch.

Models are chosen by name (:func:`get_normal_model`): ``"hertz"``, ``"exact"``,
``"kik-piotrowski"``, ``"kpec"``, ``"analyn"``.
"""

from . import exact, hertz, semi_hertzian  # noqa: F401  (register the models)
from .base import NormalSolution, get_normal_model, make_grid, normal_models
from .hertz_theory import HertzEllipse, hertz_ellipse

__all__ = ["NormalSolution", "get_normal_model", "normal_models", "make_grid",
           "hertz_ellipse", "HertzEllipse"]
