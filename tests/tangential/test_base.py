"""The tangential layer's contract (railcontact.tangential.base): the registry,
input checks and the result's derived quantities on a hand-made solution."""

import math

import numpy as np
import pytest

from railcontact.core.errors import InputError, UnknownModelError
from railcontact.tangential.base import (TANGENTIAL_CAPABILITIES, TangentialSolution,
                                         check_inputs, get_tangential_model,
                                         tangential_model_class, tangential_models,
                                         tangential_supports)


def test_registry_and_capabilities():
    names = tangential_models()
    assert {"fastsim", "polach", "linear", "exact", "fastrip"} <= set(names)
    online = tangential_models("online")
    assert set(online) == {n for n in names if tangential_supports(n, "online")}
    assert {"linear", "fastsim", "polach"} <= set(online) and "exact" not in online
    for n in names:
        assert set(tangential_model_class(n).capabilities) <= set(TANGENTIAL_CAPABILITIES)
    assert type(get_tangential_model("linear")) is tangential_model_class("linear")
    with pytest.raises(UnknownModelError):
        get_tangential_model("fastsim2")


def test_check_inputs():
    assert check_inputs([1, "2e-3", 0.5], 0.3) == (1.0, 2e-3, 0.5)
    with pytest.raises(InputError, match="three numbers"):
        check_inputs((1e-3, 0.0), 0.3)
    with pytest.raises(InputError, match="finite"):
        check_inputs((math.nan, 0.0, 0.0), 0.3)
    for mu in (-0.1, 6.0, math.inf):
        with pytest.raises(InputError, match="friction.coefficient"):
            check_inputs((0.0, 0.0, 0.0), mu)


def test_power_stick_fraction_and_dataset():
    x, y = np.array([0.0, 1e-3]), np.array([0.0, 2e-3, 4e-3])
    tx = np.array([[1e8, 0.0, 2e8], [0.0, 0.0, 0.0]])
    sx = np.array([[1e-3, 0.0, -2e-3], [0.0, 0.0, 0.0]])
    ty, sy = np.full((2, 3), 1e7), np.full((2, 3), 1e-3)
    contact = np.array([[True, True, True], [True, False, False]])
    stick = np.array([[False, True, False], [True, True, False]])
    t = TangentialSolution("hand", x, y, tx, ty, sx, sy, stick, contact, 10.0, 20.0, 0.0, 30.0)
    # |tx sx + ty sy| V per element, times dA = 2e-6 m^2 (element (0, 2): |-3.9e5| V)
    dens = np.abs(tx * sx + ty * sy) * 30.0
    assert t.power_density == pytest.approx(dens)
    assert t.frictional_power == pytest.approx(dens.sum() * 2e-6, rel=1e-12)
    assert t.frictional_power == pytest.approx((1.1e5 + 1e4 + 3.9e5 + 3e4) * 30 * 2e-6, rel=1e-12)
    assert t.stick_fraction == pytest.approx(2 / 4)       # stick outside the contact ignored
    ds = t.to_xarray()
    assert ds["traction_x"].attrs["units"] == "Pa" and ds.attrs["Fy_N"] == 20.0
    assert int(ds["stick"].sum()) == 3 and ds["x"].attrs["units"] == "m"
