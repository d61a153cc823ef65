"""Out-of-round wheels in the geometry: the deviation's table against the slices'
surface, and a wheel whose radius is smaller by d all round: its locus's gaps
larger by d, its patch gap by d cos(delta), its lowest points where the round
wheel's are."""

import math

import numpy as np
import pytest

from railcontact.geometry.out_of_round import OutOfRoundWheel
from railcontact.geometry.locus import compute_locus
from railcontact.geometry.track import Track, Wheelset
from railcontact.profiles import get_profile
from railcontact.profiles.profile import Profile
from railcontact.profiles.wheel_slices import WheelSlices, read_wheel_slices


def _smaller(ref: Profile, d: float) -> WheelSlices:
    """Slices of the reference profile with the radius smaller by d [m] all round."""
    p = Profile(ref.y, ref.z - d, kind="wheel", name="smaller")
    return WheelSlices(np.array([-math.pi, 0.0, math.pi - 1e-3]), (p, p, p), "smaller")


def test_table_against_the_slices(testbank):
    """The tabulated deviation (0.1 x 0.25 mm steps) within 2 um of the slices'
    surface on the tread (y_w from -15 to 40 mm) over the flat (1.4 mm deep);
    measured 0.9 um (in the flange root, where S1002 curves most, 6.6 um)."""
    flat = read_wheel_slices(testbank / "examples_basic" / "S1002_flat.slcw", units="mm")
    ref = flat.profiles[0]
    w = OutOfRoundWheel(flat, ref, pitch=-0.65)
    rng = np.random.default_rng(1)
    th = 0.65 + rng.uniform(-0.14, 0.14, 400)
    y = rng.uniform(-0.015, 0.04, 400)
    direct = flat.radial_deviation(th, y, ref)
    assert np.max(np.abs(w.deviation(th, y) - direct)) < 2e-6
    assert direct.min() < -1e-3


def test_uniformly_smaller_wheel():
    wheel = get_profile("S1002", "wheel")
    track = Track(get_profile("60E1", "rail"), None)
    d = 2e-4
    round_ws = Wheelset(wheel, nominal_radius=0.46)
    small_ws = Wheelset(wheel, nominal_radius=0.46,
                        out_of_round=OutOfRoundWheel(_smaller(wheel, d), wheel, pitch=0.3))
    a = compute_locus(round_ws, track, "right", 0.0, 1e-4, 0.0, 0.0)
    b = compute_locus(small_ws, track, "right", 0.0, 1e-4, 0.0, 0.0)
    ok = np.isfinite(a.gap)
    assert np.allclose(b.gap[ok], a.gap[ok] + d, atol=1e-12)
    assert np.allclose(b.point[0][ok], a.point[0][ok], atol=1e-12)
    # a patch's gap: larger by d cos(delta) everywhere
    from railcontact.geometry.out_of_round import OutOfRoundGap

    class Flat:                     # a gap evaluator of a plane, for the wrapper alone
        sign = 1.0

        def __call__(self, x, y):
            return np.zeros(np.broadcast(np.asarray(x), np.asarray(y)).shape)

    g = small_ws.out_of_round.patch_gap(Flat(), 0.0, 0.46, 0.1)
    assert isinstance(g, OutOfRoundGap)
    x = np.linspace(-0.01, 0.01, 5)[:, None]
    y = np.linspace(-0.005, 0.005, 3)[None, :]
    assert np.allclose(g(x, y), d * math.cos(0.1), atol=1e-12)


def test_row_weights_of_a_round_wheel_from_slices():
    """The weights of a patch's reference point (CONTACT's 2-D interpenetration
    centre) for slices of the round wheel itself: each locus sample's integral over
    x of the squared interpenetration of the wheel circle against the straight rail
    equals the closed form of the parabola, (16/15) (-g)^2.5 sqrt(2 r) (r the
    sample's rolling radius), within 1 %, and its centre in x is the lowest point
    (within the 0.25 mm x step of the sampling)."""
    from railcontact.geometry.out_of_round import LOCUS_STEP
    wheel = get_profile("S1002", "wheel")
    track = Track(get_profile("60E1", "rail"), None)
    ws = Wheelset(wheel, nominal_radius=0.46,
                  out_of_round=OutOfRoundWheel(_smaller(wheel, 0.0), wheel, pitch=0.3))
    from railcontact.geometry.locus import min_gap
    z = min_gap(Wheelset(wheel, nominal_radius=0.46), track, "right", 0.0, 0.0, 0.0, 0.0) + 1e-4
    loc = compute_locus(ws, track, "right", 0.0, z, 0.0, 0.0)
    inside = np.isfinite(loc.gap) & (loc.gap < -2e-5)
    assert inside.sum() > 100
    r = ws.nominal_radius + loc.z_wheel[inside]
    closed = 16.0 / 15.0 * (-loc.gap[inside]) ** 2.5 * np.sqrt(2.0 * r)
    assert np.allclose(loc.row_weight[inside], closed, rtol=0.01)
    assert np.allclose(loc.row_x[inside], loc.point[0][inside], atol=LOCUS_STEP)
    # the locus's weights are these; a round wheel's are the (-g)^2.5 of the parabola
    assert np.array_equal(loc.weights(slice(None), 2.5), loc.row_weight)
    plain = compute_locus(Wheelset(wheel, nominal_radius=0.46), track, "right", 0.0, z, 0.0,
                          0.0)
    assert plain.row_weight is None
    assert np.array_equal(plain.x_centres(slice(None)), plain.point[0])
