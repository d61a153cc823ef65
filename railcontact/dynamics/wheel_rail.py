"""Wheel–rail contact for the dynamics layer: a per-patch contact table over the
lateral shift, and the creep-force laws evaluated online.

The table comes from the geometry layer's elastic (multi-Hertzian) contact search
at the static wheel load Q_ref (:func:`railcontact.geometry.find_contact`), as the
"precomputed contact table" approach of multibody codes.  Each side has two patch
slots: slot 0 the tread (field side), slot 1 the flange/gauge side (a single patch
with |δ| > ``FLANGE_ANGLE`` sits in slot 1), so a flange patch that appears with
growing shift enters with a normal force rising from zero.  The table keeps each
patch's share of the wheel load; at a wheel load Q a patch has N = share Q / cos δ
and Hertz semi-axes scaled by (Q/Q_ref)^(1/3) (same curvatures).

Tangential laws online: the compiled ``linear``, ``fastsim`` and ``polach`` of
:mod:`railcontact.tangential.online`.  Every other registered tangential model
(``fastsim-strips``, ``fastrip``, ``exact``, ...) runs through its Python
``solve`` on the Hertz patch of the table, which is exact to the model but slow.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np
from numba import njit
from tqdm.auto import tqdm

from ..core.errors import ContactNotFoundError, InputError
from ..geometry import find_contact
from ..geometry.contact import ContactGeometry
from ..geometry.validity import flange
from ..core.hertz_theory import hertz_ellipse
from ..core.materials import Material, STEEL
from ..normal import get_normal_model
from ..tangential.kalker import kalker_coefficients
from ..tangential.online import online_law, patch_forces

log = logging.getLogger(__name__)

#: a lone patch steeper than this [rad] goes to the flange slot
FLANGE_ANGLE = 0.35
#: table fields per patch slot
FIELDS = ("load_share", "contact_angle", "rolling_radius", "y_contact", "a", "b",
          "C11", "C22", "C23", "A", "B", "y_rail", "y_wheel")
(F_SHARE, F_DELTA, F_R, F_YP, F_A, F_B, F_C11, F_C22, F_C23, F_CA, F_CB, F_YRAIL,
 F_YWHEEL) = range(13)


def _shift_grid(reference_load: float, shift_range: float, step: float) -> np.ndarray:
    """The lateral shifts [m] of a contact table: -range to range by ``step``, its
    inputs checked (a reference load > 0 N, a range in [1, 30] mm, a step of at most a
    quarter of it)."""
    if not (math.isfinite(reference_load) and reference_load > 0):
        raise InputError(f"contact table reference load {reference_load!r} N: expected > 0")
    if not (1e-3 <= shift_range <= 0.03 and 1e-5 <= step <= shift_range / 4):
        raise InputError(f"contact table range {shift_range!r} m, step {step!r} m: expected "
                         "a range in [0.001, 0.03] m and a step of at most range/4")
    n = int(round(shift_range / step))
    return np.linspace(-n * step, n * step, 2 * n + 1)


@dataclass
class WheelRailTable:
    """Per-patch contact table over the wheelset's lateral shift relative to the rails.

    Attributes
    ----------
    shift : ndarray (n,)
        Uniform grid of lateral shifts [m].
    data : ndarray (n, 2, 2, len(FIELDS))
        Per shift, side (left, right) and slot (tread, flange): the share of the
        wheel load the patch carries (its N cos δ / Q; interpolating the share, not
        N, keeps the vertical balance exact between table points where the flange
        angle changes fast), contact angle δ [rad] (track frame), rolling radius [m],
        lateral position of the contact point relative to the wheelset centre [m],
        Hertz semi-axes a, b [m], Kalker's C11, C22, C23, curvatures A, B [1/m] and
        the rail and wheel profile coordinates [m] of the contact point.  Absent
        patches have normal force 0 (other fields continued from the nearest shift
        where the slot exists).  At a wheel load Q a patch has N = share Q / cos δ
        before the creep correction.
    reference_load : float
        Vertical wheel load [N] of the table.
    nominal_radius : float
        r0 [m].
    flange_angle : float
        The wheels' largest flange angle [rad] (NaN without a flange: a conical
        table), for Nadal's flange-climb limit.
    delta_r : ndarray (n,) or None
        Rolling radius difference r_right - r_left [m] per shift, each side's patches
        combined with CONTACT's weights (the Δr(y) function of EN 15302), where built
        from profiles.
    geometry : list or None
        With ``keep_geometry``: per shift a ((left tread, left flange), (right tread,
        right flange)) tuple of the geometry layer's
        :class:`~railcontact.geometry.ContactGeometry` (None for an absent slot), at
        the reference load: the patches a post-processing solves again with any
        local contact model (:mod:`railcontact.wear.postprocess`).
    """

    shift: np.ndarray
    data: np.ndarray
    reference_load: float
    nominal_radius: float
    flange_angle: float = math.nan
    delta_r: np.ndarray | None = None
    geometry: list | None = None

    @classmethod
    def build(cls, wheelset, track, reference_load: float, material: Material = STEEL,
              shift_range: float = 0.012, step: float = 2e-4, progress: bool = False,
              keep_geometry: bool = False):
        """Contact search at every shift in [-shift_range, shift_range] (yaw 0);
        ``keep_geometry`` keeps the patches' geometry (:attr:`geometry`)."""
        shifts = _shift_grid(reference_load, shift_range, step)
        data = np.full((shifts.size, 2, 2, len(FIELDS)), np.nan)
        data[..., F_SHARE] = 0.0
        delta_r = np.full(shifts.size, np.nan)
        kept = [] if keep_geometry else None
        Es, nu = material.contact_modulus, material.nu
        for i, y in enumerate(tqdm(shifts, desc="wheel-rail contact table",
                                   disable=not progress)):
            try:
                c = find_contact(wheelset, track, float(y), 0.0, vertical_force=reference_load,
                                 material=material)
            except ContactNotFoundError as exc:
                raise InputError(f"contact table: no contact at lateral shift {y:g} m ({exc}); "
                                 "reduce the table range") from None
            radius = [c.equivalent_point(side)["rolling_radius"] for side in ("left", "right")]
            delta_r[i] = radius[1] - radius[0]
            slots_here = [[None, None], [None, None]]
            for j, side in enumerate(("left", "right")):
                ps = sorted(c.side_patches(side), key=lambda p: -p.y_rail)   # field side first
                if len(ps) > 2:
                    log.warning("lateral shift %.4g m, %s wheel: %d patches; the table keeps "
                                "the field-most and the gauge-most", y, side, len(ps))
                    ps = [ps[0], ps[-1]]
                if len(ps) == 1:
                    slots = [1 if abs(ps[0].contact_angle) > FLANGE_ANGLE else 0]
                else:
                    slots = [0, 1]
                vert = 0.0
                for k, p in zip(slots, ps):
                    A, B = p.curvatures
                    if p.approach <= 0 or A <= 0 or B <= 0:
                        continue
                    hz = hertz_ellipse(A, B, Es, penetration=p.approach)
                    C = kalker_coefficients(hz.a / hz.b, nu)
                    data[i, j, k] = (hz.force, p.contact_angle, p.rolling_radius,
                                     p.position[1] - y, hz.a, hz.b, C[0], C[1], C[2], A, B,
                                     p.y_rail, p.y_wheel)
                    vert += hz.force * math.cos(p.contact_angle)
                    slots_here[j][k] = p
                if vert > 0:       # shares of the multi-Hertzian vertical forces
                    on = data[i, j, :, F_SHARE] > 0
                    data[i, j, on, F_SHARE] *= np.cos(data[i, j, on, F_DELTA]) / vert
            if kept is not None:
                kept.append(tuple(tuple(sl) for sl in slots_here))
        # continue the fields of absent slots from the nearest shift with the slot
        default = (0.0, 0.0, wheelset.nominal_radius, 0.75, 1e-3, 1e-3, 4.0, 3.5, 1.5, 1.0,
                   1.0, 0.0, 0.0)
        for j in range(2):
            for k in range(2):
                ok = data[:, j, k, F_SHARE] > 0
                for f in range(1, len(FIELDS)):
                    if ok.any():
                        data[:, j, k, f] = np.interp(shifts, shifts[ok], data[ok, j, k, f])
                    else:
                        data[:, j, k, f] = default[f]
        flanges = [flange(wheelset.wheel(s)) for s in ("left", "right")]
        angle = min((f.max_angle for f in flanges if f is not None), default=math.nan)
        return cls(shifts, np.ascontiguousarray(data), float(reference_load),
                   float(wheelset.nominal_radius), angle, delta_r, kept)

    @classmethod
    def quasi_elastic(cls, wheelset, track, reference_load: float, alpha: float = 3e-5,
                      material: Material = STEEL, shift_range: float = 0.012,
                      step: float = 2e-4):
        """The table of Arnold's quasi-elastic contact
        (:func:`railcontact.geometry.quasi_elastic.quasi_elastic_contact`, regularisation
        ``alpha`` [m]) instead of the multi-Hertzian search: one smoothed contact point
        per wheel in the tread slot (the flange slot unloaded), carrying the whole
        wheel load, N = Q / cos δ, with the Hertz semi-axes of its weighted curvatures
        at the reference load.  Its contact angle, rolling radius and position pass
        smoothly through the jumps of the rigid contact point (docs/dynamics.md,
        "Arnold's quasi-elastic contact")."""
        from ..geometry.quasi_elastic import quasi_elastic_contact
        shifts = _shift_grid(reference_load, shift_range, step)
        data = np.zeros((shifts.size, 2, 2, len(FIELDS)))
        delta_r = np.empty(shifts.size)
        Es, nu = material.contact_modulus, material.nu
        roll = 0.0
        for i, y in enumerate(shifts):
            c = quasi_elastic_contact(wheelset, track, float(y), 0.0, alpha, roll_start=roll)
            roll = c.pose.roll
            for j, side in enumerate(("left", "right")):
                p = c.points[side]
                A, B = p.curvatures
                hz = hertz_ellipse(A, B, Es, force=reference_load / math.cos(p.contact_angle))
                C = kalker_coefficients(hz.a / hz.b, nu)
                data[i, j, 0] = (1.0, p.contact_angle, p.rolling_radius, p.position[1] - y,
                                 hz.a, hz.b, C[0], C[1], C[2], A, B, p.y_rail, p.y_wheel)
                data[i, j, 1] = data[i, j, 0]
                data[i, j, 1, F_SHARE] = 0.0
            delta_r[i] = c.points["right"].rolling_radius - c.points["left"].rolling_radius
        flanges = [flange(wheelset.wheel(s)) for s in ("left", "right")]
        angle = min((f.max_angle for f in flanges if f is not None), default=math.nan)
        return cls(shifts, data, float(reference_load), float(wheelset.nominal_radius), angle,
                   delta_r)

    def to_xarray(self):
        import xarray as xr
        units = {"load_share": "1", "contact_angle": "rad", "rolling_radius": "m",
                 "y_contact": "m", "a": "m", "b": "m", "C11": "1", "C22": "1", "C23": "1",
                 "A": "1/m", "B": "1/m", "y_rail": "m", "y_wheel": "m"}
        dims = ("lateral_shift", "side", "slot")
        return xr.Dataset({f: (dims, self.data[..., i], {"units": units[f]})
                           for i, f in enumerate(FIELDS)},
                          coords={"lateral_shift": ("lateral_shift", self.shift, {"units": "m"}),
                                  "side": ["left", "right"], "slot": ["tread", "flange"]},
                          attrs={"reference_load_N": self.reference_load,
                                 "nominal_radius_m": self.nominal_radius,
                                 "flange_angle_rad": self.flange_angle})

    @classmethod
    def conical(cls, gamma: float, reference_load: float = 75e3, r0: float = 0.46,
                half_distance: float = 0.75, semi_axes=(6e-3, 4e-3), coefficients=None,
                shift_range: float = 0.02, nu: float = 0.28, contact_angles: bool = True):
        """Linear test geometry: conical wheels (r = r0 ∓ γ y), one tread patch per
        side, contact angles ±γ (or 0 with ``contact_angles=False``: the textbook
        wheelset without spin and contact-plane tilt), fixed Hertz semi-axes at the
        reference load."""
        shifts = np.linspace(-shift_range, shift_range, 401)
        a, b = semi_axes
        C = coefficients or kalker_coefficients(a / b, nu)
        data = np.zeros((shifts.size, 2, 2, len(FIELDS)))
        for j, sgn in enumerate((-1.0, 1.0)):
            delta = -sgn * gamma if contact_angles else 0.0
            data[:, j, 0] = np.array([1.0, delta, r0, sgn *
                                      half_distance, a, b, C[0], C[1], C[2], 1.0, 1.0, 0.0,
                                      0.0])
            data[:, j, 0, F_R] = r0 + sgn * gamma * shifts
            data[:, j, 1] = data[:, j, 0]
            data[:, j, 1, F_SHARE] = 0.0
        return cls(shifts, data, float(reference_load), float(r0), delta_r=2 * gamma * shifts)


