import numpy as np
import pytest

from railcontact.core.errors import ProfileError
from railcontact.profiles import Profile, get_profile, read_profile, s1002, write_profile


def test_simpack_files(refdir):
    w = read_profile(refdir / "profiles" / "MBench_S1002_v3.prw")
    r = read_profile(refdir / "profiles" / "MBench_UIC60_v3.prr")
    assert w.kind == "wheel" and r.kind == "rail"
    # mirror.y applied: flange at negative y; tape circle at y = 0, z = 0
    assert w.y[np.argmax(w.z)] < -0.05
    assert abs(float(w.z_at(0.0))) < 1e-5
    # rail origin at the top of the inclined head
    assert float(r.z_at(0.0)) == pytest.approx(0.0, abs=1e-8)
    assert r.y_min == pytest.approx(-43.7049e-3, abs=1e-6)


@pytest.mark.parametrize("suffix", [".csv", ".txt", ".prw"])
def test_roundtrip(tmp_path, suffix):
    w = s1002().resampled(step=2e-4)
    path = write_profile(w, tmp_path / f"wheel{suffix}")
    back = read_profile(path, kind="wheel")
    y = np.linspace(-0.06, 0.05, 500)
    assert np.max(np.abs(back.z_at(y) - w.z_at(y))) < 1e-8
    assert not list(tmp_path.glob("*.tmp"))


def test_miniprof_rail_z_up_mm(tmp_path):
    r = get_profile("60E1", "rail", inclination=0.0).resampled(step=3e-4)
    lines = ["Date=2026-01-01", "Rail=right", "ColumnDef=X,Y", f"XYPoints={r.y.size}", ""]
    lines += [f"{y * 1e3:.6f} {-z * 1e3:.6f}" for y, z in zip(r.y, r.z)]   # z up, mm
    p = tmp_path / "meas.ban"
    p.write_text("\n".join(lines))
    back = read_profile(p)
    assert back.kind == "rail"
    assert np.max(np.abs(back.z_at(r.y[5:-5]) - r.z[5:-5])) < 1e-7


def test_miniprof_wheel_flange_right_is_mirrored(tmp_path):
    w = s1002().resampled(step=3e-4)
    lines = ["ColumnDef=X,Y", ""] + [f"{-y * 1e3:.5f},{z * 1e3:.5f}" for y, z in zip(w.y, w.z)]
    p = tmp_path / "w.whl"
    p.write_text("\n".join(lines))
    back = read_profile(p)
    assert back.y[np.argmax(back.z)] < 0


def test_units_explicit_and_detected(tmp_path):
    p = tmp_path / "r.txt"
    r = get_profile("54E1", "rail", inclination=0.0).resampled(step=5e-4)
    np.savetxt(p, np.c_[r.y, r.z])               # metres, no header
    assert read_profile(p, kind="rail").y_max == pytest.approx(r.y_max, abs=1e-9)
    assert read_profile(p, kind="rail", units="m").y_max == pytest.approx(r.y_max, abs=1e-9)
    with pytest.raises(ProfileError, match="implausible"):
        read_profile(p, kind="rail", units="mm")


def test_bad_profiles(tmp_path):
    with pytest.raises(ProfileError, match="does not exist"):
        read_profile(tmp_path / "missing.prr")
    y = np.linspace(-0.03, 0.03, 50)
    z = 1e-3 * np.sin(200 * y)
    with pytest.raises(ProfileError, match="NaN"):
        Profile(y, np.where(y > 0, np.nan, z))
    with pytest.raises(ProfileError, match="implausible"):
        Profile(y * 1e3, z)
    # a curve that crosses itself (a loop) is no profile; one that folds back is
    # (its visible surface, tests/profiles/test_processing.py)
    yb, zb = y.copy(), z.copy()
    yb[20:25] = yb[20:25][::-1]
    zb[20:25] = zb[20:25] + np.array([-2e-3, 2e-3, -2e-3, 2e-3, -2e-3])
    with pytest.raises(ProfileError, match="crosses itself"):
        Profile(yb, zb, kind="wheel", name="bad")
    p = tmp_path / "x.dat"
    p.write_text("1 2\n3 4\nabc def\n")
    with pytest.raises(ProfileError, match="not numeric"):
        read_profile(p, kind="rail")
    with pytest.raises(ProfileError, match="neither a built-in"):
        get_profile("S1003", "wheel")


def test_folded_flange_back_is_trimmed():
    w = s1002().resampled(step=2e-4)
    y = np.concatenate(([w.y[0] + 3e-4, w.y[0] + 1e-4], w.y))   # fold back beyond the back
    z = np.concatenate(([w.z[0] + 2e-3, w.z[0] + 1e-3], w.z))
    p = Profile(y[::-1][::-1], z, kind="wheel")
    assert p.y_min == pytest.approx(w.y_min)


def test_smoothing_and_resampling():
    w = s1002()
    rng = np.random.default_rng(0)
    noisy = Profile(w.y, w.z + rng.normal(0, 5e-6, w.y.size), kind="wheel")
    sm = noisy.smoothed(2e-3)
    y = np.linspace(-0.02, 0.03, 400)
    assert np.std(sm.z_at(y) - w.z_at(y)) < 0.5 * 5e-6
    rs = w.resampled(step=1e-3)
    assert 130 < rs.y.size < 200
    with pytest.raises(ProfileError):
        w.smoothed(-1.0)


def test_profile_files_are_read_once_per_version(tmp_path):
    """A profile file named by many cases is parsed once; a changed file is read
    again; a rail file turned by an inclination is turned once."""
    import os
    w = s1002().resampled(step=5e-4)
    path = write_profile(w, tmp_path / "wheel.prw")
    a = get_profile(str(path), "wheel")
    assert get_profile(path.name, "wheel", base_dir=tmp_path) is a
    shifted = w.shifted(dz=1e-3)
    write_profile(shifted, path)
    st = os.stat(path)
    os.utime(path, ns=(st.st_atime_ns, st.st_mtime_ns + 10**9))  # a later version
    b = get_profile(str(path), "wheel")
    assert b is not a and float(b.z_at(0.0)) == pytest.approx(float(a.z_at(0.0)) + 1e-3,
                                                             abs=1e-9)
    r = write_profile(get_profile("60E1", "rail", inclination=0.0).resampled(step=5e-4),
                      tmp_path / "rail.prr")
    r1 = get_profile(str(r), "rail", inclination=0.025)
    assert get_profile(str(r), "rail", inclination=0.025) is r1
    assert get_profile(str(r), "rail", inclination=0.0) is not r1
    # shared between cases, a cached profile cannot be edited in place
    with pytest.raises(ValueError, match="read-only"):
        r1.z[0] = 0.0
    with pytest.raises(ValueError, match="read-only"):
        a.y *= 2.0
