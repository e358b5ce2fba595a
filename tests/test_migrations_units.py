"""Each reader of an older format (:mod:`locustjump.rundir.migrations`) on its
own tables, whole: what it returns, that it changes nothing it was given,
and its words when a file is no format it reads (``tests/test_migrations.py``
reads older run directories through the public readers)."""

import copy
import dataclasses
from pathlib import Path

import numpy as np
import pytest

from helpers import exactly
from locustjump.errors import UserError
from locustjump.rundir import migrations as mg
from locustjump.rundir.layout import FORMAT, FROZEN, SEEDS_MARKER
from locustjump.sim.params import LocustParams

SRC = "c.toml"


def _refused(call, *args):
    with pytest.raises(UserError) as e:
        call(*args)
    return str(e.value)


@pytest.mark.parametrize("v", [0, -1, True, 1.0, "2", None])
def test_a_config_format_is_a_whole_number_from_1(v):
    assert _refused(mg.config_format, {"format": v}, SRC) == (
        f"{SRC}: format must be an integer >= 1, got {v!r}"
    )


def test_a_config_format_this_locustjump_reads():
    assert mg.config_format({}, SRC) == 1 and mg.config_format({"format": 2}, SRC) == 2
    assert _refused(mg.config_format, {"format": 3}, SRC) == (
        f"{SRC}: written by a newer locustjump (config format 3; this one reads "
        "up to 2); upgrade locustjump"
    )


def test_a_format_2_table_is_todays_less_its_format():
    d = {"format": 2, "rcga": {"population": 4}, "simple": "x", "model": {"a": [1]}}
    kept = copy.deepcopy(d)
    out = mg.migrate_config(d, SRC)
    assert out == {"rcga": {"population": 4}, "simple": "x", "model": {"a": [1]}}
    out["model"]["a"].append(2)
    assert d == kept  # a copy, however deep


def test_a_format_1_table_gets_todays_spelling():
    whole = {f.name: 0 for f in dataclasses.fields(LocustParams)}
    d = {"rcga": {"population": 4}, "model": {**whole, "engine": "compiled"},
         "simple": "abc", "seed": 1}  # fmt: skip
    kept = copy.deepcopy(d)
    out = mg.migrate_config(d, SRC)
    assert out == {"optimizer": {"kind": "rcga", "population": 4}, "model": whole,
                   "engine": "compiled", "frozen_digest": "abc", "seed": 1}  # fmt: skip
    assert d == kept
    out["optimizer"]["population"] = 9
    assert d["rcga"]["population"] == 4
    assert mg.migrate_config({"rcga": "odd"}, SRC) == {"optimizer": "odd"}  # left to
    # the reader of [optimizer] to name


def test_a_format_1_model_without_engine_is_the_numpy_engine_if_whole():
    names = [f.name for f in dataclasses.fields(LocustParams)]
    old = {n: 0 for n in names if n not in mg.MODEL_FIELDS_LATER}
    assert mg.migrate_config({"model": old}, SRC)["engine"] == "numpy"
    assert mg.migrate_config({"model": {**old, "strut_swing": 1}}, SRC)["engine"] == (
        "numpy"
    )
    partial = dict(list(old.items())[1:])
    assert "engine" not in mg.migrate_config({"model": partial}, SRC)
    assert mg.migrate_config({"model": old, "engine": "x"}, SRC)["engine"] == "x"
    assert mg._whole_model(old) and not mg._whole_model(partial)
    assert mg._whole_model({n: 0 for n in names})


@pytest.mark.parametrize(
    ("d", "words"),
    [
        ({"rcga": {}, "optimizer": {}},
         "give [optimizer] or the older [rcga], not both"),
        ({"model": {"engine": "a"}, "engine": "b"},
         "give engine or the older model.engine, not two"),
        ({"simple": "a", "frozen_digest": "b"},
         "give frozen_digest or the older simple, not both"),
        ({"format": 0}, "format must be an integer >= 1, got 0"),
    ],
)  # fmt: skip
def test_a_format_1_table_with_both_spellings_is_refused(d, words):
    assert _refused(mg.migrate_config, d, SRC) == f"{SRC}: {words}"


FIELDS = ["length", "width", "wall_height", "wall_margin"]


@pytest.mark.parametrize(
    ("table", "filled"),
    [
        ({"length": 1, "width": 2}, {"wall_height": 0.0, "wall_margin": 0.0}),
        ({"length": 1, "width": 2, "wall_height": 0.1}, {"wall_margin": 0.0}),
        ({"length": 1, "width": 2, "wall_height": 0.1, "wall_margin": 0.2}, {}),
    ],
)
def test_a_scene_table_as_locustjump_wrote_it_gets_the_values_absence_meant(
    table, filled
):
    assert mg.scene_before("debris", table, FIELDS) == {**table, **filled}


