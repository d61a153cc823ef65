"""Conformal contact: the patch on a curved reference surface (CONTACT's DISCNS = 4).

In the flange root of worn profiles, in grooves and on roller rigs the contact
normal turns across the patch, so that a single tangent plane (the planar
approach) measures the gap along the wrong direction and misses how the rigid
slip changes with the orientation of the surface.  The conformal approach
(Vollebregt & Segal, VSD 52 suppl., 2014, "Solving conformal wheel-rail contact
problems"; Vollebregt, VSD 56, 2018, "Conformal contact: corrections and new
results"; CONTACT's user guide, "Conformal contact") works on a curved reference
surface instead:

* the surface is prismatic along the rolling direction x; its cross-section is a
  curve through the patch, here the mid-line between the undeformed rail and
  wheel surfaces: in the patch's tangent-plane coordinates (y along y_c, b along
  the normal n, :mod:`railcontact.geometry.gap`) the points y y_c + b(y) n with
  b(y) halfway between the two surfaces along n;
* the surface is developed along the curve's arc length s: the boundary-element
  grid lies on (x, s), with the half-space influence coefficients of that flat
  grid (CONTACT's INFLCF = 2), or Blanco's, corrected for the turning of the
  surface between the elements (:class:`ConformalInfluence`, CONTACT's INFLCF = 4;
  :mod:`railcontact.normal.conformal_influence`);
* the undeformed distance of element (x, s) is measured along the local normal
  n(s) of the curve (:class:`ConformalGap`);
* the rigid slip follows the local orientation: with D(s) the angle from the
  patch's tangent to the curve's at s (positive from y_c towards n), a(s), b(s)
  the curve point, and the patch's kinematic creepages (xi, eta, phi) and
  phi' = omega . y_c / V (``ContactGeometry.spin_derivative``),

      w_x(x, s) = xi - phi a(s) - phi' b(s),
      w_y(x, s) = eta cos D(s) + phi(s) x,   phi(s) = phi cos D + phi' sin D,

  (the wheel's rigid rotation omega = V (phi' y_c - phi n) + omega_x x_c about the
  curve point; the terms of omega_x, of order yaw x (a sin D - b cos D) / r0,
  and the normal rigid velocity, zero in steady rolling, dropped).  For a
  straight curve (b = 0, D = 0) this is the planar (xi - phi y, eta + phi x);
* the patch's forces are the tractions turned back to the patch's tangent plane
  (CONTACT's "bar" forces): with tau_x, tau_s and p on the wheel,

      F_x = sum tau_x dA,  F_y = sum (tau_s cos D + p sin D) dA,
      F_n = sum (p cos D - tau_s sin D) dA,

  and CONTACT's "tilde" F_n = sum p dA, the pressure's integral on the surface.

Units: SI (m, rad).  The kernels are compiled (Numba); the curve is sampled once
per patch.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from ..core.errors import InputError
from .contact import ContactGeometry
from .gap import (GapEvaluator, SampledWheelGap, Spline, _rail_distance, _wheel_newton,
                  sane_gap)

#: spacing [m] of the samples of the reference curve along the patch's tangent y
CURVE_STEP = 2.5e-5
#: the curve is sampled this far [m] beyond the interpenetration region on each side
#: (plus four times its width): the potential contact area and its enlargements
#: lie inside; beyond, the curve is continued straight
CURVE_MARGIN = 3e-3
#: a half-distance between the surfaces beyond this [m] along the patch normal ends
#: the curve (the normal left the surfaces: the other wall of a groove, the flange).
#: A wheel section of 10 mm radius in a 10.02 mm groove (groove_li case 8) is in
#: contact up to 47 deg from the bottom, 3.2 mm deep along the patch normal: with
#: 2 mm the curve stopped at 37 deg and went on straight, 2 columns of contact
#: fewer than CONTACT's (2309 against 2337 elements with Blanco's coefficients; 5 mm:
#: 2337, and the half-space case 4 2269 against 2265, before 2275)
CURVE_REACH = 5e-3


@njit(cache=True, nogil=True)
def _mid_offsets(ys, frame, rail, wheel):
    """Half the sum of the distances along the normal n of the patch ``frame``
    (:class:`~railcontact.geometry.gap.PatchFrame`) from its tangent-plane points
    C + ys t (side frame) to the rail and to the wheel (at x = 0; ``rail``,
    ``wheel`` the profiles' :class:`~railcontact.geometry.gap.Spline`): the offset
    of the mid-line between the surfaces (NaN where a surface is missed)."""
    C, t, n, y_off, Rt, O = frame.C, frame.t, frame.n, frame.y_off, frame.Rt, frame.O
    e, r0 = frame.e, frame.r0
    rb, rc, wb, wc = rail.breaks, rail.coefs, wheel.breaks, wheel.coefs
    out = np.empty(ys.size)
    kr = -1
    kw = -1
    tr = 0.0
    tw = 0.0
    nl0 = Rt[0, 0] * n[0] + Rt[0, 1] * n[1] + Rt[0, 2] * n[2]
    nl1 = Rt[1, 0] * n[0] + Rt[1, 1] * n[1] + Rt[1, 2] * n[2]
    nl2 = Rt[2, 0] * n[0] + Rt[2, 1] * n[1] + Rt[2, 2] * n[2]
    for i in range(ys.size):
        tr, kr = _rail_distance(ys[i], C, t, n, y_off, rb, rc, tr if math.isfinite(tr) else 0.0,
                                kr)
        d0 = C[0] - O[0]
        d1 = C[1] + ys[i] * t[1] - O[1]
        d2 = C[2] + ys[i] * t[2] - O[2]
        l0 = Rt[0, 0] * d0 + Rt[0, 1] * d1 + Rt[0, 2] * d2
        l1 = Rt[1, 0] * d0 + Rt[1, 1] * d1 + Rt[1, 2] * d2
        l2 = Rt[2, 0] * d0 + Rt[2, 1] * d1 + Rt[2, 2] * d2
        tw, kw = _wheel_newton(l0, l1, l2, nl0, nl1, nl2, e, r0, wb, wc,
                               tw if math.isfinite(tw) else 0.0, kw)
        out[i] = 0.5 * (tr + tw)
    return out


@njit(cache=True, nogil=True)
def _normal_gap_kernel(xp, P, N, frame, rail, wheel):
    """Distance along the unit normals N[i] (side frame) between the rail and the
    wheel through the points P[i] + xp[i] (1, 0, 0): negative where they overlap
    (NaN where a surface is missed); the wheelset's axes and the rail's offset from
    the patch ``frame``, the profiles ``rail``, ``wheel`` as in :func:`_mid_offsets`."""
    y_off, Rt, O, e, r0 = frame.y_off, frame.Rt, frame.O, frame.e, frame.r0
    rb, rc, wb, wc = rail.breaks, rail.coefs, wheel.breaks, wheel.coefs
    h = np.empty(xp.size)
    kr = -1
    kw = -1
    zero = np.zeros(3)
    for i in range(xp.size):
        n = N[i]
        C = P[i]
        tr, kr = _rail_distance(0.0, C, zero, n, y_off, rb, rc, 0.0, kr)
        nl0 = Rt[0, 0] * n[0] + Rt[0, 1] * n[1] + Rt[0, 2] * n[2]
        nl1 = Rt[1, 0] * n[0] + Rt[1, 1] * n[1] + Rt[1, 2] * n[2]
        nl2 = Rt[2, 0] * n[0] + Rt[2, 1] * n[1] + Rt[2, 2] * n[2]
        d0 = C[0] + xp[i] - O[0]
        d1 = C[1] - O[1]
        d2 = C[2] - O[2]
        l0 = Rt[0, 0] * d0 + Rt[0, 1] * d1 + Rt[0, 2] * d2
        l1 = Rt[1, 0] * d0 + Rt[1, 1] * d1 + Rt[1, 2] * d2
        l2 = Rt[2, 0] * d0 + Rt[2, 1] * d1 + Rt[2, 2] * d2
        tw, kw = _wheel_newton(l0, l1, l2, nl0, nl1, nl2, e, r0, wb, wc, 0.0, kw)
        g = tr - tw
        h[i] = g if math.isfinite(g) else np.nan
    return h


@dataclass(frozen=True)
class ReferenceCurve:
    """The cross-section of a patch's curved reference surface, in the patch's
    tangent-plane coordinates: arc length ``s`` [m] (0 at the patch's reference
    point, increasing with the patch coordinate y), the curve point ``a`` along
    y_c and ``b`` along the normal n [m], and the angle ``turn`` [rad] from y_c to
    the curve's tangent (towards n), sampled; linear interpolation between the
    samples, straight continuation beyond them."""

    s: np.ndarray
    a: np.ndarray
    b: np.ndarray
    turn: np.ndarray

    def at(self, s):
        """(a, b, D) [m, m, rad] at arc lengths ``s`` [m] (any shape)."""
        s = np.asarray(s, dtype=float)
        lo, hi = self.s[0], self.s[-1]
        sc = np.clip(s, lo, hi)
        a = np.interp(sc, self.s, self.a)
        b = np.interp(sc, self.s, self.b)
        D = np.interp(sc, self.s, self.turn)
        beyond = s - sc                       # straight continuation at the ends
        return a + beyond * np.cos(D), b + beyond * np.sin(D), D

    def s_of_y(self, y):
        """Arc length [m] at the patch coordinate y [m] (the tangent-plane point's
        abscissa a; extrapolated straight beyond the samples)."""
        y = np.asarray(y, dtype=float)
        s = np.interp(y, self.a, self.s)
        lo = y < self.a[0]
        hi = y > self.a[-1]
        s = np.where(lo, self.s[0] - (self.a[0] - y) / max(math.cos(self.turn[0]), 1e-3), s)
        return np.where(hi, self.s[-1] + (y - self.a[-1]) / max(math.cos(self.turn[-1]), 1e-3),
                        s)

    @property
    def is_flat(self) -> bool:
        return bool(np.all(self.turn == 0.0))


def _splines(gapf: GapEvaluator):
    """The rail's and the wheel's :class:`~railcontact.geometry.gap.Spline` of a
    patch's gap evaluator."""
    return (Spline(gapf.rail._breaks, gapf.rail._coefs),
            Spline(gapf.wheel._breaks, gapf.wheel._coefs))


def reference_curve(gapf: GapEvaluator, y_lo: float, y_hi: float,
                    step: float = CURVE_STEP) -> ReferenceCurve:
    """The mid-line between rail and wheel across a patch (patch coordinates y
    from ``y_lo`` to ``y_hi`` [m], which must hold 0), from the patch's gap
    evaluator: the offsets b(y) halfway between the surfaces along the patch
    normal at x = 0, cut where a surface is missed or the mid-line moves more than
    ``CURVE_REACH`` from its offset at y = 0 (the arc length's origin)."""
    if not (y_lo < 0.0 < y_hi):
        raise InputError(f"reference curve over y = [{y_lo!r}, {y_hi!r}] m: expected a range "
                         "around the patch's reference point (0)")
    n_lo, n_hi = int(math.ceil(-y_lo / step)), int(math.ceil(y_hi / step))
    y = np.arange(-n_lo, n_hi + 1) * step
    b = _mid_offsets(np.ascontiguousarray(gapf.sign * y), gapf.patch_frame, *_splines(gapf))
    i0 = n_lo
    if not math.isfinite(b[i0]):
        raise InputError("reference curve: the patch's normal through its reference point "
                         "misses the rail or the wheel")
    ok = np.isfinite(b) & (np.abs(b - b[i0]) < CURVE_REACH)
    bad_lo = np.flatnonzero(~ok[:i0])
    bad_hi = np.flatnonzero(~ok[i0:])
    lo = bad_lo[-1] + 1 if bad_lo.size else 0
    hi = i0 + bad_hi[0] if bad_hi.size else y.size
    y, b = y[lo:hi], b[lo:hi]
    i0 -= lo
    if y.size < 3:
        raise InputError("reference curve: fewer than 3 points between the surfaces")
    db = np.gradient(b, y)
    ds = np.hypot(np.diff(y), np.diff(b))
    s = np.concatenate([[0.0], np.cumsum(ds)])
    s -= s[i0]
    return ReferenceCurve(s, y, b, np.arctan(db))


def flat_curve(y_lo: float, y_hi: float) -> ReferenceCurve:
    """The straight reference curve over [y_lo, y_hi] [m]: the planar approach."""
    y = np.array([y_lo, 0.0, y_hi])
    return ReferenceCurve(y.copy(), y, np.zeros(3), np.zeros(3))


class ConformalGap:
    """Undeformed distance h(x, s) [m] of a patch on its curved reference surface:
    along the local normal of the curve at arc length s, through the surface point
    at x along the rolling direction (the same rail and wheel surfaces as the
    planar :class:`~railcontact.geometry.gap.GapEvaluator` ``gapf``).

    ``planar``: CONTACT's rule instead (its source ``m_wr_undefdist.f90``,
    ``wr_ud_planar`` with ``curved_sc_to_planar_sp``): the planar gap function
    ``planar`` (a :class:`~railcontact.geometry.gap.SampledWheelGap`: the wheel
    linear between profile samples one DS apart) at the tangent-plane point
    (x, a(s)) below the curve point, along the patch normal, times cos D(s), the
    cosine between the patch normal and the curve's at s (:meth:`sampled`)."""

    def __init__(self, gapf: GapEvaluator, curve: ReferenceCurve, planar=None):
        self.gapf, self.curve, self.planar = gapf, curve, planar
        self._yc = gapf.sign * gapf.t                 # the patch's y_c in the side frame

    def sampled(self, y_wheel: float, ds: float, y_origin: float | None = None):
        """This patch's gap by CONTACT's conformal rule with its wheel samples every
        ``ds`` [m] of the wheel profile's chord length from the lateral wheel
        coordinate ``y_origin`` (default ``y_wheel``, the reference point's)
        (:class:`~railcontact.geometry.gap.SampledWheelGap`)."""
        return ConformalGap(self.gapf, self.curve,
                            SampledWheelGap(self.gapf, y_wheel, ds, y_origin=y_origin))

    def frames(self, s):
        """Surface points and unit normals (side frame) at arc lengths s (1-D)."""
        a, b, D = self.curve.at(s)
        g = self.gapf
        P = g.C[None, :] + a[:, None] * self._yc[None, :] + b[:, None] * g.n[None, :]
        N = -np.sin(D)[:, None] * self._yc[None, :] + np.cos(D)[:, None] * g.n[None, :]
        return P, N

    def __call__(self, x, s):
        x, s = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(s, dtype=float))
        shape = x.shape
        if self.planar is not None:
            a, _, D = self.curve.at(s)
            h = self.planar(x, a) * np.cos(D)
            return sane_gap(np.where(np.isfinite(h), h, 1.0)).reshape(shape)
        P, N = self.frames(s.ravel())
        g = self.gapf
        h = _normal_gap_kernel(np.ascontiguousarray(x.ravel()), np.ascontiguousarray(P),
                               np.ascontiguousarray(N), g.patch_frame, *_splines(g))
        h = np.where(np.isfinite(h), h, 1.0)
        return sane_gap(h).reshape(shape)


