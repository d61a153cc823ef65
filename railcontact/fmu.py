"""The contact element as an FMI 3.0 co-simulation FMU (``railcontact fmu``).

:class:`ContactElementSlave` exposes :class:`~railcontact.dynamics.contact_element.ContactElement`
through `pythonfmu3 <https://github.com/NTNU-IHB/PythonFMU3>`_'s ``Fmi3Slave``:
the wheelset's pose and motion relative to the track are its inputs, the forces
and torques of both rails on the wheelset its outputs, the profiles, material,
friction and model pair its parameters.  :func:`build_fmu` writes the FMU: a
small generated script whose class derives from :class:`ContactElementSlave`
with the chosen parameters as start values, packed by pythonfmu3 with its
FMI 3.0 binary (x86_64 Linux and Windows).

The FMU runs railcontact in the Python interpreter that loads it: that
interpreter (an FMI tool's embedded one, or the tool's process with the
``libpython`` of the environment preloaded) needs railcontact and its
dependencies installed.  What the FMU needs at run time, its variables and how a
Modelica tool calls it: ``docs/multibody.md``.

Every communication step evaluates the element at the inputs set before the
step (the element has no state of its own: its outputs after ``doStep(t, h)``
are the forces at the inputs of time t), so a step's cost is one
:meth:`ContactElement.evaluate`.  This module is also the FMU's script, and uses
absolute imports for that reason.
"""

from __future__ import annotations

import hashlib
import logging
import math
import shutil
import tempfile
from pathlib import Path

from pythonfmu3 import (Boolean, Float64, Fmi3Causality, Fmi3Slave, Fmi3Variability, FmuBuilder,
                        String, Unit)

from railcontact.cases.case import case_from_dict, load_case
from railcontact.dynamics.contact_element import MODES, ContactElement, WheelsetState
from railcontact.core.errors import InputError
from railcontact.profiles.library import DEFAULT_INCLINATION

log = logging.getLogger(__name__)

#: the FMU's model name (and model identifier)
MODEL_NAME = "RailContactElement"

#: inputs: name, unit, start value, description
INPUTS = (
    ("lateral_shift", "m", 0.0, "wheelset lateral displacement y relative to the track, "
                                "positive to the right"),
    ("vertical_position", "m", 0.0, "wheelset vertical position z, positive down, 0 with the "
                                    "axle r0 above the track plane (mode 'position')"),
    ("roll", "rad", 0.0, "roll angle about +x, positive lowers the right wheel "
                         "(mode 'position')"),
    ("yaw", "rad", 0.0, "yaw angle about +z, positive turns the front to the right"),
    ("lateral_velocity", "m/s", 0.0, "dy/dt"),
    ("vertical_velocity", "m/s", 0.0, "dz/dt (mode 'position')"),
    ("roll_rate", "rad/s", 0.0, "d(roll)/dt (mode 'position')"),
    ("yaw_rate", "rad/s", 0.0, "d(yaw)/dt"),
    ("velocity", "m/s", 30.0, "forward speed V, > 0"),
    ("pitch_velocity", "rad/s", -30.0 / 0.46, "wheelset angular velocity about its axle, "
                                              "negative rolling forward (used where "
                                              "pure_rolling is false)"),
    ("load_left", "N", 70e3, "vertical load of the left wheel (mode 'load')"),
    ("load_right", "N", 70e3, "vertical load of the right wheel (mode 'load')"),
)

#: outputs: name, unit, description
OUTPUTS = tuple(
    [(f"force_{c}", "N", f"total force of the rails on the wheelset, track {c}")
     for c in "xyz"]
    + [(f"torque_{c}", "N.m", f"total torque on the wheelset about its centre, track {c}")
       for c in "xyz"]
    + [(f"{s}_force_{c}", "N", f"force of the {s} rail on the wheelset, track {c}")
       for s in ("left", "right") for c in "xyz"]
    + [(f"{s}_torque_{c}", "N.m", f"torque of the {s} rail about the wheelset centre, track {c}")
       for s in ("left", "right") for c in "xyz"]
    + [(f"{s}_normal_force", "N", f"sum of the {s} wheel's patches' normal forces")
       for s in ("left", "right")]
    + [("pose_vertical_position", "m", "the wheelset's vertical position (given, or solved in "
                                      "mode 'load')"),
       ("pose_roll", "rad", "the wheelset's roll (given, or solved in mode 'load')"),
       ("patch_count", "1", "number of loaded contact patches")])

#: string parameters: name, default, description
STRING_PARAMETERS = (
    ("case_file", "", "a wheel-rail case file (TOML) giving profiles, dimensions, material, "
                      "friction and solver; when set, the parameters below except mode and "
                      "the model names are not used"),
    ("wheel_profile", "S1002", "wheel profile: built-in name or file path"),
    ("rail_profile", "60E1", "rail profile: built-in name or file path"),
    ("normal_model", "", "registered normal model ('': the case file's, else hertz)"),
    ("tangential_model", "", "registered tangential model ('': the case file's, else "
                             "fastsim; 'none': normal forces only)"),
    ("mode", "position", "'position': z and roll are inputs (elastic contact); 'load': the "
                         "wheel loads are inputs, z and roll solved"),
)

