"""CONTACT's rules as one record: :class:`ContactRules`.

Where CONTACT's discretisation differs from railcontact's own (both converge to the
same answer as the grid is refined, or they answer the same question by another
convention), a case may follow CONTACT's rule instead of railcontact's.  The
rules are read once, where the case enters (:func:`parse_rules`, called by
:func:`railcontact.cases.case.case_from_dict`), from one preset and the individual
keys that override it (``docs/case_files.md``, "CONTACT's rules"):

- ``solver.rules = "railcontact"`` (the default) or ``"contact"`` (every rule of
  CONTACT's; a ``.inp`` input is mapped with it:
  :mod:`railcontact.contact_inp.mapping`);
- each rule's own key, which wins over the preset (the keys kept from before the
  record: ``wheelset.locus``, ``solver.contact_angle``,
  ``solver.reference_weights``, ``solver.search_grid``,
  ``solver.normal_options.wheel_sampling`` and ``rule`` (KPEC),
  ``solver.tangential_options.march`` and ``flexibility`` (FASTSIM),
  ``thermal.scheme``; and ``solver.surface_slip``, ``track.gauge_point``,
  ``roller.turn``).

The case carries the record (``Case.rules``); the layers below the case take the
rule values they follow as their own arguments (the models' options, the
wheelset's locus, the track's gauge rule, the surface search's weights), and a
path that follows none of them (the compiled pass) asks :meth:`ContactRules.
differing` once.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

from ..core.checks import shown
from ..core.errors import CaseFileError
from .keys import CaseKeys

#: the presets of ``solver.rules``
PRESETS = ("railcontact", "contact")


@dataclass(frozen=True)
class ContactRules:
    """Which of CONTACT's rules a case follows; each field railcontact's value by
    default, CONTACT's in :data:`CONTACT_RULES` (the ``solver.rules = "contact"``
    preset).

    Attributes
    ----------
    locus : {"lowest", "contact"}
        ``wheelset.locus``: the wheel points searched above the rail: each wheel
        circle's lowest point, or CONTACT's contact locus (its ``locus_prismatic``:
        :class:`railcontact.geometry.track.Wheelset`).
    contact_angle : {"local", "wheelset"}
        ``solver.contact_angle`` (cases on rail surfaces): a patch's angle from the
        rail's inclination at each of its points, or on the rail's cross-section at
        the wheelset's position (CONTACT's).
    reference_weights : {"surface", "locus"}
        ``solver.reference_weights`` (cases on rail surfaces): a patch's reference
        point and angle weight each cell of its interpenetration by g^2 (CONTACT's
        brute-force search, D = 5), or each lateral line at its lowest point by
        (-g)^2.5 (CONTACT's contact locus, D = 2, 3: the preset's).
    search_grid : {"fine", "contact"}
        ``solver.search_grid`` (cases on rail surfaces): the search's 0.2 x 0.075 mm
        mesh, or CONTACT's gap mesh of its brute-force search from
        ``solver.element_size`` (D = 5; the preset keeps "fine", the mesh of the
        contact locus).
    wheel_sampling : {"exact", "contact"}
        ``solver.normal_options.wheel_sampling`` (the exact normal model of a case
        with a wheel): the wheel's undeformed distance on its spline, or linear
        between profile samples one lateral element apart (CONTACT's
        ``m_wr_undefdist``: :class:`railcontact.geometry.gap.SampledWheelGap`).
    kpec : {"strips", "contact"}
        ``solver.normal_options.rule`` of KPEC: on railcontact's strips, or on
        CONTACT's grid elements with its ellipse correction.
    fastsim_march : {"strips", "grid"}
        ``solver.tangential_options.march`` of FASTSIM: along each strip from its
        leading edge, or over the elements of CONTACT's grid (modified FASTSIM).
    fastsim_flexibility : str
        ``solver.tangential_options.flexibility`` of FASTSIM: "blended"
        (railcontact's), "contact" (CONTACT's blend), or another of the model's
        ("three", "single": model choices, not rules).
    thermal_scheme : {"jaeger", "contact"}
        ``thermal.scheme``: Jaeger's moving heat source on the grid, or CONTACT's
        own-element weight.
    surface_slip : {"sections", "midplane"}
        ``solver.surface_slip`` (``solver.rigid_slip = "surfaces"``, CONTACT's D = 3):
        each body's velocity at its cross-section's apex (railcontact's:
        :func:`railcontact.geometry.surface_search.surface_slip`; a yawed sphere
        rolling on a plane gets the exact slip), or CONTACT's: at the surface points,
        turned onto the mid-plane in the (x, n) plane only
        (:func:`railcontact.geometry.surface_search.midplane_slip`; the yawed
        sphere's lateral slip off by about tan(psi) times its curvature slip).
    gauge_point : {"profile", "contact"}
        ``track.gauge_point``: where a rail placed by the gauge is measured: the
        profile's z(y) crossing the gauge height, or CONTACT's spline along the
        points' chord length (:func:`railcontact.geometry.track.contact_gauge_point`;
        a fraction of a micrometre apart on a steep gauge face).
    roller_turn : {"profile", "surface"}
        ``roller.turn`` (a roller with ``roller.profile_deviation``): the surface of
        the undeformed distance of a roller turned by its roll (DROLLR) and lowered:
        the turned profile revolved about the roller's axis, the surface of the
        contact search and of the roller's rotation (railcontact's: a flat profile
        turned becomes a cone), or CONTACT's (its ``m_wr_undefdist``): the roller as
        read turned as a whole about the profile origin, its axis tilted (a flat
        profile: a tilted cylinder, 1.3 um more undeformed distance 6 mm along x
        from the contact line at R = 0.4 m, 0.2 rad:
        :meth:`railcontact.geometry.surfaces.RollerSurface.gap_height`).
    """

    locus: str = "lowest"
    contact_angle: str = "local"
    reference_weights: str = "surface"
    search_grid: str = "fine"
    wheel_sampling: str = "exact"
    kpec: str = "strips"
    fastsim_march: str = "strips"
    fastsim_flexibility: str = "blended"
    thermal_scheme: str = "jaeger"
    surface_slip: str = "sections"
    gauge_point: str = "profile"
    roller_turn: str = "profile"

    def differing(self, among: tuple | None = None) -> tuple:
        """The names of the rules (of ``among``; None: all) on which this record
        differs from railcontact's, in field order (empty: railcontact's own
        throughout)."""
        return tuple(f.name for f in fields(self) if getattr(self, f.name) != f.default
                     and (among is None or f.name in among))

    def normal_options(self, normal: str, has_wheel: bool) -> dict:
        """The normal model's options these rules set (to merge under the case's
        own ``solver.normal_options``): KPEC's ``rule``, the exact model's
        ``wheel_sampling`` where the case has a wheel; each only where it differs
        from the model's default."""
        out = {}
        if normal == "kpec" and self.kpec != "strips":
            out["rule"] = self.kpec
        if normal == "exact" and has_wheel and self.wheel_sampling != "exact":
            out["wheel_sampling"] = self.wheel_sampling
        return out

    def tangential_options(self, tangential: str) -> dict:
        """The tangential model's options these rules set: FASTSIM's ``march`` and
        ``flexibility`` where they differ from the model's defaults."""
        out = {}
        if tangential == "fastsim":
            if self.fastsim_march != "strips":
                out["march"] = self.fastsim_march
            if self.fastsim_flexibility != "blended":
                out["flexibility"] = self.fastsim_flexibility
        return out