#: the variants of Blanco's correction that railcontact computes (CONTACT's VARIANT)
BLANCO_VARIANTS = (3,)


@dataclass(frozen=True)
class ConformalInfluence:
    """Influence coefficients of a conformal patch corrected for the turning of its
    surface (Blanco-Lorenzo, Santamaria, Vadillo & Oyarzabal, Tribology
    International 2016, "On the influence of conformity on wheel-rail rolling
    contact mechanics"; CONTACT's INFLCF = 4, user guide "Conformal contact").

    The half-space coefficients A(I - J) of the developed grid (x, s) give the
    displacements at I of a traction at J in J's own frame (x, t_J, N_J), t_J the
    curve's tangent, N_J its normal at J's column; the surface inclination alpha
    of each column (rotation about x, the curve's angle D plus a constant) turns
    them into I's frame.  ``variant`` 3 (Vollebregt's proposal, the displacements
    transformed): with Delta = alpha_J - alpha_I, c = cos Delta, s = sin Delta, on
    the components (x, s, n) of tractions on the rail and of the displacement
    difference

        B_x. = A_x.,   B_s. = c A_s. - s A_n.,   B_n. = s A_s. + c A_n.

    (``.`` any column x, s, n).  ``method``: "detailed" takes alpha of each column
    as the curve has it; "fast" its least-squares line over the columns (a
    constant radius of curvature)."""

    #: "detailed" (CONTACT's IF_METH = 1) or "fast" (IF_METH = 0)
    method: str = "detailed"
    #: the correction's variant (CONTACT's VARIANT; 3 only)
    variant: int = 3

    def __post_init__(self):
        if self.method not in ("detailed", "fast"):
            raise InputError(f"conformal influence method {self.method!r}: expected "
                             "'detailed' (the inclination of every column) or 'fast' (its "
                             "linear fit)")
        if isinstance(self.variant, bool) or self.variant not in BLANCO_VARIANTS:
            raise InputError(f"conformal influence variant {self.variant!r}: expected 3 "
                             "(the displacements transformed to each element's frame; "
                             "variants 1, 2 and 4 are not implemented)")

    def angles(self, curve: "ReferenceCurve", s) -> np.ndarray:
        """The inclination alpha [rad] of the grid columns at arc lengths ``s`` [m]
        (relative to the patch's tangent plane: the curve's angle D; "fast": its
        least-squares line in s over the columns that the curve's samples reach,
        not its straight continuation beyond them)."""
        s = np.asarray(s, dtype=float)
        D = curve.at(s)[2]
        if self.method == "fast" and s.size >= 2:
            on = (s >= curve.s[0]) & (s <= curve.s[-1])
            if on.sum() < 2:
                on = np.ones(s.shape, dtype=bool)
            c1, c0 = np.polyfit(s[on], D[on], 1)
            D = c0 + c1 * s
        return np.ascontiguousarray(D, dtype=float)


