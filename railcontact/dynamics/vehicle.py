"""Railway vehicle models in track-following coordinates: bodies (:class:`Body`),
suspension elements joining them (:class:`Element`) and the vehicle they make
(:class:`VehicleModel`), with the Manchester benchmark vehicle as a preset.

Every body has the lateral displacement y [m], yaw ψ [rad] and roll φ [rad] (roll a
degree of freedom only where the body says so) relative to the design track at
its own position; the equations that move them, compiled, and the quasi-static
wheel loads and creepages of the patches are in
:mod:`railcontact.dynamics.equations_of_motion`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..core.errors import InputError

#: acceleration of gravity [m/s^2]
G_ACC = 9.81

#: a body in the compiled equations of motion (:meth:`VehicleModel.packed`): mass [kg],
#: yaw and roll inertia [kg m²], longitudinal position x [m], centre of gravity height
#: [m], whether roll is a degree of freedom, roll arm [m] (as :class:`Body`)
BODY = np.dtype([("mass", np.float64), ("yaw_inertia", np.float64),
                 ("roll_inertia", np.float64), ("x", np.float64), ("height", np.float64),
                 ("roll", np.bool_), ("roll_arm", np.float64)], align=True)
#: a suspension element (as :class:`Element`): bodies i, j (-1: the track),
#: attachment offsets a_i, a_j [m] and depths d_i, d_j [m], lateral k_y [N/m], c_y
#: [N s/m], yaw k_yaw [N m/rad], c_yaw [N m s/rad], roll k_roll [N m/rad], c_roll
#: [N m s/rad], and ``bump``: its row in the bump stop tables (-1: none)
ELEMENT = np.dtype([("i", np.int64), ("j", np.int64)]
                   + [(name, np.float64) for name in ("a_i", "a_j", "d_i", "d_j", "k_y", "c_y",
                                                       "k_yaw", "c_yaw", "k_roll", "c_roll")]
                   + [("bump", np.int64)], align=True)
#: a wheelset's load path: its body, the supported mass [kg] and first moment
#: Σ m h [kg m]
WHEELSET = np.dtype([("body", np.int64), ("mass", np.float64), ("moment", np.float64)],
                    align=True)

#: Manchester benchmark vehicle 1 (REFERENCES.md §10; Iwnicki 1998 via secondary
#: sources).  Primary cx, cy are unverified there; no yaw damper is given.
MANCHESTER = {
    "carbody_mass": 32000.0, "carbody_yaw_inertia": 1.97e6, "carbody_roll_inertia": 56800.0,
    "carbody_height": 1.8,
    "frame_mass": 2615.0, "frame_yaw_inertia": 3067.0, "frame_height": 0.6,
    "wheelset_mass": 1813.0, "wheelset_yaw_inertia": 1120.0, "wheel_radius": 0.46,
    "semi_wheelbase": 1.28, "bogie_semi_distance": 9.5,
    "primary_spacing": 1.0, "secondary_spacing": 1.0, "secondary_height": 0.8275,
    "bump_stop_height": 0.65,
    "primary_kx": 31.391e6, "primary_ky": 3.884e6, "primary_cx": 15e3, "primary_cy": 2e3,
    "secondary_kx": 160e3, "secondary_ky": 160e3, "secondary_kz": 430e3,
    "secondary_cy": 32e3, "secondary_cz": 20e3, "secondary_bending": 10.5e3,
    "anti_roll_bar": 940e3, "yaw_damper": 0.0, "yaw_damper_spacing": 1.25,
    "bump_stop_deflection": [0.0, 0.025, 0.030, 0.035, 0.040, 0.045, 0.050, 0.055, 0.060,
                             0.065],
    "bump_stop_force": [0.0, 0.0, 600.0, 1760.0, 3730.0, 6870.0, 11580.0, 17170.0, 29200.0,
                        230000.0],
}


PRESETS = {"manchester": MANCHESTER}


@dataclass
class Body:
    """A rigid body: mass [kg], yaw and roll inertia [kg m²], longitudinal position x
    [m] in the vehicle (+ forward), centre of gravity height [m] above the rails, and
    ``roll_arm`` [m]: height of the centre of gravity above the roll support (gravity
    pendulum term)."""

    name: str
    kind: str
    mass: float
    yaw_inertia: float
    roll_inertia: float = 0.0
    x: float = 0.0
    height: float = 0.0
    roll: bool = False
    roll_arm: float = 0.0


@dataclass
class Element:
    """Suspension element between body ``i`` and body ``j`` (-1: the track).

    Stiffness and damping: lateral k_y [N/m], c_y [N s/m]; yaw k_yaw [N m/rad],
    c_yaw [N m s/rad]; roll k_roll, c_roll.  ``bump`` = (deflection [m], force [N])
    table of a symmetric non-linear lateral stop."""

    name: str
    i: int
    j: int
    a_i: float = 0.0
    a_j: float = 0.0
    d_i: float = 0.0
    d_j: float = 0.0
    k_y: float = 0.0
    c_y: float = 0.0
    k_yaw: float = 0.0
    c_yaw: float = 0.0
    k_roll: float = 0.0
    c_roll: float = 0.0
    bump: tuple | None = None


@dataclass
class VehicleModel:
    """Bodies, suspension elements and the wheelsets' load paths.

    ``wheelsets`` lists (body index, supported mass [kg], supported first moment
    Σ m h [kg m]) front to back.  Build with :meth:`single_wheelset`, :meth:`bogie`,
    :meth:`vehicle` or :meth:`from_parameters`.
    """

    name: str
    bodies: list
    elements: list
    wheelsets: list
    parameters: dict = field(default_factory=dict)

    def __post_init__(self):
        nb = len(self.bodies)
        for b in self.bodies:
            for key in ("mass", "yaw_inertia"):
                v = getattr(b, key)
                if not (math.isfinite(v) and v > 0):
                    raise InputError(f"vehicle body {b.name}.{key} = {v!r}: expected > 0")
            if b.roll and not b.roll_inertia > 0:
                raise InputError(f"vehicle body {b.name}: roll needs roll_inertia > 0")
        for e in self.elements:
            if not (0 <= e.i < nb and -1 <= e.j < nb and e.i != e.j):
                raise InputError(f"suspension element {e.name}: bodies {e.i}, {e.j} out of range")
            for key in ("k_y", "c_y", "k_yaw", "c_yaw", "k_roll", "c_roll"):
                v = getattr(e, key)
                if not (math.isfinite(v) and v >= 0):
                    raise InputError(f"suspension element {e.name}.{key} = {v!r}: expected >= 0")
        if not self.wheelsets:
            raise InputError("vehicle model: no wheelset")

    @property
    def dofs(self) -> int:
        return 3 * len(self.bodies)

    @property
    def total_mass(self) -> float:
        return sum(b.mass for b in self.bodies)

    def body_index(self, kind: str) -> list:
        return [i for i, b in enumerate(self.bodies) if b.kind == kind]

    # ------------------------------------------------------------ constructors
    @classmethod
    def single_wheelset(cls, mass=1813.0, yaw_inertia=1120.0, k_y=7.768e6, k_yaw=62.78e6,
                        c_y=0.0, c_yaw=0.0, wheel_load=75e3, load_height=0.0):
        """One wheelset tied by springs to a frame that follows the track."""
        bodies = [Body("wheelset", "wheelset", mass, yaw_inertia)]
        el = [Element("primary", 0, -1, k_y=k_y, c_y=c_y, k_yaw=k_yaw, c_yaw=c_yaw)]
        M = 2 * wheel_load / G_ACC
        return cls("wheelset", bodies, el, [(0, M, M * load_height)],
                   {"wheel_load": wheel_load})

    @classmethod
    def from_parameters(cls, model: str = "vehicle", parameters: dict | None = None):
        """``model`` in {"wheelset", "bogie", "vehicle"} from a parameter dict
        (missing keys from the Manchester preset)."""
        p = dict(MANCHESTER)
        for k, v in (parameters or {}).items():
            if k not in MANCHESTER:
                raise InputError(f"vehicle parameter {k!r} unknown; expected one of "
                                 f"{sorted(MANCHESTER)}")
            p[k] = v
        for k, v in p.items():
            vals = np.atleast_1d(np.asarray(v, dtype=float))
            if not np.all(np.isfinite(vals)) or np.any(vals < 0):
                raise InputError(f"vehicle parameter {k} = {v!r}: expected values >= 0")
        if model == "vehicle":
            return cls._vehicle(p)
        if model == "bogie":
            return cls._bogie(p)
        if model == "wheelset":
            b = p["primary_spacing"]
            load = (p["carbody_mass"] / 4 + p["frame_mass"] / 2 + p["wheelset_mass"]) \
                * G_ACC / 2
            return cls.single_wheelset(p["wheelset_mass"], p["wheelset_yaw_inertia"],
                                       2 * p["primary_ky"], 2 * p["primary_kx"] * b * b,
                                       2 * p["primary_cy"], 2 * p["primary_cx"] * b * b, load)
        raise InputError(f"vehicle model {model!r}: expected 'wheelset', 'bogie' or 'vehicle'")

    @classmethod
    def bogie(cls, parameters=None):
        return cls.from_parameters("bogie", parameters)

    @classmethod
    def vehicle(cls, parameters=None):
        return cls.from_parameters("vehicle", parameters)

    @staticmethod
    def _primary(p, frame, ws, a):
        b = p["primary_spacing"]
        return Element(f"primary {ws}", ws, frame, 0.0, a, 0.0, 0.0, 2 * p["primary_ky"],
                       2 * p["primary_cy"], 2 * p["primary_kx"] * b * b,
                       2 * p["primary_cx"] * b * b)

    @classmethod
    def _bogie(cls, p):
        lw = p["semi_wheelbase"]
        bodies = [Body("frame", "frame", p["frame_mass"], p["frame_yaw_inertia"], x=0.0,
                       height=p["frame_height"]),
                  Body("wheelset 1", "wheelset", p["wheelset_mass"], p["wheelset_yaw_inertia"],
                       x=lw, height=p["wheel_radius"]),
                  Body("wheelset 2", "wheelset", p["wheelset_mass"], p["wheelset_yaw_inertia"],
                       x=-lw, height=p["wheel_radius"])]
        bs = p["secondary_spacing"]
        yd = p["yaw_damper_spacing"]
        el = [cls._primary(p, 0, 1, lw), cls._primary(p, 0, 2, -lw),
              Element("secondary", 0, -1, k_y=2 * p["secondary_ky"], c_y=2 * p["secondary_cy"],
                      k_yaw=2 * p["secondary_kx"] * bs * bs + p["secondary_bending"],
                      c_yaw=2 * p["yaw_damper"] * yd * yd)]
        half_body = p["carbody_mass"] / 2
        M = p["wheelset_mass"] + (p["frame_mass"] + half_body) / 2
        H = (p["wheelset_mass"] * p["wheel_radius"] + p["frame_mass"] / 2 * p["frame_height"]
             + half_body / 2 * p["carbody_height"])
        return cls("bogie", bodies, el, [(1, M, H), (2, M, H)], p)

    @classmethod
    def _vehicle(cls, p):
        lw, lb = p["semi_wheelbase"], p["bogie_semi_distance"]
        hc = p["carbody_height"]
        bodies = [Body("carbody", "carbody", p["carbody_mass"], p["carbody_yaw_inertia"],
                       p["carbody_roll_inertia"], 0.0, hc, roll=True,
                       roll_arm=hc - p["secondary_height"])]
        el = []
        wsets = []
        M = p["wheelset_mass"] + p["frame_mass"] / 2 + p["carbody_mass"] / 4
        H = (p["wheelset_mass"] * p["wheel_radius"] + p["frame_mass"] / 2 * p["frame_height"]
             + p["carbody_mass"] / 4 * hc)
        bs, yd = p["secondary_spacing"], p["yaw_damper_spacing"]
        bump = (np.asarray(p["bump_stop_deflection"], float),
                np.asarray(p["bump_stop_force"], float))
        for k, xb in enumerate((lb, -lb)):
            f = len(bodies)
            bodies.append(Body(f"frame {k + 1}", "frame", p["frame_mass"],
                               p["frame_yaw_inertia"], x=xb, height=p["frame_height"]))
            for m, xw in enumerate((xb + lw, xb - lw)):
                w = len(bodies)
                bodies.append(Body(f"wheelset {2 * k + m + 1}", "wheelset", p["wheelset_mass"],
                                   p["wheelset_yaw_inertia"], x=xw, height=p["wheel_radius"]))
                el.append(cls._primary(p, f, w, xw - xb))
                wsets.append((w, M, H))
            el.append(Element(f"secondary {k + 1}", 0, f, xb, 0.0,
                              hc - p["secondary_height"], 0.0,
                              2 * p["secondary_ky"], 2 * p["secondary_cy"],
                              2 * p["secondary_kx"] * bs * bs + p["secondary_bending"],
                              2 * p["yaw_damper"] * yd * yd,
                              2 * p["secondary_kz"] * bs * bs + p["anti_roll_bar"],
                              2 * p["secondary_cz"] * bs * bs))
            el.append(Element(f"bump stop {k + 1}", 0, f, xb, 0.0,
                              hc - p["bump_stop_height"], 0.0, bump=bump))
        return cls("vehicle", bodies, el, wsets, p)

    # ------------------------------------------------------------ packing
    def packed(self):
        """Structured arrays for the compiled right-hand side: the bodies
        (:data:`BODY`), the elements (:data:`ELEMENT`), the bump stop tables'
        deflections [m] and forces [N] (one row per stop, padded with the last
        point) and the wheelsets (:data:`WHEELSET`)."""
        bodies = np.array([(b.mass, b.yaw_inertia, b.roll_inertia, b.x, b.height, b.roll,
                            b.roll_arm) for b in self.bodies], dtype=BODY)
        tables = [e.bump for e in self.elements if e.bump is not None]
        npts = max([len(t[0]) for t in tables], default=2)
        bx = np.zeros((max(len(tables), 1), npts))
        bf = np.zeros_like(bx)
        elems = []
        it = 0
        for e in self.elements:
            idx = -1
            if e.bump is not None:
                d, f = (np.asarray(v, dtype=float) for v in e.bump)
                if d.size != f.size or d.size < 2 or np.any(np.diff(d) <= 0) or d[0] != 0:
                    raise InputError(f"bump stop of {e.name}: expected a table of deflections "
                                     "from 0, increasing, with one force each")
                bx[it, :] = d[-1] + np.arange(npts) * 1e-9       # pad with the last point
                bf[it, :] = f[-1]
                bx[it, :d.size], bf[it, :d.size] = d, f
                idx, it = it, it + 1
            elems.append((e.i, e.j, e.a_i, e.a_j, e.d_i, e.d_j, e.k_y, e.c_y, e.k_yaw, e.c_yaw,
                          e.k_roll, e.c_roll, idx))
        wsets = np.array([(w[0], w[1], w[2]) for w in self.wheelsets], dtype=WHEELSET)
        return bodies, np.array(elems, dtype=ELEMENT), bx, bf, wsets
