"""Rolling contact fatigue beside wear (railcontact.wear.rcf): Ekberg's surface and
subsurface fatigue indices, the WLRM damage function, their mapping onto the
profiles and accumulation with wear removal; the closed loop's RCF outputs."""

import math

import numpy as np
import pytest

import railcontact as rc
from railcontact.core.errors import CaseFileError
from railcontact.geometry import ContactGeometry
from railcontact.normal import get_normal_model
from railcontact.tangential import get_tangential_model
from railcontact.wear.rcf import (RcfParameters, _fi_sub, accumulate, covered_strips,
                                  patch_measures, profile_values, subsurface_fatigue_index,
                                  surface_fatigue_index, wlrm_damage)

MAT = rc.Material()


def test_surface_fatigue_index():
    """FI_surf = f - k/p0 with p0 = 3 F_n / (2 A) (Ekberg et al. 2002: f - 2 pi a b k /
    (3 F_z) on a Hertzian ellipse of area pi a b)."""
    a, b, fn = 6e-3, 4e-3, 1e5
    area = math.pi * a * b
    fi = surface_fatigue_index(24e3, 18e3, fn, area, 300e6)
    assert fi == pytest.approx(0.3 - 2 * math.pi * a * b * 300e6 / (3 * fn), rel=1e-12)
    assert np.isnan(surface_fatigue_index(1.0, 0.0, 0.0, area, 300e6))
    # shakedown: a higher pressure (smaller area) raises the index
    assert surface_fatigue_index(24e3, 18e3, fn, 0.5 * area, 300e6) > fi


def test_wlrm_damage_function():
    """Burstow's damage function: 0 up to 15 N, 1/20000 at 65 N, linear between, back
    to 0 at 175 N and beyond (wear dominates)."""
    t = np.array([0.0, 15.0, 40.0, 65.0, 120.0, 175.0, 300.0])
    d = wlrm_damage(t)
    np.testing.assert_allclose(d, [0, 0, 2.5e-5, 5e-5, 2.5e-5, 0, 0], atol=1e-18)
    p = RcfParameters(tgamma_peak=50.0, peak_damage=1e-4)
    assert wlrm_damage(50.0, p) == pytest.approx(1e-4)


def test_patch_measures_match_the_vector_formulas():
    geom = ContactGeometry(curvatures=(1 / 0.92, 1 / 0.6))
    ns = get_normal_model("hertz").solve(geom, MAT, normal_force=1e5, grid=(20, 20))
    ts = get_tangential_model("fastsim").solve(ns, geom, MAT, (2e-3, -1e-3, 0.5), 0.3, 30.0)
    p = RcfParameters()
    fi, tg, dmg = patch_measures(ns, ts, 30.0, p)
    assert fi == pytest.approx(float(surface_fatigue_index(ts.fx, ts.fy, ns.normal_force,
                                                           ns.area, p.shear_yield)), rel=1e-12)
    assert tg == pytest.approx(ts.frictional_power / 30.0, rel=1e-12)
    assert dmg == pytest.approx(float(wlrm_damage(tg, p)), rel=1e-12, abs=1e-20)
    assert fi == patch_measures(ns, ts, 30.0, p, ts.frictional_power)[0]


def test_fi_sub_kernel_on_a_known_history():
    """A pure shear sigma_xy = A sin(x) along the rolling line, no mean stress: the
    deviatoric range is 2A, so tau_eq,a = A; a tensile mean stress H adds a_DV H."""
    x = np.linspace(-np.pi, np.pi, 61)
    sig = np.zeros((6, x.size, 2, 3))
    sig[3, :, 1, 2] = 50e6 * np.sin(x)
    v, j, k = _fi_sub(sig, 1 / 3)
    assert (j, k) == (1, 2) and v == pytest.approx(50e6, rel=1e-3)
    sig[0:3, :, 1, 2] = 30e6
    v, _, _ = _fi_sub(sig, 1 / 3)
    assert v == pytest.approx(50e6 + 10e6, rel=1e-3)


