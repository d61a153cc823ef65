"""railcontact.core.materials: the combined elastic constants of a pair of bodies."""

import pytest

from railcontact.core.errors import InputError
from railcontact.core.materials import STEEL, Material


def test_identical_bodies():
    m = Material(2.1e11, 0.28)
    assert m.contact_modulus == pytest.approx(2.1e11 / (2 * (1 - 0.28**2)), rel=1e-14)
    assert m.shear_modulus == pytest.approx(2.1e11 / (2 * 1.28), rel=1e-14)
    assert m.nu == pytest.approx(0.28, rel=1e-14)
    assert m.difference_parameter == 0.0 and not m.is_dissimilar
    assert STEEL == Material()


def test_dissimilar_bodies_by_hand():
    """Steel rail (E1 = 210 GPa, nu1 = 0.3) and an aluminium wheel (70 GPa, 0.33)."""
    m = Material(2.1e11, 0.3, wheel_young_modulus=7e10, wheel_poisson_ratio=0.33)
    G1, G2 = 2.1e11 / 2.6, 7e10 / 2.66
    G = 2 / (1 / G1 + 1 / G2)
    assert m.shear_modulus == pytest.approx(G, rel=1e-14)
    assert m.contact_modulus == pytest.approx(1 / (0.91 / 2.1e11 + (1 - 0.33**2) / 7e10),
                                              rel=1e-14)
    assert m.nu == pytest.approx(G * (0.3 / G1 + 0.33 / G2) / 2, rel=1e-14)
    K = G * (0.4 / G1 - 0.34 / G2) / 4
    assert m.difference_parameter == pytest.approx(K, rel=1e-13)
    assert K < 0 and m.is_dissimilar                     # the softer wheel: K < 0
    assert K == pytest.approx(-0.0791, abs=1e-4)     # G = 39.70 GPa, by hand


def test_from_shear_modulus():
    m = Material.from_shear_modulus(82e9, 0.28)
    assert m.young_modulus == pytest.approx(2 * 82e9 * 1.28)
    assert m.shear_modulus == pytest.approx(82e9)


@pytest.mark.parametrize("kw, name", [({"young_modulus": -1.0}, "material.young_modulus"),
                                      ({"poisson_ratio": 0.5}, "material.poisson_ratio"),
                                      ({"wheel_poisson_ratio": float("nan")},
                                       "material.wheel_poisson_ratio"),
                                      ({"wheel_young_modulus": 1e15},
                                       "material.wheel_young_modulus")])
def test_bad_constants(kw, name):
    with pytest.raises(InputError, match=name):
        Material(**kw)


def test_interface_layer():
    """CONTACT's M = 4 layer: flexibility h3/G3, a yield limit or none, the floor
    of a softening limit at a tenth of tau_c0, and one-line errors naming the field."""
    import math
    from railcontact.core.materials import InterfaceLayer
    layer = InterfaceLayer(2e-5, 1.0625e8, 2e8, 4.35e11)
    assert layer.flexibility == pytest.approx(2e-5 / 1.0625e8)
    assert layer.plastic and layer.yield_floor == pytest.approx(2e7)
    elastic = InterfaceLayer(1.25e-3, 8.2e9)
    assert not elastic.plastic and elastic.yield_floor == 0.0
    assert InterfaceLayer().flexibility == 0.0 and InterfaceLayer().yield_stress == math.inf
    for kw, name in (({"thickness": -1e-3}, "thickness"), ({"shear_modulus": 0.0},
                     "shear_modulus"), ({"yield_stress": 0.0}, "yield_stress"),
                     ({"hardening": math.nan}, "hardening")):
        with pytest.raises(InputError, match=f"layer.{name}"):
            InterfaceLayer(**kw)
