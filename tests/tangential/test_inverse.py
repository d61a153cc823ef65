"""Prescribed tangential forces: the creepages that produce them."""

import pytest

from railcontact.core.errors import InputError
from railcontact.geometry import ContactGeometry
from railcontact.core.materials import Material
from railcontact.normal import get_normal_model
from railcontact.tangential import get_tangential_model
from railcontact.tangential.inverse import solve_for_forces

MAT = Material(2.1e11, 0.28)


@pytest.mark.parametrize("model", ["fastsim", "fastsim-strips", "exact", "polach"])
def test_round_trip(model):
    g = ContactGeometry(curvatures=(1 / 0.92, 1 / 0.6))
    ns = get_normal_model("exact" if model == "exact" else "hertz").solve(
        g, MAT, normal_force=8e4, grid=(30, 30))
    tm = get_tangential_model(model)
    creep = (-8e-4, 3e-4, 0.05)
    t = tm.solve(ns, g, MAT, creep, 0.3)
    back = solve_for_forces(tm, ns, g, MAT, (t.fx, t.fy), spin=0.05, friction=0.3)
    assert back.fx == pytest.approx(t.fx, abs=1e-4 * 0.3 * 8e4)
    assert back.fy == pytest.approx(t.fy, abs=1e-4 * 0.3 * 8e4)
    assert back.creepage[0] == pytest.approx(creep[0], rel=1e-3)
    assert back.creepage[1] == pytest.approx(creep[1], rel=1e-2, abs=2e-6)


def test_saturated_force_is_rejected():
    g = ContactGeometry(curvatures=(1.0, 2.0))
    ns = get_normal_model("hertz").solve(g, MAT, normal_force=5e4)
    with pytest.raises(InputError, match="saturation"):
        solve_for_forces(get_tangential_model("fastsim"), ns, g, MAT, (0.3 * 5e4, 0.0))
