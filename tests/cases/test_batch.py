"""Batches of patches: the compiled Hertz + creep-law path equals the models."""

import math

import numpy as np
import pytest

from railcontact.cases.batch import solve_patches
from railcontact.core.errors import InputError
from railcontact.geometry import Track, Wheelset, find_contact
from railcontact.core.materials import STEEL
from railcontact.normal import get_normal_model
from railcontact.profiles import rail_profile, s1002
from railcontact.tangential import get_tangential_model


@pytest.fixture(scope="module")
def patches():
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    out = []
    for y, yaw in ((0.0, 0.0), (3e-3, 2e-3), (6e-3, 4e-3), (-2e-3, -3e-3)):
        c = find_contact(ws, tr, lateral_shift=y, yaw=yaw, vertical_force=6e4)
        out.extend(p for p in c.patches if p.approach > 0)
    return out


def _loop(patches, normal, tangential, grid):
    nm, tm = get_normal_model(normal), get_tangential_model(tangential)
    rows = []
    for g in patches:
        ns = nm.solve(g, STEEL, penetration=g.approach, grid=grid)
        ts = tm.solve(ns, g, STEEL, g.creepage, 0.3, g.velocity)
        rows.append((ns.normal_force, ns.pmax, ts.fx, ts.fy))
    return np.array(rows)


@pytest.mark.parametrize("law", ["fastsim", "polach"])
def test_compiled_batch_equals_the_models(patches, law):
    res = solve_patches(patches, "hertz", law, fastsim_grid=(40, 40))
    ref = _loop(patches, "hertz", law, (40, 40))
    assert res.options["compiled"]
    np.testing.assert_allclose(res.normal_force, ref[:, 0], rtol=1e-9)
    np.testing.assert_allclose(res.pmax, ref[:, 1], rtol=1e-9)
    tol = 0.005 * 0.3 * ref[:, 0] if law == "fastsim" else 1e-9 * ref[:, 0]
    assert np.all(np.abs(res.Fx - ref[:, 2]) <= tol)
    assert np.all(np.abs(res.Fy - ref[:, 3]) <= tol)
    assert np.abs(res.Fx).max() > 100.0            # the cases carry creep forces


def test_hertz_fastrip_on_strips(patches):
    """FaStrip on the Hertz ellipse cut in 40 strips equals the per-patch model on a
    60 x 60 grid within 1 % of mu F_n; F_n and p_max are Hertz's exactly."""
    res = solve_patches(patches, "hertz", "fastrip", fastsim_grid=(40, 40))
    ref = _loop(patches, "hertz", "fastrip", (60, 60))
    assert res.options["compiled"] and res.options["strips"] == 40
    np.testing.assert_allclose(res.normal_force, ref[:, 0], rtol=1e-9)
    np.testing.assert_allclose(res.pmax, ref[:, 1], rtol=1e-9)
    d = np.hypot(res.Fx - ref[:, 2], res.Fy - ref[:, 3]) / (0.3 * ref[:, 0])
    assert d.max() < 0.01
    assert np.abs(res.Fx).max() > 100.0


def test_other_models_patch_by_patch(patches):
    res = solve_patches(patches[:3], "hertz", "exact", grid=(16, 16))
    ref = _loop(patches[:3], "hertz", "exact", (16, 16))
    assert not res.options["compiled"]
    np.testing.assert_allclose(np.c_[res.normal_force, res.pmax, res.Fx, res.Fy], ref,
                               rtol=1e-12)
    ds = res.to_xarray()
    assert ds["Fx"].attrs["units"] == "N" and ds.sizes["patch"] == 3


def test_bad_input(patches):
    with pytest.raises(InputError, match="no patches"):
        solve_patches([])
    with pytest.raises(InputError, match="friction"):
        solve_patches(patches, friction=-0.1)
    with pytest.raises(InputError, match="unknown tangential model"):
        solve_patches(patches, "kpec", "fastsimm")
