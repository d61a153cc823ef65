"""Plots of a wear run (railcontact.wear.plots): which wheel profiles get a panel, and
the closed loop's figures of profile evolution and measures."""

import matplotlib.image as mpimg
import numpy as np
import xarray as xr

from railcontact.wear.plots import _wheel_panels


def _ds(wheels, n_wheelsets=2):
    return xr.Dataset(coords={"wheelset": np.arange(1, n_wheelsets + 1)},
                      attrs={"wheels": wheels})


def test_one_panel_per_distinct_wheel_profile():
    """Vehicle-averaged wheels share one profile, per side two, individual wheels one
    per wheelset and side."""
    assert _wheel_panels(_ds("vehicle")) == [("all wheels", 1, "right")]
    assert _wheel_panels(_ds("side")) == [("left wheels", 1, "left"),
                                         ("right wheels", 1, "right")]
    assert _wheel_panels(_ds("individual")) == [
        ("wheelset 1, left", 1, "left"), ("wheelset 1, right", 1, "right"),
        ("wheelset 2, left", 2, "left"), ("wheelset 2, right", 2, "right")]


def test_closed_loop_figures(wear_vehicle_example):
    """examples/wear_vehicle.toml: profile evolution and measures written as PNG files
    whose curves are drawn (coloured pixels: measured 2.0 % and 1.4 % of the images;
    the axes and labels alone are grey, 0 %)."""
    out, ds = wear_vehicle_example
    for name in ("wear.png", "measures.png", "rcf.png"):
        rgb = mpimg.imread(out / name)[..., :3]
        coloured = (rgb.max(axis=-1) - rgb.min(axis=-1)) > 0.2
        assert coloured.mean() > 0.005, name
    assert ds.sizes["state"] == ds.sizes["step"] + 1
