"""docs/tuning.md stays true to the code: every setting it names exists with the value
and default it states, and every pointer from the code names one of its sections."""

import ast
import importlib
import inspect
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOC = (ROOT / "docs" / "tuning.md").read_text()
#: a setting's entry: **`railcontact.module.NAME` = value [unit]** or
#: **`railcontact.module.Class(option=default)`** or **`railcontact.module.name`**
ENTRY = re.compile(r"\*\*`(railcontact(?:\.\w+)+)(?:\((\w+)=([^)]*)\))?`(?: = ([^*]+))?")


def _leading_value(text):
    """The value at the start of ``text`` (a number, a fraction such as 1/6, a dict),
    before its unit or the next name: the longest prefix that evaluates."""
    for end in range(len(text), 0, -1):
        try:
            return eval(text[:end].strip().rstrip(","), {"__builtins__": {}})
        except Exception:
            continue
    raise ValueError(text)


def _resolve(path):
    parts = path.split(".")
    for k in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:k]))
        except ModuleNotFoundError:
            continue
        for name in parts[k:]:
            obj = getattr(obj, name)
        return obj
    raise ImportError(path)


ENTRIES = ENTRY.findall(DOC)


def test_the_doc_has_entries():
    assert len(ENTRIES) >= 15


@pytest.mark.parametrize("path,option,default,value", ENTRIES, ids=[e[0] for e in ENTRIES])
def test_every_setting_exists_with_its_stated_value(path, option, default, value):
    obj = _resolve(path)
    if option:
        stated = ast.literal_eval(default)
        assert inspect.signature(obj).parameters[option].default == stated
    if value:
        stated = _leading_value(value)
        if isinstance(stated, dict):
            assert obj == stated
        else:
            assert float(obj) == pytest.approx(float(stated), rel=1e-12)


def test_every_pointer_from_the_code_names_a_section():
    sections = set(re.findall(r"^## (.+)$", DOC, flags=re.M))
    named = set()
    for path in (ROOT / "railcontact").rglob("*.py"):
        text = re.sub(r"\n\s*#:?\s*", " ", path.read_text())     # comments across lines
        text = re.sub(r"\s+", " ", text)
        for m in re.finditer(r'docs/tuning\.md, sections? "([^"]+)"', text):
            named.add((m.group(1), path.name))
    assert named, "no pointers found"
    missing = sorted(n for n in named if n[0] not in sections)
    assert not missing, missing
