"""The layers' model contracts: every registered model keeps its Protocol and its
declared capabilities, and every normal x tangential pair meets the analytic
solutions on a Hertzian gap (as SciPy's test_ivp loops over its methods)."""

import ast
import math
import re
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest

from railcontact.cases.batch import solve_patches
from railcontact.geometry import ContactGeometry
from railcontact.core.materials import Material
from railcontact.normal import (NormalModel, get_normal_model, hertz_ellipse, normal_model_class,
                                normal_models)
from railcontact.normal.base import NORMAL_CAPABILITIES
from railcontact.tangential import (TangentialModel, get_tangential_model,
                                    tangential_model_class, tangential_models)
from railcontact.tangential.base import TANGENTIAL_CAPABILITIES
from railcontact.tangential.kalker import kalker_coefficients

MAT = Material(2.1e11, 0.28)
A, B, LOAD, MU = 1 / 0.92, 1 / 0.6, 1e5, 0.3
#: the normal models whose solution on a Hertzian gap is Hertz's (Kik-Piotrowski's
#: area is larger by design: tests/normal/test_semi_hertzian.py)
HERTZIAN = [m for m in normal_models() if m != "kik-piotrowski"]


@pytest.mark.parametrize("name", normal_models())
def test_normal_models_keep_the_contract(name):
    model = get_normal_model(name)
    assert isinstance(model, NormalModel)
    assert model.capabilities <= set(NORMAL_CAPABILITIES)
    assert "force-control" in model.capabilities


@pytest.mark.parametrize("name", tangential_models())
def test_tangential_models_keep_the_contract(name):
    model = get_tangential_model(name)
    cls = tangential_model_class(name)
    assert isinstance(model, TangentialModel)
    assert model.capabilities <= set(TANGENTIAL_CAPABILITIES)
    assert ("online" in cls.capabilities) == isinstance(getattr(cls, "online_law", None), int)
    assert ("strip-march" in cls.capabilities) == callable(getattr(cls, "strip_forces", None))


@lru_cache(maxsize=None)
def _normal(name):
    return get_normal_model(name).solve(ContactGeometry(curvatures=(A, B)), MAT,
                                        normal_force=LOAD, grid=(40, 40))


@pytest.mark.parametrize("normal", normal_models())
def test_normal_force_control(normal):
    ns = _normal(normal)
    assert ns.converged
    assert ns.normal_force == pytest.approx(LOAD, rel=1e-9)
    if normal in HERTZIAN:
        hz = hertz_ellipse(A, B, MAT.contact_modulus, force=LOAD)
        assert ns.area == pytest.approx(hz.area, rel=0.015)       # 40 x 40 elements
        assert ns.pmax == pytest.approx(hz.p0, rel=0.01)


@pytest.mark.parametrize("tangential", tangential_models())
@pytest.mark.parametrize("normal", HERTZIAN)
def test_pairs_meet_kalker_and_coulomb(normal, tangential):
    """Small creepage: Kalker's linear theory on the solution's own area,
    F_x = G c^2 C11 xi and F_y = G c^2 C22 eta with c^2 = area / pi, within 2 %
    (measured: at most 1.6 %, the exact tangential model on 40 x 40 elements);
    large creepage: full slip, |F| = mu F_n within 1 % (measured 0.8 %), except for
    the linear theory, which has no bound and stays linear."""
    ns = _normal(normal)
    tm = get_tangential_model(tangential)
    geo = ContactGeometry(curvatures=(A, B))
    hz = hertz_ellipse(A, B, MAT.contact_modulus, force=LOAD)
    c11, c22, _ = kalker_coefficients(hz.a / hz.b, MAT.nu)
    Gc2 = MAT.shear_modulus * ns.area / math.pi
    small = 1e-5
    fx = tm.solve(ns, geo, MAT, (small, 0.0, 0.0), MU, 1.0).fx
    fy = tm.solve(ns, geo, MAT, (0.0, small, 0.0), MU, 1.0).fy
    assert fx == pytest.approx(Gc2 * c11 * small, rel=0.02)
    assert fy == pytest.approx(Gc2 * c22 * small, rel=0.02)
    ts = tm.solve(ns, geo, MAT, (0.05, 0.0, 0.0), MU, 1.0)
    if tangential == "linear":
        assert ts.fx == pytest.approx(Gc2 * c11 * 0.05, rel=0.02)
    else:
        assert math.hypot(ts.fx, ts.fy) == pytest.approx(MU * ns.normal_force, rel=0.01)


@pytest.mark.parametrize("tangential", [t for t in tangential_models()
                                        if t != "exact"])
@pytest.mark.parametrize("normal", [n for n in normal_models()
                                    if "batch" in normal_model_class(n).capabilities])
def test_batch_path_equals_the_models(normal, tangential):
    """The batch path (chosen by capabilities) gives the per-patch pair's forces on
    a Hertzian gap: F_n within 1 %, F_x within 2 % of mu F_n."""
    hz = hertz_ellipse(A, B, MAT.contact_modulus, force=LOAD)
    geo = ContactGeometry(curvatures=(A, B), approach=hz.penetration,
                          creepage=(2e-3, 0.0, 0.0), velocity=1.0)
    res = solve_patches([geo], normal, tangential, MAT, MU, fastsim_grid=(40, 40))
    ns = get_normal_model(normal).solve(geo, MAT, penetration=hz.penetration, grid=(40, 40))
    ts = get_tangential_model(tangential).solve(ns, geo, MAT, geo.creepage, MU, 1.0)
    assert res.normal_force[0] == pytest.approx(ns.normal_force, rel=0.01)
    assert np.abs(res.Fx[0] - ts.fx) < 0.02 * MU * ns.normal_force


