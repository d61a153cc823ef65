"""The vehicle models (railcontact.dynamics.vehicle): the Manchester benchmark
vehicle's bodies and load paths, and the checks of a model's parameters."""

import pytest

from railcontact.dynamics import VehicleModel
from railcontact.dynamics.vehicle import G_ACC, MANCHESTER
from railcontact.core.errors import InputError


def test_manchester_vehicle_bodies_and_load_paths():
    """Carbody 32 t, two frames of 2615 kg, four wheelsets of 1813 kg: each wheelset
    carries a quarter of the total mass, 11120.5 kg (3 DOF per body)."""
    m = VehicleModel.vehicle()
    assert m.total_mass == pytest.approx(32000 + 2 * 2615 + 4 * 1813)
    assert len(m.bodies) == 7 and m.dofs == 21
    assert m.body_index("wheelset") == [2, 3, 5, 6] and m.body_index("carbody") == [0]
    assert [w[1] for w in m.wheelsets] == pytest.approx([44482.0 / 4] * 4)
    bogie = VehicleModel.bogie()
    assert bogie.total_mass == pytest.approx(2615 + 2 * 1813) and bogie.dofs == 9
    assert [w[1] for w in bogie.wheelsets] == pytest.approx([11120.5] * 2)


def test_single_wheelset_from_the_preset():
    """A wheelset with the primary suspension of both sides (2 k_y, 2 k_x b^2) and
    the static wheel load of its quarter of the vehicle."""
    m = VehicleModel.from_parameters("wheelset")
    p = MANCHESTER
    assert m.total_mass == 1813.0
    assert m.parameters["wheel_load"] == pytest.approx(
        (32000 / 4 + 2615 / 2 + 1813) * G_ACC / 2, rel=1e-12)
    e = m.elements[0]
    assert e.k_y == 2 * p["primary_ky"] and e.k_yaw == pytest.approx(2 * p["primary_kx"])
    assert m.wheelsets[0][1] == pytest.approx(2 * m.parameters["wheel_load"] / G_ACC)


def test_bad_parameters():
    with pytest.raises(InputError, match="unknown"):
        VehicleModel.from_parameters("bogie", {"frame_mas": 1.0})
    with pytest.raises(InputError, match="expected values >= 0"):
        VehicleModel.from_parameters("bogie", {"bump_stop_force": [0.0, -1.0]})
    with pytest.raises(InputError, match="mass"):
        VehicleModel.single_wheelset(mass=0.0)
    with pytest.raises(InputError, match="k_y"):
        VehicleModel.single_wheelset(k_y=-1.0)
