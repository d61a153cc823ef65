"""The post-processing of a closed-loop wear step (railcontact.wear.postprocess): each
patch of the dynamics solved force-controlled with the local model, repeated states
reused, warm starts along the time history."""

import numpy as np

from railcontact.dynamics.simulation import Integration, simulate_vehicle
from railcontact.wear import get_wear_law
from railcontact.wear.closed_loop import ClosedLoopWear
from railcontact.wear.postprocess import PatchPostProcessor
from railcontact.wear.route_tasks import build_table
from tests.wear.test_closed_loop import tiny


def test_repeated_states_and_warm_starts():
    """Repeated states: the steady curve reuses solutions; the wear per metre is that
    of solving every patch within 1 % of its maximum.  Exact + exact with and
    without warm starts along the time history agree within 1 %."""
    sc = tiny(steps=1)
    sim = ClosedLoopWear(sc, progress=False)
    s = sim.settings
    table = build_table(*sim.wheels[0], *sim.rails[0], sim.rail_offsets, s)
    item = sc.routes[0]
    ds = simulate_vehicle(sc.model, item.route, table, item.speed, item.duration,
                          friction=item.friction, integration=Integration(sample_rate=100.0))
    grid = np.arange(0.0, 0.2, 1e-4)
    wheels = [[sim.wheels[0][0], sim.wheels[0][1]]] * 2
    args = (ds, [table, table], wheels, sim.rails[0], [[grid, grid]] * 2, [grid, grid], 0.3, 5)
    out = {}
    kept = []
    for label, model, tol, warm in (("hf0", "hertz+fastsim", 0.0, True),
                                    ("hf", "hertz+fastsim", 1e-3, True),
                                    ("ex", "exact+exact", 0.0, True),
                                    ("ex_cold", "exact+exact", 0.0, False)):
        n, t = model.split("+")
        pp = PatchPostProcessor(n, t, get_wear_law("usfd"), sc.case.material, (20, 20),
                                reuse_tolerance=tol, warm=warm)
        # grid reuse through the declared capability: the exact solver (warm) only
        assert pp.regrid == (label == "ex")
        if label == "ex":
            solve = pp.nmodel.solve

            def spy(*a, **kw):
                kept.append(kw.get("reuse_grid") is not None)
                return solve(*a, **kw)
            pp.nmodel.solve = spy
        out[label] = pp.run(*args)
    assert sum(kept) > 0.5 * len(kept)          # the same table shift keeps its grid
    assert out["hf"]["stats"].reused > 0.3 * out["hf"]["stats"].patches
    assert out["hf0"]["stats"].reused == 0
    for a, b in (("hf", "hf0"), ("ex", "ex_cold")):
        wa, wb = np.array(out[a]["wheel"]), np.array(out[b]["wheel"])
        assert np.max(np.abs(wa - wb)) < 0.01 * wb.max()
    assert out["ex"]["stats"].not_converged == 0
