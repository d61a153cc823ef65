"""CONTACT's rule for the reference angles of nearby separate patches.

Two interpenetration regions of one wheel whose facing ends lie closer than the
combination distance d_sep form one patch; farther apart they are separate
patches, each in the tangent plane of its own weighted contact angle.  Without a
transition the contact angle of the patches jumps where two regions part (at
d = d_sep the combined patch has the weighted mean angle of the two, just beyond
it each has its own), and with it the lateral force.  CONTACT therefore turns the
reference angles of separate patches whose ends lie between d_sep and d_turn
apart (default 2 d_sep - d_comb) towards their weighted mean:

    alpha_comb = (W_1 alpha_1 + W_2 alpha_2) / (W_1 + W_2)
    alpha_i   += f (alpha_comb - alpha_i),   f = (d_turn - d) / (d_turn - d_sep)

for each pair of neighbouring patches (sorted along the rail) whose angles differ
by at most a_sep, with W_i the patch's total weight (the weight of its reference
point and angle, :data:`railcontact.geometry.regions.GAP_WEIGHT`) and the a-priori
angles on the right-hand side, so that a patch between two others is turned by
both (CONTACT's user guide, section "Identification of contact patches", and its
parameter D_TURN).
"""

from __future__ import annotations

import math

import numpy as np


def default_turn_distance(separation: float, full_interaction: float) -> float:
    """CONTACT's default d_turn = 2 d_sep - d_comb [m]."""
    return 2.0 * separation - full_interaction


def turned_angles(angles, weights, distances, separation: float, turn_distance: float,
                  max_angle: float = math.pi / 2) -> np.ndarray:
    """Reference angles of separate patches turned towards their weighted mean.

    Parameters
    ----------
    angles : array_like
        Weighted contact angle [rad] of each patch of one wheel, in their order
        along the rail profile (any consistent frame: the rule is the same in the
        mirrored left-side frame).
    weights : array_like
        The patches' total weights W_i (> 0).
    distances : array_like
        The distance [m] between the facing ends of each patch and the next (one
        fewer than the patches; the measure of the combination,
        :func:`railcontact.geometry.regions.end_distance`, so that at d = d_sep a
        combined patch and two fully turned ones share the weighted angle).
    separation : float
        d_sep [m]: patches closer than this are combined, not turned.
    turn_distance : float
        d_turn [m]; no turning where it does not exceed ``separation``.
    max_angle : float
        a_sep [rad]: patches whose angles differ by more are left alone.

    Returns the turned angles, in the order given.
    """
    a = np.asarray(angles, dtype=float)
    out = a.copy()
    if a.size < 2 or not turn_distance > separation:
        return out
    w = np.asarray(weights, dtype=float)
    for i, dist in enumerate(np.asarray(distances, dtype=float)):
        j = i + 1
        if abs(a[i] - a[j]) > max_angle or not separation <= dist <= turn_distance \
                or not w[i] + w[j] > 0:
            continue
        comb = (w[i] * a[i] + w[j] * a[j]) / (w[i] + w[j])
        f = (turn_distance - dist) / (turn_distance - separation)
        out[i] += f * (comb - a[i])
        out[j] += f * (comb - a[j])
    return out