@njit(cache=True, nogil=True)
def lookup(shift, data, y, out):
    """Linear interpolation of the table at shift y (clamped at the ends) into out
    (2, 2, nfields); returns True when y lies outside the table."""
    n = shift.size
    h = shift[1] - shift[0]
    t = (y - shift[0]) / h
    outside = t < 0.0 or t > n - 1
    t = min(max(t, 0.0), n - 1.0)
    i = min(int(t), n - 2)
    w = t - i
    for j in range(2):
        for k in range(2):
            for f in range(data.shape[3]):
                out[j, k, f] = (1.0 - w) * data[i, j, k, f] + w * data[i + 1, j, k, f]
    return outside


def python_patch_forces(model, material, friction, N, A, B, xi, eta, phi, V, grid):
    """(F_x, F_y, M_z) of one patch with any registered tangential model (its Python
    ``solve``) on the Hertz patch with curvatures A, B and normal force N."""
    if N <= 0:
        return 0.0, 0.0, 0.0
    geo = ContactGeometry(curvatures=(A, B))
    ns = get_normal_model("hertz").solve(geo, material, normal_force=N, grid=grid)
    ts = model.solve(ns, geo, material, creepage=(xi, eta, phi), friction=friction, velocity=V)
    return ts.fx, ts.fy, ts.mz
