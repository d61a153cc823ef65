"""The surface of a rail given by slices (railcontact.geometry.sliced_surface): through
the slices and between them, interrupted slices, against CONTACT's testbank slices."""

import numpy as np
import pytest

from railcontact.core.errors import InputError, ProfileError
from railcontact.geometry.sliced_surface import SlicedSurface
from railcontact.profiles.slices import RailSlices, read_slices, slices_from_list


def test_slices_list_equals_the_file(testbank):
    prof = testbank / "profiles"
    f = read_slices(prof / "cross_nose.slcs")
    entries = [{"s": float(s), "profile": f"cross_nose/nose_{k + 1}.prr",
                "features": list(f.features[k])} for k, s in enumerate(f.s)]
    lst = slices_from_list(entries, prof)
    a, b = SlicedSurface(f), SlicedSurface(lst)
    s = np.array([-0.0234, 0.0457, 0.0811])
    y = np.array([0.004, 0.006, 0.012])
    assert np.array_equal(a.height(s, y)[0], b.height(s, y)[0])


def test_sliced_surface_through_the_slices_and_along_the_nose(testbank):
    """At a slice the surface is that slice (to the resampling's 0.5 mm spacing:
    measured 0.07 um on the flat crown, 1.3 um on the 5 mm gauge-corner arc, whose
    curvature jumps at its ends), between slices the nose rising 1:10 rises
    linearly (the splines along s are exact for a linear rise)."""
    sl = read_slices(testbank / "profiles" / "cross_nose.slcs")
    surf = SlicedSurface(sl)
    for k in (0, 7, 13, 20):
        p = sl.profiles[k]
        y = np.linspace(0.006, 0.014, 60)                     # the nose's flat crown
        z, d = surf.height(np.full(y.shape, sl.s[k]), y)
        assert np.max(np.abs(z - p.z_at(y))) < 0.1e-6
        assert np.max(np.abs(d - p.slope(y))) < 1.5e-3
        y = np.linspace(0.0017, 0.0048, 40)                   # its 5 mm gauge-corner arc
        z, d = surf.height(np.full(y.shape, sl.s[k]), y)
        assert np.max(np.abs(z - p.z_at(y))) < 1.5e-6
        assert np.max(np.abs(d - p.slope(y))) < 1e-2
    s = np.array([-0.0951, -0.0123, 0.0457571, 0.0999])
    z, _ = surf.height(s, np.full(s.shape, 0.01))
    assert np.allclose(z, -s / 10, atol=1e-9)
    # outside the slices: no surface
    z, _ = surf.height(np.array([0.2]), np.array([0.01]))
    assert np.isnan(z[0])
    with pytest.raises(ProfileError, match="no cross-section"):
        surf.section(0.3)
    assert surf.section(0.0457).curvature(0.003) == pytest.approx(200.0, rel=0.02)
    with pytest.raises(InputError, match="spacing"):
        SlicedSurface(sl, spacing=0.1)


def test_interrupted_slices_a_nose_that_begins_between_slices(testbank):
    """CONTACT's 'interruptions' (cross+wing_extd.slcs): ten slices of a straight
    stock rail (s = -200 to -20 mm, its features 1-6 missing) ahead of the
    artificial nose and wing rail (from s = 0).  The nose exists from the first
    slice that holds it, with a vertical face at s = 0; the stock/wing rail runs
    through all 31 slices, the same surface on both sides of s = 0; at a slice
    the surface is that slice."""
    sl = read_slices(testbank / "profiles" / "cross+wing_extd.slcs")
    assert (sl.features[:10, :6] < 0).all() and (sl.features[10:] >= 0).all()
    surf = SlicedSurface(sl)
    y = np.array([0.014, 0.02, 0.1, 0.12])          # nose crown (2), stock/wing rail crown (2)
    for s, nose in ((-0.1, False), (-0.02, False), (-1e-6, False), (0.0, True), (1e-6, True),
                    (0.05, True)):
        z, _ = surf.height(np.full(y.shape, s), y)
        assert np.isfinite(z[:2]).all() == nose and np.isnan(z[:2]).all() == (not nose)
        assert z[2:] == pytest.approx([-2.5341e-3, -2.5341e-3], abs=1e-6)
        if nose:
            assert z[:2] == pytest.approx([2.25e-3, 2.25e-3], abs=1e-6)
    for k in (0, 5, 9, 10, 20):
        p = sl.profiles[k]
        yk = np.linspace(max(p.y_min, 0.0) + 1e-3, p.y_max - 1e-3, 400)
        z, _ = surf.height(np.full(yk.shape, sl.s[k]), yk)
        flat = np.abs(p.slope(yk)) < 0.5                 # away from the vertical faces
        assert np.nanmax(np.abs(z - p.z_at(yk))[flat]) < 2e-6
    # the wing rail's surface is continuous through the nose's beginning
    yw = np.linspace(0.067, 0.075, 41)
    za, _ = surf.height(np.full(yw.shape, -1e-9), yw)
    zb, _ = surf.height(np.full(yw.shape, 1e-9), yw)
    assert np.max(np.abs(za - zb)) < 1e-8


def test_interrupted_slices_a_part_missing_in_the_middle(testbank):
    """A part missing between two present ones (the nose's crown and field side
    missing from the first ten slices of cross_nose.slcs): no surface across the
    gap there; the parts on either side are the uninterrupted surface (to 0.1 um
    1 mm away from the gap, 3.5 um at its ends, where each piece's spline ends);
    where every part exists the surface is unchanged (the nose rises linearly,
    which the splines through fewer slices keep exactly)."""
    sl = read_slices(testbank / "profiles" / "cross_nose.slcs")
    f = sl.features.copy()
    f[:10, 2] = -1.0
    full = SlicedSurface(sl)
    cut = SlicedSurface(RailSlices(sl.s, sl.profiles, f, name="cut"))
    y = np.linspace(-0.005, 0.04, 4501)
    for s in (-0.05, -1e-9):
        za, _ = full.height(np.full(y.shape, s), y)
        zb, _ = cut.height(np.full(y.shape, s), y)
        gap = np.isnan(zb) & (y > -0.005) & (y < 0.04)
        assert y[gap].min() == pytest.approx(1.47e-3, abs=2e-5)
        assert y[gap].max() == pytest.approx(26.52e-3, abs=2e-5)
        far = ~gap & (np.abs(y - 1.47e-3) > 1e-3) & (np.abs(y - 26.52e-3) > 1e-3)
        assert np.max(np.abs(za - zb)[far]) < 1e-7
        assert np.nanmax(np.abs(za - zb)) < 4e-6
    for s in (0.0, 0.05):
        za, _ = full.height(np.full(y.shape, s), y)
        zb, _ = cut.height(np.full(y.shape, s), y)
        assert np.allclose(za, zb, atol=1e-12, equal_nan=True)
