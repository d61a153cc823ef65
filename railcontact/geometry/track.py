"""Wheelset and track: how the profiles are placed.

Track frame (CONTACT's convention, see ``docs/conventions.md``): x along the track
in the running direction, y to the right, z down; origin on the track centre line
in the track plane (the plane through the rail tops).

Each side is computed in a *side frame* whose lateral axis points to the field
side: the right side's frame is the track frame, the left side's is its mirror
image (y -> -y).  Wheel and rail profiles are given for a right body (y positive to
the field side), so the same profile serves both sides.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache
from types import MappingProxyType

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from ..core.errors import InputError, ProfileError
from ..profiles.profile import Profile

SIDES = ("left", "right")


def _check(name, value, lo, hi, unit):
    if not (isinstance(value, (int, float)) and math.isfinite(value) and lo <= value <= hi):
        raise InputError(f"{name} = {value!r}: expected a value in [{lo:g}, {hi:g}] {unit}")


@dataclass
class Track:
    """Straight track with two rails.

    Parameters
    ----------
    rail_right, rail_left : Profile
        Rail profiles as mounted (inclination applied), right-rail convention;
        ``rail_left`` defaults to ``rail_right``.
    gauge : float
        Track gauge [m] between the gauge faces (default 1.435).
    gauge_height : float
        Depth [m] below the rail top where the gauge is measured (default 0.014).
    rail_offsets : dict, optional
        ``{"left": o, "right": o}``: lateral positions [m] of the rail-profile origins
        in the side frames, instead of placing the rails by the gauge (worn rails stay
        where the new ones were: the new track's ``rail_offset`` of each side).
    gauge_rule : {"profile", "contact"}
        Where the gauge point of a rail placed by the gauge lies: where the profile's
        z(y) crosses the gauge height (railcontact's), or CONTACT's rule on the
        spline along the points' chord length (:func:`contact_gauge_point`; the
        case's ``track.gauge_point``, :class:`railcontact.cases.rules.ContactRules`).

    A track is not changed after it is built: assigning an attribute raises
    :class:`~railcontact.core.errors.InputError` (the rails' offsets are placed when
    it is built, and the compiled search keeps its pass profiles by the track's
    identity, :func:`railcontact.geometry.search.find_contact`); build a new one,
    e.g. ``dataclasses.replace(track, gauge=1.432)``.
    """

    rail_right: Profile
    rail_left: Profile | None = None
    gauge: float = 1.435
    gauge_height: float = 0.014
    rail_offsets: dict | None = None
    gauge_rule: str = "profile"
    _offsets: dict = field(init=False, repr=False, default_factory=dict)

    def __post_init__(self) -> None:
        if self.rail_left is None:
            self.rail_left = self.rail_right
        _check("track.gauge", self.gauge, 0.1, 2.0, "m")       # 0.1: scaled rigs
        _check("track.gauge_height", self.gauge_height, 0.0, 0.05, "m")
        if self.gauge_rule not in ("profile", "contact"):
            raise InputError(f"track.gauge_point = {self.gauge_rule!r}: expected 'profile' or "
                             "'contact'")
        for side in SIDES:
            rail = self.rail(side)
            if rail.kind != "rail":
                raise ProfileError(f"{side} rail profile {rail.name!r} is a wheel profile")
            if self.rail_offsets is not None:
                _check(f"track.rail_offsets[{side!r}]", self.rail_offsets.get(side), 0.05,
                       1.0, "m")
                self._offsets[side] = float(self.rail_offsets[side])
            else:
                self._offsets[side] = self.gauge / 2.0 - self.gauge_point(rail)
        if self.rail_offsets is not None:       # read-only, as the offsets placed from it
            object.__setattr__(self, "rail_offsets", MappingProxyType(dict(self.rail_offsets)))
        object.__setattr__(self, "_built", True)

    def __getstate__(self) -> dict:
        # (a read-only mapping does not pickle: its dict travels, e.g. to Dask workers)
        state = dict(self.__dict__)
        if state.get("rail_offsets") is not None:
            state["rail_offsets"] = dict(state["rail_offsets"])
        return state

    def __setstate__(self, state: dict) -> None:
        if state.get("rail_offsets") is not None:
            state = {**state, "rail_offsets": MappingProxyType(dict(state["rail_offsets"]))}
        self.__dict__.update(state)

    def __setattr__(self, name, value) -> None:
        # built once: the offsets and the search memos' pass profiles are this track's
        if self.__dict__.get("_built"):
            raise InputError(f"Track.{name} = {value!r}: a Track is not changed after it is "
                             f"built (its rail offsets and the contact search's profiles "
                             f"are kept by it); build a new one, e.g. "
                             f"dataclasses.replace(track, {name}=...)")
        object.__setattr__(self, name, value)

    def __delattr__(self, name) -> None:
        raise InputError(f"del Track.{name}: a Track is not changed after it is built; "
                         "build a new one")

    def rail(self, side: str) -> Profile:
        return self.rail_right if side == "right" else self.rail_left

    def gauge_point(self, rail: Profile) -> float:
        """Lateral position [m] of the gauge point in rail-profile coordinates, by the
        track's ``gauge_rule``."""
        if self.gauge_rule == "contact":
            return contact_gauge_point(rail, float(self.gauge_height))
        return _gauge_point(rail, self.gauge_height)

    def rail_offset(self, side: str) -> float:
        """Lateral position [m] of the rail-profile origin in the side frame."""
        return self._offsets[side]


@lru_cache(maxsize=64)
def _gauge_point(rail: Profile, gauge_height: float) -> float:
    """:meth:`Track.gauge_point`, once per rail profile (profiles compare by identity
    and are not changed after construction) and gauge height."""
    top_y = float(rail.y[np.argmin(rail.z)])
    z_top = float(np.min(rail.z))
    zg = z_top + gauge_height
    yy = np.linspace(rail.y_min, top_y, 4000)
    below = rail.z_at(yy) >= zg
    if not np.any(below):
        # the gauge side ends above the gauge height (a gauge face whose head overhangs
        # it, seen from above): its leftmost point, as CONTACT takes the leftmost
        # point above the gauge height
        if rail.y_min < top_y and np.isfinite(rail.z_at(rail.y_min)):
            return float(rail.y_min)
        raise ProfileError(f"rail profile {rail.name!r} does not reach {gauge_height * 1e3:.1f}"
                           " mm below its top on the gauge side; cannot place it by gauge")
    i = np.flatnonzero(below)[-1]
    return brentq(lambda t: float(rail.z_at(t)) - zg, yy[i], yy[i + 1])



def contact_gauge_point(rail: Profile, gauge_height: float) -> float:
    """Lateral position [m] of the gauge point by CONTACT's rule (its source
    ``m_wr_profiles.f90``, ``find_gauge_meas_pt``; user guide, "Track and roller
    geometry", GAUGHT): on the rail's
    parametric spline through its points (:attr:`Profile.chord_spline`, y and z
    cubic in the chord length), the head's top z_min is the spline's lowest point;
    of the points on the gauge side before the top that lie within
    ``gauge_height`` [m] of it, the one with the smallest y decides: the first of
    them, and the gauge point is where the spline crosses z_min + gauge_height
    before it; another (a face that undercuts), and it is the spline's smallest y
    between the first and the top; the first point of the profile, and it is that
    point.

    railcontact's own rule (:meth:`Track.gauge_point`) crosses the same height on
    the function z(y) through the points: on a steep gauge face with points some
    0.2 mm apart the two differ by a fraction of a micrometre (UIC60 of the
    Manchester benchmark: 0.32 um), which moves every flange contact by that much
    across the track (CONTACT's inputs take this rule:
    :mod:`railcontact.contact_inp.mapping`)."""
    cs = rail.chord_spline
    s, y, z = cs.s, cs.y, cs.z
    # the spline's top: the lowest z, refined in the interval around the lowest point
    i = int(np.argmin(z))
    lo, hi = s[max(i - 1, 0)], s[min(i + 1, s.size - 1)]
    t = np.linspace(lo, hi, 2001)
    zt = cs.point(t)[1]
    j = int(np.argmin(zt))
    r = minimize_scalar(lambda u: float(cs.point(u)[1]), method="bounded",
                        bounds=(t[max(j - 1, 0)], t[min(j + 1, t.size - 1)]),
                        options={"xatol": 1e-13})
    s_top, z_min = float(r.x), float(r.fun)
    within = np.flatnonzero((s < s_top) & (z - z_min <= gauge_height))
    if within.size == 0 or within[np.argmin(y[within])] == 0:
        return float(y[0])
    first, left = int(within[0]), int(within[np.argmin(y[within])])
    zg = z_min + gauge_height
    if left == first:
        if first == 0:
            return float(y[0])
        u = brentq(lambda v: float(cs.point(v)[1]) - zg, s[first - 1], s[first], xtol=1e-14)
        return float(cs.point(u)[0])
    # an undercut face: the smallest y of the spline between the first point within
    # the height and the top
    t = np.linspace(s[first], s_top, 20 * (int(np.searchsorted(s, s_top)) - first + 1))
    j = int(np.argmin(cs.point(t)[0]))
    r = minimize_scalar(lambda u: float(cs.point(u)[0]), method="bounded",
                        bounds=(t[max(j - 1, 0)], t[min(j + 1, t.size - 1)]),
                        options={"xatol": 1e-13})
    return float(r.fun)


@dataclass
class Wheelset:
    """Rigid wheelset with two wheels of revolution.

    Parameters
    ----------
    wheel_right, wheel_left : Profile
        Wheel profiles, right-wheel convention (flange at negative y, origin at the
        tape circle); ``wheel_left`` defaults to ``wheel_right``.
    nominal_radius : float
        Radius [m] at the tape circle (default 0.46).
    flange_back_distance : float
        Distance [m] between the flange backs (default 1.360).
    flange_back_position : float
        Lateral position [m] of the flange back in wheel-profile coordinates
        (default -0.070: S1002 tape circle 70 mm from the flange back).
    out_of_round : OutOfRoundWheel, optional
        The wheels' deviation from revolution at their pitch angle
        (:mod:`railcontact.geometry.out_of_round`).
    locus : {"lowest", "contact"}
        The contact locus (:mod:`railcontact.geometry.locus`): each wheel circle's
        lowest point above the rail (default), or CONTACT's, the point whose
        surface normal is perpendicular to the rolling direction (its
        ``locus_prismatic``; the ``.inp`` files' rule).
    """

    wheel_right: Profile
    wheel_left: Profile | None = None
    nominal_radius: float = 0.46
    flange_back_distance: float = 1.360
    flange_back_position: float = -0.070
    #: an out-of-round wheel (``railcontact.geometry.out_of_round.OutOfRoundWheel``,
    #: both wheels alike): its radial deviation enters each patch's gap; None: round
    out_of_round: object | None = None
    locus: str = "lowest"
    #: memo of the contact search by (lateral shift, yaw): its track, the minimum gaps
    #: of both wheels by roll, the last loci's wheel-sample ranges and the last roll
    #: slope, so that successive searches of one case, each starting where the last
    #: ended, do not repeat work (``railcontact.geometry.pose.PoseMemo``)
    gap_memo: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if self.wheel_left is None:
            self.wheel_left = self.wheel_right
        _check("wheel.nominal_radius", self.nominal_radius, 0.02, 1.5, "m")
        _check("wheelset.flange_back_distance", self.flange_back_distance, 0.1, 2.0, "m")
        _check("wheelset.flange_back_position", self.flange_back_position, -0.2, 0.0, "m")
        if self.locus not in ("lowest", "contact"):
            raise InputError(f"wheelset.locus = {self.locus!r}: expected 'lowest' (each wheel "
                             "circle's lowest point) or 'contact' (CONTACT's locus)")
        for side in SIDES:
            w = self.wheel(side)
            if w.kind != "wheel":
                raise ProfileError(f"{side} wheel profile {w.name!r} is a rail profile")

    def __setattr__(self, name, value) -> None:
        # a changed wheelset empties its search memo (the pass profiles, the minimum
        # gaps and the loci's wheel samples are the old wheelset's)
        object.__setattr__(self, name, value)
        memo = self.__dict__.get("gap_memo")
        if memo and name != "gap_memo":
            memo.clear()

    def wheel(self, side: str) -> Profile:
        return self.wheel_right if side == "right" else self.wheel_left

    @property
    def wheel_offset(self) -> float:
        """Lateral distance [m] from the wheelset centre to each wheel-profile origin."""
        return self.flange_back_distance / 2.0 - self.flange_back_position


@dataclass(frozen=True)
class WheelsetPose:
    """Position of the wheelset relative to the track (SI units).

    Attributes
    ----------
    lateral_shift : float   y [m], positive to the right
    vertical : float        z [m], positive down; 0 with the axle at the nominal radius
                            above the track plane
    roll : float            rotation [rad] about +x (right-hand)
    yaw : float             rotation [rad] about +z; positive turns the front to the right
    """

    lateral_shift: float = 0.0
    vertical: float = 0.0
    roll: float = 0.0
    yaw: float = 0.0


def rotation(yaw: float, roll: float) -> np.ndarray:
    """Rotation matrix Rz(yaw) Rx(roll) of the wheelset axes (columns) in the frame."""
    cy, sy, cr, sr = math.cos(yaw), math.sin(yaw), math.cos(roll), math.sin(roll)
    return np.array([[cy, -sy * cr, sy * sr], [sy, cy * cr, -cy * sr], [0.0, sr, cr]])
