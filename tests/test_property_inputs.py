"""Property-based tests (Hypothesis) of the readers of user input: any case file,
profile file or CONTACT input gives a result or one of the package's errors
(:class:`railcontact.RailContactError`), never another exception.  Examples and
time are bounded so that the whole module takes a few seconds."""

import math
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from railcontact import RailContactError
from railcontact.cases.case import _ALLOWED, case_from_dict, load_case
from railcontact.contact_inp import map_case, read_inp
from railcontact.profiles import read_profile

#: derandomized: the same examples on every run, so that the suite's result does not
#: hang on a random draw (a longer random search: pytest --hypothesis-seed=N with
#: derandomize off found the unchecked solver options, now in tests/cases/test_case.py)
FAST = settings(max_examples=60, deadline=None, database=None, derandomize=True,
                suppress_health_check=[HealthCheck.function_scoped_fixture,
                                       HealthCheck.too_slow])

numbers = st.one_of(st.integers(-10**12, 10**12), st.floats(allow_nan=True, allow_infinity=True),
                    st.sampled_from([0, 1, -1, 0.003, 7e4, 0.46, 1e-9, 2.1e11, 0.28]))
leaves = st.one_of(numbers, st.booleans(), st.text(max_size=12),
                   st.sampled_from(["S1002", "60E1", "hertz", "exact", "fastsim", "both",
                                    "right", "left", "none", "kpec"]))
values = st.recursive(leaves, lambda inner: st.one_of(
    st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=8), inner, max_size=3)),
    max_leaves=8)


@st.composite
def case_dicts(draw):
    """Case dictionaries near the valid ones: known sections and keys (with some
    unknown ones), values of any type."""
    raw = {}
    base = draw(st.sampled_from(["wheel-rail", "bodies", "any"]))
    if base == "wheel-rail":
        raw = {"wheel": {"profile": "S1002"}, "rail": {"profile": "60E1"}}
    elif base == "bodies":
        raw = {"bodies": {"radii": {"wheel_rolling": 0.46, "rail_lateral": 0.3},
                          "normal_force": 1e4}}
    sections = [k for k, v in _ALLOWED.items() if v]
    for _ in range(draw(st.integers(0, 4))):
        sec = draw(st.sampled_from(sections + ["bogus"]))
        keys = sorted(_ALLOWED.get(sec) or {"x"}) + ["unknown_key"]
        table = raw.setdefault(sec, {}) if isinstance(raw.get(sec, {}), dict) else {}
        table[draw(st.sampled_from(keys))] = draw(values)
        raw[sec] = table
    if draw(st.booleans()):
        raw[draw(st.sampled_from(sections))] = draw(values)
    return raw


@FAST
@given(case_dicts())
def test_any_case_dictionary_gives_a_case_or_a_package_error(raw):
    try:
        case_from_dict(raw)
    except RailContactError as exc:
        assert str(exc) and len(str(exc)) < 1000


@FAST
@given(st.text(max_size=300))
def test_any_case_file_text_gives_a_case_or_a_package_error(tmp_path, text):
    path = tmp_path / "c.toml"
    path.write_text(text)
    try:
        load_case(path)
    except RailContactError as exc:
        assert str(exc)


#: characters and lines of profile files (numbers in columns, headers, separators)
profile_lines = st.lists(st.one_of(
    st.tuples(st.floats(-100, 100, allow_nan=False), st.floats(-100, 100, allow_nan=False)).map(
        lambda t: f"{t[0]:.4f} {t[1]:.4f}"),
    st.tuples(st.floats(allow_nan=True), st.floats(allow_infinity=True)).map(
        lambda t: f"{t[0]},{t[1]}"),
    st.sampled_from(["y,z", "% comment", "", "NaN NaN", "1 2 3", "a b", "1e400 0", ";;",
                     "0.0 0.0", "-70 30"]),
    st.text(max_size=20)), max_size=40)


@FAST
@given(profile_lines, st.sampled_from([".csv", ".txt", ".prw", ".prr", ".ban", ".whl", ""]),
       st.sampled_from([None, "wheel", "rail"]))
def test_any_profile_file_gives_a_profile_or_a_package_error(tmp_path, lines, suffix, kind):
    path = tmp_path / f"p{suffix}"
    path.write_text("\n".join(lines))
    try:
        prof = read_profile(path, kind=kind)
    except RailContactError as exc:
        assert str(exc)
    else:
        assert prof.y.size >= 2 and all(math.isfinite(v) for v in (prof.y.min(), prof.y.max()))


REF_INP = Path(__file__).resolve().parents[2] / "shared" / "reference" / "mbench_sweep_10kN.inp"
_INP_LINES = REF_INP.read_text().splitlines()[:40] if REF_INP.is_file() else [
    "  1 MODULE", " 1203100", " 0022033", " 0001321", "  0.3 0.3"]


@st.composite
def inp_texts(draw):
    """CONTACT inputs made of lines of a real one, some dropped, swapped, repeated
    or with a token replaced."""
    lines = list(_INP_LINES)
    for _ in range(draw(st.integers(0, 6))):
        op = draw(st.sampled_from(["drop", "swap", "dup", "token", "junk"]))
        if not lines:
            break
        i = draw(st.integers(0, len(lines) - 1))
        if op == "drop":
            del lines[i]
        elif op == "swap":
            j = draw(st.integers(0, len(lines) - 1))
            lines[i], lines[j] = lines[j], lines[i]
        elif op == "dup":
            lines.insert(i, lines[i])
        elif op == "token":
            toks = lines[i].split()
            if toks:
                toks[draw(st.integers(0, len(toks) - 1))] = draw(st.sampled_from(
                    ["-1", "0", "9", "1e400", "nan", "x", "'a.prr'", "99999999", "3d", "-5r"]))
                lines[i] = " ".join(toks)
        else:
            lines.insert(i, draw(st.text(max_size=30)))
    return "\n".join(lines) + "\n"


@FAST
@given(inp_texts())
def test_any_contact_input_gives_cases_or_a_package_error(tmp_path, text):
    path = tmp_path / "x.inp"
    path.write_text(text)
    try:
        cases = read_inp(path)
        for c in cases[:2]:
            map_case(c)
    except RailContactError as exc:
        assert str(exc) and "\n" not in str(exc)


@pytest.mark.parametrize("text", ["", "\x00\x00", "1 MODULE\n" * 3, "0 MODULE\n"])
def test_degenerate_contact_inputs(tmp_path, text):
    path = tmp_path / "x.inp"
    path.write_text(text)
    with pytest.raises(RailContactError):
        read_inp(path)
