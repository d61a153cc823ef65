"""Railway vehicle models in track-following coordinates, with a compiled
right-hand side.

Every body has the lateral displacement y [m], yaw ψ [rad] and roll φ [rad] (roll a
degree of freedom only where the body says so) relative to the design track at
its own position s = s0 + V t + x_body, in the canted track plane (conventions of
docs/conventions.md: y to the right, z down, yaw positive turning the front to
the right).  The formulation is the classical linearised one of lateral vehicle
dynamics (Wickens, *Fundamentals of Rail Vehicle Dynamics*, 2003; Iwnicki (ed.),
*Handbook of Railway Vehicle Dynamics*, 2006, ch. 9):

    m (ÿ + a_u) = ΣF_y,    I_z (ψ̈ + V² κ') = ΣM_z,    I_x φ̈ = ΣM_x + m g h_r φ

with the uncompensated lateral acceleration a_u = V² κ cos φ_t − g sin φ_t of the
track frame (curvature κ, cant angle φ_t) and the yaw acceleration V² dκ/ds of the
track tangent.  Suspension elements join two bodies (or a body and the track) at
longitudinal offsets a_i, a_j; their lateral deflection and yaw difference,
compared in the track frame at the attachment point, include the chord and
tangent-angle terms of a curve:

    Δy = (y_i + a_i ψ_i − d_i φ_i − κ_i a_i²/2) − (y_j + a_j ψ_j − d_j φ_j − κ_j a_j²/2)
    Δψ = (ψ_i − κ_i a_i) − (ψ_j − κ_j a_j)

(d: depth of the attachment below the body's centre of gravity).  Elements carry a
lateral spring and damper, a non-linear symmetric bump stop table, yaw stiffness
and damping (longitudinal springs and yaw dampers at their lateral spacing b give
2 k b²), and roll stiffness and damping (vertical springs, anti-roll bar).

Wheelsets have no roll or vertical degree of freedom: the contact table of the
geometry layer gives, at the wheelset's shift relative to the rails (alignment
irregularity removed), the patches with their contact angle, rolling radius,
position and Hertz data.  The wheel loads are quasi-static: the supported mass M
and first moment H = Σ m h of each wheelset give Q = M (g cos φ_t + V² κ sin φ_t)
and the load transfer ΔQ = H a_u / (2 b0) to the outer wheel (b0 = 0.75 m).  The
creepages of each patch (CONTACT's convention; Ω = V/r0, ψ̇_abs = ψ̇ + V κ):

    ξ = r/r0 − 1 + ψ̇_abs y_p / V
    η = ((ψ − y_a') r/r0 − (ẏ/V − y_a')) cos δ
    φ = −(Ω sin δ + ψ̇_abs cos δ) / V

The normal force of a patch meets its share Q_k of the wheel load together with
the creep force's vertical part, N cos δ − F_y sin δ = Q_k (two fixed-point passes
from the table's N; this matters on the flange).  The forces of the rail on the
wheel act in the track plane as
Y = N sin δ + F_y cos δ (lateral), yaw moment −y_p F_x + M_z cos δ.  A cross-level
irregularity c adds Q_total c to the wheelset's lateral force.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numba import njit

from ..errors import InputError
from .wheel_rail import F_A, F_B, F_C11, F_C22, F_C23, F_CA, F_CB, F_DELTA, F_R, F_SHARE, \
    F_YP, F_YRAIL, F_YWHEEL, lookup, patch_forces

G_ACC = 9.81
#: half the lateral distance of the wheel loads for the load transfer [m]
LOAD_BASE = 0.75
#: per-patch inputs and outputs kept by the right-hand side
PIN = ("normal_force", "a", "b", "C11", "C22", "C23", "xi", "eta", "phi", "contact_angle",
       "y_contact", "A", "B", "y_rail", "velocity", "y_wheel")
POUT = ("Fx", "Fy", "Mz", "Y", "Q", "Tgamma")
WOUT = ("relative_shift", "outside_table", "load_left", "load_right")
#: fixed-point passes for the normal force of steep patches (creep force's vertical part)
NORMAL_PASSES = 2

#: Manchester benchmark vehicle 1 (REFERENCES.md §10; Iwnicki 1998 via secondary
#: sources).  Primary cx, cy are unverified there; no yaw damper is given.
MANCHESTER = {
    "carbody_mass": 32000.0, "carbody_yaw_inertia": 1.97e6, "carbody_roll_inertia": 56800.0,
    "carbody_height": 1.8,
    "frame_mass": 2615.0, "frame_yaw_inertia": 3067.0, "frame_height": 0.6,
    "wheelset_mass": 1813.0, "wheelset_yaw_inertia": 1120.0, "wheel_radius": 0.46,
    "semi_wheelbase": 1.28, "bogie_semi_distance": 9.5,
    "primary_spacing": 1.0, "secondary_spacing": 1.0, "secondary_height": 0.8275,
    "bump_stop_height": 0.65,
    "primary_kx": 31.391e6, "primary_ky": 3.884e6, "primary_cx": 15e3, "primary_cy": 2e3,
    "secondary_kx": 160e3, "secondary_ky": 160e3, "secondary_kz": 430e3,
    "secondary_cy": 32e3, "secondary_cz": 20e3, "secondary_bending": 10.5e3,
    "anti_roll_bar": 940e3, "yaw_damper": 0.0, "yaw_damper_spacing": 1.25,
    "bump_stop_deflection": [0.0, 0.025, 0.030, 0.035, 0.040, 0.045, 0.050, 0.055, 0.060,
                             0.065],
    "bump_stop_force": [0.0, 0.0, 600.0, 1760.0, 3730.0, 6870.0, 11580.0, 17170.0, 29200.0,
                        230000.0],
}
PRESETS = {"manchester": MANCHESTER}


@dataclass
class Body:
    """A rigid body: mass [kg], yaw and roll inertia [kg m²], longitudinal position x
    [m] in the vehicle (+ forward), centre of gravity height [m] above the rails, and
    ``roll_arm`` [m]: height of the centre of gravity above the roll support (gravity
    pendulum term)."""

    name: str
    kind: str
    mass: float
    yaw_inertia: float
    roll_inertia: float = 0.0
    x: float = 0.0
    height: float = 0.0
    roll: bool = False
    roll_arm: float = 0.0


@dataclass
class Element:
    """Suspension element between body ``i`` and body ``j`` (-1: the track).

    Stiffness and damping: lateral k_y [N/m], c_y [N s/m]; yaw k_yaw [N m/rad],
    c_yaw [N m s/rad]; roll k_roll, c_roll.  ``bump`` = (deflection [m], force [N])
    table of a symmetric non-linear lateral stop."""

    name: str
    i: int
    j: int
    a_i: float = 0.0
    a_j: float = 0.0
    d_i: float = 0.0
    d_j: float = 0.0
    k_y: float = 0.0
    c_y: float = 0.0
    k_yaw: float = 0.0
    c_yaw: float = 0.0
    k_roll: float = 0.0
    c_roll: float = 0.0
    bump: tuple | None = None


@dataclass
class VehicleModel:
    """Bodies, suspension elements and the wheelsets' load paths.

    ``wheelsets`` lists (body index, supported mass [kg], supported first moment
    Σ m h [kg m]) front to back.  Build with :meth:`single_wheelset`, :meth:`bogie`,
    :meth:`vehicle` or :meth:`from_parameters`.
    """

    name: str
    bodies: list
    elements: list
    wheelsets: list
    parameters: dict = field(default_factory=dict)

    def __post_init__(self):
        nb = len(self.bodies)
        for b in self.bodies:
            for key in ("mass", "yaw_inertia"):
                v = getattr(b, key)
                if not (math.isfinite(v) and v > 0):
                    raise InputError(f"vehicle body {b.name}.{key} = {v!r}: expected > 0")
            if b.roll and not b.roll_inertia > 0:
                raise InputError(f"vehicle body {b.name}: roll needs roll_inertia > 0")
        for e in self.elements:
            if not (0 <= e.i < nb and -1 <= e.j < nb and e.i != e.j):
                raise InputError(f"suspension element {e.name}: bodies {e.i}, {e.j} out of range")
            for key in ("k_y", "c_y", "k_yaw", "c_yaw", "k_roll", "c_roll"):
                v = getattr(e, key)
                if not (math.isfinite(v) and v >= 0):
                    raise InputError(f"suspension element {e.name}.{key} = {v!r}: expected >= 0")
        if not self.wheelsets:
            raise InputError("vehicle model: no wheelset")

    @property
    def dofs(self) -> int:
        return 3 * len(self.bodies)

    @property
    def total_mass(self) -> float:
        return sum(b.mass for b in self.bodies)

    def body_index(self, kind: str) -> list:
        return [i for i, b in enumerate(self.bodies) if b.kind == kind]

    # ------------------------------------------------------------ constructors
    @classmethod
    def single_wheelset(cls, mass=1813.0, yaw_inertia=1120.0, k_y=7.768e6, k_yaw=62.78e6,
                        c_y=0.0, c_yaw=0.0, wheel_load=75e3, load_height=0.0):
        """One wheelset tied by springs to a frame that follows the track."""
        bodies = [Body("wheelset", "wheelset", mass, yaw_inertia)]
        el = [Element("primary", 0, -1, k_y=k_y, c_y=c_y, k_yaw=k_yaw, c_yaw=c_yaw)]
        M = 2 * wheel_load / G_ACC
        return cls("wheelset", bodies, el, [(0, M, M * load_height)],
                   {"wheel_load": wheel_load})

    @classmethod
    def from_parameters(cls, model: str = "vehicle", parameters: dict | None = None):
        """``model`` in {"wheelset", "bogie", "vehicle"} from a parameter dict
        (missing keys from the Manchester preset)."""
        p = dict(MANCHESTER)
        for k, v in (parameters or {}).items():
            if k not in MANCHESTER:
                raise InputError(f"vehicle parameter {k!r} unknown; expected one of "
                                 f"{sorted(MANCHESTER)}")
            p[k] = v
        for k, v in p.items():
            vals = np.atleast_1d(np.asarray(v, dtype=float))
            if not np.all(np.isfinite(vals)) or np.any(vals < 0):
                raise InputError(f"vehicle parameter {k} = {v!r}: expected values >= 0")
        if model == "vehicle":
            return cls._vehicle(p)
        if model == "bogie":
            return cls._bogie(p)
        if model == "wheelset":
            b = p["primary_spacing"]
            load = (p["carbody_mass"] / 4 + p["frame_mass"] / 2 + p["wheelset_mass"]) \
                * G_ACC / 2
            return cls.single_wheelset(p["wheelset_mass"], p["wheelset_yaw_inertia"],
                                       2 * p["primary_ky"], 2 * p["primary_kx"] * b * b,
                                       2 * p["primary_cy"], 2 * p["primary_cx"] * b * b, load)
        raise InputError(f"vehicle model {model!r}: expected 'wheelset', 'bogie' or 'vehicle'")

    @classmethod
    def bogie(cls, parameters=None):
        return cls.from_parameters("bogie", parameters)

    @classmethod
    def vehicle(cls, parameters=None):
        return cls.from_parameters("vehicle", parameters)

    @staticmethod
    def _primary(p, frame, ws, a):
        b = p["primary_spacing"]
        return Element(f"primary {ws}", ws, frame, 0.0, a, 0.0, 0.0, 2 * p["primary_ky"],
                       2 * p["primary_cy"], 2 * p["primary_kx"] * b * b,
                       2 * p["primary_cx"] * b * b)

    @classmethod
    def _bogie(cls, p):
        lw = p["semi_wheelbase"]
        bodies = [Body("frame", "frame", p["frame_mass"], p["frame_yaw_inertia"], x=0.0,
                       height=p["frame_height"]),
                  Body("wheelset 1", "wheelset", p["wheelset_mass"], p["wheelset_yaw_inertia"],
                       x=lw, height=p["wheel_radius"]),
                  Body("wheelset 2", "wheelset", p["wheelset_mass"], p["wheelset_yaw_inertia"],
                       x=-lw, height=p["wheel_radius"])]
        bs = p["secondary_spacing"]
        yd = p["yaw_damper_spacing"]
        el = [cls._primary(p, 0, 1, lw), cls._primary(p, 0, 2, -lw),
              Element("secondary", 0, -1, k_y=2 * p["secondary_ky"], c_y=2 * p["secondary_cy"],
                      k_yaw=2 * p["secondary_kx"] * bs * bs + p["secondary_bending"],
                      c_yaw=2 * p["yaw_damper"] * yd * yd)]
        half_body = p["carbody_mass"] / 2
        M = p["wheelset_mass"] + (p["frame_mass"] + half_body) / 2
        H = (p["wheelset_mass"] * p["wheel_radius"] + p["frame_mass"] / 2 * p["frame_height"]
             + half_body / 2 * p["carbody_height"])
        return cls("bogie", bodies, el, [(1, M, H), (2, M, H)], p)

    @classmethod
    def _vehicle(cls, p):
        lw, lb = p["semi_wheelbase"], p["bogie_semi_distance"]
        hc = p["carbody_height"]
        bodies = [Body("carbody", "carbody", p["carbody_mass"], p["carbody_yaw_inertia"],
                       p["carbody_roll_inertia"], 0.0, hc, roll=True,
                       roll_arm=hc - p["secondary_height"])]
        el = []
        wsets = []
        M = p["wheelset_mass"] + p["frame_mass"] / 2 + p["carbody_mass"] / 4
        H = (p["wheelset_mass"] * p["wheel_radius"] + p["frame_mass"] / 2 * p["frame_height"]
             + p["carbody_mass"] / 4 * hc)
        bs, yd = p["secondary_spacing"], p["yaw_damper_spacing"]
        bump = (np.asarray(p["bump_stop_deflection"], float),
                np.asarray(p["bump_stop_force"], float))
        for k, xb in enumerate((lb, -lb)):
            f = len(bodies)
            bodies.append(Body(f"frame {k + 1}", "frame", p["frame_mass"],
                               p["frame_yaw_inertia"], x=xb, height=p["frame_height"]))
            for m, xw in enumerate((xb + lw, xb - lw)):
                w = len(bodies)
                bodies.append(Body(f"wheelset {2 * k + m + 1}", "wheelset", p["wheelset_mass"],
                                   p["wheelset_yaw_inertia"], x=xw, height=p["wheel_radius"]))
                el.append(cls._primary(p, f, w, xw - xb))
                wsets.append((w, M, H))
            el.append(Element(f"secondary {k + 1}", 0, f, xb, 0.0,
                              hc - p["secondary_height"], 0.0,
                              2 * p["secondary_ky"], 2 * p["secondary_cy"],
                              2 * p["secondary_kx"] * bs * bs + p["secondary_bending"],
                              2 * p["yaw_damper"] * yd * yd,
                              2 * p["secondary_kz"] * bs * bs + p["anti_roll_bar"],
                              2 * p["secondary_cz"] * bs * bs))
            el.append(Element(f"bump stop {k + 1}", 0, f, xb, 0.0,
                              hc - p["bump_stop_height"], 0.0, bump=bump))
        return cls("vehicle", bodies, el, wsets, p)

    # ------------------------------------------------------------ packing
    def packed(self):
        """Arrays for the compiled right-hand side."""
        bodies = np.array([[b.mass, b.yaw_inertia, b.roll_inertia, b.x, b.height,
                            1.0 if b.roll else 0.0, b.roll_arm] for b in self.bodies])
        tables = [e.bump for e in self.elements if e.bump is not None]
        npts = max([len(t[0]) for t in tables], default=2)
        bx = np.zeros((max(len(tables), 1), npts))
        bf = np.zeros_like(bx)
        elems = []
        it = 0
        for e in self.elements:
            idx = -1
            if e.bump is not None:
                d, f = (np.asarray(v, dtype=float) for v in e.bump)
                if d.size != f.size or d.size < 2 or np.any(np.diff(d) <= 0) or d[0] != 0:
                    raise InputError(f"bump stop of {e.name}: expected a table of deflections "
                                     "from 0, increasing, with one force each")
                bx[it, :] = d[-1] + np.arange(npts) * 1e-9       # pad with the last point
                bf[it, :] = f[-1]
                bx[it, :d.size], bf[it, :d.size] = d, f
                idx, it = it, it + 1
            elems.append([e.i, e.j, e.a_i, e.a_j, e.d_i, e.d_j, e.k_y, e.c_y, e.k_yaw, e.c_yaw,
                          e.k_roll, e.c_roll, idx])
        wsets = np.array([[w[0], w[1], w[2]] for w in self.wheelsets], dtype=float)
        return (bodies, np.array(elems, dtype=float).reshape(-1, 13), bx, bf, wsets)


@njit(cache=True, nogil=True)
def _bump_force(x, bx, bf):
    d = abs(x)
    n = bx.size
    if d <= bx[0]:
        return 0.0
    if d >= bx[n - 1]:
        f = bf[n - 1] + (d - bx[n - 1]) * (bf[n - 1] - bf[n - 2]) / (bx[n - 1] - bx[n - 2])
    else:
        f = np.interp(d, bx, bf)
    return f if x > 0 else -f


@njit(cache=True, nogil=True)
def _track_at(s, ks, kk, kc):
    """Curvature, its slope d(kappa)/ds and the cant angle at s."""
    n = ks.size
    if s <= ks[0]:
        return kk[0], 0.0, kc[0]
    if s >= ks[n - 1]:
        return kk[n - 1], 0.0, kc[n - 1]
    i = np.searchsorted(ks, s) - 1
    h = ks[i + 1] - ks[i]
    w = (s - ks[i]) / h
    slope = (kk[i + 1] - kk[i]) / h
    return kk[i] + w * (kk[i + 1] - kk[i]), slope, kc[i] + w * (kc[i + 1] - kc[i])


@njit(cache=True, nogil=True)
def rhs_core(t, u, V, s0, bodies, elems, bx, bf, wsets, ks, kk, kc, irs, ira, irc, shift,
             tables, qrefs, r0, law, tp, mode, fext, pin, pout, wout):
    """Time derivative of the state u = (q, q') with q = (y, ψ, φ) per body.

    ``tables`` (nw, n, 2, 2, nfields): each wheelset's contact table on the common
    shift grid ``shift``, with its reference loads ``qrefs`` (nw,) [N].

    ``mode`` 0: creep forces from the compiled law ``law``; 1: from ``fext``
    (nw, 2, 2, 4: F_x, F_y, M_z and the normal force, 0 for the table's) given by
    the caller.  Fills the per-patch inputs ``pin``, outputs
    ``pout`` and per-wheelset values ``wout`` for output and for ``mode`` 1."""
    nb = bodies.shape[0]
    nd = 3 * nb
    q = u[:nd]
    qd = u[nd:]
    F = np.zeros(nd)
    kap = np.empty(nb)
    dkap = np.empty(nb)
    for b in range(nb):
        s = s0 + V * t + bodies[b, 3]
        k, dk, ct = _track_at(s, ks, kk, kc)
        kap[b] = k
        dkap[b] = dk
        au = V * V * k * math.cos(ct) - G_ACC * math.sin(ct)
        F[3 * b] -= bodies[b, 0] * au
        F[3 * b + 1] -= bodies[b, 1] * V * V * dk
        if bodies[b, 5] > 0:
            F[3 * b + 2] += bodies[b, 0] * G_ACC * bodies[b, 6] * q[3 * b + 2]
    for e in range(elems.shape[0]):
        i = int(elems[e, 0])
        j = int(elems[e, 1])
        ai, aj, di, dj = elems[e, 2], elems[e, 3], elems[e, 4], elems[e, 5]
        dy = q[3 * i] + ai * q[3 * i + 1] - di * q[3 * i + 2] - 0.5 * kap[i] * ai * ai
        dyd = qd[3 * i] + ai * qd[3 * i + 1] - di * qd[3 * i + 2] - 0.5 * V * dkap[i] * ai * ai
        dp = q[3 * i + 1] - kap[i] * ai
        dpd = qd[3 * i + 1] - V * dkap[i] * ai
        dr = q[3 * i + 2]
        drd = qd[3 * i + 2]
        if j >= 0:
            dy -= q[3 * j] + aj * q[3 * j + 1] - dj * q[3 * j + 2] - 0.5 * kap[j] * aj * aj
            dyd -= qd[3 * j] + aj * qd[3 * j + 1] - dj * qd[3 * j + 2] \
                - 0.5 * V * dkap[j] * aj * aj
            dp -= q[3 * j + 1] - kap[j] * aj
            dpd -= qd[3 * j + 1] - V * dkap[j] * aj
            dr -= q[3 * j + 2]
            drd -= qd[3 * j + 2]
        f = -(elems[e, 6] * dy + elems[e, 7] * dyd)
        ib = int(elems[e, 12])
        if ib >= 0:
            f -= _bump_force(dy, bx[ib], bf[ib])
        m = -(elems[e, 8] * dp + elems[e, 9] * dpd)
        mr = -(elems[e, 10] * dr + elems[e, 11] * drd)
        F[3 * i] += f
        F[3 * i + 1] += ai * f + m
        F[3 * i + 2] += -di * f + mr
        if j >= 0:
            F[3 * j] -= f
            F[3 * j + 1] -= aj * f + m
            F[3 * j + 2] -= -dj * f + mr
    vals = np.empty((2, 2, tables.shape[4]))
    hs = 0.5 * (irs[1] - irs[0])
    for w in range(wsets.shape[0]):
        b = int(wsets[w, 0])
        s = s0 + V * t + bodies[b, 3]
        k, dk, ct = _track_at(s, ks, kk, kc)
        ya = np.interp(s, irs, ira)
        yad = (np.interp(s + hs, irs, ira) - np.interp(s - hs, irs, ira)) / (2 * hs)
        cl = np.interp(s, irs, irc)
        y, psi, yd, psid = q[3 * b], q[3 * b + 1], qd[3 * b], qd[3 * b + 1]
        yrel = y - ya
        outside = lookup(shift, tables[w], yrel, vals)
        Qt = wsets[w, 1] * (G_ACC * math.cos(ct) + V * V * k * math.sin(ct))
        dQ = wsets[w, 2] * (V * V * k * math.cos(ct) - G_ACC * math.sin(ct)) / (2 * LOAD_BASE)
        loads = (max(0.5 * Qt + dQ, 0.0), max(0.5 * Qt - dQ, 0.0))
        wout[w, 0] = yrel
        wout[w, 1] = 1.0 if outside else 0.0
        wout[w, 2] = loads[0]
        wout[w, 3] = loads[1]
        om = V / r0
        psid_abs = psid + V * k
        for sd in range(2):
            ratio = loads[sd] / qrefs[w]
            sc = ratio ** (1.0 / 3.0)
            for sl in range(2):
                v = vals[sd, sl]
                delta, r, yp = v[F_DELTA], v[F_R], v[F_YP]
                cd, sdl = math.cos(delta), math.sin(delta)
                n_tab = v[F_SHARE] * loads[sd] / cd
                N = n_tab
                xi = r / r0 - 1.0 + psid_abs * yp / V
                eta = ((psi - yad) * r / r0 - (yd / V - yad)) * cd
                phi = -(om * sdl + psid_abs * cd) / V
                p = pin[w, sd, sl]
                p[0], p[1], p[2] = N, v[F_A] * sc, v[F_B] * sc
                p[3], p[4], p[5] = v[F_C11], v[F_C22], v[F_C23]
                p[6], p[7], p[8] = xi, eta, phi
                p[9], p[10], p[11], p[12], p[13], p[14] = delta, yp, v[F_CA], v[F_CB], \
                    v[F_YRAIL], V
                p[15] = v[F_YWHEEL]
                if mode == 0:
                    fx, fy, mz = patch_forces(law, tp, N, p[1], p[2], p[3], p[4], p[5], xi, eta,
                                              phi, V)
                    # vertical equilibrium with the creep force: N cos d - Fy sin d = Q_k
                    for _ in range(NORMAL_PASSES):
                        if N <= 0.0 or abs(sdl) < 0.05:
                            break
                        n_new = max(n_tab + fy * sdl / cd, 0.0)
                        scale = (n_new / N) ** (1.0 / 3.0)
                        N = n_new
                        p[0], p[1], p[2] = N, p[1] * scale, p[2] * scale
                        fx, fy, mz = patch_forces(law, tp, N, p[1], p[2], p[3], p[4], p[5], xi,
                                                  eta, phi, V)
                else:
                    fx, fy, mz = fext[w, sd, sl, 0], fext[w, sd, sl, 1], fext[w, sd, sl, 2]
                    if fext[w, sd, sl, 3] > 0.0 and N > 0.0:
                        scale = (fext[w, sd, sl, 3] / N) ** (1.0 / 3.0)
                        N = fext[w, sd, sl, 3]
                        p[0], p[1], p[2] = N, p[1] * scale, p[2] * scale
                if N <= 0.0:
                    fx, fy, mz = 0.0, 0.0, 0.0
                o = pout[w, sd, sl]
                o[0], o[1], o[2] = fx, fy, mz
                o[3] = N * sdl + fy * cd
                o[4] = N * cd - fy * sdl
                o[5] = abs(fx * xi) + abs(fy * eta)
                F[3 * b] += o[3]
                F[3 * b + 1] += -yp * fx + mz * cd
        F[3 * b] += Qt * cl
    du = np.empty(2 * nd)
    du[:nd] = qd
    for b in range(nb):
        du[nd + 3 * b] = F[3 * b] / bodies[b, 0]
        du[nd + 3 * b + 1] = F[3 * b + 1] / bodies[b, 1]
        du[nd + 3 * b + 2] = F[3 * b + 2] / bodies[b, 2] if bodies[b, 5] > 0 else 0.0
    return du


@njit(cache=True, nogil=True)
def rk4_run(u, t0, dt, n_steps, every, V, s0, bodies, elems, bx, bf, wsets, ks, kk, kc, irs,
            ira, irc, shift, tables, qrefs, r0, law, tp, fext, pin, pout, wout, samples):
    """Classical fixed-step Runge-Kutta (4th order) with a compiled creep law: ``n_steps``
    steps of ``dt`` from (t0, u); every ``every`` steps the state goes to the next
    row of ``samples``.  Returns the final state."""
    k = 0
    for n in range(n_steps):
        t = t0 + n * dt
        k1 = rhs_core(t, u, V, s0, bodies, elems, bx, bf, wsets, ks, kk, kc, irs, ira, irc,
                      shift, tables, qrefs, r0, law, tp, 0, fext, pin, pout, wout)
        k2 = rhs_core(t + 0.5 * dt, u + 0.5 * dt * k1, V, s0, bodies, elems, bx, bf, wsets, ks,
                      kk, kc, irs, ira, irc, shift, tables, qrefs, r0, law, tp, 0, fext, pin,
                      pout, wout)
        k3 = rhs_core(t + 0.5 * dt, u + 0.5 * dt * k2, V, s0, bodies, elems, bx, bf, wsets, ks,
                      kk, kc, irs, ira, irc, shift, tables, qrefs, r0, law, tp, 0, fext, pin,
                      pout, wout)
        k4 = rhs_core(t + dt, u + dt * k3, V, s0, bodies, elems, bx, bf, wsets, ks, kk, kc,
                      irs, ira, irc, shift, tables, qrefs, r0, law, tp, 0, fext, pin, pout, wout)
        u = u + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
        if (n + 1) % every == 0 and k < samples.shape[0]:
            samples[k] = u
            k += 1
    return u
