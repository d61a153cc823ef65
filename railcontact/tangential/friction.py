"""Friction laws: Coulomb and slip-velocity dependent (falling) friction.

Falling friction after Polach (2005, *Wear* 258, 992-1000), as documented in the
CONTACT user guide ("Slip velocity dependent friction"):

    mu(w) = mu0 ((1 - A) exp(-B w) + A),   A = mu_inf / mu0,

with w the magnitude of the slip velocity [m/s] and B in s/m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError


@dataclass(frozen=True)
class FallingFriction:
    """Polach's exponential friction law (mu0 is the static coefficient)."""

    A: float = 0.4
    B: float = 0.6      # s/m

    def __post_init__(self):
        if not (0.0 <= self.A <= 1.0):
            raise InputError(f"falling friction A = {self.A!r}: expected mu_inf/mu0 in [0, 1]")
        if not (self.B >= 0.0 and math.isfinite(self.B)):
            raise InputError(f"falling friction B = {self.B!r} s/m: expected a value >= 0")

    def __call__(self, mu0: float, w):
        """Friction coefficient at slip velocity w [m/s]."""
        return mu0 * ((1.0 - self.A) * np.exp(-self.B * np.asarray(w, dtype=float)) + self.A)


def falling_friction(spec) -> FallingFriction | None:
    """Build a :class:`FallingFriction` from None, a dict {"A": .., "B": ..} or itself."""
    if spec is None or isinstance(spec, FallingFriction):
        return spec
    if isinstance(spec, dict):
        unknown = set(spec) - {"A", "B"}
        if unknown:
            raise InputError(f"falling friction: unknown keys {sorted(unknown)}; expected A, B")
        return FallingFriction(**{k: float(v) for k, v in spec.items()})
    raise InputError(f"falling friction {spec!r}: expected a table with A and B [s/m]")
