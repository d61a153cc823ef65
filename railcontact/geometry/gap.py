"""The undeformed distance h(x, y) of a patch: the rail's cylinder and the wheel's
surface of revolution, with yaw and roll, along the normal of the patch's tangent
plane (:class:`GapEvaluator`, compiled kernels), sampled on grids and lines for the
normal models (:func:`sample_gap_lines`), the spin per strip
(:func:`sample_strip_spin`), and the relative curvatures at a point by finite
differences (:func:`curvatures_fd`)."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from ..profiles.profile import ppoly_at
from .locus import Locus
from .track import Track, Wheelset


#: Newton steps of the gap evaluation stop after a correction below this [m]: the
#: convergence is quadratic, so the error left is of order kappa * NEWTON_TOL^2 with
#: kappa <= 1e3 1/m the profile curvatures, below 1e-13 m
NEWTON_TOL = 1e-8

#: Newton steps at most; a projection that has not converged by then is no point of
#: the surface (a NaN distance: the surface is missed).  An iterate left unconverged
#: wanders: beyond a profile's end, or onto a far part of the surface, where a normal
#: through a steep patch's tangent plane nearly grazes the profile
NEWTON_STEPS = 24



class Spline(NamedTuple):
    """A profile's piecewise cubic for the compiled kernels (:func:`ppoly_at`)."""

    #: breakpoints [m] of the lateral coordinate
    breaks: np.ndarray
    #: (4, n) coefficients of the cubic pieces [m^(1-k)]
    coefs: np.ndarray


class PatchFrame(NamedTuple):
    """A patch's tangent plane and the wheelset's axes, for the compiled gap kernels."""

    #: centre of the patch [m], track axes
    C: np.ndarray
    #: lateral tangent of the plane (unit; x is the rolling direction)
    t: np.ndarray
    #: normal of the plane (unit)
    n: np.ndarray
    #: lateral offset [m] of the rail profile's origin
    y_off: float
    #: (3, 3) from track to wheelset axes (the transpose of the wheelset's axes)
    Rt: np.ndarray
    #: origin of the wheelset axes [m], track axes
    O: np.ndarray
    #: lateral offset [m] of the wheel profile's origin in wheelset axes
    e: float
    #: nominal rolling radius [m]
    r0: float


class GapEvaluator:
    """Undeformed distance along the normal in a patch's tangent plane."""

    def __init__(self, wheelset: Wheelset, track: Track, side: str, loc: Locus,
                 center: np.ndarray, angle_side: float):
        self.rail = track.rail(side)
        self.wheel = wheelset.wheel(side)
        self.y_off = track.rail_offset(side)
        self.r0 = wheelset.nominal_radius
        self.e = wheelset.wheel_offset
        self.O, self.R = loc.origin, loc.axes
        self.C = center
        self.sign = 1.0 if side == "right" else -1.0
        self.n = np.array([0.0, -math.sin(angle_side), math.cos(angle_side)])
        self.t = np.array([0.0, math.cos(angle_side), math.sin(angle_side)])
        self.angle = angle_side
        self.y_ref = float(center[1] - self.y_off)
        # the frame packed for the multi-patch kernel: C, t, n, y_off, R^T, O, e, r0
        self.Rt = np.ascontiguousarray(self.R.T)
        self.frame = np.concatenate([self.C, self.t, self.n, [self.y_off], self.Rt.ravel(),
                                     self.O, [self.e, self.r0]]).astype(float)
        self.patch_frame = PatchFrame(self.C, self.t, self.n, float(self.y_off), self.Rt,
                                      self.O, float(self.e), float(self.r0))

    def contact_angle_at(self, y):
        """Local contact angle [rad] (track convention, as ``contact_angle``) at
        patch coordinate ``y`` [m]: the rail-surface inclination where the strip at
        y meets the rail, y_rail ~ y_ref + y cos(delta) on the side's profile axis."""
        ys = self.sign * np.asarray(y, dtype=float)
        yr = self.y_ref + ys * math.cos(self.angle)
        return self.sign * np.arctan(self.rail.slope(yr))

    def __call__(self, x, y):
        x = np.asarray(x, dtype=float)
        ys = self.sign * np.asarray(y, dtype=float)
        if x.ndim == 2 and ys.ndim == 2 and x.shape[1] == 1 and ys.shape[0] == 1:
            # a grid x[:, None], y[None, :]: line by line, the rail distance once per
            # line and every projection started from the neighbouring line's
            return sane_gap(_gap_lines_kernel(np.ascontiguousarray(x.T), np.ascontiguousarray(ys),
                                           self.frame[None, :], self.rail._breaks,
                                           self.rail._coefs, self.wheel._breaks,
                                           self.wheel._coefs)[0])
        x, ys = np.broadcast_arrays(x, ys)
        h = self.points(np.ascontiguousarray(x.ravel()), np.ascontiguousarray(ys.ravel()),
                        signed=True)
        return h.reshape(x.shape)

    def points(self, x, ys, signed=False):
        """The gap at points (x[i], y[i]) (1-D float arrays; ``signed``: y already
        in the side's lateral sense, as ``__call__`` passes it)."""
        if not signed:
            ys = self.sign * ys
        return sane_gap(_gap_kernel(x, ys, self.patch_frame,
                                    Spline(self.rail._breaks, self.rail._coefs),
                                    Spline(self.wheel._breaks, self.wheel._coefs)))



