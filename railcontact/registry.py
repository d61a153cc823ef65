"""Registries of models by name, one per layer."""

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

    def create(self, name: str, **options):
        try:
            cls = self._models[str(name).lower()]
        except KeyError:
            raise UnknownModelError(f"unknown {self.layer} model {name!r}; expected one of "
                                    f"{self.names()}") from None
        return cls(**options)

    def names(self) -> list:
        return sorted(self._models)
