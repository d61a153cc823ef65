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
The US track classes 1-6 ("AAR-1" ... "AAR-6": the FRA/AAR spectra of Hamid &
Yang, "Analytical description of track geometry variations", Transportation Research
Record 838, 1981, as tabulated by Garg & Dukkipati, *Dynamics of Railway Vehicle
Systems*, Academic Press 1984, and used by Tao et al. with class 6):

    S_a(Ω) = k A_a Ω_c² / (Ω² (Ω² + Ω_c²))                   alignment [cm²/(rad/m)]
    S_c(Ω) = 4 k A_v Ω_c² / ((Ω² + Ω_c²)(Ω² + Ω_s²))         cross-level [cm²/(rad/m)]

with k = 0.25, Ω_c = 0.8245 rad/m and per class A_a, A_v [cm² rad/m] and Ω_s [rad/m]
(:data:`AAR_CLASSES`).  The cross-level is the height difference of the two rails;
it becomes the angle over the rail-centre distance ``CANT_BASE`` (S_c / CANT_BASE²),
as a measured file's cross-level does.  ORE B176 took Ω_c and Ω_s = 0.4380 rad/m
of class 6, hence the ERRI values above.

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
#: FRA/AAR track classes: class -> (A_v [cm² rad/m], A_a [cm² rad/m], Ω_s [rad/m])
#: (Hamid & Yang 1981; Garg & Dukkipati 1984); Ω_c = 0.8245 rad/m and k = 0.25 for all
AAR_CLASSES = {1: (1.2107, 3.3634, 0.6046), 2: (1.0181, 1.2107, 0.9308),
               3: (0.6816, 0.4128, 0.8520), 4: (0.5376, 0.3027, 1.1312),
               5: (0.2095, 0.0762, 0.8209), 6: (0.0339, 0.0339, 0.4380)}
_AAR_OMEGA_C, _AAR_K = 0.8245, 0.25
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


def aar_psd(omega, track_class: int = 6):
    """FRA/AAR one-sided PSDs of track class 1-6 at wavenumbers ``omega`` [rad/m]
    (module notes; Hamid & Yang 1981).

    Returns (alignment [m²/(rad/m)], cross-level angle [rad²/(rad/m)]): the
    formulas' cm² turned into m², the cross-level height difference into the angle
    over ``CANT_BASE``.
    """
    if track_class not in AAR_CLASSES:
        raise InputError(f"AAR track class {track_class!r}: expected one of 1-6")
    Av, Aa, ws = AAR_CLASSES[track_class]
    w2 = np.asarray(omega, dtype=float) ** 2
    wc2 = _AAR_OMEGA_C ** 2
    with np.errstate(divide="ignore"):
        sa = _AAR_K * Aa * wc2 / (w2 * (w2 + wc2))
    sc = 4 * _AAR_K * Av * wc2 / ((w2 + wc2) * (w2 + ws ** 2))
    return sa * 1e-4, sc * 1e-4 / CANT_BASE ** 2


#: every spectrum by name: the ORE B176 ones and the AAR track classes
SPECTRUM_NAMES = tuple(sorted(SPECTRA)) + tuple(f"AAR-{c}" for c in AAR_CLASSES)


def track_psd(omega, spectrum: str = "ERRI-low"):
    """One-sided PSDs (alignment [m²/(rad/m)], cross-level angle [rad²/(rad/m)]) of
    the spectrum named ``spectrum``: "ERRI-low", "ERRI-high" (:func:`erri_psd`) or
    "AAR-1" ... "AAR-6" (:func:`aar_psd`)."""
    if spectrum not in SPECTRUM_NAMES:
        raise InputError(f"irregularity spectrum {spectrum!r}: expected one of "
                         f"{list(SPECTRUM_NAMES)}")
    if spectrum.startswith("AAR-"):
        return aar_psd(omega, int(spectrum[4:]))
    return erri_psd(omega, spectrum)


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
        """Random realisation of the ORE B176 or AAR spectra over ``length`` [m].

        Parameters
        ----------
        length : float
            Track length covered [m] (the realisation is periodic in it).
        spectrum : {"ERRI-low", "ERRI-high", "AAR-1", ..., "AAR-6"}
        seed : int
            Seed of the random phases (same seed, same track).
        wavelengths : (float, float)
            Band of wavelengths kept [m].
        step : float
            Grid step [m].
        """
        lmin, lmax = (float(w) for w in wavelengths)
        track_psd(1.0, spectrum)                 # the name checked before any work
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
        psds = track_psd(omega[1:], spectrum)        # (Ω = 0 is outside every band)
        for psd in (np.concatenate(([0.0], q)) for q in psds):
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