#: an undeformed distance below this [m] is no interpenetration of the patch: the
#: normal through the tangent-plane point met another part of a surface (far from a
#: steep patch, e.g. the other wall of a groove); taken as missing the surface
DEEPEST_GAP = -5e-3



def sane_gap(h: np.ndarray) -> np.ndarray:
    """The gap with points whose normal met another part of a surface (an
    interpenetration deeper than ``DEEPEST_GAP``) taken as missing it (1 m)."""
    return np.where(h < DEEPEST_GAP, 1.0, h)



@njit(cache=True, nogil=True, inline="always")
def _rail_distance(ysp, C, t, n, y_off, rb, rc, tr, k=-1):
    """Distance along n from the tangent-plane point C + ysp t to the rail surface
    (the rail is straight along x, so x does not enter): Newton on
    z_r(P_y + tr n_y - y_off) = P_z + tr n_z from the estimate ``tr``, starting the
    profile lookup at interval ``k``.  Returns the distance and the interval."""
    p1 = C[1] + ysp * t[1]
    p2 = C[2] + ysp * t[2]
    nr = rb.size - 1
    for _ in range(NEWTON_STEPS):
        # ppoly_at(xr, rb, rc, k), written out where the piece k holds xr (a
        # compiled call that takes arrays and is not inlined costs atomic reference
        # counts, more than the lookup)
        xr = p1 + tr * n[1] - y_off
        if 0 <= k < nr and rb[k] <= xr and (xr < rb[k + 1] or (k == nr - 1 and xr <= rb[nr])):
            q = xr - rb[k]
            zr = ((rc[0, k] * q + rc[1, k]) * q + rc[2, k]) * q + rc[3, k]
            dzr = (3.0 * rc[0, k] * q + 2.0 * rc[1, k]) * q + rc[2, k]
        else:
            zr, dzr, k = ppoly_at(xr, rb, rc, k)
        step = (zr - (p2 + tr * n[2])) / (dzr * n[1] - n[2])
        tr -= step
        if not abs(step) > NEWTON_TOL:
            return tr, k
    return np.nan, k                    # not converged: no point of the rail



@njit(cache=True, nogil=True, inline="always")
def _wheel_distance(xp, ysp, frame, wheel, tw, k=-1):
    """Distance along n from the tangent-plane point C + xp (1, 0, 0) + ysp t to
    the wheel surface (radius r0 + z_w(eta - e) in wheelset axes; ``frame`` a
    :class:`PatchFrame`, ``wheel`` the wheel profile's :class:`Spline`), by Newton
    from the estimate ``tw`` [m], starting the profile lookup at interval ``k``.
    Returns the distance and the interval."""
    C, t, n, Rt, O = frame.C, frame.t, frame.n, frame.Rt, frame.O
    nl0 = Rt[0, 0] * n[0] + Rt[0, 1] * n[1] + Rt[0, 2] * n[2]
    nl1 = Rt[1, 0] * n[0] + Rt[1, 1] * n[1] + Rt[1, 2] * n[2]
    nl2 = Rt[2, 0] * n[0] + Rt[2, 1] * n[1] + Rt[2, 2] * n[2]
    d0 = C[0] + xp - O[0]
    d1 = C[1] + ysp * t[1] - O[1]
    d2 = C[2] + ysp * t[2] - O[2]
    l0 = Rt[0, 0] * d0 + Rt[0, 1] * d1 + Rt[0, 2] * d2
    l1 = Rt[1, 0] * d0 + Rt[1, 1] * d1 + Rt[1, 2] * d2
    l2 = Rt[2, 0] * d0 + Rt[2, 1] * d1 + Rt[2, 2] * d2
    return _wheel_newton(l0, l1, l2, nl0, nl1, nl2, frame.e, frame.r0, wheel.breaks,
                         wheel.coefs, tw, k)



