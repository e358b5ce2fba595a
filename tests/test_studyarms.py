"""A study's arms (runs/studyarms.py) stated exactly: the arms' keys merged
over ``[defaults]``, each arm's own key checked with its one line, where an
arm's runs are, its seeds' training terrains, and the arms ordered so that each
follows those it builds on."""

from pathlib import Path

import pytest

from helpers import user_error
from locustjump.runs.studyarms import ARM_KEYS, _merged, parse_arms
from locustjump.sim.scene import Debris

SRC = "s.toml"
ROOT = Path("runs/x")
DEFAULTS = {"behaviour": "kick", "generations": 2, "optimizer": {"population": 4}}
#: the simple arms a composed arm builds on
SIMPLE = {"kick": {"behaviour": "kick", "score": False},
          "getup": {"behaviour": "getup", "score": False},
          "legs": {"behaviour": "return-legs", "score": False}}  # fmt: skip
FROZEN = {"kick": "kick", "getup": "getup", "return-legs": "legs"}
DEBRIS = {"kind": "debris", "seed": 10, "terrains": 2}
FIXED = ("seed: a scored arm has a run per seed of the study; a fixed seed is for "
         "an arm others build on (score = false)")  # fmt: skip


def arms(d, defaults=None):
    return parse_arms(d, DEFAULTS if defaults is None else defaults, ROOT, SRC)


def refused(d, defaults=None) -> str:
    return user_error(arms, d, defaults)


def test_an_arms_defaults():
    a = arms({"a": {}})["a"]
    assert (a.name, a.label, a.frozen, a.score) == ("a", "a", {}, True)
    assert (a.path, a.paths, a.fixed_seed) == ("runs/x/a/seed-{seed}", {}, None)
    assert (a.terrain_stride, a.extends) == (0, None)
    assert a.run_dir(3) == Path("runs/x/a/seed-3") and a.source_dir(3) is None
    assert a.config(5) == a.base.replace(seed=5) and a.base.generations == 2


def test_every_key_of_an_arm_is_read():
    table = {"label": "A", "score": False, "path": "p/{seed}", "paths": {"4": "q"},
             "extends": "e/{seed}", "seed": 9, "generations": 3, "scene": DEBRIS,
             "terrain_stride": 2}  # fmt: skip
    a = arms({"a": table})["a"]
    assert (a.label, a.score, a.fixed_seed, a.terrain_stride) == ("A", False, 9, 2)
    assert a.base.generations == 3 and a.base.seed == 9
    assert a.seed_of(0) == a.seed_of(5) == 9
    assert a.run_dir(0) == Path("p/9") and a.source_dir(1) == Path("e/9")
    b = arms({"b": {"paths": {"4": "q", "05": "r"}, "extends": "e/{seed}"}})["b"]
    assert b.paths == {4: "q", 5: "r"}
    assert b.run_dir(4) == Path("q") and b.run_dir(5) == Path("r")
    assert b.run_dir(3) == Path("runs/x/b/seed-3") and b.source_dir(4) == Path("e/4")


def test_each_seed_trains_on_its_own_terrains():
    a = arms({"a": {"scene": DEBRIS, "terrain_stride": 2}})["a"]
    for seed in (0, 1, 3):
        t = a.config(seed).scene
        assert t.scene == Debris(seed=10 + 2 * seed) and t.count == 2
        assert a.config(seed).seed == seed
    assert arms({"a": {"scene": DEBRIS}})["a"].config(3).scene.scene.seed == 10


def test_a_table_merged_key_by_key_and_replaced_by_another_kind():
    base = {"optimizer": {"kind": "rcga", "population": 4, "sub": {"x": 1, "y": 2}}}
    got = _merged(base, {"optimizer": {"sub": {"y": 3}}, "generations": 5})
    want = {"kind": "rcga", "population": 4, "sub": {"x": 1, "y": 3}}
    assert got == {"optimizer": want, "generations": 5}
    assert base["optimizer"]["sub"] == {"x": 1, "y": 2}  # a copy
    assert _merged(base, {"optimizer": {"kind": "random"}}) == {
        "optimizer": {"kind": "random"}
    }
    same_kind = _merged(base, {"optimizer": {"kind": "rcga"}})
    assert same_kind["optimizer"]["population"] == 4
    assert _merged({"a": 1}, {"a": {"b": 2}}) == {"a": {"b": 2}}
    assert _merged({"a": {"b": 2}}, {"a": 1}) == {"a": 1}
    over = {"a": {"b": [1]}}
    got = _merged({}, over)
    got["a"]["b"].append(2)
    assert over == {"a": {"b": [1]}}  # the arm's table is not shared
    got = _merged(base, {})
    got["optimizer"]["sub"]["x"] = 9
    assert base["optimizer"]["sub"]["x"] == 1