@pytest.mark.parametrize(
    "table",
    [
        {"length": 1, "width": 2, "wall_margin": 0.2},  # not the last ones added
        {"width": 2},  # a person's partial table
        {"length": 1},
        {},
    ],
)
def test_any_other_partial_scene_table_is_left_for_todays_defaults(table):
    assert mg.scene_before("debris", table, FIELDS) == table
    assert mg.scene_before("flat", table, FIELDS) == table  # nothing added later


def test_a_whole_scene_table_is_given_back_itself():
    whole = dict.fromkeys(FIELDS, 1.0)
    assert mg.scene_before("debris", whole, FIELDS) is whole
    assert mg.scene_before("flat", whole, FIELDS) is whole


def _today(**kw):
    d = {
        "engine": "compiled",
        "optimizer": {"kind": "rcga", "population": 4},
        "model": {
            "scale": 10,
            "strut_stiffness": 1.0,
            "strut_damping": 2.0,
            "strut_swing": 3.0,
        },  # fmt: skip
        "scene": {"kind": "debris", "wall_height": 0.0, "wall_margin": 0.05},
        "frozen_digest": "abc",
        "options": {"score_substeps": [3], "mine": 1},
    }
    d.update(kw)
    return d


MODEL_DEFAULTS = {"strut_stiffness": 1.0, "strut_damping": 9.0, "strut_swing": 3.0}


def test_the_hashed_table_is_the_config_as_format_1_spelled_it():
    d = _today()
    kept = copy.deepcopy(d)
    h = mg.hashed_config(d, MODEL_DEFAULTS, {"score_substeps": [3]}, False)
    assert h == {
        "rcga": {"population": 4},
        "model": {"scale": 10, "strut_damping": 2.0, "engine": "compiled"},
        "scene": {"kind": "debris", "wall_margin": 0.05},
        "simple": "abc",
        "options": {"mine": 1},
    }
    assert d == kept  # nothing it was given is changed


def test_the_hashed_table_keeps_what_differs_from_before():
    d = _today(engine="numpy", optimizer={"kind": "cma", "sigma": 1.0})
    d["scene"] = {"kind": "debris", "wall_height": 0.2, "wall_margin": 0.0}
    h = mg.hashed_config(d, MODEL_DEFAULTS, {"score_substeps": [1]}, True)
    assert h["optimizer"] == {"kind": "cma", "sigma": 1.0} and "rcga" not in h
    assert "engine" not in h["model"] and "engine" not in h
    assert h["scene"] == {"kind": "debris", "wall_height": 0.2}
    assert "options" not in h  # all at their defaults: as before options
    d = _today(scene={"kind": "flat"})
    del d["frozen_digest"], d["options"]
    h = mg.hashed_config(d, MODEL_DEFAULTS, {"score_substeps": [3]}, False)
    assert h["scene"] == {"kind": "flat"} and "simple" not in h and "options" not in h
    assert "scene" not in mg.hashed_config(
        {k: v for k, v in d.items() if k != "scene"}, MODEL_DEFAULTS, {}, True
    )


def test_an_npz_format_this_locustjump_reads(tmp_path):
    p = tmp_path / "x.npz"
    assert mg.npz_format({"format": np.array(1)}, p) == 1
    assert mg.npz_format({"format": np.array(FORMAT)}, p) == FORMAT
    for z in ({}, {"format": np.array("x")}, {"format": np.zeros(2)}):
        assert _refused(mg.npz_format, z, p) == f"{p}: no format version"
    for v in (0, FORMAT + 1):
        assert _refused(mg.npz_format, {"format": np.array(v)}, p) == (
            f"{p}: format {v}, not one this locustjump reads (1 to {FORMAT}); "
            "a newer locustjump wrote it?"
        )


def test_a_checkpoints_optimizer_and_state_in_either_spelling(tmp_path):
    p = tmp_path / "checkpoint.npz"
    now = {"format": np.array(1), "optimizer": np.array("cma"),
           "opt_mean": np.ones(2), "generation": np.array(3)}  # fmt: skip
    assert mg.checkpoint_optimizer(now) == "cma"
    state = mg.checkpoint_state(now, p)
    assert list(state) == ["mean"] and state["mean"] is now["opt_mean"]
    before = {"format": np.array(1), "generation": 1, "population": 2,
              "fitness": 3, "rng_state": 4, "best": 5}  # fmt: skip
    assert mg.checkpoint_optimizer(before) == "rcga"
    assert mg.checkpoint_state(before, p) == {
        "generation": 1, "population": 2, "fitness": 3, "rng_state": 4
    }  # fmt: skip
    del before["population"], before["rng_state"]
    assert _refused(mg.checkpoint_state, before, p) == (
        f"{p}: missing population, rng_state"
    )
    assert _refused(mg.checkpoint_state, {"optimizer": "cma"}, p) == (
        f"{p}: no format version"
    )


