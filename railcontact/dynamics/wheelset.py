"""Single wheelset on tangent track: the first model of the dynamics layer.

Lateral displacement y and yaw psi of a wheelset running at constant speed V, with
lateral and yaw stiffness k_y, k_psi to a frame moving with the track (a primary
suspension to a body that follows the track).  Contact geometry comes from the
geometry layer's contact table: the rolling radius difference dr(y), and the
contact-angle difference, which gives the gravitational stiffness.  Creep forces
follow Kalker's linear theory, F = f c (f11 = G c^2 C11 longitudinal, f22 = G c^2 C22
lateral), with the Hertz contact of the central position (Wickens,
*Fundamentals of Rail Vehicle Dynamics*, 2003, ch. 2-4; the classical model):

    m y'' + 2 f22 (y'/V - psi) + k_y y + F_grav(y) = 0
    I psi'' + 2 f11 l (l psi'/V + dr(y) / (2 r0)) + k_psi psi = 0

with l the half distance between the contact points, F_grav = Q (tan d_R(y) - tan
d_L(y)) and Q the wheel load.  For a conical wheelset dr = 2 gamma y and the
kinematic (Klingel) oscillation has the wavelength 2 pi sqrt(r0 l / gamma).

The right-hand side is compiled (Numba); the contact functions are tables.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from ..core.errors import InputError
from ..core.hertz_theory import hertz_ellipse
from ..core.materials import STEEL
from ..tangential.kalker import kalker_coefficients


@dataclass
class WheelsetModel:
    """Parameters of the single-wheelset model (SI units).

    Attributes
    ----------
    mass : kg;  yaw_inertia : kg m^2;  k_y : N/m;  k_psi : N m/rad
    r0 : nominal rolling radius [m];  l : half distance between contact points [m]
    f11, f22 : creep coefficients [N] (Kalker, per wheel)
    wheel_load : vertical load per wheel [N] (gravitational stiffness)
    table_y, table_dr, table_dtan : contact functions over the lateral shift [m]:
        rolling radius difference r_R - r_L [m] and tan(d_R) - tan(d_L) [-]
    """

    mass: float = 1813.0
    yaw_inertia: float = 1120.0
    k_y: float = 0.0
    k_psi: float = 0.0
    r0: float = 0.46
    l: float = 0.75
    f11: float = 1.0e7
    f22: float = 1.0e7
    wheel_load: float = 0.0
    table_y: np.ndarray = None
    table_dr: np.ndarray = None
    table_dtan: np.ndarray = None

    def __post_init__(self):
        for name in ("mass", "yaw_inertia", "r0", "l", "f11", "f22"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise InputError(f"wheelset model {name} = {v!r}: expected a value > 0")
        if self.table_y is None:
            raise InputError("wheelset model: contact table (table_y, table_dr) missing")
        self.table_y = np.ascontiguousarray(self.table_y, dtype=float)
        self.table_dr = np.ascontiguousarray(self.table_dr, dtype=float)
        self.table_dtan = np.ascontiguousarray(
            np.zeros_like(self.table_y) if self.table_dtan is None else self.table_dtan,
            dtype=float)

    @classmethod
    def conical(cls, gamma: float, **kw) -> "WheelsetModel":
        """Wheelset with conical wheels (dr = 2 gamma y, no gravitational stiffness)."""
        y = np.linspace(-0.02, 0.02, 401)
        return cls(table_y=y, table_dr=2 * gamma * y, table_dtan=np.zeros_like(y), **kw)

    @classmethod
    def from_table(cls, table, material=None, friction_free_load: float | None = None, **kw):
        """Wheelset from a :func:`railcontact.geometry.contact_table` (with loads).

        Creep coefficients from the Hertz contact at the central position, with the
        table's vertical force (``vertical_force_N`` attribute).
        """
        mat = material or STEEL
        y = table["lateral_shift"].values
        dr = table["delta_r"].values
        ang = table["contact_angle"].values            # (shift, side)
        dtan = np.tan(ang[:, 1]) - np.tan(ang[:, 0])
        load = float(table.attrs.get("vertical_force_N", 0.0))
        r0 = float(table.attrs["nominal_radius_m"])
        i0 = int(np.argmin(np.abs(y)))
        l = 0.75 + 0.5 * float(table["y_wheel"].values[i0, 1] - table["y_wheel"].values[i0, 0])
        params = dict(r0=r0, l=l, wheel_load=max(load, 0.0))
        if "f11" not in kw and load > 0:
            # curvatures at the centre: A = 1 / (2 r0), B from a typical tread/rail pair
            hz = hertz_ellipse(1 / (2 * r0), kw.pop("lateral_curvature", 1.0 / 0.6),
                               mat.contact_modulus, force=load)
            C11, C22, _ = kalker_coefficients(hz.a / hz.b, mat.nu)
            c2 = hz.a * hz.b
            params.update(f11=mat.shear_modulus * c2 * C11, f22=mat.shear_modulus * c2 * C22)
        params.update(kw)
        return cls(table_y=y, table_dr=dr, table_dtan=dtan, **params)

    def packed(self):
        return np.array([self.mass, self.yaw_inertia, self.k_y, self.k_psi, self.r0, self.l,
                         self.f11, self.f22, self.wheel_load])


@njit(cache=True, nogil=True)
def _rhs(t, u, V, p, ty, tdr, tdtan):
    m, I, ky, kpsi, r0, l, f11, f22, Q = p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8]
    y, yd, psi, psid = u[0], u[1], u[2], u[3]
    dr = np.interp(y, ty, tdr)
    dtan = np.interp(y, ty, tdtan)
    Fy = -2.0 * f22 * (yd / V - psi)
    Mz = -2.0 * f11 * l * (l * psid / V + dr / (2.0 * r0))
    out = np.empty(4)
    out[0] = yd
    out[1] = (Fy - ky * y - Q * dtan) / m
    out[2] = psid
    out[3] = (Mz - kpsi * psi) / I
    return out


def simulate(model: WheelsetModel, velocity: float, duration: float, y0: float = 1e-3,
             psi0: float = 0.0, sample_rate: float = 200.0, rtol: float = 1e-8):
    """Time integration (stiff-capable solver) with the compiled right-hand side.

    Returns an :class:`xarray.Dataset` with ``time`` and the lateral displacement,
    yaw angle, travelled distance and the wheel creep forces.
    """
    import xarray as xr
    if not (velocity > 0 and duration > 0 and sample_rate > 0):
        raise InputError("simulate: velocity, duration and sample_rate must be > 0")
    p = model.packed()
    t_eval = np.arange(0.0, duration + 0.5 / sample_rate, 1.0 / sample_rate)
    sol = solve_ivp(_rhs, (0.0, duration), np.array([y0, 0.0, psi0, 0.0]), method="LSODA",
                    t_eval=t_eval, rtol=rtol, atol=1e-12,
                    args=(velocity, p, model.table_y, model.table_dr, model.table_dtan))
    if not sol.success:
        raise InputError(f"simulate: integration failed: {sol.message}")
    y, yd, psi, psid = sol.y
    dr = np.interp(y, model.table_y, model.table_dr)
    Fy = -2.0 * model.f22 * (yd / velocity - psi)
    Fx = model.f11 * (model.l * psid / velocity + dr / (2 * model.r0))
    return xr.Dataset(
        {"lateral_displacement": ("time", y, {"units": "m"}),
         "yaw": ("time", psi, {"units": "rad"}),
         "distance": ("time", velocity * sol.t, {"units": "m"}),
         "lateral_creep_force": ("time", Fy, {"units": "N", "long_name": "sum of both wheels"}),
         "longitudinal_creep_force": ("time", Fx, {"units": "N",
                                                   "long_name": "right wheel (left opposite)"})},
        coords={"time": ("time", sol.t, {"units": "s"})},
        attrs={"velocity_m_s": velocity, "model": "single wheelset, linear creep"})


def wavelength(ds) -> float:
    """Mean wavelength [m] of the lateral oscillation from its upward zero crossings."""
    y = ds["lateral_displacement"].values
    x = ds["distance"].values
    s = np.flatnonzero((y[:-1] < 0) & (y[1:] >= 0))
    if s.size < 2:
        raise InputError("wavelength: fewer than two oscillation periods in the simulation")
    xc = x[s] - y[s] * (x[s + 1] - x[s]) / (y[s + 1] - y[s])
    return float(np.mean(np.diff(xc)))


def linear_matrix(model: WheelsetModel, velocity: float) -> np.ndarray:
    """State matrix of the model linearised about the centre (conicity from dr'(0))."""
    gamma = 0.5 * float(np.interp(1e-4, model.table_y, model.table_dr)
                        - np.interp(-1e-4, model.table_y, model.table_dr)) / 2e-4
    kg = model.wheel_load * float(np.interp(1e-4, model.table_y, model.table_dtan)
                                  - np.interp(-1e-4, model.table_y, model.table_dtan)) / 2e-4
    m, I, V, l, r0 = model.mass, model.yaw_inertia, velocity, model.l, model.r0
    f11, f22 = model.f11, model.f22
    return np.array([
        [0, 1, 0, 0],
        [-(model.k_y + kg) / m, -2 * f22 / (m * V), 2 * f22 / m, 0],
        [0, 0, 0, 1],
        [-2 * f11 * l * gamma / (r0 * I), 0, -model.k_psi / I, -2 * f11 * l * l / (I * V)]])


def critical_speed(model: WheelsetModel, v_min: float = 1.0, v_max: float = 200.0) -> float:
    """Speed [m/s] at which the largest real part of the eigenvalues crosses zero."""
    def growth(v):
        return float(np.max(np.linalg.eigvals(linear_matrix(model, v)).real))
    if growth(v_min) > 0:
        raise InputError(f"critical_speed: already unstable at {v_min} m/s")
    if growth(v_max) < 0:
        raise InputError(f"critical_speed: stable up to {v_max} m/s")
    return brentq(growth, v_min, v_max, xtol=1e-6)
