"""Common result type and registry of the normal-contact models."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, ClassVar, Protocol, runtime_checkable

import numpy as np
from numba import njit

from ..core.errors import InputError
from ..core.checks import shown
from ..core.registry import Registry
from ..core.status import SolverStatus


def _check_solve(geometry=None, material=None, *args, **kwargs):
    """The inputs every normal model's ``solve`` takes, checked first."""
    if not hasattr(geometry, "curvatures"):
        raise InputError(f"geometry = {shown(geometry)}: expected a ContactGeometry "
                         "(railcontact.geometry)")
    if material is not None and not hasattr(material, "contact_modulus"):
        raise InputError(f"material = {shown(material)}: expected a railcontact.Material")


_REGISTRY = Registry("normal", _check_solve)
register = _REGISTRY.register


def get_normal_model(name: str, **options):
    """Instantiate the normal model registered as ``name``."""
    return _REGISTRY.create(name, **options)


def normal_models(capability: str | None = None) -> list:
    """Names of the registered normal models (those that declare ``capability``)."""
    return _REGISTRY.names(capability)


def normal_model_class(name: str) -> type:
    """The class of the normal model registered as ``name``."""
    return _REGISTRY.model_class(name)


def normal_supports(name: str, capability: str) -> bool:
    """Whether the normal model ``name`` declares ``capability``."""
    return _REGISTRY.supports(name, capability)


#: what a normal model may declare in ``capabilities``
NORMAL_CAPABILITIES = {
    "force-control": "solve(normal_force=F) meets a given normal force",
    "contact-stiffness": "contact_stiffness(solution, material, geometry) gives dF_n/d(delta) "
                         "[N/m] of a converged solution (NaN where the model's options make it "
                         "undefined: a pressure limit, viscoelastic bodies)",
    "warm-start": "solve(..., warm_start=previous solution) starts from it",
    "grid-reuse": "solve(..., reuse_grid=previous solution) keeps its grid and kernels",
    "ellipse": "the patch is Hertz's ellipse of the geometry's curvatures (semi_axes)",
    "batch": "solves many patches at once, forces only (railcontact.cases.batch)",
    "strips": "a strip model: semi-elliptic pressure per strip (strip_theory)",
    "coupled": "takes part in the coupled normal-tangential iteration (dissimilar materials)",
}


@runtime_checkable
class NormalModel(Protocol):
    """What a normal model provides (the layer's contract; register with
    ``@register(name)``).

    ``solve`` takes a :class:`~railcontact.geometry.ContactGeometry` and exactly one
    of ``normal_force`` [N] and ``penetration`` [m] and returns a
    :class:`NormalSolution` whose ``status`` says whether it converged.  Its
    capabilities are declared, never probed: ``capabilities`` is a frozenset of
    keys of :data:`NORMAL_CAPABILITIES`.
    """

    name: ClassVar[str]
    capabilities: ClassVar[frozenset]

    def solve(self, geometry, material=..., normal_force=None, penetration=None,
              grid=None, element_size=None) -> "NormalSolution": ...


@dataclass
class NormalSolution:
    """Solution of the normal contact problem of one patch (SI units).

    Attributes
    ----------
    model : str
    x, y : ndarray
        Cell centres [m] of the potential contact grid, rolling and lateral.
    pressure : ndarray (mx, my)
        Normal pressure p(x, y) [Pa] at the cell centres.
    contact : ndarray of bool (mx, my)
        Contact mask.
    area : float         contact area [m^2]
    pmax : float         maximum pressure [Pa]
    penetration : float  approach of the bodies [m]
    normal_force : float F_n [N]
    semi_axes : (a, b) or None
        Semi-axes [m] of the (equivalent) ellipse, used for the flexibilities of
        simplified theory.
    strips : (x_lead, x_trail) arrays over y, leading and trailing edge [m] of the
        contact on each strip (rolling in +x: material enters at x_lead).
    pressure_at : callable (x, y) -> p [Pa] evaluating the pressure anywhere.
    gap : ndarray (mx, my) or None
        Undeformed distance h(x, y) [m] on the grid, where the model computed it
        (strip models); lets strip-wise tangential models reuse it.
    status : SolverStatus
        Whether the solver met its tolerance, and warnings (a contact that reaches
        the edge of the grid); ``converged`` reads it.
    pressure_limit : float
        Upper bound [Pa] of the pressure of an elastic-perfectly-plastic solution
        (inf: elastic); ``plastic`` is the mask of the elements at it and
        ``plastic_area`` their area [m^2].
    """

    model: str
    x: np.ndarray
    y: np.ndarray
    pressure: np.ndarray
    contact: np.ndarray
    area: float
    pmax: float
    penetration: float
    normal_force: float
    semi_axes: tuple | None = None
    strips: tuple | None = None
    pressure_at: Callable | None = field(default=None, repr=False)
    status: SolverStatus = field(default_factory=SolverStatus)
    cpu_time: float = 0.0
    gap: np.ndarray | None = field(default=None, repr=False)
    pressure_limit: float = math.inf

    @property
    def converged(self) -> bool:
        return self.status.converged

    @property
    def plastic(self) -> np.ndarray:
        """Mask of the elements at the pressure limit (none for an elastic solution)."""
        if not math.isfinite(self.pressure_limit):
            return np.zeros(self.pressure.shape, dtype=bool)
        return self.pressure >= self.pressure_limit * (1.0 - 1e-9)

    @property
    def plastic_area(self) -> float:
        """Area [m^2] of the elements at the pressure limit."""
        n = int(self.plastic.sum())
        return n * self.dx * self.dy if n else 0.0

    @property
    def dx(self) -> float:
        return float(self.x[1] - self.x[0]) if self.x.size > 1 else math.nan

    @property
    def dy(self) -> float:
        return float(self.y[1] - self.y[0]) if self.y.size > 1 else math.nan

    def to_xarray(self):
        """Pressure and contact mask as an :class:`xarray.Dataset` with units."""
        import xarray as xr
        ds = xr.Dataset(
            {"pressure": (("x", "y"), self.pressure, {"units": "Pa", "long_name": "normal pressure"}),
             "contact": (("x", "y"), self.contact.astype(np.int8),
                         {"long_name": "contact mask (1 = in contact)"})},
            coords={"x": ("x", self.x, {"units": "m", "long_name": "rolling direction"}),
                    "y": ("y", self.y, {"units": "m", "long_name": "lateral, in the tangent plane"})},
            attrs={"normal_model": self.model, "area_m2": self.area, "pmax_Pa": self.pmax,
                   "penetration_m": self.penetration, "normal_force_N": self.normal_force})
        return ds


