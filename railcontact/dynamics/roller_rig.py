"""A wheelset on a roller rig: its lateral dynamics, its forces under a prescribed
(excited) hunting motion, and its linear stability against the same wheelset on
tangent track.

The rig of seed 002 (Heckmann, Keck, Kaiser and Kurzeck, "The Wheel-Rail-Contact",
Modelica 2014; the DLR roller rig: a 1:5 running gear on rollers of 0.18 m radius,
6 m/s, an excited hunting of 0.5 Hz and 8 mm) is a wheelset held by its primary
suspension to a frame at rest, its two wheels on two rollers turning at the angular
speed Ω_r.  Each roller carries the rail profile (as mounted) revolved about an axis
along y at depth R_r below its crown (:class:`~railcontact.geometry.surfaces.
RollerSurface`); the rollers lie at the track's rail positions (the gauge).

Contact geometry (the cheaper exact-to-first-order geometry, checked against the
3-D roller search in tests/dynamics/test_roller_rig.py).  The wheelset's contact
table over the lateral shift (:class:`~railcontact.dynamics.wheel_rail.
WheelRailTable`, the multi-Hertzian search of the profiles) gives each patch its
contact angle δ, rolling radius r, lateral position y_p and rail-profile point
y_rail.  On a roller:

* the roller's radius at the patch is ρ = R_r − z_rail(y_rail);
* both bodies are of revolution, so the contact normal passes through the wheel's
  axle and the roller's axis.  The wheel's normal meets the axle at
  y_n = y_p + r tan δ; yawed by ψ that point lies at x = −y_n sin ψ, and the
  contact divides the normal between the axle and the roller's axis in the ratio of
  the radii:

      x_c = −y_n sin ψ · ρ / (r + ρ)        (on a rail, ρ → ∞: x_c = −y_n sin ψ)

  "the two wheels leave the apexes of the associated rollers and slightly run
  downhill" (seed 002, section 3.2);
* there the normal leans along the track by x_c cos δ / ρ: the normal force has a
  longitudinal part N x_c cos δ / ρ on the wheel, which with x_c ∝ −y_n ψ on both
  wheels gives a yaw moment ≈ +2 N l² ψ / (r + ρ): a negative (destabilising) yaw
  stiffness that track has not;
* the roller's curvature along the track adds cos δ / (2ρ) to the gap's curvature
  A: a shorter patch, other Hertz semi-axes and Kalker coefficients (recomputed at
  the patch's reference normal force).

Creepages (CONTACT's convention, the rig's surface speed V = Ω_r R_r as reference,
the wheel turning at Ω = V_w / r0 with V_w its circumferential speed at r0):

    ξ = (Ω r − Ω_r ρ) / V + ψ̇ y_p / V
    η = (ψ Ω r / V − (ẏ + ψ̇ x_c) / V) cos δ
    φ = −((Ω + Ω_r) sin δ + ψ̇ cos δ) / V

the roller's own rotation adds Ω_r sin δ to the spin.  On tangent track (``radius``
None: 1/R_r = 0) these are the equations of :mod:`railcontact.dynamics.
equations_of_motion` for the same wheelset (Ω_r ρ → V, no lean, no roller spin).

Forces on the wheel per patch: N (normal), the creep forces (F_x, F_y, M_z) of a
compiled law (:mod:`railcontact.tangential.online`), N cos δ − F_y sin δ = share · Q
for the normal force (two fixed-point passes, as on track); lateral Y = N sin δ +
F_y cos δ, longitudinal X = F_x + N x_c cos δ / ρ, yaw moment −y_p X + x_c Y +
M_z cos δ.  The wheelset (y, ψ) is tied by k_y, c_y, k_ψ, c_ψ to a frame that may
move as y_f = A sin(2π f t), ψ_f = Ψ cos(2π f t) (an actuator through the
suspension); :func:`prescribed_hunting` instead imposes that motion on the wheelset
itself (the seed's controlled running gear) and evaluates the forces.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from numba import njit
from scipy.optimize import brentq

from ..core.errors import InputError
from ..core.hertz_theory import hertz_ellipse
from ..core.materials import STEEL, Material
from ..tangential.kalker import kalker_coefficients
from ..tangential.online import online_law, patch_forces
from .wheel_rail import (F_A, F_B, F_C11, F_C22, F_C23, F_CA, F_CB, F_DELTA, F_R, F_SHARE, F_YP,
                         F_YRAIL, WheelRailTable, lookup)

#: fixed-point passes for the normal force of steep patches (as on track)
NORMAL_PASSES = 2
#: per-patch outputs of :func:`rig_forces`
POUT = ("normal_force", "Fx", "Fy", "Mz", "lateral", "longitudinal", "vertical", "x_contact",
        "xi", "eta", "phi", "roller_radius")
(O_N, O_FX, O_FY, O_MZ, O_Y, O_X, O_Q, O_XC, O_XI, O_ETA, O_PHI, O_RHO) = range(len(POUT))
#: packed parameters of the compiled right-hand side
PAR = ("mass", "yaw_inertia", "k_y", "k_yaw", "c_y", "c_yaw", "wheel_load", "V", "inv_radius",
       "r0", "wheel_speed", "frame_amplitude", "frame_yaw_amplitude", "frame_frequency",
       "reference_load")


def _non_negative(name: str, v) -> None:
    """``v`` a finite number >= 0, else an InputError naming ``name``."""
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not (math.isfinite(v) and v >= 0):
        raise InputError(f"{name} = {v!r}: expected a value >= 0")


def _positive(name, v, lo=0.0, hi=math.inf):
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) \
            or not lo < v <= hi:
        raise InputError(f"{name} = {v!r}: expected a value in ({lo:g}, {hi:g}]")
    return float(v)


@dataclass(frozen=True)
class RollerRig:
    """The rig: rollers of crown radius ``radius`` [m] (None: a tangent track, for
    comparison) turning with the surface speed ``surface_speed`` [m/s] at their
    crown (angular velocity Ω_r = surface_speed / radius); the wheel's circumferential
    speed at its nominal radius ``wheel_speed`` [m/s] (None: the rollers' surface
    speed, rolling without longitudinal creepage when centred).  The rollers' lateral
    spacing is the track's (its gauge and rail profiles)."""

    radius: float | None = 0.18
    surface_speed: float = 6.0
    wheel_speed: float | None = None

    def __post_init__(self):
        if self.radius is not None:
            _positive("roller_rig.radius", self.radius, 0.02, 10.0)
        _positive("roller_rig.surface_speed", self.surface_speed, 0.0, 200.0)
        if self.wheel_speed is not None:
            _positive("roller_rig.wheel_speed", self.wheel_speed, 0.0, 200.0)

    @property
    def angular_velocity(self) -> float:
        """Ω_r [rad/s] of the rollers (0 on track)."""
        return 0.0 if self.radius is None else self.surface_speed / self.radius

    def on_track(self) -> "RollerRig":
        """The same wheelset speeds on tangent track."""
        return RollerRig(None, self.surface_speed, self.wheel_speed)