#: every rule of CONTACT's (``solver.rules = "contact"``): its contact locus (D = 2)
#: and angle, its wheel sampling, KPEC's and FASTSIM's grid rules, its temperature
#: scheme, its rigid slip on the surfaces (D = 3), gauge point and turned roller
CONTACT_RULES = ContactRules(locus="contact", contact_angle="wheelset",
                             reference_weights="locus", search_grid="fine",
                             wheel_sampling="contact", kpec="contact", fastsim_march="grid",
                             fastsim_flexibility="contact", thermal_scheme="contact",
                             surface_slip="midplane", gauge_point="contact",
                             roller_turn="surface")

#: each rule: its case key (dotted) and the values it takes with what they mean
#: (``None``: a model's option, checked when the model is built, or
#: ``thermal.scheme``, checked with the other ``[thermal]`` keys)
_KEYS = {
    "locus": ("wheelset.locus", {
        "lowest": "each wheel circle's lowest point above the rail",
        "contact": "CONTACT's contact locus"}),
    "contact_angle": ("solver.contact_angle", {
        "local": "the rail's inclination at each point of the patch",
        "wheelset": "on its cross-section at the wheelset's position, as CONTACT"}),
    "reference_weights": ("solver.reference_weights", {
        "surface": "each cell of the interpenetration with g^2, CONTACT's D = 5",
        "locus": "each lateral line at its lowest point with (-g)^2.5, CONTACT's "
                 "contact locus, D = 2, 3"}),
    "search_grid": ("solver.search_grid", {
        "fine": "0.2 x 0.075 mm",
        "contact": "CONTACT's gap mesh of its brute-force search, from "
                   "solver.element_size"}),
    "wheel_sampling": ("solver.normal_options.wheel_sampling", None),
    "kpec": ("solver.normal_options.rule", None),
    "fastsim_march": ("solver.tangential_options.march", None),
    "fastsim_flexibility": ("solver.tangential_options.flexibility", None),
    "thermal_scheme": ("thermal.scheme", None),
    "surface_slip": ("solver.surface_slip", {
        "sections": "each body's velocity at its cross-section's apex",
        "midplane": "CONTACT's: at the surface points, turned onto the mid-plane in "
                    "the (x, n) plane"}),
    "gauge_point": ("track.gauge_point", {
        "profile": "the profile's z(y) crossing the gauge height",
        "contact": "CONTACT's spline along the points' chord length"}),
    "roller_turn": ("roller.turn", {
        "profile": "the turned profile revolved about the roller's axis",
        "surface": "CONTACT's: the roller as read turned as a whole, its axis tilted"}),
}


