"""The README's Python code runs as written (its blocks in order, one namespace)."""

import re
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def test_readme_python_blocks(monkeypatch, capsys, tmp_path):
    text = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert blocks, "README.md has no python blocks"
    # the blocks name examples/ relative to the repository and write files (e.g.
    # subsurface.png) into the working folder: a temporary one that sees examples/
    (tmp_path / "examples").symlink_to(ROOT / "examples")
    monkeypatch.chdir(tmp_path)
    ns: dict = {}
    for block in blocks:
        exec(compile(block, "README.md", "exec"), ns)
    out = capsys.readouterr().out
    assert out.strip()
    # the blocks' results are real numbers: forces of the first block, and the batch
    # arrays of the second, one value per loaded patch
    res = ns["res"]
    assert np.all(np.isfinite(res.Fx)) and np.all(res.normal_force > 0)
    fn = ns["normal"].normal_force
    assert fn > 0 and np.hypot(ns["tang"].fx, ns["tang"].fy) <= 0.3 * fn * (1 + 1e-9)
