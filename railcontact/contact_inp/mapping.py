"""From a CONTACT case (:class:`~railcontact.contact_inp.reader.InpCase`) to a
railcontact case file (SI units), and what is not supported.

Module 1 (wheel-rail) becomes a wheel-rail case in CONTACT's single-wheel mode
(``wheelset.side`` and ``wheelset.roll`` given, as CONTACT solves one wheel of a
given roll); module 3 with a Hertzian geometry (IPOTCN = -1 or -3) becomes a
``[bodies]`` case.  Every option is checked: one that railcontact does not
support raises :class:`~railcontact.contact_inp.reader.InpError` naming the case,
the option and what is supported.  ``docs/contact_users.md`` lists the mapping.

Every mapped case follows CONTACT's rules where its discretisation differs from
railcontact's (``solver.rules = "contact"``,
:class:`~railcontact.cases.rules.ContactRules`: its contact locus and angle, its
wheel sampling, KPEC's and FASTSIM's grid rules, its temperature scheme and gauge
point); only the brute-force search (D = 5) sets two rules of its own.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..cases.case import case_from_dict
from ..geometry.turning import default_turn_distance
from ..core.hertz_theory import hertz_curvatures, hertz_ellipse
from ..core.materials import Material
from ..profiles import get_profile
from .reader import WORDS, InpCase, InpError
from .wheel_slices import wheel_table

MM = 1e-3


@dataclass
class MappedCase:
    """A CONTACT case as a railcontact case dictionary (``raw``, for
    :func:`railcontact.cases.case.case_from_dict`) with what the results table needs to
    return to CONTACT's frames (``meta``)."""

    number: int
    module: int
    raw: dict
    meta: dict = field(default_factory=dict)


def _unsupported(case: InpCase, what: str, supported: str, name: str | None = None
                 ) -> InpError:
    """The error for an unsupported option, at the line of the input ``name``."""
    return InpError(f"{case.where(name)}: {what} is not supported; {supported}")


def _need(case, name):
    v = case.values.get(name)
    if v is None:
        raise InpError(f"{case.where()}: {name} is not set (no earlier case gave it)")
    return v


#: CONTACT's deviations by flexibility: the rail's (Z = 2, 3) and the wheel's (E = 4,
#: 5), positions first, then velocities
RAIL_FLEX = ("DYRAIL", "DZRAIL", "DROLLR", "VYRAIL", "VZRAIL", "VROLLR")
WHEEL_FLEX = ("DXWHL", "DYWHL", "DZWHL", "DROLLW", "DYAWW", "DPITCHW", "VXWHL", "VYWHL",
              "VZWHL", "VROLLW", "VYAWW", "VPITCHW")

#: what the unsupported values of the control digits ask for (for the error message)
MEANINGS = {
    "T": {1: "transient shift or rolling, material-fixed grid", 2: "transient rolling"},
    "D": {3: "planar contact with rigid slip on the actual surfaces", 4: "conformal contact",
          5: "brute-force contact search", 6: "brute-force search for steep slopes",
          7: "initial contact point and local angle", 8: "oblique view", 9: "oblique view"},
    "B": {1: "compressible elastic layer", 2: "elliptical traction bound",
          3: "parabolic traction bound", 4: "SDEC"},
    "C": {4: "roller rig, left wheel", 5: "roller rig, right wheel"},
    "F": {1: "total force FX_WS prescribed", 2: "moment MY_WS prescribed",
          3: "massless rail model"},
    "M": {1: "viscoelastic material", 2: "FASTSIM with one given flexibility",
          4: "interfacial layer, plasticity", 6: "original FaStrip", 7: "FaStrip with full "
          "sliding correction"},
    "N": {0: "approach PEN prescribed"},
    "C3": {3: "bilinear tractions", 4: "conformal influence coefficients",
           9: "numerical influence coefficients"},
    "H": {1: "surface temperatures", 3: "surface temperatures"},
    "M2": {2: "proportional damping"},
    "S": {1: "subsurface stresses", 2: "subsurface stresses", 3: "subsurface stresses"},
}


def _digit(case, letter, allowed: dict, label: str):
    """The meaning of a control digit, or the one-line error naming it."""
    v = case.digits[letter]
    if v not in allowed:
        supported = ", ".join(f"{k} ({m})" for k, m in allowed.items())
        what = MEANINGS.get(letter, {}).get(v)
        word = next((w for w in WORDS[case.module] if letter[0] in w), None)
        if letter in ("C3", "M2"):
            word = WORDS[case.module][1]
        raise _unsupported(case, f"{label} = {v}" + (f" ({what})" if what else ""),
                           f"expected {supported}", word)
    return allowed[v]


def _material(case) -> dict:
    nu1, nu2 = _need(case, "POISS1"), _need(case, "POISS2")
    g1, g2 = _need(case, "GG1") * 1e6, _need(case, "GG2") * 1e6      # N/mm^2 -> Pa
    mat = {"young_modulus": 2.0 * g1 * (1.0 + nu1), "poisson_ratio": nu1}
    if (g2, nu2) != (g1, nu1):
        mat.update(wheel_young_modulus=2.0 * g2 * (1.0 + nu2), wheel_poisson_ratio=nu2)
    return mat


