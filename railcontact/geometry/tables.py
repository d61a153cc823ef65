"""Contact tables over lateral shift and the equivalent conicity."""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp
from tqdm.auto import tqdm

from ..core.errors import InputError
from ..core.materials import STEEL
from .search import find_contact
from .track import SIDES


def contact_table(wheelset, track, shifts, yaw: float = 0.0, vertical_force=None,
                  material=STEEL, progress: bool = False):
    """Contact geometry over a range of lateral shifts.

    Returns an :class:`xarray.Dataset` with ``lateral_shift`` [m] and ``side`` dims:
    ``delta_r`` (= r_right - r_left, m), ``roll`` (rad), ``vertical`` (m), and per side
    ``rolling_radius``, ``contact_angle``, ``y_rail``, ``y_wheel`` (patch-combined,
    CONTACT's weighting) and ``n_patches``.
    """
    import xarray as xr
    shifts = np.asarray(shifts, dtype=float)
    n = shifts.size
    out = {k: np.full((n, 2), np.nan) for k in ("rolling_radius", "contact_angle", "y_rail",
                                                 "y_wheel")}
    npatch = np.zeros((n, 2), dtype=int)
    roll, vert = np.full(n, np.nan), np.full(n, np.nan)
    for i, y in enumerate(tqdm(shifts, desc="contact table", disable=not progress)):
        c = find_contact(wheelset, track, float(y), yaw, vertical_force=vertical_force,
                         material=material)
        roll[i], vert[i] = c.pose.roll, c.pose.vertical
        for j, side in enumerate(SIDES):
            eq = c.equivalent_point(side)
            for k in out:
                out[k][i, j] = eq[k]
            npatch[i, j] = len(c.side_patches(side))
    dims = ("lateral_shift", "side")
    ds = xr.Dataset(
        {"rolling_radius": (dims, out["rolling_radius"], {"units": "m"}),
         "contact_angle": (dims, out["contact_angle"], {"units": "rad"}),
         "y_rail": (dims, out["y_rail"], {"units": "m"}),
         "y_wheel": (dims, out["y_wheel"], {"units": "m"}),
         "n_patches": (dims, npatch),
         "delta_r": ("lateral_shift", out["rolling_radius"][:, 1] - out["rolling_radius"][:, 0],
                     {"units": "m", "long_name": "rolling radius difference r_right - r_left"}),
         "roll": ("lateral_shift", roll, {"units": "rad"}),
         "vertical": ("lateral_shift", vert, {"units": "m"})},
        coords={"lateral_shift": ("lateral_shift", shifts, {"units": "m"}),
                "side": ("side", list(SIDES))},
        attrs={"yaw_rad": yaw, "vertical_force_N": -1.0 if vertical_force is None
               else float(np.mean(vertical_force)),
               "nominal_radius_m": wheelset.nominal_radius})
    return ds


def equivalent_conicity(table, amplitude: float, method: str = "wavelength",
                        half_contact_distance: float | None = None) -> float:
    """Equivalent conicity for a wheelset lateral amplitude [m].

    Parameters
    ----------
    table : xarray.Dataset
        From :func:`contact_table`, covering at least [-amplitude, amplitude].
    method : {"wavelength", "harmonic"}
        ``"wavelength"``: integrate the kinematic (Klingel) oscillation
        y'' = -delta_r(y) / (2 e0 r0) along the track from y = amplitude, measure its
        wavelength L and return gamma_e = e0 r0 (2 pi / L)^2 (the "integration"
        approach of EN 15302).  ``"harmonic"``: first-harmonic (describing-function)
        linearisation, gamma_e = (1 / (2 pi y^)) int delta_r(y^ sin t) sin t dt.
    half_contact_distance : float, optional
        e0 [m]; default half the distance between the tape circles.
    """
    y = table["lateral_shift"].values
    dr = table["delta_r"].values
    if not (y.min() <= -amplitude + 1e-12 and y.max() >= amplitude - 1e-12) or amplitude <= 0:
        raise InputError(f"amplitude {amplitude!r} m: the table must cover [-amplitude, amplitude]"
                         f" (it covers [{y.min():g}, {y.max():g}] m)")
    r0 = float(table.attrs["nominal_radius_m"])
    e0 = half_contact_distance or 0.75
    if method == "harmonic":
        t = np.linspace(0.0, 2 * np.pi, 2001)
        f = np.interp(amplitude * np.sin(t), y, dr) * np.sin(t)
        return float(np.trapezoid(f, t) / (2 * np.pi * amplitude))
    if method != "wavelength":
        raise InputError(f"conicity method {method!r}: expected 'wavelength' or 'harmonic'")

    def rhs(s, u):
        return [u[1], -np.interp(u[0], y, dr) / (2 * e0 * r0)]

    def crest(s, u):          # velocity turns from + to -: the next crest, one wavelength
        return u[1]
    crest.direction = -1.0
    crest.terminal = 2        # the start is the first crest: stop at the second
    span = 2 * np.pi * math.sqrt(e0 * r0 / 1e-3) * 4
    sol = solve_ivp(rhs, (0.0, span), [amplitude, 0.0], events=crest, rtol=1e-10,
                    atol=1e-13, max_step=1.0)
    ev = sol.t_events[0]
    ev = ev[ev > 1e-6]
    if ev.size == 0:
        raise InputError("no kinematic oscillation found (delta_r does not restore the wheelset)")
    wavelength = float(ev[0])
    return e0 * r0 * (2 * np.pi / wavelength) ** 2
