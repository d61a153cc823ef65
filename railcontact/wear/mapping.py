"""From local wear on a contact grid to wear depth along the profiles."""

from __future__ import annotations

import numpy as np
from scipy.ndimage import gaussian_filter1d

from ..profiles.profile import Profile


def strip_depth(rate, normal):
    """Wear depth per passage d(y_c) [m] on every strip: sum of rate * dx along x."""
    return rate.sum(axis=0) * normal.dx


def profile_depth(geometry, normal, depth_y, profile: Profile, body: str, s_grid):
    """Map strip depths onto a profile's arc length.

    The contact-local lateral coordinate y_c runs in the tangent plane through the
    reference point; it is mapped to the profile's arc length s = s_ref + sgn y_c (sgn
    = +1 on the right side, -1 on the left, where y_c points to the gauge side of the
    left profile).  The depth is conserved: the integral of depth over s equals the
    integral over y_c (linear interpolation of the strip values onto ``s_grid``,
    rescaled to the strip integral).

    Returns the depth [m] on ``s_grid``.
    """
    y_ref = geometry.y_rail if body == "rail" else geometry.y_wheel
    s_ref = float(profile.arc_length(y_ref))
    sgn = 1.0 if geometry.side != "left" else -1.0
    s_strip = s_ref + sgn * normal.y
    order = np.argsort(s_strip)
    s_strip, d = s_strip[order], depth_y[order]
    ds = normal.dy
    out = np.interp(s_grid, s_strip, d, left=0.0, right=0.0)
    total = float(d.sum() * ds)
    got = float(np.trapezoid(out, s_grid))
    if got > 0 and total > 0:
        out *= total / got
    return out


def wear_profile(profile: Profile, s_grid, depth, body: str) -> Profile:
    """Move the profile points along the inward surface normal by ``depth`` [m]
    (interpolated from ``s_grid``); returns the worn profile."""
    s = profile.arc_length(profile.y)
    w = np.interp(s, s_grid, depth, left=0.0, right=0.0)
    slope = profile.slope(profile.y)
    slope = np.where(np.isfinite(slope), slope, 0.0)
    nrm = np.sqrt(1.0 + slope ** 2)
    # rail material lies at larger z (z down); wheel material towards the axle (smaller z)
    sign = 1.0 if body == "rail" else -1.0
    y_new = profile.y - sign * w * slope / nrm
    z_new = profile.z + sign * w / nrm
    return Profile(y_new, z_new, kind=profile.kind, name=profile.name,
                   smoothing=profile.smoothing)


def removed_area(old: Profile, new: Profile, body: str, n: int = 20000) -> float:
    """Cross-section area [m^2] between two profiles (material removed)."""
    lo, hi = max(old.y_min, new.y_min), min(old.y_max, new.y_max)
    y = np.linspace(lo, hi, n)
    dz = new.z_at(y) - old.z_at(y)
    sign = 1.0 if body == "rail" else -1.0
    return float(np.trapezoid(np.nan_to_num(sign * dz), y))


def arc_length_grid(profile: Profile, step: float):
    """The grid along a profile's arc length [m], from its start to its end in steps
    of ``step``: where wear depths are accumulated."""
    return np.arange(0.0, float(profile.arc_length(profile.y_max)) + step, step)


def smooth_depth(depth, step, length):
    """Gaussian smoothing of a wear depth on a grid of ``step`` with physical length
    ``length`` [m] (2 sigma), the removed area conserved; ``length`` <= 0: unchanged."""
    if length <= 0:
        return depth
    out = gaussian_filter1d(depth, sigma=length / step / 2.0, mode="constant")
    tot, got = depth.sum(), out.sum()
    return out * (tot / got) if got > 0 else out
