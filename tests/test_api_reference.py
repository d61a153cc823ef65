"""The generated API reference (``make api``, scripts/api_reference.py): every
public module gets its page, and no module is hidden behind a function of the same
name (``railcontact.solve`` the module against ``railcontact.solve`` the function
was one: pdoc, like a reader, could only reach one of them)."""

import importlib.util
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _script():
    spec = importlib.util.spec_from_file_location("api_reference",
                                                  ROOT / "scripts" / "api_reference.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_every_module_has_a_page(tmp_path):
    api = _script()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        pages = api.write(tmp_path)
    names = {p.relative_to(tmp_path).with_suffix("").as_posix().replace("/", ".")
             for p in pages}
    missing = set(api.modules()) - names
    assert not missing, f"modules without a page: {sorted(missing)}"
    shadowed = [str(w.message) for w in caught if "has already been added" in str(w.message)]
    assert not shadowed, shadowed
    # the layers' contracts are in the reference
    normal = (tmp_path / "railcontact" / "normal" / "base.html").read_text()
    assert "NormalModel" in normal and "capabilities" in normal