def _friction(case) -> dict:
    law = case.values.get("FRICTION_LAW", 0)
    if law != 0:
        raise _unsupported(case, f"FRCLAW = {law} (friction depending on slip velocity or "
                                 "temperature)", "expected L = 0 (Coulomb) or 1 (kept)")
    if case.values.get("NVF", 0):
        rows = case.values["VARFRC_ROWS"]
        if case.digits["V"] == 2:
            # along the track at SVF [mm]: CONTACT interpolates the coefficient (FKIN)
            # at the wheelset's position S_WS, one for every element of the case's
            # patches (m_wr_solvecp: fric_interp at s_ws, then V = 0)
            s0 = case.values.get("S_WS") or 0.0
            return {"coefficient": float(np.interp(s0, [r[0] for r in rows],
                                                   [r[2] for r in rows]))}
        # Coulomb friction: CONTACT uses the kinetic coefficient (FKIN) throughout
        return {"coefficient": rows[0][2],
                "variation": {"angle": [r[0] for r in rows],
                              "coefficient": [r[2] for r in rows]}}
    return {"coefficient": _need(case, "FKIN")}


def _tangential_model(case) -> tuple:
    """(tangential model, options) from the TANG and MATER digits."""
    if case.digits["T"] == 0:
        return "none", {}
    m = _digit(case, "M", {0: "exact", 3: "fastsim", 4: "exact", 5: "fastrip"}, "MATER")
    if case.digits["M"] == 4:
        return m, {"layer": layer_options(case)}
    if m in ("fastsim", "fastrip"):
        k0, alpha = case.values.get("K0_MF"), case.values.get("ALFAMF")
        if k0 is not None and (abs(k0 - 1.0) > 1e-12 or abs(alpha - 1.0) > 1e-12):
            raise _unsupported(case, f"K0_MF = {k0:g}, ALFAMF = {alpha:g} (slope reduction of "
                                     "the modified FASTSIM)", "expected K0_MF = ALFAMF = 1")
    # (FASTSIM: CONTACT's modified FASTSIM, its blended flexibilities and the march
    # over the elements of its grid, by solver.rules = "contact")
    return m, {}


def layer_options(case) -> dict:
    """The interfacial layer of MATER = 4 in SI, the exact tangential model's
    ``layer`` (:class:`~railcontact.core.materials.InterfaceLayer`): GG3 [N/mm^2],
    LAYTHK [mm], TAU_C0 [N/mm^2] (<= 0: no plasticity), K_TAU [N/mm^3]."""
    tau = _need(case, "TAU_C0")
    return {"thickness": _need(case, "LAYTHK") * 1e-3, "shear_modulus": _need(case, "GG3") * 1e6,
            "yield_stress": tau * 1e6 if tau > 0 else math.inf,
            "hardening": _need(case, "K_TAU") * 1e9}


def _check_common(case) -> None:
    d, v = case.digits, case.values
    _digit(case, "T", {0: "frictionless compression", 3: "steady rolling"}, "TANG")
    _digit(case, "S", {0: "no subsurface stresses", 1: "subsurface stresses",
                       2: "subsurface stresses", 3: "subsurface stresses"}, "STRESS")
    _digit(case, "M2", {0: "no damping", 1: "kept"}, "MATER2")
    heat = {0: "no temperatures"} if case.module == 3 else {
        0: "no temperatures", 1: "surface temperatures", 3: "surface temperatures"}
    _digit(case, "H", heat, "HEAT")
    inflcf = {0: "kept", 1: "kept", 2: "elastic half-space"}
    if case.module == 1:
        inflcf[4] = "Blanco's conformal influence coefficients"
    _digit(case, "C3", inflcf, "INFLCF")
    if d["C3"] < 2 and (v.get("INFLCF") or 2) not in inflcf:
        raise _unsupported(case, f"INFLCF = {v['INFLCF']} kept from an earlier case",
                           "expected the elastic half-space (C = 2)"
                           + (" or Blanco's coefficients (C = 4)" if case.module == 1 else "")
                           + " in force", WORDS[case.module][1])
    if d["L"] not in (0, 1):
        _friction(case)
    _digit(case, "L", {0: "Coulomb", 1: "kept"}, "FRCLAW")


