"""railcontact.core.plotting: figures with the axes, labels and units they promise."""

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pytest

import railcontact as rc
from railcontact.core import plotting
from railcontact.profiles.library import get_profile

EX = Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture
def figures(monkeypatch):
    """The figures the plotting functions close, kept for inspection."""
    kept = []
    monkeypatch.setattr(plt, "close", lambda fig=None: kept.append(fig))
    yield kept
    monkeypatch.undo()
    for fig in kept:
        plt.close(fig)


def test_profile_plot(tmp_path, figures):
    wheel = get_profile("S1002", "wheel")
    out = plotting.plot_profile(wheel, tmp_path / "w.png")
    assert out == tmp_path / "w.png" and out.read_bytes()[:4] == b"\x89PNG"
    (fig,) = figures
    (ax,) = fig.axes
    assert ax.get_xlabel() == "y [mm] (field side positive)" and ax.get_ylabel() == "z [mm] (down)"
    assert "S1002" in ax.get_title() and ax.yaxis_inverted()
    (line,) = ax.get_lines()
    x, y = line.get_data()
    assert np.allclose(x, wheel.y * 1e3) and np.allclose(y, wheel.z * 1e3)     # in mm


def test_patch_plot(tmp_path, figures):
    res = rc.solve(rc.load_case(EX / "bodies.toml"), normal="kpec", tangential="fastsim")
    out = plotting.plot_patches([("case A", res.patches[0]), ("case B", res.patches[0])],
                                tmp_path / "p.png", title="two")
    assert out.stat().st_size > 5000
    (fig,) = figures
    panels = [a for a in fig.axes if a.get_title()]
    assert [a.get_title() for a in panels] == ["case A", "case B"]
    assert all(a.get_xlabel() == "y [mm]" and a.get_ylabel() == "x [mm]" for a in panels)
    bars = [a for a in fig.axes if not a.get_title()]
    assert len(bars) == 2 and bars[0].get_ylabel() == "p [MPa]"
    image = panels[0].get_images()[0].get_array()
    assert image.max() == pytest.approx(res.patches[0].normal.pressure.max() / 1e6)
    assert fig._suptitle.get_text() == "two"
