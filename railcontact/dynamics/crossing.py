"""Vertical dynamics of a wheel passing a crossing: the load at the transfer.

Where the wheel leaves the wing rail for the nose its vertical path kinks: it
runs down the diverging wing rail (its tread is coned) and is lifted by the
rising nose.  A wheel of unsprung mass m_w at speed V meets that kink with a
vertical velocity the track has to take up: the contact force exceeds the static
load (the 'P1' force, high and short, set by the contact and rail stiffness; the
'P2' force, lower and longer, set by the track under the crossing; Jenkins et
al., Railway Engineering Journal 3, 1974).

Model (one wheel, its share of the wheelset):

* the wheel: mass ``m_w`` with the static load Q (the sprung masses' share and
  the wheel's weight, constant: the primary suspension filters the short event);
* the track under the crossing: the crossing (wing rails and nose one casting)
  and its sleepers as one mass ``m_t`` on the ballast and subgrade, a spring
  ``k_t`` and damper ``c_t`` (Jenkins's one-layer track);
* the contact: the vertical force on every rail as a function of the position s
  along the track and of the wheel's vertical approach to the rails, from a
  table built with the 3-D contact search on the rail surfaces
  (:func:`contact_table`): per s the wheel's touching height z_touch(s) (the
  quasi-static vertical path) and per rail a Hertzian patch, its offset o_i(s)
  (the approach at which it starts), its stiffness C_i(s) and contact angle,
  F_i = C_i ((d - o_i) cos delta_i)^1.5 cos delta_i with d = z_w - z_t - z_touch(s).

Equations (z down, s = s0 + V t):

    m_w z_w'' = Q - sum F_i
    m_t z_t'' = sum F_i - k_t z_t - c_t z_t'

integrated with SciPy's ``solve_ivp`` (explicit Runge-Kutta, the step limited to a
twentieth of the contact's period), from the static equilibrium at the start,
the wheel moving along the path's slope there.  :func:`simulate_crossing` returns an :class:`xarray.Dataset` over time.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field, replace

import numpy as np
from scipy.integrate import solve_ivp

from ..core.errors import ContactNotFoundError, InputError
from ..geometry.surface_search import search
from ..core.hertz_theory import hertz_ellipse
from ..core.materials import Material
from ..cases.surfaces import SurfaceScene

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class CrossingTrack:
    """The track under a crossing, per wheel: its effective mass [kg] (the crossing
    casting's and the sleepers' share), the stiffness [N/m] and damping [N s/m] of
    its support.  Defaults: a cast crossing on concrete sleepers and ballast,
    about as Jenkins's P2 parameters for one wheel (240 kg, 70 MN/m, 60 kN s/m)."""

    mass: float = 240.0
    stiffness: float = 70e6
    damping: float = 60e3

    def __post_init__(self):
        for name, v, lo, hi in (("mass", self.mass, 1.0, 1e5),
                                ("stiffness", self.stiffness, 1e5, 1e11),
                                ("damping", self.damping, 0.0, 1e8)):
            if isinstance(v, bool) or not (isinstance(v, (int, float)) and lo <= v <= hi):
                raise InputError(f"track.{name} = {v!r}: expected a value in [{lo:g}, {hi:g}]")


@dataclass
class VerticalContactTable:
    """Vertical contact of one wheel on the rails along the track (SI units).

    Attributes
    ----------
    s : ndarray (n,)            positions of the wheelset [m]
    z_touch : ndarray (n,)      the wheel's vertical position where it touches [m]
    rails : list of str         the rails
    offset : ndarray (n, r)     vertical approach [m] at which each rail's patch starts
                                (NaN: no patch)
    stiffness : ndarray (n, r)  Hertz's C [N/m^1.5], F_n = C approach^1.5
    cos_delta : ndarray (n, r)  cosine of the patch's contact angle
    depth : float               the vertical approach [m] at which the patches were found
    """

    s: np.ndarray
    z_touch: np.ndarray
    rails: list
    offset: np.ndarray
    stiffness: np.ndarray
    cos_delta: np.ndarray
    depth: float
    _filled: tuple = field(default=None, repr=False)

    def __post_init__(self):
        off = np.where(np.isfinite(self.offset), self.offset, 1.0)   # 1 m: never touched
        C = np.where(np.isfinite(self.stiffness), self.stiffness, 0.0)
        cd = np.where(np.isfinite(self.cos_delta), self.cos_delta, 1.0)
        self._filled = (np.ascontiguousarray(off.T), np.ascontiguousarray(C.T),
                        np.ascontiguousarray(cd.T))

    def forces(self, s, d) -> np.ndarray:
        """Vertical force [N] on each rail (last axis) at positions s with the wheel's
        vertical approach d [m] beyond its touching height (scalars or arrays of one
        shape), linear in s between the table's positions."""
        off, C, cd = self._filled
        s, d = np.broadcast_arrays(np.asarray(s, float), np.asarray(d, float))
        out = np.empty(s.shape + (len(self.rails),))
        for k in range(len(self.rails)):             # the rails (two or three)
            o = np.interp(s, self.s, off[k])
            c = np.interp(s, self.s, C[k])
            cs = np.interp(s, self.s, cd[k])
            pen = np.maximum((d - o) * cs, 0.0)
            out[..., k] = c * pen * np.sqrt(pen) * cs
        return out

    def touch(self, s: float) -> float:
        return float(np.interp(s, self.s, self.z_touch))

    def static_approach(self, s: float, load: float) -> float:
        """The vertical approach [m] at which the wheel carries ``load`` [N] at s."""
        from scipy.optimize import brentq
        f = lambda d: float(self.forces(s, d).sum()) - load          # noqa: E731
        hi = 1e-4
        while f(hi) < 0:
            hi *= 2
            if hi > 0.05:
                raise ContactNotFoundError(f"the table carries no {load:g} N at s = {s:.4f} m")
        return brentq(f, -0.01, hi, xtol=1e-13)