def _blanco(case, conformal: bool) -> dict:
    """INFLCF = 4 in module 1: Blanco's conformal influence coefficients
    (``solver.influence = "blanco"``) with IF_METH (0 fast, 1 detailed) and
    VARIANT; the surface inclinations are those of the conformal patch's curved
    reference surface (DISCNS = 4), as CONTACT takes them in module 1."""
    if not conformal:
        raise _unsupported(case, "INFLCF = 4 (Blanco's conformal influence coefficients) "
                                 "on a planar patch", "expected DISCNS = 4 (conformal "
                                 "contact) with it", WORDS[case.module][1])
    meth, var = _need(case, "IF_METH"), _need(case, "VARIANT")
    if meth not in (0, 1):
        raise InpError(f"{case.where('IF_METH')}: IF_METH = {meth}: expected 0 (fast) or "
                       "1 (detailed)")
    if var != 3:
        raise _unsupported(case, f"VARIANT = {var} of Blanco's coefficients", "expected 3 "
                           "(the displacements transformed; variants 1, 2, 4 are not "
                           "implemented)", "VARIANT")
    return {"influence": "blanco",
            "influence_options": {"method": "detailed" if meth == 1 else "fast",
                                  "variant": 3}}


def _thermal(case) -> dict:
    """HEAT = 1, 3 in module 1: ``[thermal]`` from BKTEMP, HEATCP, LAMBDA [W/mm C],
    DENS [kg/mm^3] (one steel for both bodies); CONTACT's scheme by the case's
    ``solver.rules``."""
    v = [[_need(case, f"{k}{b}") for k in ("BKTEMP", "HEATCP", "LAMBDA", "DENS")]
         for b in (1, 2)]
    if v[0][1:] != v[1][1:]:
        raise _unsupported(case, "different HEATCP, LAMBDA or DENS of the two bodies in "
                                 "module 1", "expected one steel for rail and wheel")
    return {"rail_temperature": v[0][0], "wheel_temperature": v[1][0],
            "heat_capacity": v[0][1], "conductivity": v[0][2] * 1e3,
            "density": v[0][3] * 1e9}


def map_case(case: InpCase, profile_dirs=()) -> MappedCase:
    """The railcontact case of one CONTACT case; InpError where it asks for what
    railcontact does not support.  Profile files are looked up next to the input
    file, in the working directory, then in ``profile_dirs``."""
    _check_common(case)
    m = _map_module3(case) if case.module == 3 else _map_module1(case, profile_dirs)
    if (case.values.get("INFLCF") or 2) == 4 and m.raw["solver"].get("influence") != "blanco":
        # (rail surfaces, slices and rigs: planar patches)
        _blanco(case, False)
    if case.digits["H"] in (1, 3):
        m.raw["thermal"] = _thermal(case)
        m.meta["heat"] = True
    m.meta["inp"] = case    # its subsurface points (.subsurface), its tractions (.transient_m1)
    return m


# ------------------------------------------------------------------ module 3
def curvature_from_axis_ratio(A: float, aob: float) -> float:
    """The lateral curvature B [1/m] of a Hertzian contact with curvature A [1/m] in
    the rolling direction whose ellipse has semi-axis ratio a/b = ``aob``
    (CONTACT's IPOTCN = -2): the smaller semi-axis lies along the larger curvature,
    their ratio A_large/A_small = ((E/(1-m)) - K)/(K - E), m = 1 - (small/large)^2
    (Johnson 1985, sec. 4.2)."""
    from ..core.hertz_theory import _ratio
    if not aob > 0:
        raise InpError(f"AOB = {aob!r}: expected a semi-axis ratio a/b > 0")
    small = min(aob, 1.0 / aob)
    r = _ratio(1.0 - small * small)
    return A / r if aob < 1.0 else A * r


def _map_module3(case: InpCase) -> MappedCase:
    d, v = case.digits, case.values
    # (B = 2, 3 with M = 2, 3, 5 of a Hertzian case: module3.solve_fastsim)
    normal = _digit(case, "B", {0: "exact", 5: "kpec", 6: "analyn"}, "BOUND")
    _digit(case, "N", {1: "normal force FN prescribed"}, "NORM")
    _digit(case, "F", {0: "creepages prescribed"}, "FORCE")
    _digit(case, "E", {0: "no extra rigid slip", 1: "kept"}, "EXRHS")
    tang, topt = _tangential_model(case)
    if abs(_need(case, "CHI")) > 1e-12:
        raise _unsupported(case, f"CHI = {v['CHI']:g} rad (rolling direction)", "expected 0")
    if (v.get("SPINXO") or 0.0) != 0.0 or (v.get("SPINYO") or 0.0) != 0.0:
        raise _unsupported(case, "SPINXO, SPINYO (a spin centre off the origin)",
                           "expected them left out")
    ipotcn = _need(case, "IPOTCN")
    mat = _material(case)
    fn = _need(case, "FN")
    es = Material(**mat).contact_modulus
    if ipotcn == -3:
        a, b = v["AA"] * MM, v["BB"] * MM
        A, B = hertz_curvatures(a, b, es, fn)
    elif ipotcn in (-1, -2):
        A = v["A1"] / MM                         # 1/mm -> 1/m
        B = v["B1"] / MM if ipotcn == -1 else curvature_from_axis_ratio(A, v["AOB"])
        h = hertz_ellipse(A, B, es, force=fn)
        a, b = h.a, h.b
    else:
        raise _unsupported(case, f"IPOTCN = {ipotcn}", "expected -1 (curvatures A1, B1), -2 "
                                                      "(A1 and a/b) or -3 (semi-axes AA, BB) of "
                                                      "a Hertzian contact")
    scale = _need(case, "SCALE")
    raw = {"title": f"{case.path.name} case {case.number}", "material": mat,
           "friction": _friction(case),
           "bodies": {"radii": {"wheel_rolling": 1.0 / (2.0 * A),
                                "wheel_lateral": 1.0 / (2.0 * B)},
                      "normal_force": fn, "velocity": _need(case, "VELOC") * MM},
           "creepage": {"longitudinal": _need(case, "CKSI"), "lateral": _need(case, "CETA"),
                        "spin": _need(case, "CPHI") / MM},
           "solver": {"normal": normal, "tangential": tang, "grid": [v["MX"], v["MY"]],
                      # the potential contact area is SCALE times the ellipse
                      "normal_options": ({"margin": scale - 1.0} if normal == "exact"
                                         else {}),
                      "tangential_options": topt, "rules": "contact"}}
    return MappedCase(case.number, 3, raw, {"module": 3, "semi_axes_mm": (a / MM, b / MM)})


