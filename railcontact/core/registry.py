"""Registries of models by name, one per layer.

A layer's registry is the only way to select one of its models: by name, and by
the capabilities a model class declares in its ``capabilities`` attribute (a
frozenset of strings; the vocabulary of each layer is written in its ``base``
module's Protocol).
"""

from __future__ import annotations

from .errors import UnknownModelError


class Registry:
    """Maps model names to classes; ``register`` is a class decorator."""

    def __init__(self, layer: str):
        self.layer = layer
        self._models: dict = {}

    def register(self, name: str):
        def deco(cls):
            cls.name = name
            self._models[name] = cls
            return cls
        return deco

    def model_class(self, name: str) -> type:
        """The class registered as ``name`` (case-insensitive)."""
        try:
            return self._models[str(name).lower()]
        except KeyError:
            raise UnknownModelError(f"unknown {self.layer} model {name!r}; expected one of "
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
