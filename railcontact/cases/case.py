"""Case files (TOML, contract v1 of ``docs/architecture.md``) and the :class:`Case` type."""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field
from pathlib import Path

from .bodies_setup import RADII, BodiesSetup, parse_bodies
from .keys import PROFILE_OPTIONS, CaseKeys
from .rules import ContactRules, parse_rules
from .surface_setup import SurfaceCaseSetup, is_surface_case, parse_surface_case
from .viscoelastic_setup import VISCOELASTIC_KEYS, viscoelastic_option
from .wheel_rail_setup import WheelRailSetup, parse_wheel_rail
from ..core.checks import check_grid_size, shown
from ..core.errors import CaseFileError, InputError, RailContactError
from ..core.files import read_toml
from ..core.materials import Material
from ..normal import get_normal_model
from ..normal.plasticity import HARDNESS_FACTOR, pressure_limit
from ..subsurface.elastoplastic import ElasticPlasticOptions, Hardening
from ..tangential import get_tangential_model
from ..tangential.temperature import SCHEMES, STEEL, ThermalProperties

_ALLOWED = {
    "title": None,
    "material": {"young_modulus", "poisson_ratio", "wheel_young_modulus",
                 "wheel_poisson_ratio", "yield_stress"},
    "friction": {"coefficient", "variation"},
    "wheel": {"profile", "nominal_radius", "profile_left", "units", "slices"} | PROFILE_OPTIONS,
    "rail": {"profile", "inclination", "profile_left", "units", "slices", "name",
             "lateral_position", "vertical_position", "slice_spacing"} | PROFILE_OPTIONS,
    "rails": None,
    "roller": {"radius", "angular_velocity", "position", "profile_deviation", "turn"},
    "track": {"gauge", "gauge_height", "rail_offset", "gauge_point"},
    "wheelset": {"flange_back_distance", "flange_back_position", "lateral_shift", "yaw", "roll",
                 "side",
                 "vertical_force", "vertical_position", "velocity", "pitch_velocity", "pitch",
                 "lateral_velocity", "yaw_rate", "wheel_deviation",
                 "combine_distance", "full_interaction_distance", "turn_distance",
                 "separation_angle", "position", "locus"},
    "creepage": {"longitudinal", "lateral", "spin"},
    "force": {"longitudinal", "lateral"},
    "solver": {"normal", "tangential", "grid", "element_size", "normal_options",
               "tangential_options", "force_tolerance", "search_length",
               "contact_angle", "rigid_slip", "allow_large", "contact_surface", "influence",
               "influence_options", "reference_weights", "search_grid", "rules",
               "surface_slip"},
    "bodies": {"radii", "normal_force", "velocity"},
    "plasticity": {"model", "yield_stress", "pressure_factor", "pressure_limit",
                   "hardening_modulus", "voce_saturation", "voce_rate", "grid", "layers",
                   "extent", "depth", "load_steps", "passes"},
    "viscoelastic": VISCOELASTIC_KEYS,
    "thermal": {"rail_temperature", "wheel_temperature", "heat_capacity", "conductivity",
                "density", "scheme"},
}