@njit(cache=True, nogil=True, inline="always")
def _wheel_newton(l0, l1, l2, nl0, nl1, nl2, e, r0, wb, wc, tw, k):
    """:func:`_wheel_distance` from the point l and the direction nl in wheelset
    axes (the point's projection along n onto the wheel, by Newton)."""
    nw = wb.size - 1
    for _ in range(NEWTON_STEPS):
        a0 = l0 + tw * nl0
        a2 = l2 + tw * nl2
        rho = math.sqrt(a0 * a0 + a2 * a2)
        # ppoly_at(xi, wb, wc, k), written out where the piece k holds xi
        xi = l1 + tw * nl1 - e
        if 0 <= k < nw and wb[k] <= xi and (xi < wb[k + 1] or (k == nw - 1 and xi <= wb[nw])):
            q = xi - wb[k]
            zw = ((wc[0, k] * q + wc[1, k]) * q + wc[2, k]) * q + wc[3, k]
            dzw = (3.0 * wc[0, k] * q + 2.0 * wc[1, k]) * q + wc[2, k]
        else:
            zw, dzw, k = ppoly_at(xi, wb, wc, k)
        step = (rho - (r0 + zw)) / ((a0 * nl0 + a2 * nl2) / rho - dzw * nl1)
        tw -= step
        if not abs(step) > NEWTON_TOL:
            return tw, k
    return np.nan, k                    # not converged: no point of the wheel



@njit(cache=True, nogil=True)
def _gap_kernel(x, ys, frame, rail, wheel):
    """Distance along the normal n between rail and wheel surfaces through the
    tangent-plane points C + x (1, 0, 0) + ys t [m] of the patch ``frame``
    (:class:`PatchFrame`; 1 m where a surface is missed); ``rail``, ``wheel`` the
    profiles' :class:`Spline`."""
    C, t, n, y_off = frame.C, frame.t, frame.n, frame.y_off
    rb, rc = rail.breaks, rail.coefs
    h = np.empty(x.size)
    kr = -1
    kw = -1
    for i in range(x.size):
        tr, kr = _rail_distance(ys[i], C, t, n, y_off, rb, rc, 0.0, kr)
        tw, kw = _wheel_distance(x[i], ys[i], frame, wheel, 0.0, kw)
        g = tr - tw
        h[i] = g if math.isfinite(g) else 1.0
    return h



@njit(cache=True, nogil=True)
def _equally_spaced(ys):
    """Whether the lines ys are equally spaced (to 1e-9 of their spacing)."""
    if ys.size < 3:
        return False
    d = ys[1] - ys[0]
    for j in range(2, ys.size):
        if abs(ys[j] - ys[j - 1] - d) > 1e-9 * abs(d):
            return False
    return True



#: lines of a grid whose points :func:`_gap_lines_kernel` solves side by side (each
#: point's Newton start waits for the point before it on its line; the lines' are
#: independent, and the processor overlaps them)
LINES_TOGETHER = 4



