"""A config.toml's values as their settings' types (rundir/config.py's coerce
and from_table), stated exactly: what each type accepts and refuses, array
items, and the file and key each error names."""

import re

import pytest

from helpers import exactly
from locustjump.errors import UserError
from locustjump.evo.map_elites import MapElitesParams
from locustjump.rundir import config as C
from locustjump.sim.scene import Debris
from locustjump.tasks.base import CommonOptions

SRC = "cfg.toml"


@pytest.mark.parametrize(
    "value, default, expected",
    [
        (True, False, True),
        (-(2**63), 0, -(2**63)),
        (2**63 - 1, 0, 2**63 - 1),
        (3, 0.5, 3.0),
        (2.5, 0.5, 2.5),
        ("a", "", "a"),
        ([1, 2], (), (1, 2)),
        ([], (), ()),
        ([1, 2.5], (0.0, 0.0), (1.0, 2.5)),
    ],
)
def test_coerce_accepts_its_type(value, default, expected):
    got = C.coerce(value, default, "k", SRC)
    assert got == expected and type(got) is type(expected)
    if isinstance(got, tuple):
        assert [type(v) for v in got] == [type(v) for v in expected]


@pytest.mark.parametrize(
    "value, default, message",
    [
        (1, False, "k must be bool, got int 1"),
        (True, 0, "k must be int, got bool True"),
        (False, 0.0, "k must be float, got bool False"),
        ("1", 0.0, "k must be float, got str '1'"),
        (1.5, 0, "k must be int, got float 1.5"),
        (2**63, 0, "k must be a 64-bit integer (TOML's), got 9223372036854775808"),
        (
            -(2**63) - 1,
            0,
            "k must be a 64-bit integer (TOML's), got -9223372036854775809",
        ),
        (1, "", "k must be str, got int 1"),
        ((1, 2), (), "k must be an array of integers, got (1, 2)"),
        ([1, True], (), "k[1] must be int, got bool True"),
        ([1.0], (0.0, 0.0), "k must be an array of 2 numbers, got [1.0]"),
        ((1.0, 2.0), (0.0, 0.0), "k must be an array of 2 numbers, got (1.0, 2.0)"),
        ([1.0, "x"], (0.0, 0.0), "k[1] must be float, got str 'x'"),
    ],
)
def test_coerce_refuses_what_is_not_its_type(value, default, message):
    with pytest.raises(UserError, match=exactly(f"{SRC}: {message}")):
        C.coerce(value, default, "k", SRC)


def test_an_array_s_items_are_of_the_field_s_item_type():
    assert C.coerce(["a", "b"], (), "k", SRC, "") == ("a", "b")
    got = C.coerce([[0, 1], [2.5, 3]], (), "k", SRC, (0.0, 0.0))
    assert got == ((0.0, 1.0), (2.5, 3.0)) and type(got[0][0]) is float
    for item, what in (("", "strings"), ((0.0, 0.0), "arrays"), (0, "integers")):
        message = f"{SRC}: k must be an array of {what}, got 'x'"
        with pytest.raises(UserError, match=exactly(message)):
            C.coerce("x", (), "k", SRC, item)


def test_from_table_reads_an_array_field_as_its_metadata_s_item_says():
    table = {"population": 4, "descriptors": ["apex_rise"], "ranges": [[0, 2]]}
    got = C.from_table(MapElitesParams, table, "optimizer", SRC)
    assert got.descriptors == ("apex_rise",) and got.ranges == ((0.0, 2.0),)
    message = f"{SRC}: optimizer.descriptors[0] must be str, got int 1"
    with pytest.raises(UserError, match=exactly(message)):
        C.from_table(MapElitesParams, {"descriptors": [1]}, "optimizer", SRC)


def test_from_table_names_the_section():
    assert C.from_table(CommonOptions, {"score_substeps": [2, 3]}, "options", SRC) == (
        CommonOptions((2, 3))
    )
    with pytest.raises(UserError, match=exactly(f"{SRC}: options must be a table")):
        C.from_table(CommonOptions, [1], "options", SRC)
    with pytest.raises(UserError, match=exactly(f"{SRC}: unknown key 'options.x'")):
        C.from_table(CommonOptions, {"x": 1}, "options", SRC)
    with pytest.raises(UserError, match=re.escape(f"{SRC}: [options] score_substeps ")):
        C.from_table(CommonOptions, {"score_substeps": [2, 2]}, "options", SRC)


def test_a_debris_table_written_before_its_walls_has_none():
    # a table that names every other field but lacks the walls was written
    # before they existed: no walls, not today's defaults
    table = {k: v for k, v in vars(Debris(seed=2)).items()}
    del table["wall_height"], table["wall_margin"]
    t = C.terrains_from_table({"kind": "debris", **table}, SRC)
    assert (t.scene.wall_height, t.scene.wall_margin) == (0.0, 0.0)
    assert Debris().wall_height != 0.0


def test_errors_inside_a_table_name_the_file_and_the_key():
    with pytest.raises(UserError, match=exactly(f"{SRC}: optimizer must be a table")):
        C.optimizer_from_table(3, SRC)
    message = f"{SRC}: options.score_substeps must be an array of integers, got 'x'"
    with pytest.raises(UserError, match=exactly(message)):
        C.from_table(CommonOptions, {"score_substeps": "x"}, "options", SRC)
    with pytest.raises(UserError, match=re.escape(f"{SRC}: written by a newer")):
        C.TrainConfig.from_dict({"format": 99}, SRC)


def test_a_setting_of_a_type_coerce_does_not_know_is_a_programming_error():
    with pytest.raises(TypeError, match=exactly("<class 'dict'>")):
        C.coerce(1, {}, "k", SRC)