@dataclass(frozen=True)
class RigWheelset:
    """The wheelset on the rig: ``mass`` [kg], ``yaw_inertia`` [kg m²], its primary
    suspension to the frame: ``k_y`` [N/m], ``k_yaw`` [N m/rad], ``c_y`` [N s/m],
    ``c_yaw`` [N m s/rad], and the vertical ``wheel_load`` [N] per wheel.

    The defaults are the Manchester benchmark wheelset (REFERENCES.md section 10)
    scaled 1:5 with the same stresses (our choice: length 1/5, force 1/25, mass
    1/125, time 1/5, speed 1:1; the wheel load set apart from the masses, since
    gravity does not scale): 1813 kg → 14.5 kg, 1120 kg m² → 0.358 kg m², k_y
    7.768e6 → 1.55e6 N/m, k_ψ 62.78e6 → 5.02e5 N m/rad, 75 kN → 3 kN."""

    mass: float = 14.5
    yaw_inertia: float = 0.358
    k_y: float = 1.55e6
    k_yaw: float = 5.02e5
    c_y: float = 0.0
    c_yaw: float = 0.0
    wheel_load: float = 3.0e3

    def __post_init__(self):
        _positive("wheelset.mass", self.mass, 0.0, 1e5)
        _positive("wheelset.yaw_inertia", self.yaw_inertia, 0.0, 1e5)
        _positive("wheelset.wheel_load", self.wheel_load, 0.0, 1e6)
        for name in ("k_y", "k_yaw", "c_y", "c_yaw"):
            _non_negative(f"wheelset.{name}", getattr(self, name))


@dataclass(frozen=True)
class RigBogie:
    """A bogie on the rig: a frame (``frame_mass`` [kg], ``frame_yaw_inertia``
    [kg m²]) carrying two wheelsets at x = ±``semi_wheelbase`` [m], each on its own
    pair of rollers, through the wheelsets' primary suspension (:class:`RigWheelset`'s
    k_y, k_yaw, c_y, c_yaw, now to the frame); the frame held by the secondary
    suspension (``secondary_k_y`` [N/m], ``secondary_k_yaw`` [N m/rad],
    ``secondary_c_y`` [N s/m], ``secondary_c_yaw`` [N m s/rad]) to the rig at rest.

    The defaults are the Manchester bogie (REFERENCES.md section 10, as
    :meth:`~railcontact.dynamics.vehicle.VehicleModel.from_parameters` assembles it)
    scaled 1:5 as :class:`RigWheelset`: 2615 kg → 20.9 kg, 3067 kg m² → 0.981 kg m²,
    1.28 m → 0.256 m, secondary 2 × 160 kN/m → 6.4e4 N/m, yaw 2 × 160 kN/m × (1 m)² +
    10.5 kN m/rad → 2644 N m/rad, 2 × 32 kN s/m → 2560 N s/m."""

    frame_mass: float = 20.92
    frame_yaw_inertia: float = 0.9814
    semi_wheelbase: float = 0.256
    secondary_k_y: float = 6.4e4
    secondary_k_yaw: float = 2644.0
    secondary_c_y: float = 2560.0
    secondary_c_yaw: float = 0.0

    def __post_init__(self):
        _positive("bogie.frame_mass", self.frame_mass, 0.0, 1e6)
        _positive("bogie.frame_yaw_inertia", self.frame_yaw_inertia, 0.0, 1e6)
        _positive("bogie.semi_wheelbase", self.semi_wheelbase, 0.0, 10.0)
        for name in ("secondary_k_y", "secondary_k_yaw", "secondary_c_y", "secondary_c_yaw"):
            _non_negative(f"bogie.{name}", getattr(self, name))

    def packed(self) -> np.ndarray:
        return np.array([self.frame_mass, self.frame_yaw_inertia, self.semi_wheelbase,
                         self.secondary_k_y, self.secondary_k_yaw, self.secondary_c_y,
                         self.secondary_c_yaw])


