"""The words of :mod:`locustjump.ranges`, whole: what a range says it
accepts, what value it quotes back, and the checks of kinds and choices every
setting's one-line error is made of (``tests/test_ranges.py`` checks that the
parser, its help and the config reader read one declaration)."""

import dataclasses

import numpy as np
import pytest

from helpers import exactly, user_error
from locustjump.errors import setting_ref
from locustjump.ranges import (
    INT64_MAX,
    Range,
    SettingError,
    SettingTypeError,
    SettingValueError,
    check_choice,
    check_settings,
    check_type,
    range_of,
    renamed,
    setting,
)


def _error(call, *args):
    with pytest.raises(SettingError) as e:
        call(*args)
    return e.value


@pytest.mark.parametrize(
    ("valid", "words"),
    [
        (Range(2, 10, integer=True), "an integer in [2, 10]"),
        (Range(0, 1, lo_open=True), "in (0, 1]"),
        (Range(0, 1, hi_open=True), "in [0, 1)"),
        (Range(0, 120, lo_open=True, unit="s"), "in (0, 120] s"),
        (Range(0, integer=True), "an integer >= 0"),
        (Range(0, lo_open=True, unit="m"), "a finite number > 0 m"),
        (Range(hi=5), "a finite number <= 5"),
        (Range(hi=5, hi_open=True, integer=True), "an integer < 5"),
        (Range(), "a finite number"),
        (Range(integer=True), "an integer"),
        (Range(unit="s"), "a finite number"),  # no bounds: no unit
        (Range(0, INT64_MAX, integer=True), "an integer in [0, 2**63-1]"),
        (Range(0.5, 2.5e6), "in [0.5, 2.5e+06]"),
        (Range(0, lo_open=True, size=2), "2 finite numbers each > 0"),
        (
            Range(1, 9, integer=True, size=3, unit="cells"),
            "3 integers each in [1, 9] cells",
        ),  # fmt: skip
        (Range(size=2), "2 finite numbers"),
    ],
)
def test_a_range_says_what_it_accepts(valid, words):
    assert str(valid) == words


def test_a_value_is_quoted_back_as_given_and_cut_at_80_characters():
    def got(value):
        return str(_error(Range(0, 1).check, "x", value)).split(", got ", 1)[1]

    assert got(2) == "2" and got(2.5) == "2.5"  # numbers as numbers
    assert got("a") == "'a'" and got(None) == "None"  # the rest as Python writes it
    assert got(True) == "True"  # a bool is not a number here
    assert got(np.float64(3.0)) == "3.0"
    tuples = Range(size=2)
    assert str(_error(tuples.check, "v", "x" * 78)).endswith(", got '" + "x" * 78 + "'")
    long = str(_error(tuples.check, "v", "x" * 79))  # its repr has 81 characters
    assert long.endswith(", got '" + "x" * 76 + "...")
    assert len(long.split(", got ", 1)[1]) == 80


def test_an_error_names_its_setting_and_keeps_what_it_was_given():
    e = _error(Range(2, 10, integer=True).check, "population", 11)
    assert isinstance(e, SettingValueError) and isinstance(e, ValueError)
    assert (e.name, e.expected, e.value) == ("population", "an integer in [2, 10]", 11)
    assert (
        e.message
        == f"{setting_ref('population')} must be an integer in [2, 10], got 11"
    )
    assert e.setting == "population"
    odd = _error(Range(0, 1).check, "options['start']", 2)  # no setting's name
    assert odd.message == "options['start'] must be in [0, 1], got 2"
    assert odd.setting is None


def test_a_renamed_error_is_the_same_error_of_another_setting():
    e = _error(Range(0, 1).check, "x", "a")
    r = e.renamed("steps")
    assert type(r) is SettingTypeError
    assert (r.name, r.expected, r.value) == ("steps", "a number in [0, 1]", "a")
    assert str(r) == "steps must be a number in [0, 1], got 'a'"
    with pytest.raises(SettingValueError, match=exactly("n must be in [0, 1], got 2")):
        with renamed({"x": "n"}):
            Range(0, 1).check("x", 2)
    with pytest.raises(SettingValueError, match=exactly("y must be in [0, 1], got 2")):
        with renamed({"x": "n"}):  # not one it renames
            Range(0, 1).check("y", 2)


def test_a_bound_is_in_or_out_as_declared():
    closed, open_ = Range(0, 1), Range(0, 1, lo_open=True, hi_open=True)
    assert closed.contains(0) and closed.contains(1)
    assert not open_.contains(0) and not open_.contains(1) and open_.contains(0.5)
    assert not closed.contains(1.0000000000000002) and not closed.contains(-1e-300)
    assert Range(hi=1).contains(-1e308) and not Range(hi=1).contains(2)