def test_subsurface_fatigue_index_of_hertz_contact():
    """A Hertzian contact without traction: FI_sub from the subsurface field equals the
    brute-force evaluation of its definition on that field, lies below the surface,
    and grows with the traction (full sliding, mu = 0.3, moves it up)."""
    from railcontact.subsurface import default_depths, subsurface_stresses
    from railcontact.tangential.base import TangentialSolution
    geom = ContactGeometry(curvatures=(2.0, 2.0))
    ns = get_normal_model("hertz").solve(geom, MAT, normal_force=1e5, grid=(21, 21))
    p = RcfParameters(depths=9)
    r = subsurface_fatigue_index(ns, None, MAT, p)
    ss = subsurface_stresses(ns, None, default_depths(ns, 9), MAT)
    s = ss.sigma
    h = s[:3].sum(axis=0) / 3
    dev = np.concatenate([s[:3] - h, s[3:]])
    d = dev[:, :, None] - dev[:, None, :]                   # (6, x1, x2, y, z)
    j2 = 0.5 * (d[:3] ** 2).sum(axis=0) + (d[3:] ** 2).sum(axis=0)
    brute = (0.5 * np.sqrt(j2.max(axis=(0, 1))) + h.max(axis=0) / 3).max()
    assert r["fi_sub"] == pytest.approx(brute, rel=1e-12)
    assert r["depth"] > 0 and r["fi_sub"] < ns.pmax
    z = np.zeros_like(ns.pressure)
    ts = TangentialSolution("sliding", ns.x, ns.y, -0.3 * ns.pressure, z, z, z,
                            z.astype(bool), ns.contact, 0.0, 0.0, 0.0, 1.0)
    rs = subsurface_fatigue_index(ns, ts, MAT, p)
    assert rs["fi_sub"] > r["fi_sub"] and rs["depth"] <= r["depth"]


class _Geom:
    y_rail, y_wheel, side = 0.01, -0.02, "left"


def test_profile_values_and_accumulation():
    """A strip value lands at s = s_ref + sgn y_c (sgn -1 on the left), unscaled; wear
    removes the fraction depth / layer of the damage."""
    from railcontact.profiles import s1002
    prof = s1002()
    s_ref = float(prof.arc_length(_Geom.y_wheel))
    grid = np.linspace(s_ref - 0.01, s_ref + 0.01, 201)
    yc = np.linspace(-3e-3, 3e-3, 7)
    vals = profile_values(_Geom(), yc, np.ones(7), prof, "wheel", grid)
    inside = np.abs(grid - s_ref) <= 3e-3 + 1e-12
    np.testing.assert_allclose(vals[inside], 1.0)
    assert np.all(vals[np.abs(grid - s_ref) > 3.2e-3] == 0.0)
    ramp = profile_values(_Geom(), yc, yc, prof, "wheel", np.array([s_ref - 2e-3]))
    assert ramp[0] == pytest.approx(2e-3)                        # left: s decreases with y_c
    np.testing.assert_allclose(accumulate([1e-3, 1e-3, 1e-3], [1e-4, 0, 0],
                                          [0.0, 5e-5, 2e-4], 1e-4), [1.1e-3, 5e-4, 0.0])


def test_parameters_from_the_scenario_table():
    p = RcfParameters.from_dict({"shear_yield": 350e6, "subsurface": True, "depths": 7})
    assert p.shear_yield == 350e6 and p.subsurface and p.depths == 7
    with pytest.raises(CaseFileError, match="unknown key wear.rcf.yield"):
        RcfParameters.from_dict({"yield": 1.0})
    with pytest.raises(CaseFileError, match="subsurface"):
        RcfParameters.from_dict({"subsurface": 1})
    with pytest.raises(CaseFileError, match="tgamma"):
        RcfParameters.from_dict({"tgamma_peak": 10.0})


def test_covered_strips():
    geom = ContactGeometry(curvatures=(2.0, 2.0))
    ns = get_normal_model("hertz").solve(geom, MAT, normal_force=1e5, grid=(10, 12))
    c = covered_strips(ns)
    assert c.shape == (12,) and set(np.unique(c)) <= {0.0, 1.0} and c.sum() >= 10


