"""Write railcontact's API reference (HTML, with pdoc) from the docstrings.

Usage: ``python scripts/api_reference.py [OUTPUT_DIR]`` (default ``docs/api``); run
by ``make api``.  Every module of the package gets a page, the private ones
(``_name``) and the command-line module excepted.
"""

from __future__ import annotations

import pkgutil
import sys
from pathlib import Path

import pdoc

import railcontact


def modules() -> list[str]:
    """Names of the documented modules: the package and all its public modules."""
    names = ["railcontact"]
    for info in pkgutil.walk_packages(railcontact.__path__, "railcontact."):
        if not any(part.startswith("_") for part in info.name.split(".")):
            names.append(info.name)
    return sorted(n for n in names if n != "railcontact.cli")


def write(out: Path) -> list[Path]:
    """Write the reference into ``out``; returns the module pages written."""
    out = Path(out)
    pdoc.render.configure(docformat="numpy", show_source=False,
                          footer_text="railcontact " + railcontact.__version__)
    pdoc.pdoc(*modules(), output_directory=out)
    return sorted(out.rglob("*.html"))


if __name__ == "__main__":
    target = Path(sys.argv[1] if len(sys.argv) > 1 else "docs/api")
    pages = write(target)
    print(f"API reference: {len(pages)} pages in {target}/ (open {target}/index.html)")