@dataclass
class RigTable:
    """The contact table of the wheelset on the rollers (or on track).

    ``data`` (n, 2, 2, 14): the fields of :class:`WheelRailTable` (share, δ, r, y_p,
    a, b, C11, C22, C23, A, B, y_rail, y_wheel) with A, a, b and C_ij those of the
    wheel on the roller, and a 14th field z_rail [m], the rail profile's height at
    the contact (the roller's radius there is R_r − z_rail)."""

    shift: np.ndarray
    data: np.ndarray
    reference_load: float
    nominal_radius: float
    radius: float | None

    @classmethod
    def from_track_table(cls, table: WheelRailTable, track, radius: float | None,
                         material: Material = STEEL) -> "RigTable":
        """The rig's table from the track's (:meth:`WheelRailTable.build` at yaw 0):
        each patch's curvature along the track gains the roller's, cos δ / (2ρ),
        its Hertz semi-axes and Kalker coefficients follow at its reference normal
        force; ``radius`` None keeps the track's."""
        n = table.shift.size
        data = np.zeros((n, 2, 2, table.data.shape[3] + 1))
        data[..., :-1] = table.data
        Es, nu = material.contact_modulus, material.nu
        for j, side in enumerate(("left", "right")):
            rail = track.rail(side)
            for k in range(2):
                yr = table.data[:, j, k, F_YRAIL]
                z = np.asarray(rail.z_at(np.clip(yr, rail.y_min, rail.y_max)), float)
                data[:, j, k, -1] = z
                if radius is None:
                    continue
                for i in range(n):
                    d = data[i, j, k]
                    share, delta = d[F_SHARE], d[F_DELTA]
                    rho = radius - z[i]
                    d[F_CA] += math.cos(delta) / (2.0 * rho)
                    if share <= 0.0:
                        continue
                    hz = hertz_ellipse(d[F_CA], d[F_CB], Es,
                                       force=share * table.reference_load / math.cos(delta))
                    C = kalker_coefficients(hz.a / hz.b, nu)
                    d[F_A], d[F_B] = hz.a, hz.b
                    d[F_C11], d[F_C22], d[F_C23] = C
        return cls(table.shift, np.ascontiguousarray(data), table.reference_load,
                   table.nominal_radius, radius)


@njit(cache=True, nogil=True)
def rig_forces(u, par, shift, tab, law, tp, pout):
    """Contact forces on the wheelset at the state u = (y, ψ, ẏ, ψ̇); fills ``pout``
    (2 sides, 2 slots, len(POUT)) and returns (F_y, M_z) [N, N m] of both rails."""
    y, psi, yd, psid = u[0], u[1], u[2], u[3]
    Q, V, kr, r0, vw = par[6], par[7], par[8], par[9], par[10]
    vals = np.empty((2, 2, tab.shape[3]))
    lookup(shift, tab, y, vals)
    om = vw / r0
    om_r = V * kr
    fy_tot = 0.0
    mz_tot = 0.0
    for sd in range(2):
        sc = (Q / par[14]) ** (1.0 / 3.0)
        for sl in range(2):
            v = vals[sd, sl]
            delta, r, yp = v[F_DELTA], v[F_R], v[F_YP]
            cd, sdl = math.cos(delta), math.sin(delta)
            z = v[13]
            # roller radius over its crown radius, and 1/rho (0 on track)
            rho_ratio = 1.0 - z * kr
            krho = kr / rho_ratio
            yn = yp + r * math.tan(delta)
            xc = -yn * math.sin(psi) / (1.0 + r * krho)
            xi = (om * r - V * rho_ratio) / V + psid * yp / V
            eta = (psi * om * r / V - (yd + psid * xc) / V) * cd
            phi = -((om + om_r) * sdl + psid * cd) / V
            n_tab = v[F_SHARE] * Q / cd
            N = n_tab
            a, b = v[F_A] * sc, v[F_B] * sc
            fx, fy, mz = 0.0, 0.0, 0.0
            if N > 0.0:
                fx, fy, mz = patch_forces(law, tp, N, a, b, v[F_C11], v[F_C22], v[F_C23], xi,
                                          eta, phi, V)
                for _ in range(NORMAL_PASSES):
                    if abs(sdl) < 0.05:
                        break
                    n_new = max(n_tab + fy * sdl / cd, 0.0)
                    if n_new <= 0.0:
                        N = 0.0
                        break
                    s3 = (n_new / N) ** (1.0 / 3.0)
                    N = n_new
                    a, b = a * s3, b * s3
                    fx, fy, mz = patch_forces(law, tp, N, a, b, v[F_C11], v[F_C22], v[F_C23],
                                              xi, eta, phi, V)
            if N <= 0.0:
                N, fx, fy, mz = 0.0, 0.0, 0.0, 0.0
            lat = N * sdl + fy * cd
            lon = fx + N * xc * cd * krho
            o = pout[sd, sl]
            o[0], o[1], o[2], o[3] = N, fx, fy, mz
            o[4], o[5], o[6], o[7] = lat, lon, N * cd - fy * sdl, xc
            o[8], o[9], o[10] = xi, eta, phi
            o[11] = 1.0 / krho if krho > 0.0 else math.inf
            fy_tot += lat
            mz_tot += -yp * lon + xc * lat + mz * cd
    return fy_tot, mz_tot