# ------------------------------------------------------------------ module 1
def _profile_path(case: InpCase, name: str, dirs, slices: bool = False) -> str:
    p = Path(name.replace("\\", "/"))
    if p.suffix.lower() in (".slcw", ".slcs") and not slices:
        raise _unsupported(case, f"the variable profile {name!r} (slices file)",
                           "expected one profile file per rail and wheel (.prr, .prw, .ban, .whl, "
                           "or 2 columns)")
    cands = [p] if p.is_absolute() else [case.path.parent / p, Path.cwd() / p] + \
        [Path(dd) / p for dd in dirs] + [Path(dd) / p.name for dd in dirs]
    for c in cands:
        if c.is_file():
            return str(c.resolve())
    where = ", ".join(str(c.parent) for c in cands[:3])
    line = next((case.where(k) for k in ("R_FNAME", "W_FNAME") if case.values.get(k) == name),
                case.where())
    raise InpError(f"{line}: profile file {name!r} not found (looked in {where}); "
                   "give its folder with --profiles DIR")


def _profile_table(case: InpCase, prefix: str, dirs, slices: bool = False) -> dict:
    """The case file's profile table ([wheel] or [rail]) of CONTACT's profile
    inputs: MIRRORY, SCALE, SMOOTH, MIRRORZ and PRFOPT's ISMOOTH, ZIGTHRS,
    KINKHIGH, KINKLOW, KINKWID."""
    g = lambda k: case.values.get(prefix + k)   # noqa: E731
    fname = _need(case, prefix + "FNAME")
    path = _profile_path(case, fname, dirs, slices)
    t = {"profile": path, "mirror_y": g("MIRRORY") == 1,
         "mirror_z": {1: True, -1: False}.get(g("MIRRORZ"), "auto"), "scale": g("SCALE")}
    suffix = Path(path).suffix.lower()
    if suffix not in (".prr", ".prw"):
        t["units"] = "mm"                         # MiniProf and plain tables: mm
    if g("MIRRORY") not in (-1, 0, 1) or g("MIRRORZ") not in (-1, 0, 1):
        raise InpError(f"{case.where()}: {prefix}MIRRORY = {g('MIRRORY')}, MIRRORZ = "
                       f"{g('MIRRORZ')}: expected -1, 0 or 1")
    smooth, ismooth = g("SMOOTH"), g("ISMOOTH")
    if smooth and smooth > 0:
        if ismooth == 0:
            t["smoothing"] = {"method": "unweighted", "lambda": smooth * MM ** 3}
        elif ismooth == 1:
            t["smoothing"] = {"method": "weighted", "length": smooth * MM}
        else:
            raise _unsupported(case, f"ISMOOTH = {ismooth} (B-spline smoothing) of "
                                     f"{fname!r}", "expected 0 (lambda) or 1 (L_filt)")
    if g("PRFOPT") >= 1:
        t["zigzag"] = g("ZIGTHRS")
        t["kinks"] = {"high": g("KINKHIGH"), "low": g("KINKLOW"), "width": g("KINKWID") * MM}
    return t


def _rail_frame(raw: dict, base_dir: Path) -> dict:
    """What returns rail-profile coordinates and the track's vertical origin to
    CONTACT's: railcontact places a rail file's origin in the track plane (and a
    rail it inclines with its origin at the new top), CONTACT shifts the rail
    until its top touches the track plane."""
    case = case_from_dict(raw, base_dir)
    options, units = case.profile_options("rail")
    kw = {"units": units, **({"options": options} if options is not None else {})}
    incl = float(raw["rail"].get("inclination", 0.0))
    upright = get_profile(raw["rail"]["profile"], "rail", inclination=0.0, **kw)
    mounted = upright.rotated(incl) if incl else upright
    top = mounted.with_origin_at_top()
    y0, z0 = float(mounted.y[0] - top.y[0]), float(mounted.z[0] - top.z[0])
    if incl:
        # railcontact's inclined rail has its origin at the top: undo that shift,
        # then the rotation, for rail-profile coordinates; its top is at z = 0
        return {"cant": incl, "origin_shift": (y0, z0), "z_top": 0.0}
    return {"cant": 0.0, "origin_shift": (0.0, 0.0), "z_top": z0}