# ---------------------------------------------------------------- on the example
def test_example_reports_rcf(wear_vehicle_example):
    """examples/wear_vehicle.toml: wear.nc holds FI_surf per route and profile position
    and the accumulated WLRM damage.  The largest FI_surf of every step is on an outer
    (left) wheel in a curve, at the flange root (-35 < y < -20 mm; measured on R300
    0.185, 0.197, 0.202, 0.175 against R1200's 0.185, 0.195, 0.159, 0.176: the
    traction coefficient is saturated, 0.287 - 0.296 against mu = 0.3, on both
    curves, and the index is mu - k / p0 of the flange-root patch); on R300 the outer
    wheel's index is above the inner's and the tangent's.  The accumulated damage
    follows the step's damage less the worn fraction of the layer."""
    _, ds = wear_vehicle_example
    y = ds["y_wheel"].values
    fi = ds["fi_surf_wheel"]
    layer = ds.attrs["rcf_layer_depth_m"]
    for k in range(ds.sizes["step"]):
        step = fi.isel(step=k).max("wheelset")
        best = step.where(np.isfinite(step), -np.inf)
        r, side, i = np.unravel_index(int(np.argmax(best.values)), best.shape)
        assert ds["route"].values[r] in ("R300", "R1200") and step["side"].values[side] == "left"
        assert -0.035 < y[i] < -0.020
        assert 0.15 < float(best.max()) < 0.3
        r300 = step.sel(route="R300")
        assert float(r300.sel(side="left").max()) > float(r300.sel(side="right").max())
        assert float(r300.sel(side="left").max()) > float(step.sel(route="tangent").max())
        for name, added in (("rcf_damage_wheel", "rcf_added_wheel"),
                            ("rcf_surface_wheel", "rcf_surface_added_wheel")):
            before = ds[name].isel(step=k - 1).values if k else 0.0
            np.testing.assert_allclose(
                ds[name].isel(step=k).values,
                accumulate(before, ds[added].isel(step=k).values,
                           ds["wear_depth_wheel"].isel(step=k).values, layer), rtol=1e-12)
    assert float(ds["rcf_damage_wheel"].isel(step=-1).max()) > 0
    assert np.all(ds["rcf_damage_wheel"].values >= 0)
    assert np.all(ds["rcf_surface_wheel"].values >= 0)
    assert np.all(ds["rcf_time"].values < ds["postprocess_time"].values)


def test_example_surface_exceedance_per_route(wear_vehicle_example):
    """The FI_surf exceedance (sum over the passages of max(FI_surf, 0)) per metre run
    on each route, at the leading wheelset's outer (left) wheel: zero on the tangent
    (FI_surf <= 0.04 there), largest at the flange root in the curves.  Which curve
    carries more depends on the profiles (measured, docs/wear.md): on the new S1002
    (steps 1, 2) R1200's leading wheel runs on its flange root in one patch (y =
    -27 to -29 mm, 17 - 19 deg, p0 2.9 - 3.2 GPa) and exceeds R300's, whose contact
    climbs the flange (-31 to -35 mm, up to 36 deg, p0 down to 1.5 GPa): 0.047 and
    0.053 against 0.026 and 0.032 per metre; on the worn profiles (steps 3, 4) R300
    exceeds R1200: 0.056 and 0.051 against 0.041 and 0.035."""
    _, ds = wear_vehicle_example
    y = ds["y_wheel"].values
    rate = ds["rcf_surface_rate_wheel"].sel(wheelset=1, side="left")
    assert rate.attrs["units"] == "1/m"
    peak = {r: rate.sel(route=r).max("y_wheel").values for r in ("tangent", "R1200", "R300")}
    where = {r: y[rate.sel(route=r).argmax("y_wheel").values] for r in ("R1200", "R300")}
    assert np.all(peak["tangent"] < 0.01 * np.minimum(peak["R1200"], peak["R300"]))
    for r in ("R1200", "R300"):
        assert np.all((where[r] > -0.036) & (where[r] < -0.022))
    assert np.all(peak["R1200"][:2] > 1.4 * peak["R300"][:2])         # new profiles
    assert np.all(where["R1200"][:2] > -0.0295) and np.all(where["R300"][:2] < -0.030)
    assert np.all(peak["R300"][2:] > 1.2 * peak["R1200"][2:])         # worn profiles


def test_tiny_loop_with_fi_sub():
    """The tiny closed loop of tests/wear/test_closed_loop.py with FI_sub: wear.nc
    holds FI_sub per route and position where FI_surf is (the same patches), and in
    the tight curve the outer (left) wheel's largest FI_sub is above the inner's."""
    import copy

    from railcontact.inputs import wear_scenario_from_dict
    from railcontact.wear.closed_loop import ClosedLoopWear
    from tests.wear.test_closed_loop import TINY
    raw = copy.deepcopy(TINY)
    raw["wear"].update(steps=1, rcf={"subsurface": True, "depths": 6})
    raw["route"] = raw["route"][:1]
    raw["solver"]["grid"] = [12, 12]
    sc = wear_scenario_from_dict(raw)
    sc.scheduler = "sync"
    ds = ClosedLoopWear(sc, None, progress=False).run(resume=False)
    sub, surf = ds["fi_sub_wheel"].isel(step=0), ds["fi_surf_wheel"].isel(step=0)
    assert sub.attrs["units"] == "Pa"
    np.testing.assert_array_equal(np.isfinite(sub.values), np.isfinite(surf.values))
    curve = sub.sel(route="R300", wheelset=1)
    assert float(curve.sel(side="left").max()) > float(curve.sel(side="right").max()) > 0
    assert float(ds["rcf_time"].sum()) > 0