@dataclass(frozen=True)
class Case(CaseKeys):
    """One contact case, validated, in SI units (frozen: built once by
    :func:`case_from_dict`).

    ``raw`` keeps the parsed TOML so that a sweep can vary any dotted key; the
    validated reading of its keys is :class:`~railcontact.cases.keys.CaseKeys`'s.
    """

    title: str = ""
    material: Material = field(default_factory=Material)
    friction: float = 0.3
    normal: str = "hertz"
    tangential: str = "fastsim"
    normal_options: dict = field(default_factory=dict)
    tangential_options: dict = field(default_factory=dict)
    grid: tuple | None = None
    element_size: tuple | None = None
    force_tolerance: float = 1e-4
    #: ``material.yield_stress`` [Pa] (None: not given), for the elastic pressure limit
    yield_stress: float | None = None
    #: ``friction.variation``: (angles [rad], coefficients) or None
    friction_variation: tuple | None = None
    #: ``friction.variation`` along the track: (x [m] from the wheelset centre,
    #: coefficients) or None (CONTACT's VARFRC = 2)
    friction_along_track: tuple | None = None
    creepage: tuple | None = None
    #: ``[plasticity] model = "elastic-plastic"``: the model's settings (None: not asked)
    elastic_plastic: ElasticPlasticOptions | None = None
    base_dir: Path = field(default_factory=Path.cwd)
    #: the wheel-rail keys parsed (None for bodies cases and cases on rail surfaces)
    wheel_rail: WheelRailSetup | None = None
    #: the keys of a case on rail surfaces parsed (None for other cases)
    surfaces: SurfaceCaseSetup | None = None
    #: the ``[bodies]`` (and ``[force]``) keys of a case given by curvatures parsed
    bodies: BodiesSetup | None = None
    #: ``[thermal]``: (rail, wheel) thermal constants of the flash temperatures
    #: (each key defaulting to steel at 20 deg C) and the discretisation
    #: (``"jaeger"``, or ``"contact"``: CONTACT's own-element weight); None without
    #: a ``[thermal]`` table: no temperatures (they cost about a millisecond per
    #: patch, as much as a whole compiled Hertz + FASTSIM case)
    thermal: tuple | None = None
    #: CONTACT's rules the case follows (``solver.rules`` and each rule's own key,
    #: :class:`~railcontact.cases.rules.ContactRules`; railcontact's by default)
    rules: ContactRules = field(default_factory=ContactRules)

    @property
    def is_bodies(self) -> bool:
        return "bodies" in self.raw

    def friction_at(self, angle: float) -> float:
        """Friction coefficient of a patch whose rail surface has the inclination
        ``angle`` [rad] (rail-profile coordinates: negative on the gauge face):
        ``friction.variation`` interpolated linearly, constant beyond its ends
        (CONTACT's VARFRC = 1), else ``friction.coefficient``."""
        if self.friction_variation is None:
            return self.friction
        import numpy as np
        angles, coefficients = self.friction_variation
        return float(np.interp(angle, angles, coefficients))

    def with_value(self, dotted: str, value) -> "Case":
        """A copy of the case with one dotted key set (used by sweeps)."""
        return self.with_values({dotted: value})

    def with_values(self, values: dict) -> "Case":
        """A copy of the case with the dotted keys of ``values`` set (``{"wheelset.yaw":
        0.002, "creepage": {...}}``; a value may be a :class:`~railcontact.profiles.Profile`
        for a profile key), parsed and checked as a case file is."""
        raw = copy.deepcopy(self.raw)
        for dotted, value in values.items():
            node = raw
            parts = dotted.split(".")
            for part in parts[:-1]:
                node = node.setdefault(part, {})
                if not isinstance(node, dict):
                    raise CaseFileError(f"{dotted}: {part} is not a table")
            node[parts[-1]] = value
        return case_from_dict(raw, self.base_dir)

    def with_models(self, normal: str | None = None, tangential: str | None = None) -> "Case":
        """A copy with other models (``[solver]``'s normal and tangential; the options of
        a replaced model are dropped), checked as a case file is."""
        raw = copy.deepcopy(self.raw)
        sol = raw.setdefault("solver", {})
        for key, name in (("normal", normal), ("tangential", tangential)):
            if name:
                sol[key] = name
                sol.pop(f"{key}_options", None)
        return case_from_dict(raw, self.base_dir)


def _check_keys(raw: dict) -> None:
    for key, value in raw.items():
        if key not in _ALLOWED:
            raise CaseFileError(f"unknown section or key [{key}]; expected one of "
                                f"{sorted(_ALLOWED)}")
        allowed = _ALLOWED[key]
        if allowed is None:
            continue
        if not isinstance(value, dict):
            raise CaseFileError(f"[{key}] must be a table")
        for sub in value:
            if sub not in allowed:
                raise CaseFileError(f"unknown key {key}.{sub}; expected one of {sorted(allowed)}")
    if "bodies" in raw and any(k in raw for k in ("wheel", "rail", "rails", "roller", "track",
                                                   "wheelset")):
        raise CaseFileError("a case has either [bodies] or [wheel]/[rail]/[track]/[wheelset], "
                            "not both")
    if "bodies" not in raw and not ("wheel" in raw and ("rail" in raw or "rails" in raw)):
        raise CaseFileError("missing [wheel] and [rail] (or [bodies]); expected a wheel-rail "
                            "case or a case given by curvatures")
    if "bodies" in raw:
        radii = raw["bodies"].get("radii")
        if not isinstance(radii, dict) or set(radii) - set(RADII) or not radii:
            raise CaseFileError(f"bodies.radii = {shown(radii)}: expected a table with keys "
                                f"{sorted(RADII)} (m; negative = concave, inf = flat)")


