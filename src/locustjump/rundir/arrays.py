"""Checks of the arrays read from a run's ``.npz`` files: each must be what
was written (dtype, shape, finite), or a ``UserError`` names the file and key.

Nothing is converted: a genome saved as ``float32``, ``int64`` or
``complex`` is refused, not rounded into one that would re-simulate to
another fitness.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Literal, overload

import numpy as np

from locustjump.errors import UserError

_KINDS = {"f": "a float64 number", "i": "an integer", "U": "text", "b": "a boolean"}
Arrays = Mapping[str, np.ndarray]


@overload
def scalar(z: Arrays, key: str, path: Path, kind: Literal["f"]) -> float: ...
@overload
def scalar(z: Arrays, key: str, path: Path, kind: Literal["i"]) -> int: ...
@overload
def scalar(z: Arrays, key: str, path: Path, kind: Literal["U"]) -> str: ...
@overload
def scalar(z: Arrays, key: str, path: Path, kind: Literal["b"]) -> bool: ...
def scalar(
    z: Arrays, key: str, path: Path, kind: Literal["f", "i", "U", "b"]
) -> float | int | str | bool:
    """``z[key]`` as a Python value: a 0-d array of ``kind`` (``"f"``:
    float64, finite; ``"i"``: any integer dtype; ``"U"``: text)."""
    a = np.asarray(z[key])
    if kind == "f":
        ok = a.dtype == np.float64
    elif kind == "i":
        ok = a.dtype.kind in "iu"
    else:
        ok = a.dtype.kind == kind
    if not ok or a.ndim != 0:
        raise UserError(
            f"{path}: {key} must be {_KINDS[kind]}, got a {a.dtype} array of "
            f"shape {a.shape}"
        )
    value: float | int | str | bool = a.item()
    if isinstance(value, float) and not math.isfinite(value):  # kind "f"
        raise UserError(f"{path}: {key} must be finite, got {value}")
    return value


def genomes(
    z: Mapping[str, np.ndarray], key: str, path: Path, shape: tuple[int, ...]
) -> np.ndarray:
    """``z[key]``: a finite float64 array of ``shape``."""
    a = np.asarray(z[key])
    if a.dtype != np.float64:
        raise UserError(f"{path}: {key} must be float64, got {a.dtype}")
    if a.shape != shape:
        raise UserError(f"{path}: {key} has shape {a.shape}, expected {shape}")
    if not np.isfinite(a).all():
        raise UserError(f"{path}: {key} must be finite")
    return a


def plain(z: Mapping[str, np.ndarray], keys: list[str], path: Path) -> None:
    """Each of ``keys`` holds numbers or text (no complex, structured or byte
    arrays) and no NaN."""
    for key in keys:
        a = np.asarray(z[key])
        if a.dtype.kind not in "biufU":
            raise UserError(f"{path}: {key} holds {a.dtype} values, not numbers")
        if a.dtype.kind == "f" and np.isnan(a).any():
            raise UserError(f"{path}: {key} holds NaN")
