"""railcontact.cases.crossing: a sweep along the track gathered per rail, the transfer
stretch, its plot.  (The sweep through the UK crossing against CONTACT is in
tests/cases/test_surfaces.py.)"""

from types import SimpleNamespace as NS

import matplotlib.pyplot as plt
import numpy as np
import pytest

from railcontact.cases.crossing import plot_track_sweep, solve_along_track, to_dataset, transfer_range
from railcontact.core.errors import InputError

S = np.array([0.0, 0.01, 0.02, 0.03, 0.04, 0.05])
WING = [100e3, 80e3, 40e3, 1e3, 0.0]             # vertical force on the wing rail [N]


def _patch(rail, fn, x):
    return NS(geometry=NS(rail=rail, position=(x, 0.0), y_rail=-0.01 if rail == "wing" else 0.0),
              normal=NS(normal_force=fn, pmax=1e9 * fn / 1e5, area=1e-4 * fn / 1e5))


def _result(wing):
    nose = 100e3 - wing
    patches = [_patch(r, f, x) for r, f, x in (("wing", wing, -0.001), ("nose", nose, 0.002))
               if f > 0]
    patches += [_patch("nose", 1e3, 0.004)] if nose > 0 else []
    forces = {"wing": wing, "nose": nose + (1e3 if nose > 0 else 0.0)}
    return NS(patches=patches, pose=NS(vertical=1e-3), converged=True,
              rail_forces=lambda: forces)


@pytest.fixture(scope="module")
def ds():
    return to_dataset(S, [_result(w) for w in WING] + [None], NS(title="pass"))


def test_dataset_per_rail_with_units(ds):
    assert list(ds["rail"].values) == ["wing", "nose"]
    assert ds["Fz"].attrs["units"] == "N" and ds["area"].attrs["units"] == "m2"
    assert ds["s"].attrs["units"] == "m" and ds.attrs["title"] == "pass"
    np.testing.assert_array_equal(ds["Fz"].sel(rail="wing").values[:4], WING[:4])
    assert np.isnan(ds["Fz"].sel(rail="wing").values[4])              # carries nothing
    assert list(ds["n_patches"].sel(rail="nose").values) == [0, 2, 2, 2, 2, 0]
    # the nose's Fn sums its two patches, its x is the larger one's
    assert ds["Fn"].sel(rail="nose").values[2] == pytest.approx(61e3)
    assert ds["x"].sel(rail="nose").values[2] == 0.002
    assert ds["total_Fz"].values[:5] == pytest.approx([100e3, 101e3, 101e3, 101e3, 101e3])
    assert list(ds["converged"].values) == [True] * 5 + [False]
    assert np.isnan(ds["vertical_position"].values[5])                # no contact there


def test_transfer_range(ds):
    """The nose carries more than 2 % from s = 10 mm; the wing rail last more than
    2 % at 20 mm (1 kN of 101 kN at 30 mm is below)."""
    assert transfer_range(ds, "wing", "nose") == (0.01, 0.02)
    assert transfer_range(ds, "wing", "nose", share=0.005) == (0.01, 0.03)
    assert transfer_range(ds, "nose", "wing") == (0.0, 0.04)
    assert transfer_range(ds, "wing", "nose", share=1.0) is None


def test_plot(ds, tmp_path):
    fig = plot_track_sweep(ds, tmp_path / "sweep.png")
    assert (tmp_path / "sweep.png").stat().st_size > 5000
    labels = [a.get_ylabel() for a in fig.axes]
    assert labels == ["vertical force [kN]", "contact x from the axle [mm]", "p_max [MPa]",
                      "area [mm$^2$]"]
    wing_line = fig.axes[0].get_lines()[0]
    assert wing_line.get_label() == "wing"
    assert wing_line.get_ydata()[0] == pytest.approx(100.0)           # kN
    plt.close(fig)


@pytest.mark.parametrize("positions", [[], [[0.0, 1.0]], [0.0, np.nan]])
def test_bad_positions(positions):
    with pytest.raises(InputError, match="positions"):
        solve_along_track(None, positions)