def _map_module1(case: InpCase, dirs) -> MappedCase:
    d, v = case.digits, case.values
    if d["E"] == 0 and "Y_WS" not in v:
        raise InpError(f"{case.where()}: EWHEEL = 0 in the first case: no wheelset data")
    sgn = -1.0 if d["C"] in (0, 4) else 1.0
    slices = Path(str(_need(case, "R_FNAME"))).suffix.lower() == ".slcs"
    translate = _translation(case) if not slices else 0.0
    if slices or d["C"] in (4, 5) or (
            d["C"] in (0, 1) and _need(case, "GAUGHT") <= 0 and not translate
            and not 250.0 <= sgn * _need(case, "RAILY0") <= 1000.0):
        # a switch or crossing, a roller rig, a test rig's rail near the centre
        return _map_surfaces(case, dirs)
    side = _digit(case, "C", {0: "left", 1: "right"}, "CONFIG")
    normal = _digit(case, "B", {0: "exact", 5: "kpec", 6: "analyn"}, "BOUND")
    force = _digit(case, "N", {0: "position", 1: "force"}, "NORM")
    _digit(case, "F", {0: "pitch velocity prescribed", 1: "total force FX_WS prescribed"},
           "FORCE")
    _digit(case, "D", {0: "kept", 1: "kept", 2: "planar contact, contact locus",
                       4: "conformal contact"}, "DISCNS")
    conformal = (d["D"] if d["D"] >= 2 else v.get("DISCNS")) == 4
    tang, topt = _tangential_model(case)
    sgn = 1.0 if side == "right" else -1.0
    track = {}
    if _need(case, "GAUGHT") <= 0:
        # absolute placement: the rail-profile origin at (RAILY0, RAILZ0)
        offset = sgn * _need(case, "RAILY0") * MM + translate
        if not 0.25 <= offset <= 1.0:
            raise _unsupported(case, f"RAILY0 = {v['RAILY0']:g} mm on the {side} side",
                               "expected the rail origin 250-1000 mm from the track centre "
                               "on its side")
        track["rail_offset"] = offset
        if v.get("CANT"):
            raise _unsupported(case, f"CANT = {v['CANT']:g} with absolute rail placement "
                                     "(GAUGHT <= 0)", "expected CANT = 0 (a rail file as mounted)")
    else:
        track.update(gauge=_need(case, "GAUGWD") * MM, gauge_height=v["GAUGHT"] * MM)
    if v.get("GAUGSQ", 0) not in (0, None):
        raise _unsupported(case, f"GAUGSQ = {v['GAUGSQ']:g}", "expected 0 (the leftmost gauge "
                                                              "face)")
    if v.get("CURV"):
        raise _unsupported(case, f"CURV = {v['CURV']:g} 1/mm (curved track)",
                           "expected 0 (straight track)")
    for name in ("DYRAIL", "DZRAIL", "DROLLR", "VYRAIL", "VZRAIL", "VROLLR"):
        if v.get(name):
            raise _unsupported(case, f"{name} = {v[name]:g} (rail deviations)", "expected 0")
    for name in ("DXWHL", "DYWHL", "DZWHL", "DROLLW", "DYAWW", "DPITCHW", "VXWHL", "VYWHL",
                 "VZWHL", "VROLLW", "VYAWW", "VPITCHW"):
        if v.get(name):
            raise _unsupported(case, f"{name} = {v[name]:g} (flexible wheelset deviations, "
                                     f"EWHEEL = {d['E']})", "expected 0")
    if v.get("YTAPE") is not None and abs(v["YTAPE"]) < 1000:
        raise _unsupported(case, f"YTAPE = {v['YTAPE']:g} mm (tape circle offset)",
                           "expected it left out")
    for name in ("VZ_WS", "VROLL"):
        if v.get(name):
            raise _unsupported(case, f"{name} = {v[name]:g}", "expected 0 (railcontact's "
                                                              "kinematic creepages use VS, VY, "
                                                              "VYAW and VPITCH)")
    if v.get("G_MISS") is not None and v["G_MISS"] >= 0:
        raise _unsupported(case, f"G_MISS = {v['G_MISS']:g} mm (near-miss patches)",
                           "expected it left out or negative")
    a_sep = _need(case, "A_SEP")
    if a_sep < math.pi / 2 - 1e-9:
        raise _unsupported(case, f"A_SEP = {a_sep:.4f} rad", "expected at least pi/2: "
                                                            "railcontact combines regions by "
                                                            "their distance alone")
    d_sep, d_comb = _need(case, "D_SEP"), _need(case, "D_COMB")
    d_turn = v.get("D_TURN")
    if d_turn is None:
        d_turn = default_turn_distance(d_sep, d_comb)
    base = case.path.parent
    raw = {"title": f"{case.path.name} case {case.number}", "material": _material(case),
           "friction": _friction(case),
           "wheel": {**wheel_table(_profile_table(case, "W_", dirs, slices=True)),
                     "nominal_radius": _need(case, "NOMRADW") * MM},
           "rail": {**_profile_table(case, "R_", dirs), "inclination": _need(case, "CANT")},
           "track": track,
           "wheelset": {"flange_back_distance": _need(case, "FBDIST") * MM,
                        "flange_back_position": _need(case, "FBPOS") * MM,
                        "lateral_shift": _need(case, "Y_WS") * MM, "yaw": _need(case, "YAW"),
                        "roll": _need(case, "ROLL"), "side": side,
                        "velocity": _need(case, "VS_WS") * MM,
                        # F = 1: found for FX_WS, from the nominal rolling radius
                        "pitch_velocity": _need(case, "VPITCH") if d["F"] == 0 else
                        -_need(case, "VS_WS") / _need(case, "NOMRADW"),
                        "lateral_velocity": (v.get("VY_WS") or 0.0) * MM,
                        "yaw_rate": v.get("VYAW") or 0.0,
                        "combine_distance": d_sep * MM, "full_interaction_distance": d_comb * MM,
                        "turn_distance": d_turn * MM if d_turn > d_sep else 0.0,
                        "separation_angle": min(a_sep, math.pi)},
           "solver": {"normal": normal, "tangential": tang,
                      "element_size": [_need(case, "DX") * MM, _need(case, "DS") * MM],
                      "tangential_options": topt,
                      # CONTACT's contact locus, wheel sampling, gauge point, ...
                      "rules": "contact"}}
    if conformal:
        raw["solver"]["contact_surface"] = "conformal"
    if (v.get("INFLCF") or 2) == 4:
        raw["solver"].update(_blanco(case, conformal))
    if translate:
        # the wheel moved with the rail (:func:`_translation`)
        raw["wheelset"]["flange_back_distance"] += 2.0 * translate
    frame = _rail_frame(raw, base)
    if "rail_offset" in track:
        # CONTACT's rail origin at z = RAILZ0; railcontact's in the track plane
        frame["z_top"] = -(v.get("RAILZ0") or 0.0) * MM
    # (else the rail is placed by its gauge point as CONTACT finds it, on the spline
    # along the points' chord length: solver.rules' gauge_point; railcontact's own
    # rule differs by a fraction of a micrometre on a steep gauge face)
    if force == "force":
        raw["wheelset"]["vertical_force"] = _need(case, "FZ_WS")
    else:
        raw["wheelset"]["vertical_position"] = _need(case, "Z_WS") * MM + frame["z_top"]
    if "slices" in raw["wheel"]:
        raw["wheelset"]["pitch"] = _need(case, "PITCH")       # the out-of-round wheel's
    meta = {"module": 1, "side": side, "nominal_radius": v["NOMRADW"] * MM,
            "wheel_offset": (v["FBDIST"] / 2 - v["FBPOS"]) * MM, **frame}
    if translate:
        meta.update(translation=translate, wheel_offset=meta["wheel_offset"] + translate)
    if d["F"] == 1:
        meta["fx_ws"] = _need(case, "FX_WS")
    return MappedCase(case.number, 1, raw, meta)