@njit(cache=True, nogil=True)
def _gap_lines_kernel(x, ys, F, rb, rc, wb, wc):
    """Gaps of many patches sharing one rail and one wheel profile on lines of
    constant y: out[k, i, j] at (x[k, i], ys[k, j]) with row k of the packed frames
    ``F`` (``GapEvaluator.frame``).  The rail distance is computed once per line;
    every projection starts from its neighbours' solutions: along the line (the
    wheel is smooth in x) where three points before it on the line are solved,
    else from the neighbouring lines.

    The wheel's projection is :func:`_wheel_newton` written out in the loop, and
    its profile lookup where the previous point's piece holds the point: a
    compiled call that takes arrays and is not inlined costs atomic reference
    counts, more than the Newton step itself.  Each point's start, its steps and
    its profile piece are those of :func:`_wheel_newton` (the piece holding a
    point is unique: the interval a lookup starts from moves no result).
    ``LINES_TOGETHER`` lines are walked side by side, their
    points i one after the other: a start along a line waits for the point
    before it, and the lines' solves are independent."""
    nx = x.shape[1]
    ny = ys.shape[1]
    h = np.empty((x.shape[0], nx, ny))
    # the wheel distance of every point of the patch (0 where not solved), each
    # line's rail distance and the weights of its start from the lines before it
    tw = np.zeros((ny, nx))
    rail = np.empty(ny)
    cs = np.zeros((ny, 3))
    run = np.zeros(LINES_TOGETHER, dtype=np.int64)
    kw = np.full(LINES_TOGETHER, -1)
    tr = np.zeros(3)
    nw = wb.size - 1
    for k in range(x.shape[0]):
        f = F[k]
        C, t, n, O = f[0:3], f[3:6], f[6:9], f[19:22]
        Rt = f[10:19].reshape((3, 3))
        y_off, e, r0 = f[9], f[22], f[23]
        kr = -1
        quadratic = _equally_spaced(ys[k])
        along = _equally_spaced(x[k])
        # n and the tangent-plane axes in wheelset axes: a point's wheelset
        # coordinates are linear in its (x, y)
        nl0 = Rt[0, 0] * n[0] + Rt[0, 1] * n[1] + Rt[0, 2] * n[2]
        nl1 = Rt[1, 0] * n[0] + Rt[1, 1] * n[1] + Rt[1, 2] * n[2]
        nl2 = Rt[2, 0] * n[0] + Rt[2, 1] * n[1] + Rt[2, 2] * n[2]
        tr[:] = 0.0
        for j in range(ny):
            # Newton starts from the last lines' solutions, extrapolated quadratically
            # on equally spaced lines (else the last line's)
            if quadratic and j >= 3:
                c0, c1, c2 = 3.0, -3.0, 1.0
            else:
                c0, c1, c2 = (1.0 if j >= 1 else 0.0), 0.0, 0.0
            start = c0 * tr[0] + c1 * tr[1] + c2 * tr[2]
            r, kr = _rail_distance(ys[k, j], C, t, n, y_off, rb, rc, start, kr)
            if not math.isfinite(r) and start != 0.0:
                # the extrapolated start led Newton astray: again from the plane
                r, kr = _rail_distance(ys[k, j], C, t, n, y_off, rb, rc, 0.0, -1)
            if not math.isfinite(r):
                # the line misses the rail profile: gap 1 m (below) and the next
                # lines start afresh
                c0, c1, c2 = 0.0, 0.0, 0.0
            tr[2], tr[1], tr[0] = tr[1], tr[0], (r if math.isfinite(r) else 0.0)
            rail[j] = r
            cs[j, 0], cs[j, 1], cs[j, 2] = c0, c1, c2
        for j0 in range(0, ny, LINES_TOGETHER):
            j1 = min(j0 + LINES_TOGETHER, ny)
            run[:] = 0                  # solved points in a row before i on each line
            for i in range(nx):
                d0 = C[0] + x[k, i] - O[0]
                for j in range(j0, j1):
                    b = j - j0
                    if along and run[b] >= 3:
                        # quadratic extrapolation along the line (equally spaced x)
                        start = 3.0 * tw[j, i - 1] - 3.0 * tw[j, i - 2] + tw[j, i - 3]
                    else:
                        start = (cs[j, 0] * (tw[j - 1, i] if j >= 1 else 0.0)
                                 + cs[j, 1] * (tw[j - 2, i] if j >= 2 else 0.0)
                                 + cs[j, 2] * (tw[j - 3, i] if j >= 3 else 0.0))
                    d1 = C[1] + ys[k, j] * t[1] - O[1]
                    d2 = C[2] + ys[k, j] * t[2] - O[2]
                    l0 = Rt[0, 0] * d0 + Rt[0, 1] * d1 + Rt[0, 2] * d2
                    l1 = Rt[1, 0] * d0 + Rt[1, 1] * d1 + Rt[1, 2] * d2
                    l2 = Rt[2, 0] * d0 + Rt[2, 1] * d1 + Rt[2, 2] * d2
                    w = np.nan
                    for attempt in range(2):
                        # Newton from the start, and again from the plane where
                        # the extrapolated start failed (:func:`_wheel_newton`)
                        if attempt == 1:
                            if math.isfinite(w) or start == 0.0:
                                break
                            start = 0.0
                            kw[b] = -1
                        w = start
                        kb = kw[b]
                        for _ in range(NEWTON_STEPS):
                            a0 = l0 + w * nl0
                            a2 = l2 + w * nl2
                            rho = math.sqrt(a0 * a0 + a2 * a2)
                            xi = l1 + w * nl1 - e
                            # ppoly_at(xi, wb, wc, kb), written out where the guess
                            # kb is the profile's piece (the point before's, mostly)
                            if (0 <= kb < nw and wb[kb] <= xi
                                    and (xi < wb[kb + 1] or (kb == nw - 1 and xi <= wb[nw]))):
                                s = xi - wb[kb]
                                zw = ((wc[0, kb] * s + wc[1, kb]) * s + wc[2, kb]) * s + wc[3, kb]
                                dzw = (3.0 * wc[0, kb] * s + 2.0 * wc[1, kb]) * s + wc[2, kb]
                            else:
                                zw, dzw, kb = ppoly_at(xi, wb, wc, kb)
                            step = (rho - (r0 + zw)) / ((a0 * nl0 + a2 * nl2) / rho - dzw * nl1)
                            w -= step
                            if not abs(step) > NEWTON_TOL:
                                break
                        else:
                            w = np.nan          # not converged: no point of the wheel
                        kw[b] = kb
                    g = rail[j] - w
                    h[k, i, j] = g if math.isfinite(g) else 1.0
                    tw[j, i] = w if math.isfinite(w) else 0.0
                    run[b] = run[b] + 1 if math.isfinite(w) else 0
    return h



