"""The equations of motion of a railway vehicle in track-following coordinates,
compiled: the right-hand side (:func:`rhs_core`) and a fixed-step integrator
(:func:`rk4_run`); the vehicle they move is :class:`~railcontact.dynamics.vehicle.VehicleModel`.

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
from typing import NamedTuple

import numpy as np
from numba import njit

from .vehicle import G_ACC
from .wheel_rail import (F_A, F_B, F_C11, F_C22, F_C23, F_CA, F_CB, F_DELTA, F_R, F_SHARE,
                         F_YP, F_YRAIL, F_YWHEEL, lookup, patch_forces)


#: half the lateral distance of the wheel loads for the load transfer [m]
LOAD_BASE = 0.75
#: fixed-point passes for the normal force of steep patches (creep force's vertical part)
NORMAL_PASSES = 2

#: per-patch inputs kept by the right-hand side, one record per (wheelset, side, slot):
#: normal force [N], Hertz semi-axes a, b [m] at that force, Kalker's C11, C22, C23 [-],
#: creepages xi [-], eta [-], phi [1/m], contact angle [rad], lateral position of the
#: contact point relative to the wheelset centre [m], curvatures A, B [1/m], rail and
#: wheel profile coordinates y_rail, y_wheel [m] and the rolling velocity [m/s]
PATCH_IN = np.dtype([(name, np.float64) for name in (
    "normal_force", "a", "b", "C11", "C22", "C23", "xi", "eta", "phi", "contact_angle",
    "y_contact", "A", "B", "y_rail", "velocity", "y_wheel")], align=True)
#: per-patch outputs: creep forces Fx, Fy [N] and spin moment Mz [N m] on the wheel
#: (contact plane), lateral Y and vertical Q force of the rail on the wheel [N] (track
#: plane) and the wear number T gamma [N]
PATCH_OUT = np.dtype([(name, np.float64) for name in ("Fx", "Fy", "Mz", "Y", "Q", "Tgamma")],
                     align=True)
#: per-wheelset outputs: shift relative to the rails [m], whether it lies outside the
#: contact table, the quasi-static wheel loads [N], and with the online contact
#: (:mod:`railcontact.dynamics.online_contact`) the vertical position [m] and roll
#: [rad] relative to the rails (0 with a table)
WHEELSET_OUT = np.dtype([("relative_shift", np.float64), ("outside_table", np.bool_),
                         ("load_left", np.float64), ("load_right", np.float64),
                         ("vertical", np.float64), ("roll", np.float64)], align=True)
#: the external creep forces of mode 1, per patch: Fx, Fy [N], Mz [N m] and the normal
#: force [N] (0: the table's)
EXTERNAL = np.dtype([(name, np.float64) for name in ("Fx", "Fy", "Mz", "normal_force")],
                    align=True)


class Vehicle(NamedTuple):
    """The vehicle's compiled form (:meth:`~railcontact.dynamics.vehicle.VehicleModel.packed`)."""

    #: (nb,) :data:`~railcontact.dynamics.vehicle.BODY` records
    bodies: np.ndarray
    #: (ne,) :data:`~railcontact.dynamics.vehicle.ELEMENT` records
    elements: np.ndarray
    #: (n_stops, n) deflections [m] of the bump stop tables (rows named by ``elements.bump``)
    bump_deflection: np.ndarray
    #: (n_stops, n) forces [N] of the bump stop tables
    bump_force: np.ndarray
    #: (nw,) :data:`~railcontact.dynamics.vehicle.WHEELSET` records
    wheelsets: np.ndarray


class Track(NamedTuple):
    """The route's compiled form (:meth:`~railcontact.dynamics.route.Route.packed`)."""

    #: knots [m] of the design geometry
    s_knots: np.ndarray
    #: curvature [1/m] at the knots (positive: curve to the right)
    curvature: np.ndarray
    #: cant angle [rad] at the knots
    cant: np.ndarray
    #: uniform distances [m] of the irregularities
    irregularity_s: np.ndarray
    #: alignment irregularity [m] at ``irregularity_s``
    alignment: np.ndarray
    #: cross-level irregularity [rad] at ``irregularity_s``
    cross_level: np.ndarray


class ContactTables(NamedTuple):
    """The wheelsets' contact tables (:class:`~railcontact.dynamics.wheel_rail.WheelRailTable`)
    on one shift grid."""

    #: (n,) uniform lateral shifts [m]
    shift: np.ndarray
    #: (nw, n, 2, 2, nfields) per wheelset the table's ``data``
    data: np.ndarray
    #: (nw,) reference wheel loads [N] of the tables
    reference_loads: np.ndarray
    #: nominal rolling radius r0 [m]
    nominal_radius: float


class System(NamedTuple):
    """Everything constant during a run: the inputs of :func:`rhs_core`."""

    #: forward speed V [m/s]
    velocity: float
    #: distance [m] of the vehicle's origin along the route at t = 0
    s0: float
    vehicle: Vehicle
    track: Track
    contact: ContactTables
    #: code of the compiled creep law (:func:`~railcontact.tangential.online.online_law`;
    #: any value with ``mode`` 1)
    law: int
    #: parameters of the creep law (:func:`~railcontact.tangential.online.patch_forces`'s ``tp``)
    law_params: np.ndarray


