"""The wheel-rail contact element of a multibody model: the forces and torques that
both rails exert on a wheelset at a given pose and motion, with any registered
normal and tangential model pair.

A multibody tool integrates the wheelset's equations of motion and asks, at every
step, for the contact forces at the wheelset's current pose relative to the track.
:class:`ContactElement` answers that question (Python API); the FMI 3.0
co-simulation FMU of :mod:`railcontact.fmu` wraps it for Modelica,
SIMPACK-like and other FMI tools (``docs/multibody.md``).

Two ways to give the vertical state (``docs/multibody.md``):

* **position** (elastic contact, the multibody use): the wheelset's vertical
  position z and roll φ are inputs.  Each wheel's deepest interpenetration follows
  from the pose (the wheel lowered from where it touches at z = 0,
  :func:`railcontact.geometry.locus.depth_at`), each of its patches is solved with
  the normal model at its own approach and the tangential model at its kinematic
  creepages.  A wheel that does not reach its rail carries nothing.
* **load** (quasi-static): the vertical wheel loads are inputs; the wheelset's
  vertical position and roll are solved so that each wheel's vertical force (normal
  and tangential contact forces of the chosen models) meets its load
  (:func:`railcontact.cases.balance.solve_wheel_rail`), as the dynamics
  layer's tables assume.

Forces and torques are those the rails exert on the wheelset, in the track frame
(x along the track, y to the right, z down; ``docs/conventions.md``), the torques
about the wheelset centre O = (0, y, z − r0).  A patch with normal force F_n,
creep forces F_x, F_y and spin moment M_z (contact-local frame, contact angle δ)
gives

    F = (F_x,  F_y cos δ + F_n sin δ,  F_y sin δ − F_n cos δ)
    T = (P − O) × F + M_z n,   n = (0, −sin δ, cos δ)

with P its reference point.  The creepages are the geometry layer's kinematic
ones (forward speed, pitch velocity, lateral velocity, yaw rate;
:func:`railcontact.geometry.kinematics.kinematic_creepage`) with the roll rate
ω_x and vertical velocity ż of the position mode added: their slip velocity at P
is (0, −ω_x (P − O)_z, ω_x (P − O)_y + ż), so the lateral creepage gains
−(v_y cos δ + v_z sin δ)/V (ω_x has no part in the spin, n_x = 0).
"""

from __future__ import annotations

import dataclasses
import logging
import math
from dataclasses import dataclass, field

import numpy as np

from ..cases.balance import solve_wheel_rail
from ..cases.bodies import build_wheelset_track
from ..cases.case import Case
from ..cases.patches import case_models, coupled_models, solve_case_patches
from ..core.errors import InputError
from ..geometry.locus import depth_at
from ..geometry.search import PatchRules, WheelsetMotion, find_contact
from ..geometry.track import SIDES, WheelsetPose

log = logging.getLogger(__name__)

#: the ways to give the wheelset's vertical state
MODES = ("position", "load")


@dataclass(frozen=True)
class WheelsetState:
    """The wheelset's pose and motion relative to the track (SI units, track frame
    of ``docs/conventions.md``).

    ``lateral_shift`` y [m], ``vertical_position`` z [m] (positive down, 0 with the
    axle r0 above the track plane), ``roll`` φ [rad], ``yaw`` ψ [rad];
    ``lateral_velocity`` ẏ [m/s], ``vertical_velocity`` ż [m/s], ``roll_rate`` φ̇
    [rad/s], ``yaw_rate`` ψ̇ [rad/s]; ``velocity`` V [m/s] the forward speed;
    ``pitch_velocity`` [rad/s] the wheelset's angular velocity about its axle
    (negative rolling forward; None: pure rolling at r0, −V/r0); ``loads`` (left,
    right) [N] the vertical wheel loads of the load mode (then z, φ, ż and φ̇ are
    not used: z and φ are solved)."""

    lateral_shift: float = 0.0
    vertical_position: float = 0.0
    roll: float = 0.0
    yaw: float = 0.0
    lateral_velocity: float = 0.0
    vertical_velocity: float = 0.0
    roll_rate: float = 0.0
    yaw_rate: float = 0.0
    velocity: float = 30.0
    pitch_velocity: float | None = None
    loads: tuple | None = None