#: largest number of elements per direction; finer requests are coarsened (logged)
MAX_ELEMENTS = 400


def make_grid(extent_x: float, extent_y: float, grid=None, element_size=None,
              center=(0.0, 0.0), origin=(0.0, 0.0)):
    """Cell centres of a potential contact grid covering [-ex, ex] x [-ey, ey] + center.

    Parameters
    ----------
    grid : (mx, my), optional   number of elements (default 40 x 40)
    element_size : (dx, dy), optional
        Element size [m]; alternative to ``grid``.  The element centres then lie on a
        lattice through ``origin`` (default the contact reference point), as in
        CONTACT, so that results do not depend on where the potential area happens
        to start.
    origin : (x0, y0)
        A point of that lattice [m] (a transient CONTACT grid's, fixed in the rail).
    """
    import logging
    if grid is not None and element_size is not None:
        raise InputError("solver: give either grid or element_size, not both")
    if element_size is not None:
        dx, dy = (float(v) for v in element_size)
        if not (dx > 0 and dy > 0):
            raise InputError(f"solver.element_size = {element_size!r}: expected two lengths > 0 m")
        coarsen = max((2 * extent_x / dx) / MAX_ELEMENTS, (2 * extent_y / dy) / MAX_ELEMENTS, 1.0)
        if coarsen > 1.0:                    # the result says so: resized_elements
            logging.getLogger(__name__).info(
                "potential contact area %.1f x %.1f mm needs more than %d elements per "
                "direction; element size enlarged by %.2f", 2e3 * extent_x, 2e3 * extent_y,
                MAX_ELEMENTS, coarsen)
            dx, dy = dx * coarsen, dy * coarsen
        ox, oy = (float(v) for v in origin)
        i0 = int(math.floor((center[0] - extent_x - ox) / dx))
        i1 = int(math.ceil((center[0] + extent_x - ox) / dx))
        j0 = int(math.floor((center[1] - extent_y - oy) / dy))
        j1 = int(math.ceil((center[1] + extent_y - oy) / dy))
        x = ox + np.arange(i0, max(i1, i0 + 1) + 1) * dx
        y = oy + np.arange(j0, max(j1, j0 + 1) + 1) * dy
        return x, y
    mx, my = (40, 40) if grid is None else (int(v) for v in grid)
    if not (2 <= mx <= 2000 and 2 <= my <= 2000):
        raise InputError(f"solver.grid = {grid!r}: expected two element counts in [2, 2000]")
    x = center[0] - extent_x + (np.arange(mx) + 0.5) * (2 * extent_x / mx)
    y = center[1] - extent_y + (np.arange(my) + 0.5) * (2 * extent_y / my)
    return x, y


def resized_elements(element_size, dx: float, dy: float) -> str:
    """The warning for a solution whose elements (``dx``, ``dy`` [m]) differ from the
    requested ``element_size`` (enlarged by :func:`make_grid` to at most
    :data:`MAX_ELEMENTS` per direction); "" where they are the requested ones."""
    if element_size is None:
        return ""
    ex, ey = (float(v) for v in element_size)
    if math.isclose(dx, ex, rel_tol=1e-6) and math.isclose(dy, ey, rel_tol=1e-6):
        return ""
    return (f"element size changed from the requested {ex * 1e3:.4g} x {ey * 1e3:.4g} mm to "
            f"{dx * 1e3:.4g} x {dy * 1e3:.4g} mm (at most {MAX_ELEMENTS} elements per "
            "direction over the potential contact area)")