class Outputs(NamedTuple):
    """What the right-hand side records of its last evaluation."""

    #: (nw, 2, 2) :data:`PATCH_IN` records per wheelset, side (left, right), slot
    #: (tread, flange)
    patch_in: np.ndarray
    #: (nw, 2, 2) :data:`PATCH_OUT` records
    patch_out: np.ndarray
    #: (nw,) :data:`WHEELSET_OUT` records
    wheelset_out: np.ndarray

    @classmethod
    def empty(cls, n_wheelsets: int) -> "Outputs":
        return cls(np.zeros((n_wheelsets, 2, 2), PATCH_IN),
                   np.zeros((n_wheelsets, 2, 2), PATCH_OUT),
                   np.zeros(n_wheelsets, WHEELSET_OUT))


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
def track_under(system, t, b):
    """The track under body b (a wheelset's) at time t: the curvature [1/m], its
    slope [1/m^2] and the cant [rad] at the body's track coordinate, the lateral
    alignment irregularity [m], its slope d(y_a)/ds [-] (central difference over
    the irregularity's own step) and the cross level [rad]."""
    track = system.track
    irs, ira = track.irregularity_s, track.alignment
    s = system.s0 + system.velocity * t + system.vehicle.bodies[b].x
    k, dk, ct = _track_at(s, track.s_knots, track.curvature, track.cant)
    hs = 0.5 * (irs[1] - irs[0])
    ya = np.interp(s, irs, ira)
    yad = (np.interp(s + hs, irs, ira) - np.interp(s - hs, irs, ira)) / (2 * hs)
    return k, dk, ct, ya, yad, np.interp(s, irs, track.cross_level)


@njit(cache=True, nogil=True)
def suspension_forces(t, q, qd, system):
    """The generalised forces (3 nb,) of everything but the wheel-rail contact at
    displacements ``q`` and velocities ``qd``: the track frame's inertia terms
    (uncompensated lateral acceleration, yaw acceleration of the track tangent), the
    gravity pendulum term of rolling bodies and the suspension elements."""
    V, s0 = system.velocity, system.s0
    bodies, elems = system.vehicle.bodies, system.vehicle.elements
    bx, bf = system.vehicle.bump_deflection, system.vehicle.bump_force
    ks, kk, kc = system.track.s_knots, system.track.curvature, system.track.cant
    nb = bodies.shape[0]
    nd = 3 * nb
    F = np.zeros(nd)
    kap = np.empty(nb)
    dkap = np.empty(nb)
    for b in range(nb):
        body = bodies[b]
        s = s0 + V * t + body.x
        k, dk, ct = _track_at(s, ks, kk, kc)
        kap[b] = k
        dkap[b] = dk
        au = V * V * k * math.cos(ct) - G_ACC * math.sin(ct)
        F[3 * b] -= body.mass * au
        F[3 * b + 1] -= body.yaw_inertia * V * V * dk
        if body.roll:
            F[3 * b + 2] += body.mass * G_ACC * body.roll_arm * q[3 * b + 2]
    for e in range(elems.shape[0]):
        el = elems[e]
        i = el.i
        j = el.j
        ai, aj, di, dj = el.a_i, el.a_j, el.d_i, el.d_j
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
        f = -(el.k_y * dy + el.c_y * dyd)
        ib = el.bump
        if ib >= 0:
            f -= _bump_force(dy, bx[ib], bf[ib])
        m = -(el.k_yaw * dp + el.c_yaw * dpd)
        mr = -(el.k_roll * dr + el.c_roll * drd)
        F[3 * i] += f
        F[3 * i + 1] += ai * f + m
        F[3 * i + 2] += -di * f + mr
        if j >= 0:
            F[3 * j] -= f
            F[3 * j + 1] -= aj * f + m
            F[3 * j + 2] -= -dj * f + mr
    return F


