"""Pickle-free reads of a run's files, bounded before anything is parsed.

A file is read only as far as its kind can be large: a TOML or JSON file up
to :data:`MAX_TEXT_BYTES` (``--config /dev/zero`` stops there) and nested at
most :data:`MAX_NESTING` deep (deeper ones would exhaust the parser's
recursion); an ``.npz`` only if the sizes its members declare fit in memory
(:func:`~locustjump.sim.resources.require_memory`, the check that guards
populations): a member never inflates past the size its zip entry declares,
and no array is allocated past the shape its header declares. Every failure
is a ``UserError`` naming the file.
"""

from __future__ import annotations

import json
import math
import os
import tomllib
import zipfile
from pathlib import Path
from typing import IO, Any

import numpy as np

from locustjump.errors import UserError
from locustjump.sim.resources import require_memory

#: the largest TOML or JSON file read (a config is a few hundred bytes)
MAX_TEXT_BYTES = 1 << 20
#: the deepest nesting of arrays and tables in one (a config needs 2)
MAX_NESTING = 32
#: the most arrays in one ``.npz`` (a checkpoint holds about a dozen)
MAX_NPZ_MEMBERS = 256


def read_text(path: str | os.PathLike[str], what: str = "text file") -> str:
    """The UTF-8 text of ``path``, at most :data:`MAX_TEXT_BYTES` of it."""
    path = Path(path)
    try:
        with open(path, "rb") as f:
            data = f.read(MAX_TEXT_BYTES + 1)
    except FileNotFoundError:
        raise UserError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise UserError(f"{path}: is a directory, expected a {what}") from None
    except OSError as e:
        raise UserError(f"{path}: cannot be read ({e.strerror or e})") from None
    if len(data) > MAX_TEXT_BYTES:
        raise UserError(
            f"{path}: larger than {MAX_TEXT_BYTES // 1024} KiB, not a {what}"
        )
    try:
        return data.decode()
    except UnicodeDecodeError as e:
        raise UserError(f"{path}: not a {what} (not UTF-8: {e.reason})") from None


def nesting(text: str) -> int:
    """How deep arrays and tables nest in TOML or JSON ``text`` (brackets in
    strings and comments do not count)."""
    depth = deepest = 0
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if c == "#":  # a comment (TOML) to the end of its line
            end = text.find("\n", i)
            i = n if end < 0 else end
            continue
        if c in "\"'":
            quote = c * 3 if text.startswith(c * 3, i) else c
            i += len(quote)
            while i < n and not text.startswith(quote, i):
                if c == '"' and text[i] == "\\":
                    i += 1
                elif len(quote) == 1 and text[i] == "\n":
                    break  # unterminated: the parser names it
                i += 1
            i += len(quote)
            continue
        if c in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif c in "]}":
            depth -= 1
        i += 1
    return deepest


def _shallow(path: Path, text: str, what: str) -> None:
    if nesting(text) > MAX_NESTING:
        raise UserError(f"{path}: nested more than {MAX_NESTING} deep, not a {what}")


def read_toml(path: str | os.PathLike[str], what: str = "TOML file") -> dict[str, Any]:
    """A TOML file, bounded in size and nesting before it is parsed."""
    path = Path(path)
    text = read_text(path, what)
    _shallow(path, text, what)
    try:
        return tomllib.loads(text)
    except (tomllib.TOMLDecodeError, RecursionError) as e:
        raise UserError(f"{path}: not valid TOML ({e})") from None


def read_json(path: str | os.PathLike[str]) -> dict[str, Any]:
    """A JSON object (every JSON file of a run is one), bounded in size and
    nesting before it is parsed."""
    path = Path(path)
    text = read_text(path, "JSON file")
    _shallow(path, text, "JSON file")
    try:
        data = json.loads(text)
    except (ValueError, RecursionError) as e:
        raise UserError(f"{path}: not readable JSON ({e})") from None
    if not isinstance(data, dict):
        raise UserError(f"{path}: not a JSON object ({type(data).__name__})")
    return data


def _npy_header(f: IO[bytes]) -> tuple[tuple[int, ...], np.dtype]:
    """Shape and dtype an ``.npy`` stream declares (its header only)."""
    version = np.lib.format.read_magic(f)
    if version == (1, 0):
        shape, _, dtype = np.lib.format.read_array_header_1_0(f)
    elif version == (2, 0):
        shape, _, dtype = np.lib.format.read_array_header_2_0(f)
    else:
        raise ValueError(f"unsupported .npy version {version}")
    return shape, dtype


def _check_members(path: Path, names: set[str], max_bytes: int | None) -> None:
    """Refuse an ``.npz`` whose members ``names`` are not plain arrays, or
    would not fit in memory (or in ``max_bytes``), from its directory and
    headers alone."""
    total = 0
    with zipfile.ZipFile(path) as zf:
        infos = zf.infolist()
        if len(infos) > MAX_NPZ_MEMBERS:
            raise UserError(f"{path}: holds {len(infos)} arrays, not a run's file")
        for info in infos:
            name = info.filename
            if name.removesuffix(".npy") not in names:
                continue  # never read
            with zf.open(info) as f:
                shape, dtype = _npy_header(f)
            if dtype.hasobject:
                raise UserError(f"{path}: {name} holds Python objects (not read)")
            declared = math.prod(shape) * dtype.itemsize
            if declared > info.file_size:
                raise UserError(
                    f"{path}: {name} declares {declared:,} bytes of data but "
                    f"holds {info.file_size:,}"
                )
            total += info.file_size
    if max_bytes is not None and total > max_bytes:
        raise UserError(
            f"{path}: {total:,} bytes of arrays, more than such a file holds "
            f"({max_bytes:,})"
        )
    require_memory(total, f"{path}: its arrays")


def load_npz(
    path: str | os.PathLike[str],
    keys: tuple[str, ...],
    *,
    optional: tuple[str, ...] = (),
    prefix: str | None = None,
    max_bytes: int | None = None,
) -> dict[str, np.ndarray]:
    """The arrays ``keys`` (required), ``optional`` and those whose name
    starts with ``prefix`` of ``path`` (no pickle; other arrays are not
    read); ``UserError`` naming the file if it is missing, not an ``.npz``,
    or holds more than ``max_bytes`` or memory allows."""
    path = Path(path)
    try:
        if path.is_dir():
            raise UserError(f"{path}: is a directory, expected an .npz file")
        if not path.is_file():
            what = "no such file" if not os.path.lexists(path) else "not a file"
            raise UserError(f"{path}: {what}")
        with np.load(path, allow_pickle=False) as z:
            missing = [k for k in keys if k not in z.files]
            if missing:
                raise UserError(f"{path}: missing {', '.join(missing)}")
            names = {*keys, *optional} | {
                k for k in z.files if prefix is not None and k.startswith(prefix)
            }
            names &= set(z.files)
            _check_members(path, names, max_bytes)
            return {k: z[k] for k in z.files if k in names}
    except UserError:
        raise
    except (
        OSError,
        ValueError,
        EOFError,
        zipfile.BadZipFile,
        KeyError,
        MemoryError,
        NotImplementedError,  # an unknown compression method
    ) as e:
        raise UserError(f"{path}: not a readable .npz file ({e})") from None