@dataclass
class ElementForces:
    """The forces of both rails on the wheelset at one state.

    Attributes
    ----------
    force, torque : ndarray (3,)
        Total force [N] and torque [N m] on the wheelset, track frame, the torque
        about the wheelset centre.
    side_force, side_torque : dict of ndarray (3,)
        The same per wheel (``"left"``, ``"right"``).
    normal_force : dict
        Sum of each wheel's patches' normal forces [N].
    pose : WheelsetPose
        The wheelset's pose: as given (position mode) or with the solved vertical
        position and roll (load mode).
    patches : list of PatchResult
        The loaded patches, left first (each with its geometry, normal and
        tangential solution).
    converged : bool
        Every model's solution (and in load mode the vertical balance) converged.
    """

    force: np.ndarray
    torque: np.ndarray
    side_force: dict
    side_torque: dict
    normal_force: dict
    pose: WheelsetPose
    patches: list = field(default_factory=list, repr=False)
    converged: bool = True

    def to_xarray(self):
        import xarray as xr
        comp = ["x", "y", "z"]
        ds = xr.Dataset(
            {"force": ("component", self.force, {"units": "N"}),
             "torque": ("component", self.torque, {"units": "N m"}),
             "side_force": (("side", "component"),
                            np.array([self.side_force[s] for s in SIDES]), {"units": "N"}),
             "side_torque": (("side", "component"),
                             np.array([self.side_torque[s] for s in SIDES]), {"units": "N m"}),
             "normal_force": ("side", [self.normal_force[s] for s in SIDES], {"units": "N"})},
            coords={"component": comp, "side": list(SIDES)},
            attrs={"lateral_shift_m": self.pose.lateral_shift,
                   "vertical_position_m": self.pose.vertical, "roll_rad": self.pose.roll,
                   "yaw_rad": self.pose.yaw, "converged": int(self.converged),
                   "frame": "track (x along, y right, z down); torques about the wheelset "
                            "centre"})
        return ds


def patch_wrench(result, centre) -> tuple:
    """Force [N] and torque [N m] (about ``centre``, track frame) that one solved
    patch exerts on the wheel (the formulas of the module docstring)."""
    g = result.geometry
    d = g.contact_angle
    c, s = math.cos(d), math.sin(d)
    fn = result.normal.normal_force
    t = result.tangential
    fx, fy, mz = (t.fx, t.fy, t.mz) if t is not None else (0.0, 0.0, 0.0)
    F = np.array([fx, fy * c + fn * s, fy * s - fn * c])
    n = np.array([0.0, -s, c])
    T = np.cross(np.asarray(g.position, dtype=float) - centre, F) + mz * n
    return F, T


def _rates_creepage(geom, centre, roll_rate, vertical_velocity):
    """The patch's creepages with the roll rate and vertical velocity's slip added."""
    if geom.creepage is None or (roll_rate == 0.0 and vertical_velocity == 0.0):
        return geom
    d = np.asarray(geom.position, dtype=float) - centre
    vy = -roll_rate * d[2]
    vz = roll_rate * d[1] + vertical_velocity
    c, s = math.cos(geom.contact_angle), math.sin(geom.contact_angle)
    xi, eta, phi = geom.creepage
    eta = eta - (vy * c + vz * s) / geom.velocity
    return dataclasses.replace(geom, creepage=(xi, eta, phi))


