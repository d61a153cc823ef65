import numpy as np
import pytest

from railcontact.profiles import read_profile, s1002
from railcontact.profiles.en13715 import S_BREAKS, s1002_height


def normal_distance(a, b):
    y = np.linspace(max(a.y_min, b.y_min), min(a.y_max, b.y_max), 20000)
    return y, (a.z_at(y) - b.z_at(y)) / np.sqrt(1 + b.slope(y) ** 2)


def test_s1002_definition_values():
    # values of the piecewise definition (REFERENCES.md 1.1)
    F = s1002_height(np.array([0.0, -55.0, -37.5]))
    assert F[0] == pytest.approx(0.0, abs=1e-12)
    assert F[1] == pytest.approx(28.0, abs=1e-6)
    assert F[2] == pytest.approx(10.0, abs=1e-3)


def test_s1002_continuous_at_breakpoints():
    for s in S_BREAKS[1:-1]:
        lo, hi = s1002_height(np.array([s - 1e-9, s + 1e-9]))
        assert abs(lo - hi) < 1e-6, s


def test_s1002_matches_manchester_file(refdir):
    wf = read_profile(refdir / "profiles" / "MBench_S1002_v3.prw")
    y, d = normal_distance(s1002(), wf)
    assert np.nanmax(np.abs(d)) < 0.01e-3


def test_s1002_spline_curvature_follows_definition():
    # second derivative of the spline against central differences of the definition,
    # on the tread and flange root (including the corrected junctions at -35 and -26)
    w = s1002()
    S = np.linspace(-34.8, 31.5, 3000)
    S = S[np.min(np.abs(S[:, None] - np.array(S_BREAKS)[None, :]), axis=1) > 0.3]
    h = 0.01
    d2 = (s1002_height(S + h) - 2 * s1002_height(S) + s1002_height(S - h)) / h ** 2 * 1e3
    assert np.max(np.abs(w.second_derivative(S * 1e-3) - d2)) < 0.05   # 1/m (max d2 ~ 176)