def case_from_dict(raw: dict, base_dir: Path | None = None) -> Case:
    """Validate a parsed case and build its frozen :class:`Case`: every key is
    checked here, once; a :class:`~railcontact.core.errors.CaseFileError` names the
    first that is wrong."""
    if not isinstance(raw, dict):
        raise CaseFileError("case: expected a TOML table")
    _check_keys(raw)
    keys = CaseKeys(raw)
    sol = raw.get("solver", {})
    normal = str(sol.get("normal", "hertz")).lower()
    tangential = str(sol.get("tangential", "fastsim")).lower()
    grid, element_size = _grid(sol)
    allow_large = sol.get("allow_large", False)
    if not isinstance(allow_large, bool):
        raise CaseFileError(f"solver.allow_large = {shown(allow_large)}: expected true or false")
    if grid:
        check_grid_size(grid, "solver.grid", allow_large)
    yield_stress = (None if keys.get("material.yield_stress") is None
                    else keys.number("material.yield_stress", None, 1e6, 1e11, "Pa"))
    rules = parse_rules(keys, normal, tangential)
    # the models' options that CONTACT's rules set, under the case's own
    normal_options = {**rules.normal_options(normal, "bodies" not in raw),
                      **_options(sol, "normal_options")}
    elastic_plastic = None
    if "plasticity" in raw and _plasticity_model(raw) == "elastic-plastic":
        elastic_plastic = _elastic_plastic(keys, normal)
    elif "plasticity" in raw:
        if "pressure_limit" in normal_options:
            raise CaseFileError("pressure limit given both in [plasticity] and in "
                                "solver.normal_options; give it once")
        normal_options["pressure_limit"] = _pressure_limit(keys, normal)
    tangential_options = {**rules.tangential_options(tangential),
                          **_options(sol, "tangential_options")}
    if "viscoelastic" in raw:       # an option of both exact models
        normal_options["viscoelastic"] = viscoelastic_option(keys, normal, tangential)
        if tangential != "none":
            tangential_options["viscoelastic"] = normal_options["viscoelastic"]
    values = dict(
        title=str(raw.get("title", "")), material=_material(keys),
        thermal=_thermal(keys, rules.thermal_scheme), rules=rules,
        friction=keys.number("friction.coefficient", 0.3, 0.0, 5.0),
        friction_variation=_friction_variation(keys),
        friction_along_track=_friction_variation(keys, "x"), normal=normal,
        tangential=tangential,
        yield_stress=yield_stress, elastic_plastic=elastic_plastic,
        normal_options=normal_options,
        tangential_options=tangential_options, grid=grid,
        element_size=element_size,
        force_tolerance=keys.number("solver.force_tolerance", 1e-4, 1e-8, 0.05, "(relative)"),
        creepage=None if "creepage" not in raw else (
            keys.number("creepage.longitudinal", 0.0, -1.0, 1.0),
            keys.number("creepage.lateral", 0.0, -1.0, 1.0),
            keys.number("creepage.spin", 0.0, -100.0, 100.0, "1/m")))
    # resolve models early so that a bad name fails before any work
    try:
        get_normal_model(normal, **normal_options)
        if tangential != "none":
            get_tangential_model(tangential, **values["tangential_options"])
    except (TypeError, InputError) as exc:
        raise CaseFileError(f"solver options: {exc}") from None
    if "force" in raw and "bodies" not in raw:
        raise CaseFileError("[force] (prescribed tangential forces) needs a [bodies] case; "
                            "for wheel-rail cases give [creepage]")
    if "bodies" in raw:
        values["bodies"] = parse_bodies(keys)
    elif is_surface_case(keys):
        # rails along the track, several rails, a roller: railcontact.cases.surfaces
        values["surfaces"] = parse_surface_case(keys, tangential, rules)
    else:
        values["wheel_rail"] = parse_wheel_rail(keys)
    if values["friction_along_track"] is not None and (
            "wheel_rail" not in values or values["material"].is_dissimilar):
        raise CaseFileError("friction.variation.x (friction along the track) applies to a "
                            "wheel-rail case on a track of identical materials; expected "
                            "friction.variation.angle or friction.coefficient")
    wr = values.get("wheel_rail")
    if wr is not None and wr.influence is not None and (
            values["normal"] != "exact" or values["tangential"] not in ("exact", "none")
            or values["material"].is_dissimilar):
        raise CaseFileError("solver.influence = 'blanco': Blanco's coefficients are those of "
                            "the exact solvers for bodies of one material; expected normal = "
                            "'exact', tangential = 'exact' (or 'none') and one material")
    if wr is not None and wr.influence is not None:
        topts = values["tangential_options"]
        # ([viscoelastic] is for bodies cases: viscoelastic_option rejects it here)
        clash = (["solver.tangential_options.layer"] if topts.get("layer") is not None
                 else []) + (["solver.tangential_options.mode = 'transient'"]
                             if topts.get("mode") == "transient" else [])
        if clash:
            raise CaseFileError(f"solver.influence = 'blanco' with {' and '.join(clash)}: "
                                "Blanco's coefficients are for steady rolling or a shift "
                                "without an interfacial layer")
    if "wheel_rail" not in values and sol.get("influence", "half-space") != "half-space":
        raise CaseFileError(f"solver.influence = {shown(sol['influence'])}: Blanco's "
                            "coefficients are for wheel-rail cases; expected 'half-space'")
    if "wheel_rail" not in values and sol.get("contact_surface", "planar") != "planar":
        raise CaseFileError(f"solver.contact_surface = {shown(sol['contact_surface'])}: the "
                            "conformal surface is for wheel-rail cases; expected 'planar'")
    return Case(raw=raw, base_dir=Path(base_dir or Path.cwd()), **values)


