"""railcontact.core.registry: models selected by name and by declared capability."""

import pytest

from railcontact.core.errors import UnknownModelError
from railcontact.normal.base import normal_model_class, normal_models, normal_supports
from railcontact.core.registry import Registry


def _registry():
    reg = Registry("toy")

    @reg.register("slow")
    class Slow:
        capabilities = frozenset({"warm-start"})

        def __init__(self, step=1.0):
            self.step = step

    @reg.register("bare")
    class Bare:            # declares nothing
        pass

    return reg, Slow


def test_register_names_and_create():
    reg, Slow = _registry()
    assert Slow.name == "slow"
    assert reg.names() == ["bare", "slow"]
    assert reg.model_class("SLOW") is Slow                  # case-insensitive
    model = reg.create("slow", step=0.5)
    assert isinstance(model, Slow) and model.step == 0.5


def test_capabilities():
    reg, _ = _registry()
    assert reg.supports("slow", "warm-start") and not reg.supports("bare", "warm-start")
    assert not reg.supports("nope", "warm-start")
    assert reg.names("warm-start") == ["slow"] and reg.names("batch") == []


def test_unknown_name_lists_the_known_ones():
    reg, _ = _registry()
    with pytest.raises(UnknownModelError, match=r"unknown toy model 'fast'; expected one of "
                                                r"\['bare', 'slow'\]"):
        reg.create("fast")


def test_the_normal_layer_registry():
    names = normal_models()
    assert {"hertz", "exact"} <= set(names)
    assert normal_model_class("exact").name == "exact"
    assert normal_supports("exact", "warm-start") and "exact" in normal_models("force-control")
    assert set(normal_models("coupled")) <= set(names)