def contact_table(scene: SurfaceScene, positions, material: Material, depth: float = 4e-4,
                  progress: bool = False) -> VerticalContactTable:
    """The vertical contact of a wheel on rail surfaces (``scene``:
    :func:`railcontact.cases.surfaces.build_surface_case` of a case) of ``material``
    at the wheelset positions ``positions`` [m]:
    per position a search with the wheel about ``depth`` [m] below its touching
    height (the patches found there, each with Hertz's stiffness from its
    curvatures and its vertical offset, see the module notes; the touching height
    from the search's smallest vertical gap); per rail the deepest patch."""
    from tqdm.auto import tqdm
    setup = scene
    mat = material
    s = np.asarray(positions, dtype=float)
    if s.ndim != 1 or s.size < 2 or np.any(np.diff(s) <= 0):
        raise InputError("contact_table: expected increasing positions along the track [m]")
    names = [r.name for r in setup.rails]
    n, r = s.size, len(names)
    z_touch = np.full(n, np.nan)
    off, C, cd = (np.full((n, r), np.nan) for _ in range(3))
    Es = mat.contact_modulus
    z_est = None                        # the last position's touching height + depth

    def find(si, z):
        return search(setup.wheel, setup.rails, replace(setup.pose, s=float(si), vertical=z),
                      setup.side, setup.motion, x_range=setup.search_length,
                      inclination=setup.inclination)

    for i, si in enumerate(tqdm(s, desc="contact table", disable=not progress)):
        # one search where the wheel stands about ``depth`` below its touching height
        # (the last position's), again where that missed by more than half of it
        z = setup.pose.vertical if z_est is None else z_est
        c = find(si, z)
        if not math.isfinite(c.min_gap):
            raise ContactNotFoundError(f"no rail under the wheel at s = {si:.4f} m")
        if z_est is None or abs(-c.min_gap - depth) > 0.5 * depth:
            z = z + c.min_gap + depth
            c = find(si, z)
        z_touch[i] = z + c.min_gap
        d_act = -c.min_gap                   # the vertical approach the patches are at
        z_est = z_touch[i] + depth
        for p in c.patches:
            if p.approach <= 0:
                continue
            k = p.rail_index
            cosd = math.cos(p.contact_angle)
            o = d_act - p.approach / cosd
            if np.isfinite(off[i, k]) and o >= off[i, k]:
                continue                                  # keep the rail's deepest patch
            A, B = p.curvatures
            hz = hertz_ellipse(A, B, Es, penetration=1e-4)
            off[i, k], C[i, k], cd[i, k] = o, hz.force / 1e-6, cosd
    return VerticalContactTable(s, z_touch, names, off, C, cd, depth)