def test_defaults_merged_under_each_arm():
    defaults = {**DEFAULTS, "optimizer": {"kind": "rcga", "population": 6}}
    got = arms({"a": {"optimizer": {"kind": "rcga", "elite": 1}}, "b": {}}, defaults)
    a = got["a"].base.optimizer
    assert (a.population, a.elite) == (6, 1)
    assert got["b"].base.optimizer.population == 6


@pytest.mark.parametrize("d", [{}, [], None, "a"])
def test_no_arms(d):
    assert refused(d) == f"{SRC}: no arms (add an [arms.NAME] table)"


@pytest.mark.parametrize("key", [*ARM_KEYS, "seed", "format"])
def test_an_arms_own_key_is_no_default(key):
    assert refused({"a": {}}, {**DEFAULTS, key: 1}) == (
        f"{SRC}: defaults.{key}: an arm's own key, not a default"
    )


@pytest.mark.parametrize(
    "d, message",
    [
        ({"a": 3}, "must be a table"),
        ({"a": {"format": 2}}, "format: an arm is today's config.toml spelling"),
        ({"a": {"seed": 3}}, FIXED),
        ({"a": {"seed": 3, "score": True}}, FIXED),
        ({"a": {"label": ""}}, "label must be a non-empty string, got ''"),
        ({"a": {"label": 1}}, "label must be a non-empty string, got 1"),
        ({"a": {"score": 1}}, "score must be true or false, got 1"),
        ({"a": {"path": " "}}, "path must be a non-empty string, got ' '"),
        ({"a": {"extends": 1}}, "extends must be a non-empty string, got 1"),
        ({"a": {"paths": ["x"]}}, 'paths must be a table of seed = "DIR"'),
        ({"a": {"paths": {"-1": "x"}}}, "paths: '-1' is not a seed"),
        ({"a": {"paths": {"0": ""}}}, "paths.0 must be a non-empty string, got ''"),
    ],
)  # fmt: skip
def test_an_arms_own_keys_are_checked(d, message):
    assert refused(d) == f"{SRC} [arms.a]: {message}"


def test_a_fixed_seed_of_an_arm_that_is_not_scored():
    assert arms({"a": {"seed": 0, "score": False}})["a"].fixed_seed == 0


@pytest.mark.parametrize(
    "key, value",
    [("path", "x/{sed}"), ("path", "x/{0}"), ("path", "x/{"), ("path", "{seed.real.x}"),
     ("path", "{seed[0]}"), ("path", "{seed:s}"), ("path", "r/{seed:c}"),
     ("extends", "y/{seed}/{n}"),
     ("extends", "{"), ("paths.3", "{}")],
)  # fmt: skip
def test_a_path_template_has_only_the_seed(key, value):
    """A run's directory, the run it extends and a single seed's directory."""
    table = {"paths": {"3": value}} if key == "paths.3" else {key: value}
    assert refused({"a": table}) == (
        f"{SRC} [arms.a]: {key} {value!r}: the only field is {{seed}}, an integer"
    )


def test_a_template_may_format_its_seed_and_keep_braces():
    a = arms({"a": {"path": "d-{seed:03d}/{{x}}", "paths": {"2": "p{seed}"},
                    "extends": "{seed}"}})["a"]  # fmt: skip
    assert a.run_dir(7) == Path("d-007/{x}") and a.run_dir(2) == Path("p2")
    assert a.source_dir(7) == Path("7")


def test_defaults_that_are_not_a_table():
    assert refused({"a": {}}, 3) == f"{SRC}: [defaults] must be a table"
    assert arms({"a": {}}, {})["a"].base.generations != 2  # none taken


def test_an_arms_config_keys_are_checked_naming_the_arm():
    assert refused({"a": {"generations": 0}}).startswith(
        f"{SRC} [arms.a]: generations must be"
    )
    assert refused({"a": {"populaton": 3}}) == (
        f"{SRC} [arms.a]: unknown key 'populaton'"
    )


