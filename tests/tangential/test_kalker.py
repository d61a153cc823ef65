import pytest

from railcontact.errors import InputError
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


def test_vectorised_coefficients_equal_scalar():
    """The compiled array version (used per strip) equals the scalar table lookup,
    asymptotic ranges included."""
    import numpy as np

    from railcontact.tangential.kalker import kalker_coefficients_array
    r = np.concatenate([np.geomspace(0.01, 100, 200), [0.1, 0.2, 1.0, 10.0]])
    for nu in (0.0, 0.28, 0.5):
        v = np.array(kalker_coefficients_array(r, nu)).T
        s = np.array([kalker_coefficients(x, nu) for x in r])
        np.testing.assert_allclose(v, s, rtol=1e-12)