#: where a translated test-rig case places its rail's origin [m] (:func:`_translation`)
TRANSLATED_RAIL = 0.75


def _translation(case: InpCase) -> float:
    """The lateral translation [m] that takes a conformal case on a test rig's rail
    at RAILY0 near the track centre (GAUGHT <= 0, a wheel in a groove: groove_li)
    onto a track's rail at :data:`TRANSLATED_RAIL` from the centre, the wheel moved
    with it (FBDIST + 2 L): the same problem where the wheelset neither rolls nor
    yaws (ROLL = YAW = VYAW = 0, whose axes lie at the track centre); the rows'
    y_tr are moved back (``meta["translation"]``).  0 for any other case."""
    d, v = case.digits, case.values
    sgn = -1.0 if d["C"] == 0 else 1.0
    conformal = (d["D"] if d["D"] >= 2 else v.get("DISCNS")) == 4
    if d["C"] not in (0, 1) or not conformal or (v.get("GAUGHT") or 0.0) > 0 or \
            250.0 <= sgn * (v.get("RAILY0") or 0.0) <= 1000.0 or \
            any(v.get(k) for k in ("ROLL", "YAW", "VYAW", "RAILZ0", "CANT")):
        return 0.0
    return TRANSLATED_RAIL - sgn * (v.get("RAILY0") or 0.0) * MM


