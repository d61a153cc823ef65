"""The lateral curvature of a patch's Hertzian force, continuous in the pose.

The finite-difference curvature of the gap at a patch's deepest point
(:func:`railcontact.geometry.wheel_pass.make_patch`,
:func:`railcontact.geometry.search._make_patch`) jumps where the deepest point
jumps between two minima of the gap (S1002 on 60E1's near-conformal tread: 3.95
to 0.28 1/m) or crosses a joint of the profiles' arcs (the flange root at 6.3 mm:
12 to 3.5 1/m), and Hertz's force at the same approach with it, so that no
interpenetration carries the load.  :func:`force_curvature` takes the region's
curvature there (:func:`moment_curvature`, the Hertzian gap with the region's depth
and moment, continuous in the pose), the deepest point's where the gap is
Hertzian.  The compiled case (:mod:`railcontact.cases.compiled_case`), the
per-patch path (:mod:`railcontact.normal.hertz`, ``ContactGeometry.force_curvature``)
and the online dynamics (:mod:`railcontact.dynamics.online_contact`) share it.
Source: Hertz's elliptic contact (Johnson, Contact Mechanics, 1985, ch. 4); the
region's equivalent paraboloid as in the equivalent-elastic contact of MBS codes
(e.g. Piotrowski & Kik, Veh. Syst. Dyn. 46, 2008).
"""

from __future__ import annotations

import math

from numba import njit


@njit(cache=True, nogil=True)
def region_depth(gap, i0, i1):
    """The deepest sample im of region [i0, i1] of a locus's vertical gap ``gap``
    [m] (the first of equal ones) and its interpenetration d = -gap[im] [m] (not
    positive where the region does not interpenetrate)."""
    im = i0
    for i in range(i0, i1 + 1):
        if gap[i] < gap[im]:
            im = i
    return im, -gap[im]


@njit(cache=True, nogil=True)
def deepest_fraction(gap, im):
    """Where between the samples the locus's minimum lies: the offset f in
    [-0.5, 0.5] (samples) from im, the deepest sample, of the vertex of the
    parabola through the gap ``gap`` [m] at im - 1, im and im + 1 (0 at the
    locus's ends, beside a sample without a finite gap and where the three are
    not convex).  Where the deepest sample passes from im to im + 1 (their gaps
    equal) the vertex is half-way between them from either side (f = 0.5 from im,
    -0.5 from im + 1), so that the point :func:`at_fraction` gives is continuous
    in the pose, where the deepest sample is not."""
    n = gap.size
    if im < 1 or im > n - 2:
        return 0.0
    a, b, c = gap[im - 1], gap[im], gap[im + 1]
    if not (math.isfinite(a) and math.isfinite(b) and math.isfinite(c)):
        return 0.0
    den = a - 2.0 * b + c
    if not den > 0.0:
        return 0.0
    return min(max(0.5 * (a - c) / den, -0.5), 0.5)


@njit(cache=True, nogil=True)
def at_fraction(v, im, f):
    """The locus array ``v`` interpolated linearly at sample im + f
    (:func:`deepest_fraction`; ``v`` at im where f is 0)."""
    if f > 0.0:
        return v[im] + f * (v[im + 1] - v[im])
    if f < 0.0:
        return v[im] + f * (v[im] - v[im - 1])
    return v[im]


@njit(cache=True, nogil=True)
def deepest_gap(gap, im):
    """The gap [m] at the locus's minimum between the samples (sample im +
    :func:`deepest_fraction`): the cubic through the four samples about it (im - 1,
    im, im + 1 and the next one on the minimum's side) there, continuous in the pose
    (at f = 0 the sample's own gap; where the deepest sample passes to its neighbour
    both take the same four samples at the same point); the parabola's vertex
    through the three where the fourth has no finite gap (the locus's ends), the
    deepest sample's gap where f is 0.  (The parabola's vertex alone jumps there by
    (gap[im - 1] - gap[im + 2]) / 8.)"""
    f = deepest_fraction(gap, im)
    if f == 0.0:
        return gap[im]
    a, b, c = gap[im - 1], gap[im], gap[im + 1]
    x = abs(f)
    if f < 0.0:
        a, c = c, a                         # mirrored: the minimum towards im - 1
        j = im - 2
    else:
        j = im + 2
    if 0 <= j < gap.size and math.isfinite(gap[j]):
        # Lagrange's cubic through x = -1, 0, 1, 2 (a, b, c, the fourth)
        return (-a * x * (x - 1.0) * (x - 2.0) / 6.0
                + b * (x + 1.0) * (x - 1.0) * (x - 2.0) / 2.0
                - c * (x + 1.0) * x * (x - 2.0) / 2.0
                + gap[j] * (x + 1.0) * x * (x - 1.0) / 6.0)
    return b + 0.5 * x * (c - a) + 0.5 * x * x * (a - 2.0 * b + c)


