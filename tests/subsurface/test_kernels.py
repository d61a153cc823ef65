"""Half-space stresses of uniform rectangular loads: boundary conditions,
equilibrium, the FFT operator against direct summation, and CONTACT's subsurf.inp
(examples_basic) against its reference output subsurf.ref_subs."""

import numpy as np
import pytest

from railcontact.contact_inp.reader import read_inp
from railcontact.core.errors import InputError
from railcontact.subsurface.kernels import (COMPONENTS, clear_cache, convolve_depths,
                                            grid_kernels, stresses_at_points)

NU = 0.28
UNIT = [[-0.5, 0.5, -0.5, 0.5]]
LOADS = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0])


@pytest.mark.parametrize("load", LOADS)
def test_surface_tractions(load):
    """At the surface sigma_zz = -p, sigma_xz = -q_x, sigma_yz = -q_y inside the
    loaded element and 0 outside (the load acts on the body, tension positive)."""
    s = stresses_at_points([[0.1, 0.2, 0.0], [-0.3, 0.45, 0.0], [2.0, 1.0, 0.0]], UNIT,
                           [load], NU)
    expect = -np.array([load[0], load[1], load[2]])
    for row in s[:2]:
        np.testing.assert_allclose(row[[2, 4, 5]], expect, atol=1e-12)
    np.testing.assert_allclose(s[2, [2, 4, 5]], 0.0, atol=1e-12)


@pytest.mark.parametrize("load", LOADS)
@pytest.mark.parametrize("point", [(0.3, -0.2, 0.4), (1.3, 0.7, 0.15), (-0.1, 0.05, 2.0)])
def test_equilibrium(load, point):
    """div sigma = 0 inside the body (central differences, h = 1e-4)."""
    h = 1e-4
    x0 = np.array(point)
    idx = {(0, 0): 0, (1, 1): 1, (2, 2): 2, (0, 1): 3, (0, 2): 4, (1, 2): 5}
    pts, signs = [], []
    for j in range(3):
        for sgn in (1, -1):
            e = np.zeros(3)
            e[j] = sgn * h
            pts.append(x0 + e)
    s = stresses_at_points(pts, UNIT, [load], NU)
    scale = np.abs(s).max()
    for i in range(3):
        div = sum((s[2 * j, idx[tuple(sorted((i, j)))]] - s[2 * j + 1, idx[tuple(sorted((i, j)))]])
                  / (2 * h) for j in range(3))
        assert abs(div) < 1e-5 * scale


def test_stress_of_far_point_load():
    """Far from a small element the stresses are Boussinesq's and Cerruti's of a
    point force (sigma_zz = -3 P z^3 / (2 pi rho^5), sigma_xz under a tangential force
    Q: -3 Q x^2 z / (2 pi rho^5))."""
    d = 1e-3
    x, y, z = 0.3, -0.2, 0.5
    rho = np.sqrt(x * x + y * y + z * z)
    s = stresses_at_points([[x, y, z]], [[-d / 2, d / 2, -d / 2, d / 2]],
                           [[1.0, 1.0, 0.0]], NU)[0] / d ** 2
    assert s[2] == pytest.approx(-3 * z ** 3 / (2 * np.pi * rho ** 5) - 3 * x * z * z / (2 * np.pi * rho ** 5),
                                 rel=1e-5)
    assert s[4] == pytest.approx(-3 * x * z * z / (2 * np.pi * rho ** 5) - 3 * x * x * z / (2 * np.pi * rho ** 5),
                                 rel=1e-5)


