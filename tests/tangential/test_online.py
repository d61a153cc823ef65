"""Compiled creep-force laws for one elliptic patch (railcontact.tangential.online):
law codes, Kalker's linear limit, saturation at mu N, falling friction."""

import math

import numpy as np
import pytest

from railcontact.core.errors import UnknownModelError
from railcontact.tangential import kalker_coefficients
from railcontact.tangential.online import online_law, patch_forces

G, N, A, B = 8e10, 1e5, 6e-3, 4e-3
C = kalker_coefficients(A / B, 0.28)
#: mu0, G, FASTSIM elements, Polach's kA, kS, falling friction A = 1 (constant), B
TP = np.array([0.3, G, 30, 30, 1.0, 1.0, 1.0, 0.0])


def test_codes_of_the_online_models():
    assert [online_law(n) for n in ("linear", "fastsim", "polach")] == [0, 1, 2]
    assert online_law("exact") is None
    with pytest.raises(UnknownModelError):
        online_law("no-such-law")


@pytest.mark.parametrize("law, rel", [(0, 1e-14), (1, 1e-3), (2, 1e-4)])
def test_small_creepage_is_kalkers_linear_theory(law, rel):
    c = math.sqrt(A * B)
    fx, fy, _ = patch_forces(law, TP, N, A, B, *C, 1e-6, 0.0, 0.0, 30.0)
    assert fx == pytest.approx(G * c * c * C[0] * 1e-6, rel=rel)
    fx, fy, _ = patch_forces(law, TP, N, A, B, *C, 0.0, 1e-6, 0.0, 30.0)
    assert fy == pytest.approx(G * c * c * C[1] * 1e-6, rel=rel)


def test_saturation_and_falling_friction():
    # linear: unbounded; FASTSIM: mu N within its discretisation; Polach: mu N
    assert patch_forces(0, TP, N, A, B, *C, 0.5, 0.0, 0.0, 30.0)[0] > 100 * 0.3 * N
    assert patch_forces(1, TP, N, A, B, *C, 0.5, 0.0, 0.0, 30.0)[0] == \
        pytest.approx(0.3 * N, rel=5e-3)
    assert patch_forces(2, TP, N, A, B, *C, 0.5, 0.0, 0.0, 30.0)[0] == \
        pytest.approx(0.3 * N, rel=1e-6)
    # Polach with mu = mu0 ((1 - A) exp(-B w) + A) at w = 0.5 * 30 m/s
    tp = TP.copy()
    tp[6], tp[7] = 0.4, 0.6
    mu = 0.3 * (0.6 * math.exp(-0.6 * 15.0) + 0.4)
    assert patch_forces(2, tp, N, A, B, *C, 0.5, 0.0, 0.0, 30.0)[0] == \
        pytest.approx(mu * N, rel=1e-6)


@pytest.mark.parametrize("law", [0, 1, 2])
def test_no_load_no_force(law):
    assert patch_forces(law, TP, 0.0, A, B, *C, 0.01, 0.01, 0.1, 30.0) == (0.0, 0.0, 0.0)
    assert patch_forces(law, TP, N, 0.0, B, *C, 0.01, 0.01, 0.1, 30.0) == (0.0, 0.0, 0.0)
