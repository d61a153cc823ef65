"""Registries of models by name, one per layer.

A layer's registry is the only way to select one of its models: by name, and by
the capabilities a model class declares in its ``capabilities`` attribute (a
frozenset of strings; the vocabulary of each layer is written in its ``base``
module's Protocol).
"""

from __future__ import annotations

from .checks import shown
from .errors import UnknownModelError


class Registry:
    """Maps model names to classes; ``register`` is a class decorator."""

    def __init__(self, layer: str, check_solve=None):
        self.layer = layer
        self._models: dict = {}
        self._check = check_solve

    def register(self, name: str):
        """Class decorator registering a model as ``name``; where the registry has a
        ``check_solve(*args, **kwargs)``, the class's ``solve`` calls it first (the
        layer's inputs checked for every model: the package's errors, not
        AttributeErrors from deep inside a model)."""
        def deco(cls):
            cls.name = name
            self._models[name] = cls
            solve = cls.__dict__.get("solve")
            if self._check is not None and solve is not None and \
                    not getattr(solve, "_checked", False):
                cls.solve = _checked(solve, self._check)
            return cls
        return deco

    def model_class(self, name: str) -> type:
        """The class registered as ``name`` (case-insensitive)."""
        try:
            return self._models[str(name).lower()]
        except KeyError:
            raise UnknownModelError(f"unknown {self.layer} model {shown(name)}; expected one of "
                                    f"{self.names()}") from None

    def create(self, name: str, **options):
        return self.model_class(name)(**options)

    def supports(self, name: str, capability: str) -> bool:
        """Whether the model ``name`` declares ``capability`` (False for unknown names)."""
        cls = self._models.get(str(name).lower())
        return cls is not None and capability in getattr(cls, "capabilities", frozenset())

    def names(self, capability: str | None = None) -> list:
        """Registered names, or those that declare ``capability``."""
        return sorted(n for n in self._models
                      if capability is None or self.supports(n, capability))


def _checked(solve, check):
    import functools

    @functools.wraps(solve)
    def checked_solve(self, *args, **kwargs):
        check(*args, **kwargs)
        return solve(self, *args, **kwargs)
    checked_solve._checked = True
    return checked_solve
