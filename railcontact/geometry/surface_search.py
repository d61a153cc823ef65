"""Contact search over the 3-D surfaces of a wheel and of several rails.

Where the rail varies along the track (a crossing, a switch), where several rails
carry one wheel (wing rail and nose, check rail, switch blade and stock rail) or
where the rail is a roller, the contact is no longer found under the axle along a
contact locus: it may lie ahead of or behind the axle, on each rail at another x.
This module searches the surfaces themselves, as CONTACT's brute-force search
(its option D = 5, "grid-based algorithm instead of contact locus"):

1. The wheel (a surface of revolution, with the wheelset's yaw and roll) and each
   placed rail (:class:`railcontact.geometry.surfaces.PlacedRail`) are sampled on
   vertical lines of a grid in (x, y) of the wheel's side frame, at the wheelset
   position s along the track: the vertical gap g = z_rail - z_wheel, negative
   where the surfaces interpenetrate.  A coarse grid (``COARSE``) finds where the
   gap comes within ``CANDIDATE_GAP`` of zero; a fine grid (``FINE``) covers
   those places.
2. Each connected region of g < 0 (8-connected) on a rail is a patch.  Its
   reference point and contact angle are the means over the region weighted with
   g^2 (CONTACT's default "squared weighting", ``compute_wgt_center_2d``): x, y
   and the inclination atan(dz/dy) of the rail surface; the reference point lies
   on the rail surface.
3. The patch's tangent plane is CONTACT's planar contact: x_c = (1, 0, 0),
   t = (0, cos d, sin d), n = (0, -sin d, cos d).  The undeformed distance h(x, y)
   on it is measured along n between the 3-D surfaces (:class:`SurfaceGap`: the
   line through each point of the plane along n is intersected with the rail
   surface and with the wheel's surface of revolution by Newton's method); the
   approach is -min h, the curvatures are the principal curvatures of h at its
   minimum (finite differences; a yawed wheel on a roller turns their axes).
4. Kinematic creepages from the velocities of the wheel and of the rail (a roller
   turns) at the wheel point Q = C + approach n (:func:`creepages`).

Everything is computed in the wheel's side frame (y to the field side, z down);
for a left wheel the pose is mirrored and the results mirrored back, so that
positions, contact angles and creepages are in the track frame of
``docs/conventions.md``.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
from scipy import ndimage

from ..core.errors import ContactNotFoundError, InputError
from ..profiles.profile import Profile
from .contact import ContactGeometry
from .track import rotation

log = logging.getLogger(__name__)

#: coarse search grid (dx, dy) [m]
COARSE = (1.0e-3, 0.4e-3)
class FineMesh(NamedTuple):
    """The fine search grid: spacings ``dx``, ``dy`` [m]; ``aligned``: its x nodes
    at multiples of dx from the wheelset's centre (CONTACT's gap mesh of its
    brute-force search, whose wheel is sampled at slices dx apart through the
    wheel's lowest line), else from the candidate place's coarse node."""

    dx: float
    dy: float
    aligned: bool = False


#: fine search grid (dx, dy) [m] over the candidate places
FINE = FineMesh(0.2e-3, 0.075e-3)


def contact_gap_mesh(nominal_radius: float, dx: float, ds: float) -> FineMesh:
    """CONTACT's gap mesh of its brute-force search (D = 5) for elements DX, DS [m]
    and a wheel of nominal radius r0 [m]: the wheel sampled on nslc slices over
    [-r0/8, r0/8] (over +-0.242 r0 below r0 = 30.5 mm), nslc = round(range /
    (1.5 DX) + 2) made odd, one through its lowest line; laterally 0.75 DS
    (``compute_round_whl``, ``compute_wr_surfc``)."""
    half = nominal_radius / 8.0 if nominal_radius >= 0.0305 else 0.242 * nominal_radius
    nslc = int(math.floor(2.0 * half / (1.5 * dx) + 2.0 + 0.5))
    if nslc % 2 == 0:
        nslc += 1
    return FineMesh(2.0 * half / (nslc - 1), 0.75 * ds, True)
#: a coarse sample whose vertical gap is below this [m] marks a candidate place (the
#: gap between coarse samples can lie lower by about A dx^2/4 + B dy^2/4; docs/tuning.md,
#: section "Geometry search")
CANDIDATE_GAP = 3e-5
#: finite-difference steps (rolling, lateral) [m] of the gap's curvatures
FD_STEP = (1e-3, 1e-4)


@dataclass(frozen=True)
class SurfacePose:
    """Position of a wheelset relative to the track (SI units; track frame).

    Attributes
    ----------
    s : float          position along the track [m] of the wheelset centre
    lateral : float    y [m], positive to the right
    vertical : float   z [m], positive down; 0 with the axle the nominal radius above
                       the track plane (CONTACT's Z_WS)
    roll, yaw : float  [rad], right-hand about +x and +z
    """

    s: float = 0.0
    lateral: float = 0.0
    vertical: float = 0.0
    roll: float = 0.0
    yaw: float = 0.0

    def mirrored(self, side: str) -> "SurfacePose":
        """The pose in the side frame of ``side`` (the left side: y, roll, yaw negated)."""
        if side == "right":
            return self
        return SurfacePose(self.s, -self.lateral, self.vertical, -self.roll, -self.yaw)


@dataclass(frozen=True)
class Motion:
    """Velocities of the wheelset (track frame) for the kinematic creepages.

    Attributes
    ----------
    velocity : float         forward speed V [m/s] of the wheelset along the track
                             (0 on a roller rig, where the rollers turn)
    pitch_velocity : float   angular velocity about the axle [rad/s] (negative for
                             forward rolling)
    lateral_velocity, vertical_velocity : float   [m/s]
    roll_rate, yaw_rate : float                   [rad/s]
    """

    velocity: float = 30.0
    pitch_velocity: float = -30.0 / 0.46
    lateral_velocity: float = 0.0
    vertical_velocity: float = 0.0
    roll_rate: float = 0.0
    yaw_rate: float = 0.0

    def mirrored(self, side: str) -> "Motion":
        if side == "right":
            return self
        return Motion(self.velocity, self.pitch_velocity, -self.lateral_velocity,
                      self.vertical_velocity, -self.roll_rate, -self.yaw_rate)


@dataclass
class SurfaceWheel:
    """A wheel of revolution in its wheelset (side frame).

    Parameters
    ----------
    profile : Profile   wheel profile (right-wheel convention)
    nominal_radius : float   radius [m] at the profile origin
    offset : float      lateral distance [m] from the wheelset centre to the profile
                        origin (flange-back distance / 2 - flange-back position)
    deviation : tuple of 6 floats, optional
        The wheel's deviation by flexibility from its design place in the wheelset
        (CONTACT's DXWHL, DYWHL, DZWHL [m], DROLLW, DYAWW, DPITCHW [rad]; side
        frame): the wheel turned about its profile origin by Rz(yaw) Rx(roll)
        Ry(pitch), then displaced.  It moves the wheel's surface only: the wheel's
        velocities stay those of the wheelset's motion about the design axle (the
        deviations' own velocities are not modelled), as CONTACT takes them.
    """

    profile: Profile
    nominal_radius: float = 0.46
    offset: float = 0.75
    deviation: tuple | None = None

    def __post_init__(self):
        if self.profile.kind != "wheel":
            raise InputError(f"profile {self.profile.name!r} is a rail profile; expected a "
                             "wheel profile")
        if not (0.01 <= self.nominal_radius <= 1.5):
            raise InputError(f"wheel nominal radius {self.nominal_radius!r} m: expected a "
                             "value in [0.01, 1.5]")

    def frame(self, pose: SurfacePose):
        """Centre O (side frame) and rotation R of the wheelset (side-frame pose)."""
        O = np.array([0.0, pose.lateral, pose.vertical - self.nominal_radius])
        return O, rotation(pose.yaw, pose.roll)

    def shape_frame(self, pose: SurfacePose):
        """Centre and rotation of the wheel's body of revolution (side frame): the
        wheelset's :meth:`frame`, with the :attr:`deviation` where given (a point p
        of the design wheel, wheelset coordinates, lies at P0 + d + D (p - P0), P0 =
        (0, offset, nominal radius) the profile origin)."""
        O, R = self.frame(pose)
        if not self.deviation:
            return O, R
        dx, dy, dz, droll, dyaw, dpitch = self.deviation
        cp, sp = math.cos(dpitch), math.sin(dpitch)
        D = rotation(dyaw, droll) @ np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
        P0 = np.array([0.0, self.offset, self.nominal_radius])
        return O + R @ (P0 + np.array([dx, dy, dz]) - D @ P0), R @ D

    def intersect(self, pose: SurfacePose, Q0, n, iterations: int = 30):
        """Where the lines Q0 + lam n (Q0 (..., 3), n (3,) or (..., 3), side frame)
        leave the wheel downwards: lam [m] with the point on the wheel surface (the
        intersection below the axle), NaN where a line misses the profile."""
        O, R = self.shape_frame(pose)
        p0 = (np.asarray(Q0, float) - O) @ R              # wheelset coordinates
        m = np.broadcast_to(np.asarray(n, float) @ R, p0.shape)
        r0, off, prof = self.nominal_radius, self.offset, self.profile
        # start: the radius at the line's axial position, below the axle
        t = p0[..., 1] - off
        z0 = prof.z_at(np.clip(t, prof.y_min, prof.y_max))
        rad = r0 + z0
        lam = (np.sqrt(np.maximum(rad * rad - p0[..., 0] ** 2, 0.0)) - p0[..., 2]) / m[..., 2]
        for _ in range(iterations):
            px = p0[..., 0] + lam * m[..., 0]
            pz = p0[..., 2] + lam * m[..., 2]
            yw = p0[..., 1] + lam * m[..., 1] - off
            zw, dzw = prof.z_and_slope(yw)
            rho = np.hypot(px, pz)
            f = rho - (r0 + zw)
            df = (px * m[..., 0] + pz * m[..., 2]) / np.maximum(rho, 1e-12) - dzw * m[..., 1]
            step = f / df
            lam = lam - step
            if np.all(~np.isfinite(step) | (np.abs(step) < 1e-13)):
                break
        px = p0[..., 0] + lam * m[..., 0]
        pz = p0[..., 2] + lam * m[..., 2]
        yw = p0[..., 1] + lam * m[..., 1] - off
        ok = np.isfinite(lam) & (pz > 0) & (yw >= prof.y_min) & (yw <= prof.y_max)
        return np.where(ok, lam, np.nan)

    def profile_coordinates(self, pose: SurfacePose, P):
        """Wheel-profile coordinates (y_w, radius) [m] of side-frame points P (3,)."""
        O, R = self.shape_frame(pose)
        p = (np.asarray(P, float) - O) @ R
        return float(p[1] - self.offset), float(math.hypot(p[0], p[2]))


def _rail_intersect(rail, s0, Q0, n, iterations: int = 30):
    """lam [m] where the lines Q0 + lam n (n with no x component) meet the rail's
    surface of the undeformed distance (track position s0 + x;
    :meth:`railcontact.geometry.surfaces.PlacedRail.gap_height`: a deviated
    roller's under ``ContactRules.roller_turn``)."""
    Q0 = np.asarray(Q0, float)
    s = s0 + Q0[..., 0]
    lam = np.zeros(Q0.shape[:-1])
    for _ in range(iterations):
        y = Q0[..., 1] + lam * n[1]
        z, dz = rail.gap_height(s, y)
        f = Q0[..., 2] + lam * n[2] - z
        df = n[2] - dz * n[1]
        step = f / df
        lam = lam - step
        if np.all(~np.isfinite(step) | (np.abs(step) < 1e-13)):
            break
    return lam


class SurfaceGap:
    """The undeformed distance h(x, y) [m] between a wheel and one rail on the
    tangent plane of a patch: x along the track, y along t (in the side frame's
    lateral sense; the track frame's for ``sign`` = -1), h along n, positive where
    the surfaces are apart (``ContactGeometry.gap_function``)."""

    def __init__(self, wheel: SurfaceWheel, rail, pose: SurfacePose, C, delta: float,
                 sign: float = 1.0):
        self.wheel, self.rail, self.pose = wheel, rail, pose
        self.C = np.asarray(C, float)
        self.delta = float(delta)
        self.t = np.array([0.0, math.cos(delta), math.sin(delta)])
        self.n = np.array([0.0, -math.sin(delta), math.cos(delta)])
        self.sign = float(sign)

    def points(self, x, y):
        """h at the points (x, y) (arrays of one shape)."""
        x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        Q0 = (self.C + x[..., None] * np.array([1.0, 0.0, 0.0])
              + (self.sign * y)[..., None] * self.t)
        lr = _rail_intersect(self.rail, self.pose.s, Q0, self.n)
        lw = self.wheel.intersect(self.pose, Q0, self.n)
        h = lr - lw
        return np.where(np.isfinite(h), h, 1.0)          # no surface: far apart

    def __call__(self, x, y):
        return self.points(x, y)


@dataclass
class SurfacePatch(ContactGeometry):
    """A contact patch found on the 3-D surfaces: :class:`ContactGeometry` and the
    rail it lies on (``rail``: its name; ``rail_index``: its place in the search's
    list of rails), the track position s [m] of its reference point and the
    rail's rolling radius there (a roller's; inf for a rail)."""

    rail: str = ""
    rail_index: int = 0
    s: float = math.nan
    rail_rolling_radius: float = math.inf
    region_cells: int = 0


@dataclass
class SurfaceContact:
    """Result of the 3-D contact search for one wheel at one wheelset position."""

    pose: SurfacePose
    side: str
    patches: list
    min_gap: float = math.nan
    grids: list = field(default_factory=list, repr=False)


def _grid_gap(wheel, rail, pose, xs, ys):
    """Vertical gap g = z_rail - z_wheel [m] on the grid xs x ys (side frame), its
    rail surface height and slope; NaN where a surface is missing."""
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    Q0 = np.stack((X, Y, np.zeros_like(X)), axis=-1)
    zw = wheel.intersect(pose, Q0, np.array([0.0, 0.0, 1.0]))
    zr, dz = rail.height(pose.s + X, Y)
    return zr - zw, zr, dz


def _wheel_span(wheel: SurfaceWheel, pose: SurfacePose):
    """Lateral range [m] of the wheel (side frame) and the x of its lowest line at
    both ends (a yawed wheel's bottom line runs obliquely)."""
    O, R = wheel.shape_frame(pose)
    ends = []
    for yw in (wheel.profile.y_min, wheel.profile.y_max):
        r = wheel.nominal_radius + float(wheel.profile.z_at(yw))
        ends.append(O + R @ np.array([0.0, wheel.offset + yw, r]))
    return ends


def search(wheel: SurfaceWheel, rails: list, pose: SurfacePose, side: str = "right",
           motion: Motion | None = None, x_range: float | None = None,
           coarse=COARSE, fine=FINE, min_cells: int = 1,
           inclination: str = "local", combine_distance: float = 0.0,
           weights: str = "surface") -> SurfaceContact:
    """All contact patches of a wheel on the rails at the wheelset pose ``pose``.

    Parameters
    ----------
    wheel : SurfaceWheel
    rails : list of PlacedRail
        The rails, placed in the wheel's side frame.
    pose : SurfacePose
        Track-frame pose (mirrored here for a left wheel).
    side : {"right", "left"}
    motion : Motion, optional
        Velocities for the kinematic creepages (default: rolling at 30 m/s).
    x_range : float, optional
        Half-length [m] of the search along the track around the wheel's lowest
        line (default 0.15 x the nominal radius: a rail rising 1:10 touches a wheel
        0.1 r ahead of the axle).
    coarse, fine : (dx, dy)
        Spacings [m] of the coarse and fine search grids (``fine`` a
        :class:`FineMesh` whose x nodes may be aligned on the wheelset's centre).
    min_cells : int
        Interpenetration regions of fewer fine cells are dropped.
    inclination : {"local", "wheelset"}
        Where the rail's lateral inclination in the weighted contact angle is
        taken: at each cell of the region (``"local"``, default), or on the
        cross-section at the wheelset's position s for every cell
        (``"wheelset"``: CONTACT's brute-force search, which evaluates the
        inclination on the rail profile at s_ws; the cell's own where that
        section has no surface, an interrupted rail; how far the two differ:
        docs/tuning.md, section "Geometry search").
    combine_distance : float
        Interpenetration regions on one rail whose lateral extents lie closer
        than this [m] (their gap in y, wherever they lie in x) are one patch, as
        CONTACT combines regions closer than D_SEP; 0 (default): every region
        its own patch.
    weights : {"surface", "locus"}
        How a patch's reference point and contact angle weight its
        interpenetration: each fine cell with g^2 (``"surface"``, default:
        CONTACT's brute-force search, D = 5, ``compute_wgt_center_2d``), or each
        lateral line of the grid at its lowest point along x (refined by a
        parabola through its neighbours) with (-g)^2.5 (``"locus"``: CONTACT's
        contact locus, D = 2 and 3, which integrates the squared interpenetration
        of a parabola along x, ``compute_wgt_center_1d``).

    Returns
    -------
    SurfaceContact with the patches (:class:`SurfacePatch`), numbered as CONTACT
    numbers them: from the field side towards the gauge side (by their reference
    points' lateral position), then by x.
    """
    if side not in ("left", "right"):
        raise InputError(f"wheelset.side = {side!r}: expected 'left' or 'right' for a "
                         "contact on rail surfaces")
    if inclination not in ("local", "wheelset"):
        raise InputError(f"inclination = {inclination!r}: expected 'local' or 'wheelset'")
    if weights not in ("surface", "locus"):
        raise InputError(f"weights = {weights!r}: expected 'surface' or 'locus'")
    motion = motion or Motion()
    sp = pose.mirrored(side)
    mo = motion.mirrored(side)
    r0 = wheel.nominal_radius
    xr = 0.15 * r0 if x_range is None else float(x_range)
    e0, e1 = _wheel_span(wheel, sp)
    x_lo, x_hi = min(e0[0], e1[0]) - xr, max(e0[0], e1[0]) + xr
    y_lo, y_hi = min(e0[1], e1[1]), max(e0[1], e1[1])
    patches, grids, gmin = [], [], math.inf
    for ir, rail in enumerate(rails):
        xs = np.arange(x_lo, x_hi + coarse[0], coarse[0])
        ys = np.arange(y_lo, y_hi + coarse[1], coarse[1])
        g, _, _ = _grid_gap(wheel, rail, sp, xs, ys)
        if np.isfinite(g).any():
            gmin = min(gmin, float(np.nanmin(g)))
        cand = np.where(np.isfinite(g), g, 1.0) < CANDIDATE_GAP
        if not cand.any():
            continue
        lab, nlab = ndimage.label(cand, structure=np.ones((3, 3)))
        if combine_distance > 0 and nlab > 1:
            lab = _combine_labels(lab, nlab, ys, combine_distance)
        for sl in ndimage.find_objects(lab):
            if sl is None:
                continue
            i0, i1 = max(sl[0].start - 1, 0), min(sl[0].stop + 1, xs.size)
            j0, j1 = max(sl[1].start - 1, 0), min(sl[1].stop + 1, ys.size)
            if getattr(fine, "aligned", False):
                fx = fine[0] * np.arange(math.ceil(xs[i0] / fine[0]),
                                         math.floor(xs[i1 - 1] / fine[0]) + 1)
            else:
                fx = np.arange(xs[i0], xs[i1 - 1] + 0.5 * fine[0], fine[0])
            fy = np.arange(ys[j0], ys[j1 - 1] + 0.5 * fine[1], fine[1])
            gf, zr, dz = _grid_gap(wheel, rail, sp, fx, fy)
            if inclination == "wheelset":
                _, d0 = rail.height(np.full(fy.shape, sp.s), fy)
                # the local inclination where that section has no surface (a rail
                # interrupted between the wheelset's position and the patch)
                dz = np.where(np.isfinite(d0), d0, dz)
            grids.append((ir, fx, fy, gf))
            inside = np.where(np.isfinite(gf), gf, 1.0) < 0.0
            if not inside.any():
                continue
            lab2, n2 = ndimage.label(inside, structure=np.ones((3, 3)))
            if combine_distance > 0 and n2 > 1:
                lab2 = _combine_labels(lab2, n2, fy, combine_distance)
            for k in range(1, n2 + 1):
                cells = lab2 == k
                if cells.sum() < min_cells:
                    continue
                patches.append(_make_patch(wheel, rail, ir, sp, side, mo,
                                           _FineGrid(fx, fy, gf, zr, dz, fine), cells,
                                           weights))
    # CONTACT's numbering: from the field side towards the gauge side (the side
    # frame's y falling), then along x
    fs = 1.0 if side == "right" else -1.0
    patches.sort(key=lambda p: (-round(fs * float(p.position[1]), 9), p.position[0]))
    patches = _unique(patches)
    return SurfaceContact(pose, side, patches, gmin, grids)


def surface_slip(patch: "SurfacePatch", wheel: SurfaceWheel, rail, motion: Motion, x, y):
    """The rigid slip on the actual surfaces at the points (x, y) of a patch's
    tangent plane (arrays of one shape), CONTACT's option D = 3: the velocity of
    the rail's material relative to the wheel's, over the patch's rolling
    velocity, in the plane's axes (x_c, y_c).  Each body's velocity is that of its
    surface point in the cross-section (perpendicular to its axis) through the
    plane point, where that section comes closest to the other body: the wheel's
    at the point's axial position a, at its radius r0 + z_w(a - offset); a
    roller's at its apex at the point's lateral position; a rail is at rest.
    (The surfaces' curvature along the rolling direction gives the particles that
    pass through the patch no slip in steady rolling; their radii across it do: a
    sphere rolling on a plane brakes by -y^2 / (2 R^2).)  Returns (s_x, s_y) [-]."""
    gap = patch.gap_function
    side = patch.side
    sp = gap.pose
    mo = motion.mirrored(side)
    x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
    Q0 = gap.C + x[..., None] * np.array([1.0, 0.0, 0.0]) + (gap.sign * y)[..., None] * gap.t
    O, R = wheel.frame(sp)
    Os, Rs = wheel.shape_frame(sp)                    # the wheel's surface (deviated)
    p = (Q0 - Os) @ Rs                                # wheel coordinates
    m = gap.n @ Rs                                    # the normal there: the section's
    mm = math.hypot(m[0], m[2])                       # point nearest the rail
    r = wheel.nominal_radius + wheel.profile.z_at(p[..., 1] - wheel.offset)
    pb = np.stack((r * m[0] / mm, p[..., 1], r * m[2] / mm), axis=-1)
    om_w = R @ np.array([mo.roll_rate, mo.pitch_velocity, 0.0]) + np.array([0, 0, mo.yaw_rate])
    v_w = np.array([mo.velocity, mo.lateral_velocity, mo.vertical_velocity]) \
        + np.cross(om_w, Os + pb @ Rs.T - O)
    # a point at x off its section's apex moves across the plane by the body's
    # rotation about the normal (the spin): (omega x d) . t = a (omega . n) for the
    # in-plane offset d = a e_x + b t from the apex
    a_w = Q0[..., 0] - (Os + pb @ Rs.T)[..., 0]
    turn = -a_w * float(om_w @ gap.n)
    if rail.is_roller:
        surf = rail.surface
        rho = surf.rolling_radius(Q0[..., 1] - rail.lateral_position)
        apex = np.stack((np.zeros_like(rho), np.zeros_like(rho), -rho), axis=-1)
        om_r = np.array([0.0, rail.angular_velocity, 0.0])
        v_r = np.cross(om_r, apex)
        turn = turn + (Q0[..., 0] - surf.position) * float(om_r @ gap.n)
    else:
        v_r = np.zeros_like(v_w)
    dv = (v_r - v_w) / patch.velocity
    return dv[..., 0], gap.sign * (dv @ gap.t + turn / patch.velocity)


def midplane_slip(patch: "SurfacePatch", wheel: SurfaceWheel, rail, motion: Motion, x, y,
                  rail_share: float = 0.5):
    """CONTACT's rule for the rigid slip on the actual surfaces (its D = 3,
    ``m_wr_rigslip``; ``ContactRules.surface_slip = "midplane"``), at the points (x,
    y) of a patch's tangent plane (arrays of one shape): each body's velocity at its
    own undeformed surface point on the plane's normal through (x, y) (the wheel's
    rigid-body velocity, a rail at rest, a roller turning about its axis); on a
    track or test rig the contact frame's velocity, the wheelset's forward speed VS
    along x, taken from both; then each body's (x, n) components turned onto the
    direction in the (x, n) plane of the mid-plane velocity (``rail_share`` times the
    rail's plus the rest times the wheel's: (1 - nu_r) G_w / ((1 - nu_r) G_w + (1 -
    nu_w) G_r), 0.5 for one material), the lateral components as they are; the
    difference (rail's minus wheel's) over the rolling velocity V (|VS| on a track or
    test rig, the mean of both bodies' x velocities at the patch's centre on a
    roller rig).

    The turn acts in the (x, n) plane only: for a body moving along x it removes the
    slip of the surfaces' curvature along the rolling direction as
    :func:`surface_slip` does; for a body rolling along a heading turned by the yaw
    psi it leaves a lateral slip of about tan(psi) times the curvature slip along
    the heading (a sphere of radius R yawed by 0.3 rad on a plane: the slip
    (x_h^2 + y_a^2) sin(psi) / (2 R) across x where the exact answer is y_a^2 / (2 R)
    along the heading; x_h, y_a along the heading and the axle).  Returns (s_x, s_y)
    [-]."""
    gap = patch.gap_function
    sp = gap.pose
    mo = motion.mirrored(patch.side)
    x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
    ex, t, n = np.array([1.0, 0.0, 0.0]), gap.t, gap.n
    Q0 = gap.C + x[..., None] * ex + (gap.sign * y)[..., None] * t
    lw = wheel.intersect(sp, Q0, n)
    lw = np.where(np.isfinite(lw), lw, 0.0)
    Qw = Q0 + lw[..., None] * n
    O, R = wheel.frame(sp)
    om_w = R @ np.array([mo.roll_rate, mo.pitch_velocity, 0.0]) + np.array([0, 0, mo.yaw_rate])
    v_w = np.array([mo.velocity, mo.lateral_velocity, mo.vertical_velocity]) \
        + np.cross(om_w, Qw - O)
    if rail.is_roller:
        surf = rail.surface
        Qr = Q0 + _rail_intersect(rail, sp.s, Q0, n)[..., None] * n
        O_r = np.array([surf.position, rail.lateral_position,
                        rail.vertical_position + surf.radius])
        v_r = np.cross(np.array([0.0, rail.angular_velocity, 0.0]), Qr - O_r)
        i0 = np.unravel_index(np.argmin(x * x + y * y), x.shape)
        V = -0.5 * float(v_r[i0][0] + v_w[i0][0])
    else:
        v_r = np.zeros_like(v_w)
        V = mo.velocity
        v_w = v_w - V * ex
        v_r = v_r - V * ex
    sgn = 1.0 if V >= 0 else -1.0
    V = abs(V)
    # components along the plane's axes: x, t (y), n
    comp = lambda v: (v[..., 0], v @ t, v @ n)  # noqa: E731
    (wx, wy, wn), (rx, ry, rn) = comp(v_w), comp(v_r)
    mx = rail_share * rx + (1.0 - rail_share) * wx
    mn = rail_share * rn + (1.0 - rail_share) * wn
    scale = -sgn / np.sqrt(np.maximum(mx * mx + mn * mn, 1e-16 * V * V))
    rx1 = (rx * mx + rn * mn) * scale
    wx1 = (wx * mx + wn * mn) * scale
    V = V if V > 1e-9 else 1.0
    return (rx1 - wx1) / V, gap.sign * (ry - wy) / V


def _combine_labels(lab, n: int, y, distance: float):
    """Labelled regions (``lab``: 1..n on an x-by-y grid with lateral positions
    ``y``) relabelled so that regions whose lateral extents [y_min, y_max] lie
    closer than ``distance`` [m] carry one label (transitively); labels that no
    longer occur leave gaps in 1..n."""
    cols = [np.flatnonzero((lab == k).any(axis=0)) for k in range(1, n + 1)]
    ext = np.array([(y[c[0]], y[c[-1]]) for c in cols])
    order = np.argsort(ext[:, 0])
    new = np.arange(n + 1)
    head, hi = order[0], ext[order[0], 1]
    for k in order[1:]:
        if ext[k, 0] - hi < distance:
            new[k + 1] = head + 1
            hi = max(hi, ext[k, 1])
        else:
            head, hi = k, ext[k, 1]
    return new[lab]


def _unique(patches):
    """Patches found twice (from overlapping candidate boxes) once."""
    out = []
    for p in patches:
        if not any(q.rail_index == p.rail_index and abs(q.position[0] - p.position[0]) < 1e-9
                   and abs(q.position[1] - p.position[1]) < 1e-9 for q in out):
            out.append(p)
    return out


@dataclass(frozen=True)
class _FineGrid:
    """The fine search grid around a candidate region, in track axes."""

    #: (nx,) longitudinal positions [m] relative to the wheelset
    x: np.ndarray
    #: (ny,) lateral positions [m]
    y: np.ndarray
    #: (nx, ny) vertical gap [m] (inf where a surface is missed)
    gap: np.ndarray
    #: (nx, ny) rail surface height [m]
    rail_height: np.ndarray
    #: (nx, ny) lateral inclination dz/dy of the rail surface [-]
    inclination: np.ndarray
    #: (dx, dy) spacing [m]
    spacing: tuple


def _locus_weights(grid: _FineGrid, cells):
    """CONTACT's contact-locus weights of a region (``search``'s ``weights =
    "locus"``): on each lateral line of the grid its lowest point along x, refined
    by the parabola through it and its neighbours in the region; its weight
    (-g)^2.5 (times the x step, for the scale of the 2-D weights).  Returns the
    weights, x, y [m] and the inclination dz/dy there, one per line that
    interpenetrates."""
    g = np.where(cells, grid.gap, np.inf)
    nx = g.shape[0]
    cols = np.flatnonzero(np.isfinite(g).any(axis=0))
    k = np.argmin(g[:, cols], axis=0)
    gm = g[k, cols]
    x = grid.x[k].astype(float)
    dxs = grid.spacing[0]
    km, kp = np.maximum(k - 1, 0), np.minimum(k + 1, nx - 1)
    g0, g1 = g[km, cols], g[kp, cols]
    inner = (k > 0) & (k < nx - 1) & np.isfinite(g0) & np.isfinite(g1)
    g0, g1 = np.where(inner, g0, gm), np.where(inner, g1, gm)
    den = g0 - 2.0 * gm + g1
    ok = den > 0
    frac = np.clip(np.where(ok, 0.5 * (g0 - g1) / np.where(ok, den, 1.0), 0.0), -0.5, 0.5)
    x = x + frac * dxs
    gm = gm - 0.25 * (g0 - g1) * frac
    inc = grid.inclination[k, cols]
    keep = gm < 0.0
    return ((-gm[keep]) ** 2.5 * dxs, x[keep], grid.y[cols][keep], inc[keep])


def _make_patch(wheel, rail, ir, sp, side, mo, grid: _FineGrid, cells, weights="surface"):
    """The patch of one interpenetration region (``cells`` of the fine ``grid``) of
    rail ``ir`` at the wheelset's pose ``sp`` and motion ``mo`` (mirrored to the
    side), its reference point and angle with ``search``'s ``weights``."""
    fx, fy, g, zr, dz, fine = grid.x, grid.y, grid.gap, grid.rail_height, grid.inclination, \
        grid.spacing
    sgn = 1.0 if side == "right" else -1.0
    X, Y = np.meshgrid(fx, fy, indexing="ij")
    lw = _locus_weights(grid, cells) if weights == "locus" else None
    if lw is not None and lw[0].sum() > 0:
        w, xs, ys, incs = lw
        W = w.sum()
        x_c = float((w * xs).sum() / W)
        y_c = float((w * ys).sum() / W)
        a_c = float((w * np.arctan(incs)).sum() / W)
    else:
        w = np.where(cells, g * g, 0.0)
        W = w.sum()
        x_c = float((w * X).sum() / W)
        y_c = float((w * Y).sum() / W)
        a_c = float((w * np.arctan(np.where(cells, dz, 0.0))).sum() / W)
    z_c = float(rail.height(np.array(sp.s + x_c), np.array(y_c))[0])
    C = np.array([x_c, y_c, z_c])
    gap = SurfaceGap(wheel, rail, sp, C, a_c, sign=sgn)
    # the deepest point in plane coordinates, refined by minimising h
    i, j = np.unravel_index(np.argmin(np.where(cells, g, np.inf)), g.shape)
    P = np.array([X[i, j], Y[i, j], zr[i, j]])
    start = np.array([P[0] - x_c, sgn * float((P - C) @ gap.t)])
    xm, ym = _deepest(gap, start, fine)
    A, B, h0 = _principal_curvatures(gap, xm, ym)
    approach = max(-h0, 0.0)
    # extent of the region in plane coordinates
    Pc = np.stack((X[cells], Y[cells], zr[cells]), axis=-1) - C
    yp = sgn * (Pc @ gap.t)
    extent = (float(Pc[:, 0].min() - fine[0]), float(Pc[:, 0].max() + fine[0]),
              float(yp.min() - fine[1]), float(yp.max() + fine[1]))
    # wheel point Q = C + approach n: profile coordinates and radius
    Q = C + approach * gap.n
    yw, r_q = wheel.profile_coordinates(sp, Q)
    zw = float(wheel.profile.z_at(yw))
    y_r = y_c - rail.lateral_position
    rr = rail.rolling_radius(y_r)
    creep, V, dphi = creepages(wheel, rail, sp, mo, Q, gap.t, gap.n, C)
    if side == "left":
        creep = (creep[0], -creep[1], -creep[2])
        dphi = -dphi
    return SurfacePatch(curvatures=(A, max(B, 1e-6)), side=side, contact_angle=sgn * a_c,
                        rolling_radius=wheel.nominal_radius + zw, y_rail=y_r, y_wheel=yw,
                        z_rail=z_c - rail.vertical_position, z_wheel=zw,
                        position=np.array([x_c, sgn * y_c, z_c]), approach=approach,
                        weight=float(W * fine[0] * fine[1]), creepage=creep, velocity=V,
                        extent=extent, gap_function=gap, spin_derivative=dphi,
                        rail=rail.name, rail_index=ir, s=sp.s + x_c, rail_rolling_radius=rr,
                        region_cells=int(cells.sum()))


def _principal_curvatures(gap, x0, y0):
    """Principal curvatures (A, B) [1/m] of the gap at (x0, y0), h ~ A x'^2 + B y'^2
    in its principal axes (A the one nearer the rolling direction: a yawed wheel
    on a roller turns them), and h(x0, y0): finite differences on nine points."""
    hx, hy = FD_STEP
    dx = np.array([0, 1, -1, 0, 0, 1, 1, -1, -1], float)
    dy = np.array([0, 0, 0, 1, -1, 1, -1, 1, -1], float)
    h = gap.points(x0 + hx * dx, y0 + hy * dy)
    hxx = (h[1] + h[2] - 2 * h[0]) / (hx * hx)
    hyy = (h[3] + h[4] - 2 * h[0]) / (hy * hy)
    hxy = (h[5] - h[6] - h[7] + h[8]) / (4 * hx * hy)
    if abs(hxy) <= 1e-6 * (abs(hxx) + abs(hyy)):
        return float(0.5 * hxx), float(0.5 * hyy), float(h[0])
    m = 0.5 * (hxx + hyy)
    r = math.hypot(0.5 * (hxx - hyy), hxy)
    big, small = m + r, m - r
    # the eigenvector of the larger one points along x where hxx > hyy
    return (float(0.5 * big), float(0.5 * small), float(h[0])) if hxx >= hyy else \
        (float(0.5 * small), float(0.5 * big), float(h[0]))


def _deepest(gap, start, fine, steps: int = 8):
    """Where the gap h is least near ``start`` (plane coordinates): Newton steps on
    h's finite-difference gradient and Hessian (nine points each, within the fine
    cell's size), each kept only where it lowers h below the stencil's best point,
    else (and where the Hessian is not positive definite) a move to that point: a
    descent, which stops at the edge of a rail that ends (an interruption) instead
    of stepping off it."""
    x, y = float(start[0]), float(start[1])
    hx, hy = 0.5 * fine[0], 0.5 * fine[1]
    dx = np.array([-1, 0, 1, -1, 0, 1, -1, 0, 1], float)
    dy = np.array([-1, -1, -1, 0, 0, 0, 1, 1, 1], float)
    for _ in range(steps):
        h = gap.points(x + hx * dx, y + hy * dy)
        k = int(np.argmin(h))
        gx = (h[5] - h[3]) / (2 * hx)
        gy = (h[7] - h[1]) / (2 * hy)
        hxx = (h[5] - 2 * h[4] + h[3]) / hx ** 2
        hyy = (h[7] - 2 * h[4] + h[1]) / hy ** 2
        hxy = (h[8] - h[6] - h[2] + h[0]) / (4 * hx * hy)
        det = hxx * hyy - hxy * hxy
        if hxx > 0 and det > 0:
            sx = -(hyy * gx - hxy * gy) / det
            sy = -(hxx * gy - hxy * gx) / det
            # at most two stencil widths per step
            f = min(1.0, 2 * hx / max(abs(sx), 1e-300), 2 * hy / max(abs(sy), 1e-300))
            if float(gap.points(np.array(x + f * sx), np.array(y + f * sy))) <= h[k]:
                x, y = x + f * sx, y + f * sy
                if f == 1.0 and abs(sx) < 1e-3 * hx and abs(sy) < 1e-3 * hy:
                    break
                continue
        if k == 4:
            break
        x, y = x + hx * dx[k], y + hy * dy[k]
    return x, y


def creepages(wheel: SurfaceWheel, rail, pose: SurfacePose, motion: Motion, Q, t, n, C=None):
    """Kinematic creepages (xi, eta, phi [1/m]), rolling velocity V [m/s] and
    d(phi)/d(delta) [1/m] with tangent t and normal n: the rigid slip of the rail
    relative to the wheel, (v_rail(C) - v_wheel(Q)) . (x_c, t) / V and
    (omega_rail - omega_wheel) . n / V, each body's velocity at its own undeformed
    surface point (the wheel's Q = C + approach n, the rail's C, default Q: a
    roller's surface speed is that at its crown radius), with V the mean of both
    bodies' speeds through the contact (the contact moving with the wheelset's
    forward speed along a track, at rest on a roller rig); CONTACT's definitions
    (``docs/conventions.md``) for a rail at rest."""
    C = Q if C is None else C
    O, R = wheel.frame(pose)
    om_w = R @ np.array([motion.roll_rate, motion.pitch_velocity, 0.0]) \
        + np.array([0.0, 0.0, motion.yaw_rate])
    v_ws = np.array([motion.velocity, motion.lateral_velocity, motion.vertical_velocity])
    v_w = v_ws + np.cross(om_w, Q - O)
    if rail.is_roller:
        surf = rail.surface
        O_r = np.array([surf.position, rail.lateral_position,
                        rail.vertical_position + surf.radius])
        om_r = np.array([0.0, rail.angular_velocity, 0.0])
        v_r = np.cross(om_r, np.asarray(C, float) - O_r)
        v_cp = np.zeros(3)
    else:
        om_r = np.zeros(3)
        v_r = np.zeros(3)
        v_cp = np.array([motion.velocity, 0.0, 0.0])
    ex = np.array([1.0, 0.0, 0.0])
    V = 0.5 * (abs(float((v_w - v_cp) @ ex)) + abs(float((v_r - v_cp) @ ex)))
    if not V > 0:
        raise ContactNotFoundError("rolling velocity is zero at the contact: give the "
                                   "wheelset's speed (or the roller's angular velocity)")
    dv = v_r - v_w
    dom = om_r - om_w
    return ((float(dv @ ex / V), float(dv @ t / V), float(dom @ n / V)), V,
            float(-dom @ t / V))
