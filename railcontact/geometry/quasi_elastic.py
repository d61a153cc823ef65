"""Arnold's quasi-elastic contact: the rigid single-point contact constraint with its
maximum regularised (Arnold, Netter & Frik; in the DLR RailwayDynamics Library,
Heckmann et al., "The Wheel-Rail-Contact" (Modelica 2014, revised), eq. 6).

The rigid contact of one wheel is ``z_w + max_s Δ(s; y_w, φ, ψ) = 0`` with the
height function Δ along the wheel profile coordinate s: the wheel touches where
its vertical gap to the rail is smallest, and the contact point jumps where two
parts of the profile (tread and flange root on S1002/60E1) become equally close.
Arnold et al. replace the maximum by a smooth maximum

    smax_α Δ = α ln( ∫ exp(Δ(s)/α) ds / ∫ ds ),     s over the wheel profile,

with α of 1e-5 to 5e-5 m.  Since smax_α Δ ≤ max Δ, the wheel sinks into the rail
by the penetration δ = max Δ − smax_α Δ ≥ 0: the "quasi-elastic" contact, whose δ
is meant to be of the size of the Hertzian approach.  Here Δ(s) = −g(s), the
negative vertical gap of the contact locus (:mod:`railcontact.geometry.locus`) at
the wheel-profile samples s (uniform, ``LOCUS_STEP``), and ∫ ds is the wheel
profile's width L.  For a gap locally parabolic, g ≈ g_min + c (s − s*)², this
gives

    δ = α ln( L √(c / (π α)) ),

logarithmic in the profile's width and the gap's curvature c.

The wheelset's pose: each side's smallest vertical gap equals −δ of that side
(:func:`railcontact.geometry.pose.solve_pose` with the targets δ, iterated since δ
depends on the roll through the gap's shape).  The contact point's quantities
(lateral positions on wheel and rail, contact angle, rolling radius, the relative
curvatures) are the means over the profile with the weights of the soft maximum,
w(s) ∝ exp(Δ(s)/α) (its gradient with respect to Δ): where two parts of the
profile are nearly equally close the point moves smoothly between them instead of
jumping.  The weights are computed on the locus within ``LOCUS_WINDOW`` (1 mm) of
the closest approach; beyond it a weight is below exp(−1 mm / α) ≤ 2e-9.

The quasi-elastic contact is a geometric constraint: it fixes the vertical
position, not a force.  The normal force follows from the wheel load (the
dynamics' quasi-static loads: N = Q / cos δ_c with the contact angle δ_c), and δ does
not depend on the load.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..core.errors import InputError
from .locus import LOCUS_STEP, Locus, _wheel_samples
from .pose import solve_pose
from .search import _locus_curvatures
from .track import SIDES, Track, Wheelset, WheelsetPose

#: the range of α that Arnold et al. propose [m]
ALPHA_RANGE = (1e-5, 5e-5)
#: weights below this fraction of the largest do not enter the curvature mean
CURVATURE_WEIGHT = 1e-4


@dataclass
class QuasiElasticPoint:
    """The smoothed contact point of one wheel (SI units; track frame).

    ``penetration`` δ [m] (vertical, max Δ − smax_α Δ); ``contact_angle`` [rad];
    ``rolling_radius`` [m]; ``y_rail``, ``y_wheel`` [m] (profile coordinates, positive
    to the field side); ``position`` (3,) [m]; ``curvatures`` (A, B) [1/m];
    ``spread`` [m]: the weights' standard deviation along the wheel profile (the
    width over which the point is smoothed)."""

    side: str
    penetration: float
    contact_angle: float
    rolling_radius: float
    y_rail: float
    y_wheel: float
    position: np.ndarray
    curvatures: tuple
    spread: float


@dataclass
class QuasiElasticContact:
    """The wheelset's pose under the quasi-elastic constraint and its two contact
    points (``points["left"]``, ``points["right"]``); ``alpha`` [m]."""

    pose: WheelsetPose
    alpha: float
    points: dict
    loci: dict = field(repr=False, default_factory=dict)


def soft_min_offset(gap: np.ndarray, step: float, width: float, alpha: float):
    """δ = smin_α(g) − min(g) ≥ 0 [m] of vertical gaps ``gap`` sampled every ``step``
    [m] over a profile of ``width`` [m] (non-finite gaps: off the rail, weight 0), and
    the normalised weights exp(−(g − min g)/α) / Σ."""
    g = np.where(np.isfinite(gap), gap, np.inf)
    gmin = float(np.min(g))
    if not math.isfinite(gmin):
        raise InputError("quasi-elastic contact: the locus has no finite gap")
    e = np.exp(-(g - gmin) / alpha)
    total = float(e.sum())
    return -alpha * math.log(total * step / width), e / total


def _point(loc: Locus, side: str, weights: np.ndarray, delta: float, wheelset: Wheelset,
           track: Track) -> QuasiElasticPoint:
    sgn = 1.0 if side == "right" else -1.0
    r0 = wheelset.nominal_radius
    angle = float(np.dot(weights, np.arctan(np.where(np.isfinite(loc.slope), loc.slope, 0.0))))
    y_rail = float(np.dot(weights, np.where(np.isfinite(loc.y_rail), loc.y_rail, 0.0)))
    y_wheel = float(np.dot(weights, loc.y_wheel))
    radius = r0 + float(np.dot(weights, loc.z_wheel))
    x = float(np.dot(weights, loc.point[0]))
    spread = math.sqrt(max(float(np.dot(weights, (loc.y_wheel - y_wheel) ** 2)), 0.0))
    # curvatures: the weighted mean over the samples that carry weight, at most ~60
    idx = np.flatnonzero(weights >= CURVATURE_WEIGHT * weights.max())
    idx = idx[::max(1, idx.size // 60)]
    AB = np.array([_locus_curvatures(loc, int(i), r0) for i in idx])
    w = weights[idx] / weights[idx].sum()
    A, B = float(w @ AB[:, 0]), float(w @ AB[:, 1])
    z_rail = float(track.rail(side).z_at(y_rail))
    pos = np.array([x, sgn * (track.rail_offset(side) + y_rail), z_rail])
    return QuasiElasticPoint(side, delta, sgn * angle, radius, y_rail, y_wheel, pos, (A, B),
                             spread)


def quasi_elastic_contact(wheelset: Wheelset, track: Track, lateral_shift: float = 0.0,
                          yaw: float = 0.0, alpha: float = 2e-5, roll_start: float = 0.0,
                          tol: float = 1e-13, max_iter: int = 20) -> QuasiElasticContact:
    """The wheelset's vertical position and roll under Arnold's quasi-elastic contact
    and its two smoothed contact points.

    Parameters
    ----------
    wheelset, track : Wheelset, Track
    lateral_shift, yaw : float
        [m], [rad].
    alpha : float
        The regularisation α [m] (Arnold et al.: 1e-5 to 5e-5; α → 0 is the rigid
        single-point contact).
    roll_start : float
        Where the roll search starts [rad].
    tol, max_iter :
        The penetrations' fixed point (they depend on the roll): stop when they
        change by less than ``tol`` [m].
    """
    if not (isinstance(alpha, (int, float)) and 1e-8 <= alpha <= 1e-3):
        raise InputError(f"quasi-elastic alpha = {alpha!r} m: expected a value in "
                         f"[1e-8, 1e-3] m (Arnold et al.: {ALPHA_RANGE[0]:g} to "
                         f"{ALPHA_RANGE[1]:g} m)")
    width = {s: _wheel_samples(wheelset.wheel(s), LOCUS_STEP, wheelset.wheel_offset,
                               wheelset.nominal_radius)[0] for s in SIDES}
    width = {s: float(w[-1] - w[0]) for s, w in width.items()}
    targets = {s: 0.0 for s in SIDES}
    roll = roll_start
    for _ in range(max_iter):
        z, roll, loci = solve_pose(wheelset, track, lateral_shift, yaw, targets, roll0=roll)
        new = {s: soft_min_offset(loci[s].gap, LOCUS_STEP, width[s], alpha)[0] for s in SIDES}
        change = max(abs(new[s] - targets[s]) for s in SIDES)
        targets = new
        if change < tol:
            break
    z, roll, loci = solve_pose(wheelset, track, lateral_shift, yaw, targets, roll0=roll)
    points = {}
    for s in SIDES:
        delta, w = soft_min_offset(loci[s].gap, LOCUS_STEP, width[s], alpha)
        points[s] = _point(loci[s], s, w, targets[s], wheelset, track)
    return QuasiElasticContact(WheelsetPose(lateral_shift, z, roll, yaw), float(alpha), points,
                               loci)


def quasi_elastic_table(wheelset: Wheelset, track: Track, shifts, alpha: float = 2e-5,
                        yaw: float = 0.0):
    """:func:`quasi_elastic_contact` over lateral shifts, as an :class:`xarray.Dataset`
    with the fields of :func:`railcontact.geometry.contact_table` (``delta_r``,
    ``rolling_radius``, ``contact_angle``, ``y_rail``, ``y_wheel``, ``roll``,
    ``vertical``; so :func:`~railcontact.geometry.equivalent_conicity` takes it) and
    the ``penetration`` and ``spread`` of each side."""
    import xarray as xr
    shifts = np.asarray(shifts, dtype=float)
    keys = ("rolling_radius", "contact_angle", "y_rail", "y_wheel", "penetration", "spread")
    out = {k: np.full((shifts.size, 2), np.nan) for k in keys}
    roll, vert = np.full(shifts.size, np.nan), np.full(shifts.size, np.nan)
    r = 0.0
    for i, y in enumerate(shifts):
        c = quasi_elastic_contact(wheelset, track, float(y), yaw, alpha, roll_start=r)
        r = c.pose.roll
        roll[i], vert[i] = c.pose.roll, c.pose.vertical
        for j, s in enumerate(SIDES):
            for k in keys:
                out[k][i, j] = getattr(c.points[s], k)
    dims = ("lateral_shift", "side")
    units = {"rolling_radius": "m", "contact_angle": "rad", "y_rail": "m", "y_wheel": "m",
             "penetration": "m", "spread": "m"}
    data = {k: (dims, out[k], {"units": units[k]}) for k in keys}
    data["delta_r"] = ("lateral_shift", out["rolling_radius"][:, 1] - out["rolling_radius"][:, 0],
                       {"units": "m", "long_name": "rolling radius difference r_right - r_left"})
    data["roll"] = ("lateral_shift", roll, {"units": "rad"})
    data["vertical"] = ("lateral_shift", vert, {"units": "m"})
    return xr.Dataset(data, coords={"lateral_shift": ("lateral_shift", shifts, {"units": "m"}),
                                    "side": ("side", list(SIDES))},
                      attrs={"yaw_rad": yaw, "alpha_m": float(alpha),
                             "nominal_radius_m": wheelset.nominal_radius,
                             "model": "quasi-elastic (Arnold et al.)"})
