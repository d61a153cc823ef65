"""Subsurface stresses under solved patches against closed forms: Hertz's circular
contact on the axis (Johnson 1985, eq. 3.45), Hamilton's (1983) explicit stresses
of the Hertzian pressure at points off the axis, and the sliding sphere's traction
(Cerruti's point force integrated over the Hertzian traction; Hamilton & Goodman
1966 at the trailing edge)."""

import math

import numpy as np
import pytest

import railcontact as rc
from railcontact.core.errors import InputError
from railcontact.geometry import ContactGeometry
from railcontact.normal import get_normal_model
from railcontact.subsurface.kernels import stresses_at_points
from railcontact.subsurface.stresses import (MEASURES, SubsurfaceStresses, default_depths,
                                             stresses_on_grid, subsurface_stresses)
from railcontact.tangential import get_tangential_model
from railcontact.tangential.base import TangentialSolution

MAT = rc.Material()
NU = MAT.poisson_ratio
FN = 1e5
SPHERE = ContactGeometry(curvatures=(1 / 0.5, 1 / 0.5))


def _hertz(grid, margin=0.05):
    return get_normal_model("hertz", margin=margin).solve(SPHERE, MAT, normal_force=FN, grid=grid)


def _sliding(ns, mu):
    """Full sliding of the wheel in -x over the rail: traction mu p on the rail in +x,
    i.e. -mu p on the wheel (the tangential solution's tractions)."""
    z = np.zeros_like(ns.pressure)
    return TangentialSolution(model="sliding", x=ns.x, y=ns.y, traction_x=-mu * ns.pressure,
                              traction_y=z, slip_x=z, slip_y=z, stick=z.astype(bool),
                              contact=ns.contact, fx=0.0, fy=0.0, mz=0.0, velocity=1.0)


def hamilton_pressure(x, y, z, a, P, nu):
    """Hamilton (1983), the stresses of the Hertzian pressure of total force P on a
    circle of radius a at (x, y, z), r > 0 (tension positive): with
    A = r^2 + z^2 - a^2, S = sqrt(A^2 + 4 a^2 z^2), M = sqrt((S + A)/2),
    N = sqrt((S - A)/2), phi = atan(a/M), G = M^2 - N^2 + zM - aN, H = 2MN + aM + zN."""
    r2 = x * x + y * y
    A = r2 + z * z - a * a
    S = math.sqrt(A * A + 4 * a * a * z * z)
    M, N = math.sqrt((S + A) / 2), math.sqrt((S - A) / 2)
    phi = math.atan(a / M)
    G, H = M * M - N * N + z * M - a * N, 2 * M * N + a * M + z * N
    c = 3 * P / (2 * math.pi * a ** 3)
    B = (1 - nu) * N * z * z - (1 - 2 * nu) / 3 * (N * S + 2 * A * N + a ** 3) - nu * M * z * a
    sx = c * ((1 + nu) * z * phi + ((y * y - x * x) / r2 * B - N * (x * x + 2 * nu * y * y)
                                   - M * x * x * z * a / S) / r2)
    sy = c * ((1 + nu) * z * phi + ((x * x - y * y) / r2 * B - N * (y * y + 2 * nu * x * x)
                                   - M * y * y * z * a / S) / r2)
    sz = c * (-N + a * z * M / S)
    sxy = c * (x * y * (1 - 2 * nu) / r2 ** 2 * (-N * r2 + 2 / 3 * N * (S + 2 * A)
                                                 - z * (z * N + a * M) + 2 / 3 * a ** 3)
               + x * y * z / r2 ** 2 * (-a * M * r2 / S - z * N + a * M))
    sxz = -c * z * (x * N / S - x * z * H / (G * G + H * H))
    syz = -c * z * (y * N / S - y * z * H / (G * G + H * H))
    return np.array([sx, sy, sz, sxy, sxz, syz])


