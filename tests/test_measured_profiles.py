"""Measured MiniProf and SIMPACK profiles of CONTACT's testbank, read, mirrored,
smoothed and solved from case files, on the tread and in flange contact.

The options are those CONTACT's own testbank gives these files (mirror_y for the
rails measured with the track centre to the right, mirror_z for the guard rail,
lambda = 10 mm^3 of the unweighted spline for the MiniProf wheels); the wheelset
of North American heavy haul (back-to-back 1347.4 mm, gauge 1435.1 mm measured
15.875 mm below the top, wheel radius 431.8 mm at the flange back's origin).
"""

import math

import numpy as np
import pytest

import railcontact as rc
from railcontact.profiles import ProfileOptions, Smoothing, read_profile
from railcontact.profiles.processing import remove_zigzags

LAMBDA = 1e-8                      # 10 mm^3: CONTACT's SMOOTH = 10 with ISMOOTH = 0
WHEELS = ["Car7216_0001r.whl", "Car7358_0001r.whl", "Car7422_0001r.whl",
          "Car7813_0001r.whl", "avg_wheel.whl"]
RAILS = {"avg_HR.BAN": {"mirror_y": True}, "avg_low2.ban": {"mirror_y": True},
         "guard_rail_test.ban": {"mirror_y": True, "mirror_z": True},
         "site_b_hr.prr": {"mirror_y": False}}


@pytest.fixture(scope="module")
def prof(testbank):
    return testbank / "profiles"


def test_every_measured_profile_is_read(prof):
    for w in WHEELS:
        p = read_profile(prof / w, options=ProfileOptions(mirror_y=False))
        assert p.kind == "wheel" and np.all(np.diff(p.y) > 0)
        # the flange (largest z, away from the axle) near the flange back at y ~ 0
        assert p.y[np.argmax(p.z)] < 0.03 and 0.025 < p.z.max() - p.z_at(0.07) < 0.04
    for r, opts in RAILS.items():
        p = read_profile(prof / r, options=ProfileOptions(**opts))
        assert p.kind == "rail" and np.all(np.diff(p.y) > 0)
        if r != "guard_rail_test.ban":
            # z down into the head: its gauge face reaches down from the top
            assert p.z[0] > p.z.min() + 0.01 and p.z[-1] > p.z.min()
    # the guard rail lies at the track centre side of the running rail, the groove
    # between them 40-50 mm deep
    g = read_profile(prof / "guard_rail_test.ban", options=ProfileOptions(**RAILS[
        "guard_rail_test.ban"]))
    groove = (g.y > -0.05) & (g.y < 0.0)
    assert 0.04 < g.z[groove].max() < 0.05 and g.z[g.y < -0.06].min() < 0.005


def test_left_side_measurements_need_mirroring(prof):
    """avg_HR.BAN is measured with the track centre at positive y: as read, its
    gauge face lies at the larger y; mirrored, at the smaller, as a right rail's."""
    as_is = read_profile(prof / "avg_HR.BAN", options=ProfileOptions(mirror_y=False))
    right = read_profile(prof / "avg_HR.BAN", options=ProfileOptions(mirror_y=True))
    for p, sign in ((as_is, 1.0), (right, -1.0)):
        deep = p.y[p.z > p.z.min() + 0.015]          # the gauge face below the head
        assert np.all(sign * deep > sign * p.y[np.argmin(p.z)])


def test_data_repairs(prof):
    """The stitched point of avg_HR.BAN (29.27 / 29.26 mm) is one zig-zag; the
    annotated lines of avg_low2.ban and guard_rail_test.ban (comments after '"')
    and the old-style header of Car7422_0001r.whl are read."""
    from railcontact.profiles.io import _read_miniprof
    y, z, *_ = _read_miniprof(prof / "avg_HR.BAN")
    assert remove_zigzags(y, z)[2] == 1
    n = {f: _read_miniprof(prof / f)[0].size for f in ("avg_low2.ban", "guard_rail_test.ban",
                                                       "Car7422_0001r.whl")}
    assert n == {"avg_low2.ban": 526, "guard_rail_test.ban": 1065, "Car7422_0001r.whl": 644}


@pytest.mark.parametrize("wheel", WHEELS)
def test_smoothing_moves_the_flange_less_than_contact_does(prof, wheel):
    """CONTACT's smoothing of these wheels (lambda = 10 mm^3) moves their flanges by
    at most 0.28 mm; railcontact's spline along the arc length with the same
    lambda moves the flange points (z beyond 5 mm) by at most 0.212 mm (measured:
    Car7216 0.212, Car7358 0.069, Car7422 0.187, Car7813 0.142, avg_wheel 0.086)."""
    from scipy.spatial import cKDTree
    raw = read_profile(prof / wheel, options=ProfileOptions(mirror_y=False))
    sm = read_profile(prof / wheel, options=ProfileOptions(
        mirror_y=False, smoothing=Smoothing("unweighted", LAMBDA)))
    yy = np.linspace(sm.y_min, sm.y_max, 100000)
    tree = cKDTree(np.c_[yy, sm.z_at(yy)])
    flange = raw.z > 5e-3
    d, _ = tree.query(np.c_[raw.y[flange], raw.z[flange]])
    assert d.max() <= 0.28e-3
    assert 1e-6 < np.sqrt(np.mean(d ** 2)) < 0.05e-3          # it does smooth