def _material(keys: CaseKeys) -> Material:
    """``[material]``: one material, or the wheel's own beside the rail's."""
    try:
        wE, wnu = keys.get("material.wheel_young_modulus"), keys.get("material.wheel_poisson_ratio")
        return Material(keys.number("material.young_modulus", 2.1e11, unit="Pa"),
                        keys.number("material.poisson_ratio", 0.28),
                        None if wE is None else keys.number("material.wheel_young_modulus",
                                                            unit="Pa"),
                        None if wnu is None else keys.number("material.wheel_poisson_ratio"))
    except InputError as exc:
        raise CaseFileError(str(exc)) from None


def _thermal(keys: CaseKeys, scheme: str = "jaeger") -> tuple | None:
    """``[thermal]``: bulk temperatures [deg C] of rail and wheel and the steel's
    heat capacity [J/(kg K)], conductivity [W/(m K)] and density [kg/m^3] (both
    bodies), and the ``scheme`` (the case's rule, ``thermal.scheme`` over
    ``solver.rules``), for the flash temperatures (docs/case_files.md)."""
    if "thermal" not in keys.raw:
        return None
    if scheme not in SCHEMES:
        raise CaseFileError(f"thermal.scheme = {shown(scheme)}: expected one of {SCHEMES}")
    try:
        c = (keys.number("thermal.heat_capacity", STEEL.heat_capacity, 1.0, 1e5, "J/(kg K)"),
             keys.number("thermal.conductivity", STEEL.conductivity, 1e-3, 1e4, "W/(m K)"),
             keys.number("thermal.density", STEEL.density, 1.0, 1e5, "kg/m^3"))
        return (*(ThermalProperties(keys.number(f"thermal.{b}_temperature",
                                                STEEL.bulk_temperature, -273.15, 2000.0,
                                                "degC"), *c) for b in ("rail", "wheel")),
                scheme)
    except InputError as exc:
        raise CaseFileError(str(exc)) from None


def _options(sol: dict, key: str) -> dict:
    """``solver.normal_options`` or ``solver.tangential_options``: a table of a model's
    options (checked by the model when it is built)."""
    v = sol.get(key, {})
    if not isinstance(v, dict):
        raise CaseFileError(f"solver.{key} = {shown(v)}: expected a table of the model's "
                            "options")
    return dict(v)


