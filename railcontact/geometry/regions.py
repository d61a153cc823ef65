"""Contact regions on a locus: the interpenetration regions of a side, combined
where closer than ``combine_distance``, their territories (halfway to their
neighbours) and their weighted contact angles (CONTACT's weights)."""

from __future__ import annotations

import math

import numpy as np

from .locus import Locus


#: exponent of the interpenetration in the weights of a patch's reference point and
#: contact angle: CONTACT's default weights each locus sample by the integral of the
#: squared interpenetration over x, which for a parabolic gap in x grows as (-g)^2.5
#: (docs/tuning.md, section "Geometry search")
GAP_WEIGHT = 2.5



def _end_point(loc: Locus, i: int, k: int):
    """Rail-surface point (y, z) [m] where the interpenetration region ending at
    locus sample i ends towards its neighbour k = i +- 1: the zero of the gap
    interpolated between them, so that it moves continuously with the
    interpenetration."""
    zr = loc.gap + loc.point[2]
    gi, gk = loc.gap[i], loc.gap[k]
    t = gi / (gi - gk) if np.isfinite(gk) and gk > 0 > gi else 0.0
    return (loc.y_rail[i] + t * (loc.y_rail[k] - loc.y_rail[i]),
            zr[i] + t * (zr[k] - zr[i]) if np.isfinite(zr[k]) else zr[i])



def x_extent(loc: Locus, i0: int, i1: int):
    """The extent [m] along the track of the interpenetration of locus samples i0 ..
    i1: each wheel circle's chord through the rail, x_i -+ sqrt(2 rho_i (-g_i))
    (rho_i its radius, g_i its vertical gap), at the samples that interpenetrate."""
    g = loc.gap[i0:i1 + 1]
    inside = np.isfinite(g) & (g < 0.0)
    if not inside.any():
        x = loc.point[0, i0:i1 + 1]
        return float(x.min()), float(x.max())
    P = loc.point[:, i0:i1 + 1][:, inside]
    d = P - np.asarray(loc.origin, dtype=float)[:, None]
    axle = np.asarray(loc.axes, dtype=float)[:, 1]
    rho = np.linalg.norm(d - axle[:, None] * (axle @ d)[None, :], axis=0)
    half = np.sqrt(2.0 * rho * (-g[inside]))
    return float((P[0] - half).min()), float((P[0] + half).max())



def end_distance(loc: Locus, i: int, j: int, first: int | None = None,
                 last: int | None = None) -> float:
    """Distance [m] between the facing ends of two interpenetration regions, the
    one ending at locus sample i and the one starting at sample j > i, on the rail
    surface: CONTACT measures it in y and z, so that a region on the flange flank,
    below one on the gauge corner, lies apart from it however close their lateral
    positions (its ends interpolated, :func:`_end_point`).  With the regions'
    other ends ``first`` (of the one ending at i) and ``last`` (of the one starting
    at j) also along the track: the gap between their extents in x
    (:func:`x_extent`; CONTACT measures distances on the interpenetration areas'
    extents in x, y and z, user guide, "potential contact area"), which parts a
    yawed wheelset's flange contact, far ahead of its flange-root contact, from it."""
    (yi, zi), (yj, zj) = _end_point(loc, i, i + 1), _end_point(loc, j, j - 1)
    dx = 0.0
    if first is not None and last is not None:
        a0, a1 = x_extent(loc, first, i)
        b0, b1 = x_extent(loc, j, last)
        dx = max(0.0, b0 - a1, a0 - b1)
    return float(math.sqrt((yj - yi) ** 2 + (zj - zi) ** 2 + dx * dx))



def contact_regions(loc: Locus, rigid: bool, combine_distance: float):
    """Index ranges [i0, i1] of the interpenetration regions of a locus, each with
    the joins inside it where regions closer than ``combine_distance`` were
    combined: (rail-profile position halfway between the facing ends [m], their
    distance [m], :func:`end_distance`)."""
    if rigid:
        return [(loc.i_min, loc.i_min, ())]
    inside = loc.gap < 0.0
    if not inside.any():
        return [(loc.i_min, loc.i_min, ())]
    d = np.diff(inside.astype(int))
    starts = list(np.flatnonzero(d == 1) + 1)
    ends = list(np.flatnonzero(d == -1))
    if inside[0]:
        starts.insert(0, 0)
    if inside[-1]:
        ends.append(inside.size - 1)
    runs = [[int(a), int(b)] for a, b in zip(starts, ends)]
    merged = [runs[0] + [[]]]
    for a, b in runs[1:]:
        end = merged[-1][1]
        dist = end_distance(loc, end, a, merged[-1][0], b)
        if dist < combine_distance:
            merged[-1][1] = b
            merged[-1][2].append((0.5 * float(loc.y_rail[a] + loc.y_rail[end]), float(dist)))
        else:
            merged.append([a, b, []])
    return [(a, b, tuple(j)) for a, b, j in merged]



def territories(loc: Locus, regions) -> list:
    """Rail-profile lateral bounds (y_min, y_max) [m] of each region's territory:
    halfway between its ends and the facing ends of the neighbouring regions of the
    same locus (unbounded without a neighbour on that side)."""
    spans = [(float(min(loc.y_rail[a], loc.y_rail[b])), float(max(loc.y_rail[a], loc.y_rail[b])))
             for a, b, _ in regions]
    out = []
    for lo, hi in spans:
        below = [h for l, h in spans if h < lo]
        above = [l for l, h in spans if l > hi]
        out.append((0.5 * (lo + max(below)) if below else -math.inf,
                    0.5 * (hi + min(above)) if above else math.inf))
    return out



def weighted_angle(loc: Locus, i0: int, i1: int):
    """Weighted contact angle [rad] (side frame) and total weight of the region
    [i0, i1] of a locus (the weights of :func:`_make_patch`)."""
    sl = slice(i0, i1 + 1)
    w = loc.weights(sl, GAP_WEIGHT)
    if not w.sum() > 0:
        return float(np.arctan(loc.slope[loc.i_min])), 0.0
    return (float(np.dot(w, np.arctan(loc.slope[sl])) / w.sum()),
            float(w.sum() * abs(loc.y_wheel[1] - loc.y_wheel[0])))