def _marker(**kw):
    m = {"budget": "quick", "seed": 0, "population": 8,
         "generations": {"kick": 1, "getup": 2}, "command": "c",
         "locustjump": "1.0"}  # fmt: skip
    m.update(kw)
    return m


def test_a_marker_as_every_locustjump_wrote_one_is_read_as_it_is():
    m = _marker()
    assert mg.check_marker(m, Path("r/reproduce.toml")) is m
    s = {**_marker(seeds=[0, 3], optimizer="rcga")}
    del s["seed"]
    assert mg.check_marker(s, Path("r") / SEEDS_MARKER) is s
    assert mg.check_marker({**s, "seeds": []}, Path(SEEDS_MARKER))["seeds"] == []


@pytest.mark.parametrize(
    ("key", "value", "words"),
    [
        ("budget", 1, "a budget's name"),
        ("seed", True, "a seed"),
        ("seed", 1.0, "a seed"),
        ("population", "8", "an integer"),
        ("generations", {"kick": 0}, "a table of each stage's generations"),
        ("generations", {"kick": True}, "a table of each stage's generations"),
        ("generations", [1], "a table of each stage's generations"),
        ("command", None, "the command"),
        ("locustjump", 1, "the version"),
    ],
)
def test_a_marker_key_of_another_form_is_named(key, value, words):
    p = Path("r/reproduce.toml")
    assert _refused(mg.check_marker, _marker(**{key: value}), p) == (
        f"{p}: {key} must be {words}, got {str(value)[:60]!r}"
    )


def test_a_seeds_marker_key_of_another_form_is_named():
    p = Path("r") / SEEDS_MARKER
    m = _marker(seeds=[0, 1], optimizer="rcga")
    del m["seed"]
    for key, value, words in (("seeds", [0, -1], "a list of seeds"),
                              ("seeds", [True], "a list of seeds"),
                              ("seeds", "0", "a list of seeds"),
                              ("optimizer", 3, "an optimizer's name")):  # fmt: skip
        assert _refused(mg.check_marker, {**m, key: value}, p) == (
            f"{p}: {key} must be {words}, got {str(value)!r}"
        )
    long = 10**70
    assert _refused(mg.check_marker, {**m, "command": 7, "budget": long}, p) == (
        f"{p}: budget must be a budget's name, got {str(long)[:60]!r}"
    )  # the first key found wrong; its value cut at 60 characters


def test_a_marker_without_its_keys_is_no_reproductions():
    p = Path("r/reproduce.toml")
    assert _refused(mg.check_marker, {"seed": 0}, p) == (
        f"{p}: missing budget, population, generations, command, locustjump "
        "(every reproduction's marker holds them: a directory no reproduction made?)"
    )
    m = _marker()
    assert _refused(mg.check_marker, m, Path(SEEDS_MARKER)).startswith(
        f"{SEEDS_MARKER}: missing seeds, optimizer ("
    )


def test_a_marker_and_a_summary_get_the_keys_added_later():
    assert mg.reproduction_marker({"seed": 1, "engine": "compiled"}) == {
        "optimizer": "rcga", "engine": "compiled", "seed": 1,
        "scene": {"kind": "flat", "terrains": 1, "aggregate": "mean"},
    }  # fmt: skip
    old = {"model": {"scale": 10, "engine": "numpy"}, "x": [1]}
    kept = copy.deepcopy(old)
    new = mg.rules_summary(old, "compiled")
    assert new == {"model": {"scale": 10}, "engine": "numpy", "x": [1]}
    assert old == kept
    new["x"].append(2)
    assert old["x"] == [1]
    assert mg.rules_summary({}, "compiled") == {"model": {}, "engine": "compiled"}
    assert mg.rules_summary({"model": {"engine": "a"}, "engine": "b"}, "c") == {
        "model": {}, "engine": "b"
    }  # fmt: skip
    assert mg.rules_summary({"model": 3}, "c") == {"model": 3, "engine": "c"}


def test_the_frozen_genomes_under_the_name_they_were_written_with(tmp_path):
    assert mg.frozen_path(tmp_path) == tmp_path / FROZEN
    (tmp_path / mg.FROZEN_BEFORE).touch()
    assert mg.frozen_path(tmp_path) == tmp_path / mg.FROZEN_BEFORE
    (tmp_path / FROZEN).touch()
    assert mg.frozen_path(str(tmp_path)) == tmp_path / FROZEN


def test_a_configs_source_is_named_in_every_refusal():
    with pytest.raises(UserError, match=exactly("a/b.toml: format must be an integer "
                                                ">= 1, got 0")):  # fmt: skip
        mg.migrate_config({"format": 0}, "a/b.toml")