@pytest.mark.parametrize(
    "value, message",
    [
        (True, "terrain_stride must be an integer >= 0, got True"),
        (-1, "terrain_stride must be an integer >= 0, got -1"),
        (2**31, f"terrain_stride must be an integer >= 0, got {2**31}"),
        (2.0, "terrain_stride must be an integer >= 0, got 2.0"),
        (1, "terrain_stride 1 < terrains 2: the seeds' training terrains would "
            "overlap"),
    ],
)  # fmt: skip
def test_the_terrain_stride(value, message):
    got = refused({"a": {"scene": DEBRIS, "terrain_stride": value}})
    assert got == f"{SRC} [arms.a]: {message}"


def test_the_terrain_stride_at_its_edges():
    a = arms({"a": {"scene": DEBRIS, "terrain_stride": 2**31 - 1}})["a"]
    assert a.terrain_stride == 2**31 - 1
    assert arms({"a": {"scene": DEBRIS, "terrain_stride": 2}})["a"].terrain_stride == 2
    assert arms({"a": {"scene": DEBRIS, "terrain_stride": 0}})["a"].terrain_stride == 0
    assert arms({"a": {"terrain_stride": 0}})["a"].terrain_stride == 0  # flat, off
    assert refused({"a": {"terrain_stride": 4}}) == (
        f"{SRC} [arms.a]: terrain_stride: the flat scene has no terrains to choose from"
    )


@pytest.mark.parametrize(
    "frozen, message",
    [
        ({"kick": 3}, 'frozen must be a table of behaviour = "ARM"'),
        ("kick", 'frozen must be a table of behaviour = "ARM"'),
        ({}, "frozen must name the arm of each of kick, getup, return-legs"),
        ({"kick": "kick", "getup": "getup"}, "frozen must name the arm of each of "
         "kick, getup, return-legs (got getup, kick)"),
        ({**FROZEN, "x": "kick"}, "frozen must name the arm of each of kick, getup, "
         "return-legs (got getup, kick, return-legs, x)"),
        ({**FROZEN, "kick": "nokick"}, "frozen: no arm 'nokick' in this study"),
    ],
)  # fmt: skip
def test_a_composed_arm_names_the_arm_of_each_behaviour_it_builds_on(frozen, message):
    got = refused({**SIMPLE, "c": {"behaviour": "composed", "frozen": frozen}})
    assert got == f"{SRC} [arms.c]: {message}"


def test_a_simple_arm_builds_on_no_runs():
    assert refused({**SIMPLE, "a": {"frozen": {"kick": "kick"}}}) == (
        f"{SRC} [arms.a]: frozen: kick builds on no runs"
    )


def test_the_arms_come_in_file_order_each_after_those_it_builds_on():
    got = arms({"c": {"behaviour": "composed", "frozen": FROZEN}, "z": {}, **SIMPLE})
    assert list(got) == ["kick", "getup", "legs", "c", "z"]
    assert got["c"].frozen == FROZEN and list(got["c"].frozen) == [
        "kick", "getup", "return-legs"
    ]  # fmt: skip
    mixed = {"getup": "getup", "return-legs": "legs", "kick": "kick"}
    got = arms({**SIMPLE, "c": {"behaviour": "composed", "frozen": mixed}})
    assert list(got["c"].frozen) == ["kick", "getup", "return-legs"]
    assert list(got) == ["kick", "getup", "legs", "c"]


def test_arms_that_build_on_each_other_in_a_circle():
    d = {"kick": {"behaviour": "composed",
                  "frozen": {**FROZEN, "kick": "c"}, "score": False},
         "getup": SIMPLE["getup"], "legs": SIMPLE["legs"],
         "c": {"behaviour": "composed", "frozen": FROZEN}}  # fmt: skip
    assert refused(d) == (
        f"{SRC}: the arms build on each other in a circle: kick -> c -> kick"
    )
    d["kick"]["frozen"] = {**FROZEN}
    circle = f"{SRC}: the arms build on each other in a circle:"
    assert refused(d) == f"{circle} kick -> kick"


def test_two_arms_of_one_label():
    got = refused({"a": {"label": "b"}, "b": {}})
    assert got == f"{SRC} [arms.b]: label 'b' is arm 'a''s already"
    assert set(arms({"a": {"label": "A"}, "b": {"label": "B"}})) == {"a", "b"}
