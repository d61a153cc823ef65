"""Contact regions and their territories (railcontact.geometry.regions)."""

import math

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
