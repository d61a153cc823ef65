"""Mapping CONTACT's input to a railcontact case in SI units
(railcontact.contact_inp.mapping), and the one-line errors for what is not supported."""

import pytest

from railcontact.contact_inp import InpError, load_inp
from tests.contact_inp.test_reader import CASE1, _write


@pytest.fixture
def files(tmp_path, refdir):
    import shutil
    for name in ("MBench_UIC60_v3.prr", "MBench_S1002_v3.prw"):
        shutil.copy(refdir / "profiles" / name,
                    tmp_path / ("rail.prr" if "UIC" in name else "wheel.prw"))
    return tmp_path


def test_mapping_to_a_case_in_si_units(files):
    (m1, m2) = load_inp(_write(files, CASE1))
    r = m1.raw
    assert r["material"]["young_modulus"] == pytest.approx(2 * 82e9 * 1.28)
    assert r["solver"] == {"normal": "exact", "tangential": "exact",
                           "element_size": [2e-4, 2.5e-4], "tangential_options": {}}
    ws = r["wheelset"]
    assert ws["side"] == "right" and ws["roll"] == 0.0001 and ws["yaw"] == 0.0024
    assert ws["lateral_shift"] == pytest.approx(1.5e-3) and ws["vertical_force"] == 1e4
    assert ws["velocity"] == 2.0 and ws["pitch_velocity"] == -4.348
    # CONTACT's patch rules: D_SEP, D_COMB and the default D_TURN = 2 D_SEP - D_COMB
    assert (ws["combine_distance"], ws["full_interaction_distance"],
            ws["turn_distance"]) == pytest.approx((8e-3, 4e-3, 12e-3))
    assert r["track"] == {"gauge": pytest.approx(1.435), "gauge_height": pytest.approx(0.014)}
    w = r["wheel"]
    assert w["mirror_y"] is True and w["mirror_z"] is False and w["nominal_radius"] == 0.46
    assert w["smoothing"] == {"method": "weighted", "length": pytest.approx(0.01)}
    assert w["kinks"]["width"] == pytest.approx(2e-3)
    assert r["rail"]["mirror_z"] == "auto" and "smoothing" not in r["rail"]
    assert m2.raw["wheelset"]["lateral_shift"] == pytest.approx(2.5e-3)


@pytest.mark.parametrize("old, new, match", [
    ("0022033    V-L-D-C-M-Z-E", "0042033    V-L-D-C-M-Z-E", r"DISCNS = 4 \(conformal contact\)"),
    ("0022033    V-L-D-C-M-Z-E", "0023033    V-L-D-C-M-Z-E", r"INFLCF = 3 \(bilinear"),
    ("1203100    C-P-B-T-N-F-S   comment", "5203100    C-P-B-T-N-F-S   comment",
     r"GAUGHT = 14 mm with a roller rig \(a rail placed by its gauge face\)"),
    ("1435.0   0.000", "1435.0   0.025 1e-5", r"CURV = 1e-05 1/mm \(curved track\)"),
    ("     0.0    0.0   0.000          % DY", "     0.5    0.0   0.000   % DY",
     r"DYRAIL = 0.5 \(rail deviations\)"),
    ("1360.0  -70.0   460.0", "1360.0  -70.0   460.0  -10.0", r"YTAPE = -10 mm"),
])
def test_unsupported_options_stop_with_one_line(files, old, new, match):
    assert old in CASE1
    with pytest.raises(InpError, match=match) as err:
        load_inp(_write(files, CASE1.replace(old, new, 1)))
    assert "\n" not in str(err.value) and "is not supported" in str(err.value)


def test_unsupported_material_after_its_inputs(files):
    text = CASE1.replace("0022033    V-L-D-C-M-Z-E", "0022133    V-L-D-C-M-Z-E", 1).replace(
        "82000.  82000.                POISS 1,2,  GG 1,2",
        "82000.  82000.                POISS 1,2,  GG 1,2\n  1e3 1e3 0.1 0.1  FG, VT", 1)
    with pytest.raises(InpError, match=r"MATER = 1 \(viscoelastic material\) is not supported"):
        load_inp(_write(files, text))


def test_missing_profile_names_where_it_looked(tmp_path):
    with pytest.raises(InpError, match="profile file 'wheel.prw' not found.*--profiles"):
        load_inp(_write(tmp_path, CASE1))
    with pytest.raises(InpError, match="no case 7"):
        load_inp(_write(tmp_path, CASE1), cases=[7])


def test_module3_hertzian_case(refdir):
    (m,) = load_inp(refdir / "kalker_example.inp")
    r = m.raw
    assert m.module == 3 and r["solver"]["grid"] == [80, 80]
    assert r["solver"]["normal_options"] == {"margin": pytest.approx(0.1)}
    assert r["bodies"]["normal_force"] == pytest.approx(52359.8776)
    assert r["creepage"] == {"longitudinal": 1e-5, "lateral": 0.0, "spin": 0.0}
    # the curvatures of the 5 mm circle at that load
    from railcontact import Material
    from railcontact.core.hertz_theory import hertz_ellipse
    rad = r["bodies"]["radii"]
    h = hertz_ellipse(0.5 / rad["wheel_rolling"], 0.5 / rad["wheel_lateral"],
                      Material(**r["material"]).contact_modulus, force=52359.8776)
    assert (h.a, h.b) == pytest.approx((5e-3, 5e-3), rel=1e-9)
