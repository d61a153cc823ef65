"""Elastic-plastic normal contact with isotropic hardening (semi-analytical method).

The method of Jacq, Nelias, Lormand & Girodin (*Development of a three-dimensional
semi-analytical elastic-plastic contact code*, J. Tribol. 124, 2002, 653-667),
for the normal contact of an elastic body (the wheel) on an elastic-plastic
half-space (the rail, a crossing nose of Mn13):

* a volume grid of mx x my x nz cuboids below the patch grid (the surface grid of
  the exact normal solver) carries the plastic strain eps_p, the equivalent
  plastic strain alpha (the hardening state) and the flow stress sigma_y(alpha);
* **surface problem**: the exact normal solver's problem (Kalker; Polonsky & Keer's
  conjugate gradients, :func:`railcontact.normal.polonsky_keer.polonsky_keer`,
  FFT products of :mod:`railcontact.normal.influence`) on the gap h + u_r, u_r the
  normal surface displacement of the plastic strains (the permanent dent,
  :class:`~railcontact.subsurface.eigenstrain.EigenstrainInfluence`), the force
  given;
* **stresses**: the elastic stresses of the pressure (Love's kernels by FFT per
  depth, :func:`~railcontact.subsurface.stresses.stresses_on_grid`) plus the
  residual stresses of the plastic strains (:mod:`~railcontact.subsurface.eigenstrain`);
* **plastic corrector**: von Mises' yield function with isotropic hardening and
  the radial return (Simo & Hughes, *Computational Inelasticity*, 1998, box 3.1):
  from the trial stress T = sigma_e + sigma_r(eps_p) + 2 mu d eps_p (the step's
  plastic strain increment d eps_p taken back), q = sqrt(3/2 s:s) of its deviator
  s, the increment dgamma solves q - 3 mu dgamma = sigma_y(alpha_n + dgamma) and
  d eps_p = 3/2 dgamma s / q;
* the increment, the residual stress, the dent and the pressure are iterated to a
  fixed point per load step (Jacq's loop), the load applied in steps.

Repeated passes (:meth:`ElasticPlasticContact.run_passes`) load and unload the
patch, standing or moving along x, and report the plastic strain increment per
pass: zero after some passes is shakedown, an increment that stays is ratchetting.

Mn13 hardening (:data:`MN13`): see :class:`Hardening`.

What it leaves out: kinematic hardening (the Bauschinger effect, which drives
ratchetting in cyclic rolling), tangential tractions in the plastic loop (the
frictionless normal problem, as the FE of seed 003), large deformations and the
real body's shape below the surface (a half-space).  All inputs and results in SI.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..core.errors import InputError
from ..core.materials import Material
from ..core.status import SolverStatus
from ..normal.base import NormalSolution
from ..normal.influence import normal_operator
from ..normal.polonsky_keer import polonsky_keer
from .eigenstrain import EigenstrainInfluence, VolumeGrid
from .kernels import COMPONENTS
from .stresses import stresses_on_grid, von_mises

log = logging.getLogger(__name__)

#: weights of the six components in s : s (tensor shears counted twice)
_W = np.array([1.0, 1.0, 1.0, 2.0, 2.0, 2.0])


@dataclass(frozen=True)
class Hardening:
    """Isotropic hardening of von Mises plasticity: the flow stress [Pa]

        sigma_y(alpha) = yield_stress + modulus alpha + saturation (1 - exp(-rate alpha))

    (linear plus Voce), alpha the equivalent plastic strain [-].

    Parameters
    ----------
    yield_stress : float   initial yield stress Y [Pa] (1e6 .. 1e11)
    modulus : float        linear hardening modulus H [Pa] (>= 0)
    saturation : float     Voce's saturation stress Q [Pa] (>= 0)
    rate : float           Voce's rate b [-] (>= 0)
    """

    yield_stress: float
    modulus: float = 0.0
    saturation: float = 0.0
    rate: float = 0.0

    def __post_init__(self):
        vals = (self.yield_stress, self.modulus, self.saturation, self.rate)
        if any(isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v)
               for v in vals) or not 1e6 <= self.yield_stress <= 1e11 or min(vals[1:]) < 0:
            raise InputError(f"hardening (yield_stress, modulus, saturation, rate) = {vals!r}: "
                             "expected a yield stress in [1e6, 1e11] Pa and moduli, saturation "
                             "and rate >= 0")

    def flow_stress(self, alpha):
        """sigma_y(alpha) [Pa]."""
        return (self.yield_stress + self.modulus * alpha
                + self.saturation * (1.0 - np.exp(-self.rate * alpha)))

    def slope(self, alpha):
        """d sigma_y / d alpha [Pa]."""
        return self.modulus + self.saturation * self.rate * np.exp(-self.rate * alpha)


#: Mn13 (Hadfield's austenitic manganese steel, X120Mn12) of crossing noses.  The
#: yield stress 360 MPa is seed 003's (Wiest et al., Wear 265, 2008, Table 1; the
#: paper states von Mises plasticity with "extremely good hardening" and gives no
#: curve).  The hardening is linear, H = 2.4 GPa (sigma_y(0.35) = 1.20 GPa): an
#: estimate of the high, nearly constant work-hardening rate of Hadfield steel in
#: tension, which Hutchinson & Ridley (Scripta Mater. 55, 2006, 299-302) trace to
#: twinning beyond true strains of about 0.15.  The value is an engineering
#: estimate of typical Hadfield flow curves (yield 350-400 MPa, about 1.2 GPa near
#: a true strain of 0.35), not read from that paper's figures nor fitted to a test
#: of the seed's cast: give a measured curve (Hardening) where one is known.
#: No published hardening law for Mn13 in crossings could be read in issue 31's
#: literature search (Harzallah, Mouftiez et al. 2010, Wear; Pletz, Daves &
#: Ossberger 2012, Wear and Proc. IMechE F; Wiest et al.; Skrypnyk et al.
#: 2019, Wear 428-429, an Ohno-Wang fit; the MCL Leoben crossing papers in Metals
#: 2022-2023): only their titles or abstracts were reachable, so H stays the
#: estimate above (docs/subsurface.md, "Mn13").  A second search (branch lit31:
#: flow curves of Hadfield steel, EN 15689 / EN 10349 properties, Johnson-Cook
#: fits, crossing FE theses, material cards in the code index) found no value
#: either; its record is in the same section.
MN13 = Hardening(yield_stress=360e6, modulus=2.4e9)


def _deviator(s):
    m = (s[0] + s[1] + s[2]) / 3.0
    d = s.copy()
    d[:3] -= m
    return d


def _return_map(T, alpha, hardening: Hardening, mu: float):
    """Radial return of trial stresses T (6, ...) from the hardening state alpha:
    the plastic strain increment (6, ...) and its dgamma (...)."""
    s = _deviator(T)
    q = np.sqrt(1.5 * np.tensordot(_W, s * s, axes=1))
    f = q - hardening.flow_stress(alpha)
    yielding = f > 0
    dg = np.zeros_like(q)
    if yielding.any():
        qy, ay = q[yielding], alpha[yielding]
        g = f[yielding] / (3.0 * mu + hardening.slope(ay))
        for _ in range(20):                        # Newton on the nonlinear (Voce) part
            r = qy - 3.0 * mu * g - hardening.flow_stress(ay + g)
            step = r / (3.0 * mu + hardening.slope(ay + g))
            g = g + step
            if np.all(np.abs(step) <= 1e-12 * np.maximum(g, 1e-30)):
                break
        dg[yielding] = np.maximum(g, 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        n = np.where(q > 0, 1.5 * s / np.where(q > 0, q, 1.0), 0.0)
    return dg * n, dg


class _Anderson:
    """Anderson's acceleration (type II, depth ``m``) of the fixed point x = G(x) of
    the step's plastic strain increment (Walker & Ni, SIAM J. Numer. Anal. 49, 2011):
    the plain iteration converges linearly with a ratio near 1 where the plastic zone
    is weakly constrained (a shear layer below the free surface) and the hardening
    modulus is small against 3 mu."""

    def __init__(self, m: int = 5):
        self.m, self.dG, self.dF, self.last = m, [], [], None

    def __call__(self, x, g):
        f = (g - x).ravel()
        gr = g.ravel()
        if self.last is not None:
            self.dF.append(f - self.last[0])
            self.dG.append(gr - self.last[1])
            if len(self.dF) > self.m:
                self.dF.pop(0)
                self.dG.pop(0)
        self.last = (f, gr)
        if not self.dF:
            return g
        F = np.stack(self.dF, axis=1)
        gamma, *_ = np.linalg.lstsq(F, f, rcond=None)
        return (gr - np.stack(self.dG, axis=1) @ gamma).reshape(g.shape)


@dataclass
class ElasticPlasticResult:
    """The state of an elastic-plastic contact after a load history.

    Attributes
    ----------
    normal : NormalSolution
        The surface solution of the last load state (pressure on the patch grid,
        area, p_max, approach): model "elastic-plastic".
    x, y, z : ndarray          cell centres [m] (rolling, lateral, depth)
    plastic_strain : ndarray (6, mx, my, nz)
        eps_p [-] (:data:`COMPONENTS`, tensor shears).
    equivalent_plastic_strain : ndarray (mx, my, nz)
        alpha [-], the hardening state.
    flow_stress : ndarray (mx, my, nz)    sigma_y(alpha) [Pa]
    stress : ndarray (6, mx, my, nz)      the stresses under the last load [Pa]
    residual_stress : ndarray (6, mx, my, nz)
        The stresses of the plastic strains alone (the load removed) [Pa].
    residual_displacement : ndarray (mx, my)
        The permanent normal displacement of the surface, into the body [m].
    history : dict of lists
        Per load state: ``force`` [N], ``x_shift`` [m], ``pass``, ``area`` [m^2],
        ``pmax`` [Pa], ``penetration`` [m], ``iterations``, ``plastic_increment``
        (largest increment of alpha in the state) [-].
    passes : dict of lists
        Per pass: ``plastic_increment`` (largest increment of alpha over the pass),
        ``mean_increment`` (its mean over the cells that yielded in the first pass),
        ``net_increment`` (the mean there of the equivalent of the pass's net change
        of eps_p: equal to ``mean_increment`` for ratchetting, much smaller for
        alternating plasticity, closed cycles),
        ``max_alpha`` [-], ``max_residual_von_mises`` [Pa].
    hardening : Hardening
    status : SolverStatus
    cpu_time : float           [s]
    """

    normal: NormalSolution
    x: np.ndarray
    y: np.ndarray
    z: np.ndarray
    plastic_strain: np.ndarray
    equivalent_plastic_strain: np.ndarray
    flow_stress: np.ndarray
    stress: np.ndarray
    residual_stress: np.ndarray
    residual_displacement: np.ndarray
    history: dict
    passes: dict
    hardening: Hardening
    status: SolverStatus = field(default_factory=SolverStatus)
    cpu_time: float = 0.0

    @property
    def plastic_zone_depth(self) -> float:
        """Deepest cell centre [m] with plastic strain (0 if none)."""
        k = np.flatnonzero(self.equivalent_plastic_strain.max(axis=(0, 1)) > 0)
        return float(self.z[k[-1]]) if k.size else 0.0

    def to_xarray(self):
        """Plastic strain, hardening state, stresses and the surface as an
        :class:`xarray.Dataset` with units; the surface figures as attributes."""
        import xarray as xr
        d3 = ("x", "y", "z")
        data = {}
        for i, c in enumerate(COMPONENTS):
            data[f"plastic_strain_{c}"] = (d3, self.plastic_strain[i],
                                           {"units": "1", "long_name": f"plastic strain {c}"})
            data[f"residual_stress_{c}"] = (d3, self.residual_stress[i],
                                            {"units": "Pa", "long_name": f"residual stress {c}"})
            data[f"stress_{c}"] = (d3, self.stress[i],
                                   {"units": "Pa", "long_name": f"stress {c} under the last load"})
        data["equivalent_plastic_strain"] = (d3, self.equivalent_plastic_strain,
                                             {"units": "1", "long_name": "hardening state alpha"})
        data["flow_stress"] = (d3, self.flow_stress, {"units": "Pa",
                                                      "long_name": "von Mises flow stress"})
        data["residual_von_mises"] = (d3, von_mises(self.residual_stress),
                                      {"units": "Pa", "long_name": "von Mises residual stress"})
        data["pressure"] = (("x", "y"), self.normal.pressure, {"units": "Pa"})
        data["residual_displacement"] = (("x", "y"), self.residual_displacement,
                                         {"units": "m", "long_name": "permanent dent, into the body"})
        n = self.normal
        return xr.Dataset(data, coords={
            "x": ("x", self.x, {"units": "m", "long_name": "rolling direction"}),
            "y": ("y", self.y, {"units": "m", "long_name": "lateral"}),
            "z": ("z", self.z, {"units": "m", "long_name": "depth into the plastic body"})},
            attrs={"model": "elastic-plastic (Jacq et al. 2002)", "area_m2": n.area,
                   "pmax_Pa": n.pmax, "penetration_m": n.penetration,
                   "normal_force_N": n.normal_force,
                   "yield_stress_Pa": self.hardening.yield_stress,
                   "hardening_modulus_Pa": self.hardening.modulus,
                   "voce_saturation_Pa": self.hardening.saturation,
                   "voce_rate": self.hardening.rate,
                   "max_equivalent_plastic_strain": float(self.equivalent_plastic_strain.max()),
                   "plastic_zone_depth_m": self.plastic_zone_depth})


class ElasticPlasticContact:
    """An elastic body pressed on an elastic-plastic half-space (module notes).

    Parameters
    ----------
    x, y : ndarray
        Cell centres [m] of the uniform patch grid (rolling, lateral).
    gap : callable (X, Y) -> ndarray
        Undeformed distance [m] at the points X (mx, 1), Y (1, my) of the load's
        frame (min about 0: touching); the load moved by s along x sees gap(x - s, y).
    material : Material
        Its rail (body 1) is the plastic body; the pair's contact modulus gives the
        surface compliance.
    hardening : Hardening
    depth : float
        Depth [m] of the volume grid.
    nz : int
        Number of layers (1 .. 64).
    tol : float
        Relative tolerance of the plastic fixed point: the change of the step's
        plastic strain increment in an iteration, relative to the increment, both in
        the 2-norm over the cells (1e-6 .. 0.1; the contact edge moving by a cell
        leaves changes of a few 1e-3 in single cells next to it, not in the norm).
    maxiter : int
        Limit of fixed-point iterations per load state.
    """

    def __init__(self, x, y, gap, material: Material, hardening: Hardening, depth: float,
                 nz: int = 16, tol: float = 1e-3, maxiter: int = 100):
        x, y = np.asarray(x, float), np.asarray(y, float)
        if x.ndim != 1 or y.ndim != 1 or x.size < 4 or y.size < 4:
            raise InputError(f"elastic-plastic grid of {x.shape} x {y.shape} centres: expected "
                             "at least 4 x 4 cells")
        if isinstance(nz, bool) or not isinstance(nz, (int, np.integer)) or not 1 <= nz <= 64:
            raise InputError(f"elastic-plastic nz = {nz!r}: expected a number of layers in [1, 64]")
        if not (isinstance(depth, (int, float)) and math.isfinite(depth) and depth > 0):
            raise InputError(f"elastic-plastic depth = {depth!r} m: expected a depth > 0")
        if not (1e-6 <= tol <= 0.1):
            raise InputError(f"elastic-plastic tol = {tol!r}: expected a value in [1e-6, 0.1]")
        if not isinstance(hardening, Hardening):
            raise InputError(f"hardening {hardening!r}: expected a Hardening")
        (E1, nu1), _ = material.bodies
        self.x, self.y, self.gap, self.hardening = x, y, gap, hardening
        self.E, self.nu, self.mu = float(E1), float(nu1), float(E1) / (2.0 * (1.0 + nu1))
        self.tol, self.maxiter = float(tol), int(maxiter)
        self.grid = VolumeGrid(x=x, y=y, dz=float(depth) / int(nz), nz=int(nz))
        self.dx, self.dy = float(x[1] - x[0]), float(y[1] - y[0])
        self.influence = EigenstrainInfluence(self.grid, self.E, self.nu)
        self._op = normal_operator(x.size, y.size, self.dx, self.dy, material.contact_modulus)
        shape = self.grid.shape
        self.eps_p = np.zeros((6,) + shape)
        self.alpha = np.zeros(shape)
        self.residual = np.zeros((6,) + shape)
        self.dent = np.zeros((x.size, y.size))
        self.stress = np.zeros((6,) + shape)
        self.pressure = np.zeros((x.size, y.size))
        self.approach = 0.0
        self.ok = True
        self.history = {k: [] for k in ("force", "x_shift", "pass", "area", "pmax",
                                        "penetration", "iterations", "plastic_increment")}
        self.passes = {k: [] for k in ("plastic_increment", "mean_increment", "net_increment",
                                       "max_alpha", "max_residual_von_mises")}
        self._pass = 0
        self._cpu = 0.0

    def _surface(self, force, h, p0):
        """Pressure [Pa] and approach [m] carrying ``force`` on the gap h."""
        if force <= 0:
            return np.zeros_like(h), 0.0, True
        dA = self.dx * self.dy
        p, app, _, ok = polonsky_keer(self._op, h, dA, force=force, tol=1e-7, maxiter=3000,
                                      p0=p0 if p0 is not None and p0.max() > 0 else None)
        return p, app, ok

    def load(self, force: float, x_shift: float = 0.0) -> int:
        """Bring the contact to the normal force [N] with the load at x_shift [m]
        from the committed state (one load state, Jacq's fixed point); commits it.
        Returns the number of iterations."""
        if not (math.isfinite(force) and force >= 0):
            raise InputError(f"elastic-plastic normal force {force!r} N: expected >= 0")
        t0 = time.perf_counter()
        h0 = self.gap((self.x - x_shift)[:, None], self.y[None, :])
        z = self.grid.z
        de = np.zeros_like(self.eps_p)
        p = self.pressure
        sig_r, dent = self.residual, self.dent
        it, ok = 0, True
        accel = _Anderson()
        for it in range(1, self.maxiter + 1):
            p, app, good = self._surface(force, h0 + dent, p)
            ok &= good
            sig_e = stresses_on_grid(self.x, self.y, p, depths=z, poisson=self.nu) \
                if force > 0 else np.zeros_like(self.eps_p)
            T = sig_e + sig_r + 2.0 * self.mu * de
            new, _ = _return_map(T, self.alpha, self.hardening, self.mu)
            change = float(np.linalg.norm(new - de))
            scale = float(np.linalg.norm(new))
            de = accel(de, new) if change > self.tol * max(scale, 1e-12) else new
            sig_r, dent = self.influence(self.eps_p + de) if scale > 0 or change > 0 \
                else (self.residual, self.dent)
            if change <= self.tol * max(scale, 1e-12):
                p, app, good = self._surface(force, h0 + dent, p)
                ok &= good
                break
        else:
            ok = False
            log.info("elastic-plastic contact: no fixed point in %d iterations", self.maxiter)
        sig_e = stresses_on_grid(self.x, self.y, p, depths=z, poisson=self.nu) \
            if force > 0 else np.zeros_like(self.eps_p)
        dalpha = np.sqrt(2.0 / 3.0 * np.tensordot(_W, de * de, axes=1))
        self.eps_p = self.eps_p + de
        self.alpha = self.alpha + dalpha
        self.residual, self.dent = sig_r, dent
        self.stress = sig_e + sig_r
        self.pressure, self.approach = p, app
        self.ok &= ok
        dA = self.dx * self.dy
        for k, v in (("force", force), ("x_shift", x_shift), ("pass", self._pass),
                     ("area", float((p > 0).sum() * dA)), ("pmax", float(p.max())),
                     ("penetration", float(app)), ("iterations", it),
                     ("plastic_increment", float(dalpha.max()))):
            self.history[k].append(v)
        self._cpu += time.perf_counter() - t0
        return it

    def ramp(self, force: float, steps: int = 4, x_shift: float = 0.0):
        """Load from zero to ``force`` [N] in ``steps`` equal steps."""
        if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 1:
            raise InputError(f"elastic-plastic load steps = {steps!r}: expected an integer >= 1")
        for k in range(1, steps + 1):
            self.load(force * k / steps, x_shift)

    def run_passes(self, force: float, passes: int, shifts=(0.0,), steps: int = 4):
        """``passes`` passes of the load: ramped to ``force`` [N] at shifts[0], moved
        through the shifts [m] along x, unloaded; per pass the largest increment of
        the equivalent plastic strain (shakedown: it goes to zero; ratchetting: it
        stays, and so does the net strain of a pass) is recorded in :attr:`passes`."""
        if isinstance(passes, bool) or not isinstance(passes, (int, np.integer)) or passes < 1:
            raise InputError(f"elastic-plastic passes = {passes!r}: expected an integer >= 1")
        shifts = np.atleast_1d(np.asarray(shifts, float))
        first = None
        for _ in range(int(passes)):
            self._pass += 1
            a0, e0 = self.alpha.copy(), self.eps_p.copy()
            self.ramp(force, steps, float(shifts[0]))
            for s in shifts[1:]:
                self.load(force, float(s))
            self.load(0.0, float(shifts[-1]))
            inc = self.alpha - a0
            if first is None:
                first = inc > 0
            self.passes["plastic_increment"].append(float(inc.max()))
            self.passes["mean_increment"].append(float(inc[first].mean()) if first.any() else 0.0)
            de = self.eps_p - e0
            net = np.sqrt(2.0 / 3.0 * np.tensordot(_W, de * de, axes=1))
            self.passes["net_increment"].append(float(net[first].mean()) if first.any() else 0.0)
            self.passes["max_alpha"].append(float(self.alpha.max()))
            self.passes["max_residual_von_mises"].append(float(von_mises(self.residual).max()))

    def result(self) -> ElasticPlasticResult:
        """The committed state as an :class:`ElasticPlasticResult`."""
        p = self.pressure
        dA = self.dx * self.dy
        status = SolverStatus(True, "", int(sum(self.history["iterations"]))) if self.ok else \
            SolverStatus.failed("elastic-plastic contact: a load state did not converge",
                                int(sum(self.history["iterations"])))
        normal = NormalSolution(model="elastic-plastic", x=self.x, y=self.y, pressure=p,
                                contact=p > 0, area=float((p > 0).sum() * dA),
                                pmax=float(p.max()), penetration=float(self.approach),
                                normal_force=float(p.sum() * dA), status=status)
        return ElasticPlasticResult(
            normal=normal, x=self.x, y=self.y, z=self.grid.z, plastic_strain=self.eps_p.copy(),
            equivalent_plastic_strain=self.alpha.copy(),
            flow_stress=self.hardening.flow_stress(self.alpha), stress=self.stress.copy(),
            residual_stress=self.residual.copy(), residual_displacement=self.dent.copy(),
            history={k: list(v) for k, v in self.history.items()},
            passes={k: list(v) for k, v in self.passes.items()}, hardening=self.hardening,
            status=status, cpu_time=self._cpu)


def patch_gap(geometry):
    """The undeformed distance of a patch as a callable gap(X, Y) [m] of
    :class:`ElasticPlasticContact`: the geometry layer's exact gap where it has one
    (plus its approach: touching at 0), else its curvatures A x^2 + B y^2."""
    if getattr(geometry, "gap_function", None) is not None and geometry.extent is not None:
        from ..normal.potential_area import own_gap
        app = float(geometry.approach)
        return lambda X, Y: own_gap(geometry, X.ravel(), Y.ravel()) + app
    A, B = geometry.curvatures
    return lambda X, Y: A * X * X + B * Y * Y


@dataclass(frozen=True)
class ElasticPlasticOptions:
    """The model's settings (``[plasticity] model = "elastic-plastic"`` of a case).

    Attributes
    ----------
    hardening : Hardening        default :data:`MN13`
    grid : (mx, my)              surface cells (default 32 x 32)
    layers : int                 cells in depth nz (default 16)
    extent : float               the grid's half-widths over the elastic contact's (2)
    depth : float                the volume's depth over the elastic contact's
                                 equivalent radius sqrt(a b) (3)
    load_steps : int             load steps of a pass (4)
    passes : int                 passes of the load; all but the last unloaded (1)
    tol : float                  tolerance of the plastic fixed point (1e-3)
    """

    hardening: Hardening = MN13
    grid: tuple = (32, 32)
    layers: int = 16
    extent: float = 2.0
    depth: float = 3.0
    load_steps: int = 4
    passes: int = 1
    tol: float = 1e-3

    def __post_init__(self):
        g = self.grid
        if not (isinstance(g, tuple) and len(g) == 2 and all(
                isinstance(v, (int, np.integer)) and not isinstance(v, bool) and 4 <= v <= 256
                for v in g)):
            raise InputError(f"elastic-plastic grid = {g!r}: expected two cell counts in [4, 256]")
        for name, lo, hi in (("layers", 1, 64), ("load_steps", 1, 100), ("passes", 1, 1000)):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not lo <= v <= hi:
                raise InputError(f"elastic-plastic {name} = {v!r}: expected an integer in "
                                 f"[{lo}, {hi}]")
        if not (1.0 < self.extent <= 10.0 and 0.1 <= self.depth <= 20.0):
            raise InputError(f"elastic-plastic extent = {self.extent!r}, depth = {self.depth!r}:"
                             " expected extent in (1, 10] and depth in [0.1, 20]")
        if not 1e-6 <= self.tol <= 0.1:
            raise InputError(f"elastic-plastic tol = {self.tol!r}: expected a value in "
                             "[1e-6, 0.1]")


def solve_elastic_plastic(geometry, material: Material, normal_force: float,
                          options: ElasticPlasticOptions = ElasticPlasticOptions()
                          ) -> ElasticPlasticResult:
    """Elastic-plastic contact of one patch under a normal force (module notes).

    The elastic solution of the exact normal model fixes the grid: centred on its
    contact, ``options.extent`` times the contact's half-widths on each side,
    ``options.grid`` cells; the volume grid ``options.depth`` times its equivalent
    radius sqrt(a b) deep in ``options.layers`` layers.

    Parameters
    ----------
    geometry : ContactGeometry        the patch (exact gap or curvatures)
    material : Material               rail = the plastic body
    normal_force : float              [N]
    options : ElasticPlasticOptions

    Returns
    -------
    ElasticPlasticResult
    """
    from ..normal.base import make_grid
    from ..normal.exact import ExactNormalModel
    if not (isinstance(normal_force, (int, float)) and math.isfinite(normal_force)
            and normal_force > 0):
        raise InputError(f"elastic-plastic normal force {normal_force!r} N: expected > 0")
    if not isinstance(options, ElasticPlasticOptions):
        raise InputError(f"elastic-plastic options {options!r}: expected ElasticPlasticOptions")
    o = options
    extent, grid, nz, steps, passes = o.extent, o.grid, o.layers, o.load_steps, o.passes
    el = ExactNormalModel().solve(geometry, material, normal_force=normal_force)
    ii, jj = np.nonzero(el.contact)
    x0, x1 = el.x[ii.min()] - 0.5 * el.dx, el.x[ii.max()] + 0.5 * el.dx
    y0, y1 = el.y[jj.min()] - 0.5 * el.dy, el.y[jj.max()] + 0.5 * el.dy
    ex, ey = 0.5 * (x1 - x0), 0.5 * (y1 - y0)
    x, y = make_grid(extent * ex, extent * ey, grid, center=(0.5 * (x0 + x1), 0.5 * (y0 + y1)))
    contact = ElasticPlasticContact(x, y, patch_gap(geometry), material, o.hardening,
                                    o.depth * math.sqrt(ex * ey), nz, o.tol)
    if passes > 1:
        contact.run_passes(normal_force, passes - 1, steps=steps)
        contact._pass += 1
    contact.ramp(normal_force, steps)
    return contact.result()


__all__ = ["ElasticPlasticContact", "ElasticPlasticResult", "ElasticPlasticOptions",
           "Hardening", "MN13",
           "solve_elastic_plastic", "patch_gap"]