#: float parameters: name, unit, default, case key, description
FLOAT_PARAMETERS = (
    ("friction", "1", 0.3, "friction.coefficient", "friction coefficient"),
    ("nominal_radius", "m", 0.46, "wheel.nominal_radius", "wheel nominal radius r0"),
    ("rail_inclination", "rad", DEFAULT_INCLINATION, "rail.inclination",
     "rail inclination, for a built-in profile and a profile file alike (default 1:40; "
     "a file as mounted: 0)"),
    ("gauge", "m", 1.435, "track.gauge", "track gauge"),
    ("flange_back_distance", "m", 1.360, "wheelset.flange_back_distance",
     "distance between the flange backs"),
    ("young_modulus", "Pa", 2.1e11, "material.young_modulus", "Young's modulus of both bodies"),
    ("poisson_ratio", "1", 0.28, "material.poisson_ratio", "Poisson's ratio of both bodies"),
)

_UNITS = {"s": {"s": 1}, "m": {"m": 1}, "rad": {"rad": 1}, "m/s": {"m": 1, "s": -1},
          "rad/s": {"rad": 1, "s": -1}, "N": {"kg": 1, "m": 1, "s": -2},
          "N.m": {"kg": 1, "m": 2, "s": -2}, "Pa": {"kg": 1, "m": -1, "s": -2}, "1": {}}


def element_case(values: dict) -> dict:
    """The wheel-rail case (a dict of ``docs/case_files.md``) that the parameter
    values ``values`` (name -> value, the FMU's parameters) describe; a case file
    is read as it is, with the model names set where given."""
    if values.get("case_file"):
        raw = dict(load_case(values["case_file"]).raw)
        raw["solver"] = dict(raw.get("solver", {}))
    else:
        raw = {"wheel": {"profile": values["wheel_profile"]},
               "rail": {"profile": values["rail_profile"]}, "solver": {}}
        for name, _, _, key, _ in FLOAT_PARAMETERS:
            table, k = key.split(".")
            raw.setdefault(table, {})[k] = float(values[name])
    for name, key in (("normal_model", "normal"), ("tangential_model", "tangential")):
        if values.get(name):
            raw["solver"][key] = values[name]
    raw.pop("creepage", None)
    return raw


class ContactElementSlave(Fmi3Slave):
    """FMI 3.0 co-simulation slave of the contact element (variables: :data:`INPUTS`,
    :data:`OUTPUTS`, :data:`STRING_PARAMETERS`, :data:`FLOAT_PARAMETERS` and the
    Boolean ``pure_rolling``, true: the pitch velocity is −V/r0 and the
    ``pitch_velocity`` input is not used).  ``START`` (class attribute): start
    values of the parameters that differ from the defaults (:func:`build_fmu`)."""

    START: dict = {}

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.author = "railcontact"
        self.description = ("Wheel-rail contact element: forces and torques of both rails on "
                            "a wheelset from its pose and motion (railcontact)")
        self.register_units([Unit(n, **dims) for n, dims in _UNITS.items()])
        self.time = 0.0
        self.register_variable(Float64("time", causality=Fmi3Causality.independent,
                                       variability=Fmi3Variability.continuous, unit="s"))
        start = {n: d for n, d, _ in STRING_PARAMETERS}
        start.update({n: d for n, _, d, _, _ in FLOAT_PARAMETERS})
        start["pure_rolling"] = True
        unknown = set(self.START) - set(start)
        if unknown:
            raise InputError(f"FMU start values {sorted(unknown)}: expected parameters among "
                             f"{sorted(start)}")
        start.update(self.START)
        for name, default, desc in STRING_PARAMETERS:
            setattr(self, name, str(start[name]))
            self.register_variable(String(name, causality=Fmi3Causality.parameter,
                                          variability=Fmi3Variability.fixed, description=desc))
        for name, unit, _, _, desc in FLOAT_PARAMETERS:
            setattr(self, name, float(start[name]))
            self.register_variable(Float64(name, causality=Fmi3Causality.parameter,
                                           variability=Fmi3Variability.fixed, unit=unit,
                                           description=desc))
        self.pure_rolling = bool(start["pure_rolling"])
        self.register_variable(Boolean("pure_rolling", causality=Fmi3Causality.parameter,
                                       variability=Fmi3Variability.fixed,
                                       description="pitch velocity -V/r0 (the pitch_velocity "
                                                   "input not used)"))
        for name, unit, value, desc in INPUTS:
            setattr(self, name, float(value))
            self.register_variable(Float64(name, causality=Fmi3Causality.input,
                                           variability=Fmi3Variability.continuous, unit=unit,
                                           description=desc))
        for name, unit, desc in OUTPUTS:
            setattr(self, name, 0.0)
            self.register_variable(Float64(name, causality=Fmi3Causality.output,
                                           variability=Fmi3Variability.continuous, unit=unit,
                                           description=desc))
        self.converged = True
        self.register_variable(Boolean("converged", causality=Fmi3Causality.output,
                                       variability=Fmi3Variability.discrete,
                                       description="every model (and in mode 'load' the "
                                                   "vertical balance) converged"))
        self.element = None

    def parameter_values(self) -> dict:
        """The parameters' current values by name."""
        names = ([n for n, _, _ in STRING_PARAMETERS] + [n for n, *_ in FLOAT_PARAMETERS]
                 + ["pure_rolling"])
        return {n: getattr(self, n) for n in names}

    def state(self) -> WheelsetState:
        """The inputs' current values as a :class:`WheelsetState`."""
        return WheelsetState(
            lateral_shift=self.lateral_shift, vertical_position=self.vertical_position,
            roll=self.roll, yaw=self.yaw, lateral_velocity=self.lateral_velocity,
            vertical_velocity=self.vertical_velocity, roll_rate=self.roll_rate,
            yaw_rate=self.yaw_rate, velocity=self.velocity,
            pitch_velocity=None if self.pure_rolling else self.pitch_velocity,
            loads=(self.load_left, self.load_right) if self.mode == "load" else None)

    def exit_initialization_mode(self):
        if self.mode not in MODES:
            raise InputError(f"FMU parameter mode = {self.mode!r}: expected one of {MODES}")
        base = Path(self.case_file).parent if self.case_file else None
        case = case_from_dict(element_case(self.parameter_values()), base)
        self.element = ContactElement(case, mode=self.mode)
        self._update()

    def _update(self):
        res = self.element.evaluate(self.state())
        for c, i in zip("xyz", range(3)):
            setattr(self, f"force_{c}", float(res.force[i]))
            setattr(self, f"torque_{c}", float(res.torque[i]))
            for s in ("left", "right"):
                setattr(self, f"{s}_force_{c}", float(res.side_force[s][i]))
                setattr(self, f"{s}_torque_{c}", float(res.side_torque[s][i]))
        for s in ("left", "right"):
            setattr(self, f"{s}_normal_force", float(res.normal_force[s]))
        self.pose_vertical_position = float(res.pose.vertical)
        self.pose_roll = float(res.pose.roll)
        self.patch_count = float(len(res.patches))
        self.converged = bool(res.converged)

    def do_step(self, current_time, step_size):
        self._update()
        self.time = current_time + step_size
        return True