@dataclass
class ConformalPatch:
    """What a conformal patch adds to its :class:`ContactGeometry`: the reference
    curve (``ContactGeometry.surface``), from which the rigid slip and the bar
    forces follow, and the influence coefficients' correction where asked."""

    curve: ReferenceCurve
    #: the planar patch's approach [m] (along its tangent plane's normal)
    planar_approach: float
    #: Blanco's corrected influence coefficients (None: the half-space's)
    influence: ConformalInfluence | None = None


def blanco_influence(geom):
    """The correction of a patch's influence coefficients
    (:class:`ConformalInfluence`, Blanco's), or None for a planar patch or the
    half-space coefficients."""
    surf = getattr(geom, "surface", None)
    return None if surf is None else surf.influence


def influence_angles(geom, s):
    """The column inclinations [rad] of a patch whose influence coefficients are
    corrected (:func:`blanco_influence`) at arc lengths ``s`` [m]; None for a
    planar patch or the half-space coefficients."""
    influence = blanco_influence(geom)
    return None if influence is None else influence.angles(geom.surface.curve, s)


def conformal_geometry(geom: ContactGeometry,
                       influence: ConformalInfluence | None = None) -> ContactGeometry:
    """The patch ``geom`` (planar, from the contact search, with its
    :class:`~railcontact.geometry.gap.GapEvaluator`) on its curved reference
    surface: the gap along the curve's normals on (x, s), the lateral coordinate of
    the extent, bounds and interaction borders turned into arc length, the local
    contact angle of the curve.  A patch without profile geometry (a bodies case)
    is returned as it is.  ``influence``: Blanco's corrected influence
    coefficients for the exact solvers (:class:`ConformalInfluence`; None: the
    half-space's)."""
    gapf = geom.gap_function
    if not isinstance(gapf, GapEvaluator):
        return geom
    x0, x1, y0, y1 = geom.extent if geom.extent is not None else (0.0, 0.0, -1e-3, 1e-3)
    y0, y1 = min(y0, -1e-4), max(y1, 1e-4)
    w = y1 - y0
    curve = reference_curve(gapf, y0 - 4 * w - CURVE_MARGIN, y1 + 4 * w + CURVE_MARGIN)
    s_of = curve.s_of_y
    extent = None if geom.extent is None else (x0, x1, float(s_of(y0)), float(s_of(y1)))
    bounds = tuple(float(s_of(v)) if math.isfinite(v) else v for v in geom.bounds)
    inter = tuple((float(s_of(v)), f) for v, f in geom.interaction)
    cgap = ConformalGap(gapf, curve)
    delta0 = geom.contact_angle
    sgn = 1.0 if geom.side != "left" else -1.0

    def local_angle(s):
        # track convention: the side's angle turned by D (mirrored on the left)
        return delta0 + sgn * curve.at(s)[2]

    # the deepest interpenetration along the curve's normals: the approach
    xs = np.linspace(x0, x1, 9) if geom.extent is not None else np.zeros(1)
    ss = np.linspace(extent[2], extent[3], 41) if extent is not None else np.zeros(1)
    h = cgap(xs[:, None], ss[None, :])
    approach = max(0.0, -float(h.min())) if np.isfinite(h).any() else geom.approach
    return dataclasses.replace(geom, gap_function=cgap, extent=extent, bounds=bounds,
                               interaction=inter, local_contact_angle=local_angle,
                               approach=approach,
                               surface=ConformalPatch(curve, geom.approach, influence))