@njit(cache=True, nogil=True)
def rig_rhs(t, u, par, shift, tab, law, tp, pout):
    """du/dt of the wheelset on the rig, u = (y, ψ, ẏ, ψ̇), its frame moving as
    y_f = A sin(2π f t), ψ_f = Ψ cos(2π f t) (par[11:14])."""
    fy, mz = rig_forces(u, par, shift, tab, law, tp, pout)
    w = 2.0 * math.pi * par[13]
    yf, yfd = par[11] * math.sin(w * t), par[11] * w * math.cos(w * t)
    pf, pfd = par[12] * math.cos(w * t), -par[12] * w * math.sin(w * t)
    du = np.empty(4)
    du[0] = u[2]
    du[1] = u[3]
    du[2] = (fy - par[2] * (u[0] - yf) - par[4] * (u[2] - yfd)) / par[0]
    du[3] = (mz - par[3] * (u[1] - pf) - par[5] * (u[3] - pfd)) / par[1]
    return du


@njit(cache=True, nogil=True)
def bogie_rhs(t, u, par, bp, shift, tab, law, tp, pout):
    """du/dt of a bogie on the rig, u = (q, q') with q = (y_f, ψ_f, y_1, ψ_1, y_2, ψ_2):
    the frame and the leading (x = +a) and trailing (x = −a) wheelsets; ``bp``
    :meth:`RigBogie.packed`; ``pout`` (2 wheelsets, 2, 2, len(POUT))."""
    q = u[:6]
    qd = u[6:]
    F = np.zeros(6)
    uw = np.empty(4)
    for i in range(2):
        x = bp[2] if i == 0 else -bp[2]
        b = 2 + 2 * i
        uw[0], uw[1], uw[2], uw[3] = q[b], q[b + 1], qd[b], qd[b + 1]
        fy, mz = rig_forces(uw, par, shift, tab, law, tp, pout[i])
        f = -(par[2] * (q[b] - q[0] - x * q[1]) + par[4] * (qd[b] - qd[0] - x * qd[1]))
        m = -(par[3] * (q[b + 1] - q[1]) + par[5] * (qd[b + 1] - qd[1]))
        F[b] += fy + f
        F[b + 1] += mz + m
        F[0] -= f
        F[1] -= x * f + m
    F[0] -= bp[3] * q[0] + bp[5] * qd[0]
    F[1] -= bp[4] * q[1] + bp[6] * qd[1]
    du = np.empty(12)
    du[:6] = qd
    du[6], du[7] = F[0] / bp[0], F[1] / bp[1]
    for b in range(2, 6, 2):
        du[6 + b] = F[b] / par[0]
        du[7 + b] = F[b + 1] / par[1]
    return du


@njit(cache=True, nogil=True)
def system_rhs(t, u, par, bp, shift, tab, law, tp, pout):
    """The wheelset's (u of size 4, ``pout`` (1, 2, 2, ...)) or the bogie's (size 12)
    right-hand side."""
    if u.size == 4:
        return rig_rhs(t, u, par, shift, tab, law, tp, pout[0])
    return bogie_rhs(t, u, par, bp, shift, tab, law, tp, pout)


@njit(cache=True, nogil=True)
def rig_rk4(u, steps, par, bp, shift, tab, law, tp, pout, samples):
    """Fixed-step RK4: ``steps`` = (t0, dt, n_steps, every); every ``every`` steps
    the state goes to the next row of ``samples``.  Returns the final state."""
    t0, dt, n, every = steps[0], steps[1], int(steps[2]), int(steps[3])
    k = 0
    for i in range(n):
        t = t0 + i * dt
        k1 = system_rhs(t, u, par, bp, shift, tab, law, tp, pout)
        k2 = system_rhs(t + 0.5 * dt, u + 0.5 * dt * k1, par, bp, shift, tab, law, tp, pout)
        k3 = system_rhs(t + 0.5 * dt, u + 0.5 * dt * k2, par, bp, shift, tab, law, tp, pout)
        k4 = system_rhs(t + dt, u + dt * k3, par, bp, shift, tab, law, tp, pout)
        u = u + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
        if (i + 1) % every == 0 and k < samples.shape[0]:
            samples[k] = u
            k += 1
    return u


@njit(cache=True, nogil=True)
def rig_history(states, par, shift, tab, law, tp, out):
    """Per-patch outputs (``out``: (n, 2, 2, len(POUT))) along wheelset states (n, 4)."""
    for i in range(states.shape[0]):
        rig_forces(states[i], par, shift, tab, law, tp, out[i])