def same_grid(x1, y1, x2, y2) -> bool:
    """Whether two grids of element centres (equally spaced, as :func:`make_grid`
    makes them) are one: as many elements, first and last centres within 1e-6 of an
    element."""
    if x1 is x2 and y1 is y2:
        return True
    for a, b in ((x1, x2), (y1, y2)):
        if a.size != b.size or a.size < 2:
            return False
        tol = 1e-6 * abs(float(a[1]) - float(a[0]))
        if abs(float(a[0]) - float(b[0])) > tol or abs(float(a[-1]) - float(b[-1])) > tol:
            return False
    return True


def bilinear(x, y, f, xq, yq) -> np.ndarray:
    """Values ``f`` on the element centres (x, y) of a grid (at least 2 x 2) at the
    points (xq, yq) (arrays of one shape): bilinear between the centres, zero
    outside them (as ``scipy.ndimage.map_coordinates`` with ``order=1,
    mode="constant"``, compiled: a warm start interpolates a neighbour's solution
    onto its grid several times per case).  ``map_coordinates`` itself was measured
    (issue 29) 1.9x to 4.8x slower per call on 30 x 30 to 120 x 120 grids and 10 %
    slower on FASTSIM over an exact pressure (``pressure_at``), so it stays the
    reference of the tests.  Points on grid lines, ``xq`` of shape (n, 1) and ``yq``
    of shape (1, m) (another grid's centres, as a warm start asks), are
    interpolated line by line (:func:`_bilinear_lines`: the same arithmetic, no
    broadcast arrays; issue 30)."""
    xq, yq = np.asarray(xq, float), np.asarray(yq, float)
    if xq.ndim == 2 and yq.ndim == 2 and xq.shape[1] == 1 and yq.shape[0] == 1:
        out = np.empty((xq.shape[0], yq.shape[1]))
        _bilinear_lines(np.ascontiguousarray(f, dtype=float),
                        np.ascontiguousarray((xq[:, 0] - x[0]) / (x[1] - x[0])),
                        np.ascontiguousarray((yq[0] - y[0]) / (y[1] - y[0])), out)
        return out
    xq, yq = np.broadcast_arrays(xq, yq)
    u = ((xq - x[0]) / (x[1] - x[0])).ravel()
    v = ((yq - y[0]) / (y[1] - y[0])).ravel()
    out = np.empty(u.size)
    _bilinear_kernel(np.ascontiguousarray(f, dtype=float), u, v, out)
    return out.reshape(xq.shape)


@njit(cache=True, nogil=True)
def _bilinear_lines(f, u, v, out):
    """out[i, j] = f bilinear at the fractional indices (u[i], v[j]) (the lines of
    another grid); 0 outside the grid of centres.  The arithmetic of
    :func:`bilinear_at`, its cell and fraction found once per line."""
    mx, my = f.shape
    ic, ac, inside_u = _cells(u, mx)
    jc, bc, inside_v = _cells(v, my)
    for i in range(u.size):
        if not inside_u[i]:
            for j in range(v.size):
                out[i, j] = 0.0
            continue
        i0, a = ic[i], ac[i]
        for j in range(v.size):
            if not inside_v[j]:
                out[i, j] = 0.0
                continue
            j0, b = jc[j], bc[j]
            out[i, j] = ((1.0 - a) * ((1.0 - b) * f[i0, j0] + b * f[i0, j0 + 1])
                         + a * ((1.0 - b) * f[i0 + 1, j0] + b * f[i0 + 1, j0 + 1]))


@njit(cache=True, nogil=True)
def _cells(u, m):
    """The cell (its lower centre, at most m - 2), the fraction within it and
    whether it lies on the m centres, of each fractional index u (as
    :func:`bilinear_at` finds them)."""
    cell = np.zeros(u.size, dtype=np.int64)
    frac = np.zeros(u.size)
    inside = np.zeros(u.size, dtype=np.bool_)
    for k in range(u.size):
        a = u[k]
        if 0.0 <= a <= m - 1:
            i = min(int(a), m - 2)
            cell[k] = i
            frac[k] = a - i
            inside[k] = True
    return cell, frac, inside


@njit(cache=True, nogil=True)
def bilinear_at(f, a, b):
    """f bilinear at the fractional index (a, b); 0 outside the grid of centres."""
    mx, my = f.shape
    if not (0.0 <= a <= mx - 1 and 0.0 <= b <= my - 1):
        return 0.0
    i = min(int(a), mx - 2)
    j = min(int(b), my - 2)
    a -= i
    b -= j
    return ((1.0 - a) * ((1.0 - b) * f[i, j] + b * f[i, j + 1])
            + a * ((1.0 - b) * f[i + 1, j] + b * f[i + 1, j + 1]))


@njit(cache=True, nogil=True)
def _bilinear_kernel(f, u, v, out):
    """out[k] = f bilinear at the fractional indices (u[k], v[k]); 0 outside the
    grid of centres."""
    for k in range(u.size):
        out[k] = bilinear_at(f, u[k], v[k])