def _choice(keys: CaseKeys, key: str, default: str, choices: dict) -> str:
    v = keys.get(key, default)
    if not isinstance(v, str) or v not in choices:
        expected = " or ".join(f"{k!r} ({m})" for k, m in choices.items())
        raise CaseFileError(f"{key} = {shown(v)}: expected {expected}")
    return v


def parse_rules(keys: CaseKeys, normal: str = "hertz", tangential: str = "fastsim"
                ) -> ContactRules:
    """The case's :class:`ContactRules`: ``solver.rules`` (``"railcontact"``, the
    default, or ``"contact"``) and each rule's own key over it.  The model options
    among them (``wheel_sampling`` and ``rule`` of the normal model ``normal``,
    FASTSIM's ``march`` and ``flexibility`` for ``tangential``) are read where that
    model is the case's, and checked when the model is built; the other keys are
    checked here.  A :class:`~railcontact.core.errors.CaseFileError` names the
    first key that is wrong."""
    preset = keys.get("solver.rules", "railcontact")
    if not isinstance(preset, str) or preset not in PRESETS:
        raise CaseFileError(f"solver.rules = {shown(preset)}: expected 'railcontact' "
                            "(railcontact's own rules) or 'contact' (CONTACT's: its contact "
                            "locus and angle, wheel sampling, KPEC's and FASTSIM's grid "
                            "rules, temperature scheme, rigid slip on the surfaces, "
                            "gauge point and turned roller's undeformed distance)")
    base = CONTACT_RULES if preset == "contact" else ContactRules()
    values = {}
    model_of = {"wheel_sampling": normal == "exact", "kpec": normal == "kpec",
                "fastsim_march": tangential == "fastsim",
                "fastsim_flexibility": tangential == "fastsim"}
    for name, (key, choices) in _KEYS.items():
        default = getattr(base, name)
        if name in model_of:
            values[name] = keys.get(key, default) if model_of[name] else default
        elif choices is None:
            values[name] = keys.get(key, default)       # thermal.scheme: see _thermal
        else:
            values[name] = _choice(keys, key, default, choices)
    return ContactRules(**values)
