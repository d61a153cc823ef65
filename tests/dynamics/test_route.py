"""Track design geometry and ORE B176 irregularities."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from railcontact.dynamics.route import CANT_BASE, Irregularities, Route, erri_psd
from railcontact.core.errors import CaseFileError, InputError


def test_segments_curvature_and_cant():
    r = Route.from_segments([{"type": "tangent", "length": 100},
                             {"type": "transition", "length": 50},
                             {"type": "curve", "radius": -500, "cant": 0.12, "length": 200},
                             {"type": "transition", "length": 50}])
    k, c = r.at(np.array([50, 125, 150, 300, 375, 400, 500]))
    phi = math.asin(0.12 / CANT_BASE)
    np.testing.assert_allclose(k, [0, -1 / 1000, -1 / 500, -1 / 500, -1 / 1000, 0, 0], atol=1e-9)
    np.testing.assert_allclose(c, [0, -phi / 2, -phi, -phi, -phi / 2, 0, 0], atol=1e-9)
    assert r.length == pytest.approx(400)


def test_curve_without_transition_steps():
    r = Route.from_segments([{"type": "tangent", "length": 10},
                             {"type": "curve", "radius": 300, "length": 10}])
    k, _ = r.at(np.array([9.99, 10.5, 11.01]))          # spread over 1 m
    np.testing.assert_allclose(k, [0, 0.5 / 300, 1 / 300], atol=1e-9)


@pytest.mark.parametrize("seg, word", [
    ({"type": "spiral", "length": 10}, "type"),
    ({"type": "curve", "length": 10, "radius": 5}, "radius"),
    ({"type": "curve", "length": 10, "radius": 500, "cant": 0.5}, "cant"),
    ({"type": "tangent", "length": -1}, "length"),
    ({"type": "tangent", "length": 10, "radius": 300}, "radius"),
    ({"type": "tangent", "length": 10, "colour": 1}, "colour")])
def test_bad_segments(seg, word):
    with pytest.raises(CaseFileError, match=word):
        Route.from_segments([seg])


def test_psd_matches_gensys_table():
    """ORE B176 high level, lateral, at 0.1 cycles/m: 6.1608e-6 m^2/(1/m) in the
    GENSYS TRC_IPSD manual (PSD per cycles/m = 2 pi x PSD per rad/m)."""
    sa, _ = erri_psd(2 * np.pi * 0.1, "ERRI-high")
    assert 2 * np.pi * float(sa) == pytest.approx(6.1608e-6, rel=2e-3)


@pytest.mark.parametrize("spectrum", ["ERRI-low", "ERRI-high"])
def test_realisation_has_the_spectrum_variance(spectrum):
    lmin, lmax = 3.0, 120.0
    irr = Irregularities.from_psd(20000.0, spectrum, seed=3, wavelengths=(lmin, lmax))
    w0, w1 = 2 * np.pi / lmax, 2 * np.pi / lmin
    var_a = quad(lambda w: erri_psd(w, spectrum)[0], w0, w1, limit=200)[0]
    var_c = quad(lambda w: erri_psd(w, spectrum)[1], w0, w1, limit=200)[0]
    assert np.var(irr.alignment) == pytest.approx(var_a, rel=0.01)
    assert np.var(irr.cross_level) == pytest.approx(var_c, rel=0.01)
    # the shape: the variance in the 10-30 m band follows the spectrum
    spec = np.abs(np.fft.rfft(irr.alignment)) ** 2
    om = 2 * np.pi * np.fft.rfftfreq(irr.s.size, irr.s[1] - irr.s[0])
    band = (om > 2 * np.pi / 30) & (om < 2 * np.pi / 10)
    frac = spec[band].sum() / spec.sum()
    expect = quad(lambda w: erri_psd(w, spectrum)[0], 2 * np.pi / 30, 2 * np.pi / 10)[0] / var_a
    assert frac == pytest.approx(expect, rel=0.02)
    # same seed, same track
    again = Irregularities.from_psd(20000.0, spectrum, seed=3, wavelengths=(lmin, lmax))
    np.testing.assert_array_equal(again.alignment, irr.alignment)


def test_irregularity_file(tmp_path):
    f = tmp_path / "irr.csv"
    f.write_text("s,alignment,cross_level\n0,0,0\n10,0.001,0.0015\n20,0,0\n")
    irr = Irregularities.from_file(f)
    assert irr.alignment[1] == 0.001
    assert irr.cross_level[1] == pytest.approx(0.001)
    (tmp_path / "bad.csv").write_text("s,alignment\n0,0\n1,0\n")
    with pytest.raises(CaseFileError, match="cross_level"):
        Irregularities.from_file(tmp_path / "bad.csv")
    with pytest.raises(CaseFileError, match="does not exist"):
        Irregularities.from_file(tmp_path / "none.csv")
    with pytest.raises(InputError, match="NaN"):
        Irregularities(np.arange(3.0), np.array([0, np.nan, 0]), np.zeros(3))
