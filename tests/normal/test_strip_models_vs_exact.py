"""All normal models against our exact solver on S1002 / UIC60 (the Manchester
benchmark profiles, 10 kN, 0.2 mm elements), shifts including the two-region
(5 mm) and the lateral-curvature-jump (1, 3 mm) patches.

Bound: the largest deviation from CONTACT that Tao et al. (CM2015, seed 001,
Tables 1-2, shifts 0/3/5/8 mm) report for the same family of models:

* Hertz: area -36 %, pmax +13 %;
* Kik-Piotrowski: area +51 %, pmax -49 %;
* STRIPES ("Ayasse"): area -23 %, pmax +15 %;
* ANALYN ("Sichani"): area +17 %, pmax +13 %;
* KPEC is not in the table and gets the STRIPES/ANALYN bound.

Measured (``tests`` run, area/pmax): STRIPES -1..-16 % / -1..+7 %, ANALYN -6..+4 % /
-1..+4 %, KPEC -13..+5 % / -4..+3 %, Kik-Piotrowski -5..+23 % / -7..-25 %.
"""

from functools import lru_cache

import pytest

import railcontact as rc

BOUND = {"hertz": (0.36, 0.13), "kik-piotrowski": (0.51, 0.49), "stripes": (0.23, 0.15),
         "analyn": (0.17, 0.13), "kpec": (0.23, 0.15)}


def _case(refdir, y, method):
    prof = refdir / "profiles"
    return rc.case_from_dict({
        "material": {"young_modulus": 2 * 82e9 * 1.28, "poisson_ratio": 0.28},
        "wheel": {"profile": str(prof / "MBench_S1002_v3.prw")},
        "rail": {"profile": str(prof / "MBench_UIC60_v3.prr"), "inclination": 0.0},
        "wheelset": {"lateral_shift": y * 1e-3, "vertical_force": 1e4, "velocity": 2.0},
        "solver": {"normal": method, "tangential": "fastsim", "element_size": [2e-4, 2e-4]}})


@lru_cache(maxsize=None)
def _right(refdir, y, method):
    res = rc.solve(_case(refdir, y, method))
    assert res.converged
    ps = [q for q in res.patches if q.geometry.side == "right"]
    return sum(q.normal.area for q in ps), max(q.normal.pmax for q in ps), len(ps)


@pytest.mark.parametrize("y", [0.0, 1.0, 3.0, 5.0, 8.0])
@pytest.mark.parametrize("method", sorted(BOUND))
def test_within_literature_spread(refdir, method, y):
    area, pmax, n = _right(refdir, y, method)
    area_x, pmax_x, n_x = _right(refdir, y, "exact")
    if method != "hertz":
        assert n == n_x                      # tread + flange-root regions found alike
    ba, bp = BOUND[method]
    assert abs(area / area_x - 1) <= ba
    assert abs(pmax / pmax_x - 1) <= bp


@pytest.mark.parametrize("y", [3.0, 5.0, 8.0])
def test_kik_piotrowski_larger_area_than_exact(refdir, y):
    """KP's known over-estimate of the area (and under-estimate of pmax)."""
    area, pmax, _ = _right(refdir, y, "kik-piotrowski")
    area_x, pmax_x, _ = _right(refdir, y, "exact")
    assert area > 1.03 * area_x and pmax < 0.95 * pmax_x


def test_stripes_differs_from_analyn_on_curvature_jump(refdir):
    """At 1 mm the lateral curvature jumps inside the patch: the two methods' patch
    corrections differ (measured: STRIPES -16 %, ANALYN -1 % area)."""
    a_s = _right(refdir, 1.0, "stripes")[0]
    a_a = _right(refdir, 1.0, "analyn")[0]
    assert abs(a_s / a_a - 1) > 0.05