@njit(cache=True, nogil=True)
def deepest_slope(gap, slope, im):
    """The rail slope dz/dy at the locus's minimum (:func:`deepest_fraction`)
    about the deepest sample im: continuous in the pose where the deepest sample
    passes to its neighbour (where the sample's did not: at 6.76 mm on S1002/60E1's
    flange the force curvature's cos³ of it moved the Hertzian force by 1.6 % of
    the load at each step, with the approach taken at the sample)."""
    return at_fraction(slope, im, deepest_fraction(gap, im))


@njit(cache=True, nogil=True)
def level_curvature(loc, i0, i1, level):
    """Half the lateral curvature B [1/m] of the Hertzian gap with the depth and
    width of region [i0, i1] of a locus at a fraction ``level`` of its depth:
    B = level d / w² cos³(θ), with d the deepest vertical interpenetration (at
    sample im), w half the width of the interval around im where the gap lies
    below -(1 - level) d (its crossings interpolated between the samples) and θ
    the rail's slope angle at the locus's minimum about im (:func:`deepest_slope`;
    the vertical gap turned to the contact plane, as
    :func:`railcontact.geometry.wheel_pass.locus_curvatures`).  For a Hertzian gap, g = -d + B y², it is B itself
    at every level.  NaN where the interval reaches the locus's ends or a sample
    without a finite gap."""
    gap, yr, slope = loc[5], loc[4], loc[6]
    n = gap.size
    im, d = region_depth(gap, i0, i1)
    if not d > 0.0:
        return math.nan
    g0 = -(1.0 - level) * d
    lo = im
    while lo > 0 and gap[lo - 1] < g0:
        lo -= 1
    hi = im
    while hi < n - 1 and gap[hi + 1] < g0:
        hi += 1
    if lo < 1 or hi > n - 2 or not (math.isfinite(gap[lo - 1]) and math.isfinite(gap[hi + 1])):
        return math.nan
    ylo = yr[lo] + (gap[lo] - g0) / (gap[lo] - gap[lo - 1]) * (yr[lo - 1] - yr[lo])
    yhi = yr[hi] + (gap[hi] - g0) / (gap[hi] - gap[hi + 1]) * (yr[hi + 1] - yr[hi])
    w = 0.5 * abs(yhi - ylo)
    if not (w > 0.0 and math.isfinite(w)):
        return math.nan
    return level * d / (w * w) * math.cos(math.atan(deepest_slope(gap, slope, im))) ** 3


@njit(cache=True, nogil=True)
def region_curvature(loc, i0, i1):
    """:func:`level_curvature` between the gap's zero crossings (level 1): the
    Hertzian gap with the interpenetration interval's depth d and half-width w,
    B = d / w² cos³(θ).

    Why: the finite-difference curvature of :func:`railcontact.geometry.wheel_pass.make_patch` is that of the
    deepest point.  In the near-conformal tread contact of S1002 on 60E1 the gap
    across a region 20 mm wide is flat within a micrometre and has two minima; as
    the deepest point jumps from one to the other, B jumps (measured: 3.95 to
    0.28 1/m), and Hertz's force at the same approach with it, by a factor of
    two.  The region's width changes continuously with the pose (but for the
    instant two intervals join: :data:`FORCE_LEVEL`)."""
    return level_curvature(loc, i0, i1, 1.0)


@njit(cache=True, nogil=True)
def moment_curvature(loc, i0, i1):
    """Half the lateral curvature B [1/m] of the Hertzian gap g = -d + B y² with the
    depth d and the moment I = ∫ max(-g, 0)^p dy (p = ``MOMENT_POWER``) of region
    [i0, i1] of a locus: I = c_p d^(p+1/2) / sqrt(B), c_p = ∫ (1 - u²)^p du over
    [-1, 1] (16/15 for p = 2), so B = (c_p d^(p+1/2) / I)², turned to the contact
    plane by cos³(θ) of the rail's slope angle at the locus's minimum
    (:func:`deepest_slope`, as
    :func:`railcontact.geometry.wheel_pass.locus_curvatures`).  The trapezoidal moment over the samples (with the
    region's outer neighbours, outside the interpenetration) is continuous in the
    pose where the deepest point jumps between two minima, where an interval joins
    (it enters with no moment) and where the deepest point crosses a joint of the
    profiles' arcs; the power puts the weight near the deepest point.  For a
    Hertzian gap it is B itself.  NaN where the region reaches the locus's ends."""
    gap, yr, slope = loc[5], loc[4], loc[6]
    n = gap.size
    if i0 < 1 or i1 > n - 2:
        return math.nan
    im, d = region_depth(gap, i0, i1)
    if not d > 0.0:
        return math.nan
    p = MOMENT_POWER
    s = 0.0
    fa = 0.0
    for k in range(i0 - 1, i1 + 1):
        g = gap[k + 1]
        fb = (-g) ** p if g < 0.0 else 0.0
        dy = abs(yr[k + 1] - yr[k])
        if fa + fb > 0.0 and math.isfinite(dy):     # (samples a sparse locus skipped:
            s += 0.5 * (fa + fb) * dy               # outside the interpenetration)
        fa = fb
    if not (s > 0.0 and math.isfinite(s)):
        return math.nan
    c = 16.0 / 15.0 if p == 2 else 4.0 / 3.0
    r = c * d ** (p + 0.5) / s
    return r * r * math.cos(math.atan(deepest_slope(gap, slope, im))) ** 3


