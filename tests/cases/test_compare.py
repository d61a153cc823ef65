"""railcontact.cases.compare: the same case solved by several normal models."""

from pathlib import Path

from railcontact.cli import main

EX = Path(__file__).resolve().parents[2] / "examples"


def run_cli(args, capsys):
    code = main(args)
    out = capsys.readouterr()
    return code, out.out, out.err


def test_compare_cli(tmp_path, capsys):
    code, out, err = run_cli(["compare", str(EX / "bodies.toml"), "--models",
                              "hertz,kpec,analyn,exact", "--out", str(tmp_path)], capsys)
    assert code == 0, err
    assert "kpec" in out and "analyn" in out
    import csv
    rows = list(csv.DictReader(open(tmp_path / "comparison.csv")))
    assert [r["model"] for r in rows] == ["hertz", "kpec", "analyn", "exact"]
    # on a Hertzian case all four agree on the contact area within 3 %
    areas = [float(r["area_mm2"]) for r in rows]
    assert max(areas) / min(areas) < 1.03
    for f in ("outlines.png", "lateral_pressure.png"):
        assert (tmp_path / f).stat().st_size > 5000
    code, out, err = run_cli(["compare", str(EX / "bodies.toml"), "--models", "hertz,nope"],
                             capsys)
    assert code == 2 and "nope" in err
