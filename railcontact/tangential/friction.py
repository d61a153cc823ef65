"""Friction laws: Coulomb, slip-velocity dependent (falling) and temperature
dependent friction.

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


@dataclass(frozen=True)
class SlipVelocityFriction:
    """CONTACT's slip-velocity dependent friction laws (user guide, "Slip velocity
    dependent friction"; FRCLAW L = 2, 3, 4), at the magnitude s_a [m/s] of the
    absolute slip velocity, without friction memory:

    * ``"linear"`` (L = 2): mu_kin + c1 max(0, 1 - s_a/(2 s_h1)) + c2 max(0, 1 - s_a/(2 s_h2));
    * ``"rational"`` (L = 3): mu_kin + c1/(1 + s_a/s_h1) + c2/(1 + (s_a/s_h2)^2);
    * ``"exponential"`` (L = 4): mu_kin + c1 exp(-ln2 s_a/s_h1) + c2 exp(-ln2 s_a/s_h2)
      (Polach's law with c2 = 0: mu_kin = A mu_stat, c1 = (1 - A) mu_stat,
      s_h1 = ln 2 / B).

    ``c`` = (c1, c2), ``sh`` = (s_h1, s_h2) [m/s] (a term with c = 0 is off).
    """

    kind: str
    mu_kin: float
    c: tuple = (0.0, 0.0)
    sh: tuple = (1.0, 1.0)

    def __post_init__(self):
        if self.kind not in ("linear", "rational", "exponential"):
            raise InputError(f"friction law {self.kind!r}: expected 'linear', 'rational' or "
                             "'exponential'")
        if not self.mu_kin > 0:
            raise InputError(f"friction law mu_kin = {self.mu_kin!r}: expected a value > 0")
        for c, sh in zip(self.c, self.sh):
            if c and not sh > 0:
                raise InputError(f"friction law s_h = {sh!r} m/s for a term of size {c!r}: "
                                 "expected s_h > 0")

    @property
    def static(self) -> float:
        """The coefficient at zero slip velocity."""
        return float(self(0.0))

    def __call__(self, sa):
        """Friction coefficient at absolute slip velocity ``sa`` [m/s]."""
        sa = np.abs(np.asarray(sa, dtype=float))
        out = np.full(sa.shape, float(self.mu_kin))
        for k, (c, sh) in enumerate(zip(self.c, self.sh)):
            if not c:
                continue
            r = sa / sh
            if self.kind == "linear":
                out += c * np.maximum(0.0, 1.0 - 0.5 * r)
            elif self.kind == "rational":
                out += c / (1.0 + (r if k == 0 else r * r))
            else:
                out += c * np.exp(-math.log(2.0) * r)
        return out


@dataclass(frozen=True)
class TemperatureFriction:
    """CONTACT's temperature dependent friction (user guide, "Temperature
    dependent friction"; FRCLAW L = 6): piecewise linear in the surface
    temperature T [deg C],

        mu(T) = mu_ref + dmu min(max(T - T_ref, 0), dT) / dT,

    mu_ref below T_ref, mu_ref + dmu (the kinetic value) above T_ref + dT.  The
    temperature is body 1's flash temperature
    (:mod:`railcontact.tangential.temperature`), which itself depends on the
    friction: the solvers iterate to a fixed point."""

    mu_ref: float
    t_ref: float
    dmu: float
    dt: float

    def __post_init__(self):
        for name in ("mu_ref", "t_ref", "dmu", "dt"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v)):
                raise InputError(f"temperature friction {name} = {v!r}: expected a number")
        if not self.mu_ref > 0:
            raise InputError(f"temperature friction mu_ref = {self.mu_ref!r}: expected > 0")
        if not self.dt > 0:
            raise InputError(f"temperature friction dT = {self.dt!r} K: expected > 0")
        if not self.mu_ref + self.dmu > 0:
            raise InputError(f"temperature friction mu_ref + dmu = {self.mu_ref + self.dmu!r}:"
                             " expected a positive kinetic coefficient")

    @property
    def static(self) -> float:
        """The coefficient at low temperatures, mu_ref."""
        return float(self.mu_ref)

    @property
    def mu_kin(self) -> float:
        """The coefficient at high temperatures, mu_ref + dmu."""
        return float(self.mu_ref + self.dmu)

    def __call__(self, temperature):
        """Friction coefficient at surface temperature ``temperature`` [deg C]."""
        t = np.asarray(temperature, dtype=float)
        return self.mu_ref + self.dmu * np.clip(t - self.t_ref, 0.0, self.dt) / self.dt