def test_hertz_axis_against_johnson():
    """Hertz circular contact, 41 x 41 grid (the axis on an element centre): sigma_r
    and sigma_z on the axis within 0.5 % of Johnson's eq. 3.45 from 0.1 a to 2 a
    (measured: largest deviation 0.38 %, sigma_r at z = a where it is small;
    sigma_r is left out at 1.5 a, next to its change of sign at 1.43 a); the
    largest von Mises stress within 0.5 % of the closed form's maximum over depth."""
    ns = _hertz((41, 41))
    a, p0 = ns.semi_axes[0], ns.pmax
    zr = np.array([0.1, 0.25, 0.5, 0.75, 1.0, 1.5, 2.0])
    ss = subsurface_stresses(ns, depths=zr * a, material=MAT)
    i, j = int(np.argmin(abs(ns.x))), int(np.argmin(abs(ns.y)))
    assert ns.x[i] == pytest.approx(0.0, abs=1e-12 * a)
    sz = -p0 / (1 + zr ** 2)
    sr = p0 * (-(1 + NU) * (1 - zr * np.arctan(1 / zr)) + 0.5 / (1 + zr ** 2))
    # sigma_r changes sign near z = 1.43 a: compared where it is not near zero
    far = zr != 1.5
    np.testing.assert_allclose(ss.sigma[0, i, j][far], sr[far], rtol=0.005)
    np.testing.assert_allclose(ss.sigma[1, i, j][far], sr[far], rtol=0.005)
    np.testing.assert_allclose(ss.sigma[2, i, j], sz, rtol=0.005)
    np.testing.assert_allclose(ss.sigma[3:, i, j], 0.0, atol=1e-9 * p0)
    # von Mises: |sigma_z - sigma_r| on the axis, largest near z = 0.48 a
    zf = np.linspace(0.3, 0.7, 41)
    vm = np.abs(-1 / (1 + zf ** 2) + (1 + NU) * (1 - zf * np.arctan(1 / zf)) - 0.5 / (1 + zf ** 2))
    ss = subsurface_stresses(ns, depths=zf * a, material=MAT)
    m = ss.maximum("von_mises")
    assert m["value"] == pytest.approx(p0 * vm.max(), rel=0.005)
    assert m["depth"] == pytest.approx(a * zf[np.argmax(vm)], abs=0.03 * a)
    assert abs(m["x"]) < 1e-9 and abs(m["y"]) < 1e-9


#: points (x/a, y/a, z/a), r <= 0.75 a: where the element centres of the 81 x 81 grid
#: lie nearest; Hamilton's equations are evaluated at the centres themselves
HAMILTON_POINTS = [(0.5, 0.25, 0.1), (0.5, 0.25, 0.5), (-0.75, 0.5, 0.3), (0.25, -0.6, 0.5),
                   (0.25, -0.6, 1.0), (1.0, 0.0, 0.5), (1.5, 0.5, 0.25)]


def test_hamilton_pressure_off_axis():
    """The Hertzian pressure's six stresses at HAMILTON_POINTS within 1 % of
    Hamilton's explicit equations, with a floor of 1 % of p0 for the components that
    vanish (measured: largest deviation 0.06 % of p0)."""
    ns = _hertz((81, 81), margin=0.0)
    a, p0 = ns.semi_axes[0], ns.pmax
    depths = sorted({pt[2] for pt in HAMILTON_POINTS})
    ss = subsurface_stresses(ns, depths=np.array(depths) * a, material=MAT)
    worst = 0.0
    for fx, fy, fz in HAMILTON_POINTS:
        i, j, k = (int(np.argmin(abs(ns.x - fx * a))), int(np.argmin(abs(ns.y - fy * a))),
                   depths.index(fz))
        ref = hamilton_pressure(ns.x[i], ns.y[j], fz * a, a, FN, NU)
        got = ss.sigma[:, i, j, k]
        assert np.all(np.abs(got - ref) <= 0.01 * np.maximum(np.abs(ref), p0))
        worst = max(worst, np.abs(got - ref).max() / p0)
    assert worst < 1e-3


def _cerruti_traction(x, y, z, a, q0, n=200):
    """sigma_zz, sigma_xz, sigma_yz at (x, y, z) of the traction q0 sqrt(1 - r^2/a^2)
    in +x: Cerruti's point force (-3 Q x z^2, -3 Q x^2 z, -3 Q x y z over 2 pi rho^5)
    integrated over the circle, Gauss-Legendre in r and theta (n points each; the
    integrand is smooth for z > 0)."""
    t, w = np.polynomial.legendre.leggauss(n)
    r = 0.5 * a * (t + 1)
    th = np.pi * (t + 1)
    R, TH = np.meshgrid(r, th, indexing="ij")
    W = np.outer(0.5 * a * w, np.pi * w) * R * q0 * np.sqrt(1 - (R / a) ** 2)
    dx, dy = x - R * np.cos(TH), y - R * np.sin(TH)
    rho5 = (dx * dx + dy * dy + z * z) ** 2.5
    c = -3 / (2 * np.pi)
    return np.array([np.sum(W * c * dx * z * z / rho5), np.sum(W * c * dx * dx * z / rho5),
                     np.sum(W * c * dx * dy * z / rho5)])


