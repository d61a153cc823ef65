"""railcontact.cases.patches: models of a case, warm-start neighbours, per-patch friction,
creepage and validity."""

from pathlib import Path
from types import SimpleNamespace as NS

import pytest

import railcontact as rc
import railcontact.cases.patches as patches
from railcontact.geometry.validity import contact_size

EX = Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture(scope="module")
def case():
    return rc.load_case(EX / "bodies.toml")


def test_case_models_and_overrides(case):
    nname, tname, nmodel, tmodel, kw = patches.case_models(case)
    assert (nname, tname, nmodel.name, tmodel.name) == ("hertz", "fastsim", "hertz", "fastsim")
    assert kw == {"grid": case.grid, "element_size": case.element_size}
    nname, tname, nmodel, tmodel, _ = patches.case_models(case, "KPEC", "none")
    assert (nname, tname, nmodel.name, tmodel) == ("kpec", "none", "kpec", None)


def test_coupling_only_for_dissimilar_bodies_with_coupled_models(case):
    exact_n, exact_t = patches.case_models(case, "exact", "exact")[2:4]
    hertz_n, fastsim_t = patches.case_models(case)[2:4]
    steel_alu = NS(material=rc.Material(2.1e11, 0.28, wheel_young_modulus=7e10))
    assert not patches.coupled_models(case, exact_n, exact_t)              # identical steel
    assert patches.coupled_models(steel_alu, exact_n, exact_t)
    assert not patches.coupled_models(steel_alu, hertz_n, fastsim_t)
    assert not patches.coupled_models(steel_alu, exact_n, None)


def test_blanco_patches_are_coupled_and_the_balance_not_lazy():
    """Blanco's coefficients couple the problems as dissimilar materials do: the
    exact models solve them together (one driver), so the vertical balance
    evaluates them whole, not normal-only (lazy)."""
    from railcontact.cases.balance import WheelRailContact
    wr = rc.load_case(EX / "wheel_rail.toml").with_values(
        {"solver.contact_surface": "conformal", "solver.normal": "exact",
         "solver.tangential": "exact"})
    b = wr.with_value("solver.influence", "blanco")
    exact_n, exact_t = patches.case_models(b)[2:4]
    assert not patches.coupled_models(wr, exact_n, exact_t)
    assert patches.coupled_models(b, exact_n, exact_t)
    assert not patches.coupled_models(b.with_value("solver.tangential", "none"), exact_n, None)
    ev = WheelRailContact(b, exact_n, exact_t, patches.case_models(b)[4], None, None)
    assert ev.coupled and not ev.lazy


def test_conformal_patch_of_dissimilar_bodies_takes_the_conformal_slip():
    """Dissimilar materials on a conformal patch (the coupled driver): the rigid
    slip of the curved surface as for one material, F_x moved from the planar
    patch's by +243.3 N (one material: +238.4 N; 10 % asserted)."""
    wr = rc.load_case(EX / "wheel_rail.toml").with_values(
        {"solver.normal": "exact", "solver.tangential": "exact"})
    dis = wr.with_values({"material.wheel_young_modulus": 1.9e11,
                          "material.wheel_poisson_ratio": 0.3})

    def shift(c):
        fx = [rc.solve(c.with_value("solver.contact_surface", s)).patches[0].tangential.fx
              for s in ("planar", "conformal")]
        return fx[1] - fx[0]
    same, other = shift(wr), shift(dis)
    assert same > 100.0
    assert other == pytest.approx(same, rel=0.1)


def _patch(side, y_rail, fy=0.0, fn=1e4):
    return NS(geometry=NS(side=side, y_rail=y_rail), normal=NS(normal_force=fn),
              tangential=NS(fy=fy))


def test_nearest_patch_same_side_within_the_warm_distance():
    prev = [_patch("right", 0.000), _patch("right", 0.002), _patch("left", 0.0021)]
    assert patches.nearest_patch(prev, NS(side="right", y_rail=0.0015)) is prev[1]
    assert patches.nearest_patch(prev, NS(side="left", y_rail=0.0)) is prev[2]
    far = 0.002 + patches.WARM_DISTANCE * 1.01
    assert patches.nearest_patch(prev, NS(side="right", y_rail=far)) is None
    assert patches.nearest_patch(None, NS(side="right", y_rail=0.0)) is None


def test_lateral_ratio():
    assert patches.lateral_ratio(_patch("right", 0.0, fy=-2e3)) == -0.2
    assert patches.lateral_ratio(_patch("right", 0.0, fy=5.0, fn=0.0)) == 0.0
    assert patches.lateral_ratio(None) == 0.0


def test_friction_and_creepage_of_a_bodies_patch(case):
    geom = NS(side=None, contact_angle=0.0, creepage=(9.0, 9.0, 9.0))
    assert patches.patch_friction(case, geom) == 0.3
    assert patches.patch_creepage(case, geom) == (1e-3, -5e-4, 0.2)        # the case's


def test_half_space_validity_of_a_bodies_patch(case, monkeypatch):
    res = rc.solve(case)
    (p,) = res.patches
    a, b = contact_size(p.normal)
    assert p.halfspace_ratio == pytest.approx(max(b / 0.3, a / 0.46), rel=1e-12)
    assert p.validity.warnings == ()
    monkeypatch.setattr(patches, "HALF_SPACE_LIMIT", p.halfspace_ratio / 2)
    p = patches.bodies_validity(case, p)
    assert res.converged and len(res.warnings) == 1 and "half-space" in res.warnings[0]


def test_friction_along_the_track_per_element():
    """Friction along the track: each element's coefficient at the patch's reference
    x plus its own, over the coefficient at the reference point (the patch's
    ``friction``)."""
    import numpy as np
    case = NS(friction_along_track=((-0.06, 0.04), (0.2, 0.3)), friction_variation=None)
    geom = NS(position=(0.01, 0.7, 0.0))
    normal = NS(x=np.array([-0.002, 0.0, 0.002]), pressure=np.zeros((3, 2)))
    assert patches.patch_friction(case, geom) == pytest.approx(0.27)
    scale = patches.friction_along_track(case, geom, normal)
    assert scale.shape == (3, 2)
    np.testing.assert_allclose(scale[:, 1] * 0.27, [0.268, 0.27, 0.272])