class RigSystem:
    """A wheelset or a bogie on the rig (or on track) with a compiled creep law: the
    packed parameters and the right-hand side.

    Parameters
    ----------
    wheelset : RigWheelset
    rig : RollerRig
    table : RigTable
    tangential : {"linear", "fastsim", "polach"}
        A compiled law (:mod:`railcontact.tangential.online`).
    friction : float
    material : Material
    fastsim_grid : (nx, ny)
    frame : (A [m], Ψ [rad], f [Hz])
        A single wheelset's frame motion (an actuator through the suspension);
        zeros: at rest.
    bogie : RigBogie or None
        Two such wheelsets in a bogie frame (state (y_f, ψ_f, y_1, ψ_1, y_2, ψ_2) and
        their rates).
    """

    def __init__(self, wheelset: RigWheelset, rig: RollerRig, table: RigTable,
                 tangential: str = "fastsim", friction: float = 0.3,
                 material: Material = STEEL, fastsim_grid=(12, 12), frame=(0.0, 0.0, 0.0),
                 bogie: RigBogie | None = None):
        if (rig.radius is None) != (table.radius is None) or \
                (rig.radius is not None and abs(rig.radius - table.radius) > 1e-12):
            raise InputError(f"roller rig radius {rig.radius!r} m and its table's "
                             f"{table.radius!r} m differ: build the table for the rig")
        law = online_law(tangential)
        if law is None:
            raise InputError(f"roller rig: tangential = {tangential!r} has no compiled law; "
                             "expected 'linear', 'fastsim' or 'polach'")
        if not (math.isfinite(friction) and 0 < friction <= 2):
            raise InputError(f"friction coefficient {friction!r}: expected a value in (0, 2]")
        if bogie is not None and any(frame):
            raise InputError("roller rig: a moving frame is a single wheelset's actuator; "
                             "a bogie's frame is a body")
        self.wheelset, self.rig, self.table, self.bogie = wheelset, rig, table, bogie
        self.tangential = tangential
        self.law = law
        nx, ny = (int(v) for v in fastsim_grid)
        self.tp = np.array([friction, material.shear_modulus, nx, ny, 1.0, 1.0, 1.0, 0.0])
        w = wheelset
        vw = rig.surface_speed if rig.wheel_speed is None else rig.wheel_speed
        kr = 0.0 if rig.radius is None else 1.0 / rig.radius
        self.par = np.array([w.mass, w.yaw_inertia, w.k_y, w.k_yaw, w.c_y, w.c_yaw,
                             w.wheel_load, rig.surface_speed, kr, table.nominal_radius, vw,
                             *(float(f) for f in frame), table.reference_load])
        self.bp = np.zeros(7) if bogie is None else bogie.packed()
        self.n_wheelsets = 1 if bogie is None else 2
        self.size = 4 if bogie is None else 12
        self.pout = np.zeros((self.n_wheelsets, 2, 2, len(POUT)))

    @property
    def velocity(self) -> float:
        return self.rig.surface_speed

    @property
    def positions(self) -> np.ndarray:
        """Longitudinal positions [m] of the wheelsets in the frame."""
        if self.bogie is None:
            return np.zeros(1)
        return np.array([self.bogie.semi_wheelbase, -self.bogie.semi_wheelbase])

    def rhs(self, t, u):
        return system_rhs(t, np.asarray(u, float), self.par, self.bp, self.table.shift,
                          self.table.data, self.law, self.tp, self.pout)

    def wheelset_states(self, states) -> np.ndarray:
        """(y, ψ, ẏ, ψ̇) of each wheelset (n, n_wheelsets, 4) from system states."""
        states = np.atleast_2d(np.asarray(states, float))
        if self.bogie is None:
            return states[:, None, :4]
        q, qd = states[:, :6], states[:, 6:]
        return np.stack([np.stack([q[:, b], q[:, b + 1], qd[:, b], qd[:, b + 1]], axis=1)
                         for b in (2, 4)], axis=1)

    def forces(self, states) -> np.ndarray:
        """Per-patch outputs (n, n_wheelsets, 2, 2, len(POUT)) along system states."""
        ws = np.ascontiguousarray(self.wheelset_states(states).reshape(-1, 4))
        out = np.zeros((ws.shape[0], 2, 2, len(POUT)))
        rig_history(ws, self.par, self.table.shift, self.table.data, self.law, self.tp, out)
        return out.reshape(-1, self.n_wheelsets, 2, 2, len(POUT))

    def state_matrix(self, step: float = 1e-7) -> np.ndarray:
        """The state matrix about the centred position (central differences)."""
        n = self.size
        J = np.empty((n, n))
        for c in range(n):
            du = np.zeros(n)
            du[c] = step
            J[:, c] = (self.rhs(0.0, du) - self.rhs(0.0, -du)) / (2 * step)
        return J


def critical_speed(wheelset: RigWheelset, rig: RollerRig, table: RigTable,
                   material: Material = STEEL, v_min: float = 0.5,
                   v_max: float = 200.0, points: int = 40,
                   bogie: RigBogie | None = None) -> float:
    """Linear critical speed [m/s] of the wheelset (or of the ``bogie``) on the rig
    (or on track, with ``rig.radius`` None): the lowest speed (the rollers' surface
    speed, the wheels rolling with it) at which the largest real part of the
    eigenvalues of the state matrix (linear creep law, Kalker's coefficients of the
    table) crosses zero, found on ``points`` speeds spaced geometrically over
    [v_min, v_max] and refined by Brent's method.  An
    :class:`~railcontact.core.errors.InputError` where the wheelset is unstable at
    ``v_min`` or stable up to ``v_max``."""
    def growth(v):
        r = RollerRig(rig.radius, v, None)
        J = RigSystem(wheelset, r, table, "linear", material=material,
                      bogie=bogie).state_matrix()
        return float(np.max(np.linalg.eigvals(J).real))
    vs = np.geomspace(v_min, v_max, points)
    g = np.array([growth(v) for v in vs])
    if g[0] > 0:
        raise InputError(f"critical_speed: already unstable at {v_min} m/s")
    up = np.flatnonzero(g > 0)
    if up.size == 0:
        raise InputError(f"critical_speed: stable up to {v_max} m/s")
    i = int(up[0])
    return brentq(growth, vs[i - 1], vs[i], xtol=1e-6)


def hunting_motion(t, amplitude: float, frequency: float, velocity: float,
                   yaw_amplitude: float | None = None):
    """The excited hunting of seed 002 as a kinematic motion: y = A sin(2π f t),
    ψ = Ψ cos(2π f t) with Ψ = 2π f A / V (the wheelset following its own
    sinusoid of wavelength V / f) unless given; returns (y, ψ, ẏ, ψ̇) (n, 4)."""
    t = np.asarray(t, float)
    w = 2 * math.pi * frequency
    psi = w * amplitude / velocity if yaw_amplitude is None else float(yaw_amplitude)
    return np.stack([amplitude * np.sin(w * t), psi * np.cos(w * t),
                     amplitude * w * np.cos(w * t), -psi * w * np.sin(w * t)], axis=1)