def test_sliding_sphere_traction():
    """The sliding sphere (mu = 0.3, traction mu p on the rail): at HAMILTON_POINTS
    below the surface the stresses sigma_zz, sigma_xz, sigma_yz of the traction
    within 1 % (floor 1 % of mu p0) of Cerruti's point force integrated over the
    Hertzian traction; the pressure's stresses unchanged (superposition)."""
    mu = 0.3
    ns = _hertz((81, 81), margin=0.0)
    a, p0 = ns.semi_axes[0], ns.pmax
    depths = sorted({pt[2] for pt in HAMILTON_POINTS})
    dry = subsurface_stresses(ns, depths=np.array(depths) * a, material=MAT)
    wet = subsurface_stresses(ns, _sliding(ns, mu), depths=np.array(depths) * a, material=MAT)
    for fx, fy, fz in HAMILTON_POINTS:
        i, j, k = (int(np.argmin(abs(ns.x - fx * a))), int(np.argmin(abs(ns.y - fy * a))),
                   depths.index(fz))
        ref = _cerruti_traction(ns.x[i], ns.y[j], fz * a, a, mu * p0)
        got = (wet.sigma - dry.sigma)[[2, 4, 5], i, j, k]
        assert np.all(np.abs(got - ref) <= 0.01 * np.maximum(np.abs(ref), mu * p0))


def test_sliding_sphere_trailing_edge():
    """The largest tensile stress of the sliding sphere, at the surface at the
    trailing edge x = -a: sigma_x = p0 [(1 - 2 nu)/3 + (4 + nu) pi mu / 8] (Hamilton &
    Goodman 1966; Johnson 1985, eq. 7.?); 1 % after Richardson extrapolation in the
    square root of the element size (the traction's stress varies as the square root
    of the distance to the edge, so the piecewise constant elements converge as
    sqrt(dx): measured 0.598 p0 at dx = a/50, 0.614 p0 at a/100 -> 0.652 p0)."""
    mu, a, p0 = 0.3, 1.0, 1.0
    vals = []
    for K in (50, 100):
        d = a / K
        c = (np.arange(2 * K + 3) - (K + 1)) * d          # -a and a are element centres
        X, Y = np.meshgrid(c, c, indexing="ij")
        p = p0 * np.sqrt(np.clip(1 - (X ** 2 + Y ** 2) / a ** 2, 0, None))
        m = p > 0
        rects = np.c_[X[m] - d / 2, X[m] + d / 2, Y[m] - d / 2, Y[m] + d / 2]
        s = stresses_at_points([[-a, 0.0, 0.0]], rects, np.c_[p[m], mu * p[m], 0 * p[m]], NU)
        vals.append(s[0, 0])
    r2 = math.sqrt(2.0)
    extrapolated = (r2 * vals[1] - vals[0]) / (r2 - 1)
    exact = p0 * ((1 - 2 * NU) / 3 + (4 + NU) * math.pi * mu / 8)
    assert extrapolated == pytest.approx(exact, rel=0.01)
    assert vals[0] < vals[1] < exact


