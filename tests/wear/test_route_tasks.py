"""The tasks of a closed-loop wear step (railcontact.wear.route_tasks): contact
tables that travel to Dask's processes, and the step-size measure's mask of the
positions the contact skips."""

import pickle
from types import SimpleNamespace

import numpy as np

from railcontact.dynamics.wheel_rail import F_SHARE, F_YWHEEL
from railcontact.wear.closed_loop import ClosedLoopWear
from railcontact.wear.route_tasks import away_from_contact_jumps, build_table
from tests.wear.test_closed_loop import tiny


def test_tables_travel_to_processes():
    """A table with its patches' geometry pickles (Dask's process and cluster
    schedulers ship it) and gives the same gap after the round trip."""
    sim = ClosedLoopWear(tiny(steps=1), progress=False)
    t = build_table(*sim.wheels[0], *sim.rails[0], sim.rail_offsets, sim.settings)
    t2 = pickle.loads(pickle.dumps(t))
    g, g2 = t.geometry[20][1][0], t2.geometry[20][1][0]
    x, y = np.linspace(-5e-3, 5e-3, 7), np.linspace(-5e-3, 5e-3, 5)
    np.testing.assert_array_equal(g.gap(x[:, None], y[None, :]), g2.gap(x[:, None], y[None, :]))


def test_away_from_contact_jumps():
    """The step-size measure's mask: the wheel positions the contact skips (gaps
    wider than 1 mm between the tabulated contact positions), widened by 2 mm."""
    data = np.zeros((5, 2, 2, 13))
    data[:, 0, 0, F_YWHEEL] = [0.0, 0.5e-3, 1.0e-3, 5.0e-3, 5.5e-3]     # a jump 1 -> 5 mm
    data[:, 0, 0, F_SHARE] = 1.0
    data[:, 1, 1, F_YWHEEL] = -0.03                 # no share: not a contact position
    y = (np.arange(-4, 10) + 0.5) * 1e-3
    keep = away_from_contact_jumps([SimpleNamespace(data=data)], y)
    np.testing.assert_allclose(y[~keep] * 1e3, np.arange(-0.5, 7.0))   # (-1, 7) mm