def conformal_slip(geom: ContactGeometry, creepage, x, s, x_spin=None):
    """The conformal part of the rigid slip on the grid x (rows), s (columns) [m]:
    the difference (w_x, w_y) between the rigid slip of the curved surface (module
    docstring) and the planar (xi - phi s, eta + phi x_spin) of the creepages
    ``creepage`` = (xi, eta, phi) [-, -, 1/m] (``x_spin``: the abscissae at which
    the planar solver takes the spin, default x).  Zero for a planar patch."""
    x = np.asarray(x, dtype=float)
    s = np.asarray(s, dtype=float)
    xs = x if x_spin is None else np.asarray(x_spin, dtype=float)
    surf = getattr(geom, "surface", None)
    if surf is None:
        shape = (x.size, s.size)
        return np.zeros(shape), np.zeros(shape)
    xi, eta, phi = (float(c) for c in creepage)
    dphi = geom.spin_derivative if math.isfinite(geom.spin_derivative) else 0.0
    a, b, D = surf.curve.at(s)
    b = b - float(surf.curve.at(0.0)[1])            # about the reference point
    wx = (-phi * (a - s) - dphi * b)[None, :] * np.ones((x.size, 1))
    phi_s = phi * np.cos(D) + dphi * np.sin(D)
    wy = eta * (np.cos(D) - 1.0)[None, :] + (phi_s - phi)[None, :] * xs[:, None]
    return np.ascontiguousarray(wx), np.ascontiguousarray(wy)


def bar_forces(geom: ContactGeometry, s, pressure, tau_s=None, dA: float = 1.0):
    """CONTACT's bar forces of a conformal patch: (F_n, F_y) [N] in the patch's
    tangent plane from the pressure and the lateral traction on the wheel (along
    the curve; None: none) on a grid with columns at arc lengths ``s``, and the
    tilde F_n = sum p dA (the pressure's integral on the curved surface)."""
    p = np.asarray(pressure, dtype=float)
    ts = np.zeros_like(p) if tau_s is None else np.asarray(tau_s, dtype=float)
    surf = getattr(geom, "surface", None)
    tilde = float(p.sum() * dA)
    if surf is None:
        return tilde, float(ts.sum() * dA), tilde
    D = surf.curve.at(np.asarray(s, dtype=float))[2][None, :]
    fn = float((p * np.cos(D) - ts * np.sin(D)).sum() * dA)
    fy = float((ts * np.cos(D) + p * np.sin(D)).sum() * dA)
    return fn, fy, tilde
