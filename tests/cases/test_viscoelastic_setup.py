"""``[viscoelastic]`` in a ``[bodies]`` case: the option of both exact models, its
limits (tau_c = 0: the elastic case with the final modulus E_g / (1 + f);
tau_c -> inf: Hertz with the initial modulus) and the rolling asymmetry between."""

import copy
import math

import numpy as np
import pytest

from railcontact.cases.case import case_from_dict
from railcontact.cases.solve import solve
from railcontact.core.errors import CaseFileError
from railcontact.core.hertz_theory import hertz_ellipse

E_G, NU, FN = 3.2e9, 0.4, 2000.0

BASE = {
    "material": {"young_modulus": E_G, "poisson_ratio": NU},
    "bodies": {"radii": {"wheel_rolling": 0.1, "wheel_lateral": 0.1, "rail_rolling": 0.1,
                         "rail_lateral": math.inf},
               "normal_force": FN, "velocity": 1.0},
    "viscoelastic": {"spring_ratio": 1.0, "relaxation_time": 0.003},
    "creepage": {"longitudinal": -0.002},
    "friction": {"coefficient": 0.3},
    "solver": {"normal": "exact", "tangential": "exact", "grid": [30, 30]},
}


def _case(**changes):
    raw = copy.deepcopy(BASE)
    for dotted, v in changes.items():
        sec, key = dotted.split("__")
        if v is None:
            raw[sec].pop(key, None)
        else:
            raw.setdefault(sec, {})[key] = v
    return raw


def _solve(raw):
    res = solve(case_from_dict(raw))
    assert res.converged
    return res.patches[0]


def test_option_reaches_both_models():
    c = case_from_dict(_case())
    opt = c.normal_options["viscoelastic"]
    assert opt == {"spring_ratio": [1.0, 1.0], "relaxation_time": [0.003, 0.003],
                   "velocity": 1.0}
    assert c.tangential_options["viscoelastic"] == opt
    c = case_from_dict(_case(viscoelastic__wheel_relaxation_time=0.0))
    assert c.normal_options["viscoelastic"]["relaxation_time"] == [0.003, 0.0]


def test_no_relaxation_is_the_elastic_case_with_the_final_modulus():
    """tau_c = 0 and f = 1: the elastic case with E_g / 2, on the same grid: F_x, p_max
    and the area equal to the elastic iteration's tolerance (tol = 1e-5; measured
    5e-6 in p_max: the active set solves its equations exactly)."""
    v = _solve(_case(viscoelastic__relaxation_time=0.0))
    raw = _case(material__young_modulus=E_G / 2)
    del raw["viscoelastic"]
    e = _solve(raw)
    assert v.normal.pmax == pytest.approx(e.normal.pmax, rel=1e-5)
    assert v.normal.area == pytest.approx(e.normal.area, rel=1e-9)
    assert v.tangential.fx == pytest.approx(e.tangential.fx, rel=1e-5)


def test_long_relaxation_is_hertz_with_the_initial_modulus():
    """tau_c = 1e4 s: Hertz with E_g, issue 34's tolerances (p_max and the area
    within 3 %: measured -0.06 % and +1.8 % on 60 x 60 elements, the grid sized for
    the softer final modulus; the elastic exact model on its own grid +1.0 %), F_x
    that of the elastic case with E_g within 1 % (measured 0.4 %)."""
    v = _solve(_case(viscoelastic__relaxation_time=1e4, solver__grid=[60, 60]))
    Es = E_G / (2 * (1 - NU * NU))
    hz = hertz_ellipse(10.0, 5.0, Es, force=FN)
    assert v.normal.pmax == pytest.approx(hz.p0, rel=0.03)
    assert v.normal.area == pytest.approx(hz.area, rel=0.03)
    assert v.normal.normal_force == pytest.approx(FN, rel=1e-9)
    raw = _case(solver__grid=[60, 60])
    del raw["viscoelastic"]
    assert v.tangential.fx == pytest.approx(_solve(raw).tangential.fx, rel=0.01)


def test_rolling_asymmetry():
    """A relaxation length near the contact's size: the pressure's centre ahead
    (towards +x, the leading edge: a rolling resistance), p_max between the limits."""
    v = _solve(_case())
    n = v.normal
    xc = float((n.x[:, None] * n.pressure).sum() / n.pressure.sum())
    a = 0.5 * np.ptp(n.x[n.contact.any(axis=1)])
    assert xc > 0.02 * a
    Es = E_G / (2 * (1 - NU * NU))
    assert hertz_ellipse(10.0, 5.0, Es / 2, force=FN).p0 < n.pmax < \
        hertz_ellipse(10.0, 5.0, Es, force=FN).p0


@pytest.mark.parametrize("changes, match", [
    ({"solver__normal": "hertz"}, "option of the exact models"),
    ({"viscoelastic__spring_ratio": -1.0}, "spring_ratio"),
    ({"viscoelastic__relaxation_time": None}, "relaxation_time: missing"),
    ({"viscoelastic__tau": 1.0}, "tau"),
])
def test_bad_sections_named(changes, match):
    with pytest.raises(CaseFileError, match=match):
        case_from_dict(_case(**changes))