def build_fmu(dest, parameters: dict | None = None) -> Path:
    """Write the contact element's FMU.

    Parameters
    ----------
    dest : path
        The FMU file to write (``.fmu``), or an existing folder (then
        ``RailContactElement.fmu`` in it).
    parameters : dict, optional
        Start values of the FMU's parameters (:data:`STRING_PARAMETERS`,
        :data:`FLOAT_PARAMETERS`, ``pure_rolling``) that differ from the defaults;
        they are checked by building the element once here (profiles found, model
        names registered).

    Returns
    -------
    Path of the FMU written.
    """
    params = dict(parameters or {})
    defaults = {n: d for n, d, _ in STRING_PARAMETERS}
    defaults.update({n: d for n, _, d, _, _ in FLOAT_PARAMETERS})
    defaults["pure_rolling"] = True
    unknown = set(params) - set(defaults)
    if unknown:
        raise InputError(f"FMU parameters {sorted(unknown)}: expected names among "
                         f"{sorted(defaults)}")
    values = {**defaults, **params}
    if values["mode"] not in MODES:
        raise InputError(f"FMU parameter mode = {values['mode']!r}: expected one of {MODES}")
    if values["case_file"]:
        values["case_file"] = str(Path(values["case_file"]).resolve())
        params["case_file"] = values["case_file"]
    for name, _, _, _, _ in FLOAT_PARAMETERS:
        if not math.isfinite(float(values[name])):
            raise InputError(f"FMU parameter {name} = {values[name]!r}: expected a finite number")
    base = Path(values["case_file"]).parent if values["case_file"] else None
    ContactElement(case_from_dict(element_case(values), base), mode=values["mode"])
    dest = Path(dest)
    target = dest / f"{MODEL_NAME}.fmu" if dest.is_dir() else dest
    if target.suffix != ".fmu":
        raise InputError(f"FMU destination {str(dest)!r}: expected a .fmu file or a folder")
    script = (f'"""railcontact\'s contact element (written by railcontact fmu)."""\n'
              f"from pythonfmu3 import Fmi3Slave\n"
              f"from railcontact.fmu import ContactElementSlave\n\n\n"
              f"class {MODEL_NAME}(ContactElementSlave, Fmi3Slave):\n"
              f"    START = {params!r}\n")
    with tempfile.TemporaryDirectory(prefix="railcontact_fmu_") as tmp:
        # the script's module name differs between configurations: two FMUs of the
        # element loaded into one process must not share one imported module
        digest = hashlib.sha1(repr(sorted(params.items())).encode()).hexdigest()[:12]
        path = Path(tmp) / f"railcontact_element_{digest}.py"
        path.write_text(script)
        built = FmuBuilder.build_FMU(path, dest=Path(tmp) / "out")
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.move(str(built), target)
    log.info("FMU written to %s", target)
    return target