def _grid(sol: dict) -> tuple:
    """``solver.grid`` (two integers) and ``solver.element_size`` (two lengths [m]),
    at most one of them given."""
    out = {}
    for key in ("grid", "element_size"):
        v = sol.get(key)
        if v is not None:
            if not (isinstance(v, list) and len(v) == 2
                    and all(isinstance(t, (int, float)) and not isinstance(t, bool)
                            and math.isfinite(t) and t > 0 for t in v)):
                raise CaseFileError(f"solver.{key} = {shown(v)}: expected two positive "
                                    "finite numbers (rolling, lateral)")
            if key == "grid" and not all(float(t).is_integer() and 2 <= t <= 2000 for t in v):
                raise CaseFileError(f"solver.grid = {shown(v)}: expected two integers in "
                                    "[2, 2000]")
            out[key] = tuple(int(t) if key == "grid" else float(t) for t in v)
    if len(out) == 2:
        raise CaseFileError("solver: give either grid or element_size, not both")
    return out.get("grid"), out.get("element_size")


#: the keys of ``[plasticity]`` that only the elastic-plastic model reads
_EP_KEYS = ("hardening_modulus", "voce_saturation", "voce_rate", "grid", "layers", "extent",
            "depth", "load_steps", "passes")


def _plasticity_model(raw: dict) -> str:
    """``plasticity.model``: "pressure-cap" (default) or "elastic-plastic"."""
    model = raw["plasticity"].get("model", "pressure-cap")
    if model not in ("pressure-cap", "elastic-plastic"):
        raise CaseFileError(f"plasticity.model = {shown(model)}: expected 'pressure-cap' "
                            "(the pressure bounded by pressure_factor x yield_stress) or "
                            "'elastic-plastic' (plastic strains with isotropic hardening)")
    if model == "pressure-cap":
        extra = sorted(k for k in _EP_KEYS if k in raw["plasticity"])
        if extra:
            raise CaseFileError(f"[plasticity]: {', '.join(extra)} belong to model = "
                                "'elastic-plastic'; the pressure cap reads yield_stress, "
                                "pressure_factor or pressure_limit")
    return model


def _elastic_plastic(keys: CaseKeys, normal: str) -> ElasticPlasticOptions:
    """``[plasticity] model = "elastic-plastic"``: the settings of
    :mod:`railcontact.subsurface.elastoplastic` (its surface problem is the exact
    normal model's).  ``yield_stress`` [Pa] is required; the hardening, linear
    (``hardening_modulus`` [Pa]) plus Voce (``voce_saturation`` [Pa],
    ``voce_rate``), defaults to none (perfectly plastic); the grid and load keys to
    :class:`~railcontact.subsurface.elastoplastic.ElasticPlasticOptions`'s
    defaults (docs/case_files.md)."""
    pl = keys.raw["plasticity"]
    if normal != "exact":
        raise CaseFileError(f"[plasticity] model = 'elastic-plastic' solves the surface with "
                            f"the exact normal model; solver.normal is {shown(normal)} "
                            "(expected 'exact')")
    for k in ("pressure_factor", "pressure_limit"):
        if k in pl:
            raise CaseFileError(f"[plasticity]: {k} belongs to model = 'pressure-cap'")
    if "yield_stress" not in pl:
        raise CaseFileError("[plasticity]: model = 'elastic-plastic' needs yield_stress (Pa)")

    def count(name, default, hi):
        v = pl.get(name, default)
        if isinstance(v, bool) or not isinstance(v, int) or not 1 <= v <= hi:
            raise CaseFileError(f"plasticity.{name} = {shown(v)}: expected an integer in "
                                f"[1, {hi}]")
        return v

    grid = pl.get("grid", [32, 32])
    if not (isinstance(grid, (list, tuple)) and len(grid) == 2
            and all(isinstance(v, int) and not isinstance(v, bool) and 4 <= v <= 256
                    for v in grid)):
        raise CaseFileError(f"plasticity.grid = {shown(grid)}: expected [mx, my], cell counts "
                            "in [4, 256]")
    try:
        hardening = Hardening(
            yield_stress=keys.number("plasticity.yield_stress", None, 1e6, 1e11, "Pa"),
            modulus=keys.number("plasticity.hardening_modulus", 0.0, 0.0, 1e12, "Pa"),
            saturation=keys.number("plasticity.voce_saturation", 0.0, 0.0, 1e11, "Pa"),
            rate=keys.number("plasticity.voce_rate", 0.0, 0.0, 1e5))
        return ElasticPlasticOptions(
            hardening=hardening, grid=(int(grid[0]), int(grid[1])),
            layers=count("layers", 16, 64),
            extent=keys.number("plasticity.extent", 2.0, 1.01, 10.0),
            depth=keys.number("plasticity.depth", 3.0, 0.1, 20.0),
            load_steps=count("load_steps", 4, 100), passes=count("passes", 1, 1000))
    except InputError as exc:
        raise CaseFileError(str(exc)) from None


