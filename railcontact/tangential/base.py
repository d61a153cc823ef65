"""Common result type and registry of the tangential-contact models."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar, Protocol, runtime_checkable

import numpy as np

from ..core.errors import InputError
from ..core.checks import shown
from ..core.registry import Registry
from ..core.status import SolverStatus


def _check_solve(normal=None, geometry=None, material=None, *args, **kwargs):
    """The inputs every tangential model's ``solve`` takes, checked first."""
    if not hasattr(normal, "pressure"):
        raise InputError(f"normal = {shown(normal)}: expected the NormalSolution of the patch")
    if geometry is not None and not hasattr(geometry, "curvatures"):
        raise InputError(f"geometry = {shown(geometry)}: expected a ContactGeometry "
                         "(railcontact.geometry)")
    if material is not None and not hasattr(material, "contact_modulus"):
        raise InputError(f"material = {shown(material)}: expected a railcontact.Material")


_REGISTRY = Registry("tangential", _check_solve)
register = _REGISTRY.register


def get_tangential_model(name: str, **options):
    """Instantiate the tangential model registered as ``name``."""
    return _REGISTRY.create(name, **options)


def tangential_models(capability: str | None = None) -> list:
    """Names of the registered tangential models (those that declare ``capability``)."""
    return _REGISTRY.names(capability)


def tangential_model_class(name: str) -> type:
    """The class of the tangential model registered as ``name``."""
    return _REGISTRY.model_class(name)


def tangential_supports(name: str, capability: str) -> bool:
    """Whether the tangential model ``name`` declares ``capability``."""
    return _REGISTRY.supports(name, capability)


#: what a tangential model may declare in ``capabilities``
TANGENTIAL_CAPABILITIES = {
    "warm-start": "solve(..., warm_start=previous solution) starts from it",
    "online": "a compiled law for one elliptic patch (class attribute online_law, "
              "railcontact.tangential.online): vehicle dynamics and batches",
    "strip-march": "marches the strips of many patches at once (class method "
                   "strip_forces): batches of the strip models",
    "coupled": "takes part in the coupled normal-tangential iteration (dissimilar materials; "
               "attribute mode: 'rolling', 'shift' or 'transient', how the pressure's "
               "displacements enter the slip)",
    "lazy": "costly: the vertical balance lets FASTSIM stand in for it until its last "
            "passes (railcontact.cases.equilibrium)",
    "friction-field": "solve(..., friction_scale=array) varies the friction coefficient "
                      "across the patch, element by element (friction along the track)",
    "extra-slip": "solve(..., extra_slip=(w_x, w_y)) takes a rigid slip per element beside "
                  "the creepages (conformal patches, railcontact.cases.conformal)",
}


@runtime_checkable
class TangentialModel(Protocol):
    """What a tangential model provides (the layer's contract; register with
    ``@register(name)``).

    ``solve(normal, geometry, material, creepage, friction, velocity)`` returns a
    :class:`TangentialSolution` whose ``status`` says whether it converged.
    ``capabilities`` is a frozenset of keys of :data:`TANGENTIAL_CAPABILITIES`; a
    model with ``"online"`` names its compiled law in ``online_law``, one with
    ``"strip-march"`` implements ``strip_forces``, one with ``"coupled"`` says in
    ``mode`` whether it rolls or shifts.
    """

    name: ClassVar[str]
    capabilities: ClassVar[frozenset]

    def solve(self, normal, geometry=None, material=..., creepage=(0.0, 0.0, 0.0),
              friction: float = 0.3, velocity: float = 1.0) -> "TangentialSolution": ...


def check_inputs(creepage, friction):
    """Validate creepages (xi, eta, phi) and the friction coefficient; return floats."""
    import math

    try:
        xi, eta, phi = (float(c) for c in creepage)
    except (TypeError, ValueError):
        raise InputError(f"creepage = {shown(creepage)}: expected three numbers (xi, eta, phi)") \
            from None
    if not all(math.isfinite(c) for c in (xi, eta, phi)):
        raise InputError(f"creepage = {shown(creepage)}: expected finite values")
    if not (math.isfinite(friction) and 0.0 <= friction <= 5.0):
        raise InputError(f"friction.coefficient = {shown(friction)}: expected a value in [0, 5]")
    return xi, eta, phi


