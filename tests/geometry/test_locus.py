"""Contact locus and minimum gap (railcontact.geometry.locus)."""

import math

import numpy as np

from railcontact.geometry import Track, Wheelset
from railcontact.geometry.locus import compute_locus, min_gap
from railcontact.profiles import rail_profile, s1002


def test_min_gap_on_a_locus_window_equals_the_full_search():
    """Searching only the wheel samples of a locus at a roll within 1e-4 rad gives the
    same minimum gap, to the bit, as the search over the whole wheel (tread, flange
    root and flange positions)."""
    ws, tr = Wheelset(s1002()), Track(rail_profile("60E1", math.atan(1 / 40)))
    for y in (-3e-3, 2e-3, 6e-3, 8e-3):
        for side in ("left", "right"):
            loc = compute_locus(ws, tr, side, y, 0.0, 2e-4, 1e-3)
            i0, i1 = loc.samples
            assert 0 <= i0 < i1 and loc.y_wheel.size == i1 - i0
            for roll in (2e-4, 2.5e-4, 1.1e-4):
                full = min_gap(ws, tr, side, y, 0.0, roll, 1e-3)
                assert np.isfinite(full)
                assert min_gap(ws, tr, side, y, 0.0, roll, 1e-3, samples=(i0, i1)) == full
