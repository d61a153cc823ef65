"""The S1002 wheel profile of EN 13715, piecewise-analytic definition.

The coefficients are the widely used piecewise form credited to H. Netter (DLR);
see ``REFERENCES.md`` section 1.1.  In the definition, S [mm] is lateral with
S = 0 at the tape circle and S increasing towards the field side; the flange back
is at S = -70 mm.  F(S) [mm] is the height above the tape circle (positive towards
the flange tip), i.e. the local radius is r0 + F(S).  That is exactly this
package's wheel convention (z = F, positive away from the axle).

The flange-root polynomial (section C) joins its neighbours only to about
1.2e-4 mm.  A linear correction of at most that size is added to section C so
that the profile is continuous; this keeps the spline curvature free of spikes at
S = -35 and S = -26 mm.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from .profile import Profile

#: breakpoints [mm], from the flange back to the field side
S_BREAKS = (-70.0, -62.764705882, -49.662510381, -39.764473993, -38.426669071,
            -35.0, -26.0, 32.15796, 60.0)

_B = (0.0, 3.358537058e-02, 1.565681624e-03, 2.810427944e-05, 5.844240864e-08,
      1.562379023e-08, 5.309217349e-15, 5.957839843e-12, 2.646656573e-13)
_C = (4.320221063e+03, 1.038384026e+03, 1.065501873e+02, 6.051367875,
      2.054332446e-01, 4.169739389e-03, 4.687195829e-05, 2.252755540e-07)


def _piece_A(S):
    return 1.364323640 - 0.066666667 * S


def _piece_B(S):
    sign = np.array([1, -1, 1, -1, 1, -1, 1, -1, 1])
    return sum(sign[k] * _B[k] * S ** k for k in range(9))


def _piece_C_raw(S):
    return -sum(_C[k] * S ** k for k in range(8))


def _piece_D(S):
    return 16.446 - np.sqrt(np.maximum(13.0 ** 2 - (S + 26.210665) ** 2, 0.0))


def _piece_E(S):
    return -93.576667419 - 2.747477419 * S


def _piece_F(S):
    return 8.834924130 + np.sqrt(np.maximum(20.0 ** 2 - (S + 58.558326413) ** 2, 0.0))


def _piece_G(S):
    return 16.0 + np.sqrt(np.maximum(12.0 ** 2 - (S + 55.0) ** 2, 0.0))


def _piece_H(S):
    return 9.519259302 + np.sqrt(np.maximum(20.5 ** 2 - (S + 49.5) ** 2, 0.0))


# continuity correction of piece C (linear, |corr| <= ~1.2e-4 mm)
_dC_lo = _piece_D(-35.0) - _piece_C_raw(-35.0)
_dC_hi = _piece_B(-26.0) - _piece_C_raw(-26.0)


def _piece_C(S):
    t = (S + 35.0) / 9.0
    return _piece_C_raw(S) + (1 - t) * _dC_lo + t * _dC_hi


_PIECES = (_piece_H, _piece_G, _piece_F, _piece_E, _piece_D, _piece_C, _piece_B, _piece_A)


def s1002_height(S) -> np.ndarray:
    """Height F(S) [mm] of the S1002 profile at lateral position S [mm].

    Half-open intervals [S_i, S_i+1) select the piece; S = 60 belongs to the last.
    Outside [-70, 60] the result is NaN.
    """
    S = np.asarray(S, dtype=float)
    idx = np.clip(np.searchsorted(S_BREAKS, S, side="right") - 1, 0, len(_PIECES) - 1)
    out = np.full(S.shape, np.nan)
    for k, piece in enumerate(_PIECES):  # eight analytic pieces, vectorised within each
        m = idx == k
        if np.any(m):
            out[m] = piece(S[m])
    out[(S < S_BREAKS[0]) | (S > S_BREAKS[-1])] = np.nan
    return out


@lru_cache(maxsize=8)
def s1002(step: float = 1e-4, flange_back_margin: float = 1e-6) -> Profile:
    """Built-in S1002 wheel profile.

    Parameters
    ----------
    step : float
        Sampling step along the arc length [m] (default 0.1 mm).
    flange_back_margin : float
        The flange back has a vertical tangent at S = -70 mm, where z(y) has an
        infinite slope.  The profile starts this far [m] inside it (default 0.001 mm).

    Returns
    -------
    Profile
        Wheel profile, y [m] from the tape circle (positive to the field side of a
        right wheel), z [m] positive away from the axle.
    """
    S0, S1 = S_BREAKS[0] + flange_back_margin * 1e3, S_BREAKS[-1]
    # uniform arc-length sampling: dense where the profile is steep
    Sf = np.linspace(S0, S1, 200001)
    Ff = s1002_height(Sf)
    arc = np.concatenate(([0.0], np.cumsum(np.hypot(np.diff(Sf), np.diff(Ff)))))
    n = int(arc[-1] / (step * 1e3)) + 1
    S = np.interp(np.linspace(0, arc[-1], n), arc, Sf)
    S = np.unique(np.concatenate((S, S_BREAKS[1:-1])))
    return Profile(S * 1e-3, s1002_height(S) * 1e-3, kind="wheel", name="S1002")
