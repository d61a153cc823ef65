"""Many contact patches at once: compiled normal and tangential models, forces only.

For sweeps, wear loops and anything that needs the forces of thousands of patches
(the geometry layer's :class:`~railcontact.geometry.ContactGeometry` objects), where
building grids and result objects per patch would dominate.  Hertz's solution is
vectorised over the patches (:func:`railcontact.core.hertz_theory.hertz_ellipses`),
Kalker's coefficients come from the compiled table lookup, and the creep law runs in
one compiled loop (:mod:`railcontact.tangential.online`).  The strip models run on
strips of all patches together (:mod:`railcontact.normal.strip_batch`), with FASTSIM,
its strip-wise variant or FaStrip marching their strip pressures in compiled loops.
Any other model pair is solved patch by patch with the registered models (same
outputs, slower).  Which path a pair takes follows from the capabilities the models
declare in their registries: ``"ellipse"`` and ``"batch"`` (normal), ``"online"``
and ``"strip-march"`` (tangential).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from numba import njit

from ..core.checks import shown
from ..core.errors import InputError
from ..core.materials import Material, STEEL
from ..normal import get_normal_model, normal_model_class, normal_supports
from ..normal.strip_batch import hertz_ellipse_strips, patch_hertz_ellipses, solve_strips
from ..tangential import get_tangential_model, tangential_model_class, tangential_supports
from ..tangential.kalker import kalker_coefficients_array
from ..tangential.online import online_law, patch_forces


@dataclass
class PatchForces:
    """Per-patch results of :func:`solve_patches` (SI units, forces of the rail on
    the wheel in each patch's contact-local frame)."""

    normal_force: np.ndarray
    area: np.ndarray
    pmax: np.ndarray
    penetration: np.ndarray
    a: np.ndarray
    b: np.ndarray
    Fx: np.ndarray
    Fy: np.ndarray
    Mz: np.ndarray
    normal: str = "hertz"
    tangential: str = "fastsim"
    cpu_time: float = 0.0
    options: dict = field(default_factory=dict)

    def to_xarray(self):
        import xarray as xr
        units = {"normal_force": "N", "area": "m^2", "pmax": "Pa", "penetration": "m",
                 "a": "m", "b": "m", "Fx": "N", "Fy": "N", "Mz": "N m"}
        return xr.Dataset({k: ("patch", getattr(self, k), {"units": u})
                           for k, u in units.items()},
                          attrs={"normal": self.normal, "tangential": self.tangential,
                                 "cpu_time_s": self.cpu_time})


@njit(cache=True, nogil=True)
def _forces(law, tp, N, a, b, C, creep, V, out):
    """The online law per patch: Kalker's coefficients ``C`` (3, n) (C11, C22, C23),
    creepages ``creep`` (3, n) (xi, eta, phi) into ``out`` (n, 3)."""
    for i in range(N.size):
        out[i, 0], out[i, 1], out[i, 2] = patch_forces(law, tp, N[i], a[i], b[i], C[0, i],
                                                        C[1, i], C[2, i], creep[0, i],
                                                        creep[1, i], creep[2, i], V[i])


def solve_patches(patches, normal: str = "hertz", tangential: str = "fastsim",
                  material: Material = STEEL, friction: float = 0.3,
                  fastsim_grid=(20, 20), grid=None, strips: int = 40) -> PatchForces:
    """Normal and tangential solution of many patches, each at the geometry's approach
    and creepages.

    Parameters
    ----------
    patches : sequence of ContactGeometry
        With ``approach`` [m], ``creepage`` and ``velocity`` (the geometry layer's
        patches; patches without creepage get zero creepage at 1 m/s).
    normal, tangential : str
        ``"hertz"`` with ``"fastsim"``, ``"polach"`` or ``"linear"`` runs compiled
        (FASTSIM on ``fastsim_grid`` = (elements per strip, strips)).  The strip
        models ``"kik-piotrowski"``, ``"kpec"``, ``"stripes"`` and ``"analyn"`` with
        the same creep laws run on ``strips`` strips per patch
        (:mod:`railcontact.normal.strip_batch`), FASTSIM marching the strips'
        semi-elliptic pressures with ``fastsim_grid[0]`` elements per strip and the
        flexibilities of the equivalent ellipse, Polach and the linear law on that
        ellipse.  With them, ``"fastsim-strips"`` marches the same strips with the
        flexibilities of each strip's local ellipse and the spin of its local contact
        angle, and ``"fastrip"`` runs FaStrip's strip theory and spin march on them;
        ``"hertz"`` with ``"fastrip"`` cuts the ellipse in ``fastsim_grid[1]`` strips.
        Any other registered pair is solved patch by patch on ``grid``.
    """
    patches = list(patches)
    if not patches:
        raise InputError("solve_patches: no patches given")
    if not (math.isfinite(friction) and 0 < friction <= 5):
        raise InputError(f"friction coefficient {shown(friction)}: expected a value in (0, 5]")
    t0 = time.perf_counter()
    n = len(patches)
    A = np.fromiter((p.curvatures[0] for p in patches), float, n)
    B = np.fromiter((p.curvatures[1] for p in patches), float, n)
    pen = np.fromiter((p.approach for p in patches), float, n)
    cr = np.array([p.creepage if p.creepage is not None else (0.0, 0.0, 0.0)
                   for p in patches], dtype=float).reshape(n, 3)
    V = np.fromiter((p.velocity if math.isfinite(p.velocity) else 1.0 for p in patches),
                    float, n)
    normal_model_class(normal), tangential_model_class(tangential)     # known names
    law = online_law(tangential)
    ellipse = normal_supports(normal, "ellipse")
    if ellipse and law is not None:
        nx, ny = (int(v) for v in fastsim_grid)
        if not (2 <= nx <= 500 and 2 <= ny <= 500):
            raise InputError(f"fastsim_grid {shown(fastsim_grid)}: expected two integers in "
                             "[2, 500]")
        a, b, F = patch_hertz_ellipses(patches, material.contact_modulus, pen)
        ok = F > 0
        C11, C22, C23 = (np.ones(n) for _ in range(3))
        if ok.any():
            c = kalker_coefficients_array(a[ok] / b[ok], material.nu)
            C11[ok], C22[ok], C23[ok] = c
        tp = np.array([friction, material.shear_modulus, nx, ny, 1.0, 1.0, 1.0, 0.0])
        out = np.zeros((n, 3))
        _forces(law, tp, F, a, b, np.array([C11, C22, C23]), np.ascontiguousarray(cr.T), V,
                out)
        area = math.pi * a * b
        with np.errstate(divide="ignore", invalid="ignore"):
            pmax = np.where(ok, 1.5 * F / area, 0.0)
        return PatchForces(F, area, pmax, np.maximum(pen, 0.0), a, b, out[:, 0], out[:, 1],
                           out[:, 2], normal, tangential, time.perf_counter() - t0,
                           {"compiled": True, "fastsim_grid": (nx, ny)})
    marches = tangential_supports(tangential, "strip-march")
    if normal_supports(normal, "batch") and (law is not None or marches):
        if ellipse:                            # the ellipse in strips, as FASTSIM's grid
            strips = int(fastsim_grid[1])
        return _strip_patches(patches, normal, tangential, material, friction, cr, V,
                              strips, fastsim_grid[0], t0)
    nm, tm = get_normal_model(normal), get_tangential_model(tangential)
    res = np.zeros((n, 9))
    for i, g in enumerate(patches):
        if g.approach <= 0:
            continue
        ns = nm.solve(g, material, penetration=g.approach, grid=grid)
        ts = tm.solve(ns, g, material, tuple(cr[i]), friction, V[i])
        ab = ns.semi_axes if ns.semi_axes is not None else (math.nan, math.nan)
        res[i] = (ns.normal_force, ns.area, ns.pmax, ns.penetration, ab[0], ab[1], ts.fx,
                  ts.fy, ts.mz)
    return PatchForces(*res.T, normal, tangential, time.perf_counter() - t0,
                       {"compiled": False})


def _strip_patches(patches, normal, tangential, material, friction, cr, V, strips, nx, t0):
    """Compiled path of :func:`solve_patches` for the normal models with strips in
    batch (the strip models, and Hertz's ellipse cut in strips): a tangential model
    that marches strips does so (``strip_forces``), an online law runs on each
    patch's equivalent ellipse."""
    if not (isinstance(strips, (int, np.integer)) and 5 <= strips <= 1000):
        raise InputError(f"strips {shown(strips)}: expected an integer in [5, 1000]")
    nx = int(nx)
    if not 2 <= nx <= 500:
        raise InputError(f"fastsim_grid elements per strip {shown(nx)}: expected [2, 500]")
    if normal_supports(normal, "ellipse"):
        st = hertz_ellipse_strips(patches, material.contact_modulus, strips=int(strips))
    elif normal_supports(normal, "strips"):
        st = solve_strips(normal, patches, material.contact_modulus, strips=int(strips))
    else:
        raise InputError(f"normal model {normal!r} in batch: expected one that declares "
                         "'ellipse' or 'strips'")
    F = st.normal_force
    a, b = st.equivalent_ellipses()
    ok = (F > 0) & (a > 0) & (b > 0)
    n = F.size
    creepage = tuple(np.ascontiguousarray(cr[:, i]) for i in range(3))
    out = np.zeros((n, 3))
    if tangential_supports(tangential, "strip-march"):
        tangential_model_class(tangential).strip_forces(st, patches, a, b, ok, creepage,
                                                        material, friction, nx, out)
    else:
        C11, C22, C23 = (np.ones(n) for _ in range(3))
        if ok.any():
            C11[ok], C22[ok], C23[ok] = kalker_coefficients_array(a[ok] / b[ok], material.nu)
        tp = np.array([friction, material.shear_modulus, nx, nx, 1.0, 1.0, 1.0, 0.0])
        _forces(online_law(tangential), tp, np.where(ok, F, 0.0), a, b,
                np.array([C11, C22, C23]), np.array(creepage), V, out)
    return PatchForces(F, st.area, st.pmax, st.penetration, a, b, out[:, 0], out[:, 1],
                       out[:, 2], normal, tangential, time.perf_counter() - t0,
                       {"compiled": True, "strips": int(strips), "fastsim_elements": nx})