def simulate_crossing(table: VerticalContactTable, velocity: float, load: float,
                      wheel_mass: float = 900.0, track: CrossingTrack | None = None,
                      start: float | None = None, end: float | None = None,
                      output_step: float = 2e-5):
    """A wheel crossing the table's stretch of track at ``velocity`` [m/s] under the
    static load ``load`` [N] (see the module notes).

    Parameters
    ----------
    table : VerticalContactTable
    velocity : float         [m/s]
    load : float             static wheel load Q [N] (sprung share and wheel weight)
    wheel_mass : float       unsprung mass per wheel m_w [kg] (half a wheelset's)
    track : CrossingTrack    the track under the crossing
    start, end : float       positions [m] where the run starts and ends (default the
                             table's ends)
    output_step : float      time step [s] of the returned histories

    Returns
    -------
    xarray.Dataset over ``time`` [s]: ``s``, ``z_wheel``, ``z_track`` [m], ``approach``
    [m], ``force`` [N] on each rail (dims time x rail), ``total_force`` [N],
    ``load_factor`` (total / Q); attributes: the peak force and where it occurs.
    """
    import xarray as xr
    track = track or CrossingTrack()
    for name, v, lo, hi in (("velocity", velocity, 0.01, 150.0), ("load", load, 1.0, 1e6),
                            ("wheel_mass", wheel_mass, 1.0, 1e4)):
        if isinstance(v, bool) or not (isinstance(v, (int, float)) and lo <= v <= hi):
            raise InputError(f"{name} = {v!r}: expected a value in [{lo:g}, {hi:g}]")
    s0 = float(table.s[0] if start is None else start)
    s1 = float(table.s[-1] if end is None else end)
    if not (table.s[0] <= s0 < s1 <= table.s[-1]):
        raise InputError(f"crossing run from {s0} to {s1} m: expected a stretch within the "
                         f"table's [{table.s[0]:.4f}, {table.s[-1]:.4f}] m")
    V = float(velocity)
    m_w, m_t, k_t, c_t = float(wheel_mass), track.mass, track.stiffness, track.damping
    # static equilibrium at the start: the track carries Q + its own weight share
    d0 = table.static_approach(s0, load)
    zt0 = load / k_t                                    # the load's deflection of the track
    zw0 = zt0 + table.touch(s0) + d0
    # the contact's period at the static load (a stiffness 1.5 Q / d): the step limit
    k_c = 1.5 * load / max(d0, 1e-7)
    period = 2 * math.pi / math.sqrt(k_c * (1 / m_w + 1 / m_t))
    T = (s1 - s0) / V

    def rhs(t, y):
        zw, vw, zt, vt = y
        s = s0 + V * t
        d = zw - zt - table.touch(s)
        F = table.forces(s, d).sum()
        return [vw, (load - F) / m_w, vt, (F - k_t * zt - c_t * vt) / m_t]

    # the wheel follows the path's slope at the start: its vertical velocity V dz/ds
    vw0 = V * float(np.interp(s0, table.s, np.gradient(table.z_touch, table.s)))
    sol = solve_ivp(rhs, (0.0, T), [zw0, vw0, zt0, 0.0], method="RK45",
                    max_step=period / 20, rtol=1e-8, atol=1e-12, dense_output=True)
    if not sol.success:
        raise InputError(f"crossing run: the integration failed: {sol.message}")
    t = np.arange(0.0, T, output_step)
    zw, vw, zt, vt = sol.sol(t)
    s = s0 + V * t
    touch = np.interp(s, table.s, table.z_touch)
    d = zw - zt - touch
    forces = table.forces(s, d)
    total = forces.sum(axis=1)
    i = int(np.argmax(total))
    ds = xr.Dataset(
        {"s": ("time", s, {"units": "m", "long_name": "wheelset position along the track"}),
         "z_wheel": ("time", zw, {"units": "m", "long_name": "wheel vertical position (down)"}),
         "z_track": ("time", zt, {"units": "m", "long_name": "track deflection (down)"}),
         "z_touch": ("time", touch, {"units": "m", "long_name":
                                     "quasi-static touching height of the wheel"}),
         "approach": ("time", d, {"units": "m", "long_name": "vertical approach of the wheel"}),
         "force": (("time", "rail"), forces, {"units": "N", "long_name":
                                               "vertical contact force on each rail"}),
         "total_force": ("time", total, {"units": "N", "long_name": "vertical contact force"}),
         "support_force": ("time", k_t * zt + c_t * vt + (load - k_t * zt0),
                           {"units": "N", "long_name": "force of the track's support "
                            "(ballast) beyond the track's weight"}),
         "load_factor": ("time", total / load, {"units": "1", "long_name": "force / Q"})},
        coords={"time": ("time", t, {"units": "s"}), "rail": ("rail", list(table.rails))},
        attrs={"velocity_m_s": V, "load_N": float(load), "wheel_mass_kg": m_w,
               "track_mass_kg": m_t, "track_stiffness_N_m": k_t, "track_damping_N_s_m": c_t,
               "peak_force_N": float(total[i]), "peak_position_m": float(s[i]),
               "peak_load_factor": float(total[i] / load), "evaluations": int(sol.nfev)})
    return ds


def jenkins_p2(load: float, velocity: float, dip_angle: float, wheel_mass: float,
               track: CrossingTrack) -> float:
    """Jenkins's P2 force [N] at a dip of total angle ``dip_angle`` [rad] (2 alpha):
    P2 = Q + 2 alpha V sqrt(m_u / (m_u + m_t)) (1 - pi c_t / (4 sqrt(k_t (m_u + m_t))))
    sqrt(k_t m_u)  (Jenkins et al. 1974; the track as one mass on a spring and
    damper, the contact rigid)."""
    m_u, m_t, k_t, c_t = wheel_mass, track.mass, track.stiffness, track.damping
    return load + dip_angle * velocity * math.sqrt(m_u / (m_u + m_t)) * (
        1.0 - math.pi * c_t / (4.0 * math.sqrt(k_t * (m_u + m_t)))) * math.sqrt(k_t * m_u)
