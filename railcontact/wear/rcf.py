"""Rolling contact fatigue (RCF) beside wear: damage measures of a solved patch and
their accumulation along the profiles.

Three measures per patch (docs/wear.md, "Rolling contact fatigue"):

* **surface fatigue index** (Ekberg, Kabo & Andersson 2002, "An engineering model
  for prediction of rolling contact fatigue of railway wheels", Fatigue Fract. Engng
  Mater. Struct. 25(10), 899-909; restated in Ekberg & Kabo 2005, Wear 258,
  1288-1300): FI_surf = f - 2 pi a b k / (3 F_n) = f - k / p0, the
  traction coefficient f = |F_t| / F_n against the shakedown limit of surface
  ratchetting, k the yield stress in shear of the cyclically hardened steel and p0
  the Hertzian peak pressure of the patch's force on its area (p0 = 3 F_n / (2 A),
  for any normal model).  Surface-initiated RCF is predicted where FI_surf > 0;
* **subsurface fatigue index** (the same paper's Dang Van-type criterion):
  FI_sub = tau_eq,a + a_DV sigma_h,max, with tau_eq,a half the largest range of the
  deviatoric stress (sqrt(J2) of the difference of the deviators) met by a material
  point as the patch rolls over it, and sigma_h,max the largest mean stress there
  (tension positive), from the full subsurface stress field of the patch
  (:mod:`railcontact.subsurface`), largest over the lateral positions and depths;
  initiation is predicted where FI_sub exceeds the shear fatigue limit tau_e;
* **WLRM damage** (the Whole Life Rail Model's damage function of T gamma, Burstow
  2003 and 2004, RSSB research programme): per passage, 0 below T gamma = 15 N,
  rising linearly to 1/20000 at 65 N, falling linearly to 0 at 175 N (above it wear
  dominates and removes the initiated cracks); T gamma = frictional power / V of the
  patch (creep forces times creepages, spin included).  The shape (rise, then fall
  as wear takes over) is that of the Network Rail / RSSB T gamma model described in
  "Experience of premium grade rail steels to resist rolling contact fatigue (RCF)
  on GB network", Ironmaking & Steelmaking, doi:10.1179/1743281212Y.0000000042; the
  function is reproduced in Krishna et al. 2022, Railway Engineering Science 30(1),
  doi:10.1007/s40534-021-00253-y.

Parameter values: the defaults k = 300 MPa, a_DV = 1/3, tau_e = 300 MPa and the
damage function's corners (15, 65, 175 N; 1/20000) could NOT be verified against
the text of these sources (issue 31: only their titles, abstracts or introductions
were reachable); none that was read contradicts them.  A second search (branch
lit31) reached no further; the one implementation of the damage function found
(GitHub aliSaleh123/railway_project, crack_initiation/create_di_df.py, no source
given) shares the 65 N peak and the 175 N end but starts at 20 N and peaks at
1.0e-5 per passage.  docs/wear.md ("Sources of the parameters") lists what was
checked.

Along a profile every position covered by a patch's strips takes its measures
(:func:`profile_values`); the WLRM damage and the FI_surf exceedance max(FI_surf, 0)
(railcontact's accumulation of Ekberg's index where it predicts surface initiation)
add up over the passages and wear removes them (:func:`accumulate`); FI_surf and
FI_sub themselves are kept as their largest values.  railcontact assumes the damage
lives in a surface layer of depth d (``layer_depth``, default 0.1 mm) and that
wearing off a depth w removes the fraction w / d of it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np
from numba import njit

from ..core.checks import shown
from ..core.errors import CaseFileError


@dataclass(frozen=True)
class RcfParameters:
    """Parameters of the damage measures (SI units; ``[wear.rcf]`` of a wear scenario).

    Attributes
    ----------
    shear_yield : float
        Yield stress in shear k [Pa] of the cyclically hardened steel, Ekberg, Kabo &
        Andersson (2002)'s k; default 300 MPa for wheel steel (value not verified
        against the paper, see the module docstring).
    tgamma_threshold, tgamma_peak, tgamma_wear : float
        T gamma [N] where the WLRM damage starts (15), peaks (65) and returns to 0
        (175): Burstow's Whole Life Rail Model (RSSB, 2003/2004; values not verified
        against the report, see the module docstring).
    peak_damage : float
        WLRM damage per passage at the peak (1/20000: crack initiation after 20000
        passages at T gamma = 65 N), Burstow (2004); not verified, as above.
    layer_depth : float
        Depth [m] of the surface layer holding the damage, which wear removes in
        proportion (railcontact's assumption; 0.1 mm).
    subsurface : bool
        Compute FI_sub (a subsurface stress field per solved patch; see
        docs/wear.md for its cost).
    dang_van : float
        a_DV, the weight of the mean stress in FI_sub (1/3, Ekberg et al. 2002; not
        verified against the paper).
    fatigue_limit : float
        tau_e [Pa], the shear fatigue limit FI_sub is compared with (default 300 MPa,
        Ekberg et al. 2002's order for wheel steel; not verified against the paper).
    depths : int
        Depths of the subsurface field for FI_sub, from 0 to twice the patch's
        equivalent radius.
    """

    shear_yield: float = 300e6
    tgamma_threshold: float = 15.0
    tgamma_peak: float = 65.0
    tgamma_wear: float = 175.0
    peak_damage: float = 5e-5
    layer_depth: float = 1e-4
    subsurface: bool = False
    dang_van: float = 1.0 / 3.0
    fatigue_limit: float = 300e6
    depths: int = 11

    def __post_init__(self):
        if not (self.shear_yield > 0 and self.fatigue_limit > 0):
            raise CaseFileError(f"wear.rcf: shear_yield = {self.shear_yield!r}, fatigue_limit = "
                                f"{self.fatigue_limit!r}: expected stresses > 0 Pa")
        if not (0 <= self.tgamma_threshold < self.tgamma_peak < self.tgamma_wear):
            raise CaseFileError("wear.rcf: expected 0 <= tgamma_threshold < tgamma_peak < "
                                f"tgamma_wear, got {self.tgamma_threshold!r}, "
                                f"{self.tgamma_peak!r}, {self.tgamma_wear!r}")
        if not (self.peak_damage > 0 and self.layer_depth > 0 and self.depths >= 2):
            raise CaseFileError("wear.rcf: expected peak_damage > 0, layer_depth > 0 m and "
                                "depths >= 2")

    @classmethod
    def from_dict(cls, raw) -> "RcfParameters":
        """From the ``[wear.rcf]`` table (unknown keys and wrong types raise)."""
        if raw is None:
            return cls()
        if not isinstance(raw, dict):
            raise CaseFileError(f"wear.rcf = {shown(raw)}: expected a table")
        known = {f.name: f.type for f in fields(cls)}
        bad = sorted(set(raw) - set(known))
        if bad:
            name = shown(str(bad[0])).strip("'")
            raise CaseFileError(f"unknown key wear.rcf.{name}; expected one of {sorted(known)}")
        out = {}
        for k, v in raw.items():
            if k == "subsurface":
                if not isinstance(v, bool):
                    raise CaseFileError(f"wear.rcf.subsurface = {shown(v)}: expected true or "
                                        "false")
            elif k == "depths":
                if isinstance(v, bool) or not isinstance(v, int):
                    raise CaseFileError(f"wear.rcf.depths = {shown(v)}: expected an integer >= 2")
            elif isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise CaseFileError(f"wear.rcf.{k} = {shown(v)}: expected a number")
            out[k] = v
        return cls(**out)


def surface_fatigue_index(fx, fy, fn, area, shear_yield):
    """Ekberg's surface fatigue index FI_surf = f - k / p0 [-] (arrays broadcast).

    Parameters
    ----------
    fx, fy : creep forces [N];  fn : normal force [N];  area : contact area [m^2]
    shear_yield : k [Pa]
    """
    fn = np.asarray(fn, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        f = np.hypot(fx, fy) / fn
        p0 = 1.5 * fn / np.asarray(area, float)
        return np.where((fn > 0) & (p0 > 0), f - shear_yield / p0, np.nan)


def wlrm_damage(tgamma, params: RcfParameters = RcfParameters()):
    """WLRM damage per passage [-] of T gamma [N] (Burstow 2004; arrays broadcast)."""
    t = np.asarray(tgamma, float)
    t0, t1, t2, pk = (params.tgamma_threshold, params.tgamma_peak, params.tgamma_wear,
                      params.peak_damage)
    rise = pk * (t - t0) / (t1 - t0)
    fall = pk * (t2 - t) / (t2 - t1)
    return np.where((t > t0) & (t <= t1), rise, np.where((t > t1) & (t < t2), fall, 0.0))


@njit(cache=True, nogil=True)
def _fi_sub(sig, a_dv):
    """max over (y, z) of tau_eq,a + a_DV sigma_h,max along x, and where (j, k):
    tau_eq,a = half the largest sqrt(J2) of the difference of two deviators met along
    the rolling line x at (y, z)."""
    _, nx, ny, nz = sig.shape
    best, bj, bk = -np.inf, 0, 0
    dev = np.empty((6, nx))
    for j in range(ny):
        for k in range(nz):
            hmax = -np.inf
            for i in range(nx):
                h = (sig[0, i, j, k] + sig[1, i, j, k] + sig[2, i, j, k]) / 3.0
                hmax = max(hmax, h)
                dev[0, i] = sig[0, i, j, k] - h
                dev[1, i] = sig[1, i, j, k] - h
                dev[2, i] = sig[2, i, j, k] - h
                for c in range(3, 6):
                    dev[c, i] = sig[c, i, j, k]
            r2 = 0.0
            for i1 in range(nx):
                for i2 in range(i1 + 1, nx):
                    d0 = dev[0, i1] - dev[0, i2]
                    d1 = dev[1, i1] - dev[1, i2]
                    d2 = dev[2, i1] - dev[2, i2]
                    d3 = dev[3, i1] - dev[3, i2]
                    d4 = dev[4, i1] - dev[4, i2]
                    d5 = dev[5, i1] - dev[5, i2]
                    j2 = 0.5 * (d0 * d0 + d1 * d1 + d2 * d2) + d3 * d3 + d4 * d4 + d5 * d5
                    r2 = max(r2, j2)
            v = 0.5 * math.sqrt(r2) + a_dv * hmax
            if v > best:
                best, bj, bk = v, j, k
    return best, bj, bk


def subsurface_fatigue_index(normal, tangential, material, params: RcfParameters = RcfParameters(),
                             body: str = "rail") -> dict:
    """Ekberg's subsurface fatigue index of a patch from its full stress field.

    Returns
    -------
    dict with ``fi_sub`` [Pa] (tau_eq,a + a_DV sigma_h,max, largest over the lateral
    positions and depths), ``y`` and ``depth`` [m] where, and ``exceeds``
    (FI_sub > tau_e).
    """
    from ..subsurface import default_depths, subsurface_stresses
    z = default_depths(normal, params.depths)
    ss = subsurface_stresses(normal, tangential, z, material, body)
    v, j, k = _fi_sub(np.ascontiguousarray(ss.sigma), float(params.dang_van))
    return {"fi_sub": float(v), "y": float(ss.y[j]), "depth": float(ss.z[k]),
            "exceeds": bool(v > params.fatigue_limit)}


def patch_measures(normal, tangential, velocity: float, params: RcfParameters,
                   frictional_power: float | None = None) -> tuple:
    """(FI_surf [-], T gamma [N], WLRM damage per passage [-]) of a solved patch (the
    formulas of :func:`surface_fatigue_index` and :func:`wlrm_damage` on scalars);
    ``frictional_power`` [W]: the tangential solution's, when already computed."""
    fn, area = float(normal.normal_force), float(normal.area)
    fi = (math.hypot(tangential.fx, tangential.fy) / fn - params.shear_yield * area / (1.5 * fn)
          if fn > 0 and area > 0 else math.nan)
    power = tangential.frictional_power if frictional_power is None else frictional_power
    tg = float(power) / velocity if velocity > 0 else 0.0
    t0, t1, t2, pk = (params.tgamma_threshold, params.tgamma_peak, params.tgamma_wear,
                      params.peak_damage)
    dmg = (pk * (tg - t0) / (t1 - t0) if t0 < tg <= t1 else
           pk * (t2 - tg) / (t2 - t1) if t1 < tg < t2 else 0.0)
    return fi, tg, dmg


def covered_strips(normal) -> np.ndarray:
    """1.0 on the patch's strips with contact, 0.0 elsewhere."""
    return normal.contact.any(axis=0).astype(float)


def profile_window(geometry, strip_y, values_y, profile, body: str, s_grid) -> tuple:
    """(slice of ``s_grid`` between the first and the last strip, the values there):
    a value per strip placed on a profile's arc length as the wear depth is
    (:func:`railcontact.wear.mapping.profile_depth`: s = s_ref + sgn y_c, sgn = -1 on
    the left side), linear between the strips, not rescaled (a value, not a depth)."""
    y_ref = geometry.y_rail if body == "rail" else geometry.y_wheel
    s_ref = float(profile.arc_length(y_ref))
    sgn = 1.0 if geometry.side != "left" else -1.0
    s = s_ref + sgn * np.asarray(strip_y, float)
    v = np.asarray(values_y, float)
    if sgn < 0:
        s, v = s[::-1], v[::-1]
    i0 = int(np.searchsorted(s_grid, s[0], "left"))
    i1 = int(np.searchsorted(s_grid, s[-1], "right"))
    sl = slice(i0, max(i0, i1))
    return sl, np.interp(s_grid[sl], s, v)


def profile_values(geometry, strip_y, values_y, profile, body: str, s_grid) -> np.ndarray:
    """:func:`profile_window` on the whole grid (0 outside the strips)."""
    out = np.zeros(np.shape(s_grid))
    sl, v = profile_window(geometry, strip_y, values_y, profile, body, s_grid)
    out[sl] = v
    return out


def accumulate(damage, added, wear_depth, layer_depth: float):
    """Damage after a step: the previous damage less the fraction of its surface
    layer worn off (wear_depth / layer_depth, at most all of it), plus the step's."""
    keep = np.clip(1.0 - np.asarray(wear_depth, float) / layer_depth, 0.0, 1.0)
    return np.asarray(damage, float) * keep + np.asarray(added, float)