def _case(prof, wheel, rail, y, smooth=True, **extra):
    sm = {"smoothing": {"method": "unweighted", "lambda": LAMBDA}} if smooth else {}
    raw = {"material": {"young_modulus": 2 * 82e9 * 1.28},
           "friction": {"coefficient": 0.35},
           "wheel": {"profile": str(prof / wheel), "mirror_y": False, "nominal_radius": 0.4318,
                     **sm},
           "rail": {"profile": str(prof / rail), **RAILS[rail], **sm},
           "track": {"gauge": 1.4351, "gauge_height": 0.015875},
           "wheelset": {"flange_back_distance": 1.3474, "flange_back_position": 0.0,
                        "lateral_shift": y, "vertical_force": 60e3, "velocity": 10.0,
                        "pitch_velocity": -10.0 / 0.4318 * 1.001, "side": "right",
                        "roll": 0.0, "combine_distance": 8e-3,
                        "full_interaction_distance": 4e-3, "turn_distance": 12e-3},
           "solver": {"normal": "exact", "tangential": "exact",
                      "element_size": [5e-4, 5e-4]}}
    for k, v in extra.items():
        raw[k].update(v)
    return raw


def _write_toml(path, raw):
    """A minimal TOML writer for these case dictionaries."""
    def val(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return f'"{v}"'
        if isinstance(v, dict):
            return "{" + ", ".join(f"{k} = {val(x)}" for k, x in v.items()) + "}"
        if isinstance(v, list):
            return "[" + ", ".join(val(x) for x in v) + "]"
        return repr(v)
    lines = []
    for sec, table in raw.items():
        lines.append(f"[{sec}]")
        lines += [f"{k} = {val(v)}" for k, v in table.items()]
    path.write_text("\n".join(lines) + "\n")
    return path


#: wheel, rail, lateral shift [m] on the tread and in flange contact
PAIRS = [("avg_wheel.whl", "avg_HR.BAN", 8e-3, 18e-3),
         ("Car7216_0001r.whl", "avg_low2.ban", 4e-3, 13e-3),
         ("Car7358_0001r.whl", "site_b_hr.prr", 8e-3, 16e-3),
         ("Car7422_0001r.whl", "avg_HR.BAN", 6e-3, 17e-3)]


@pytest.mark.parametrize("wheel, rail, tread, flange", PAIRS)
def test_solved_from_a_case_file(prof, tmp_path, wheel, rail, tread, flange):
    """Each pair on the tread and in flange contact (contact angle beyond 0.9 rad),
    smoothed as CONTACT's testbank smooths them: the load is met, the exact
    solvers converge, the creep forces stay within friction."""
    for y, flanged in ((tread, False), (flange, True)):
        path = _write_toml(tmp_path / "case.toml", _case(prof, wheel, rail, y))
        res = rc.solve(rc.load_case(path))
        assert res.converged, res.status.message
        angles = [p.geometry.contact_angle for p in res.patches]
        if flanged:
            assert min(angles) < -0.9
        else:
            assert max(abs(a) for a in angles) < 0.2
        for p in res.patches:
            t = p.tangential
            assert math.hypot(t.fx, t.fy) <= 0.35 * p.normal.normal_force * (1 + 1e-6)
            assert not any("edge" in w for w in p.normal.status.warnings)


@pytest.mark.parametrize("wheel, rail, y", [("avg_wheel.whl", "avg_HR.BAN", 18e-3),
                                            ("Car7216_0001r.whl", "avg_low2.ban", 13e-3)])
def test_raw_profiles_in_flange_contact(prof, wheel, rail, y):
    """Unsmoothed measurements in flange contact: the vertical balance converges
    and no patch's contact reaches the edge of its potential area."""
    res = rc.solve(rc.case_from_dict(_case(prof, wheel, rail, y, smooth=False)))
    assert res.converged, res.status.message
    assert min(p.geometry.contact_angle for p in res.patches) < -0.9
    assert abs(res.balance.residual["right"]) <= 1e-4


def test_guard_rail(prof):
    """guard_rail_test.ban: a running rail with a guard rail beside it, placed by
    its origin (track.rail_offset: by the gauge the guard rail's face would be
    taken for the gauge face); the Car7813 wheel on the running rail's tread and
    flange."""
    for y, flanged in ((0.0, False), (16e-3, True)):
        raw = _case(prof, "Car7813_0001r.whl", "guard_rail_test.ban", y,
                    track={"rail_offset": 0.71756})
        del raw["track"]["gauge"], raw["track"]["gauge_height"]
        res = rc.solve(rc.case_from_dict(raw))
        assert res.converged, res.status.message
        a = [p.geometry.contact_angle for p in res.patches]
        assert (min(a) < -0.9) if flanged else (max(abs(v) for v in a) < 0.2)


def test_case_file_options_are_checked(prof, tmp_path):
    raw = _case(prof, "avg_wheel.whl", "avg_HR.BAN", 8e-3)
    raw["rail"]["smoothing"] = {"method": "cubic", "lambda": 1.0}
    with pytest.raises(rc.CaseFileError, match="smoothing method 'cubic'"):
        rc.case_from_dict(raw)
    raw = _case(prof, "avg_wheel.whl", "avg_HR.BAN", 8e-3)
    raw["wheel"]["profile"] = "S1002"
    with pytest.raises(rc.ProfileError, match="built in"):
        rc.solve(rc.case_from_dict(raw))
    raw = _case(prof, "avg_wheel.whl", "avg_HR.BAN", 8e-3)
    raw["wheelset"]["turn_distance"] = 5e-3
    with pytest.raises(rc.CaseFileError, match="turn_distance"):
        rc.case_from_dict(raw)
