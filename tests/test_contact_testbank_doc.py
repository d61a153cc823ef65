"""docs/contact_users.md's table of every testbank input is the one
benchmarks/contact_testbank.py wrote into benchmarks/contact_testbank.md (the script
writes both; neither is edited by hand)."""

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _bench():
    spec = importlib.util.spec_from_file_location(
        "contact_testbank_bench", ROOT / "benchmarks" / "contact_testbank.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_the_user_guide_holds_the_benchmarks_table():
    bench = _bench()
    written = bench.table_of((ROOT / "benchmarks" / "contact_testbank.md").read_text()
                             .splitlines())
    doc = bench.doc_table((ROOT / "docs" / "contact_users.md").read_text().splitlines())
    assert len(written) > 50           # every input of the testbank and the reference
    assert doc == written


def test_the_script_rewrites_the_table_between_the_markers(tmp_path, monkeypatch):
    bench = _bench()
    guide = tmp_path / "guide.md"
    guide.write_text("before\n" + bench.DOC_BEGIN + "\n| old |\n" + bench.DOC_END + "\nafter\n")
    monkeypatch.setattr(bench, "DOC", guide)
    bench.write_doc_table([bench.TABLE_HEADER, "|---|---|---|", "| `a.inp` | runs | x |"])
    assert guide.read_text() == ("before\n" + bench.DOC_BEGIN + "\n" + bench.TABLE_HEADER
                                 + "\n|---|---|---|\n| `a.inp` | runs | x |\n" + bench.DOC_END
                                 + "\nafter\n")