class ContactElement:
    """Wheel-rail contact element: forces of both rails on a wheelset at a state.

    Parameters
    ----------
    case : Case
        A parsed wheel-rail case (:func:`railcontact.load_case`,
        :func:`railcontact.inputs.contact_element` from names) giving the profiles,
        wheelset and track dimensions, material, friction, models and their grids;
        its wheelset state is ignored (the state is :meth:`evaluate`'s).
    normal, tangential : str, optional
        Registered model names overriding the case's ``[solver]``.
    mode : {"position", "load"}
        How the vertical state is given (module docstring).

    Each :meth:`evaluate` is independent of the earlier ones (no warm start), so
    the same state always gives the same forces.
    """

    def __init__(self, case: Case, normal: str | None = None, tangential: str | None = None,
                 mode: str = "position"):
        if not isinstance(case, Case) or case.wheel_rail is None:
            raise InputError("contact element: expected a parsed wheel-rail case ([wheel], "
                             "[rail], [wheelset]) as a Case")
        if mode not in MODES:
            raise InputError(f"contact element mode = {mode!r}: expected one of {MODES}")
        if case.creepage is not None:
            raise InputError("contact element: the case gives [creepage]; the element's "
                             "creepages follow from the wheelset's motion (remove [creepage])")
        self.case, self.mode = case, mode
        (self.normal, self.tangential, self.nmodel, self.tmodel,
         self.kw) = case_models(case, normal, tangential)
        self.coupled = coupled_models(case, self.nmodel, self.tmodel)
        self.bodies = build_wheelset_track(case)
        self.nominal_radius = self.bodies[0].nominal_radius

    def _check(self, st: WheelsetState) -> None:
        for name in ("lateral_shift", "vertical_position", "roll", "yaw", "lateral_velocity",
                     "vertical_velocity", "roll_rate", "yaw_rate", "velocity"):
            v = getattr(st, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise InputError(f"wheelset state {name} = {v!r}: expected a finite number")
        if not st.velocity > 0:
            raise InputError(f"wheelset state velocity = {st.velocity!r} m/s: expected > 0")
        if self.mode == "load":
            q = st.loads
            if (q is None or len(q) != 2
                    or not all(isinstance(v, (int, float)) and v > 0 for v in q)):
                raise InputError(f"wheelset state loads = {q!r}: the load mode expects "
                                 "(left, right) vertical wheel loads > 0 N")

    def evaluate(self, state: WheelsetState) -> ElementForces:
        """Forces and torques of both rails on the wheelset at ``state``."""
        self._check(state)
        if self.mode == "load":
            results, pose, converged = self._by_load(state)
        else:
            results, pose, converged = self._by_position(state)
        centre = np.array([0.0, pose.lateral_shift, pose.vertical - self.nominal_radius])
        side_force = {s: np.zeros(3) for s in SIDES}
        side_torque = {s: np.zeros(3) for s in SIDES}
        normal = dict.fromkeys(SIDES, 0.0)
        for r in results:
            F, T = patch_wrench(r, centre)
            side = r.geometry.side
            side_force[side] += F
            side_torque[side] += T
            normal[side] += r.normal.normal_force
            converged = converged and r.status.converged
        return ElementForces(side_force["left"] + side_force["right"],
                             side_torque["left"] + side_torque["right"], side_force,
                             side_torque, normal, pose, results, bool(converged))

    def _by_position(self, st: WheelsetState):
        ws, tr = self.bodies
        s = self.case.wheel_rail
        y, z, roll, yaw = st.lateral_shift, st.vertical_position, st.roll, st.yaw
        if not (abs(roll) <= 0.1 and abs(yaw) <= 0.1 and abs(y) <= 0.05):
            raise InputError(f"wheelset state (lateral shift {y!r} m, roll {roll!r} rad, yaw "
                             f"{yaw!r} rad): expected |y| <= 0.05 m, |roll|, |yaw| <= 0.1 rad")
        centre = np.array([0.0, y, z - self.nominal_radius])
        results = []
        for side in SIDES:
            depth = depth_at(ws, tr, side, y, z, roll, yaw)
            if not depth > 0:
                continue                  # the wheel is off its rail
            contact = find_contact(ws, tr, y, yaw, material=self.case.material,
                                   motion=WheelsetMotion(st.velocity, st.pitch_velocity,
                                                         st.lateral_velocity, st.yaw_rate),
                                   rules=PatchRules(s.combine_distance,
                                                    s.full_interaction_distance,
                                                    s.turn_distance, s.separation_angle),
                                   interpenetration={side: depth}, roll=roll, side=side)
            contact.patches = [_rates_creepage(p, centre, st.roll_rate, st.vertical_velocity)
                               for p in contact.patches]
            results += solve_case_patches(self.case, contact, self.nmodel, self.tmodel,
                                          self.kw, coupled=self.coupled)
        return results, WheelsetPose(y, z, roll, yaw), True

    def _by_load(self, st: WheelsetState):
        setup = dataclasses.replace(
            self.case.wheel_rail, lateral_shift=float(st.lateral_shift), yaw=float(st.yaw),
            roll=None, side="both", vertical_position=None,
            loads={"left": float(st.loads[0]), "right": float(st.loads[1])},
            velocity=float(st.velocity), lateral_velocity=float(st.lateral_velocity),
            yaw_rate=float(st.yaw_rate),
            pitch_velocity=None if st.pitch_velocity is None else float(st.pitch_velocity))
        case = dataclasses.replace(self.case, wheel_rail=setup)
        results, contact, balance = solve_wheel_rail(case, self.nmodel, self.tmodel, self.kw,
                                                     rtol=case.force_tolerance)
        return results, contact.pose, balance.converged