#: the region's lateral curvature (:func:`moment_curvature`) takes over from the
#: deepest point's where the region holds a second minimum of the gap (of the
#: vertical interpenetration d): as deep as the deepest within ``TWIN_DEPTH`` d
#: (weight falling linearly to 0 there), parted from it by a barrier that lies
#: ``TWIN_BARRIER`` d or more below the surface (the two in one interpenetration
#: interval; 0 where the barrier reaches the surface, as two regions joined by
#: the combine distance) and ``TWIN_PROMINENCE`` d or more above the second
#: minimum (0 for a minimum being born): each factor is continuous, so the weight
#: is, and it is 1 where the deepest point jumps between two minima of equal depth
TWIN_DEPTH = 0.5
TWIN_BARRIER = 0.5
TWIN_PROMINENCE = 0.005
#: |ln(B_r / B)| (B_r: :func:`moment_curvature`) from which the region's curvature starts to take over, and
#: where it has taken over (:func:`force_curvature`)
DISAGREE = (math.log(1.25), math.log(1.5))
#: the power p (1 or 2) of the interpenetration in :func:`moment_curvature`
MOMENT_POWER = 2


@njit(cache=True, nogil=True)
def twin_weight(gap, i0, i1, im):
    """Weight in [0, 1] of the region's curvature against the deepest point's in
    region [i0, i1] of a locus whose deepest sample is im (``TWIN_DEPTH``):
    the largest over the region's other local minima of the product of the three
    clipped factors."""
    d = -gap[im]
    if not d > 0.0:
        return 0.0
    u = 0.0
    for step in (-1, 1):            # outward from im, the barrier the running maximum
        gb = gap[im]
        k = im + step
        while i0 < k < i1:
            gb = max(gb, gap[k])
            if gap[k] <= gap[k - 1] and gap[k] < gap[k + 1]:
                s1 = 1.0 - (gap[k] - gap[im]) / (TWIN_DEPTH * d)
                s2 = -gb / (TWIN_BARRIER * d)
                s3 = (gb - gap[k]) / (TWIN_PROMINENCE * d)
                w = (min(max(s1, 0.0), 1.0) * min(max(s2, 0.0), 1.0)
                     * min(max(s3, 0.0), 1.0))
                u = max(u, w)
            k += step
    return u


@njit(cache=True, nogil=True)
def force_curvature(loc, i0, i1, im, B):
    """The lateral curvature [1/m] of region [i0, i1]'s Hertzian force: the deepest
    point's B blended (in ln B) with the region's (:func:`moment_curvature`, B_r)
    by the larger of :func:`twin_weight` and the disagreement weight
    (|ln(B_r / B)| between the bounds of ``DISAGREE``, linear); B where the
    weight is 0 or B_r is undefined.  Continuous in the pose: the weight is 1 on
    both sides of wherever B jumps (two minima of equal depth, a joint of the
    profiles' arcs), and B_r is continuous (measured on the 1000-case sweep:
    every case meets the load, against 987 with B alone).  Where the gap is
    Hertzian, B_r is B and the patch is as before."""
    if not B > 0.0:
        return B
    br = moment_curvature(loc, i0, i1)
    if not br > 0.0:
        return B
    # where the two disagree by more than DISAGREE[0] in ln B (a gap that is not
    # Hertzian across the region, e.g. the deepest point next to a joint of the
    # profiles' arcs, where their curvature jumps), the region's takes over too
    lo, hi = DISAGREE
    u = min(max((abs(math.log(br / B)) - lo) / (hi - lo), 0.0), 1.0)
    u = max(u, twin_weight(loc[5], i0, i1, im))
    if not u > 0.0:
        return B
    return math.exp(u * math.log(br) + (1.0 - u) * math.log(B))
