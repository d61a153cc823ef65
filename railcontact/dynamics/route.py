"""Track design geometry and irregularities for the dynamics layer.

Design geometry is a chain of segments: tangent, transition (clothoid: curvature and
cant vary linearly with distance) and circular curve.  Curvature κ [1/m] is positive
for a curve to the **right** (centre on the +y side of the track frame); cant is
given as the superelevation height [m] of the outer rail over a rail-centre distance
of ``CANT_BASE``, and turns into the cant angle φ_t = asin(h / CANT_BASE) of the
track plane, with the sign of the curve (the outer rail is raised).

Irregularities (lateral alignment [m] and cross-level angle [rad]) come either from
a file or from the ORE B176 / ERRI power spectral densities (ORE B176, "Bogies with
steered or steering wheelsets", Report 1, Utrecht 1989; the spectra as used by
e.g. Claus & Schiehlen and the GENSYS program TRC_IPSD):

    S_a(Ω) = A_a Ω_c² / ((Ω² + Ω_r²)(Ω² + Ω_c²))              alignment [m²/(rad/m)]
    S_c(Ω) = (A_v / b²) Ω_c² Ω² / ((Ω² + Ω_r²)(Ω² + Ω_c²)(Ω² + Ω_s²))   cross-level
                                                                   [rad²/(rad/m)]

with Ω_c = 0.8246, Ω_r = 0.0206, Ω_s = 0.4380 rad/m, b = 0.75 m, and A_a, A_v
= 2.119e-7, 4.032e-7 m·rad (low level) or 6.125e-7, 1.080e-6 m·rad (high level).
A realisation is a sum of harmonics with random phases whose variance in each
wavenumber band equals the spectrum's (inverse real FFT on a uniform grid).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..core.errors import CaseFileError, InputError

#: length [m] over which a curvature step without a transition is spread
STEP_RAMP = 1.0
#: rail-centre distance for converting a cant height into an angle [m]
CANT_BASE = 1.5
#: ORE B176 spectra: name -> (A_a [m rad], A_v [m rad])
SPECTRA = {"ERRI-low": (2.119e-7, 4.032e-7), "ERRI-high": (6.125e-7, 1.080e-6)}
_OMEGA_C, _OMEGA_R, _OMEGA_S, _B = 0.8246, 0.0206, 0.4380, 0.75
_KINDS = ("tangent", "transition", "curve")


def erri_psd(omega, spectrum: str = "ERRI-low"):
    """ORE B176 one-sided PSDs at wavenumbers ``omega`` [rad/m].

    Returns (alignment [m²/(rad/m)], cross-level angle [rad²/(rad/m)]).
    """
    if spectrum not in SPECTRA:
        raise InputError(f"irregularity spectrum {spectrum!r}: expected one of {sorted(SPECTRA)}")
    Aa, Av = SPECTRA[spectrum]
    w2 = np.asarray(omega, dtype=float) ** 2
    base = _OMEGA_C ** 2 / ((w2 + _OMEGA_R ** 2) * (w2 + _OMEGA_C ** 2))
    return Aa * base, Av / _B ** 2 * base * w2 / (w2 + _OMEGA_S ** 2)


@dataclass
class Irregularities:
    """Lateral alignment y_a(s) [m] (rails moved to +y) and cross-level angle c(s)
    [rad] (right rail lowered, same sign as the cant angle) on a uniform grid."""

    s: np.ndarray
    alignment: np.ndarray
    cross_level: np.ndarray
    source: str = ""

    def __post_init__(self):
        self.s = np.ascontiguousarray(self.s, dtype=float)
        self.alignment = np.ascontiguousarray(self.alignment, dtype=float)
        self.cross_level = np.ascontiguousarray(self.cross_level, dtype=float)
        n = self.s.size
        if n < 2 or self.alignment.size != n or self.cross_level.size != n:
            raise InputError("irregularities: s, alignment and cross_level must be arrays of "
                             "one length >= 2")
        if not (np.all(np.isfinite(self.s)) and np.all(np.isfinite(self.alignment))
                and np.all(np.isfinite(self.cross_level))):
            raise InputError("irregularities: NaN or infinite values")
        if np.any(np.diff(self.s) <= 0):
            raise InputError("irregularities: distance s must increase strictly")

    @classmethod
    def none(cls) -> "Irregularities":
        return cls(np.array([0.0, 1.0]), np.zeros(2), np.zeros(2), "none")

    @classmethod
    def from_psd(cls, length: float, spectrum: str = "ERRI-low", seed: int = 0,
                 wavelengths=(3.0, 120.0), step: float = 0.25) -> "Irregularities":
        """Random realisation of the ORE B176 spectra over ``length`` [m].

        Parameters
        ----------
        length : float
            Track length covered [m] (the realisation is periodic in it).
        spectrum : {"ERRI-low", "ERRI-high"}
        seed : int
            Seed of the random phases (same seed, same track).
        wavelengths : (float, float)
            Band of wavelengths kept [m].
        step : float
            Grid step [m].
        """
        lmin, lmax = (float(w) for w in wavelengths)
        if not (length > 0 and step > 0 and 2 * step <= lmin < lmax):
            raise InputError(f"irregularities: length {length!r} m, step {step!r} m, wavelengths "
                             f"{wavelengths!r}: expected length, step > 0 and "
                             "2 step <= shortest < longest wavelength")
        n = int(math.ceil(max(length, lmax) / step)) + 1
        n += n % 2
        s = np.arange(n) * step
        k = np.arange(n // 2 + 1)
        omega = 2 * np.pi * k / (n * step)
        d_omega = 2 * np.pi / (n * step)
        band = (omega >= 2 * np.pi / lmax) & (omega <= 2 * np.pi / lmin)
        rng = np.random.default_rng(seed)
        out = []
        for psd in erri_psd(omega, spectrum):
            amp = np.where(band, np.sqrt(2 * psd * d_omega), 0.0)
            coef = 0.5 * n * amp * np.exp(1j * rng.uniform(0, 2 * np.pi, k.size))
            out.append(np.fft.irfft(coef, n))
        return cls(s, out[0], out[1], f"{spectrum}, seed {seed}, {lmin:g}-{lmax:g} m")

    @classmethod
    def from_file(cls, path) -> "Irregularities":
        """CSV with a header row and columns ``s`` [m], ``alignment`` [m] and
        ``cross_level`` [m] (height difference of the rails; converted to an angle)."""
        path = Path(path)
        if not path.is_file():
            raise CaseFileError(f"irregularity file {str(path)!r} does not exist")
        try:
            data = np.genfromtxt(path, delimiter=",", names=True)
        except ValueError as exc:
            raise CaseFileError(f"{path}: cannot read irregularities: {exc}") from None
        need = {"s", "alignment", "cross_level"}
        if data.dtype.names is None or not need <= set(data.dtype.names):
            raise CaseFileError(f"{path}: expected columns {sorted(need)}, found "
                                f"{list(data.dtype.names or [])}")
        return cls(data["s"], data["alignment"],
                   np.arcsin(np.clip(data["cross_level"] / CANT_BASE, -1, 1)), str(path))


@dataclass
class Route:
    """Design track geometry: curvature and cant angle as piecewise-linear functions
    of the distance s [m] (knots ``s_knots``), plus irregularities.

    Build it with :meth:`from_segments`; beyond the last knot the last values hold.
    """

    s_knots: np.ndarray
    curvature: np.ndarray
    cant: np.ndarray
    irregularities: Irregularities = field(default_factory=Irregularities.none)
    segments: list = field(default_factory=list)

    @property
    def length(self) -> float:
        return float(self.s_knots[-1])

    @classmethod
    def tangent(cls, length: float = 1e4, irregularities=None) -> "Route":
        return cls.from_segments([{"type": "tangent", "length": length}], irregularities)

    @classmethod
    def from_segments(cls, segments, irregularities: Irregularities | None = None) -> "Route":
        """Chain of segments, each a dict with ``type`` in {"tangent", "transition",
        "curve"} and ``length`` [m]; curves have ``radius`` [m] (positive to the
        right, negative to the left) and ``cant`` [m] (outer-rail superelevation,
        >= 0).  A transition goes linearly from the previous segment's end values to
        the next segment's (to straight track if it is the last).  A curve joined
        without a transition has its curvature and cant step spread over the first
        ``STEP_RAMP`` (1 m) of the next segment."""
        if not segments:
            raise InputError("route: at least one segment is needed")
        ends = []
        for i, seg in enumerate(segments):
            name = f"route.segment[{i}]"
            if not isinstance(seg, dict):
                raise CaseFileError(f"{name}: expected a table with type and length")
            bad = set(seg) - {"type", "length", "radius", "cant"}
            if bad:
                raise CaseFileError(f"{name}: unknown key(s) {sorted(bad)}; expected type, "
                                    "length, radius, cant")
            kind = seg.get("type")
            if kind not in _KINDS:
                raise CaseFileError(f"{name}.type = {kind!r}: expected one of {list(_KINDS)}")
            length = seg.get("length")
            if isinstance(length, bool) or not isinstance(length, (int, float)) \
                    or not 0 < length < 1e6:
                raise CaseFileError(f"{name}.length = {length!r}: expected a length in m > 0")
            kappa = cant = 0.0
            if kind == "curve":
                r = seg.get("radius")
                if isinstance(r, bool) or not isinstance(r, (int, float)) or not 10 <= abs(r):
                    raise CaseFileError(f"{name}.radius = {r!r}: expected |radius| >= 10 m "
                                        "(positive: curve to the right)")
                h = seg.get("cant", 0.0)
                if isinstance(h, bool) or not isinstance(h, (int, float)) or not 0 <= h <= 0.3:
                    raise CaseFileError(f"{name}.cant = {h!r}: expected an outer-rail "
                                        "superelevation in [0, 0.3] m")
                kappa = 1.0 / r
                cant = math.copysign(math.asin(h / CANT_BASE), kappa)
            elif "radius" in seg or "cant" in seg:
                raise CaseFileError(f"{name}: radius and cant belong to curves (a {kind} takes "
                                    "its values from its neighbours)")
            ends.append((kind, float(length), kappa, cant))
        s, k, c = [0.0], [], []
        for i, (kind, length, kappa, cant) in enumerate(ends):
            if kind == "transition":
                prev = (k[-1], c[-1]) if k else (0.0, 0.0)
                nxt = next(((kk, cc) for kd, _, kk, cc in ends[i + 1:] if kd != "transition"),
                           (0.0, 0.0))
                if not k:
                    k.append(prev[0])
                    c.append(prev[1])
                s.append(s[-1] + length)
                k.append(nxt[0])
                c.append(nxt[1])
            else:
                if not k or k[-1] != kappa or c[-1] != cant:
                    if k:
                        s.append(s[-1])          # a step in curvature at the joint
                    k.append(kappa)
                    c.append(cant)
                s.append(s[-1] + length)
                k.append(kappa)
                c.append(cant)
        s_arr = np.array(s)
        # a step in curvature (two knots at one s) would be a Dirac in the yaw
        # acceleration of the track tangent: spread it over STEP_RAMP (at most half
        # the next knot distance)
        for j in range(1, s_arr.size):
            if s_arr[j] <= s_arr[j - 1]:
                room = s_arr[j + 1] - s_arr[j] if j + 1 < s_arr.size else 2 * STEP_RAMP
                s_arr[j] = s_arr[j - 1] + min(STEP_RAMP, 0.5 * room)
        return cls(s_arr, np.array(k), np.array(c), irregularities or Irregularities.none(),
                   list(segments))

    def at(self, s):
        """Curvature [1/m] and cant angle [rad] at distances ``s`` [m]."""
        return (np.interp(s, self.s_knots, self.curvature),
                np.interp(s, self.s_knots, self.cant))

    def packed(self):
        """Arrays for the compiled right-hand side."""
        irr = self.irregularities
        return (np.ascontiguousarray(self.s_knots), np.ascontiguousarray(self.curvature),
                np.ascontiguousarray(self.cant), irr.s, irr.alignment, irr.cross_level)