def profile_groups(patches) -> tuple[list, list]:
    """The indices of ``patches`` whose gap is a :class:`GapEvaluator`, grouped by
    their rail and wheel profile pair (each group evaluated in one compiled loop),
    and the indices of the others (bodies cases: their ``gap`` in Python)."""
    groups: dict = {}
    others = []
    for k, p in enumerate(patches):
        f = p.gap_function
        if isinstance(f, GapEvaluator):
            groups.setdefault((id(f.rail), id(f.wheel)), []).append(k)
        else:
            others.append(k)
    return list(groups.values()), others


def sample_gap_lines(patches, x, y) -> np.ndarray:
    """Undeformed distance [m] of many patches at once on lines of constant y:
    ``x`` (patches, nx) and ``y`` (patches, ny) in each patch's tangent-plane
    coordinates give h of shape (patches, nx, ny).  Patches of the geometry layer
    are evaluated in one compiled loop per rail/wheel profile pair; others (bodies
    cases) through their ``gap`` method."""
    x = np.ascontiguousarray(x, dtype=float)
    y = np.ascontiguousarray(y, dtype=float)
    h = np.empty((x.shape[0], x.shape[1], y.shape[1]))
    groups, others = profile_groups(patches)
    for k in others:
        h[k] = patches[k].gap(x[k][:, None], y[k][None, :])
    for idx in groups:
        f0 = patches[idx[0]].gap_function
        frames = np.array([patches[k].gap_function.frame for k in idx])
        sign = np.array([patches[k].gap_function.sign for k in idx])
        h[idx] = sane_gap(_gap_lines_kernel(x[idx], np.ascontiguousarray(sign[:, None] * y[idx]),
                                         frames, f0.rail._breaks, f0.rail._coefs,
                                         f0.wheel._breaks, f0.wheel._coefs))
    return h