def _dataset(system: RigSystem, t, states, out, attrs):
    import xarray as xr
    ws = system.wheelset_states(states)
    total = out.sum(axis=3)
    tw = ("time", "wheelset")
    tws = ("time", "wheelset", "side")
    data = {
        "lateral_displacement": (tw, ws[..., 0], {"units": "m"}),
        "yaw": (tw, ws[..., 1], {"units": "rad"}),
        "lateral_velocity": (tw, ws[..., 2], {"units": "m/s"}),
        "yaw_rate": (tw, ws[..., 3], {"units": "rad/s"}),
        "normal_force": (tws, total[..., O_N],
                         {"units": "N", "long_name": "normal force of the roller on the wheel "
                                                     "(sum of its patches)"}),
        "vertical_force": (tws, total[..., O_Q], {"units": "N"}),
        "longitudinal_force": (tws, total[..., O_X],
                               {"units": "N", "long_name": "longitudinal force on the wheel: "
                                "creep force and the leaning normal force"}),
        "lateral_force": (tws, total[..., O_Y],
                          {"units": "N", "long_name": "lateral force on the wheel (track "
                                                      "plane), Y"}),
    }
    if system.bogie is not None:
        st = np.atleast_2d(states)
        data["frame_lateral_displacement"] = ("time", st[:, 0], {"units": "m"})
        data["frame_yaw"] = ("time", st[:, 1], {"units": "rad"})
    for name, idx, unit in (("x_contact", O_XC, "m"), ("xi", O_XI, "1"), ("eta", O_ETA, "1"),
                            ("phi", O_PHI, "1/m"), ("patch_normal_force", O_N, "N"),
                            ("roller_radius", O_RHO, "m")):
        data[name] = (tws + ("patch",), out[..., idx], {"units": unit})
    coords = {"time": ("time", t, {"units": "s"}),
              "wheelset": np.arange(1, system.n_wheelsets + 1),
              "wheelset_position": ("wheelset", system.positions, {"units": "m"}),
              "side": ["left", "right"], "patch": ["tread", "flange"]}
    return xr.Dataset(data, coords=coords, attrs=attrs)


def _attrs(system: RigSystem, what: str) -> dict:
    rig = system.rig
    body = "wheelset" if system.bogie is None else "bogie"
    return {"model": f"{body} on {'rollers' if rig.radius else 'tangent track'}",
            "run": what, "velocity_m_s": rig.surface_speed,
            "roller_radius_m": math.nan if rig.radius is None else rig.radius,
            "roller_angular_velocity_rad_s": rig.angular_velocity,
            "tangential": system.tangential, "wheel_load_N": system.wheelset.wheel_load}


def prescribed_hunting(system: RigSystem, amplitude: float = 1.6e-3, frequency: float = 0.5,
                       duration: float = 4.0, sample_rate: float = 200.0,
                       yaw_amplitude: float | None = None):
    """The forces of the wheelset (or of the bogie, its frame moving and carrying its
    wheelsets rigidly: y_i = y_f + x_i ψ_f, ψ_i = ψ_f) moved through the excited
    hunting of seed 002 (:func:`hunting_motion`): an :class:`xarray.Dataset` over
    time with the motion and per wheel the normal, longitudinal and lateral forces of
    the roller on the wheel, per patch the contact's x position and creepages."""
    _positive("excitation.amplitude", amplitude, 0.0, 0.05)
    _positive("excitation.frequency", frequency, 0.0, 100.0)
    _positive("duration", duration, 0.0, 1e4)
    t = np.arange(0.0, duration + 0.5 / sample_rate, 1.0 / sample_rate)
    m = hunting_motion(t, amplitude, frequency, system.velocity, yaw_amplitude)
    if system.bogie is None:
        states = m
    else:
        states = np.zeros((t.size, 12))
        states[:, 0], states[:, 1], states[:, 6], states[:, 7] = m.T
        for b, x in zip((2, 4), system.positions):
            states[:, b] = m[:, 0] + x * m[:, 1]
            states[:, b + 1] = m[:, 1]
            states[:, 6 + b] = m[:, 2] + x * m[:, 3]
            states[:, 7 + b] = m[:, 3]
    t0 = time.perf_counter()
    out = system.forces(states)
    attrs = _attrs(system, "prescribed hunting")
    attrs.update(amplitude_m=amplitude, frequency_Hz=frequency,
                 yaw_amplitude_rad=float(np.max(np.abs(m[:, 1]))),
                 wall_time_s=time.perf_counter() - t0)
    return _dataset(system, t, states, out, attrs)