# ------------------------------- module 1 on rail surfaces: slices (S&C), roller rigs
def _map_surfaces(case: InpCase, dirs) -> MappedCase:
    """A module 1 case as a case on rail surfaces (:mod:`railcontact.cases.surfaces`):
    a rail given by slices (``.slcs``: a switch or crossing), a roller rig (CONFIG
    = 4, 5: the rail profile turned about the roller's axis, NOMRAD_R and
    VPITCH_ROL in the places of CANT and VS) or a rail placed at RAILY0 closer to
    the track centre than 250 mm (a test rig).  The rail's profile origin at
    (RAILY0, RAILZ0) in the track frame (GAUGHT <= 0), the wheelset at S_WS along
    the track, the contact angle by CONTACT's rule (the rail's inclination on the
    cross-section at the wheelset: ``solver.contact_angle = "wheelset"``) for D =
    2 (contact locus) and D = 5 (brute-force search) alike (railcontact searches
    the surfaces once, on a 3-D grid), D = 3 the rigid slip on the actual surfaces
    (``solver.rigid_slip = "surfaces"``, by CONTACT's rule of it: the preset's
    ``surface_slip = "midplane"``), the patch separation distance D_SEP, and
    CONTACT's profile processing (MIRRORY, SCALE, SMOOTH) applied to every
    slice."""
    d, v = case.digits, case.values
    side = _digit(case, "C", {0: "left", 1: "right", 4: "left", 5: "right"}, "CONFIG")
    roller = d["C"] in (4, 5)
    fname = _need(case, "R_FNAME")
    slices = Path(str(fname)).suffix.lower() == ".slcs"
    what = "rail slices" if slices else ("a roller rig" if roller else "a rail at RAILY0")
    normal = _digit(case, "B", {0: "exact", 5: "kpec", 6: "analyn"}, "BOUND")
    force = _digit(case, "N", {0: "position", 1: "force"}, "NORM")
    _digit(case, "F", {0: "pitch velocity prescribed"}, "FORCE")
    allowed_d = {0: "kept", 1: "kept", 2: "planar contact, contact locus",
                 5: "brute-force contact search"}
    if not slices:
        allowed_d[3] = "planar contact with rigid slip on the actual surfaces"
    _digit(case, "D", allowed_d, f"DISCNS ({what})")
    # D = 0, 1 keep the search of the case that set it
    discns = d["D"] if d["D"] >= 2 else (v.get("DISCNS") or 2)
    tang, topt = _tangential_model(case)
    if _need(case, "GAUGHT") > 0:
        raise _unsupported(case, f"GAUGHT = {v['GAUGHT']:g} mm with {what} (a rail placed "
                                 "by its gauge face)",
                           "expected GAUGHT <= 0: the rail's origin at RAILY0, RAILZ0")
    if v.get("RAILZ0"):
        raise _unsupported(case, f"RAILZ0 = {v['RAILZ0']:g} mm with {what}",
                           "expected 0 (the rail's heights as given)")
    if v.get("CANT") and not roller:
        raise _unsupported(case, f"CANT = {v['CANT']:g} with {what}",
                           "expected 0 (the rail as mounted)")
    # a roller's DZRAIL, DROLLR deviate its profile about a fixed axis; a rail's
    # roll and the deviations' velocities are not supported
    rail_flex = RAIL_FLEX[3:] if roller else RAIL_FLEX[2:]
    for name in ("CURV", "VZ_WS", "VROLL") + rail_flex + WHEEL_FLEX[6:]:
        if v.get(name):
            raise _unsupported(case, f"{name} = {v[name]:g} with {what}", "expected 0" + (
                " (the wheel's deviations by flexibility DXWHL .. DPITCHW, a rail's "
                "DYRAIL, DZRAIL on a track or test rig, a roller's DYRAIL, DZRAIL, DROLLR)"
                if name in RAIL_FLEX + WHEEL_FLEX
                else ""))
    if v.get("G_MISS") is not None and v["G_MISS"] >= 0:
        raise _unsupported(case, f"G_MISS = {v['G_MISS']:g} mm (near-miss patches)",
                           "expected it left out or negative")
    if _need(case, "A_SEP") < math.pi / 2 - 1e-9:
        raise _unsupported(case, f"A_SEP = {v['A_SEP']:.4f} rad", "expected at least pi/2: "
                                                                   "regions are combined by "
                                                                   "their distance alone")
    # the rail's deviation by flexibility (Z = 2, 3): DYRAIL in track coordinates,
    # DZRAIL down, as the rail's placement
    place = {"lateral_position": (1.0 if side == "right" else -1.0) * (
        _need(case, "RAILY0") + (v.get("DYRAIL") or 0.0)) * MM,
             "vertical_position": 0.0 if roller else (v.get("DZRAIL") or 0.0) * MM}
    if _need(case, "VS_WS") == 0 and not roller:
        raise _unsupported(case, f"VS = 0 mm/s with {what}", "expected VS != 0 (rolling "
                                 "towards -x: VS < 0)")
    if not slices:
        return _surface_case(case, dirs, side, normal, force, tang, topt,
                             {**_profile_table(case, "R_", dirs), **place}, roller, discns)
    rail = {"slices": _profile_path(case, fname, dirs, slices=True), **place}
    g = lambda k: v.get("R_" + k)   # noqa: E731
    if g("MIRRORY") not in (-1, 0) or g("MIRRORZ") not in (-1, 0):
        raise _unsupported(case, f"MIRRORY = {g('MIRRORY')}, MIRRORZ = {g('MIRRORZ')} for "
                                 f"the slices {fname!r}", "expected -1 or 0 (slices as given, "
                                                          "z down)")
    scale = g("SCALE") or 1.0
    # CONTACT's SCALE converts the slice files' unit to mm
    if abs(scale - 1000.0) < 1e-9:
        rail["units"] = "m"
    else:
        rail["units"] = "mm"
        if abs(scale - 1.0) > 1e-12:
            rail["scale"] = scale
    smooth, ismooth = g("SMOOTH"), g("ISMOOTH")
    if smooth and smooth > 0:
        if ismooth not in (0, 1, None):
            raise _unsupported(case, f"ISMOOTH = {ismooth} (B-spline smoothing) of {fname!r}",
                               "expected 0 (lambda) or 1 (L_filt)")
        rail["smoothing"] = ({"method": "weighted", "length": smooth * MM} if ismooth == 1
                             else {"method": "unweighted", "lambda": smooth * MM ** 3})
    return _surface_case(case, dirs, side, normal, force, tang, topt, rail, False, discns)


