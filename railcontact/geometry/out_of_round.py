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
from dataclasses import dataclass

import numpy as np

from ..core.errors import InputError
from ..profiles.profile import Profile
from ..profiles.wheel_slices import WheelSlices


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
        and wheel-profile coordinates y_w [m]."""
        return self.slices.radial_deviation(theta, y_w, self.reference)

    def patch_gap(self, gap, y_w0: float, radius: float, angle: float):
        """The patch's gap function ``gap`` (a GapEvaluator) with the deviation:
        :class:`OutOfRoundGap`."""
        return OutOfRoundGap(gap, self, float(y_w0), float(radius), float(angle))


class OutOfRoundGap:
    """A patch's undeformed distance with the wheel's radial deviation (module
    docstring); every other attribute is that of the wrapped gap evaluator."""

    def __init__(self, gap, wheel: OutOfRoundWheel, y_w0: float, radius: float,
                 angle: float):
        self._gap, self._wheel = gap, wheel
        self._y_w0, self._radius = y_w0, radius
        self._cos = math.cos(angle)

    def __getattr__(self, name):
        return getattr(self._gap, name)

    def _deviation(self, x, ys):
        theta = -self._wheel.pitch + x / self._radius
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
