"""The package's layering (docs/architecture.md, "Layers"): imports only run downhill,
and no two modules import each other, directly or around a circle, counting the
imports inside functions too."""

import ast
from collections import defaultdict
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "railcontact"

#: rank of each part of the package (docs/architecture.md, "Layers"); a module may
#: import from its own rank or below
RANKS = {
    "core": 0,                     # base: no model, no case
    "profiles": 1, "geometry": 2, "normal": 3, "tangential": 4,   # the pipeline's layers
    "subsurface": 4,               # stresses below a solved patch (its solutions only)
    "cases": 5, "contact_inp": 5,  # cases above the layers, and CONTACT's input files
    "dynamics": 6, "wear": 7,      # systems that run cases
    "demo": 8, "cli": 8, "inputs": 8, "fmu": 8, "__init__": 8,   # the face and the front ends
}


def _modules():
    out = {}
    for path in PACKAGE.rglob("*.py"):
        rel = path.relative_to(PACKAGE.parent).with_suffix("")
        parts = list(rel.parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def _imports(mods):
    """Module -> the package's modules it imports, anywhere in it: inside functions
    and under ``if TYPE_CHECKING:`` too (a type a lower layer needs belongs there)."""
    edges = defaultdict(set)
    for name, path in mods.items():
        tree = ast.parse(path.read_text())
        package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                base = package[:len(package) - node.level + 1] if node.level else []
                target = ".".join(base + ([node.module] if node.module else []))
                for alias in node.names:
                    full = f"{target}.{alias.name}"
                    edges[name].add(full if full in mods else target)
            elif isinstance(node, ast.Import):
                edges[name].update(a.name for a in node.names)
        edges[name] = {t for t in edges[name] if t in mods and t != name}
    return edges


def _rank(module):
    parts = module.split(".")
    return RANKS[parts[1] if len(parts) > 1 else "__init__"]


def test_every_part_has_a_rank():
    parts = {m.split(".")[1] for m in _modules() if "." in m}
    assert parts <= set(RANKS), sorted(parts - set(RANKS))


def test_imports_run_downhill():
    edges = _imports(_modules())
    uphill = sorted(f"{m} -> {t}" for m, ts in edges.items() for t in ts
                    if _rank(t) > _rank(m) and not t.endswith(".__init__"))
    assert not uphill, uphill


def test_no_import_circles():
    """Module-level circles, through the imports inside functions too (a package's
    __init__ re-exporting its modules is not a circle)."""
    mods = _modules()
    edges = _imports(mods)
    packages = {m for m, p in mods.items() if p.name == "__init__.py"}
    graph = {m: {t for t in ts if t not in packages} for m, ts in edges.items()}
    state, circles = {}, []

    def visit(m, path):
        state[m] = 1
        for t in sorted(graph.get(m, ())):
            if state.get(t) == 1:
                circles.append(path[path.index(t):] + [t])
            elif t not in state:
                visit(t, path + [t])
        state[m] = 2

    for m in sorted(graph):
        if m not in state:
            visit(m, [m])
    assert not circles, [" -> ".join(c) for c in circles]


def test_every_module_has_its_test_file():
    """tests/ mirrors the package: railcontact/<sub>/<name>.py is tested in
    tests/<sub>/test_<name>.py (railcontact/<name>.py in tests/test_<name>.py)."""
    tests = PACKAGE.parent / "tests"
    missing = []
    for path in PACKAGE.rglob("*.py"):
        if path.name == "__init__.py":
            continue
        rel = path.relative_to(PACKAGE)
        mirror = tests / rel.parent / f"test_{rel.name}"
        if not mirror.is_file():
            missing.append(str(mirror.relative_to(PACKAGE.parent)))
    assert not missing, sorted(missing)


#: at most this many parameters per function, compiled kernels included
#: (docs/architecture.md): a longer list takes a parameter object
MAX_PARAMETERS = 12


def _parameter_count(node) -> int:
    """Parameters of a function: positional and keyword-only (not self or cls),
    *args and **kwargs one each."""
    a = node.args
    names = [x.arg for x in a.posonlyargs + a.args + a.kwonlyargs]
    n = len(names) - (1 if names and names[0] in ("self", "cls") else 0)
    return n + (a.vararg is not None) + (a.kwarg is not None)


def _long_signatures(source: str, module: str) -> dict:
    """``module:function`` -> parameter count of every function (methods, nested
    functions and compiled kernels too) over ``MAX_PARAMETERS``."""
    out = {}
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            n = _parameter_count(node)
            if n > MAX_PARAMETERS:
                out[f"{module}:{node.name}"] = n
    return out


def test_no_function_takes_more_than_twelve_parameters():
    found = {}
    for module, path in _modules().items():
        found.update(_long_signatures(path.read_text(encoding="utf-8"), module))
    assert not found, f"functions with more than {MAX_PARAMETERS} parameters: {found}"


def test_the_parameter_check_catches_long_signatures():
    names = [f"a{i}" for i in range(13)]
    src = (f"def thirteen({', '.join(names)}):\n    pass\n"
           f"def twelve({', '.join(names[:12])}):\n    pass\n"
           "class K:\n"
           f"    def method(self, {', '.join(names[:12])}):\n        pass\n"
           f"    def starred(self, {', '.join(names[:11])}, *args, **kw):\n        pass\n"
           "@njit(cache=True)\n"
           f"def kernel({', '.join(names[:10])}, *, b0, b1, b2=1):\n    pass\n")
    assert _long_signatures(src, "m") == {"m:thirteen": 13, "m:starred": 13, "m:kernel": 13}


#: who may call the case-file parser (railcontact.cases.case: case_from_dict,
#: load_case): the front ends, the parser's own module, the sweep (which varies a
#: case file's dotted keys) and CONTACT's input files (read into case files); every
#: other module takes parsed, typed objects (docs/architecture.md, "Data flow")
CASE_PARSER_USERS = {"railcontact", "railcontact.cli", "railcontact.demo", "railcontact.inputs",
                     "railcontact.fmu", "railcontact.cases.case", "railcontact.cases.sweep",
                     "railcontact.contact_inp", "railcontact.contact_inp.mapping",
                     "railcontact.contact_inp.transient_m1"}


def test_only_front_ends_parse_case_files():
    users = set()
    for name, path in _modules().items():
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.module and (
                    node.module.endswith("cases.case") or node.module == "railcontact"
                    or (node.level == 1 and node.module == "case" and ".cases" in name)):
                if {a.name for a in node.names} & {"case_from_dict", "load_case"}:
                    users.add(name)
    assert users - CASE_PARSER_USERS == set(), sorted(users - CASE_PARSER_USERS)
    assert "railcontact.cli" in users and "railcontact.inputs" in users   # the scan sees them