def _surface_case(case, dirs, side, normal, force, tang, topt, rail, roller,
                  discns) -> MappedCase:
    """The surface case of :func:`_map_surfaces` with its ``rail`` table."""
    d, v = case.digits, case.values
    wheel = {**_profile_table(case, "W_", dirs), "nominal_radius": _need(case, "NOMRADW") * MM}
    ws = {"side": side, "position": (v.get("S_WS") or 0.0) * MM,
          "lateral_shift": _need(case, "Y_WS") * MM, "yaw": _need(case, "YAW"),
          "roll": _need(case, "ROLL"),
          "pitch_velocity": _need(case, "VPITCH"),
          "lateral_velocity": (v.get("VY_WS") or 0.0) * MM, "yaw_rate": v.get("VYAW") or 0.0,
          "flange_back_distance": _need(case, "FBDIST") * MM,
          "flange_back_position": _need(case, "FBPOS") * MM,
          "combine_distance": _need(case, "D_SEP") * MM}
    dev = [(v.get(k) or 0.0) * (MM if i < 3 else 1.0) for i, k in enumerate(WHEEL_FLEX[:6])]
    if any(dev):
        # the wheel's deviation by flexibility (E = 4, 5) about its profile origin
        ws["wheel_deviation"] = dev
    if force == "force":
        ws["vertical_force"] = _need(case, "FZ_WS")
    else:
        ws["vertical_position"] = _need(case, "Z_WS") * MM
    raw = {"title": f"{case.path.name} case {case.number}", "material": _material(case),
           "friction": _friction(case), "wheel": wheel, "rail": rail, "wheelset": ws,
           "solver": {"normal": normal, "tangential": tang,
                      "element_size": [_need(case, "DX") * MM, _need(case, "DS") * MM],
                      "tangential_options": topt,
                      # CONTACT's contact angle, wheel sampling, ...; its reference
                      # point of the contact locus (D = 2, 3)
                      "rules": "contact"}}
    if discns == 5:
        # the brute-force search: CONTACT's reference point on the 2-D gap function,
        # on the gap mesh of its search (its wheel sampled in slices about 1.5 DX
        # apart through the lowest line)
        raw["solver"].update(reference_weights="surface", search_grid="contact")
    if roller:
        # CONTACT's roller rig: NOMRAD_R and VPITCH_ROL read in the places of CANT
        # and VS; the wheelset does not travel
        raw["roller"] = {"radius": _need(case, "CANT") * MM,
                         "angular_velocity": _need(case, "VS_WS")}
        if v.get("DZRAIL") or v.get("DROLLR"):
            # the roller's profile turned (DROLLR, track frame: mirrored on the left)
            # and lowered (DZRAIL) about the roller's fixed axis
            raw["roller"]["profile_deviation"] = [
                (v.get("DZRAIL") or 0.0) * MM,
                (1.0 if side == "right" else -1.0) * (v.get("DROLLR") or 0.0)]
    else:
        ws["velocity"] = _need(case, "VS_WS") * MM
    if discns == 3:
        if tang != "exact":
            raise _unsupported(case, f"DISCNS = 3 with MATER = {d['M']}",
                               "expected MATER = 0 (the exact tangential model)")
        raw["solver"]["rigid_slip"] = "surfaces"
    meta = {"module": 1, "side": side, "nominal_radius": v["NOMRADW"] * MM,
            "wheel_offset": (v["FBDIST"] / 2 - v["FBPOS"]) * MM, "cant": 0.0,
            "origin_shift": (0.0, 0.0), "z_top": 0.0, "surfaces": True}
    if "profile_deviation" in raw.get("roller", {}):
        # the rows' rail-profile coordinates in the profile as read (CONTACT's)
        meta["profile_deviation"] = tuple(raw["roller"]["profile_deviation"])
    return MappedCase(case.number, 1, raw, meta)
