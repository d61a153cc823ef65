"""The results of a contact case: :class:`PatchResult` per patch and
:class:`SolveResult` per case (SI units; the JSON contract of ``docs/architecture.md``)."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np

from .equilibrium import VerticalBalance
from ..geometry.contact import ContactGeometry
from ..geometry.search import WheelsetContact
from ..geometry.track import WheelsetPose
from ..normal import NormalSolution
from ..core.status import SolverStatus
from ..tangential import TangentialSolution
from ..tangential.temperature import patch_temperatures

__all__ = ["PatchResult", "SolveResult", "VerticalBalance", "vertical_force_on_rail",
           "geometry_dict"]


def _f(v):
    v = float(v)
    return None if math.isnan(v) else v



@dataclass
class PatchResult:
    """Geometry, normal and tangential solution of one contact patch.

    ``validity`` says where the patch leaves the range of its models (flange climb,
    derailment, a patch large against the radii of curvature:
    :mod:`railcontact.geometry.validity`); ``halfspace_ratio`` is the patch's size
    against those radii (NaN where not evaluated)."""

    geometry: ContactGeometry
    normal: NormalSolution
    tangential: TangentialSolution | None
    creepage: tuple
    validity: SolverStatus = field(default_factory=SolverStatus)
    halfspace_ratio: float = math.nan
    #: the elastic-plastic solution of ``[plasticity] model = "elastic-plastic"``
    #: (:class:`~railcontact.subsurface.elastoplastic.ElasticPlasticResult`), else None
    elastic_plastic: object | None = None
    #: (rail, wheel) :class:`~railcontact.tangential.temperature.ThermalProperties`
    #: and the scheme of the case's ``[thermal]`` (set by
    #: :func:`railcontact.cases.solve.solve`); None: no temperatures
    thermal: tuple | None = field(default=None, repr=False)

    @property
    def temperatures(self):
        """Flash temperatures (T_rail, T_wheel) [deg C] of the surfaces on the
        tangential solution's grid (Jaeger's moving heat source,
        :func:`~railcontact.tangential.temperature.patch_temperatures`), or None
        (no tangential solution, no thermal constants).  Computed once."""
        if self.thermal is None or self.tangential is None:
            return None
        cache = self.__dict__.setdefault("_temperatures", {})
        if "t" not in cache:
            cache["t"] = patch_temperatures(self.tangential, *self.thermal)
        return cache["t"]

    @property
    def max_temperature(self) -> float | None:
        """The largest surface temperature of both bodies in the contact [deg C]
        (CONTACT's MAX(T1,T2)); None without temperatures."""
        t = self.temperatures
        if t is None:
            return None
        c = np.asarray(self.tangential.contact, bool)
        return float(max(t[0][c].max(), t[1][c].max()))

    @property
    def status(self) -> SolverStatus:
        """The patch's solutions and validity combined."""
        label = f"{self.geometry.side} patch" if self.geometry.side else "patch"
        return SolverStatus.combine([
            (f"{label}, {self.normal.model} normal", self.normal.status),
            (f"{label}, {self.tangential.model} tangential" if self.tangential else "",
             self.tangential.status if self.tangential is not None else None),
            ("", self.validity),
            (f"{label}, elastic-plastic" if self.elastic_plastic is not None else "",
             self.elastic_plastic.status if self.elastic_plastic is not None else None)])

    def to_dict(self) -> dict:
        """The JSON patch contract of ``docs/architecture.md`` (SI units) plus extra keys."""
        g, n, t = self.geometry, self.normal, self.tangential
        d = {"side": g.side, "area": n.area, "pmax": n.pmax, "penetration": n.penetration,
             "Fn": n.normal_force, "Fx": t.fx if t else 0.0, "Fy": t.fy if t else 0.0,
             "Mz": t.mz if t else 0.0, "contact_angle": float(g.contact_angle),
             "rolling_radius": _f(g.rolling_radius), "y_rail": _f(g.y_rail),
             "y_wheel": _f(g.y_wheel),
             "creepage": {"longitudinal": self.creepage[0], "lateral": self.creepage[1],
                          "spin": self.creepage[2]}}
        if n.semi_axes is not None:
            d["semi_axes"] = [float(n.semi_axes[0]), float(n.semi_axes[1])]
        d["curvatures"] = [float(c) for c in g.curvatures]
        if t is not None:
            d["stick_fraction"] = t.stick_fraction
            d["frictional_power"] = t.frictional_power
        if self.max_temperature is not None:
            d["max_temperature_degC"] = self.max_temperature
        d["halfspace_ratio"] = _f(self.halfspace_ratio)
        if math.isfinite(getattr(n, "pressure_limit", math.inf)):
            d["pressure_limit"] = n.pressure_limit
            d["plastic_area"] = n.plastic_area
        ep = self.elastic_plastic
        if ep is not None:
            d["elastic_plastic"] = {
                "area": ep.normal.area, "pmax": ep.normal.pmax,
                "penetration": ep.normal.penetration,
                "max_equivalent_plastic_strain": float(ep.equivalent_plastic_strain.max()),
                "plastic_zone_depth": ep.plastic_zone_depth,
                "max_residual_displacement": float(ep.residual_displacement.max())}
        return d



@dataclass
class SolveResult:
    """All patches of one case, with the models used and the CPU time; for a
    wheel-rail case also the contact search's result (``contact``: wheelset pose,
    patch geometries, loci) and how the vertical-force iteration ended
    (``balance``)."""

    patches: list
    normal: str
    tangential: str
    cpu_time: float
    title: str = ""
    pose: WheelsetPose | None = None
    contact: WheelsetContact | None = field(default=None, repr=False)
    balance: VerticalBalance | None = field(default=None, repr=False)

    @property
    def status(self) -> SolverStatus:
        """The case's status: the vertical balance's and every patch's solutions and
        validity combined (:meth:`SolverStatus.combine`), so that no unconverged part
        hides behind a converged whole."""
        parts = [("vertical balance", self.balance.status if self.balance else None)]
        parts += [("", p.status) for p in self.patches]
        return SolverStatus.combine(parts)

    @property
    def converged(self) -> bool:
        """False when the vertical-force iteration did not meet the load to its
        tolerance (also where the model's force jumps across it: then
        ``balance.force_jump``), a solver or the normal-tangential coupling did not
        converge, or a wheel derailed (``status.message`` says which)."""
        return self.status.converged

    @property
    def warnings(self) -> list:
        """Where the result leaves the range of its models (``status.warnings``)."""
        return list(self.status.warnings)

    @property
    def vertical_residual(self) -> dict | None:
        """Relative residual (F_z - Q)/Q [-] of each side's vertical balance for a
        wheel-rail case (None for a bodies case): within ``solver.force_tolerance``
        unless the model's force jumps across the load (see ``docs/case_files.md``)."""
        return self.balance.residual if self.balance is not None else None

    def to_dict(self) -> dict:
        status = self.status
        d = {"patches": [p.to_dict() for p in self.patches], "normal": self.normal,
             "tangential": self.tangential, "cpu_time": self.cpu_time,
             "converged": status.converged, "message": status.message,
             "warnings": list(status.warnings)}
        if self.vertical_residual is not None:
            d["vertical_residual"] = dict(self.vertical_residual)
        return d

    def to_json(self, **kw) -> str:
        return json.dumps(self.to_dict(), **kw)

    def to_xarray(self):
        """Patch results as an :class:`xarray.Dataset` along a ``patch`` dimension."""
        import xarray as xr
        rows = [p.to_dict() for p in self.patches]
        units = {"area": "m2", "pmax": "Pa", "penetration": "m", "Fn": "N", "Fx": "N",
                 "Fy": "N", "Mz": "N m", "contact_angle": "rad", "rolling_radius": "m",
                 "y_rail": "m", "y_wheel": "m"}
        data = {k: ("patch", np.array([np.nan if r[k] is None else r[k] for r in rows], float),
                    {"units": u}) for k, u in units.items()}
        data["frictional_power"] = (
            "patch", np.array([r.get("frictional_power", 0.0) for r in rows], float),
            {"units": "W", "long_name": "frictional power dissipated in the patch"})
        if any("max_temperature_degC" in r for r in rows):
            data["max_temperature"] = (
                "patch", np.array([r.get("max_temperature_degC", np.nan) for r in rows], float),
                {"units": "degC", "long_name": "largest flash temperature of the rail and "
                                               "wheel surfaces in the patch"})
        for c, u in (("longitudinal", "1"), ("lateral", "1"), ("spin", "m-1")):
            data[f"creepage_{c}"] = ("patch", np.array([r["creepage"][c] for r in rows]),
                                     {"units": u})
        return xr.Dataset(data, coords={"side": ("patch", [str(r["side"]) for r in rows])},
                          attrs={"normal_model": self.normal, "tangential_model": self.tangential,
                                 "title": self.title, **self._status_attrs()})

    def _status_attrs(self) -> dict:
        """The status as NetCDF attributes: converged (0/1), message, warnings (one
        string, '; ' between them)."""
        s = self.status
        return {"converged": int(s.converged), "message": s.message,
                "warnings": "; ".join(s.warnings)}



def patch_vertical_force(r, fy: float | None = None) -> float:
    """Vertical force [N] that the wheel exerts on the rail through one patch (track z).

    On the rail, F_z = f_n cos(d) + f_s sin(d) with f_s = -F_y the lateral force on
    the rail (the patch results hold forces on the wheel).  ``fy``: a lateral force
    F_y [N] that stands in for the patch's tangential solution; else the tangential
    solution's (0 without one).
    """
    d = r.geometry.contact_angle
    if fy is None:
        fy = r.tangential.fy if r.tangential is not None else 0.0
    return r.normal.normal_force * math.cos(d) - fy * math.sin(d)


def vertical_force_on_rail(results, side: str, lateral=None) -> float:
    """Total vertical force [N] the wheel exerts on the rail of one side (track z):
    :func:`patch_vertical_force` summed over the side's patches.  ``lateral``: a
    function of a patch result giving the lateral force F_y [N] that stands in for
    its tangential solution (:class:`WheelRailContact`)."""
    return sum(patch_vertical_force(r, lateral(r) if lateral is not None else None)
               for r in results if r.geometry.side == side)



def geometry_dict(contact: WheelsetContact, side: str = "both") -> dict:
    """JSON of the contact points found by the geometry layer (no forces)."""
    patches = [p.to_dict() for p in contact.patches if side == "both" or p.side == side]
    return {"patches": patches, "roll": contact.pose.roll, "vertical": contact.pose.vertical,
            "lateral_shift": contact.pose.lateral_shift, "yaw": contact.pose.yaw}