@njit(cache=True, nogil=True)
def rhs_core(t, u, system, mode, fext, out):
    """Time derivative of the state u = (q, q') with q = (y, ψ, φ) per body.

    Parameters
    ----------
    t : float
        Time [s].
    u : ndarray (6 nb,)
        State: displacements [m, rad] then velocities [m/s, rad/s], three per body.
    system : System
        The vehicle, track, contact tables, speed and creep law.
    mode : int
        0: creep forces from the compiled law ``system.law``; 1: from ``fext``.
    fext : ndarray (nw, 2, 2) of :data:`EXTERNAL`
        With ``mode`` 1: the creep forces per patch given by the caller.
    out : Outputs
        Filled with the per-patch inputs and outputs and the per-wheelset values of
        this evaluation (for output, and for ``mode`` 1).
    """
    V = system.velocity
    bodies, wsets = system.vehicle.bodies, system.vehicle.wheelsets
    shift, tables = system.contact.shift, system.contact.data
    qrefs, r0 = system.contact.reference_loads, system.contact.nominal_radius
    law, tp = system.law, system.law_params
    pin, pout, wout = out.patch_in, out.patch_out, out.wheelset_out
    nb = bodies.shape[0]
    nd = 3 * nb
    q = u[:nd]
    qd = u[nd:]
    F = suspension_forces(t, q, qd, system)
    vals = np.empty((2, 2, tables.shape[4]))
    for w in range(wsets.shape[0]):
        ws = wsets[w]
        b = ws.body
        k, dk, ct, ya, yad, cl = track_under(system, t, b)
        y, psi, yd, psid = q[3 * b], q[3 * b + 1], qd[3 * b], qd[3 * b + 1]
        yrel = y - ya
        outside = lookup(shift, tables[w], yrel, vals)
        Qt = ws.mass * (G_ACC * math.cos(ct) + V * V * k * math.sin(ct))
        dQ = ws.moment * (V * V * k * math.cos(ct) - G_ACC * math.sin(ct)) / (2 * LOAD_BASE)
        loads = (max(0.5 * Qt + dQ, 0.0), max(0.5 * Qt - dQ, 0.0))
        wo = wout[w]
        wo.relative_shift = yrel
        wo.outside_table = outside
        wo.load_left = loads[0]
        wo.load_right = loads[1]
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
                p.normal_force, p.a, p.b = N, v[F_A] * sc, v[F_B] * sc
                p.C11, p.C22, p.C23 = v[F_C11], v[F_C22], v[F_C23]
                p.xi, p.eta, p.phi = xi, eta, phi
                p.contact_angle, p.y_contact, p.A, p.B = delta, yp, v[F_CA], v[F_CB]
                p.y_rail, p.velocity, p.y_wheel = v[F_YRAIL], V, v[F_YWHEEL]
                if mode == 0:
                    fx, fy, mz = patch_forces(law, tp, N, p.a, p.b, p.C11, p.C22, p.C23, xi,
                                              eta, phi, V)
                    # vertical equilibrium with the creep force: N cos d - Fy sin d = Q_k
                    for _ in range(NORMAL_PASSES):
                        if N <= 0.0 or abs(sdl) < 0.05:
                            break
                        n_new = max(n_tab + fy * sdl / cd, 0.0)
                        scale = (n_new / N) ** (1.0 / 3.0)
                        N = n_new
                        p.normal_force, p.a, p.b = N, p.a * scale, p.b * scale
                        fx, fy, mz = patch_forces(law, tp, N, p.a, p.b, p.C11, p.C22, p.C23,
                                                  xi, eta, phi, V)
                else:
                    fe = fext[w, sd, sl]
                    fx, fy, mz = fe.Fx, fe.Fy, fe.Mz
                    if fe.normal_force > 0.0 and N > 0.0:
                        scale = (fe.normal_force / N) ** (1.0 / 3.0)
                        N = fe.normal_force
                        p.normal_force, p.a, p.b = N, p.a * scale, p.b * scale
                if N <= 0.0:
                    fx, fy, mz = 0.0, 0.0, 0.0
                o = pout[w, sd, sl]
                o.Fx, o.Fy, o.Mz = fx, fy, mz
                o.Y = N * sdl + fy * cd
                o.Q = N * cd - fy * sdl
                o.Tgamma = abs(fx * xi) + abs(fy * eta)
                F[3 * b] += o.Y
                F[3 * b + 1] += -yp * fx + mz * cd
        F[3 * b] += Qt * cl
    du = np.empty(2 * nd)
    du[:nd] = qd
    for b in range(nb):
        body = bodies[b]
        du[nd + 3 * b] = F[3 * b] / body.mass
        du[nd + 3 * b + 1] = F[3 * b + 1] / body.yaw_inertia
        du[nd + 3 * b + 2] = F[3 * b + 2] / body.roll_inertia if body.roll else 0.0
    return du


@njit(cache=True, nogil=True)
def rk4_run(u, t0, dt, n_steps, every, system, fext, out, samples):
    """Classical fixed-step Runge-Kutta (4th order) with the compiled creep law of
    ``system``: ``n_steps`` steps of ``dt`` [s] from (t0 [s], u); every ``every``
    steps the state goes to the next row of ``samples`` (n, 6 nb).  ``fext`` is
    :func:`rhs_core`'s (unused: mode 0); ``out`` (:class:`Outputs`) holds the last
    evaluation's values.  Returns the final state."""
    k = 0
    for n in range(n_steps):
        t = t0 + n * dt
        k1 = rhs_core(t, u, system, 0, fext, out)
        k2 = rhs_core(t + 0.5 * dt, u + 0.5 * dt * k1, system, 0, fext, out)
        k3 = rhs_core(t + 0.5 * dt, u + 0.5 * dt * k2, system, 0, fext, out)
        k4 = rhs_core(t + dt, u + dt * k3, system, 0, fext, out)
        u = u + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
        if (n + 1) % every == 0 and k < samples.shape[0]:
            samples[k] = u
            k += 1
    return u
