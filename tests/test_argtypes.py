"""The parser's argument types (:mod:`locustjump.cli.argtypes`), whole: what
each returns, and the words of what each refuses (argparse prints them after
``argument OPTION:`` on one line, exit 2)."""

import argparse
import dataclasses

import pytest

from locustjump.cli.argtypes import (
    _seeds,
    _terrain_seeds,
    accepts,
    int_list,
    option_type,
    out_path,
    ranged,
)
from locustjump.ranges import Range
from locustjump.tasks.options import option


def _refused(parse, text):
    with pytest.raises(argparse.ArgumentTypeError) as e:
        parse(text)
    return str(e.value)


def test_a_ranged_option_returns_its_number_and_names_itself_when_refused():
    valid = Range(2, 10, integer=True)
    parse = ranged("--population", valid)
    assert parse("7") == 7 and type(parse("7")) is int
    assert parse.valid is valid  # the help reads it
    assert _refused(parse, "11") == "--population must be an integer in [2, 10], got 11"
    assert _refused(parse, "x") == "--population must be an integer in [2, 10], got 'x'"
    assert accepts(valid) == "an integer in [2, 10]"


def test_integers_separated_by_commas_each_in_range():
    parse = int_list("--cells", Range(1, 9, integer=True))
    assert parse("3") == (3,) and parse("1,9,4") == (1, 9, 4)
    assert parse.valid == Range(1, 9, integer=True)
    for bad in ("0", "1,10", "1,,2", "a", "1.5"):
        assert _refused(parse, bad) == (
            f"--cells must be integers separated by commas, each in [1, 9], got {bad!r}"
        )


@dataclasses.dataclass(frozen=True)
class _Options:
    steps: int = option(5, "steps", "N", Range(1, 9, integer=True))
    subs: tuple[int, ...] = option((3,), "subs", "N,...", Range(1, 4, integer=True))
    plain_ints: tuple[int, ...] = option((1, 2), "ints", "N,...")
    count: int = option(2, "count", "N")
    share: float = option(0.5, "share", "X")
    name: str = option("a", "name", "NAME")
    switch: bool = False  # no option() takes a bool; a field may hold one


def _type(name):
    field = {f.name: f for f in dataclasses.fields(_Options)}[name]
    return option_type(f"--{name}", field)


def test_a_behaviours_option_is_parsed_by_its_declaration_or_its_default():
    assert _type("steps")("9") == 9
    assert (
        _refused(_type("steps"), "0") == "--steps must be an integer in [1, 9], got 0"
    )
    assert _type("subs")("1,4") == (1, 4)
    assert _refused(_type("subs"), "5") == (
        "--subs must be integers separated by commas, each in [1, 4], got '5'"
    )
    assert _type("plain_ints")("-3,4") == (-3, 4)  # any 64-bit integers
    assert _refused(_type("plain_ints"), str(2**63)).startswith("--plain_ints must be ")
    assert _type("count")(str(-(2**63))) == -(2**63)
    assert _refused(_type("count"), str(2**63)) == (
        f"--count must be an integer in [-9223372036854775808, 2**63-1], got {2**63}"
    )
    assert _refused(_type("count"), "1.5").startswith("--count must be an integer")
    assert _type("share")("-1e300") == -1e300 and type(_type("share")("2")) is float
    assert _refused(_type("share"), "inf") == "--share must be a finite number, got inf"
    assert _type("name") is str and _type("switch") is str  # checked by its class


def test_seed_lists_name_what_is_wrong():
    assert _seeds("0-2,5") == [0, 1, 2, 5]
    assert _terrain_seeds("3") == [3]
    message = _refused(_seeds, "2-1")
    assert message and not message.startswith("--")
    assert _refused(_terrain_seeds, "2-1") == f"--terrain-seeds {message}"


@pytest.mark.parametrize("text", ["", "  ", "a\0b", "\0"])
def test_an_out_path_is_a_path(text):
    assert _refused(out_path, text) == f"--out must be a path, got {text!r}"


def test_an_out_path_is_given_back_as_written():
    assert out_path(" a b ") == " a b " and out_path("runs/x") == "runs/x"