def test_fft_operator_against_direct_summation():
    """The FFT operator (kernels at non-negative offsets, mirrored by parity, spectra
    by DCT-I / DST-I) gives the direct sums of the element corners, to round-off, on
    a grid with an odd and an even size."""
    rng = np.random.default_rng(3)
    mx, my, dx, dy = 7, 10, 0.3, 0.2
    loads = rng.normal(size=(3, mx, my))
    x, y = np.arange(mx) * dx, np.arange(my) * dy
    X, Y = np.meshgrid(x, y, indexing="ij")
    rects = np.c_[X.ravel() - dx / 2, X.ravel() + dx / 2, Y.ravel() - dy / 2, Y.ravel() + dy / 2]
    clear_cache()
    got = convolve_depths(loads, dx, dy, [0.0, 0.17], NU)
    again = convolve_depths(loads, dx, dy, [0.17], NU)          # from the cache
    np.testing.assert_array_equal(again[..., 0], got[..., 1])
    for k, z in enumerate((0.0, 0.17)):
        pts = np.c_[X.ravel(), Y.ravel(), np.full(X.size, z)]
        ref = stresses_at_points(pts, rects, loads.reshape(3, -1).T, NU)
        np.testing.assert_allclose(got[..., k].reshape(6, -1).T, ref,
                                   atol=1e-12 * np.abs(ref).max())
    # the full kernels' parities
    K = grid_kernels(mx, my, dx, dy, 0.17, NU)
    np.testing.assert_allclose(K[0, 3], -K[0, 3][::-1], atol=1e-15)     # p, xy: odd in x


@pytest.mark.parametrize("mx, my", [(9, 5), (8, 6)])
def test_kernel_spectra_against_numpy_fft(mx, my):
    """The kernels' spectra from the quarter of the corners by half-length real FFTs
    (even and odd half-lengths: 2 x 9 and 2 x 5, 2 x 8 and 2 x 6 points) are the DFT
    of the full kernels on the padded grid (FACTOR times them), to round-off."""
    from railcontact.subsurface.kernels import FACTOR, kernel_spectra, padded_shape
    dx, dy, z = 0.3, 0.2, 0.13
    full = grid_kernels(mx, my, dx, dy, z, NU)
    N1, N2 = padded_shape(mx, my)
    assert N1 % 2 == 0 and N2 % 2 == 0 and N1 >= 2 * mx and N2 >= 2 * my
    per = np.zeros((3, 6, N1, N2))
    a = (np.arange(2 * mx - 1) - (mx - 1)) % N1
    b = (np.arange(2 * my - 1) - (my - 1)) % N2
    per[:, :, a[:, None], b[None, :]] = full
    ref = np.fft.rfft2(per)
    got = FACTOR[..., None, None] * kernel_spectra(mx, my, dx, dy, [z], NU)[0]
    np.testing.assert_allclose(got, ref, atol=1e-13 * np.abs(ref).max())


def test_cache_reuses_the_arrays_of_forgotten_spectra():
    """clear_cache keeps the spectra's arrays for the next grid of the same shape (the
    stresses recomputed in them are the same); release=True frees them."""
    from railcontact.subsurface import kernels
    loads = np.random.default_rng(5).normal(size=(3, 6, 4))
    first = convolve_depths(loads, 0.1, 0.2, [0.05, 0.3], NU).copy()
    clear_cache()
    assert kernels._CACHE.free_size > 0 and not kernels._CACHE.items
    np.testing.assert_array_equal(convolve_depths(loads, 0.1, 0.2, [0.05, 0.3], NU), first)
    other = convolve_depths(loads, 0.1, 0.25, [0.05], NU)          # another grid, same shape
    assert np.abs(other[..., 0] - first[..., 0]).max() > 1e-3 * np.abs(first).max()
    clear_cache(release=True)
    assert kernels._CACHE.free_size == 0 and not kernels._CACHE.free
    # an array under a lease (a thread between its lookup and its use) is never
    # handed out again while the lease is held; it goes back for reuse with the lease
    convolve_depths(loads, 0.1, 0.2, [0.05], NU)
    with kernels._CACHE.lease((6, 4, 0.1, 0.2, 0.05, NU), None) as held:
        kept = held.copy()
        clear_cache()
        assert kernels._CACHE.free_size == 0
        convolve_depths(loads, 0.3, 0.2, [0.05], NU)
        np.testing.assert_array_equal(held, kept)
    assert kernels._CACHE.free_size == held.nbytes
    np.testing.assert_array_equal(convolve_depths(loads, 0.1, 0.25, [0.05], NU), other)
    assert kernels._CACHE.free_size == 0
    # an array forgotten under a lease and released before the lease is given back
    # does not come back with it
    with kernels._CACHE.lease((6, 4, 0.1, 0.25, 0.05, NU), None):
        clear_cache()
        assert kernels._CACHE.free_size > 0             # the other grid's, under no lease
        clear_cache(release=True)
    assert kernels._CACHE.free_size == 0 and not kernels._CACHE.free


