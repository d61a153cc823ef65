import pytest

from railcontact.core.errors import InputError
from railcontact.tangential import kalker_coefficients
from tests.conftest import read_csv


def test_table_nodes():
    assert kalker_coefficients(1.0, 0.25) == pytest.approx((4.12, 3.67, 1.47))
    assert kalker_coefficients(0.8, 0.25)[2] == pytest.approx(1.25)   # not the 1.15 typo
    assert kalker_coefficients(2.0, 0.0) == pytest.approx((4.37, 4.37, 2.35))
    assert kalker_coefficients(0.1, 0.5) == pytest.approx((4.85, 2.53, 0.731))


def test_interpolation_matches_contact(refdir):
    # CONTACT's embedded table with its quadratic interpolation of 1/C in nu
    for r in read_csv(refdir / "kalker_coefficients_contact.csv"):
        c = kalker_coefficients(float(r["a_over_b"]), float(r["nu"]))
        assert c[0] == pytest.approx(float(r["kalker_C11"]), rel=2e-3)
        assert c[1] == pytest.approx(float(r["kalker_C22"]), rel=2e-3)
        assert c[2] == pytest.approx(float(r["kalker_C23"]), rel=2e-3)


def test_asymptotes_continue_table():
    for ab in (0.1, 10.0):
        inside = kalker_coefficients(ab * (1.0001 if ab < 1 else 0.9999), 0.25)
        outside = kalker_coefficients(ab * (0.9999 if ab < 1 else 1.0001), 0.25)
        for i, o in zip(inside, outside):
            assert o == pytest.approx(i, rel=0.1)


def test_bad_input():
    with pytest.raises(InputError):
        kalker_coefficients(-1.0, 0.25)
    with pytest.raises(InputError):
        kalker_coefficients(1.0, 0.6)


def test_vectorised_coefficients_keep_shape_and_check_input():
    """The array version (used per strip) keeps the input's shape, gives the same
    values as one-by-one calls, and rejects bad ratios."""
    import numpy as np

    from railcontact.tangential.kalker import kalker_coefficients_array
    r = np.geomspace(0.01, 100, 24).reshape(4, 6)
    c11, c22, c23 = kalker_coefficients_array(r, 0.28)
    assert c11.shape == c22.shape == c23.shape == (4, 6)
    assert c22[1, 2] == kalker_coefficients(float(r[1, 2]), 0.28)[1]
    with pytest.raises(InputError):
        kalker_coefficients_array(np.array([1.0, -1.0]), 0.28)


def test_slender_limits():
    """Kalker's asymptotic expressions: a/b -> 0 gives C11 = pi^2/(4(1 - nu)),
    C22 = pi^2/4; for b/a = g -> 0 (nu = 0), C11 = C22 = 2 pi/(lam g) (1 + (3 - ln 4)/lam)
    with lam = ln(16/g^2)."""
    import math
    c11, c22, _ = kalker_coefficients(0.05, 0.25)
    assert c11 == pytest.approx(math.pi ** 2 / 3, rel=1e-12)
    assert c22 == pytest.approx(math.pi ** 2 / 4, rel=1e-12)
    g = 0.05
    lam = math.log(16 / g ** 2)
    c11, c22, _ = kalker_coefficients(1 / g, 0.0)
    expected = 2 * math.pi / (lam * g) * (1 + (3 - math.log(4)) / lam)
    assert c11 == pytest.approx(expected, rel=1e-12)
    assert c22 == pytest.approx(expected, rel=1e-12)