def test_every_model_surface_pressure_and_wheel_body(tmp_path):
    """Exact normal + FASTSIM on a 20 x 24 grid: at the surface sigma_zz = -p and
    (sigma_xz, sigma_yz) = the tractions on the rail (minus the wheel's) at every
    element centre; the wheel's stresses are the rail's with the tractions reversed
    for a load symmetric in y; NetCDF round trip and the plot."""
    geom = ContactGeometry(curvatures=(1 / 0.92, 1 / 0.6))
    ns = get_normal_model("exact").solve(geom, MAT, normal_force=FN, grid=(20, 24))
    ts = get_tangential_model("fastsim").solve(ns, geom, MAT, (1e-3, -5e-4, 0.0), 0.3, 30.0)
    ss = subsurface_stresses(ns, ts, depths=[0.0, 1e-3, 2e-3], material=MAT)
    scale = ns.pmax
    np.testing.assert_allclose(ss.sigma[2, :, :, 0], -ns.pressure, atol=1e-9 * scale)
    np.testing.assert_allclose(ss.sigma[4, :, :, 0], ts.traction_x, atol=1e-9 * scale)
    np.testing.assert_allclose(ss.sigma[5, :, :, 0], ts.traction_y, atol=1e-9 * scale)
    assert "exact" in ss.source and "fastsim" in ss.source
    # the wheel, longitudinal traction only, symmetric patch
    tsx = _sliding(ns, 0.2)
    wheel = subsurface_stresses(ns, tsx, depths=[5e-4], material=MAT, body="wheel")
    rev = _sliding(ns, -0.2)
    rail = subsurface_stresses(ns, rev, depths=[5e-4], material=MAT)
    np.testing.assert_allclose(wheel.sigma, rail.sigma, atol=1e-9 * scale)
    # measures and their maxima
    mx = ss.maxima()
    assert set(mx) == set(MEASURES)
    # von Mises <= Tresca <= 2/sqrt(3) von Mises (uniaxial, pure shear)
    assert np.all(ss.tresca >= ss.von_mises * (1 - 1e-12))
    assert np.all(ss.tresca <= 2 / math.sqrt(3) * ss.von_mises * (1 + 1e-12))
    ps = ss.principal
    np.testing.assert_allclose(ps.sum(axis=0), 3 * ss.hydrostatic, atol=1e-9 * scale)
    ds = ss.to_xarray()
    path = tmp_path / "subsurface.nc"
    ds.to_netcdf(path, engine="h5netcdf")
    import xarray as xr
    back = xr.load_dataset(path, engine="h5netcdf")
    np.testing.assert_allclose(back["sigma_zz"].values, ss.sigma[2])
    assert back.attrs["max_von_mises_Pa"] == pytest.approx(mx["von_mises"]["value"])
    assert back["von_mises"].attrs["units"] == "Pa"
    png = ss.plot_sections(tmp_path / "sections.png")
    assert png.stat().st_size > 10_000


def test_defaults_and_errors():
    ns = _hertz((10, 10))
    z = default_depths(ns)
    a = ns.semi_axes[0]
    assert z[0] == 0.0 and z[-1] == pytest.approx(2 * a, rel=0.02)
    ss = subsurface_stresses(ns)
    assert isinstance(ss, SubsurfaceStresses) and ss.sigma.shape == (6, 10, 10, z.size)
    with pytest.raises(InputError, match="body"):
        subsurface_stresses(ns, body="axle")
    with pytest.raises(InputError, match="depths"):
        subsurface_stresses(ns, depths=[-1e-3])
    with pytest.raises(InputError, match="measure"):
        ss.maximum("rainflow")
    with pytest.raises(InputError, match="uniform grid"):
        stresses_on_grid(np.array([0.0, 1.0, 3.0]), np.array([0.0, 1.0]), np.ones((3, 2)))


def test_patch_of_a_solved_case():
    """A patch of a solved case (its normal and tangential solutions): sigma_zz = -p
    and (sigma_xz, sigma_yz) = minus the tractions on the wheel at the surface."""
    case = rc.case_from_dict({
        "bodies": {"radii": {"wheel_rolling": 0.46, "wheel_lateral": math.inf,
                             "rail_rolling": math.inf, "rail_lateral": 0.3},
                   "normal_force": 1e5, "velocity": 30.0},
        "creepage": {"longitudinal": 1e-3, "lateral": -5e-4, "spin": 0.2},
        "solver": {"normal": "exact", "tangential": "fastsim", "grid": [16, 16]}})
    res = rc.solve(case)
    patch = res.patches[0]
    ss = subsurface_stresses(patch, depths=[0.0, 5e-4])
    np.testing.assert_allclose(ss.sigma[2, :, :, 0], -patch.normal.pressure,
                               atol=1e-9 * patch.normal.pmax)
    np.testing.assert_allclose(ss.sigma[4, :, :, 0], patch.tangential.traction_x,
                               atol=1e-9 * patch.normal.pmax)
    assert patch.normal.model in ss.source and patch.tangential.model in ss.source
