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

import numpy as np
from numba import njit

from .vehicle import G_ACC
from .wheel_rail import (F_A, F_B, F_C11, F_C22, F_C23, F_CA, F_CB, F_DELTA, F_R, F_SHARE,
                         F_YP, F_YRAIL, F_YWHEEL, lookup, patch_forces)


#: half the lateral distance of the wheel loads for the load transfer [m]
LOAD_BASE = 0.75
#: per-patch inputs and outputs kept by the right-hand side
PIN = ("normal_force", "a", "b", "C11", "C22", "C23", "xi", "eta", "phi", "contact_angle",
       "y_contact", "A", "B", "y_rail", "velocity", "y_wheel")
POUT = ("Fx", "Fy", "Mz", "Y", "Q", "Tgamma")
WOUT = ("relative_shift", "outside_table", "load_left", "load_right")
#: fixed-point passes for the normal force of steep patches (creep force's vertical part)
NORMAL_PASSES = 2


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
