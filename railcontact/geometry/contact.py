"""Per-patch contact geometry: the :class:`ContactGeometry` result type.

A patch is described in its contact-local frame: origin at the contact reference
point on the undeformed rail surface, x along the track (rolling direction), y
lateral in the tangent plane and n the normal pointing from the wheel into the
rail.  In track coordinates (CONTACT's planar contact approach)

    x_c = (1, 0, 0),   y_c = (0, cos d, sin d),   n = (0, -sin d, cos d),

with d the contact angle (negative on the gauge side of the right rail's tread,
positive on the left rail).  ``gap(x, y)`` is the undeformed distance along n
between the surfaces at the wheelset position of the search: positive is a gap,
negative an interpenetration.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..core.errors import ContactNotFoundError


@dataclass
class ContactGeometry:
    """Geometry of one contact patch (SI units).

    Attributes
    ----------
    side : str or None
        ``"left"``/``"right"`` for wheel-rail contact, None for a bodies case.
    curvatures : (A, B)
        Relative principal curvatures [1/m] of the gap at the point of deepest
        interpenetration, h ~ A x^2 + B y^2.
    contact_angle : float
        d [rad], rotation about +x from track vertical to the contact normal.
    rolling_radius : float
        Wheel radius [m] at the contact point.
    y_rail, y_wheel : float
        Lateral position [m] of the contact reference point in rail and wheel
        profile coordinates (positive to the field side on both sides).
    z_rail, z_wheel : float
        Vertical profile coordinates [m] of the reference point.
    position : ndarray (3,)
        Reference point in track coordinates [m].
    force_curvature : float or None
        Lateral curvature [1/m] of Hertz's force at the approach where it is not
        ``curvatures[1]`` (:func:`railcontact.geometry.wheel_pass.force_curvature`:
        the region's, where the deepest point's is meaningless); the ellipse keeps
        ``curvatures``, at that force.  None: ``curvatures[1]``.
    approach : float
        Geometric interpenetration [m] along n at the search position (0 for rigid).
    weight : float
        Interpenetration weight of the patch, used to combine patches.
    creepage : (xi, eta, phi) or None
        Kinematic creepages [-, -, 1/m] from the wheelset motion.
    velocity : float
        Rolling velocity V [m/s] used for the creepages.
    gap_function : callable (x, y) -> h, optional
        Undeformed distance [m] on the contact-local tangent plane.
    spin_derivative : float
        d(phi)/d(delta) [1/m]: the change of the spin creepage with the contact angle
        of a surface element, (omega . s)/V with s the lateral tangent.  The spin on a
        strip whose local contact angle differs by D from ``contact_angle`` is
        phi cos D + spin_derivative sin D (NaN where unknown).
    local_contact_angle : callable y -> delta(y), optional
        Local contact angle [rad] across the patch (patch coordinate y [m]).
    interaction : tuple of (y, factor)
        For a patch combined from several interpenetration regions
        (``wheelset.combine_distance``): the borders [m] between them (patch
        coordinate y, halfway between their facing ends, ascending) and the factor
        on the mutual influence of the sub-regions across each in the normal problem
        (CONTACT's reduced interaction, ``wheelset.full_interaction_distance``);
        empty for a patch of one region.
    bounds : (y_min, y_max)
        The patch's own band of its tangent plane [m] (patch coordinate y): halfway
        to the interpenetration regions of the other patches on its wheel, whose
        overlap a grid reaching across would count twice (unbounded by default).
    surface : ConformalPatch or None
        The curved reference surface of a conformal patch
        (:mod:`railcontact.geometry.conformal`, ``solver.contact_surface =
        "conformal"``): then the lateral patch coordinate is the arc length s along
        it and ``gap_function`` measures along its normals; None for the planar
        approach (the tangent plane).
    grid_origin : (x0, y0)
        Where the element lattice of a grid given by its element size lies [m],
        patch coordinates: its element centres at (x0 + i dx, y0 + j dy).  Default
        the reference point; a transient CONTACT case's super-grid elsewhere
        (:mod:`railcontact.contact_inp.transient_m1`).
    """

    curvatures: tuple
    side: str | None = None
    contact_angle: float = 0.0
    rolling_radius: float = math.nan
    y_rail: float = math.nan
    y_wheel: float = math.nan
    z_rail: float = math.nan
    z_wheel: float = math.nan
    position: np.ndarray = field(default_factory=lambda: np.full(3, np.nan))
    approach: float = 0.0
    weight: float = 1.0
    creepage: tuple | None = None
    velocity: float = math.nan
    extent: tuple | None = None     # (x_min, x_max, y_min, y_max) of the interpenetration [m]
    gap_function: Callable | None = field(default=None, repr=False)
    spin_derivative: float = math.nan
    local_contact_angle: Callable | None = field(default=None, repr=False)
    bounds: tuple = (-math.inf, math.inf)
    interaction: tuple = ()
    surface: object | None = field(default=None, repr=False)
    force_curvature: float | None = None
    grid_origin: tuple = (0.0, 0.0)

    def foreign(self, y) -> np.ndarray:
        """Whether the points at patch coordinate ``y`` [m] lie outside the patch's
        own band (:attr:`bounds`), in another patch's territory."""
        y = np.asarray(y, dtype=float)
        return (y < self.bounds[0]) | (y > self.bounds[1])

    def spin_at(self, y, phi: float):
        """Spin creepage [1/m] per strip at patch coordinates ``y`` [m] for the patch
        spin ``phi``, from the local contact angle (constant ``phi`` where the patch
        has no profile geometry)."""
        y = np.asarray(y, dtype=float)
        if self.local_contact_angle is None or not math.isfinite(self.spin_derivative):
            return np.full(y.shape, float(phi))
        d = self.local_contact_angle(y) - self.contact_angle
        d = np.where(np.isfinite(d), d, 0.0)          # off the profile: patch value
        return phi * np.cos(d) + self.spin_derivative * np.sin(d)

    @property
    def A(self) -> float:
        return self.curvatures[0]

    @property
    def B(self) -> float:
        return self.curvatures[1]

    def gap(self, x, y):
        """Undeformed distance h(x, y) [m]; quadratic A x^2 + B y^2 if no profiles."""
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        if self.gap_function is None:
            return self.A * x * x + self.B * y * y - self.approach
        return self.gap_function(x, y)

    def to_dict(self) -> dict:
        """Geometry keys of the JSON patch contract (SI units)."""
        d = {"side": self.side, "contact_angle": float(self.contact_angle),
             "rolling_radius": _num(self.rolling_radius), "y_rail": _num(self.y_rail),
             "y_wheel": _num(self.y_wheel), "curvatures": [float(c) for c in self.curvatures],
             "position": [_num(v) for v in self.position], "approach": float(self.approach)}
        if self.creepage is not None:
            d["creepage"] = {"longitudinal": float(self.creepage[0]),
                             "lateral": float(self.creepage[1]),
                             "spin": float(self.creepage[2])}
        return d


def _num(v):
    v = float(v)
    return None if math.isnan(v) else v


def interaction_factor(distance: float, full: float, separate: float) -> float:
    """Factor on the mutual influence of two sub-regions of a combined patch whose
    facing ends lie ``distance`` [m] apart: 1 up to ``full``, 0 from ``separate``,
    ((separate - d) / (separate - full))^0.8 between: CONTACT's rule for combined
    patches (its source, eve70a/CONTACT, ``combine_cpatches``; D_COMB = 4 mm and
    D_SEP = 8 mm; its normal solver scales the sub-patches' mutual influence by it),
    which blends two separate patches continuously into one."""
    if distance <= full:
        return 1.0
    if distance >= separate:
        return 0.0
    return float(((separate - distance) / (separate - full)) ** 0.8)


@dataclass
class WheelsetContact:
    """Result of the contact search for one wheelset position.

    Attributes
    ----------
    pose : WheelsetPose
        Lateral shift and yaw as given; vertical position and roll as solved.
    patches : list of ContactGeometry
        All contact patches, left side first, each side from field to gauge side.
    loci : dict
        The contact locus of each side (side frame).
    loads : dict or None
        The vertical wheel load [N] of each side the search was given, else None.
    interpenetration : dict or None
        The vertical interpenetration [m] of each side the patches were cut at.

    How the solve layer's vertical-force iteration ended is not the search's: see
    :class:`railcontact.cases.equilibrium.VerticalBalance`.
    """

    pose: WheelsetPose
    patches: list
    loci: dict = field(repr=False, default_factory=dict)
    loads: dict | None = None
    interpenetration: dict | None = None

    def side_patches(self, side: str) -> list:
        return [p for p in self.patches if p.side == side]

    def equivalent_point(self, side: str) -> dict:
        """Weighted combination of a side's patches (CONTACT's patch-combination rule).

        Returns rolling radius [m], contact angle [rad] and y positions [m].
        """
        ps = self.side_patches(side)
        if not ps:
            raise ContactNotFoundError(f"no contact on the {side} side")
        w = np.array([p.weight for p in ps])
        w = w / w.sum()
        return {k: float(np.dot(w, [getattr(p, k) for p in ps]))
                for k in ("rolling_radius", "contact_angle", "y_rail", "y_wheel")}