@dataclass
class TangentialSolution:
    """Solution of the tangential (creep) problem of one patch (SI units).

    Tractions are those the rail exerts on the wheel; slip is the slip of the rail
    relative to the wheel, divided by the rolling velocity (the creepage convention),
    so that in slip areas the traction points along the slip.

    Attributes
    ----------
    model : str
    x, y : ndarray            cell centres [m] (same grid as the normal solution)
    traction_x, traction_y : ndarray (mx, my)   tangential tractions [Pa]
    slip_x, slip_y : ndarray (mx, my)           relative slip [-]
    stick : ndarray of bool (mx, my)            adhesion (stick) area
    contact : ndarray of bool (mx, my)          contact area
    fx, fy : float            creep forces [N] on the wheel, contact-local frame
    mz : float                spin moment [N m] about the normal through the origin
    power_density : ndarray   frictional power per unit area [W/m^2]
    frictional_power : float  frictional power of the patch [W] (see the property)
    velocity : float          rolling velocity [m/s]
    status : SolverStatus     whether the solver met its tolerance (``converged``)
    options : dict            model-specific details (iterations, flexibilities, ...)
    power : float or None     frictional power [W] summed by the model on its own
                              elements (the strip marches' mid-points), where it has
                              them; None: from the grid fields
    """

    model: str
    x: np.ndarray
    y: np.ndarray
    traction_x: np.ndarray
    traction_y: np.ndarray
    slip_x: np.ndarray
    slip_y: np.ndarray
    stick: np.ndarray
    contact: np.ndarray
    fx: float
    fy: float
    mz: float
    velocity: float
    creepage: tuple = (0.0, 0.0, 0.0)
    friction: float = 0.3
    cpu_time: float = 0.0
    options: dict = field(default_factory=dict)
    status: SolverStatus = field(default_factory=SolverStatus)
    power: float | None = None

    @property
    def converged(self) -> bool:
        return self.status.converged

    @property
    def power_density(self) -> np.ndarray:
        """Frictional power density |traction . slip| V [W/m^2]."""
        return np.abs(self.traction_x * self.slip_x + self.traction_y * self.slip_y) * self.velocity

    @property
    def frictional_power(self) -> float:
        """Frictional power [W] dissipated in the patch: the integral of traction
        times local slip velocity, P = V * sum |t . s| dA (>= 0).

        * Models with local fields (exact, FASTSIM, FaStrip): from their own
          discretisation -- the exact model's grid (the same sum as CONTACT's
          ``FRIC.POWER``, Vollebregt's CONTACT user guide, section "Overall output
          quantities": FRIC = V dx dy sum p_I . s_I, in W, of the tractions on
          body 1 and its slip, hence CONTACT's negative sign), the strip marches'
          mid-points (``power``).
        * Models without local fields (``options["local_fields"]`` False: linear,
          Polach): the macroscopic power V (xi F_x + eta F_y + phi M_z), which the
          local sum equals in the continuum limit of steady rolling of
          quasi-identical bodies with constant creepages (the same section).
        """
        if self.power is not None:
            return float(self.power)
        if self.options.get("local_fields", True) is False:
            xi, eta, phi = self.creepage
            return float(abs(self.velocity * (xi * self.fx + eta * self.fy + phi * self.mz)))
        dA = (self.x[1] - self.x[0]) * (self.y[1] - self.y[0])
        return float(self.power_density.sum() * dA)

    @property
    def stick_fraction(self) -> float:
        n = int(self.contact.sum())
        return float((self.stick & self.contact).sum() / n) if n else 0.0

    def to_xarray(self):
        """Tractions, slip, stick map and power density as an :class:`xarray.Dataset`."""
        import xarray as xr
        dims = ("x", "y")
        ds = xr.Dataset(
            {"traction_x": (dims, self.traction_x, {"units": "Pa"}),
             "traction_y": (dims, self.traction_y, {"units": "Pa"}),
             "slip_x": (dims, self.slip_x, {"units": "1", "long_name": "relative slip, x"}),
             "slip_y": (dims, self.slip_y, {"units": "1", "long_name": "relative slip, y"}),
             "stick": (dims, self.stick.astype(np.int8), {"long_name": "1 = adhesion"}),
             "power_density": (dims, self.power_density, {"units": "W m-2"})},
            coords={"x": ("x", self.x, {"units": "m"}), "y": ("y", self.y, {"units": "m"})},
            attrs={"tangential_model": self.model, "Fx_N": self.fx, "Fy_N": self.fy,
                   "Mz_Nm": self.mz, "velocity_m_s": self.velocity, "friction": self.friction})
        return ds
