"""Subsurface stresses under a solved contact patch.

The surface loads of a patch -- the pressure of its normal solution and the
tractions of its tangential solution, piecewise constant on the elements of the
patch grid -- are convolved in the plane with the half-space influence kernels of
uniform rectangular loads (:mod:`railcontact.subsurface.kernels`, Love 1929;
Johnson 1985, section 3.2), one depth at a time, with zero-padded real FFTs (the
discrete convolution of Liu, Wang & Liu 2000, "DC-FFT").  This is what CONTACT
does with its piecewise constant elements (Vollebregt, user guide, section 5.6;
Kalker 1990, appendix C); its ``subsurf.inp`` example is reproduced to the printed
digits (tests/subsurface).

Every normal and tangential model returns its pressure and tractions on the patch
grid (Hertz and the strip models sample their closed-form distributions at the
element centres), so every model's result has a subsurface field.

Frame and signs: x rolling, y lateral (the patch's contact-local frame) and z the
depth into the chosen body; stresses in Pa, tension positive.  ``body="rail"``
(default): z along the contact normal n (wheel into rail), the rail loaded by the
pressure and by minus the tractions of the tangential solution (which are those
on the wheel).  ``body="wheel"``: z = -n, depth into the wheel, loaded by the
pressure and the solution's tractions; the components are given in the axes
(x, y, z) all the same (a left-handed triple: sigma_xy and sigma_yz change sign
with the mirror image).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..core.errors import InputError
from .kernels import COMPONENTS, convolve_depths

log = logging.getLogger(__name__)

#: the derived measures of :class:`SubsurfaceStresses` whose maxima are reported
MEASURES = ("von_mises", "tresca", "orthogonal_shear_xz", "orthogonal_shear_yz")


def stresses_on_grid(x, y, pressure, traction_x=None, traction_y=None, depths=(0.0,),
                     poisson: float = 0.28) -> np.ndarray:
    """Stress tensor under piecewise constant surface loads on a uniform grid.

    Parameters
    ----------
    x, y : ndarray
        Element centres [m] of a uniform grid (at least 2 per direction).
    pressure : ndarray (mx, my)
        Pressure [Pa] pushing into the body.
    traction_x, traction_y : ndarray (mx, my), optional
        Shear tractions [Pa] acting on the body (zero when omitted).
    depths : sequence of float
        Depths z >= 0 [m].
    poisson : float
        Poisson's ratio of the body [-].

    Returns
    -------
    ndarray (6, mx, my, nz)
        sigma_xx, yy, zz, xy, xz, yz [Pa] (tension positive) at the element centres
        and depths (:func:`~railcontact.subsurface.kernels.convolve_depths`).
    """
    x, y = np.asarray(x, float), np.asarray(y, float)
    p = np.asarray(pressure, float)
    mx, my = x.size, y.size
    if mx < 2 or my < 2 or p.shape != (mx, my):
        raise InputError(f"pressure of shape {p.shape} on a grid of {mx} x {my} centres: "
                         "expected a (mx, my) array on a grid of at least 2 x 2 elements")
    dx, dy = float(x[1] - x[0]), float(y[1] - y[0])
    if not (dx > 0 and dy > 0) or (np.ptp(np.diff(x)) > 1e-6 * dx or np.ptp(np.diff(y)) > 1e-6 * dy):
        raise InputError("subsurface stresses: expected a uniform grid of increasing element "
                         "centres x, y")
    zero = np.zeros_like(p)
    qx = zero if traction_x is None else np.asarray(traction_x, float)
    qy = zero if traction_y is None else np.asarray(traction_y, float)
    if qx.shape != p.shape or qy.shape != p.shape:
        raise InputError(f"tractions of shapes {qx.shape}, {qy.shape}: expected {p.shape}")
    z = np.atleast_1d(np.asarray(depths, float))
    if z.ndim != 1 or z.size == 0 or np.any(~np.isfinite(z)) or np.any(z < 0):
        raise InputError(f"subsurface depths {depths!r}: expected one or more depths >= 0 m")
    return convolve_depths(np.stack([p, qx, qy]), _round(dx), _round(dy),
                           [_round(v) for v in z], float(poisson))


def _round(v: float) -> float:
    """v to 12 digits: element sizes and depths that differ by round-off share the
    cached kernel spectra."""
    return float(f"{v:.12g}")


def von_mises(s: np.ndarray) -> np.ndarray:
    """Von Mises equivalent stress [Pa] of stresses s (6, ...)."""
    xx, yy, zz, xy, xz, yz = s
    return np.sqrt(0.5 * ((xx - yy) ** 2 + (yy - zz) ** 2 + (zz - xx) ** 2)
                   + 3.0 * (xy * xy + xz * xz + yz * yz))


def principal_stresses(s: np.ndarray) -> np.ndarray:
    """Principal stresses (3, ...) [Pa], ascending (sigma_3, sigma_2, sigma_1)."""
    xx, yy, zz, xy, xz, yz = s
    T = np.stack([np.stack([xx, xy, xz], -1), np.stack([xy, yy, yz], -1),
                  np.stack([xz, yz, zz], -1)], -2)
    ev = np.linalg.eigvalsh(T)
    return np.moveaxis(ev, -1, 0)


@dataclass
class SubsurfaceStresses:
    """The stress tensor below a patch, on its grid, at a set of depths.

    Attributes
    ----------
    x, y : ndarray          element centres [m] (rolling, lateral)
    z : ndarray             depths [m] into ``body``
    sigma : ndarray (6, nx, ny, nz)
        sigma_xx, yy, zz, xy, xz, yz [Pa], tension positive (:data:`COMPONENTS`).
    body : str              "rail" or "wheel"
    poisson : float         Poisson's ratio used [-]
    source : str            the models that gave the surface loads
    """

    x: np.ndarray
    y: np.ndarray
    z: np.ndarray
    sigma: np.ndarray
    body: str = "rail"
    poisson: float = 0.28
    source: str = ""
    _principal: np.ndarray | None = field(default=None, repr=False)

    def component(self, name: str) -> np.ndarray:
        """One component ("xx", "yy", "zz", "xy", "xz", "yz") [Pa]."""
        if name not in COMPONENTS:
            raise InputError(f"stress component {name!r}: expected one of {COMPONENTS}")
        return self.sigma[COMPONENTS.index(name)]

    @property
    def von_mises(self) -> np.ndarray:
        """Von Mises stress [Pa]."""
        return von_mises(self.sigma)

    @property
    def principal(self) -> np.ndarray:
        """Principal stresses (3, nx, ny, nz) [Pa], ascending."""
        if self._principal is None:
            self._principal = principal_stresses(self.sigma)
        return self._principal

    @property
    def tresca(self) -> np.ndarray:
        """Tresca equivalent stress sigma_1 - sigma_3 [Pa] (twice the largest shear)."""
        ps = self.principal
        return ps[2] - ps[0]

    @property
    def hydrostatic(self) -> np.ndarray:
        """Mean stress (sigma_xx + sigma_yy + sigma_zz) / 3 [Pa]."""
        return self.sigma[:3].sum(axis=0) / 3.0

    @property
    def orthogonal_shear_xz(self) -> np.ndarray:
        """Orthogonal shear stress tau_xz [Pa]: shear on planes parallel and normal to
        the surface, in the rolling direction (Johnson 1985, section 4.2)."""
        return self.sigma[4]

    @property
    def orthogonal_shear_yz(self) -> np.ndarray:
        """Orthogonal shear stress tau_yz [Pa], lateral."""
        return self.sigma[5]

    def maximum(self, measure: str) -> dict:
        """Largest value of a measure (of its magnitude for the shears) and where.

        Parameters
        ----------
        measure : str   one of :data:`MEASURES`

        Returns
        -------
        dict with ``value`` [Pa], ``x``, ``y``, ``depth`` [m].
        """
        if measure not in MEASURES:
            raise InputError(f"subsurface measure {measure!r}: expected one of {MEASURES}")
        f = np.abs(getattr(self, measure))
        i, j, k = np.unravel_index(int(np.argmax(f)), f.shape)
        return {"value": float(f[i, j, k]), "x": float(self.x[i]), "y": float(self.y[j]),
                "depth": float(self.z[k])}

    def maxima(self) -> dict:
        """:meth:`maximum` of every measure in :data:`MEASURES`."""
        return {m: self.maximum(m) for m in MEASURES}

    def to_xarray(self):
        """Components, von Mises, Tresca, principal and hydrostatic stresses as an
        :class:`xarray.Dataset` with units; the maxima and their positions as
        attributes (``max_<measure>_Pa``, ``depth_max_<measure>_m``, ...)."""
        import xarray as xr
        dims = ("x", "y", "z")
        data = {f"sigma_{c}": (dims, self.sigma[i], {"units": "Pa",
                                                       "long_name": f"stress {c}, tension positive"})
                for i, c in enumerate(COMPONENTS)}
        ps = self.principal
        data.update({
            "von_mises": (dims, self.von_mises, {"units": "Pa", "long_name": "von Mises stress"}),
            "tresca": (dims, ps[2] - ps[0], {"units": "Pa",
                                              "long_name": "Tresca stress sigma_1 - sigma_3"}),
            "sigma_1": (dims, ps[2], {"units": "Pa", "long_name": "largest principal stress"}),
            "sigma_3": (dims, ps[0], {"units": "Pa", "long_name": "smallest principal stress"}),
            "hydrostatic": (dims, self.hydrostatic, {"units": "Pa", "long_name": "mean stress"})})
        attrs = {"body": self.body, "poisson_ratio": self.poisson, "source": self.source,
                 "frame": "x rolling, y lateral, z depth into the body (contact-local)"}
        for m, v in self.maxima().items():
            attrs[f"max_{m}_Pa"] = v["value"]
            attrs[f"x_max_{m}_m"] = v["x"]
            attrs[f"y_max_{m}_m"] = v["y"]
            attrs[f"depth_max_{m}_m"] = v["depth"]
        return xr.Dataset(data, coords={
            "x": ("x", self.x, {"units": "m", "long_name": "rolling direction"}),
            "y": ("y", self.y, {"units": "m", "long_name": "lateral, in the tangent plane"}),
            "z": ("z", self.z, {"units": "m", "long_name": f"depth into the {self.body}"})},
            attrs=attrs)

    def plot_sections(self, path, measure: str = "von_mises"):
        """Sections of a measure (or a component "sigma_xx" ...) in MPa: the x-z plane
        and the y-z plane through its maximum, and the x-y plane at the depth of the
        maximum; written to ``path`` (PNG)."""
        from ..core.plotting import _plt
        if measure.startswith("sigma_"):
            f = self.component(measure[6:])
        elif measure in MEASURES:
            f = getattr(self, measure)
        else:
            raise InputError(f"subsurface measure {measure!r}: expected one of {MEASURES} "
                             "or sigma_<component>")
        m = np.abs(f)
        i, j, k = np.unravel_index(int(np.argmax(m)), m.shape)
        plt = _plt()
        fig, axes = plt.subplots(1, 3, figsize=(14, 4))
        mm, mpa = 1e3, 1e-6
        panels = ((self.x, self.z, f[:, j, :], f"x-z plane, y = {self.y[j] * mm:.2f} mm", "x [mm]"),
                  (self.y, self.z, f[i, :, :], f"y-z plane, x = {self.x[i] * mm:.2f} mm", "y [mm]"))
        for ax, (h, z, sec, title, xl) in zip(axes[:2], panels):
            c = ax.pcolormesh(h * mm, z * mm, sec.T * mpa, shading="auto", cmap="viridis")
            ax.invert_yaxis()
            ax.set_xlabel(xl)
            ax.set_ylabel(f"depth into the {self.body} [mm]")
            ax.set_title(title)
            fig.colorbar(c, ax=ax, label=f"{measure} [MPa]")
        ax = axes[2]
        c = ax.pcolormesh(self.x * mm, self.y * mm, f[:, :, k].T * mpa, shading="auto",
                          cmap="viridis")
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
        ax.set_title(f"x-y plane, depth {self.z[k] * mm:.2f} mm")
        fig.colorbar(c, ax=ax, label=f"{measure} [MPa]")
        fig.tight_layout()
        fig.savefig(path, dpi=110)
        plt.close(fig)
        return Path(path)


def default_depths(normal, n: int = 21) -> np.ndarray:
    """Depths [m] from the surface to twice the equivalent radius sqrt(area / pi) of
    the contact (the maximum von Mises stress of a Hertzian contact lies near 0.5 a)."""
    r = math.sqrt(max(float(normal.area), 0.0) / math.pi)
    if not r > 0:
        r = 0.5 * min(float(np.ptp(normal.x)), float(np.ptp(normal.y)))
    return np.linspace(0.0, 2.0 * r, n)


def subsurface_stresses(normal, tangential=None, depths=None, material=None,
                        body: str = "rail") -> SubsurfaceStresses:
    """The stress tensor below a solved patch.

    Parameters
    ----------
    normal : NormalSolution or PatchResult
        The patch's normal solution (its pressure on its grid), or a patch of a
        solved case (:class:`~railcontact.cases.results.PatchResult`), whose normal and
        tangential solutions are then used.
    tangential : TangentialSolution, optional
        Its tangential solution on the same grid (frictionless when omitted).
    depths : sequence of float, optional
        Depths [m] into the body (default :func:`default_depths`).
    material : Material, optional
        Gives Poisson's ratio of the body (default steel, 0.28).
    body : {"rail", "wheel"}
        The body whose stresses are computed (see the module's notes on signs).

    Returns
    -------
    SubsurfaceStresses
    """
    from ..core.materials import STEEL
    if hasattr(normal, "normal") and hasattr(normal, "tangential"):      # a PatchResult
        if tangential is None:
            tangential = normal.tangential
        normal = normal.normal
    if body not in ("rail", "wheel"):
        raise InputError(f"subsurface body {body!r}: expected 'rail' or 'wheel'")
    mat = STEEL if material is None else material
    (_, nu_rail), (_, nu_wheel) = mat.bodies
    nu = nu_rail if body == "rail" else nu_wheel
    z = default_depths(normal) if depths is None else np.atleast_1d(np.asarray(depths, float))
    p = np.asarray(normal.pressure, float)
    source = normal.model
    tx = ty = None
    if tangential is not None:
        if tangential.traction_x.shape != p.shape:
            raise InputError(f"tangential solution on a {tangential.traction_x.shape} grid: "
                             f"expected the normal solution's {p.shape}")
        tx, ty = np.asarray(tangential.traction_x, float), np.asarray(tangential.traction_y, float)
        source += f" + {tangential.model}"
    if body == "rail":
        qx = None if tx is None else -tx
        qy = None if ty is None else -ty
        sigma = stresses_on_grid(normal.x, normal.y, p, qx, qy, z, nu)
    else:
        # mirror y: the wheel's right-handed frame (x, -y, -n); then back to (x, y)
        yy = -normal.y[::-1]
        qy = None if ty is None else -ty[:, ::-1]
        sigma = stresses_on_grid(normal.x, yy, p[:, ::-1], tx[:, ::-1] if tx is not None else None,
                                 qy, z, nu)[:, :, ::-1, :]
        sigma[3] *= -1.0
        sigma[5] *= -1.0
    return SubsurfaceStresses(x=np.asarray(normal.x, float), y=np.asarray(normal.y, float), z=z,
                              sigma=sigma, body=body, poisson=float(nu), source=source)
