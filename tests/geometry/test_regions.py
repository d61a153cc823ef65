"""Contact regions and their territories (railcontact.geometry.regions)."""

import math

import numpy as np
import pytest

from railcontact.geometry import Track, Wheelset, find_contact
from railcontact.profiles import rail_profile, s1002


def _two_patch_contact():
    """S1002 on 60E1 1:40 at 5.40 mm shift: the right wheel touches with a flange
    root region (0.33 rad) and, a few mm to the field side, a shallow tread region
    (0.15 rad) just entering the contact."""
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    c = find_contact(ws, tr, lateral_shift=5.3976e-3, vertical_force=6e4,
                     interpenetration={"left": 74.069e-6, "right": 90.303e-6})
    return [p for p in c.patches if p.side == "right"]


def test_patch_bounds_lie_halfway_between_the_regions():
    """Each patch owns the band of its tangent plane up to halfway to the other
    region of its wheel: the two finite bounds meet at one rail position between
    the regions, the far bounds are open, and each region lies in its own band."""
    pats = _two_patch_contact()
    assert len(pats) == 2
    meet = []
    for p in pats:
        lo, hi = p.bounds
        assert math.isinf(lo) != math.isinf(hi)
        b = hi if math.isinf(lo) else lo
        meet.append(p.y_rail + b * math.cos(p.contact_angle))   # right wheel: y along t
        assert lo < p.extent[2] < p.extent[3] < hi
    assert meet[0] == pytest.approx(meet[1], abs=1e-9)
    ys = sorted(p.y_rail for p in pats)
    assert ys[0] < meet[0] < ys[1]


def test_region_distance_along_the_track(testbank):
    """mbench_conf.inp (yaw 24 mrad, y_ws 6.25 mm): the flange contact lies 26 mm
    ahead of the flange-root one.  On CONTACT's contact locus (the ``.inp`` rule)
    their facing ends are 7.875 mm apart in y and z (CONTACT prints ends 7.881 mm
    apart), under D_SEP = 9 mm, but their interpenetration areas' extents along
    the track ([8.38, 19.84] and [-17.47, -7.08] mm, each wheel circle's chord
    through the rail; CONTACT's [8.45, 19.74] and [-17.45, -7.11]) are 15.5 mm
    apart: 17.35 mm in x, y and z (CONTACT 17.44), so that CONTACT's two patches
    are two (CONTACT measures on the extents in x, y and z)."""
    from railcontact.cases.bodies import build_wheelset_track, contact_search
    from railcontact.cases.case import case_from_dict
    from railcontact.contact_inp import load_inp
    from railcontact.geometry.locus import depth_at
    from railcontact.geometry.regions import contact_regions, end_distance, x_extent
    path = testbank / "examples_conformal" / "mbench_conf.inp"
    (m,) = load_inp(path)
    case = case_from_dict(m.raw, path.parent)
    ws, tr = build_wheelset_track(case)
    s = case.wheel_rail
    d = depth_at(ws, tr, s.side, s.lateral_shift, s.vertical_position, s.roll, s.yaw)
    loc = contact_search(case, interpenetration={s.side: d}, bodies=(ws, tr)).loci[s.side]
    (a0, a1, _), (b0, b1, _) = contact_regions(loc, False, 0.0)
    assert end_distance(loc, a1, b0) == pytest.approx(7.881e-3, abs=0.02e-3)
    assert end_distance(loc, a1, b0, a0, b1) == pytest.approx(17.438e-3, abs=0.1e-3)
    fa, fb = x_extent(loc, a0, a1), x_extent(loc, b0, b1)
    assert fa[0] > 0 > fb[1] and fa[0] - fb[1] == pytest.approx(15.46e-3, abs=0.02e-3)
    # the chord of each circle: x +- sqrt(2 rho (-g)) at its deepest sample
    k = a0 + int(np.argmin(loc.gap[a0:a1 + 1]))
    rho = ws.nominal_radius + loc.z_wheel[k]
    assert fa[1] - fa[0] >= 2 * np.sqrt(2 * rho * -loc.gap[k]) * 0.999
    assert len(contact_regions(loc, False, 9e-3)) == 2