@njit(cache=True, nogil=True)
def strip_spin(rail, spin, y, out):
    """Spin creepage [1/m] per strip of one patch on the rail profile ``rail``
    (:class:`Spline`) at patch coordinates ``y`` into ``out``:
    phi(y) = phi cos(D) + dphi sin(D), D the local contact angle minus the patch's
    (:meth:`ContactGeometry.spin_at`).  ``spin``: (side sign, the reference point's
    rail coordinate y_ref [m], cos of the side's contact angle, the contact angle
    delta [rad], the patch's spin phi [1/m], d(phi)/d(delta) [1/m]); off the
    profile the patch's spin."""
    sign, yref, cosa, delta, phi, dphi = spin
    cdl, sdl = math.cos(delta), math.sin(delta)
    k = -1
    rb, rc = rail.breaks, rail.coefs
    nr = rb.size - 1
    for j in range(y.size):
        # local angle sign * atan(s) with s the rail's slope: D = that - delta, and
        # cos D, sin D without the angles (1 / sqrt(1 + s^2) = cos(atan s)); the
        # slope ppoly_at(xr, rb, rc, k)[1], written out where the piece k holds xr
        xr = yref + sign * y[j] * cosa
        if 0 <= k < nr and rb[k] <= xr and (xr < rb[k + 1] or (k == nr - 1 and xr <= rb[nr])):
            q = xr - rb[k]
            sl = (3.0 * rc[0, k] * q + 2.0 * rc[1, k]) * q + rc[2, k]
        else:
            _, sl, k = ppoly_at(xr, rb, rc, k)
        if math.isfinite(sl):
            s = sign * sl
            c = 1.0 / math.sqrt(1.0 + s * s)
            out[j] = phi * (c * (cdl + s * sdl)) + dphi * (c * (s * cdl - sdl))
        else:
            out[j] = phi


@njit(cache=True, nogil=True)
def _strip_spins(rail, pars, y, out):
    for k in range(y.shape[0]):
        p = pars[k]
        strip_spin(rail, (p[0], p[1], p[2], p[3], p[4], p[5]), y[k], out[k])


def sample_strip_spin(patches, y) -> np.ndarray:
    """Spin creepage [1/m] of many patches per strip, at patch coordinates ``y``
    (patches, strips), as :meth:`ContactGeometry.spin_at` with each patch's own spin:
    patches on the same rail profile in one compiled loop (:func:`strip_spin`, the
    compiled case's kernel)."""
    y = np.ascontiguousarray(y, dtype=float)
    out = np.empty(y.shape)
    groups: dict = {}
    for k, p in enumerate(patches):
        f = p.gap_function
        if (isinstance(f, GapEvaluator) and math.isfinite(p.spin_derivative)
                and getattr(p.local_contact_angle, "__self__", None) is f):
            groups.setdefault(id(f.rail), []).append(k)
        else:
            out[k] = p.spin_at(y[k], p.creepage[2] if p.creepage is not None else 0.0)
    for idx in groups.values():
        pars = np.array([(p.gap_function.sign, p.gap_function.y_ref,
                          math.cos(p.gap_function.angle), p.contact_angle,
                          p.creepage[2] if p.creepage is not None else 0.0,
                          p.spin_derivative) for p in (patches[k] for k in idx)])
        rail = patches[idx[0]].gap_function.rail
        o = np.empty((len(idx), y.shape[1]))
        _strip_spins(Spline(rail._breaks, rail._coefs), pars, y[idx], o)
        out[idx] = o
    return out



#: finite-difference steps for the curvatures of the gap [m] (rolling, lateral)
FD_STEP = (2e-3, 2e-4)



def curvatures_fd(gapf, x0, y0):
    """Curvatures (A, B) [1/m] of the gap and the gap itself at (x0, y0): one
    vectorised evaluation of the five-point stencil."""
    hx, hy = FD_STEP
    xs = np.array([x0, x0 + hx, x0 - hx, x0, x0])
    ys = np.array([y0, y0, y0, y0 + hy, y0 - hy])
    h = gapf.points(xs, ys)
    A = (h[1] + h[2] - 2 * h[0]) / (2 * hx * hx)
    B = (h[3] + h[4] - 2 * h[0]) / (2 * hy * hy)
    return float(A), float(B), float(h[0])



@njit(cache=True, nogil=True)
def _rail_distances(ys, frame, rail):
    """Distances [m] along the normal from the tangent-plane points C + ys t (ys in
    the side's lateral sense) to the rail surface (:func:`_rail_distance`)."""
    out = np.empty(ys.size)
    k = -1
    for i in range(ys.size):
        tr, k = _rail_distance(ys[i], frame.C, frame.t, frame.n, frame.y_off, rail.breaks,
                               rail.coefs, 0.0, k)
        out[i] = tr
    return out



