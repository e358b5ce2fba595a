"""The behaviours' registry (``tasks/__init__.py``): what it holds, in which
order, how a new behaviour is registered and refused, when the plugins are
asked, and what ``get_behaviour`` hands on."""

import numpy as np
import pytest

from locustjump import plugins, tasks
from locustjump.sim.scene import Debris, Terrains
from locustjump.tasks import (
    Behaviour,
    ComposedRepertoire,
    GetUp,
    Kick,
    behaviour_class,
    behaviour_names,
    get_behaviour,
    register_behaviour,
)

PAPER = ("kick", "getup", "return-legs", "composed", "monolithic")
BEYOND = (
    "kick-apex",
    "kick-open",
    "kick-apex-open",
    "composed-height",
    "monolithic-height",
    "composed-repertoire",
)


@pytest.fixture
def registry(monkeypatch):
    """A copy of the registry, restored after the test; plugins not asked."""
    monkeypatch.setattr(tasks, "_REGISTRY", dict(tasks._REGISTRY))
    calls = []
    monkeypatch.setattr(plugins, "load", lambda *args: calls.append(args))
    return calls


def test_the_papers_behaviours_then_ours_in_order():
    assert tasks.BEHAVIOURS == PAPER
    assert tasks.SIMPLE_BEHAVIOURS == ("kick", "getup", "return-legs")
    assert behaviour_names()[: len(PAPER + BEYOND)] == PAPER + BEYOND
    assert behaviour_class("kick") is Kick and behaviour_class("getup") is GetUp
    assert behaviour_class("composed-repertoire") is ComposedRepertoire


def test_a_new_behaviour_is_registered_by_its_name(registry):
    class Hop(Kick):
        name = "hop"

    assert register_behaviour(Hop) is Hop  # usable as a decorator
    assert behaviour_class("hop") is Hop
    assert behaviour_names()[-1] == "hop"


@pytest.mark.parametrize("missing", ["name", "n_steps"])
def test_a_behaviour_without_a_name_or_length_is_refused(registry, missing):
    attrs = {"name": "stand", "n_steps": 10}
    del attrs[missing]
    cls = type("Stand", (), attrs)
    with pytest.raises(TypeError) as got:
        register_behaviour(cls)
    assert str(got.value) == f"Stand must set {missing!r}"
    assert "stand" not in tasks._REGISTRY


def test_an_unknown_name_asks_the_plugins_once_then_is_named(registry):
    assert behaviour_class("kick") is Kick
    assert registry == []  # a known name does not ask
    with pytest.raises(ValueError) as got:
        behaviour_class("fly")
    assert registry == [(plugins.TASKS, register_behaviour)]
    assert str(got.value) == (
        "unknown behaviour 'fly'; choose from " + ", ".join(tasks._REGISTRY)
    )
    assert str(got.value).startswith("unknown behaviour 'fly'; choose from kick, getup")
    assert got.value.__suppress_context__  # not "during handling of KeyError"


def test_the_names_include_the_plugins(registry):
    behaviour_names()
    assert registry == [(plugins.TASKS, register_behaviour)]


def test_get_behaviour_hands_on_its_arguments():
    kick = get_behaviour("kick")
    assert type(kick) is Kick and kick.frozen is None
    assert kick.terrains == Terrains() and kick.options == Kick.Options()
    frozen = np.arange(6).reshape(2, 3)
    terrains = Terrains(Debris(seed=1), 2)
    options = GetUp.Options()
    getup = get_behaviour("getup", frozen, options, terrains)
    assert getup.options is options and getup.terrains is terrains
    np.testing.assert_array_equal(getup.frozen, frozen)
    assert isinstance(getup, Behaviour)


def test_the_monolithic_network_is_the_composed_task_as_one_network():
    """Its episode and fitness are the composed task's; what it records when
    evaluated has no switcher memory (it has none), and it is the behaviour
    behind the successive-jumping Gymnasium environment."""
    from locustjump.tasks.composed import Successive

    mono, composed = get_behaviour("monolithic"), get_behaviour("composed")
    assert isinstance(mono, Successive) and type(mono).name == "monolithic"
    assert mono.eval_record == ("qpos", "obs", "ctrl")
    assert composed.eval_record == ("qpos", "obs", "ctrl", "memory")
    assert mono.gym_id == "LocustSuccessiveJump-v0" and composed.gym_id is None
