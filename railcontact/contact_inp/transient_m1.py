"""CONTACT's module 1 (wheel-rail) transient problems: T = 1 (shift, material-fixed
grid) and T = 2 (transient rolling, contact-fixed grid), case after case.

A module 1 case with T = 1 or 2 is mapped as its steady counterpart
(:func:`railcontact.contact_inp.mapping.map_case`, with T = 3), its normal problem
solved by the wheel-rail case (:func:`railcontact.cases.solve.solve`: the
contact search, the patches, the vertical position or force), and each patch's
tangential problem by one time step of the exact solver
(:class:`railcontact.tangential.exact.ExactTangentialModel`, mode
``"transient"``: the same semi-smooth Newton iteration and influence
coefficients as steady rolling) from the previous time instance.  A rail placed
at RAILY0 near the track centre (a case on rail surfaces,
:func:`railcontact.cases.surfaces.solve_on_surfaces`) takes the same model.

The kinematics (CONTACT's user guide, "Wheelset position and velocity" and
"Identification of contact patches"):

* T = 1: the wheelset's velocities are the distances moved per time step (the
  time step taken as 1 s): VS the forward shift, VPITCH the pitch angle turned,
  ... .  The rigid shift of the rail against the wheel over the step is the
  relative velocity of the contact point times 1 s: the patch's kinematic
  creepages (xi, eta, phi) times its rolling velocity V.  The grid is fixed in
  the rail's material: the previous tractions act at the same track positions
  x_tr = S_WS + x (S_WS, the wheelset's position along the track of each case).
* T = 2: the grid moves with the contact; per step the contact rolls DQ = DQREL
  DX over the rail, the rigid shift is DQ (xi - phi y, eta + phi (x + DQ/6)), and
  the previous tractions act DQ behind (towards -x) where they were; within DQ of
  the leading edge CONTACT's leading-edge correction
  (:func:`railcontact.tangential.exact.leading_edge`).

What carries over follows the P digit (user guide, "P - PVTIME"): P = 0 the last
case's tractions (a steady-rolling case's too) are the previous instance; P = 1
and P = 2 start from zero tangential tractions; P = 3 repeats the last case's
step from its previous instance.

The previous instance is kept per patch as tractions on its element centres,
each placed in the materials along the track (x_tr, S_WS included) and across
the rail as CONTACT's super-grid places it: the rail's s (the chord length along
its points) at the patch's reference point plus the element's distance from it
in the tangent plane, so that the element of a grid laid on the super-grid
(:class:`SupergridNormal`) keeps its place from case to case.  A new
patch takes its predecessors' tractions as CONTACT does (:func:`carried_tractions`;
``m_wr_locatecp.f90``, ``wr_connect_cps``, and ``m_wr_solvecp.f90``,
``merge_prev_potcon``): a previous patch with loaded elements on its grid within
its own band (halfway to the other patches of its wheel) is a predecessor, and
every new patch connected to it takes its whole previous solution (a patch that
splits gives each part a copy, patches that merge give all theirs), on the new
grid extended to the rectangle that also holds the contact area CONTACT keeps
with the predecessor (its element division of the time before,
:attr:`PatchState.kept`: after a steady case its own contact area, after a
transient step with P = 0, 1, 3 that of the patches it continued, after P = 2
none, the old grid's first element); tractions outside that rectangle are lost.
Patches that merge (t1_merge_cp), split (t1_split_cp, t3_t2_conformal case 3) or
move so take the old tractions where they acted.  The tractions are carried to
the new grid by area weighting (each old element's force shared among the four
new elements around its centre: total force and moment kept; where the grids
coincide, as CONTACT's super-grid makes them, the transfer is exact); their
displacement difference at the new elements is then that of the previous time step
(:func:`railcontact.tangential.exact.previous_displacement`).

A conformal patch (DISCNS = 4, kept by D = 0, 1; :mod:`railcontact.cases.conformal`)
takes the same step on its developed grid (x, s): its conformal part of the rigid
slip (:func:`railcontact.geometry.conformal.conformal_slip`) is the step's extra
slip, read as the creepages are (times 1 s for T = 1, times DQ with the spin DQ/6
ahead for T = 2), each column's friction that of its local angle, and the patch's
forces its bar forces; a column's place along the rail profile is the reference
point's arc length plus s (the reference curve follows the rail profile).

Units: CONTACT's (mm, N) at the boundary, SI inside.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from dataclasses import dataclass

import numpy as np

from ..cases.balance import solve_at_position, solve_wheel_rail
from ..cases.bodies import build_wheelset_track
from ..cases.case import case_from_dict
from ..cases.patches import case_models
from ..cases.results import PatchResult, SolveResult
from ..cases.surfaces import solve_on_surfaces
from ..core.errors import RailContactError
from ..geometry.conformal import conformal_slip
from ..geometry.gap import GapEvaluator, SampledWheelGap
from ..tangential.exact import ExactTangentialModel
from .mapping import map_case
from .reader import InpCase, InpError
from .table import rail_coordinates, rows

log = logging.getLogger(__name__)

MM = 1e-3
#: the exact solver's tolerance in a time step (largest complementarity residual
#: over the largest traction bound)
TANGENTIAL_TOL = 1e-8
TANGENTIAL_MAXITER = 200


def handles(case: InpCase) -> bool:
    """Whether a case is solved here: module 1 with a transient tangential problem
    (T = 1, 2)."""
    return case.module == 1 and case.digits["T"] in (1, 2)


#: T = 1 reads the distances moved per step in the places of the velocities
SHIFTS = {"SHFT_SWS": "VS_WS", "SHFT_YWS": "VY_WS", "SHFT_ZWS": "VZ_WS", "SHFT_ROL": "VROLL",
          "SHFT_YAW": "VYAW", "SHFT_WPIT": "VPITCH"}


def shift_scale(case: InpCase) -> float:
    """T = 1: the factor on the shifts per step that makes the forward one 1 m
    (its kinematic creepages are ratios of the velocities, unchanged; the shifts
    are the creepages times the rolling velocity over this factor)."""
    vs = case.values.get("SHFT_SWS", case.values.get("VS_WS"))
    if vs is None or not vs > 0:
        raise _unsupported(case, f"SHFT_SWS = {vs!r} mm with TANG = 1", "expected a forward "
                                 "shift per step > 0")
    return 1000.0 / vs


def _steady(case: InpCase) -> InpCase:
    """The case with T = 3: what the mapping onto a wheel-rail case checks; for T = 1
    the shifts per step as the velocities (a time step of 1 s)."""
    values = dict(case.values)
    if case.digits["T"] == 1:
        for shift, velocity in SHIFTS.items():
            if shift in values:
                values[velocity] = values[shift]
        k = shift_scale(case)
        for velocity in SHIFTS.values():
            if values.get(velocity) is not None:
                values[velocity] = values[velocity] * k
    return dataclasses.replace(case, digits={**case.digits, "T": 3}, values=values)


def _unsupported(case, what, expected):
    return InpError(f"{case.where()}: {what} is not supported; {expected}")


def check(case: InpCase, profile_dirs=()) -> None:
    """The one-line InpError of an option a transient module 1 case does not
    support (the mapping's checks of its steady counterpart, then these): the
    exact tangential model (M = 0), identical materials, a rail profile (not
    slices or a roller rig)."""
    mapped = map_case(_steady(case), profile_dirs)
    d = case.digits
    raw = mapped.raw
    if mapped.meta.get("surfaces") and ("slices" in raw["rail"] or "roller" in raw):
        raise _unsupported(case, f"TANG = {d['T']} with rail slices or a roller rig",
                           "expected a rail profile (placed by its gauge face or at RAILY0)")
    if d["F"] != 0:
        raise _unsupported(case, f"TANG = {d['T']} with FORCE = {d['F']}",
                           "expected FORCE = 0 (the pitch velocity or shift prescribed)")
    if d["M"] != 0:
        raise _unsupported(case, f"TANG = {d['T']} with MATER = {d['M']}",
                           "expected MATER = 0 (the exact tangential model)")
    discns = d["D"] if d["D"] >= 2 else case.values.get("DISCNS")
    if discns not in (None, 2, 4) and not mapped.meta.get("surfaces"):
        # D = 0, 1 keep an earlier case's contact search (t3_t1_conformal: D = 4)
        raise _unsupported(case, f"TANG = {d['T']} with DISCNS = {discns}",
                           "expected DISCNS = 2 (planar contact, contact locus) or 4 "
                           "(conformal)")
    mat = mapped.raw["material"]
    if "wheel_young_modulus" in mat:
        raise _unsupported(case, f"TANG = {d['T']} with dissimilar materials",
                           "expected GG1 = GG2 and POISS1 = POISS2")
    if d["T"] == 2:
        dq = case.values.get("DQREL")
        if dq is None or not dq > 0 or abs(dq - round(dq)) > 1e-9:
            raise _unsupported(case, f"DQREL = {dq!r} with TANG = 2", "expected a whole "
                                     "number of elements per step (>= 1)")
    vs = case.values.get("VS_WS") or 0.0
    if d["T"] == 2 and not vs > 0:
        raise _unsupported(case, f"VS = {vs:g} mm/s with TANG = 2", "expected VS > 0")


@dataclass
class PatchState:
    """A patch's tangential tractions on the rail [Pa] at the end of a time step on
    its grid's element centres ``x``, ``y`` [m], with where the grid lies in the
    materials: ``x0`` [m] the track position of its reference point (the rail's
    material coordinate, S_WS included), ``m`` [m] per grid column the arc length
    along the rail profile where the column lies (:class:`_Frames`), signed to
    increase with y.

    ``area`` is the rectangle (x_lo, x_hi, m_lo, m_hi) [m] of the element centres
    in contact at this instance (x along the track as ``x0 + x``); ``kept`` the
    rectangle of the earlier contact area that CONTACT keeps with the patch (its
    element division of the previous time, ``igv``), over which a following
    patch's grid is extended (:func:`carried_tractions`): after a steady case its
    own contact area, after a transient case that continued earlier patches (P = 0,
    1, 3) their contact areas, else (P = 2, a new patch) none: None, the grid's
    first element."""

    x0: float
    m: np.ndarray
    x: np.ndarray
    y: np.ndarray
    px: np.ndarray
    py: np.ndarray
    area: tuple | None = None
    kept: tuple | None = None


def _placement(s: PatchState, x0, m_of, x, y, back, bounds):
    """Where the loaded elements of a previous patch ``s`` fall on a new patch's grid
    (see :func:`carried_tractions`): their mask in ``s``, their material place
    (x_tr before the material moved ``back``, m), fractional indices (fi, fj) on
    the new grid and the columns' places ``(cols, m_cols)`` used; and whether ``s``
    is the new patch's predecessor (loaded elements on its grid within its band)."""
    mx, my = x.size, y.size
    dy = float(y[1] - y[0])
    # the new grid's columns along the rail profile, far enough to hold every old
    # traction (the arc length grows about as y)
    span = float(np.ptp(m_of(y[[0, -1]]))) + float(np.ptp(s.m))
    extra = int(min(math.ceil(span / dy) + 2, 2000))
    cols = np.arange(-extra, my + extra)
    m_cols = m_of(y[0] + cols * dy)
    keep = (s.px != 0.0) | (s.py != 0.0)
    X, M = np.broadcast_arrays(s.x[:, None], s.m[None, :])
    xm, mm = X[keep] + s.x0, M[keep]
    fi = (xm - back - x0 - x[0]) / float(x[1] - x[0])
    fj = np.interp(mm, m_cols, cols)
    yy = y[0] + fj * dy
    band = (yy >= bounds[0]) & (yy <= bounds[1])
    on = band & (fi > -0.5) & (fi < mx - 0.5) & (fj > -0.5) & (fj < my - 0.5)
    return keep, xm, mm, fi, fj, bool(on.any())


def is_predecessor(s: PatchState, x0, m_of, x, y, back: float = 0.0,
                   bounds=(-math.inf, math.inf)) -> bool:
    """Whether the previous patch ``s`` is a predecessor of the new patch on the grid
    (x, y) (as in :func:`carried_tractions`)."""
    if x.size < 2 or y.size < 2 or not ((s.px != 0.0) | (s.py != 0.0)).any():
        return False
    return _placement(s, x0, m_of, x, y, back, bounds)[5]


def carried_tractions(states, x0, m_of, x, y, back: float = 0.0,
                      bounds=(-math.inf, math.inf)):
    """The tractions [Pa] of the previous patches ``states`` that a patch takes: the
    patch's reference point at ``x0`` along the track, ``m_of(y)`` the arc length
    along the rail profile of its lateral coordinate y (see :class:`PatchState`),
    the material moved ``back`` [m] towards -x since (T = 2: DQ).

    CONTACT's rule (``m_wr_locatecp.f90``, ``wr_connect_cps``, ``wr_update_allcps``;
    ``m_wr_solvecp.f90``, ``merge_prev_potcon``): a previous patch is the new one's
    predecessor where some of its loaded elements lie on the new grid within the
    patch's own band ``bounds`` (patch coordinate y [m], halfway to the other
    patches of its wheel); every new patch connected to it takes its whole
    previous solution (patches that split each a copy, patches that merge all of
    theirs) on its grid extended to the rectangle that also holds the
    predecessor's kept contact area (:attr:`PatchState.kept`; None: the
    predecessor grid's first element): the predecessor's tractions inside that
    rectangle are carried, those outside it are lost.  A patch split from a
    steady or continued contact area so starts from all of the area's tractions;
    one split from a contact formed in a P = 2 step (t1_split_cp) from those
    between the old grid's first element and its own grid's end.  Each old
    element's force goes to the four elements around its centre by area weighting
    (force and moment kept; exact where the grids coincide).  Returns the extended
    grid's centres (xe, ye) [m] and the tractions on it."""
    mx, my = x.size, y.size
    dx, dy = float(x[1] - x[0]), float(y[1] - y[0])
    pts = []
    for s in states:
        if not ((s.px != 0.0) | (s.py != 0.0)).any():
            continue
        keep, xm, mm, fi, fj, connected = _placement(s, x0, m_of, x, y, back, bounds)
        if not connected:
            continue
        # the merged grid: the new grid's rectangle and the kept area's, in the
        # grids' frame before the material moved
        if s.kept is not None:
            kx0, kx1, km0, km1 = s.kept
        else:
            kx0 = kx1 = s.x0 + float(s.x[0])
            km0 = km1 = float(s.m[0])
        gm = m_of(y[[0, -1]])
        lo_x, hi_x = min(x0 + x[0], kx0), max(x0 + x[-1], kx1)
        lo_m, hi_m = min(float(gm.min()), km0), max(float(gm.max()), km1)
        tol_x, tol_m = 0.5 * abs(dx), 0.5 * abs(dy)
        inside = ((xm > lo_x - tol_x) & (xm < hi_x + tol_x)
                  & (mm > lo_m - tol_m) & (mm < hi_m + tol_m))
        if not inside.any():
            continue
        da = float((s.x[1] - s.x[0]) * (s.y[1] - s.y[0]))
        fx, fy = s.px[keep][inside] * da, s.py[keep][inside] * da
        pts.append((fi[inside], fj[inside], fx, fy))
    if not pts:
        return x, y, np.zeros((mx, my)), np.zeros((mx, my))
    fi, fj, fx, fy = (np.concatenate([q[k] for q in pts]) for k in range(4))
    i0, j0 = np.floor(fi).astype(int), np.floor(fj).astype(int)
    lo_i, hi_i = min(0, int(i0.min())), max(mx, int(i0.max()) + 2)
    lo_j, hi_j = min(0, int(j0.min())), max(my, int(j0.max()) + 2)
    qx, qy = np.zeros((hi_i - lo_i, hi_j - lo_j)), np.zeros((hi_i - lo_i, hi_j - lo_j))
    wi, wj = fi - i0, fj - j0
    for di, wx in ((0, 1.0 - wi), (1, wi)):
        for dj, wy in ((0, 1.0 - wj), (1, wj)):
            at = (i0 + di - lo_i, j0 + dj - lo_j)
            np.add.at(qx, at, wx * wy * fx)
            np.add.at(qy, at, wx * wy * fy)
    xe = x[0] + dx * np.arange(lo_i, hi_i)
    ye = y[0] + dy * np.arange(lo_j, hi_j)
    return xe, ye, qx / (dx * dy), qy / (dx * dy)


@dataclass
class _Previous:
    """The previous time instance as :meth:`ExactTangentialModel.solve` reads it:
    a grid and tractions on the wheel (the rail's negated)."""

    x: np.ndarray
    y: np.ndarray
    traction_x: np.ndarray
    traction_y: np.ndarray


class _Frames:
    """Where a patch's grid lies in the materials for the case's rails and wheelset
    position S_WS [m]: ``frames(geom)`` gives the track position of its reference
    point (S_WS included) and the function y -> m, the place across the rail [m]
    of the patch's lateral coordinate y: on a planar patch the rail's s (chord
    length, :attr:`railcontact.profiles.profile.Profile.chord_spline`) at the
    reference point plus y (CONTACT's super-grid: s_r,ref + s_p), on a conformal
    patch the profile's arc length at the reference point plus y; signed to
    increase with y."""

    def __init__(self, case, s_ws: float):
        self.track, self.s_ws = build_wheelset_track(case)[1], s_ws

    def __call__(self, geom):
        sgn = 1.0 if geom.side == "right" else -1.0
        rail = self.track.rail(geom.side)
        c = math.cos(float(geom.contact_angle))
        y_ref = float(geom.y_rail)
        if getattr(geom, "surface", None) is not None:
            # a conformal patch's y is the arc length s along its reference curve,
            # which follows the rail profile: the profile's arc length from the
            # reference point's
            m_ref = sgn * float(rail.arc_length(y_ref))

            def m_of(y):
                return m_ref + np.asarray(y, dtype=float)
        else:
            # CONTACT's super-grid: a point's place across the rail is the rail's s
            # (chord length) at the reference point plus its distance in the plane
            m_ref = sgn * float(rail.chord_spline.s_at_y(y_ref))

            def m_of(y):
                return m_ref + np.asarray(y, dtype=float)

        return float(geom.position[0]) + self.s_ws, m_of


class _SurfaceFrames:
    """:class:`_Frames` of a case on rail surfaces (a rail profile placed at RAILY0,
    :mod:`railcontact.cases.surfaces`): a patch's track position is its ``s``
    (S_WS included), its lateral material coordinate the rail-profile position of
    its reference point plus y (signed to increase with y)."""

    def __call__(self, geom):
        sgn = 1.0 if geom.side == "right" else -1.0
        y_ref = sgn * float(geom.y_rail)

        def m_of(y):
            return y_ref + np.asarray(y, dtype=float)

        return float(geom.s), m_of


class SupergridNormal:
    """The case's normal model on CONTACT's transient grid (T = 1, 2: its
    "super-grid"; source ``m_wr_locatecp.f90``, ``set_cpatch_reference``, and
    ``m_wr_undefdist.f90``): the grid's origin lies in the patch's tangent plane at
    -sr_ref from the reference point across the track, sr_ref the rail's chord
    length s at the reference (0 where the rail profile's y = 0,
    :class:`railcontact.profiles.processing.ChordSpline`), and along the track at
    x_tr = -S_WS (T = 1: fixed in the rails) or 0 (T = 2); the element centres lie
    on the lattice DX, DS through it.  CONTACT's wheel samples
    (``wheel_sampling = "contact"``) are counted from that origin's lateral wheel
    coordinate (beyond the wheel profile: from its end), so that a grid point can
    fall anywhere between two samples.  A conformal patch's grid lies on the same
    lattice along its reference curve's arc length, its wheel samples counted from
    the same origin (:meth:`railcontact.geometry.conformal.ConformalGap.sampled`).
    Other patches (rail surfaces, bodies) and grids given by their number of
    elements are the model's own."""

    def __init__(self, model, t: int, s_ws: float, meta: dict, wheel_sampling: str = "exact"):
        self.model, self.t, self.s_ws, self.meta = model, t, s_ws, meta
        # the case's normal option the model was built with (CONTACT's wheel samples)
        self.sampled = wheel_sampling == "contact"

    def __getattr__(self, name):
        return getattr(self.model, name)

    def origin(self, geometry, element_size):
        """(geometry on CONTACT's grid and wheel samples) of a wheel-rail patch."""
        gf = geometry.gap_function
        conformal = getattr(geometry, "surface", None) is not None
        if conformal:
            # a conformal patch (CONTACT's compute_curved_potcon: in a transient
            # case its columns lie at multiples of DS of the rail's s, the arc
            # length s along the reference curve standing for it): the grid origin
            # -sr from the reference point along the curve; CONTACT's wheel samples
            # counted from the super-grid origin's lateral wheel coordinate as on a
            # planar patch
            conformal_gap, gf = gf, getattr(gf, "gapf", None)
        if element_size is None or not isinstance(gf, GapEvaluator):
            return geometry
        sr = rail_chord_length(gf.rail, float(geometry.y_rail), self.meta)
        x_ref = float(geometry.position[0])
        x_pot = -self.s_ws if self.t == 1 else 0.0       # the grid origin's x_tr
        # the origin in the side frame: along the track, then -sr along the plane
        P = gf.C + np.array([x_pot - x_ref, 0.0, 0.0]) - sr * gf.t
        y_origin = float((gf.R.T @ (P - gf.O))[1] - gf.e)
        out = dataclasses.replace(geometry, grid_origin=(x_pot - x_ref, -gf.sign * sr))
        if conformal:
            if self.sampled:
                out = dataclasses.replace(out, gap_function=conformal_gap.sampled(
                    geometry.y_wheel, float(element_size[1]), y_origin=y_origin))
            return out
        if self.sampled:
            out = dataclasses.replace(out, gap_function=SampledWheelGap(
                gf, geometry.y_wheel, float(element_size[1]), y_origin=y_origin))
        return out

    def solve(self, geometry, material, normal_force=None, penetration=None, **kw):
        return self.model.solve(self.origin(geometry, kw.get("element_size")), material,
                                normal_force=normal_force, penetration=penetration, **kw)


def rail_chord_length(rail, y_rail: float, meta: dict) -> float:
    """CONTACT's s [m] of the rail point at railcontact's rail-profile coordinate
    ``y_rail`` [m]: the chord length along the points from where the rail file's y
    is 0 (CONTACT's ``grid_make_arclength``: there when y increases strictly along
    the points, else at the point nearest the file's origin); ``meta`` the mapped
    case's frame (:func:`railcontact.contact_inp.table.rail_coordinates`)."""
    cs = rail.chord_spline
    yc, zc = rail_coordinates(cs.y, cs.z, meta)
    if np.all(np.diff(yc) > 0) and yc[0] <= 0.0 <= yc[-1]:
        s0 = float(np.interp(0.0, yc, cs.s))
    else:
        s0 = float(cs.s[int(np.argmin(yc * yc + zc * zc))])
    return float(cs.s_at_y(y_rail)) - s0


class TransientStep:
    """The tangential model of a transient module 1 case: one time step of the
    exact solver (:class:`ExactTangentialModel`, ``mode="transient"``) per patch,
    from the previous instance's tractions carried onto the patch's grid
    (:func:`carried_tractions`).  T = 1 (``dq = 0``): the rigid shift over the step
    is the patch's creepages times its rolling velocity over ``scale``
    (:func:`shift_scale`); T = 2: rolling over ``dq`` [m].

    Not "lazy": a vertical balance solves the step at every evaluation, since
    FASTSIM's steady-rolling lateral forces, the stand-in of a lazy model, are not a
    shift's (t1_force_cp: 0.6 % of the load in the vertical balance; with CONTACT's
    wheel sampling, ``wheel_sampling = "contact"``, enough to send the balance to
    a second root 2.4 um higher, where tread and gauge corner form separate
    patches)."""

    name = "exact"
    capabilities = frozenset({"friction-field"})

    def __init__(self, previous, frames, dq: float, scale: float):
        self.previous, self.frames, self.dq, self.scale = previous, frames, dq, scale
        self.model = ExactTangentialModel(tol=TANGENTIAL_TOL, maxiter=TANGENTIAL_MAXITER,
                                          mode="transient", step=dq)

    def solve(self, normal, geometry, material, creepage, friction, velocity,
              friction_scale=None, **_):
        x, y = np.asarray(normal.x), np.asarray(normal.y)
        prev = None
        if self.previous:
            x0, m_of = self.frames(geometry)
            xe, ye, qx, qy = carried_tractions(self.previous, x0, m_of, x, y, self.dq,
                                               geometry.bounds)
            # on the grid that the model's step maps onto this one (dq ahead)
            prev = _Previous(xe + self.dq, ye, -qx, -qy)
        # a conformal patch's part of the rigid slip, with the spin where the step
        # takes it (DQ/6 ahead in rolling), read as the creepages are
        extra = None
        if getattr(geometry, "surface", None) is not None:
            extra = conformal_slip(geometry, creepage, x, y, x_spin=x + self.dq / 6.0)
        if self.dq == 0.0:
            v = velocity / self.scale
            creepage = tuple(c * v for c in creepage)
            if extra is not None:
                extra = (extra[0] * v, extra[1] * v)
        return self.model.solve(normal, geometry, material, creepage, friction, velocity,
                                previous=prev, extra_slip=extra, friction_scale=friction_scale)


class WheelRailSequence:
    """Module 1 cases solved in file order with CONTACT's state rules for the
    transient ones (see the module's text).  ``run(case, profile_dirs)`` returns the
    case's rows (:mod:`.table`); ``remember(case, raw, result)`` keeps a steady
    case's tractions as a time instance."""

    def __init__(self):
        self.last: list | None = None           # PatchState of the last case
        self.last_previous: list | None = None  # the instance it started from

    def reset(self):
        self.last, self.last_previous = None, None

    def remember(self, case: InpCase | None, raw: dict | None, result) -> None:
        """A module 1 case solved elsewhere (steady rolling; ``raw`` its case
        dictionary): its tractions become the previous time instance of a
        following transient case."""
        if case is None or case.module != 1 or raw is None or result is None \
                or not result.patches or "rail" not in raw or "slices" in raw["rail"] \
                or "roller" in raw:
            self.reset()
            return
        try:
            frames = _SurfaceFrames() if "lateral_position" in raw["rail"] else _Frames(
                case_from_dict(raw, case.path.parent), (case.values.get("S_WS") or 0.0) * MM)
            self.last = [_state(p, frames) for p in result.patches
                         if p.tangential is not None]
        except RailContactError as exc:     # a case this path cannot continue from
            log.debug("no transient state kept from %s: %s", case.where(), exc)
            self.last = None
        self.last_previous = None

    def _previous(self, case) -> list:
        p = case.digits["P"]
        if p in (1, 2):
            return []
        if p == 3:
            return self.last_previous or []
        return self.last or []

    def run(self, case: InpCase, profile_dirs=()) -> list:
        check(case, profile_dirs)
        t0 = time.perf_counter()
        prev = self._previous(case)
        mapped = map_case(_steady(case), profile_dirs)
        c = case_from_dict(mapped.raw, case.path.parent)
        t = case.digits["T"]
        surfaces = bool(mapped.meta.get("surfaces"))
        frames = _SurfaceFrames() if surfaces else _Frames(c, (case.values.get("S_WS")
                                                               or 0.0) * MM)
        dq = (case.values["DQREL"] * case.values["DX"] * MM) if t == 2 else 0.0
        scale = shift_scale(case) if t == 1 else 1.0
        tmodel = TransientStep(prev, frames, dq, scale)
        if surfaces:
            res = solve_on_surfaces(c, tangential_model=tmodel)
            results = res.patches
        else:
            nname, _, nmodel, _, kw = case_models(c)
            nmodel = SupergridNormal(nmodel, t, (case.values.get("S_WS") or 0.0) * MM,
                                     mapped.meta,
                                     c.normal_options.get("wheel_sampling", "exact"))
            balance = None
            if c.wheel_rail.vertical_position is not None:
                results, contact = solve_at_position(c, nmodel, tmodel, kw)
            else:
                results, contact, balance = solve_wheel_rail(c, nmodel, tmodel, kw,
                                                             rtol=c.force_tolerance)
            res = SolveResult(results, nname, "exact", time.perf_counter() - t0, c.title,
                              contact.pose, contact, balance)
        # what CONTACT keeps of the earlier contact area with each patch: P = 2
        # clears it, P = 0, 1 (and 3) keep its predecessors' contact areas
        pv = case.digits["P"]
        pred = [] if pv == 2 else (prev if pv == 3 else (self.last or []))
        self.last_previous = prev
        self.last = [_state(p, frames, _kept_area(pred, p, frames, dq)) for p in results]
        table = rows(res, mapped)
        if t == 1:
            # CONTACT prints a shift's CKSI, CETA [mm] and CPHI [rad], VELOC 1
            for r, p in zip(table, results):
                v = p.geometry.velocity / scale
                r.update(cksi=p.creepage[0] * v / MM, ceta=p.creepage[1] * v / MM,
                         cphi_per_mm=p.creepage[2] * v, veloc_mm_s=1.0)
        for r in table:
            r["T"] = t
        return table


def _state(p: PatchResult, frames, kept=False) -> PatchState:
    """The patch's :class:`PatchState`; ``kept`` its kept contact area
    (:attr:`PatchState.kept`), False: its own contact area (a steady case)."""
    x0, m_of = frames(p.geometry)
    ts = p.tangential
    x, y = np.asarray(ts.x), np.asarray(ts.y)
    m = m_of(y)
    contact = np.asarray(ts.contact, dtype=bool)
    area = None
    if contact.any():
        rows_, cols_ = contact.any(axis=1), contact.any(axis=0)
        area = (x0 + float(x[rows_].min()), x0 + float(x[rows_].max()),
                float(m[cols_].min()), float(m[cols_].max()))
    return PatchState(x0, m, x, y, -ts.traction_x, -ts.traction_y, area,
                      area if kept is False else kept)


def _kept_area(states, p: PatchResult, frames, back: float):
    """CONTACT's kept contact area of a patch after a transient step that continued
    the previous patches ``states`` (its element division of the previous time,
    copied at the step's start, P = 0, 1): the rectangle over the contact areas of
    its predecessors; None where it has none."""
    x0, m_of = frames(p.geometry)
    x, y = np.asarray(p.tangential.x), np.asarray(p.tangential.y)
    boxes = [s.area for s in states if s.area is not None
             and is_predecessor(s, x0, m_of, x, y, back, p.geometry.bounds)]
    if not boxes:
        return None
    b = np.array(boxes)
    return (float(b[:, 0].min()), float(b[:, 1].max()), float(b[:, 2].min()),
            float(b[:, 3].max()))


def run_case(seq: WheelRailSequence, case: InpCase, profile_dirs=()) -> list:
    """:meth:`WheelRailSequence.run` with a solver error as the case's one row."""
    try:
        return seq.run(case, profile_dirs)
    except RailContactError as exc:
        seq.reset()
        return [{"case": case.number, "module": 1, "patch": 0, "npatch": 0,
                 "converged": False, "message": f"error: {exc}"}]