def test_the_value_in_an_error_is_the_whole_value_given():
    v = Range(0, 1, size=2)
    assert _error(v.check, "v", (0.5, 2)).value == (0.5, 2)
    assert _error(v.check, "v", (0.5, True)).value == (0.5, True)
    assert _error(v.check, "v", (0.5, "a")).value == (0.5, "a")
    assert _error(Range(0, 1).check, "x", 10**400).value == 10**400  # beyond floats
    assert _error(Range(integer=True).check, "n", 1.0).value == 1.0


def test_an_options_text_is_parsed_into_the_range():
    assert Range(0, 10, integer=True).parse("n", "7") == 7
    assert Range(size=2).parse("v", "1,2.5") == (1.0, 2.5)
    assert Range(integer=True, size=2).parse("c", "3,4") == (3, 4)
    with pytest.raises(SettingTypeError) as e:
        Range(size=2).parse("v", "1 2")
    assert (str(e.value), e.value.value) == (
        "v must be 2 finite numbers, got '1 2'",
        "1 2",
    )
    with pytest.raises(
        SettingTypeError, match=exactly("v must be 2 finite numbers, got '1'")
    ):
        Range(size=2).parse("v", "1")
    with pytest.raises(SettingValueError) as e:  # one of them out of range
        Range(0, lo_open=True, size=2).parse("v", "1,-2")
    assert (str(e.value), e.value.value) == (
        "v must be 2 finite numbers each > 0, got '1,-2'",
        "1,-2",
    )
    with pytest.raises(
        SettingTypeError, match=exactly("n must be an integer, got '1.5'")
    ):
        Range(integer=True).parse("n", "1.5")
    with pytest.raises(
        SettingValueError, match=exactly("n must be an integer >= 2, got 1")
    ):
        Range(2, integer=True).parse("n", "1")  # one number: quoted as a number
    with pytest.raises(
        SettingTypeError, match=exactly("n must be an integer, got '1,2'")
    ):
        Range(integer=True).parse("n", "1,2")


def test_a_dataclass_declares_its_ranges_once():
    @dataclasses.dataclass(frozen=True)
    class Settings:
        n: int = setting(3, Range(1, 9, integer=True))
        x: float = setting(0.5, Range(0, 1), compare=False)
        plain: str = "free"

        def __post_init__(self):
            check_settings(self)

    assert Settings().n == 3 and Settings().x == 0.5
    assert not dataclasses.fields(Settings)[1].compare  # kwargs reach the field
    assert Settings(x=1).x == 1.0 and type(Settings(x=1).x) is float
    assert Settings(n=np.int64(4)).n == 4 and type(Settings(n=np.int64(4)).n) is int
    assert range_of(Settings, "n") == Range(1, 9, integer=True)
    assert range_of(Settings(), "x") == Range(0, 1)
    with pytest.raises(KeyError) as e:
        range_of(Settings, "plain")
    assert e.value.args == ("Settings declares no range for 'plain'",)
    with pytest.raises(KeyError) as e:
        range_of(Settings(), "nothing")
    assert e.value.args == (f"{Settings()!r} declares no range for 'nothing'",)
    assert user_error(Settings, n=0) == "n must be an integer in [1, 9], got 0"


def test_a_kind_is_checked_and_a_bool_is_not_an_integer():
    assert check_type("k", 3, int, "an integer") == 3
    assert check_type("k", True, bool, "on or off") is True
    assert check_type("k", True, (int, bool), "a count or a switch") is True
    assert check_type("k", "a", (int, str), "a name or a number") == "a"
    e = _error(check_type, "k", True, int, "an integer")
    assert type(e) is SettingTypeError
    assert (e.name, e.expected, e.value) == ("k", "an integer", True)
    assert str(e) == "k must be an integer, got True"
    assert str(_error(check_type, "k", 1.5, (int, str), "a number")) == (
        "k must be a number, got 1.5"
    )


def test_a_choice_is_one_of_its_names():
    assert check_choice("scene", "flat", ("flat", "debris")) == "flat"
    e = _error(check_choice, "scene", "moon", ("flat", "debris"))
    assert type(e) is SettingValueError
    assert (e.name, e.expected, e.value) == ("scene", "one of flat, debris", "moon")
    assert str(e) == "scene must be one of flat, debris, got 'moon'"
    e = _error(check_choice, "scene", 3, ("flat", "debris"))
    assert type(e) is SettingTypeError
    assert str(e) == "scene must be one of flat, debris, got 3"