# ------------------------------------------------ capabilities used, not probed
#: the attributes of the models' contract (the Protocols) and those a declared
#: capability names (``online_law``, ``strip_forces``, ``mode``)
CONTRACT_ATTRIBUTES = {"name", "capabilities", "solve", "online_law", "strip_forces", "mode"}
#: the functions that ask a registry for a capability, by layer
_REGISTRY_CALLS = {"normal_supports": ("normal", 1), "normal_models": ("normal", 0),
                   "tangential_supports": ("tangential", 1),
                   "tangential_models": ("tangential", 0)}
_MODEL = re.compile(r"(^|\.|_)(n|t)?model$|^cls$")
_SCENARIO = re.compile(r"(^|\.)(sc|scenario)$")


def _layers(text: str) -> set:
    """The layers whose models an expression names (``self.nmodel``, ``tmodel``)."""
    out = set()
    if re.search(r"nmodel|normal", text):
        out.add("normal")
    if re.search(r"tmodel|tangential", text):
        out.add("tangential")
    return out or {"normal", "tangential"}


@lru_cache(maxsize=None)
def _scan():
    """What the package's callers ask of the models: (where, layers, capability) of
    every ``"cap" in x.capabilities`` and registry query, and (where, object,
    attribute) of every getattr/hasattr on a model or a scenario."""
    import railcontact
    root = Path(railcontact.__file__).parent
    asked, probes = [], []
    for path in sorted(root.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            where = f"{path.relative_to(root.parent)}:{getattr(node, 'lineno', 0)}"
            if (isinstance(node, ast.Compare) and isinstance(node.left, ast.Constant)
                    and isinstance(node.left.value, str)
                    and isinstance(node.ops[0], (ast.In, ast.NotIn))):
                caps = [n for n in ast.walk(node.comparators[0])
                        if isinstance(n, ast.Attribute) and n.attr == "capabilities"]
                for n in caps:
                    asked.append((where, frozenset(_layers(ast.unparse(n.value))),
                                  node.left.value))
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
                fn = node.func.id
                if fn in _REGISTRY_CALLS:
                    layer, pos = _REGISTRY_CALLS[fn]
                    if len(node.args) > pos and isinstance(node.args[pos], ast.Constant):
                        asked.append((where, frozenset({layer}), node.args[pos].value))
                if fn in ("getattr", "hasattr") and len(node.args) >= 2 \
                        and isinstance(node.args[1], ast.Constant):
                    obj = ast.unparse(node.args[0])
                    if _MODEL.search(obj) or _SCENARIO.search(obj):
                        probes.append((where, obj, node.args[1].value))
    return asked, probes


def test_the_scan_sees_the_callers():
    """The scan finds known uses (so that the tests below can fail)."""
    asked, _ = _scan()
    found = {(w.split(":")[0], c) for w, _, c in asked}
    assert ("railcontact/wear/postprocess.py", "grid-reuse") in found
    assert ("railcontact/cases/batch.py", "strip-march") in found


@pytest.mark.parametrize("layer, declared", [("normal", NORMAL_CAPABILITIES),
                                             ("tangential", TANGENTIAL_CAPABILITIES)])
def test_every_declared_capability_is_used(layer, declared):
    asked, _ = _scan()
    used = {c for _, layers, c in asked if layer in layers}
    assert set(declared) - used == set(), f"{layer} capabilities no caller asks for"


def test_no_caller_asks_an_undeclared_capability():
    asked, _ = _scan()
    declared = {"normal": set(NORMAL_CAPABILITIES), "tangential": set(TANGENTIAL_CAPABILITIES)}
    bad = [(w, c) for w, layers, c in asked
           if not any(c in declared[layer] for layer in layers)]
    assert bad == []


def test_no_caller_probes_a_model_or_a_scenario():
    """getattr/hasattr on a model only for its contract's attributes; never on a
    scenario (its type says what it is)."""
    _, probes = _scan()
    bad = [(w, obj, attr) for w, obj, attr in probes
           if _SCENARIO.search(obj) or attr not in CONTRACT_ATTRIBUTES]
    assert bad == []


@pytest.mark.parametrize("name", tangential_models())
def test_coupled_models_declare_their_mode(name):
    cls = tangential_model_class(name)
    model = get_tangential_model(name)
    assert ("coupled" in cls.capabilities) == isinstance(getattr(model, "mode", None), str)


@pytest.mark.parametrize("name", tangential_models())
def test_extra_slip_models_take_it(name):
    """A model declaring "extra-slip" takes extra_slip in solve, one declaring
    "friction-field" takes friction_scale (the conformal patches and friction along
    the track pass them only to such models)."""
    import inspect
    cls = tangential_model_class(name)
    params = inspect.signature(cls.solve).parameters
    assert ("extra-slip" in cls.capabilities) == ("extra_slip" in params)
    assert ("friction-field" in cls.capabilities) == ("friction_scale" in params)
