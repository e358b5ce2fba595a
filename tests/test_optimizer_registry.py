"""The optimizer registry (evo/__init__.py) stated exactly: what a registered
class must have, plugins' optimizers loaded once and only when asked for, and
descriptors passed only to an optimizer that names them."""

import numpy as np
import pytest

from helpers import Fixed, exactly
from locustjump.evo import (
    RCGA,
    Optimizer,
    RandomSearch,
    RandomSearchParams,
    RCGAParams,
    optimizer_kinds,
)

#: the optimizers locustjump registers itself
BUILTIN = optimizer_kinds()


def test_the_registry_names_what_a_class_lacks(monkeypatch):
    import locustjump.evo as evo

    monkeypatch.setattr(evo, "_REGISTRY", dict(evo._REGISTRY))
    with pytest.raises(
        TypeError, match=exactly("dict is not a subclass of locustjump.evo.Optimizer")
    ):
        evo.register(dict)
    with pytest.raises(
        TypeError, match=exactly("3 is not a subclass of locustjump.evo.Optimizer")
    ):
        evo.register(3)

    class Half(Optimizer):
        def _ask(self): ...

    with pytest.raises(
        TypeError, match=exactly("Half does not define _set_state, _state, _tell")
    ):
        evo.register(Half)

    class NoParams(Fixed):
        pass

    with pytest.raises(
        TypeError, match=exactly("NoParams has no Params settings class")
    ):
        evo.register(NoParams)

    class Hill(Fixed):
        Params = type("HillParams", (), {"kind": "hill", "population": 1})

    assert evo.register(Hill) is Hill
    assert evo.optimizer_kinds() == (*BUILTIN, "hill")
    assert evo.params_class("hill") is Hill.Params
    assert type(evo.make_optimizer(RandomSearchParams(2), 3, 5)) is RandomSearch
    opt = evo.make_optimizer(RCGAParams(population=4, elite=1), 3, 5)
    assert type(opt) is RCGA and opt.seed == 5 and opt.num_params == 3
    assert opt.params == RCGAParams(population=4, elite=1)
    with pytest.raises(
        ValueError,
        match=exactly(
            f"unknown optimizer 'sa'; choose from {', '.join(BUILTIN)}, hill"
        ),
    ):
        evo.make_optimizer(type("P", (), {"kind": "sa"})(), 3, 0)


class Entry:
    """An entry point of the optimizers' group, as importlib.metadata gives."""

    def __init__(self, obj):
        self.obj, self.dist = obj, None
        self.name, self.module, self.value = "hill", "hillpkg", "hillpkg:Hill"

    def load(self):
        return self.obj


def test_a_plugin_s_optimizer_is_loaded_once_and_only_when_asked_for(monkeypatch):
    import locustjump.evo as evo
    from locustjump import plugins

    class Hill(Fixed):
        Params = type("HillParams", (), {"kind": "hill", "population": 1})

    calls = []

    def entry_points(group):
        calls.append(group)
        return [Entry(Hill)] if group == plugins.OPTIMIZERS else []

    monkeypatch.setattr(evo, "_REGISTRY", dict(evo._REGISTRY))
    monkeypatch.setattr(plugins, "_loaded", set())
    monkeypatch.setattr(plugins.importlib.metadata, "entry_points", entry_points)
    assert evo.params_class("rcga") is RCGAParams  # known: nothing loaded
    with pytest.raises(ValueError, match="unknown optimizer 5"):
        evo.params_class(5)  # no name: nothing loaded
    assert calls == []
    assert evo.params_class("hill") is Hill.Params
    assert calls == [plugins.OPTIMIZERS]
    assert evo.optimizer_kinds() == (*BUILTIN, "hill")
    assert calls == [plugins.OPTIMIZERS]  # once


def test_all_kinds_include_the_plugins(monkeypatch):
    import locustjump.evo as evo
    from locustjump import plugins

    class Hill(Fixed):
        Params = type("HillParams", (), {"kind": "hill", "population": 1})

    monkeypatch.setattr(evo, "_REGISTRY", dict(evo._REGISTRY))
    monkeypatch.setattr(plugins, "_loaded", set())
    monkeypatch.setattr(
        plugins.importlib.metadata,
        "entry_points",
        lambda group: [Entry(Hill)] if group == plugins.OPTIMIZERS else [],
    )
    assert evo.optimizer_kinds() == (*BUILTIN, "hill")


class Described(Fixed):
    """Takes two behaviour descriptors with each fitness, and keeps them."""

    rows = np.zeros((2, 3))
    descriptor_names = ("height", "distance")

    def _tell_described(self, genomes, fitness, descriptors):
        self.told = (genomes.copy(), fitness.copy(), descriptors)
        return None


def test_descriptors_are_checked_and_passed_only_to_an_optimizer_that_names_them():
    opt = Described(3, RandomSearchParams(population=2))
    x = opt.ask()
    with pytest.raises(
        ValueError,
        match=exactly(
            "Described needs the descriptors height, distance with the fitness"
        ),
    ):
        opt.tell([1.0, 2.0])
    with pytest.raises(
        ValueError,
        match=exactly("got descriptors of shape (2, 3), expected (2, 2)"),
    ):
        opt.tell([1.0, 2.0], np.zeros((2, 3)))
    with pytest.raises(ValueError, match=exactly("descriptors are not finite")):
        opt.tell([1.0, 2.0], [[0.0, np.nan], [0.0, 0.0]])
    opt.tell([1.0, 2.0], [[1, 2], [3, 4]])
    genomes, fitness, m = opt.told
    np.testing.assert_array_equal(genomes, x)
    np.testing.assert_array_equal(fitness, [1.0, 2.0])
    assert m.dtype == np.float64
    np.testing.assert_array_equal(m, [[1.0, 2.0], [3.0, 4.0]])
    assert opt.generation == 1 and opt.best_fitness == 2.0
    plain = RandomSearch(3, RandomSearchParams(population=2), 0)
    plain.ask()
    with pytest.raises(ValueError, match=exactly("RandomSearch takes no descriptors")):
        plain.tell([1.0, 2.0], np.zeros((2, 0)))
    with pytest.raises(
        NotImplementedError, match=exactly("RandomSearch takes no descriptors")
    ):
        plain._tell_described(x, np.zeros(2), np.zeros((2, 0)))
