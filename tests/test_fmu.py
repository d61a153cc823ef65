"""The contact element's FMI 3.0 co-simulation FMU, driven by a real FMI client
(FMPy): built once per session by ``railcontact fmu``, validated, simulated through
a time history with its outputs equal to the Python API's
(:class:`~railcontact.dynamics.contact_element.ContactElement`) to 1e-9."""

import logging
import time
import zipfile

import numpy as np
import pytest

pytest.importorskip("pythonfmu3")
fmpy = pytest.importorskip("fmpy")

from railcontact.cli import main                                     # noqa: E402
from railcontact.dynamics.contact_element import WheelsetState  # noqa: E402
from railcontact.inputs import contact_element  # noqa: E402
from railcontact.fmu import INPUTS, OUTPUTS, build_fmu      # noqa: E402
from railcontact.core.errors import InputError                       # noqa: E402

log = logging.getLogger(__name__)


@pytest.fixture(scope="session")
def fmu_file(tmp_path_factory):
    """The FMU written by ``railcontact fmu`` (default parameters: S1002 on 60E1,
    Hertz + FASTSIM, position mode)."""
    path = tmp_path_factory.mktemp("fmu") / "element.fmu"
    assert main(["fmu", "--out", str(path)]) == 0
    return path


def _history(n=21, dt=0.01):
    """A hunting-like time history of the inputs: lateral shift 3 mm and yaw 1 mrad at
    5 Hz, the vertical position and roll that keep both wheels in contact, velocities
    consistent with them; forward speed 30 m/s."""
    t = np.arange(n) * dt
    w = 2 * np.pi * 5.0
    names = [name for name, *_ in INPUTS]
    sig = np.zeros(n, dtype=[("time", float)] + [(k, float) for k in names])
    sig["time"] = t
    sig["lateral_shift"] = 3e-3 * np.sin(w * t)
    sig["lateral_velocity"] = 3e-3 * w * np.cos(w * t)
    sig["yaw"] = 1e-3 * np.cos(w * t)
    sig["yaw_rate"] = -1e-3 * w * np.sin(w * t)
    sig["vertical_position"] = 3.0e-4
    sig["roll"] = -1e-4 * np.sin(w * t)
    sig["roll_rate"] = -1e-4 * w * np.cos(w * t)
    sig["velocity"] = 30.0
    sig["pitch_velocity"] = -30.0 / 0.46
    sig["load_left"] = sig["load_right"] = 70e3
    return sig


def _state(row, pure_rolling=True, load=False):
    return WheelsetState(
        lateral_shift=row["lateral_shift"], vertical_position=row["vertical_position"],
        roll=row["roll"], yaw=row["yaw"], lateral_velocity=row["lateral_velocity"],
        vertical_velocity=row["vertical_velocity"], roll_rate=row["roll_rate"],
        yaw_rate=row["yaw_rate"], velocity=row["velocity"],
        pitch_velocity=None if pure_rolling else row["pitch_velocity"],
        loads=(row["load_left"], row["load_right"]) if load else None)


def _expected(element, sig, **kw):
    """The API's outputs at the communication points: after exitInitializationMode the
    forces at the first inputs, after doStep(t_k, h) those at the inputs of t_k."""
    res = [element.evaluate(_state(row, **kw)) for row in sig]
    res = [res[0]] + res[:-1]
    out = {}
    for i, c in enumerate("xyz"):
        out[f"force_{c}"] = [r.force[i] for r in res]
        out[f"torque_{c}"] = [r.torque[i] for r in res]
        for s in ("left", "right"):
            out[f"{s}_force_{c}"] = [r.side_force[s][i] for r in res]
            out[f"{s}_torque_{c}"] = [r.side_torque[s][i] for r in res]
    for s in ("left", "right"):
        out[f"{s}_normal_force"] = [r.normal_force[s] for r in res]
    out["pose_vertical_position"] = [r.pose.vertical for r in res]
    out["pose_roll"] = [r.pose.roll for r in res]
    return {k: np.array(v) for k, v in out.items()}