def _pressure_limit(keys: CaseKeys, normal: str) -> float:
    """``[plasticity]``: the pressure limit [Pa] of elastic-perfectly-plastic contact
    (:mod:`railcontact.normal.plasticity`), passed to the exact normal model as its
    ``pressure_limit`` option: ``pressure_limit`` [Pa] as given, else
    ``pressure_factor`` (default 3, Tabor's hardness) x ``yield_stress`` [Pa]."""
    pl = keys.raw["plasticity"]
    if normal != "exact":
        raise CaseFileError(f"[plasticity] bounds the pressure of the exact normal model; "
                            f"solver.normal is {shown(normal)} (expected 'exact')")
    if "pressure_limit" in pl:
        if "yield_stress" in pl or "pressure_factor" in pl:
            raise CaseFileError("[plasticity]: give pressure_limit, or yield_stress (with "
                                "pressure_factor), not both")
        return keys.number("plasticity.pressure_limit", None, 1e6, 1e12, "Pa")
    if "yield_stress" not in pl:
        raise CaseFileError("[plasticity]: missing yield_stress (Pa) or pressure_limit (Pa)")
    try:
        return pressure_limit(keys.number("plasticity.yield_stress", unit="Pa"),
                              keys.number("plasticity.pressure_factor", HARDNESS_FACTOR))
    except InputError as exc:
        raise CaseFileError(str(exc)) from None


def _friction_variation(case: CaseKeys, axis: str = "angle") -> tuple | None:
    """``friction.variation = {angle = [...], coefficient = [...]}``: friction
    coefficients at rail surface inclinations [rad], increasing; or ``{x = [...],
    coefficient = [...]}`` (``axis = "x"``): along the track, at x [m] from the
    wheelset centre (CONTACT's VARFRC = 2), each element of a patch its own (the
    exact tangential model).  Returned as (angles or x, coefficients) tuples of
    floats, None where not given or given along the other axis."""
    var = case.get("friction.variation")
    if var is None:
        return None
    if isinstance(var, dict) and set(var) == {"x", "coefficient"}:
        if axis != "x":
            return None
        if str(case.get("solver.tangential", "fastsim")).lower() != "exact":
            raise CaseFileError("friction.variation.x (friction along the track, varying across "
                                "a patch) needs solver.tangential = 'exact'")
    elif axis == "x":
        return None
    ok = isinstance(var, dict) and set(var) == {axis, "coefficient"}
    if ok:
        a, c = var[axis], var["coefficient"]
        ok = (isinstance(a, list) and isinstance(c, list) and len(a) == len(c) >= 1
              and all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
                      for v in a + c))
    if not ok:
        raise CaseFileError(f"friction.variation = {shown(var)}: expected a table with lists angle "
                            "[rad] (or x [m]) and coefficient of equal length")
    if any(b <= a for a, b in zip(var[axis], var[axis][1:])):
        raise CaseFileError(f"friction.variation.{axis} = {shown(var[axis])}: expected increasing "
                            + ("angles [rad]" if axis == "angle" else "positions [m]"))
    if any(not 0.0 <= c <= 5.0 for c in var["coefficient"]):
        raise CaseFileError(f"friction.variation.coefficient = {shown(var['coefficient'])}: expected "
                            "values in [0, 5]")
    return (tuple(float(a) for a in var[axis]), tuple(float(c) for c in var["coefficient"]))


def load_case(path) -> Case:
    """Read and validate a TOML case file."""
    path = Path(path)
    raw = read_toml(path, "case file")
    try:
        return case_from_dict(raw, path.parent)
    except CaseFileError as exc:
        raise CaseFileError(f"{path.name}: {exc}") from None
    except RailContactError:
        raise
