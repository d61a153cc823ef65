"""Out-of-round wheels (a wheel flat, polygonisation) in a wheel-rail patch.

The wheel is given by profiles around its circumference
(:class:`~railcontact.profiles.wheel_slices.WheelSlices`, CONTACT's ``.slcw``)
and turned by its pitch angle theta_ws about the axle: the material angle at the
contact's bottom point is theta_wc = -theta_ws (CONTACT's user guide: negative
pitch angles bring a flat at positive theta_wc into contact), and along the
rolling direction x of a patch theta_wc(x) = -theta_ws + x / r, r the rolling
radius.  The contact search and the patch frame are those of the wheel of
revolution with the reference profile (the wheel's ``profile``); the patch's
undeformed distance adds the radial deviation dr(theta, y_w) of the wheel's
surface from it, along the patch normal,

    h(x, y) = h_rev(x, y) - dr(theta_wc(x), y_w(y)) cos(delta),

with y_w(y) = y_w0 + y cos(delta) the wheel-profile coordinate across the patch
(delta the patch's contact angle).  A first-order perturbation of the wheel's
surface: exact in the radial deviation for small contact angles and slopes of the
deviation (a flat's are a few per cent), as for CONTACT's tread contact.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.interpolate import RegularGridInterpolator

from ..core.errors import InputError
from ..profiles.profile import Profile
from ..profiles.wheel_slices import WheelSlices

#: the deviation is tabulated this far [rad] either side of the contact's angle
#: -pitch, in steps (angle [rad], lateral [m]) (0.1 mm and 0.25 mm on a 0.49 m wheel)
TABLE_ANGLE = 0.15
TABLE_STEPS = (2e-4, 2.5e-4)
#: the locus looks for an out-of-round wheel's lowest point this far [m] either side
#: of the round wheel's, in steps [m]
LOCUS_REACH = 0.05
LOCUS_STEP = 2.5e-4


@dataclass(frozen=True)
class OutOfRoundWheel:
    """A wheel's deviation from its surface of revolution, at its pitch angle.

    Parameters
    ----------
    slices : WheelSlices   the wheel's profiles around its circumference
    reference : Profile    the profile of the wheel of revolution (the search's)
    pitch : float          the wheelset's pitch angle theta_ws [rad]
    """

    slices: WheelSlices
    reference: Profile
    pitch: float = 0.0

    def __post_init__(self):
        if not (isinstance(self.pitch, (int, float)) and math.isfinite(self.pitch)):
            raise InputError(f"wheelset.pitch = {self.pitch!r} rad: expected a finite angle")

    def deviation(self, theta, y_w) -> np.ndarray:
        """Radial deviation dr [m] (positive outwards) at material angles theta [rad]
        and wheel-profile coordinates y_w [m]: bilinear in a table of the slices'
        surface around the contact (``TABLE_ANGLE`` either side of -pitch, steps
        ``TABLE_STEPS``), the surface itself beyond it; 0 off the slices' lateral
        range."""
        th, y = np.broadcast_arrays(np.asarray(theta, float), np.asarray(y_w, float))
        table = self._table()
        out = table(np.stack([th.ravel(), y.ravel()], axis=-1)).reshape(th.shape)
        miss = ~np.isfinite(out)
        if miss.any():
            out[miss] = self.slices.radial_deviation(th[miss], y[miss], self.reference)
        return np.where(np.isfinite(out), out, 0.0)

    def _table(self):
        t = self.__dict__.get("_table_cache")
        if t is None:
            lo, hi = self.slices.y_range
            lo, hi = max(lo, self.reference.y_min), min(hi, self.reference.y_max)
            d_th, d_y = TABLE_STEPS
            th = -self.pitch + np.arange(-TABLE_ANGLE, TABLE_ANGLE + 0.5 * d_th, d_th)
            ys = np.linspace(lo, hi, max(int((hi - lo) / d_y) + 1, 2))
            T, Y = np.meshgrid(th, ys, indexing="ij")
            dr = self.slices.radial_deviation(T, Y, self.reference)
            t = RegularGridInterpolator((th, ys), dr, bounds_error=False, fill_value=np.nan)
            object.__setattr__(self, "_table_cache", t)
        return t

    def locus(self, loc, nominal_radius: float):
        """The contact locus of the wheel of revolution (:class:`~railcontact.geometry
        .locus.Locus`) for this wheel: at each lateral sample the smallest vertical
        gap along the rolling direction, g(x) = g_0 + (r - sqrt(r^2 - x^2)) - dr(theta(x),
        y_w) (the wheel's rise along its circle and its deviation; the rail
        straight), and its x; the wheel point moved there.  Each sample's weight in
        a patch's reference point and angle is the integral over x of its squared
        interpenetration, at that integral's centre in x (``Locus.row_weight``,
        ``Locus.row_x``: CONTACT's 2-D gap function of a wheel from slices,
        compute_wgt_center_2d), so that the reference point lies where an
        out-of-round wheel touches, its interpenetration asymmetric about the
        lowest point on a flat."""
        r = nominal_radius + np.asarray(loc.z_wheel, float)
        ok = np.isfinite(loc.gap)
        if not ok.any():
            return loc
        xs = np.arange(-LOCUS_REACH, LOCUS_REACH + 0.5 * LOCUS_STEP, LOCUS_STEP)
        x0 = loc.point[0][ok]
        rr = r[ok][:, None]
        X = x0[:, None] + xs[None, :]
        rise = rr - np.sqrt(np.maximum(rr * rr - X * X, 0.0))
        dr = self.deviation(-self.pitch + X / rr, np.broadcast_to(loc.y_wheel[ok][:, None],
                                                                   X.shape))
        g = loc.gap[ok][:, None] + rise - dr
        k = np.argmin(g, axis=1)
        rows = np.arange(k.size)
        gap, point = loc.gap.copy(), loc.point.copy()
        gap[ok] = g[rows, k]
        point[0, ok] = X[rows, k]
        point[2, ok] = point[2, ok] - rise[rows, k] + dr[rows, k]
        # the weights of a patch's reference point: the integral over x of each
        # sample's squared interpenetration, and its centre in x (CONTACT's 2-D gap
        # function of an out-of-round wheel, compute_wgt_center_2d); a flat's
        # interpenetration is not symmetric about its lowest point
        pen2 = np.minimum(g, 0.0) ** 2
        tot = pen2.sum(axis=1)
        weight = np.zeros(loc.gap.size)
        xc = loc.point[0].copy()
        weight[ok] = tot * LOCUS_STEP
        has = tot > 0.0
        xc_ok = X[rows, k].copy()
        xc_ok[has] = (pen2[has] * X[has]).sum(axis=1) / tot[has]
        xc[ok] = xc_ok
        return replace(loc, gap=gap, point=point, row_weight=weight, row_x=xc)

    def patch_gap(self, gap, y_w0: float, radius: float, angle: float, x0: float = 0.0):
        """The patch's gap function ``gap`` (a GapEvaluator, its origin at x0 [m]
        along the track from the wheel's lowest point) with the deviation:
        :class:`OutOfRoundGap`."""
        return OutOfRoundGap(gap, self, (float(y_w0), float(x0)), float(radius), float(angle))


class OutOfRoundGap:
    """A patch's undeformed distance with the wheel's radial deviation (module
    docstring); every other attribute is that of the wrapped gap evaluator."""

    def __init__(self, gap, wheel: OutOfRoundWheel, origin: tuple, radius: float,
                 angle: float):
        self._gap, self._wheel = gap, wheel
        (self._y_w0, self._x0), self._radius = origin, radius
        self._cos = math.cos(angle)

    def __getattr__(self, name):
        return getattr(self._gap, name)

    def _deviation(self, x, ys):
        theta = -self._wheel.pitch + (x + self._x0) / self._radius
        dr = self._wheel.deviation(theta, self._y_w0 + ys * self._cos)
        # beyond the slices' lateral range (off the wheel's tread): no deviation
        return np.where(np.isfinite(dr), dr, 0.0) * self._cos

    def __call__(self, x, y):
        h = self._gap(x, y)
        x, ys = np.broadcast_arrays(np.asarray(x, float), self._gap.sign * np.asarray(y, float))
        return h - self._deviation(x, ys)

    def points(self, x, ys, signed=False):
        h = self._gap.points(x, ys, signed)
        s = np.asarray(ys, float) if signed else self._gap.sign * np.asarray(ys, float)
        return h - self._deviation(np.asarray(x, float), s)