def test_inputs_checked():
    with pytest.raises(InputError, match="points"):
        stresses_at_points([[0.0, 0.0]], UNIT, [LOADS[0]], NU)
    with pytest.raises(InputError, match="depth"):
        stresses_at_points([[0.0, 0.0, -1.0]], UNIT, [LOADS[0]], NU)
    with pytest.raises(InputError, match="poisson"):
        grid_kernels(3, 3, 1.0, 1.0, 0.0, 0.5)


def _ref_subs(path):
    """The blocks of a CONTACT .subs file: arrays of rows X Y Z UX UY UZ SIGHYD SIGVM
    SIGXX SIGXY SIGXZ SIGYY SIGYZ SIGZZ."""
    blocks, lines = [], [ln for ln in open(path) if ln.strip()]
    i = 0
    while i < len(lines):
        if lines[i].lstrip().startswith("%   NX"):
            nx, ny, nz = (int(float(v)) for v in lines[i + 1].split()[:3])
            n = nx * ny * nz
            rows = [[float(v) for v in ln.split()] for ln in lines[i + 3:i + 3 + n]]
            blocks.append(np.array(rows))
            i += 3 + n
        else:
            i += 1
    return blocks


def test_contact_subsurf_reference(testbank):
    """examples_basic/subsurf.inp, case 2: a unit pressure and a traction 0.999 in x on
    one square element ([-0.4999, 0.5001] x [-0.4998, 0.5002] mm), nu = 0.28, at the
    two blocks of points the input lists (15 on the axis, 21 x 21 x 15 in a box, the
    surface included).  subsurf.ref_subs (CONTACT's output of the last case) within
    1 % of each stress, with a floor of 1e-4 of the largest (where CONTACT prints
    round-off, e.g. 1e-10); measured: largest deviation 2.6e-6 of the largest
    stress.  Von Mises and the mean stress likewise."""
    folder = testbank / "examples_basic"
    cases = read_inp(folder / "subsurf.inp")
    case = cases[1]
    v = case.values
    blocks_in = v["SUBSURFACE_BLOCKS"]
    assert [b["isubs"] for b in blocks_in] == [9, 9]
    area = v["DX"] * v["DY"] * v["MX"] * v["MY"]
    assert v["MX"] == v["MY"] == 1
    # one element carries the whole force: FN; FX given relative to FSTAT FN (F = 1)
    assert case.digits["F"] == 1
    p = v["FN"] / area
    qx = v["FXREL"] * v["FSTAT"] * v["FN"] / area
    rect = [[v["XL"], v["XL"] + v["DX"], v["YL"], v["YL"] + v["DY"]]]
    ref_blocks = _ref_subs(folder / "subsurf.ref_subs")
    assert len(ref_blocks) == 2
    worst = 0.0
    for b, ref in zip(blocks_in, ref_blocks):
        # CONTACT's order: x fastest, then y, then z (points sorted ascending)
        Z, Y, X = np.meshgrid(sorted(b["z"]), sorted(b["y"]), sorted(b["x"]), indexing="ij")
        pts = np.c_[X.ravel(), Y.ravel(), Z.ravel()]
        np.testing.assert_allclose(pts, ref[:, :3], atol=1e-4)
        s = stresses_at_points(pts, rect, [[p, qx, 0.0]], v["POISS1"])
        cols = {"xx": 8, "xy": 9, "xz": 10, "yy": 11, "yz": 12, "zz": 13}
        r = np.stack([ref[:, cols[c]] for c in COMPONENTS], axis=1)
        scale = np.abs(r).max()
        err = np.abs(s - r)
        assert np.all(err <= 0.01 * np.abs(r) + 1e-4 * scale)
        worst = max(worst, err.max() / scale)
        vm = np.sqrt(0.5 * ((s[:, 0] - s[:, 1]) ** 2 + (s[:, 1] - s[:, 2]) ** 2
                            + (s[:, 2] - s[:, 0]) ** 2) + 3 * (s[:, 3:] ** 2).sum(axis=1))
        np.testing.assert_allclose(vm, ref[:, 7], rtol=0.01, atol=1e-4 * scale)
        np.testing.assert_allclose(s[:, :3].sum(axis=1) / 3, ref[:, 6], rtol=0.01,
                                   atol=1e-4 * scale)
    assert worst < 1e-5


