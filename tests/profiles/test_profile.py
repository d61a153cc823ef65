"""Profile evaluation."""

import numpy as np


def test_z_and_slope_equal_separate_evaluations():
    from railcontact.profiles import s1002
    p = s1002()
    y = np.linspace(p.y_min - 1e-3, p.y_max + 1e-3, 3001)
    z, d = p.z_and_slope(y)
    np.testing.assert_array_equal(z, p.z_at(y))
    np.testing.assert_array_equal(d, p.slope(y))
