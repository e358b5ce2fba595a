"""Argument types of ``locustjump``'s parser: each checks one value and
names the option in its one-line error."""

from __future__ import annotations

import argparse

import numpy as np


def _int_at_least(name: str, lo: int):
    def parse(text: str) -> int:
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{name} must be an integer, got {text!r}"
            ) from None
        if v < lo:
            raise argparse.ArgumentTypeError(f"{name} must be >= {lo}, got {v}")
        return v

    return parse


def _substeps(text: str) -> tuple[int, ...]:
    try:
        return tuple(int(t) for t in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"--score-substeps must be integers separated by commas, got {text!r}"
        ) from None


def _seeds(text: str) -> list[int]:
    from locustjump.multiseed import parse_seeds

    try:
        return parse_seeds(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def _finite_float(name: str, *, above: float | None = None, allow_equal: bool = False):
    """A finite number; with ``above``, also > it (or >= with ``allow_equal``)."""

    def parse(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{name} must be a number, got {text!r}"
            ) from None
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