def test_duplicate_kernels():
    """The kernels copied rather than transformed are equal to their originals."""
    from railcontact.subsurface.kernels import DUPLICATES
    K = grid_kernels(6, 5, 0.2, 0.3, 0.25, NU)
    for (ld, c), (ld0, c0) in DUPLICATES:
        np.testing.assert_allclose(K[ld, c], K[ld0, c0], atol=1e-14)


@pytest.fixture
def small_cache(monkeypatch):
    """The spectra cache with a budget of two arrays of a 3 x 2 grid, emptied after."""
    from railcontact.subsurface import kernels
    from railcontact.subsurface.kernels import padded_shape
    n1, n2 = padded_shape(3, 2)
    one = 15 * (n1 // 2 + 1) * (n2 // 2 + 1) * 8
    clear_cache(release=True)
    monkeypatch.setattr(kernels._CACHE, "budget", 2 * one)
    yield kernels._CACHE, one
    clear_cache(release=True)


@pytest.mark.parametrize("arrays", [2, 4])
def test_spectra_cache_shared_by_threads(small_cache, monkeypatch, arrays):
    """Threads evaluating twice as many grids as the cache holds (2: no array kept
    for reuse; 4: one, handed out again while other threads hold leases): no error,
    every result equal to the one computed alone, the cache's byte count true and
    within the budget, and no lease left held."""
    import threading
    cache, one = small_cache
    monkeypatch.setattr(cache, "budget", arrays * one)
    loads = np.random.default_rng(1).normal(size=(3, 3, 2))
    dxs = [0.1 + 0.01 * i for i in range(2 * arrays)]
    alone = {dx: convolve_depths(loads, dx, 0.2, [0.05], NU).copy() for dx in dxs}
    failures = []

    def work(seed):
        r = np.random.default_rng(seed)
        for _ in range(400):
            dx = dxs[r.integers(len(dxs))]
            try:
                if not np.array_equal(convolve_depths(loads, dx, 0.2, [0.05], NU), alone[dx]):
                    failures.append("wrong stresses")
            except Exception as err:        # noqa: BLE001 - any error is a failure here
                failures.append(repr(err))
    threads = [threading.Thread(target=work, args=(s,)) for s in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert failures == []
    assert cache.size == sum(e.spectra.nbytes for e in cache.items.values()) <= cache.budget
    assert cache.free_size == sum(S.nbytes for v in cache.free.values() for S in v)
    assert cache.free_size <= cache.budget // 4
    assert all(e.leases == 0 for e in cache.items.values())


def test_spectra_lease_given_back_however_the_block_ends(small_cache, monkeypatch):
    """A lease is given back when its block raises (the spectra forgotten meanwhile
    go back for reuse then), and one lease is not held twice at a time."""
    from railcontact.core.errors import RailContactError
    cache, one = small_cache
    monkeypatch.setattr(cache, "budget", 4 * one)           # one array kept for reuse
    loads = np.random.default_rng(4).normal(size=(3, 3, 2))
    convolve_depths(loads, 0.1, 0.2, [0.05], NU)
    lease = cache.lease((3, 2, 0.1, 0.2, 0.05, NU), None)
    with pytest.raises(ZeroDivisionError):
        with lease:
            clear_cache()
            1 / 0
    assert cache.free_size == one
    convolve_depths(loads, 0.1, 0.2, [0.05], NU)
    with lease, pytest.raises(RailContactError, match="twice"):
        with lease:
            pass


def test_spectra_cache_keeps_its_budget(small_cache):
    """Many depths in one call leave at most the budget in the cache."""
    cache, one = small_cache
    loads = np.random.default_rng(2).normal(size=(3, 3, 2))
    convolve_depths(loads, 0.1, 0.2, np.linspace(0.01, 0.2, 21), NU)
    assert len(cache.items) == 2
    assert cache.size == 2 * one <= cache.budget
