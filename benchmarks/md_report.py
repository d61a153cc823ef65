"""The Markdown report a benchmark prints and writes (``benchmarks/exact_case.py``,
``benchmarks/exact_normal.py``)."""

from __future__ import annotations

from pathlib import Path


def write_report(title: str, intro: str, lines: list, out=None) -> list:
    """Print the report: the heading ``title``, the paragraph ``intro`` (the command
    that made it and what it measures) and the result ``lines``; written also to the
    file ``out`` where one is given (None or "": printed only).  Returns ``lines``."""
    text = "\n".join([f"# {title}", "", intro, ""] + lines) + "\n"
    print(text)
    if out:
        Path(out).write_text(text)
    return lines