def test_fmu_validates_and_describes_its_variables(fmu_file):
    from fmpy import read_model_description
    from fmpy.validation import validate_fmu
    assert validate_fmu(str(fmu_file)) == []
    md = read_model_description(str(fmu_file))
    assert md.fmiVersion == "3.0" and md.coSimulation is not None
    var = {v.name: v for v in md.modelVariables}
    for name, unit, *_ in INPUTS:
        assert var[name].causality == "input" and var[name].unit == unit
    for name, unit, _ in OUTPUTS:
        assert var[name].causality == "output" and var[name].unit == unit
    assert var["normal_model"].causality == "parameter" and var["normal_model"].type == "String"
    with zipfile.ZipFile(fmu_file) as z:
        names = z.namelist()
    assert "binaries/x86_64-linux/RailContactElement.so" in names
    assert any(n.startswith("resources/railcontact_element_") for n in names)


def test_fmu_time_history_equals_the_api(fmu_file):
    sig = _history()
    dt = sig["time"][1] - sig["time"][0]
    outputs = [name for name, *_ in OUTPUTS if name != "patch_count"]
    t0 = time.perf_counter()
    res = fmpy.simulate_fmu(str(fmu_file), start_time=0.0, stop_time=sig["time"][-1],
                            output_interval=dt, input=sig, output=outputs)
    wall = time.perf_counter() - t0
    log.info("FMPy: %d steps in %.3f s (%.2f ms per step, with set-up)", sig.size - 1, wall,
             wall / (sig.size - 1) * 1e3)
    assert res.size == sig.size
    np.testing.assert_allclose(res["time"], sig["time"], rtol=0, atol=1e-12)
    exp = _expected(contact_element(), sig)
    # the history runs through contact: both wheels loaded, forces that change
    assert np.all(exp["left_normal_force"][1:] > 1e3) and np.all(exp["right_normal_force"] > 1e3)
    assert np.ptp(exp["force_y"]) > 1e3
    for name in outputs:
        scale = 1.0 if name.startswith(("pose", "torque", "left_t", "right_t")) else 1e5
        np.testing.assert_allclose(res[name], exp[name], rtol=1e-9, atol=1e-9 * scale,
                                   err_msg=name)


@pytest.mark.parametrize("built", [False, True])
def test_fmu_parameters_load_mode_and_model_pair(fmu_file, tmp_path, built):
    """The load mode with Kalker's linear theory, against the API with the same pair:
    set through the String parameters at instantiation, or built into a second FMU
    by ``railcontact fmu --mode load --tangential linear`` (loaded into the process
    after the first: the two must not share their configuration)."""
    sig = _history(n=6)
    dt = sig["time"][1] - sig["time"][0]
    start = {"pure_rolling": False}
    if built:
        path = tmp_path / "load.fmu"
        assert main(["fmu", "--mode", "load", "--tangential", "linear", "--out", str(path)]) == 0
    else:
        path = fmu_file
        start.update({"mode": "load", "tangential_model": "linear"})
    res = fmpy.simulate_fmu(str(path), start_time=0.0, stop_time=sig["time"][-1],
                            output_interval=dt, input=sig, start_values=start,
                            output=["force_x", "force_y", "force_z", "torque_z",
                                    "pose_vertical_position", "pose_roll"])
    el = contact_element(tangential="linear", mode="load")
    exp = _expected(el, sig, pure_rolling=False, load=True)
    for name in ("force_x", "force_y", "force_z", "torque_z"):
        np.testing.assert_allclose(res[name], exp[name], rtol=1e-9, atol=1e-4, err_msg=name)
    np.testing.assert_allclose(res["pose_vertical_position"], exp["pose_vertical_position"],
                               rtol=1e-9)
    # the loads are met
    np.testing.assert_allclose(res["force_z"], -140e3, rtol=1e-4)


def test_fmu_cli_errors(tmp_path, capsys):
    assert main(["fmu", "--out", str(tmp_path / "x.fmu"), "--normal", "nonsense"]) == 2
    assert "nonsense" in capsys.readouterr().err
    with pytest.raises(InputError, match=r"\.fmu"):
        build_fmu(tmp_path / "x.zip")
    with pytest.raises(InputError, match="parameters"):
        build_fmu(tmp_path / "y.fmu", {"gague": 1.435})
