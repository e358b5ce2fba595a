"""Argument types of ``locustjump``'s parser: each checks one value and
names the option in its one-line error."""

from __future__ import annotations

import argparse

import numpy as np

from locustjump.runs.multiseed import parse_seeds


def _as(kind, noun: str, name: str, text: str):
    """``kind(text)``, or the one-line error that ``name`` must be ``noun``."""
    try:
        return kind(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{name} must be {noun}, got {text!r}"
        ) from None


#: the largest integer a run records (TOML's integers are 64-bit)
INT_MAX = 2**63 - 1


def _int_at_least(name: str, lo: int):
    def parse(text: str) -> int:
        v = _as(int, "an integer", name, text)
        if v < lo:
            raise argparse.ArgumentTypeError(f"{name} must be >= {lo}, got {v}")
        if v > INT_MAX:
            raise argparse.ArgumentTypeError(
                f"{name} must be at most 2**63-1 (a 64-bit integer), got {v}"
            )
        return v

    return parse


def _int_list(name: str):
    def parse(text: str) -> tuple[int, ...]:
        return _as(lambda t: tuple(int(v) for v in t.split(",")),
                   "integers separated by commas", name, text)  # fmt: skip

    return parse


def option_type(name: str, default: object):
    """The argument type of option ``name`` (a behaviour's, declared with
    :func:`locustjump.tasks.base.option`) whose default is ``default``: the
    value's form only; the behaviour's ``Options`` checks its range."""
    if isinstance(default, int):
        return _int_at_least(name, -INT_MAX - 1)
    if isinstance(default, float):
        return _finite_float(name)
    if isinstance(default, tuple):
        return _int_list(name)
    return str


def _cell(text: str) -> tuple[int, ...]:
    """``--cell I,J``: a grid cell, one index (from 0) per descriptor."""
    try:
        cell = tuple(int(t) for t in text.split(","))
    except ValueError:
        cell = ()
    if not cell or min(cell) < 0:
        raise argparse.ArgumentTypeError(
            f"--cell must be indices >= 0 separated by commas (e.g. 3,7), got {text!r}"
        )
    return cell


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


def _finite_float(name: str, *, above: float | None = None, allow_equal: bool = False):
    """A finite number; with ``above``, also > it (or >= with ``allow_equal``)."""

    def parse(text: str) -> float:
        v = _as(float, "a number", name, text)
        low = above is not None and (v < above if allow_equal else v <= above)
        if not np.isfinite(v) or low:
            bound = (
                ""
                if above is None
                else f" and {'>=' if allow_equal else '>'} {above:g}"
            )
            raise argparse.ArgumentTypeError(
                f"{name} must be finite{bound}, got {text}"
            )
        return v

    return parse


def _positive_float(name: str, *, allow_zero: bool = False):
    return _finite_float(name, above=0.0, allow_equal=allow_zero)


def out_path(text: str) -> str:
    """An ``--out`` path: not empty (``''`` would be the working directory)."""
    if not text.strip():
        raise argparse.ArgumentTypeError(f"--out must be a path, got {text!r}")
    return text
