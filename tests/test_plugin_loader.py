"""The plugin loader in this process (:mod:`locustjump.plugins`), with entry
points stood in for: what is registered, what is skipped and said, where a
run's classes came from and what reading it elsewhere needs.
``tests/test_plugins.py`` installs real plugins in subprocesses."""

import logging
import sys
import types

import pytest

from helpers import exactly
from locustjump import plugins
from locustjump.errors import UserError


class _EntryPoint:
    def __init__(self, name, value, dist="", obj=None, error=None):
        self.name, self.value = name, value
        self.module = value.partition(":")[0]
        self.dist = types.SimpleNamespace(name=dist) if dist else None
        self._obj, self._error = obj, error

    def load(self):
        if self._error is not None:
            raise self._error
        return self._obj


@pytest.fixture
def fresh(monkeypatch):
    monkeypatch.setattr(plugins, "_loaded", set())
    monkeypatch.setattr(plugins, "_distributions", {})
    return monkeypatch


class Hill:
    pass


def test_a_groups_classes_are_registered_once(fresh):
    got = []
    points = [("g", _EntryPoint("hill", "hillpkg.opt:Hill", "hill-dist", Hill)),
              ("g", _EntryPoint("mod", "hillpkg.side", "", types.ModuleType("m"))),
              ("other", _EntryPoint("x", "x:X", "", Hill))]  # fmt: skip

    def entry_points(group=None):
        return [p for g, p in points if g == group]

    fresh.setattr(plugins.importlib.metadata, "entry_points", entry_points)
    plugins.load("g", got.append)
    assert got == [Hill]  # a module entry is imported, not registered
    plugins.load("g", got.append)
    assert got == [Hill]  # once per process
    assert plugins._loaded == {"g"}
    assert plugins._distributions == {"hillpkg.opt": "hill-dist"}


def test_a_plugin_that_fails_is_skipped_and_named(fresh, caplog):
    got = []
    long = "x " * 150
    points = [
        _EntryPoint("bad", "badpkg:Bad", "bad-dist", error=ImportError("no\nnumpy")),
        _EntryPoint("worse", "worse:W", "", error=RuntimeError(long)),
        _EntryPoint("good", "goodpkg:Hill", "", Hill),
    ]
    fresh.setattr(plugins.importlib.metadata, "entry_points", lambda group: points)
    with caplog.at_level(logging.WARNING, logger="locustjump.plugins"):
        plugins.load("g", got.append)
    assert got == [Hill]
    said = [r.getMessage() for r in caplog.records]
    assert said[0] == (
        "plugin 'bad' of distribution bad-dist (badpkg:Bad in g) failed to load and "
        "is skipped: ImportError: no numpy"
    )
    cut = " ".join(long.split())[:197] + "..."
    assert said[1] == (
        "plugin 'worse' (worse:W in g) failed to load and is skipped: "
        f"RuntimeError: {cut}"
    )
    assert len(said) == 2


def test_a_plugins_import_may_ask_its_registry_again(fresh):
    seen = []

    def register(cls):
        seen.append(cls)
        plugins.load("g", seen.append)  # the group is being loaded: no loop

    fresh.setattr(plugins.importlib.metadata, "entry_points",
                  lambda group: [_EntryPoint("h", "h:Hill", "", Hill)])  # fmt: skip
    plugins.load("g", register)
    assert seen == [Hill]


def test_a_module_named_is_imported_or_named(fresh):
    plugins.load_module("json")
    for bad in ("no such", "1mod", "a..b", ""):
        with pytest.raises(UserError, match=exactly(
            f"plugin: {bad!r} is not a module name (e.g. mypkg.mod)"
        )):  # fmt: skip
            plugins.load_module(bad)
    with pytest.raises(UserError) as e:
        plugins.load_module("locustjump_no_such_module")
    assert str(e.value) == (
        "plugin locustjump_no_such_module: cannot import it (ModuleNotFoundError: "
        "No module named 'locustjump_no_such_module')"
    )


def test_where_a_runs_classes_came_from(fresh):
    from locustjump.evo.rcga import RCGA

    outside = type("Hill", (), {"__module__": "hillpkg.opt"})
    mine = type("Mine", (), {"__module__": "__main__"})
    fresh.setattr(plugins, "_distributions", {"hillpkg.opt": "hill-dist"})
    fresh.setattr(plugins, "_packages", lambda: {"solo": ["solo-dist"],
                                                 "two": ["a", "b"]})  # fmt: skip
    solo = type("S", (), {"__module__": "solo.mod"})
    two = type("T", (), {"__module__": "two.mod"})
    assert plugins.provenance([RCGA, outside, mine, solo, two]) == {
        "hillpkg.opt": "hill-dist", "__main__": "", "solo.mod": "solo-dist",
        "two.mod": "",
    }  # fmt: skip
    assert plugins.provenance([type("L", (), {"__module__": "locustjump_x.y"})]) == {
        "locustjump_x.y": ""
    }  # a name that only starts like ours


def test_a_run_made_with_plugins_names_what_it_needs(fresh):
    assert plugins.check_loaded({"json": "", "sys": "x"}, "c.toml") is None
    assert sys.modules.get("hillpkg.opt") is None
    with pytest.raises(UserError, match=exactly(
        "c.toml: made with the plugin hillpkg.opt (distribution hill-dist), which "
        "is not loaded here: install hill-dist, or give plugin hillpkg.opt"
    )):  # fmt: skip
        plugins.check_loaded({"json": "", "hillpkg.opt": "hill-dist"}, "c.toml")
    with pytest.raises(UserError, match=exactly(
        "c.toml: made with the plugin hillpkg.opt, which is not loaded here: "
        "install it, or give plugin hillpkg.opt"
    )):  # fmt: skip
        plugins.check_loaded({"hillpkg.opt": ""}, "c.toml")
    fresh.delitem(sys.modules, "__main__")
    with pytest.raises(UserError, match=exactly(
        "c.toml: made with classes defined in a script or notebook (__main__), "
        "which cannot be loaded here: make them a plugin module "
        "(docs/architecture.md, Plugins)"
    )):  # fmt: skip
        plugins.check_loaded({"__main__": ""}, "c.toml")


def test_the_installed_packages_are_read_once_or_none(monkeypatch):
    plugins._packages.cache_clear()
    monkeypatch.setattr(plugins.importlib.metadata, "packages_distributions",
                        lambda: {"p": ["d"]})  # fmt: skip
    assert plugins._packages() == {"p": ["d"]}

    def broken():
        raise OSError("a broken installation")

    monkeypatch.setattr(plugins.importlib.metadata, "packages_distributions", broken)
    assert plugins._packages() == {"p": ["d"]}  # cached
    plugins._packages.cache_clear()
    assert plugins._packages() == {}
    plugins._packages.cache_clear()


def test_an_error_is_one_line_of_at_most_200_characters():
    assert plugins._one_line(ValueError("a\n  b\tc")) == "a b c"
    assert plugins._one_line(ValueError("x" * 200)) == "x" * 200
    assert plugins._one_line(ValueError("x" * 201)) == "x" * 197 + "..."
