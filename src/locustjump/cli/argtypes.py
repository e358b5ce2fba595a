"""Argument types of ``locustjump``'s parser: each checks one value against
the range its setting declares (:mod:`locustjump.ranges`) and names the option
in its one-line error; :func:`accepts` says the same range in the help."""

from __future__ import annotations

import argparse
import dataclasses
from collections.abc import Callable
from typing import Any

from locustjump.ranges import Range, SettingError
from locustjump.runs.multiseed import parse_seeds


def ranged(option: str, valid: Range) -> Callable[[str], Any]:
    """The argument type of ``option``, whose setting accepts ``valid``."""

    def parse(text: str) -> Any:
        try:
            return valid.parse(option, text)
        except SettingError as e:
            raise argparse.ArgumentTypeError(str(e)) from None

    parse.valid = valid  # type: ignore[attr-defined]  # the help says it
    return parse


def accepts(valid: Range) -> str:
    """``valid`` for a help text: ``an integer in [2, 1000000]``."""
    return str(valid)


def int_list(option: str, each: Range) -> Callable[[str], tuple[int, ...]]:
    """Integers separated by commas, each in ``each``."""
    what = f"integers separated by commas, each in {each.interval()}"

    def parse(text: str) -> tuple[int, ...]:
        try:
            return tuple(each.parse(option, t) for t in text.split(","))
        except SettingError:
            raise argparse.ArgumentTypeError(
                f"{option} must be {what}, got {text!r}"
            ) from None

    parse.valid = each  # type: ignore[attr-defined]
    return parse


#: a behaviour's option that declares no range: any 64-bit integer, any finite
#: number (its ``Options`` class checks it)
_ANY_INT = Range(-(2**63), 2**63 - 1, integer=True)
_ANY_NUMBER = Range()


def option_type(name: str, field: dataclasses.Field[Any]) -> Callable[[str], Any]:
    """The argument type of option ``name``, a behaviour's (declared with
    :func:`locustjump.tasks.options.option`): its declared range (of each
    number, for a tuple), else the form of its default."""
    if "range" in field.metadata:
        return ranged(name, field.metadata["range"])
    if isinstance(field.default, tuple):
        return int_list(name, field.metadata.get("each", _ANY_INT))
    if isinstance(field.default, bool) or not isinstance(field.default, int | float):
        return str
    return ranged(name, _ANY_INT if isinstance(field.default, int) else _ANY_NUMBER)


def _seeds(text: str) -> list[int]:

    try:
        return parse_seeds(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def _terrain_seeds(text: str) -> list[int]:
    try:
        return parse_seeds(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(f"--terrain-seeds {e}") from None


def out_path(text: str) -> str:
    """An ``--out`` path: not empty (``''`` would be the working directory),
    no null byte (which no path holds; only a caller of ``main`` can pass one)."""
    if not text.strip() or "\0" in text:
        raise argparse.ArgumentTypeError(f"--out must be a path, got {text!r}")
    return text
