"""The README's Python code runs as written (its blocks in order, one namespace)."""

import re
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def test_readme_python_blocks(monkeypatch, capsys):
    text = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert blocks, "README.md has no python blocks"
    monkeypatch.chdir(ROOT)                     # the blocks name examples/ relative to it
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


def readme_commands():
    """The shell block of README.md's "Command line" section: (line, exit status
    given in its comment as 'exit N', else 0)."""
    text = (ROOT / "README.md").read_text()
    section = text[text.index("## Command line"):]
    block = re.search(r"```sh\n(.*?)```", section, flags=re.S).group(1)
    out = []
    for line in block.splitlines():
        if line.strip():
            m = re.search(r"#\s*exit (\d+)", line)
            out.append((line, int(m.group(1)) if m else 0))
    return out


def test_readme_commands_run_as_written(tmp_path):
    """Every command of the README's command-line block, exactly as written, in one
    shell in a copy of the repository's layout (examples/ and .venv/ linked, the
    reference data beside it): each exits with its stated status, prints no
    traceback, and nothing is written outside out/."""
    import os
    import subprocess
    import time
    shared = ROOT.parent / "shared"
    if not (shared / "reference").is_dir() or not (ROOT / ".venv" / "bin" / "railcontact").exists():
        import pytest
        pytest.skip("needs ../shared/reference and .venv")
    repo = tmp_path / "repo"
    repo.mkdir()
    for name in ("examples", ".venv"):
        (repo / name).symlink_to(ROOT / name)
    (tmp_path / "shared").symlink_to(shared)
    commands = readme_commands()
    script = ["set +e"]
    for i, (line, _) in enumerate(commands):
        script += [f"t0=$(date +%s.%N)", line, f"echo \"@@ {i} $? $t0 $(date +%s.%N)\" >&2"]
    env = {k: v for k, v in os.environ.items() if k != "RAILCONTACT_NO_FORK"}
    r = subprocess.run(["bash", "-c", "\n".join(script)], cwd=repo, capture_output=True,
                       text=True, env=env, timeout=1500)
    got = {}
    for ln in r.stderr.splitlines():
        if ln.startswith("@@ "):
            _, i, code, t0, t1 = ln.split()
            got[int(i)] = (int(code), float(t1) - float(t0))
    assert "Traceback" not in r.stderr, r.stderr[-3000:]
    for i, (line, expected) in enumerate(commands):
        assert got[i][0] == expected, (line, got[i], r.stderr.split(f"@@ {i - 1} ")[-1][:3000])
    assert sorted(p.name for p in repo.iterdir()) == [".venv", "examples", "out"]
    print("\n".join(f"{got[i][1]:7.1f} s  {line}" for i, (line, _) in enumerate(commands)))
