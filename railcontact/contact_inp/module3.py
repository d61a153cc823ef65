"""CONTACT's module 3 on its own grid: non-Hertzian geometries (IPOTCN > 0), the
transient problems (TANG = 1, shift; TANG = 2, transient rolling), prescribed
forces, slip-velocity dependent friction and surface temperatures, case after case.

A case with a potential contact area given by its grid (IPOTCN = 1 .. 4, the
undeformed distance IBASE = 1, 2, 3), a transient tangential problem, the approach
or a tangential force prescribed, friction laws L = 2-4 or temperatures (H = 1, 3)
is solved here (:func:`handles`), on CONTACT's grid, rather than through a
railcontact case file:

* normal problem: Kalker's exact theory (:func:`railcontact.normal.polonsky_keer.polonsky_keer`
  with the influence coefficients of :mod:`railcontact.normal.influence`), the
  normal force FN (N = 1) or the approach PEN (N = 0) given;
* tangential problem: the exact solver of :mod:`railcontact.tangential.exact`,
  steady rolling (T = 3, :func:`~railcontact.tangential.exact.steady_rolling`)
  or one time step of a transient problem (T = 1, 2,
  :func:`~railcontact.tangential.exact.transient_step`; T = 2 with CONTACT's
  leading-edge correction, :func:`~railcontact.tangential.exact.leading_edge_slip`),
  with the creepages
  (F = 0) or the relative forces FX/(FSTAT FN) (F = 1, with CETA; F = 2, with
  FY) given; a force is met by Brent's method on the creepage (or shift);
  falling friction by a fixed point of the coefficients (:func:`friction_law`);
* temperatures: :mod:`railcontact.tangential.temperature` (steady rolling);
* dissimilar materials (K != 0) in steady rolling and in a shift (T = 1): the
  normal and tangential problems solved in turn, the pressure's tangential
  displacements a rigid slip (in a shift, those of the step: u_t(p) - u_t(p')),
  the tractions' normal ones a gap (:mod:`railcontact.cases.coupling`), until
  neither changes (bentall.inp, spence35.inp);
* modified FASTSIM (M = 2, 3) and Modified FaStrip (M = 5) with the elliptical or
  parabolic traction bound (B = 2, 3) of a Hertzian case: :func:`solve_fastsim`.

What carries over from case to case follows CONTACT's PVTIME digit (user guide,
"P - PVTIME"): the tractions that a case leaves are the next case's previous time
instance where it has P = 0; P = 1 and P = 2 start from zero tangential tractions
(P = 2: a new sequence); P = 3 repeats the last case's time step (its previous
instance is kept).  The inputs kept or re-read between cases are the reader's
(:mod:`.reader`, the D, Z, C digits).

Rigid shift per step of element I (user guide, "Tangential quantities in case of
a shift" and "... of rolling"), in mm:

* T = 1: W = (CKSI - CPHI y, CETA + CPHI x), CKSI, CETA the shift [mm], CPHI [rad];
  the coordinates are material-fixed, so the previous tractions act where they
  were (a grid that moves between cases does so by whole elements);
* T = 2: W = DQ (CKSI - CPHI y, CETA + CPHI (x + DQ/6)), creepages; the grid moves
  with the contact by DQ per step (rolling direction CHI = 0 or 180 degrees), so
  the previous displacements are taken DQ upstream.

Units: CONTACT's (mm, N, N/mm^2) at this boundary, SI inside.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from ..core.hertz_theory import hertz_curvatures, hertz_ellipse
from ..normal.influence import normal_operator
from ..normal.polonsky_keer import polonsky_keer
from ..tangential.friction import SlipVelocityFriction, TemperatureFriction
from ..tangential.temperature import ThermalProperties, flash_temperatures
from ..core.errors import RailContactError
from ..core.materials import InterfaceLayer
from ..tangential.exact import (grid_offset, layer_bound, leading_edge_slip, plastic_flow,
                                previous_displacement, shifted_tractions, steady_rolling,
                                transient_step)
from ..cases.coupling import normal_gap_from_tractions, slip_from_pressure
from .mapping import curvature_from_axis_ratio, layer_options
from .viscoelastic import (active_set_normal, check_viscoelastic, viscoelastic_normal_operator,
                           viscoelastic_pair)
from .reader import InpCase, InpError

log = logging.getLogger(__name__)

MM = 1e-3
#: relative tolerance of the normal iteration and of the tangential residual
NORMAL_TOL = 1e-9
TANGENTIAL_TOL = 1e-9
#: a prescribed relative force is met to this absolute tolerance (of FX / (FSTAT FN))
FORCE_TOL = 1e-7


def handles(case: InpCase) -> bool:
    """Whether the case is solved here: module 3 with a grid-given potential contact
    area (IPOTCN > 0), a transient tangential problem (T = 1, 2), a prescribed
    tangential force (F = 1, 2), the approach prescribed (N = 0), surface
    temperatures (H = 1, 3), a slip-velocity dependent friction law (L = 2-6) or
    an interfacial layer (M = 4)."""
    return case.module == 3 and (is_fastsim_grid(case) or case.digits["T"] in (1, 2)
                                 or case.digits["M"] == 4
                                 or case.digits["F"] in (1, 2)
                                 or case.digits["N"] == 0 or case.digits["H"] in (1, 3)
                                 or case.values.get("FRICTION_LAW", 0) not in (0, 1)
                                 or (case.values.get("IPOTCN") or -1) > 0)


def _unsupported(case, what, expected):
    return InpError(f"{case.where()}: {what} is not supported; {expected}")


def _need(case, name):
    v = case.values.get(name)
    if v is None:
        raise InpError(f"{case.where()}: {name} is not set (no earlier case gave it)")
    return v


def is_fastsim_grid(case: InpCase) -> bool:
    """Modified FASTSIM (M = 2, 3) or Modified FaStrip (M = 5) with the elliptical or
    parabolic traction bound (B = 2, 3) of a Hertzian case: solved on CONTACT's grid
    (:func:`solve_fastsim`)."""
    return case.module == 3 and case.digits["M"] in (2, 3, 5) and case.digits["B"] in (2, 3)


def check(case: InpCase) -> None:
    """The one-line InpError of an option this path does not support."""
    d = case.digits
    if is_fastsim_grid(case):
        _check_fastsim(case)
        return
    allowed = {"B": (0,), "T": (0, 1, 2, 3), "N": (0, 1), "F": (0, 1, 2), "S": (0, 1, 2, 3),
               "L": (0, 1, 2, 3, 4, 6), "M": (0, 1, 4), "H": (0, 1, 3), "M2": (0, 1),
               "E": (0, 1, 9), "C3": (0, 1, 2, 9)}
    names = {"B": "BOUND", "T": "TANG", "N": "NORM", "F": "FORCE", "S": "STRESS",
             "L": "FRCLAW", "M": "MATER", "H": "HEAT", "M2": "MATER2", "E": "EXRHS",
             "C3": "INFLCF"}
    for k, vals in allowed.items():
        if d[k] not in vals:
            raise _unsupported(case, f"{names[k]} = {d[k]} with the grid-given or transient "
                                     "module 3 problem", f"expected {names[k]} in {vals}")
    if d["T"]:
        friction_law(case)
    if case.values.get("FRICTION_LAW", 0) == 6 and (d["T"] != 3 or d["H"] not in (1, 3)):
        raise _unsupported(case, f"FRCLAW = 6 with TANG = {d['T']}, HEAT = {d['H']}",
                           "expected temperature dependent friction in steady rolling (T = 3) "
                           "with surface temperatures (H = 1, 3)")
    if case.values.get("NVF", 0):
        raise _unsupported(case, "friction variation (VARFRC)", "expected V = 0")
    ipotcn = _need(case, "IPOTCN")
    if ipotcn > 0 and case.values.get("B") is None:
        raise InpError(f"{case.where()}: IPOTCN = {ipotcn} without an undeformed distance "
                       "(IBASE, IPLAN and B1 .. B6)")
    if ipotcn < 0 and ipotcn not in (-1, -2, -3):
        raise _unsupported(case, f"IPOTCN = {ipotcn}", "expected -1, -2, -3 or 1 .. 4")
    if (case.values.get("SPINXO") or 0.0) or (case.values.get("SPINYO") or 0.0):
        raise _unsupported(case, "SPINXO, SPINYO (a spin centre off the origin)",
                           "expected them left out")
    if d["T"] in (2, 3):
        chi = _need(case, "CHI")
        if abs(math.sin(chi)) > 1e-9:
            raise _unsupported(case, f"CHI = {chi:g} rad", "expected 0 or 180d (pi)")
    if d["H"] in (1, 3) and d["T"] != 3:
        raise _unsupported(case, f"HEAT = {d['H']} with TANG = {d['T']}", "expected surface "
                                 "temperatures in steady rolling (T = 3)")
    if d["H"] in (1, 3):
        for k in ("BKTEMP1", "HEATCP1", "LAMBDA1", "DENS1", "BKTEMP2", "HEATCP2", "LAMBDA2",
                  "DENS2"):
            _need(case, k)
    g1, g2 = _need(case, "GG1"), _need(case, "GG2")
    n1, n2 = _need(case, "POISS1"), _need(case, "POISS2")
    if d["M"] == 4:
        interface_layer(case)
    if d["M"] == 1:
        check_viscoelastic(case)
    if _dissimilar(case) and d["T"] == 2:
        raise _unsupported(case, "dissimilar materials (K != 0) with transient rolling (T = 2)",
                           "expected quasi-identical materials ((1 - 2 nu)/G equal for both "
                           "bodies), a shift (T = 1) or steady rolling (T = 3)")
    if _dissimilar(case) and d["T"] == 3 and d["L"] not in (0, 1):
        raise _unsupported(case, f"dissimilar materials with FRCLAW = {d['L']}",
                           "expected Coulomb friction (L = 0, 1)")


def _dissimilar(case) -> bool:
    """Whether the bodies' materials couple the normal and tangential problems
    (Kalker's difference parameter K != 0)."""
    g1, g2 = _need(case, "GG1"), _need(case, "GG2")
    n1, n2 = _need(case, "POISS1"), _need(case, "POISS2")
    return abs((1 - 2 * n1) / g1 - (1 - 2 * n2) / g2) > 1e-9 * (1 / g1 + 1 / g2)


#: the alternation between the normal and tangential problems of dissimilar bodies
#: stops when both change by less than this (relative to p_max, mu p_max)
COUPLING_TOL = 1e-7
COUPLING_ITERATIONS = 50


@dataclass
class Grid:
    """Element centres [m] of the potential contact area and element sizes [m]."""

    x: np.ndarray
    y: np.ndarray
    dx: float
    dy: float

    @property
    def origin(self):
        return float(self.x[0]), float(self.y[0])


@dataclass
class Instance:
    """Tangential tractions [Pa] on body 1 of a time instance and their grid (and
    an interfacial layer's accumulated plastic displacement u*_pl [m], M = 4)."""

    px: np.ndarray
    py: np.ndarray
    grid: Grid
    #: the pressure [Pa] of that instance (dissimilar bodies: its tangential
    #: displacements are the previous ones of the shift)
    pn: np.ndarray | None = None
    #: the interfacial layer's accumulated plastic displacement [m] (M = 4)
    ustar: np.ndarray | None = None


def interface_layer(case) -> InterfaceLayer | None:
    """The interfacial layer of MATER = 4 (GG3 [N/mm^2], LAYTHK [mm], TAU_C0
    [N/mm^2], K_TAU [N/mm^3]; TAU_C0 <= 0: no plasticity), or None."""
    if case.digits["M"] != 4:
        return None
    try:
        return InterfaceLayer(**layer_options(case))
    except RailContactError as exc:
        raise InpError(f"{case.where()}: GG3, LAYTHK, TAU_C0, K_TAU = "
                       f"{_need(case, 'GG3'):g}, {_need(case, 'LAYTHK'):g}, "
                       f"{_need(case, 'TAU_C0'):g}, {_need(case, 'K_TAU'):g}: {exc}") from None


def _materials(case):
    """(E* [Pa] of the normal problem, G [Pa] and nu of the tangential one):
    Kalker's combined constants 1/G = (1/G1 + 1/G2)/2, nu/G = (nu1/G1 + nu2/G2)/2."""
    g1, g2 = _need(case, "GG1") * 1e6, _need(case, "GG2") * 1e6
    n1, n2 = _need(case, "POISS1"), _need(case, "POISS2")
    es = 1.0 / ((1 - n1) / (2 * g1) + (1 - n2) / (2 * g2))
    G = 2.0 / (1 / g1 + 1 / g2)
    nu = 0.5 * G * (n1 / g1 + n2 / g2)
    return es, G, nu


def _grid_and_gap(case, es):
    """The grid and the undeformed distance h [m] on it (before the approach)."""
    v = case.values
    ipotcn = v["IPOTCN"]
    mx, my = int(v["MX"]), int(v["MY"])
    if ipotcn < 0:                     # a Hertzian geometry on CONTACT's grid
        fn = v.get("FN")
        if ipotcn == -3:
            a, b = v["AA"] * MM, v["BB"] * MM
            A, B = hertz_curvatures(a, b, es, fn)
        else:
            A = v["A1"] / MM
            B = v["B1"] / MM if ipotcn == -1 else curvature_from_axis_ratio(A, v["AOB"])
            h = hertz_ellipse(A, B, es, force=fn)
            a, b = h.a, h.b
        s = v["SCALE"]
        dx, dy = 2 * s * a / mx, 2 * s * b / my
        x = -s * a + (np.arange(mx) + 0.5) * dx
        y = -s * b + (np.arange(my) + 0.5) * dy
        return Grid(x, y, dx, dy), A * x[:, None] ** 2 + B * y[None, :] ** 2
    if ipotcn == 1:
        dx, dy = v["DX"], v["DY"]
        x0, y0 = v["XL"] + 0.5 * dx, v["YL"] + 0.5 * dy
    elif ipotcn == 2:
        dx, dy = (v["XH"] - v["XL"]) / mx, (v["YH"] - v["YL"]) / my
        x0, y0 = v["XL"] + 0.5 * dx, v["YL"] + 0.5 * dy
    elif ipotcn == 3:
        dx, dy = v["DX"], v["DY"]
        x0, y0 = v["XC1"], v["YC1"]
    else:
        if mx < 2 or my < 2:
            raise InpError(f"{case.where()}: IPOTCN = 4 with MX or MY = 1; expected both >= 2")
        dx, dy = (v["XCM"] - v["XC1"]) / (mx - 1), (v["YCM"] - v["YC1"]) / (my - 1)
        x0, y0 = v["XC1"], v["YC1"]
    if not (dx > 0 and dy > 0 and mx >= 1 and my >= 1):
        raise InpError(f"{case.where()}: potential contact MX, MY = {mx}, {my}, DX, DY = "
                       f"{dx:g}, {dy:g} mm: expected positive sizes")
    xm, ym = x0 + np.arange(mx) * dx, y0 + np.arange(my) * dy
    X, Y = xm[:, None], ym[None, :]
    if v["IBASE"] == 9:
        h = per_element(case, v["B"], 1)[..., 0]
    else:
        h = undeformed_distance(v["IBASE"], v["B"], X, Y)
    h = np.broadcast_to(h, (mx, my)).copy()
    return Grid(xm * MM, ym * MM, dx * MM, dy * MM), h * MM


def per_element(case, values, k: int) -> np.ndarray:
    """``k`` values per element in CONTACT's element order (I = ix + (iy - 1) MX, x
    fastest; IBASE = 9, EXRHS) as an (MX, MY, k) array; an InpError where their
    number is not the grid's."""
    mx, my = int(case.values["MX"]), int(case.values["MY"])
    a = np.asarray(values, dtype=float)
    if a.size != k * mx * my:
        raise InpError(f"{case.where()}: {a.size // k} values per element given for a grid "
                       f"of MX x MY = {mx} x {my}; expected {mx * my} (the grid changed?)")
    return a.reshape(my, mx, k).transpose(1, 0, 2)


def extra_slip(case) -> tuple | None:
    """CONTACT's EXRHS (E = 9, or kept by E = 1) as the extra rigid slip per element
    (x, y components, (MX, MY) each): relative slip in steady rolling (T = 3) and
    T = 2 (times DQ there), a shift [m] for T = 1 (user guide, equations of the
    rigid shift); None where there is none."""
    ex = case.values.get("EXRHS")
    if ex is None or case.digits["E"] == 0:
        return None
    a = per_element(case, ex, 2)
    scale = MM if case.digits["T"] == 1 else 1.0
    return a[..., 0] * scale, a[..., 1] * scale


def _numerical_influence(case) -> None:
    """Numerical influence coefficients (INFLCF = 9, file CFNAME) are not supported:
    the case's error names the file (and whether it is there), so that the other
    cases of its file run."""
    name = str(case.values.get("CFNAME") or "")
    path = case.path.parent / name.replace("\\", "/")
    where = "not found" if not path.is_file() else "found, but such files are not read"
    raise InpError(f"{case.where('CFNAME')}: numerical influence coefficients (INFLCF = 9) "
                   f"from {name!r} ({where}) are not supported; expected INFLCF = 2 "
                   "(the elastic half-space)")


def undeformed_distance(ibase, b, X, Y):
    """CONTACT's undeformed distance h(x, y) [mm] at (X, Y) [mm] (user guide,
    "Non-Hertzian geometry specification"): IBASE = 1, b1 x^2 + b2 x y + b3 y^2 + b4
    x + b5 y + b6; IBASE = 2, p(y) + (x - x_m)^2 / (2 R_m) with p linear between NN
    heights from Y1 in steps DY1 (extrapolated linearly); IBASE = 3, b1 sin(b2 (x
    - b3)) - b4 sin(b5 (x - b6)) + x^2/b7 + y^2/b8."""
    if ibase == 1:
        b1, b2, b3, b4, b5, b6 = b
        return b1 * X ** 2 + b2 * X * Y + b3 * Y ** 2 + b4 * X + b5 * Y + b6
    if ibase == 3:
        b1, b2, b3, b4, b5, b6, b7, b8 = b
        return (b1 * np.sin(b2 * (X - b3)) - b4 * np.sin(b5 * (X - b6)) + X ** 2 / b7
                + Y ** 2 / b8)
    nn, xm, rm, y1, dy1, heights = b
    hk = np.asarray(heights, dtype=float)
    if nn == 1:
        p = np.full(np.shape(Y), hk[0])
    else:
        t = (np.asarray(Y, dtype=float) - y1) / dy1
        k = np.clip(np.floor(t).astype(int), 0, nn - 2)
        p = hk[k] + (t - k) * (hk[k + 1] - hk[k])
    return p + (X - xm) ** 2 / (2.0 * rm)


@dataclass
class CaseResult:
    """One solved case: the normal and tangential solution on its grid (SI), the
    creepages (or shift) met and CONTACT's table row."""

    grid: Grid
    pressure: np.ndarray
    px: np.ndarray
    py: np.ndarray
    stick: np.ndarray
    row: dict
    mu: np.ndarray | None = None       # a slip-velocity dependent law's coefficients
    ustar: np.ndarray | None = None    # an interfacial layer's plastic displacement [m]
    #: both bodies' surface temperatures (T_1, T_2) [deg C] on the grid (H = 1, 3)
    temperature: tuple | None = None


class Sequence:
    """Module 3 cases solved in file order with CONTACT's state rules: the previous
    time instance (tangential tractions) carried from case to case by the PVTIME
    digit.  ``run(case)`` returns the case's table row."""

    def __init__(self):
        self.last: CaseResult | None = None       # the last case's solution
        self.last_previous: Instance | None = None    # the instance it started from

    def reset(self):
        """A case solved elsewhere (a Hertzian case file): no transient state."""
        self.last, self.last_previous = None, None

    def _previous(self, case) -> Instance | None:
        p, t = case.digits["P"], case.digits["T"]
        if t not in (1, 2) or p in (1, 2):
            return None
        if p == 3:
            return self.last_previous
        if self.last is None:
            return None
        # a steady rolling case's tractions are a time instance too (the steady
        # state of transient rolling on its grid)
        return Instance(self.last.px, self.last.py, self.last.grid, self.last.pressure,
                        self.last.ustar)

    def run(self, case: InpCase) -> dict:
        check(case)
        if is_fastsim_grid(case):
            # steady rolling with the simplified theory: no memory between cases
            self.last, self.last_previous = None, None
            return solve_fastsim(case).row
        prev = self._previous(case)
        start = None
        if self.last is not None and self.last.row.get("T") == case.digits["T"]:
            start = (self.last.row["cksi"], self.last.row["ceta"])
        mu_start = self.last.mu if self.last is not None else None
        res = solve_case(case, prev, start, mu_start)
        self.last, self.last_previous = res, prev
        return res.row


def _normal(case, grid, h, es):
    """Pressure [Pa], approach [m], converged."""
    dA = grid.dx * grid.dy
    if case.digits["M"] == 1:
        op = viscoelastic_normal_operator(grid.x.size, grid.y.size, grid.dx, grid.dy,
                                          viscoelastic_pair(case))
    else:
        op = normal_operator(grid.x.size, grid.y.size, grid.dx, grid.dy, es)
    if case.digits["N"] == 1:
        fn = _need(case, "FN")
        p, app, _, ok = polonsky_keer(op, h, dA, force=fn, tol=NORMAL_TOL, maxiter=20000)
    else:
        fn, app = None, _need(case, "PEN") * MM
        p, _, _, ok = polonsky_keer(op, h - app, dA, None, tol=NORMAL_TOL, maxiter=20000)
    if case.digits["M"] == 1:
        # the viscoelastic operator is not symmetric: the conjugate gradients' result
        # is the start of an active-set solve
        p, app1, _, ok = active_set_normal(op, h if fn is not None else h - app, dA, fn, p)
        app = app1 if fn is not None else app
    return p, app, ok


def _rigid_shift(case, grid, creep):
    """W [m] per element from (CKSI, CETA) and CPHI: T = 1 shifts, T = 2 creepages
    times DQ (spin taken DQ/6 along the rolling direction)."""
    cphi = _need(case, "CPHI")
    X, Y = grid.x[:, None], grid.y[None, :]
    if case.digits["T"] == 1:
        wx = creep[0] * MM - cphi * Y
        wy = creep[1] * MM + cphi * X
    else:
        dq = _need(case, "DQ") * MM
        cs = math.cos(_need(case, "CHI"))
        wx = dq * (creep[0] - cphi / MM * Y)
        wy = dq * (creep[1] + cphi / MM * (X + cs * dq / 6.0))
    shape = (grid.x.size, grid.y.size)
    return np.broadcast_to(wx, shape), np.broadcast_to(wy, shape)


def solve_case(case: InpCase, prev: Instance | None, start=None,
               mu_start=None) -> CaseResult:
    """Solve one case (normal, then tangential) from the previous instance ``prev``
    (None: zero previous tractions); ``start``: the creepages (CKSI, CETA) where the
    search for a prescribed force starts (the last case's); ``mu_start``: the last
    case's friction coefficients on its solver grid (INISLP = 0)."""
    d, v = case.digits, case.values
    if (v.get("INFLCF") or d["C3"]) == 9:
        _numerical_influence(case)
    es, G, nu = _materials(case)
    # the tangential kernels: the elastic pair's, or M = 1's viscoelastic ones
    G_t = viscoelastic_pair(case) if d["M"] == 1 else G
    grid, h = _grid_and_gap(case, es)
    t = d["T"]
    mx_given = grid.x.size
    if mx_given == 1 and t in (1, 3):
        # one element along x (a shift, or one column in steady rolling): the solver's
        # grid gets an empty second column ahead of it, kept out of contact (no
        # traction there, no effect)
        grid = Grid(np.array([grid.x[0], grid.x[0] + grid.dx]), grid.y, grid.dx, grid.dy)
        h = np.r_[h, np.full((1, h.shape[1]), 1.0)]
    pressure, approach, ok_n = _normal(case, grid, h, es)
    shape = pressure.shape
    law = friction_law(case) if t else None
    mu = (law.static if law is not None else _need(case, "FKIN")) if t else 0.0
    fstat = (law.static if law is not None else _need(case, "FSTAT")) if t else 0.0
    contact = np.ascontiguousarray(pressure > 0)
    bound = np.ascontiguousarray(mu * pressure)
    dA = grid.dx * grid.dy
    fn = float(pressure.sum() * dA)
    zero = np.zeros(shape)
    px, py, stick, ok_t, creep = zero, zero, np.zeros(shape, bool), True, (0.0, 0.0)
    state = {"mu": None, "w_extra": None}
    message = "" if ok_n else "normal problem not converged"
    layer = interface_layer(case)
    ustar_prev, ustar, nplast = None, None, 0
    if t:
        u_prev, p_start, pn_prev, u_here = (zero, zero), None, None, None
        if t in (1, 2) and prev is not None:
            shift = (0.0, 0.0)
            if t == 2:
                shift = (math.cos(_need(case, "CHI")) * _need(case, "DQ") * MM, 0.0)
            if abs(prev.grid.dx - grid.dx) > 1e-9 * grid.dx or \
                    abs(prev.grid.dy - grid.dy) > 1e-9 * grid.dy:
                raise InpError(f"{case.where()}: the element size changed from the previous "
                               "time instance's; expected the same DX, DY in a sequence")
            off = grid_offset(prev.grid.origin, grid.origin, (grid.dx, grid.dy), shift)
            u_prev = previous_displacement(prev.px, prev.py, off, shape, grid.dx, grid.dy,
                                           G, nu)
            # the start of the iteration: the previous tractions where the material is
            p_start = shifted_tractions(prev.px, prev.py, off, shape)
            if t == 2:
                # their displacement where they acted, for the leading edge
                off0 = grid_offset(prev.grid.origin, grid.origin, (grid.dx, grid.dy))
                u_here = previous_displacement(prev.px, prev.py, off0, shape, grid.dx,
                                               grid.dy, G, nu)
                if layer is not None:
                    q = shifted_tractions(prev.px, prev.py, off0, shape)
                    u_here = (u_here[0] + layer.flexibility * q[0],
                              u_here[1] + layer.flexibility * q[1])
            if prev.pn is not None:
                pn_prev = shifted_tractions(prev.pn, prev.pn, off, shape)[0]
            if layer is not None:
                # the layer's own displacement of the previous tractions, and the
                # plastic displacement the material has accumulated
                f = layer.flexibility
                u_prev = (u_prev[0] + f * p_start[0], u_prev[1] + f * p_start[1])
                if prev.ustar is not None:
                    ustar_prev = shifted_tractions(prev.ustar, zero, off, shape)[0]

        if grid.x.size < 2:
            raise InpError(f"{case.where()}: MX = 1 with TANG = {t}; expected MX >= 2 (the "
                           "rolling direction)")
        # one strip (MY = 1, a 2-D problem): the solver's grid gets an empty second
        # strip, outside the contact (no traction there, no effect)
        pad = grid.y.size == 1
        yt = np.array([grid.y[0], grid.y[0] + grid.dy]) if pad else grid.y
        widen = (lambda a: np.ascontiguousarray(np.c_[a, np.zeros(a.shape[0], a.dtype)])
                 ) if pad else (lambda a: a)
        ct, bt = widen(contact), widen(bound)
        u_t = (widen(u_prev[0]), widen(u_prev[1]))
        edge_step = (math.cos(_need(case, "CHI")) * _need(case, "DQ") * MM) if t == 2 else 0.0
        u_edge = None if u_here is None else (widen(u_here[0]), widen(u_here[1]))
        us_t = None if ustar_prev is None else widen(ustar_prev)

        def lb(b, mirror=lambda a: a):
            # the traction bound: an interfacial layer's (M = 4) with the friction's
            return b if layer is None else layer_bound(
                layer, b, None if us_t is None else mirror(us_t))
        state["p0"] = None if p_start is None else (widen(p_start[0]), widen(p_start[1]))

        # the absolute slip velocity [m/s] of a slip of the solver: steady rolling,
        # relative slip times V; transient, the slip distance over the step's time
        # DQ / V (T = 2) or 1 s (T = 1, as CONTACT takes it)
        veloc = _need(case, "VELOC") * MM
        per_slip = veloc if t == 3 else (veloc / (_need(case, "DQ") * MM) if t == 2 else 1.0)
        # the start of a slip-velocity dependent law's iteration picks the branch
        # where the solutions are several (user guide, INISLP): INISLP > 0 from the
        # static coefficient, < 0 from the kinetic one (which gives CONTACT's branches
        # on veldep_fric.inp), 0 from the last case's coefficients on the same grid
        inislp = case.values.get("INISLP") or 0
        state["mu"] = np.full(ct.shape, mu)
        if law is not None and inislp < 0:
            state["mu"] = np.full(ct.shape, law.mu_kin)
        elif law is not None and inislp == 0 and mu_start is not None \
                and mu_start.shape == ct.shape:
            state["mu"] = mu_start.copy()

        backwards = t == 3 and math.cos(_need(case, "CHI")) < 0
        memdst = (v.get("MEMDST") or 0.0) * MM if law is not None else 0.0
        # friction memory in steady rolling (user guide, "Friction memory"): the
        # material's coefficient relaxes towards mu_s(s_a) over the distance MEMDST,
        # from the static coefficient at the leading edge; one element per time step
        # DX / VELOC
        # L = 6: body 1's surface temperature of a solution on the solver's grid
        state["temperature"] = lambda out: surface_temperatures(
            case, grid.dx, out[:4], ct)[0]
        state["memory"] = None if memdst <= 0 else (
            memdst, (v.get("MEM_S0") or 0.0) * MM, grid.dx / veloc, backwards)

        def solve_once(cx, cy, bt):
            if t == 3 and backwards:
                # rolling towards -x (CHI = 180 deg): the problem mirrored in x (x' = -x:
                # CKSI and CPHI change sign), solved as rolling towards +x, mirrored back
                f = lambda a: np.ascontiguousarray(a[::-1])                 # noqa: E731
                p0 = state["p0"]
                p0 = None if p0 is None else (-f(p0[0]), f(p0[1]))
                out = steady_rolling(-grid.x[::-1], yt, f(ct), lb(f(bt), f),
                                     (-cx, cy, -_need(case, "CPHI") / MM), G_t, nu,
                                     TANGENTIAL_TOL, 200, p0=p0, w_extra=state["w_extra"])
                px_, py_, sx_, sy_, st_, it_, ok_ = out
                return -f(px_), f(py_), -f(sx_), f(sy_), f(st_), it_, ok_
            if t == 3:
                return steady_rolling(grid.x, yt, ct, lb(bt), (cx, cy, _need(case, "CPHI") / MM),
                                      G_t, nu, TANGENTIAL_TOL, 200, p0=state["p0"],
                                      w_extra=state["w_extra"])
            w = _rigid_shift(case, grid, (cx, cy))
            if exrhs is not None:
                w = (w[0] + exrhs[0], w[1] + exrhs[1])
            wx, wy = widen(np.array(w[0])), widen(np.array(w[1]))
            u_s = u_t
            if t == 2:
                # CONTACT's leading-edge correction: material that entered the
                # contact during the step (within DQ of the leading edge)
                (wx, wy), u_s = leading_edge_slip(ct, grid.dx, edge_step,
                                                  np.broadcast_to((wx, wy), (2,) + ct.shape),
                                                  u_t, u_edge)
            if state["w_extra"] is not None:
                # dissimilar bodies: the pressure's tangential displacements of this
                # step less those of the previous instance
                wx, wy = wx + state["w_extra"][0], wy + state["w_extra"][1]
            return transient_step(grid.x, yt, ct, lb(bt), (wx, wy),
                                  u_s, G, nu, TANGENTIAL_TOL, 200, p0=state["p0"])

        def tangential(cx, cy):
            if law is None:
                out = solve_once(cx, cy, bt)
            else:
                out = _falling_friction(solve_once, cx, cy, law, widen(pressure), ct,
                                        per_slip, state)
            if out[-1]:
                state["p0"] = (out[0], out[1])
            if pad:
                out = tuple(o[:shape[0], :shape[1]] if isinstance(o, np.ndarray) else o
                            for o in out)
            return out

        exrhs = extra_slip(case)
        if exrhs is not None and t == 2:
            exrhs = tuple(e * _need(case, "DQ") * MM for e in exrhs)
        if exrhs is not None and backwards:
            # the problem mirrored in x (below): x' = -x, the slip's x component too
            exrhs = (-exrhs[0][::-1], exrhs[1][::-1])
        # (steady rolling: the extra slip with the solver's w_extra; transient: with
        # the rigid shift)
        state["w_extra"] = None if exrhs is None or t != 3 else tuple(
            np.ascontiguousarray(widen(e)) for e in exrhs)
        coupled = t in (1, 3) and _dissimilar(case)
        if coupled:
            # dissimilar bodies: the pressure's tangential displacements add a rigid
            # slip, the tractions' normal displacements a gap; the two problems are
            # solved in turn until neither changes (Kalker 1990, sec. 5.2)
            mat = _body_material(case)
            xs = -grid.x[::-1].copy() if backwards else grid.x
            fm = (lambda a: np.ascontiguousarray(a[::-1])) if backwards else (lambda a: a)

            def pressure_slip(p):
                if t == 3:
                    return slip_from_pressure(xs, yt, widen(fm(p)), mat)
                # a shift (T = 1): u_t(p) - u_t(p') over the step
                ux, uy = slip_from_pressure(grid.x, yt, widen(p), mat, mode="shift")
                if pn_prev is not None:
                    vx, vy = slip_from_pressure(grid.x, yt, widen(pn_prev), mat, mode="shift")
                    ux, uy = ux - vx, uy - vy
                return np.ascontiguousarray(ux), np.ascontiguousarray(uy)
            opx, opy = None, None
            # (on the solver's grid: a 2-D problem's second, empty strip included)
            for it in range(COUPLING_ITERATIONS):
                state["w_extra"] = _plus(pressure_slip(pressure), exrhs if t == 3 else None,
                                         widen)
                creep, out = _tangential_forces(case, tangential, fn, fstat, dA, contact, G,
                                                start)
                gap = normal_gap_from_tractions(grid.x, yt, widen(out[0]), widen(out[1]),
                                                mat)[:, :grid.y.size]
                p_new, approach, ok_n = _normal(case, grid, h + gap, es)
                pm = max(float(p_new.max()), 1e-300)
                dp = float(np.max(np.abs(p_new - pressure))) / pm
                dt = 0.0 if opx is None else float(np.max(np.hypot(
                    out[0] - opx, out[1] - opy))) / (max(mu, 1e-300) * pm)
                opx, opy = out[0], out[1]
                pressure = p_new
                contact = np.ascontiguousarray(pressure > 0)
                bound = np.ascontiguousarray(mu * pressure)
                ct, bt = widen(contact), widen(bound)
                fn = float(pressure.sum() * dA)
                if dp <= COUPLING_TOL and it > 0 and dt <= COUPLING_TOL:
                    break
            else:
                message = (message + "; " if message else "") + \
                    f"normal-tangential alternation not converged in {COUPLING_ITERATIONS}"
            state["w_extra"] = _plus(pressure_slip(pressure), exrhs if t == 3 else None,
                                     widen)
        creep, out = _tangential_forces(case, tangential, fn, fstat, dA, contact, G, start)
        px, py, sx, sy, stick, _, ok_t = out
        if layer is not None:
            ustar, plast = _plastic_state(case, layer, grid, bound, (sx, sy), ustar_prev)
            nplast = int(np.count_nonzero(plast & contact))
        if not ok_t:
            what = "tangential problem not converged"
            if state.get("friction", 0.0) > FRICTION_TOL:
                what = (f"friction coefficients not settled (still changing by "
                        f"{state['friction']:.1e})")
            message = (message + "; " if message else "") + what
    tmax, temps = None, None
    if t == 3 and d["H"] in (1, 3):
        temps = surface_temperatures(case, grid.dx, (px, py, out[2], out[3]), contact)
        tmax = float(max(temps[0][contact].max(), temps[1][contact].max())) \
            if contact.any() else None
    ncon = int(np.count_nonzero(contact))
    nadh = int(np.count_nonzero(contact & stick)) if t else 0
    X, Y = grid.x[:, None], grid.y[None, :]
    fric = None
    if t == 3:
        # CONTACT's FRIC.POWER [W]: V sum p . s dA of the tractions on body 1 and its
        # relative slip (negative: the slip opposes them)
        fric = float(v.get("VELOC") or 1.0) * MM * float((px * sx + py * sy).sum() * dA)
    row = {"case": case.number, "module": 3, "patch": 1, "npatch": 1, "T": t,
           "cksi": float(creep[0]), "ceta": float(creep[1]),
           "cphi_per_mm": float(v.get("CPHI") or 0.0),
           "veloc_mm_s": float(v.get("VELOC") or 1.0) if t in (2, 3) else 1.0,
           "mu": float(mu) if t else None,
           "fn_N": fn, "fx_N": float(px.sum() * dA), "fs_N": float(py.sum() * dA),
           "mn_Nmm": float((X * py - Y * px).sum() * dA) * 1e3, "fric_power_W": fric,
           "approach_mm": approach / MM, "pmax_MPa": float(pressure.max()) * 1e-6,
           "area_mm2": ncon * dA * 1e6, "ncon": ncon, "nadh": nadh,
           "nslip": ncon - nadh - nplast if t else 0, "mx": mx_given, "my": shape[1],
           "dx_mm": grid.dx / MM, "ds_mm": grid.dy / MM, "tmax_C": tmax,
           "converged": bool(ok_n and ok_t), "message": message}
    if layer is not None:
        row["nplast"] = nplast
    return CaseResult(grid, pressure, px, py, stick, row,
                      state["mu"] if t and law is not None else None, ustar, temps)


def _plastic_state(case, layer, grid, bound, slip, ustar_prev):
    """The plastic displacement u*_pl [m] the material has accumulated after the
    case (M = 4): the previous instance's plus the step's flow (T = 1, 2), or
    summed along the strips from the leading edge (T = 3; towards +x for CHI = 180
    degrees), and the mask of the elements in plastic flow."""
    t = case.digits["T"]
    sx, sy = slip
    if t in (1, 2):
        inc, _, plast = plastic_flow(layer_bound(layer, bound, ustar_prev), sx, sy, grid.dx,
                                     False)
        return (inc if ustar_prev is None else ustar_prev + inc), plast
    f = (lambda a: a[::-1]) if math.cos(_need(case, "CHI")) < 0 else (lambda a: a)
    _, acc, plast = plastic_flow(layer_bound(layer, f(bound)), f(sx), f(sy), grid.dx, True)
    return np.ascontiguousarray(f(acc)), f(plast)


def _plus(w, extra, widen):
    """The rigid slip ``w`` (x, y) plus CONTACT's extra term ``extra`` (already in the
    solver's orientation; None: none) on the solver's grid."""
    if extra is None:
        return w
    return (w[0] + widen(extra[0]), w[1] + widen(extra[1]))


def _body_material(case):
    """CONTACT's two bodies as a railcontact Material (body 1 the rail, body 2 the
    wheel: :attr:`~railcontact.core.materials.Material.difference_parameter`)."""
    from ..core.materials import Material
    g1, g2 = _need(case, "GG1") * 1e6, _need(case, "GG2") * 1e6
    n1, n2 = _need(case, "POISS1"), _need(case, "POISS2")
    return Material(2 * g1 * (1 + n1), n1, 2 * g2 * (1 + n2), n2)


def _thermal(case, body):
    """A body's thermal constants from CONTACT's (W/mm C, kg/mm^3) in SI."""
    v = case.values
    return ThermalProperties(v[f"BKTEMP{body}"], v[f"HEATCP{body}"], v[f"LAMBDA{body}"] * 1e3,
                             v[f"DENS{body}"] * 1e9)


def surface_temperatures(case, dx, solution, contact):
    """Both bodies' surface temperatures (T_1, T_2) [deg C] on the grid of a steady
    rolling ``solution`` (p_x, p_y [Pa], s_x, s_y relative slips) with element
    length ``dx`` [m]: the frictional power density |p_t| |s| V along the
    material's path, CONTACT's scheme."""
    px, py, sx, sy = solution
    v = _need(case, "VELOC") * MM
    q = np.hypot(px, py) * np.hypot(sx, sy) * v
    # rolling towards +x (CHI = 0) the material enters at the leading edge, +x, and
    # moves towards -x: the path runs along falling x index; for CHI = 180 deg along
    # rising index (the user guide's "particles traverse the contact from left to right")
    f = (lambda a: a[::-1]) if math.cos(_need(case, "CHI")) > 0 else (lambda a: a)
    t1, t2, _ = flash_temperatures(f(q), f(contact), dx, v, _thermal(case, 1),
                                   _thermal(case, 2), scheme="contact")
    return f(t1), f(t2)


#: the friction coefficient of a slip-velocity dependent law is iterated until no
#: element's changes by more than this
FRICTION_TOL = 1e-8
FRICTION_ITERATIONS = 300


def friction_law(case):
    """The case's slip-velocity dependent friction law (FRCLAW 2-4), its temperature
    dependent one (L = 6), or None for Coulomb friction (L = 0); InpError for
    friction memory (MEMDST > 0) in transient problems and L = 5 (Polach's inputs,
    not in CONTACT's open release)."""
    law = case.values.get("FRICTION_LAW", 0)
    if law == 0:
        return None
    if law not in (2, 3, 4, 6):
        raise _unsupported(case, f"FRCLAW = {law}", "expected 0 (Coulomb), 2-4 (slip-"
                                                    "velocity dependent) or 6 (temperature "
                                                    "dependent)")
    if (case.values.get("MEMDST") or 0.0) > 0 and case.digits["T"] != 3:
        raise _unsupported(case, f"MEMDST = {case.values['MEMDST']:g} mm (friction memory) "
                                 f"with TANG = {case.digits['T']}",
                           "expected MEMDST = 0 (an instantaneous friction law) or steady "
                           "rolling (T = 3)")
    v = case.values
    if law == 6:
        try:
            return TemperatureFriction(_need(case, "FREF"), _need(case, "TREF"),
                                       _need(case, "DFHEAT"), _need(case, "DTHEAT"))
        except RailContactError as exc:
            raise InpError(f"{case.where()}: FREF, TREF, DFHEAT, DTHEAT: {exc}") from None
    name = {2: "FLIN", 3: "FRAT", 4: "FEXP"}[law]
    kind = {2: "linear", 3: "rational", 4: "exponential"}[law]
    return SlipVelocityFriction(kind, _need(case, "FKIN"), (v[f"{name}1"], v[f"{name}2"]),
                                (v["SABSH1"] * MM, v["SABSH2"] * MM))


def _falling_friction(solve_once, cx, cy, law, pressure, contact, per_slip, state):
    """The tangential solution under a slip-velocity dependent friction coefficient
    mu(s_a): the bound mu p_n taken from the last solution's slip velocities and the
    problem solved again until the coefficients stop changing (a fixed point of
    mu = mu_s(s_a), CONTACT's instantaneous law).  The update is relaxed by omega,
    halved where it turns against the last one (an oscillation) and grown by half
    (up to 1) where it does not.  Returns the solver's output, its convergence
    flag cleared where the coefficients did not settle (``state["friction"]`` then
    says by how much they still changed)."""
    mu = state["mu"]
    omega, last = 1.0, None
    out, change = None, math.inf
    for _ in range(FRICTION_ITERATIONS):
        out = solve_once(cx, cy, np.ascontiguousarray(mu * pressure))
        sa = np.hypot(out[2], out[3]) * per_slip
        # L = 6: the law of body 1's surface temperature of this solution
        arg = state["temperature"](out) if isinstance(law, TemperatureFriction) else sa
        target = np.where(contact, law(arg), law.static)
        if state.get("memory") is not None:
            target = _friction_memory(target, sa, law.static, state["memory"])
        step = target - mu
        change = float(np.max(np.abs(step)))
        if change <= FRICTION_TOL:
            break
        if last is not None:
            omega = 0.5 * omega if float(np.sum(step * last)) < 0 else min(1.0, 1.5 * omega)
        last = step
        mu = mu + omega * step
    state["mu"] = mu
    state["friction"] = change
    if change > FRICTION_TOL:
        out = (*out[:-1], False)
    return out


def _friction_memory(target, sa, static, memory):
    """Steady rolling with friction memory (MEMDST = d_c > 0): the coefficient each
    element's material carries, marched from the leading edge (entering with the
    static coefficient) with CONTACT's implicit step over the time dt of one
    element, mu_I = theta mu_I+ + (1 - theta) mu_s(s_a,I), theta = d_c / (d_c + dt
    max(s_a,I, s_0)) (user guide, "Friction memory").  ``memory`` (d_c [m], s_0
    [m/s], dt [s], rolling towards -x)."""
    dc, s0, dt, backwards = memory
    f = (lambda a: a) if backwards else (lambda a: a[::-1])
    tg, sv = f(target), f(sa)
    theta = dc / (dc + dt * np.maximum(sv, s0))
    mu = np.empty_like(tg)
    prev = np.full(tg.shape[1:], static)
    for i in range(tg.shape[0]):                 # rows from the leading edge
        prev = theta[i] * prev + (1.0 - theta[i]) * tg[i]
        mu[i] = prev
    return f(mu)


def _tangential_forces(case, tangential, fn, fstat, dA, contact, G, start=None):
    """Solve the tangential problem with the creepages (F = 0) or relative forces
    (F = 1: FX with CETA, F = 2: FX and FY) given; returns ((CKSI, CETA) met, the
    solver's output)."""
    d, v = case.digits, case.values
    f = d["F"]
    if f == 0:
        c = (_need(case, "CKSI"), _need(case, "CETA"))
        return c, tangential(*c)
    if not fn > 0:
        raise InpError(f"{case.where()}: a tangential force prescribed (F = {f}) without "
                       "contact (FN = 0)")
    scale = fstat * fn
    targets = [_need(case, "FXREL")] + ([_need(case, "FYREL")] if f == 2 else [])
    if any(abs(tg) >= 1.0 for tg in targets):
        raise InpError(f"{case.where()}: relative force {max(targets, key=abs):g}: expected "
                       "|FX/(FSTAT FN)| < 1 (full slip has no unique creepage)")
    # the creepage scale: a hundredth of the rigid shift [m] at which a Hertzian
    # contact of this area slides under FSTAT FN (Mindlin: about mu FN / (G a));
    # the bracket grows from it
    t = d["T"]
    ac = max(np.count_nonzero(contact) * dA, dA)
    shift = 0.01 * scale / (G * math.sqrt(ac))
    c = [0.0, _need(case, "CETA") if f == 1 else 0.0]
    step = shift / MM if t == 1 else shift / (_need(case, "DQ") * MM if t == 2 else
                                             math.sqrt(ac))
    if start is not None:
        # from the last case's creepage, first steps of a hundredth of it
        c[0] = start[0]
        if f == 2:
            c[1] = start[1]
        step = min(step, 0.01 * max(abs(start[0]), abs(start[1]))) or step
    cache = {}

    def force(k, val):
        cc = list(c)
        cc[k] = val
        out = tangential(*cc)
        cache["out"] = out
        comp = out[0] if k == 0 else out[1]
        return float(comp.sum() * dA) / scale - targets[k]

    out = None
    for _sweep in range(20 if f == 2 else 1):
        moved = 0.0
        for k in range(len(targets)):
            root = _root(lambda val: force(k, val), c[k], step)
            moved = max(moved, abs(root - c[k]))
            c[k] = root
        out = tangential(*c)
        if f == 1:
            break
        fy = float(out[1].sum() * dA) / scale - targets[1]
        fx = float(out[0].sum() * dA) / scale - targets[0]
        if max(abs(fx), abs(fy)) <= 10 * FORCE_TOL:
            break
    return tuple(c), out


def _root(fun, start, step):
    """The root of a decreasing function (the relative force against its creepage),
    bracketed from ``start`` by steps growing by a factor 4, then Brent's method."""
    f0 = fun(start)
    if abs(f0) <= FORCE_TOL:
        return start
    direction = -1.0 if f0 < 0 else 1.0      # decreasing: a positive residual asks more
    lo, flo = start, f0
    s = step
    for _ in range(80):
        hi = start + direction * s
        fhi = fun(hi)
        if fhi * flo <= 0:
            a, b = sorted((lo, hi))
            return brentq(fun, a, b, xtol=1e-14, rtol=1e-12, maxiter=200)
        lo, flo = hi, fhi
        s *= 4.0
    raise InpError("prescribed tangential force: no creepage found that carries it")


# ----------------------------------------------- modified FASTSIM on CONTACT's grid
def _check_fastsim(case: InpCase) -> None:
    """What modified FASTSIM on CONTACT's grid supports: steady rolling (T = 3) of a
    Hertzian case (IPOTCN = -1, -2, -3) with the creepages given (F = 0), the
    normal force (N = 1), Coulomb friction, rolling along +-x."""
    d = case.digits
    allowed = {"T": (3,), "N": (1,), "F": (0,), "S": (0, 1, 2, 3), "L": (0, 1, 2, 3, 4), "H": (0,),
               "M2": (0, 1), "E": (0, 1), "C3": (0, 1, 2)}
    names = {"T": "TANG", "N": "NORM", "F": "FORCE", "S": "STRESS", "L": "FRCLAW",
             "H": "HEAT", "M2": "MATER2", "E": "EXRHS", "C3": "INFLCF"}
    for k, vals in allowed.items():
        if d[k] not in vals:
            raise _unsupported(case, f"{names[k]} = {d[k]} with modified FASTSIM (M = "
                                     f"{d['M']}, B = {d['B']})", f"expected {names[k]} in {vals}")
    ipotcn = _need(case, "IPOTCN")
    if ipotcn not in (-1, -2, -3):
        raise _unsupported(case, f"IPOTCN = {ipotcn} with the traction bound B = {d['B']}",
                           "expected a Hertzian case, IPOTCN = -1, -2 or -3")
    chi = _need(case, "CHI")
    if abs(math.sin(chi)) > 1e-9:
        raise _unsupported(case, f"CHI = {chi:g} rad", "expected 0 or 180d (pi)")
    if case.values.get("NVF", 0):
        raise _unsupported(case, "friction variation (VARFRC)", "expected V = 0")
    if (case.values.get("SPINXO") or 0.0) or (case.values.get("SPINYO") or 0.0):
        raise _unsupported(case, "SPINXO, SPINYO (a spin centre off the origin)",
                           "expected them left out")
    for k in ("K0_MF", "ALFAMF", "BETAMF") + (("FLX",) if d["M"] == 2 else ()):
        _need(case, k)
    if d["M"] == 5 and case.values.get("FRICTION_LAW", 0) != 0:
        raise _unsupported(case, f"FRCLAW = {case.values['FRICTION_LAW']} with Modified "
                                 "FaStrip (M = 5)", "expected 0 (Coulomb)")
    if case.values.get("FRICTION_LAW", 0) not in (0, 2, 3, 4):
        raise _unsupported(case, f"FRCLAW = {case.values['FRICTION_LAW']} with modified "
                                 "FASTSIM", "expected 0 (Coulomb) or 2-4 (slip-velocity "
                                 "dependent)")


def _fastsim_friction(case) -> float:
    """The friction coefficient of modified FASTSIM: FKIN (Coulomb), or a slip-velocity
    dependent law's steady value at the slip velocity VELOC |(CKSI, CETA)| of the
    whole patch (CONTACT's "f_eff"; a friction memory MEMDST plays no part in steady
    rolling)."""
    v = case.values
    law = v.get("FRICTION_LAW", 0)
    if law == 0:
        return _need(case, "FKIN")
    name = {2: "FLIN", 3: "FRAT", 4: "FEXP"}[law]
    kind = {2: "linear", 3: "rational", 4: "exponential"}[law]
    f = SlipVelocityFriction(kind, _need(case, "FKIN"), (v[f"{name}1"], v[f"{name}2"]),
                             (v["SABSH1"] * MM, v["SABSH2"] * MM))
    w = _need(case, "VELOC") * MM * math.hypot(_need(case, "CKSI"), _need(case, "CETA"))
    return float(f(np.array([w]))[0])


def _fastrip_rows(case, grid, pressure, contact, creep, out) -> None:
    """CONTACT's Modified FaStrip (M = 5) after the FASTSIM march, in the march's
    frame (rolling towards +x): the strip theory's adhesion zone per row
    (:func:`railcontact.tangential.fastrip.contact_fastrip_rows`) on the
    equivalent ellipse of the contact's elements (Piotrowski & Kik 2008: the area
    and the ratio of the extents kept, a = sqrt(A/pi) sqrt(L/W); CONTACT's
    equivalent ellipse), with F_n, FSTAT and Poisson's ratio of the case.
    ``grid`` = (x, y, dx, dy) [m], ``out`` = (px, py, stick), changed in place."""
    from ..tangential.fastrip import (StripTheoryRows, contact_fastrip_rows,
                                      contact_strip_creepages)
    x, y, dx, dy = grid
    es, G, nu = _materials(case)
    ix = np.flatnonzero(contact.any(axis=1))
    iy = np.flatnonzero(contact.any(axis=0))
    if ix.size == 0:
        return
    area = np.count_nonzero(contact) * dx * dy
    length, width = (ix[-1] - ix[0] + 1) * dx, (iy[-1] - iy[0] + 1) * dy
    a = math.sqrt(area / math.pi) * math.sqrt(length / width)
    b = math.sqrt(area / math.pi) * math.sqrt(width / length)
    mu = _need(case, "FSTAT")
    cr, pmax = contact_strip_creepages(a, b, G, nu, mu, _need(case, "FN"), creep)
    rows = StripTheoryRows(np.ascontiguousarray(x), np.ascontiguousarray(y), float(dx),
                           pressure, contact, float(mu), float(pmax), float(a), cr,
                           float(nu))
    contact_fastrip_rows(rows, *out)


def solve_fastsim(case: InpCase) -> CaseResult:
    """CONTACT's modified FASTSIM (M = 2: one given flexibility FLX; M = 3: three,
    :func:`railcontact.tangential.fastsim.contact_flexibilities`) in steady rolling
    on CONTACT's grid of a Hertzian case (SCALE times the ellipse in MX x MY
    elements), with the traction bound mu p of the Hertzian pressure (B = 2,
    elliptical: 3 F_n/(2 pi a b) sqrt(1 - x^2/a^2 - y^2/b^2)) or Kalker's parabolic
    one (B = 3: 2 F_n/(pi a b) (1 - x^2/a^2 - y^2/b^2)) at the element centres, the
    contact the elements whose centres lie inside the ellipse; each row marched
    from its leading element, one element per step, the spin's lever taken dq/6
    ahead (:func:`railcontact.tangential.fastsim.fastsim_grid`; CONTACT's user
    guide, "Flexibilities of the simplified theory").  M = 5 (Modified FaStrip):
    then the strip theory per row (:func:`_fastrip_rows`)."""
    from ..core.hertz_theory import hertz_ellipse as _ellipse
    from ..tangential.fastsim import contact_flexibilities, fastsim_grid, \
        modification_factor
    from ..tangential.kalker import kalker_coefficients
    d, v = case.digits, case.values
    es, G, nu = _materials(case)
    fn = _need(case, "FN")
    ipotcn = v["IPOTCN"]
    if ipotcn == -3:
        a, b = v["AA"] * MM, v["BB"] * MM
    else:
        A = v["A1"] / MM
        B = v["B1"] / MM if ipotcn == -1 else curvature_from_axis_ratio(A, v["AOB"])
        h = _ellipse(A, B, es, force=fn)
        a, b = h.a, h.b
    mx, my, s = int(v["MX"]), int(v["MY"]), v["SCALE"]
    if mx < 2:
        raise InpError(f"{case.where()}: MX = {mx} with FASTSIM; expected MX >= 2")
    dx, dy = 2 * s * a / mx, 2 * s * b / my
    x = -s * a + (np.arange(mx) + 0.5) * dx
    y = -s * b + (np.arange(my) + 0.5) * dy
    r = 1.0 - (x[:, None] / a) ** 2 - (y[None, :] / b) ** 2
    contact = r > 0
    if d["B"] == 2:
        pressure = np.where(contact, 1.5 * fn / (math.pi * a * b) * np.sqrt(np.maximum(r, 0)),
                            0.0)
    else:
        pressure = np.where(contact, 2.0 * fn / (math.pi * a * b) * r, 0.0)
    mu = _fastsim_friction(case)
    cphi = _need(case, "CPHI") / MM
    creep = (_need(case, "CKSI"), _need(case, "CETA"), cphi)
    mod = (v["K0_MF"], v["ALFAMF"], v["BETAMF"])
    if d["M"] == 2:
        C11 = kalker_coefficients(a / b, nu)[0]
        k = modification_factor(mod, a, b, G, C11, creep, mu, fn)
        flex = np.full(3, v["FLX"] * MM ** 3 / k)        # mm^3/N -> m^3/N
    else:
        flex = np.array(contact_flexibilities(a, b, G, nu, creep, mu, fn, mod))
    backwards = math.cos(_need(case, "CHI")) < 0
    dq = dx
    # rolling towards -x (CHI = 180 deg): the problem mirrored in x (x' = -x: CKSI,
    # CPHI and p_x change sign), marched towards +x', mirrored back
    f = (lambda q: np.ascontiguousarray(q[::-1])) if backwards else np.ascontiguousarray
    xs = -x[::-1].copy() if backwards else x
    cr = np.array([-creep[0], creep[1], -creep[2]] if backwards else creep, float)
    bound = f(mu * pressure)
    px, py, sx, sy = (np.zeros((mx, my)) for _ in range(4))
    stick = np.zeros((mx, my), dtype=np.bool_)
    fastsim_grid(xs, y, bound, flex, cr, dq / 6.0, px, py, sx, sy, stick)
    if d["M"] == 5:
        _fastrip_rows(case, (xs, y, dx, dy), f(pressure), f(contact), cr, (px, py, stick))
    if backwards:
        px, py, sx, sy, stick = -f(px), f(py), -f(sx), f(sy), f(stick)
    dA = dx * dy
    ncon = int(np.count_nonzero(contact))
    nadh = int(np.count_nonzero(contact & stick))
    X, Y = x[:, None], y[None, :]
    row = {"case": case.number, "module": 3, "patch": 1, "npatch": 1, "T": 3,
           "cksi": float(creep[0]), "ceta": float(creep[1]),
           "cphi_per_mm": float(v.get("CPHI") or 0.0),
           "veloc_mm_s": float(v.get("VELOC") or 1.0), "mu": float(mu),
           "fn_N": float(fn), "fx_N": float(px.sum() * dA),
           "fs_N": float(py.sum() * dA), "mn_Nmm": float((X * py - Y * px).sum() * dA) * 1e3,
           "approach_mm": None, "pmax_MPa": float(pressure.max()) * 1e-6,
           "area_mm2": ncon * dA * 1e6, "ncon": ncon, "nadh": nadh, "nslip": ncon - nadh,
           "mx": mx, "my": my, "dx_mm": dx / MM, "ds_mm": dy / MM, "tmax_C": None,
           "converged": True, "message": "", "flexibilities": tuple(float(q) for q in flex)}
    return CaseResult(Grid(x, y, dx, dy), pressure, px, py, stick, row)