def simulate_rig(system: RigSystem, duration: float = 2.0, initial_lateral_shift: float = 1e-3,
                 step: float = 1e-4, sample_rate: float = 500.0):
    """Time integration of the wheelset (or bogie) on the rig (fixed-step RK4,
    compiled) from a lateral shift of every wheelset: the dataset of
    :func:`prescribed_hunting`."""
    _positive("duration", duration, 0.0, 1e4)
    every = max(int(round(1.0 / (sample_rate * step))), 1)
    n = int(round(duration / step))
    samples = np.zeros((n // every, system.size))
    u0 = np.zeros(system.size)
    if system.bogie is None:
        u0[0] = initial_lateral_shift
    else:
        u0[2] = u0[4] = initial_lateral_shift
    t0 = time.perf_counter()
    uf = rig_rk4(u0.copy(), np.array([0.0, step, n, every]), system.par, system.bp,
                 system.table.shift, system.table.data, system.law, system.tp, system.pout,
                 samples)
    if not np.all(np.isfinite(uf)):
        raise InputError(f"roller rig run diverged with step {step:g} s: give a smaller "
                         "simulation.step")
    states = np.vstack([u0, samples])
    t = np.arange(states.shape[0]) * every * step
    out = system.forces(states)
    attrs = _attrs(system, "free run")
    attrs.update(initial_lateral_shift_m=initial_lateral_shift, step_s=step,
                 wall_time_s=time.perf_counter() - t0)
    return _dataset(system, t, states, out, attrs)


def plot_rig_forces(ds, path, side: str = "right", wheelset: int | None = None):
    """The seed's figures 11-13: the normal, longitudinal and lateral force of the
    roller on one wheel (default: the rear wheelset's right wheel, as the seed's)
    over time, with the wheelset's motion."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    wheelset = int(ds["wheelset"].values[-1]) if wheelset is None else wheelset
    t = ds["time"].values
    w = ds.sel(wheelset=wheelset)
    fig, axes = plt.subplots(4, 1, figsize=(8, 9), sharex=True)
    axes[0].plot(t, w["lateral_displacement"] * 1e3, color="C0")
    axes[0].set_ylabel("y [mm]", color="C0")
    ax = axes[0].twinx()
    ax.plot(t, w["yaw"] * 1e3, color="C1")
    ax.set_ylabel("yaw [mrad]", color="C1")
    w = w.sel(side=side)
    for axis, name, label in ((axes[1], "normal_force", "normal"),
                              (axes[2], "longitudinal_force", "longitudinal"),
                              (axes[3], "lateral_force", "lateral")):
        axis.plot(t, w[name], color="k", lw=1)
        axis.set_ylabel(f"{label} [N]")
        axis.grid(alpha=0.3)
    axes[3].set_xlabel("time [s]")
    fig.suptitle(f"{ds.attrs['model']}, {ds.attrs['run']}: wheelset {wheelset}, {side} "
                 f"wheel, {ds.attrs['velocity_m_s']:g} m/s")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


# --------------------------------------------------------------- scenario files
_RIG = {"radius", "surface_speed", "wheel_speed"}
_WHEELSET = {"mass", "yaw_inertia", "k_y", "k_yaw", "c_y", "c_yaw", "wheel_load"}
_BOGIE = {"frame_mass", "frame_yaw_inertia", "semi_wheelbase", "secondary_k_y",
          "secondary_k_yaw", "secondary_c_y", "secondary_c_yaw"}
_EXC = {"amplitude", "frequency", "yaw_amplitude"}
_SIM = {"duration", "sample_rate", "tangential", "fastsim_grid", "table_range", "table_step",
        "initial_lateral_shift", "step"}
#: the sections of a roller-rig scenario that are not a case's
RIG_SECTIONS = ("title", "roller_rig", "vehicle", "excitation", "simulation")


@dataclass(frozen=True)
class RigScenario:
    """A roller-rig scenario (``railcontact simulate`` of a file with ``[roller_rig]``),
    validated, SI units: the wheelset and track of the case sections (the rollers
    carry the track's rails at its gauge), ``rig``, ``vehicle`` (the wheelset on
    it), ``bogie`` (None: a single wheelset; else two of them in this frame),
    ``excitation`` ((A [m], f [Hz], Ψ [rad] or None: kinematic) or None: a free
    run from ``initial_lateral_shift``), the run's ``duration`` [s],
    ``sample_rate`` [Hz], ``step`` [s] (free run), the compiled ``tangential`` law,
    ``fastsim_grid`` and the contact table's ``table_range`` and ``table_step``
    [m]."""

    wheelset: object
    track: object
    material: Material
    friction: float
    rig: RollerRig
    vehicle: RigWheelset
    bogie: RigBogie | None = None
    excitation: tuple | None = None
    duration: float = 4.0
    sample_rate: float = 200.0
    step: float = 1e-4
    initial_lateral_shift: float = 1e-3
    tangential: str = "fastsim"
    fastsim_grid: tuple = (12, 12)
    table_range: float = 2.4e-3
    table_step: float = 4e-5
    title: str = ""


def _table(sec: dict, name: str, allowed: set) -> dict:
    from ..core.errors import CaseFileError
    if not isinstance(sec, dict):
        raise CaseFileError(f"[{name}]: expected a table")
    bad = set(sec) - allowed
    if bad:
        raise CaseFileError(f"unknown key(s) {name}.{sorted(bad)}; expected {sorted(allowed)}")
    return sec


def _number(sec, name, key, default, lo, hi):
    from ..core.errors import CaseFileError
    v = sec.get(key, default)
    if v is None:
        return None
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not lo <= v <= hi:
        raise CaseFileError(f"{name}.{key} = {v!r}: expected a value in [{lo:g}, {hi:g}]")
    return float(v)


def rig_scenario_from_sections(sections: dict, bodies) -> RigScenario:
    """The :class:`RigScenario` of a scenario file's ``[roller_rig]``, ``[vehicle]``,
    ``[excitation]`` and ``[simulation]`` tables; ``bodies()`` gives (Wheelset,
    Track, Material, friction) from its case sections.  A
    :class:`~railcontact.core.errors.CaseFileError` names the first wrong key."""
    from ..core.errors import CaseFileError
    rs = _table(sections.get("roller_rig", {}), "roller_rig", _RIG)
    vs = dict(_table(sections.get("vehicle", {}), "vehicle", _WHEELSET | _BOGIE | {"model"}))
    model = vs.pop("model", "wheelset")
    if model not in ("wheelset", "bogie"):
        raise CaseFileError(f"vehicle.model = {model!r}: expected 'wheelset' or 'bogie' on "
                            "the roller rig")
    if model == "wheelset" and set(vs) & _BOGIE:
        raise CaseFileError(f"vehicle keys {sorted(set(vs) & _BOGIE)} belong to model = "
                            "'bogie'")
    sim = _table(sections.get("simulation", {}), "simulation", _SIM)
    try:
        rig = RollerRig(_number(rs, "roller_rig", "radius", 0.18, 0.02, 10.0),
                        _number(rs, "roller_rig", "surface_speed", 6.0, 0.01, 200.0),
                        _number(rs, "roller_rig", "wheel_speed", None, 0.01, 200.0))
        d = RigWheelset()
        veh = RigWheelset(**{k: _number(vs, "vehicle", k, getattr(d, k), 0.0, 1e10)
                             for k in _WHEELSET})
        bogie = None
        if model == "bogie":
            db = RigBogie()
            bogie = RigBogie(**{k: _number(vs, "vehicle", k, getattr(db, k), 0.0, 1e10)
                                for k in _BOGIE})
    except InputError as exc:
        if isinstance(exc, CaseFileError):
            raise
        raise CaseFileError(str(exc)) from None
    exc_ = None
    if "excitation" in sections:
        ex = _table(sections["excitation"], "excitation", _EXC)
        exc_ = (_number(ex, "excitation", "amplitude", 1.6e-3, 1e-6, 0.05),
                _number(ex, "excitation", "frequency", 0.5, 1e-3, 100.0),
                _number(ex, "excitation", "yaw_amplitude", None, 0.0, 0.1))
    tang = sim.get("tangential", "fastsim")
    if tang not in ("linear", "fastsim", "polach"):
        raise CaseFileError(f"simulation.tangential = {tang!r}: expected 'linear', 'fastsim' "
                            "or 'polach' (compiled laws) on the roller rig")
    grid = sim.get("fastsim_grid", [12, 12])
    if not (isinstance(grid, list) and len(grid) == 2 and all(isinstance(g, int) for g in grid)):
        raise CaseFileError(f"simulation.fastsim_grid = {grid!r}: expected [nx, ny] integers")
    rng = _number(sim, "simulation", "table_range", 2.4e-3, 1e-3, 0.03)
    stp = _number(sim, "simulation", "table_step", 4e-5, 1e-5, 1e-3)
    if stp > rng / 4:
        raise CaseFileError(f"simulation.table_step = {stp!r}: expected at most table_range/4")
    wheelset, track, material, friction = bodies()
    return RigScenario(
        wheelset=wheelset, track=track, material=material, friction=float(friction), rig=rig,
        vehicle=veh, bogie=bogie, excitation=exc_,
        duration=_number(sim, "simulation", "duration", 4.0, 1e-3, 1e4),
        sample_rate=_number(sim, "simulation", "sample_rate", 200.0, 1.0, 1e5),
        step=_number(sim, "simulation", "step", 1e-4, 1e-6, 1e-2),
        initial_lateral_shift=_number(sim, "simulation", "initial_lateral_shift", 1e-3,
                                      -0.015, 0.015),
        tangential=tang, fastsim_grid=tuple(grid), table_range=rng, table_step=stp,
        title=str(sections.get("title", "")))


def rig_tables(sc: RigScenario, progress: bool = False):
    """(rig table, track table) of a scenario, from one search of the profiles."""
    tb = WheelRailTable.build(sc.wheelset, sc.track, sc.vehicle.wheel_load, sc.material,
                              sc.table_range, sc.table_step, progress=progress)
    return (RigTable.from_track_table(tb, sc.track, sc.rig.radius, sc.material),
            RigTable.from_track_table(tb, sc.track, None, sc.material))


def run_rig_scenario(sc: RigScenario, out=None, progress: bool = True):
    """Run a roller-rig scenario: the prescribed hunting (``[excitation]``) or a free
    run, and the linear critical speeds of the wheelset on the rig and on tangent
    track (attributes ``critical_speed_m_s`` and ``track_critical_speed_m_s``; NaN
    where none lies in 0.5-200 m/s).  With ``out``: ``simulation.nc`` and
    ``rig_forces.png`` (the seed's figures 11-13: the rear wheelset's right wheel)."""
    from ..core.files import write_netcdf
    t0 = time.perf_counter()
    rig_tab, track_tab = rig_tables(sc, progress)
    system = RigSystem(sc.vehicle, sc.rig, rig_tab, sc.tangential, sc.friction, sc.material,
                       sc.fastsim_grid, bogie=sc.bogie)
    if sc.excitation is not None:
        a, f, psi = sc.excitation
        ds = prescribed_hunting(system, a, f, sc.duration, sc.sample_rate, psi)
    else:
        ds = simulate_rig(system, sc.duration, sc.initial_lateral_shift, sc.step,
                          sc.sample_rate)
    speeds = {}
    for key, rig, tab in (("critical_speed_m_s", sc.rig, rig_tab),
                          ("track_critical_speed_m_s", sc.rig.on_track(), track_tab)):
        try:
            speeds[key] = critical_speed(sc.vehicle, rig, tab, sc.material, bogie=sc.bogie)
        except (InputError, ValueError):
            speeds[key] = math.nan
    ds.attrs.update(title=sc.title, **speeds, wall_time_s=time.perf_counter() - t0)
    if out is not None:
        from pathlib import Path
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        write_netcdf(ds, out / "simulation.nc")
        plot_rig_forces(ds, out / "rig_forces.png")
    return ds