class SampledWheelGap:
    """A patch's undeformed distance with the wheel surface taken as CONTACT's planar
    contact takes it: linear across the patch between wheel-profile samples every
    ``ds`` [m] along the profile, counted from the wheel point at lateral wheel
    coordinate ``y_wheel`` [m]; the rail and the rolling direction exact.

    CONTACT's rule (its source ``m_wr_undefdist.f90``, ``wr_ud_planar`` and
    ``trim_wheel_profile``; ``m_interp_sub.f90``, ``interp_wgt_surf2unif``): the
    wheel profile's parametric spline y(s), z(s), s the summed chord length of its
    points (:attr:`railcontact.profiles.profile.Profile.chord_spline`), is sampled
    at s_k = s_0 + k DS, s_0 where the spline reaches the lateral wheel coordinate
    of the potential contact grid's origin (steady rolling: the contact reference
    point, on the rail surface; DS the grid's lateral element size); the samples
    are revolved into slices DX apart, the mesh turned into the patch's tangent
    plane, and the wheel's normal coordinate interpolated bilinearly onto the grid
    points (x, s_p); the rail's normal coordinate is exact on its spline.  Where
    the wheel's profile is curved across the plane (the flange root of a worn
    wheel, lateral radius R of 10-20 mm) a chord lies off the arc by up to
    DS^2 / (8 R): about 1 um at 0.4 mm elements, some per cent of the force of a
    gauge-corner patch; on the tread the chords and the arc coincide.  The slices'
    chords in x (DX^2 / (8 r), r the wheel radius) are below 0.1 um and left out:
    each sample lies on its wheel circle at the point's x.  The samples lie on
    railcontact's wheel surface (their y from the chord-length spline; the two
    splines differ by nanometres).

    ``evaluator``: the patch's exact :class:`GapEvaluator`, whose attributes this
    object shares; called as it is, on patch coordinates (x, y) [m].  ``y_wheel``:
    the reference point's lateral wheel coordinate [m]; ``y_origin``: that of the
    grid's origin where the samples are counted from, if not the reference point
    (a transient case's grid, :func:`supergrid_origin`).  Points beyond the
    samples, or whose neighbouring samples miss a surface, keep the exact gap.
    """

    def __init__(self, evaluator: GapEvaluator, y_wheel: float, ds: float,
                 y_origin: float | None = None):
        if not (math.isfinite(ds) and ds > 0):
            raise ValueError(f"wheel sample spacing {ds!r} m: expected a length > 0")
        self.evaluator, self.ds = evaluator, float(ds)
        self._curve = evaluator.wheel.chord_spline
        self._s_ref = float(self._curve.s_at_y(float(y_wheel)))
        self._s0 = (self._s_ref if y_origin is None
                    else float(self._curve.s_at_y(float(y_origin))))

    def __getattr__(self, name):
        return getattr(self.evaluator, name)

    def _samples(self, span: float):
        """Wheel-profile samples (y_w, radius) covering +-``span`` [m] of the patch
        about the reference: every ``ds`` of chord length from s_0, those whose
        lateral position lies within the span (with a margin) of the reference's."""
        c = self._curve
        s_ref = self._s_ref
        lo, hi = float(c.s[0]), float(c.s[-1])
        k0 = math.floor((max(s_ref - 2.0 * span, lo) - self._s0) / self.ds) - 4
        k1 = math.ceil((min(s_ref + 2.0 * span, hi) - self._s0) / self.ds) + 4
        s = self._s0 + np.arange(k0, k1 + 1) * self.ds
        s = s[(s >= lo) & (s <= hi)]
        yw = c.point(s)[0]
        return yw, self.evaluator.r0 + self.evaluator.wheel.z_at(yw)

    def _node_coordinates(self, xs, yw, rho):
        """Patch y [m] and normal coordinate w [m] (the distance along n from the
        tangent plane) of the samples (columns) on their wheel circles at the track
        x of the patch coordinates ``xs`` (rows), sorted by y along each row."""
        ev = self.evaluator
        R, O = ev.R, ev.O
        eta = ev.e + yw
        X = ev.C[0] + xs[:, None]
        st = np.zeros((xs.size, yw.size))
        for _ in range(3):          # Newton on the circle angle (sin) where x = X
            ct = np.sqrt(1.0 - st * st)
            px = O[0] + eta * R[0, 1] + rho * (st * R[0, 0] + ct * R[0, 2])
            st = np.clip(st + (X - px) / (rho * R[0, 0]), -0.5, 0.5)
        ct = np.sqrt(1.0 - st * st)
        dy = O[1] + eta * R[1, 1] + rho * (st * R[1, 0] + ct * R[1, 2]) - ev.C[1]
        dz = O[2] + eta * R[2, 1] + rho * (st * R[2, 0] + ct * R[2, 2]) - ev.C[2]
        yp = ev.sign * (dy * ev.t[1] + dz * ev.t[2])
        w = dy * ev.n[1] + dz * ev.n[2]
        order = np.argsort(yp, axis=1)
        return np.take_along_axis(yp, order, 1), np.take_along_axis(w, order, 1)

    def _nodes(self, xs, yw, rho):
        """Patch y [m] of the samples (columns) on their wheel circles at the track x
        of the patch coordinates ``xs`` (rows), sorted along each row."""
        return self._node_coordinates(xs, yw, rho)[0]

    def __call__(self, x, y):
        ev = self.evaluator
        X, Y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        shape = X.shape
        X, Y = np.ascontiguousarray(X.ravel()), np.ascontiguousarray(Y.ravel())
        if X.size == 0:
            return np.empty(shape)
        xs, row = np.unique(X, return_inverse=True)
        yw, rho = self._samples(2.0 * float(np.max(np.abs(Y))))
        if yw.size < 2:
            return ev.points(X, Y).reshape(shape)
        nodes, w = self._node_coordinates(xs, yw, rho)
        nk = yw.size
        # one sorted array of every row's nodes, each row lifted above the last
        lift = 10.0 + 2.0 * float(np.max(np.abs(nodes)))
        j = np.searchsorted((nodes + lift * np.arange(xs.size)[:, None]).ravel(),
                            Y + lift * row) - 1 - row * nk
        ok = (j >= 0) & (j <= nk - 2)
        jl = np.clip(j, 0, nk - 2)
        ya, yb = nodes[row, jl], nodes[row, jl + 1]
        lam = (Y - ya) / np.where(yb > ya, yb - ya, 1.0)
        # the wheel's normal coordinate linear between the samples (CONTACT's
        # bilinear interpolation on the slice through the point), the rail exact
        tr = _rail_distances(np.ascontiguousarray(ev.sign * Y), ev.patch_frame,
                             Spline(ev.rail._breaks, ev.rail._coefs))
        h = tr - ((1.0 - lam) * w[row, jl] + lam * w[row, jl + 1])
        ok &= np.isfinite(h) & (h >= DEEPEST_GAP) & (h < 0.5)
        if not np.all(ok):
            # beyond the samples or off the rail: the exact gap
            bad = ~ok
            h[bad] = ev.points(np.ascontiguousarray(X[bad]), np.ascontiguousarray(Y[bad]))
        return h.reshape(shape)


def sampled_wheel_geometry(geometry, ds: float):
    """``geometry`` (a :class:`~railcontact.geometry.contact.ContactGeometry`) with
    its wheel-rail gap taken as CONTACT's planar contact takes it
    (:class:`SampledWheelGap`, wheel samples every ``ds`` [m]); unchanged where its
    gap is not a wheel-rail :class:`GapEvaluator` (surfaces, bodies)."""
    import dataclasses
    gf = geometry.gap_function
    if callable(getattr(gf, "sampled", None)):
        # a conformal patch (:class:`railcontact.geometry.conformal.ConformalGap`):
        # CONTACT's conformal rule with the same wheel samples (kept where they are
        # taken already: a transient grid's, counted from its origin)
        if gf.planar is not None:
            return geometry
        return dataclasses.replace(geometry, gap_function=gf.sampled(geometry.y_wheel, ds))
    if not isinstance(gf, GapEvaluator):
        return geometry
    return dataclasses.replace(geometry, gap_function=SampledWheelGap(
        geometry.gap_function, geometry.y_wheel, ds))
