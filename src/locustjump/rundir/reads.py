"""Pickle-free reads of a run's files, bounded before anything is parsed.

Every file any command reads goes through :func:`open_regular`: a regular
file (after symbolic links) is opened, anything else — a directory, a FIFO or
pipe (``/dev/stdin``), a device (``/dev/zero``), a socket — is refused before
it is opened, so that no read blocks or never ends. Sizes are bounded by the
bytes actually read, never by the size a file reports (``/proc`` files report
0): a TOML or JSON file up to :data:`MAX_TEXT_BYTES` (``--config /dev/zero``
stops there); its nesting at most :data:`MAX_NESTING` deep however it is
spelled — brackets counted before parsing (deeper ones exhaust the parser's
recursion), dotted keys and table headers (``a.a.a = 1``, which the parser
reads without recursion) counted in the parsed value, before any code walks
it. An ``.npz`` holds only the arrays asked for, at most
:data:`MAX_NPZ_MEMBERS` of them, and the sizes their headers declare must fit
the caller's bound and memory
(:func:`~locustjump.sim.resources.require_memory`) before any is inflated: no
member inflates past the size its header declares. Every failure is a
``UserError`` naming the file.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import stat
import tomllib
import zipfile
import zlib
from collections.abc import Iterator
from pathlib import Path
from typing import IO, Any, BinaryIO

import numpy as np

from locustjump.errors import UserError
from locustjump.sim.resources import require_memory

#: the largest TOML or JSON file read (a config is a few hundred bytes)
MAX_TEXT_BYTES = 1 << 20
#: the deepest nesting of arrays and tables in one (a config needs 2)
MAX_NESTING = 32
#: the most arrays in one ``.npz`` (a checkpoint holds about a dozen)
MAX_NPZ_MEMBERS = 256
#: the most bytes of arrays an ``.npz`` may declare where its reader knows no
#: tighter bound (each of a run's files has its own: genome files by their
#: genomes, the checkpoint by its population)
MAX_NPZ_BYTES = 1 << 28
#: what an ``.npz`` file holds beside its arrays, at most (zip and ``.npy``
#: headers, names)
NPZ_OVERHEAD = 1 << 20

#: what each kind of file that is not a regular one is called
_NOT_REGULAR = (
    (stat.S_ISDIR, "a directory"),
    (stat.S_ISFIFO, "a FIFO (named pipe)"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)


def _article(what: str) -> str:
    return f"an {what}" if what[:1].lower() in "aeiou." else f"a {what}"


def _not_regular(path: Path, mode: int, what: str) -> UserError | None:
    if stat.S_ISREG(mode):
        return None
    kind = next((k for test, k in _NOT_REGULAR if test(mode)), "something else")
    return UserError(
        f"{path}: is {kind}, not a regular file; expected {_article(what)}"
    )


def _unreadable(path: Path, e: OSError) -> UserError:
    if isinstance(e, FileNotFoundError):
        if os.path.lexists(path):
            return UserError(f"{path}: a broken symbolic link")
        return UserError(f"{path}: no such file")
    return UserError(f"{path}: cannot be read ({e.strerror or e})")


@contextlib.contextmanager
def open_regular(
    path: str | os.PathLike[str], what: str = "file"
) -> Iterator[BinaryIO]:
    """``path`` opened for binary reading, if it is a regular file (symbolic
    links followed); ``UserError`` naming it if it is missing or anything
    else (``what``: what it should be, for the message). It is looked at
    before it is opened, and opened without blocking and looked at again (it
    may have been replaced meanwhile): a FIFO is never waited on, a device
    never read."""
    path = Path(path)
    try:
        refused = _not_regular(path, os.stat(path).st_mode, what)
    except OSError as e:
        raise _unreadable(path, e) from None
    if refused is not None:
        raise refused
    flags = os.O_RDONLY | os.O_NONBLOCK | os.O_NOCTTY | getattr(os, "O_CLOEXEC", 0)
    try:
        fd = os.open(path, flags)
    except OSError as e:
        raise _unreadable(path, e) from None
    with os.fdopen(fd, "rb") as f:
        refused = _not_regular(path, os.fstat(fd).st_mode, what)
        if refused is not None:
            raise refused
        yield f


def read_bytes(path: str | os.PathLike[str], what: str, limit: int) -> bytes:
    """The bytes of regular file ``path`` (:func:`open_regular`), at most
    ``limit`` of them: a longer one is refused once ``limit + 1`` are read,
    whatever size it reports."""
    path = Path(path)
    with open_regular(path, what) as f:
        try:
            data = f.read(limit + 1)
        except OSError as e:
            raise _unreadable(path, e) from None
    if len(data) > limit:
        raise UserError(f"{path}: larger than {_size(limit)}, not {_article(what)}")
    return data


def _size(n: int) -> str:
    for unit, shift in (("GiB", 30), ("MiB", 20), ("KiB", 10)):
        if n >= 1 << shift and n % (1 << shift) == 0:
            return f"{n >> shift} {unit}"
    return f"{n:,} bytes"


def read_text(
    path: str | os.PathLike[str], what: str = "text file", limit: int = MAX_TEXT_BYTES
) -> str:
    """The UTF-8 text of regular file ``path``, at most ``limit`` bytes of it."""
    data = read_bytes(path, what, limit)
    try:
        return data.decode()
    except UnicodeDecodeError as e:
        raise UserError(
            f"{path}: not {_article(what)} (not UTF-8: {e.reason})"
        ) from None


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


def depth(value: Any) -> int:
    """How deep tables (dicts) and arrays (lists) nest in ``value`` (a scalar:
    0), counted without recursion, so that any depth can be measured."""
    deepest = 0
    stack = [(value, 1)]
    while stack:
        v, d = stack.pop()
        if isinstance(v, dict):
            v = list(v.values())
        elif not isinstance(v, list):
            continue
        deepest = max(deepest, d)
        stack.extend((x, d + 1) for x in v)
    return deepest


def _too_deep(path: Path, what: str) -> UserError:
    return UserError(
        f"{path}: nested more than {MAX_NESTING} deep, not {_article(what)}"
    )


def read_toml(path: str | os.PathLike[str], what: str = "TOML file") -> dict[str, Any]:
    """A TOML file, bounded in size and nesting (brackets before it is parsed,
    dotted keys once it is)."""
    path = Path(path)
    text = read_text(path, what)
    if nesting(text) > MAX_NESTING:
        raise _too_deep(path, what)
    try:
        data = tomllib.loads(text)
    except (tomllib.TOMLDecodeError, RecursionError) as e:
        raise UserError(f"{path}: not valid TOML ({e})") from None
    if depth(data) > MAX_NESTING:
        raise _too_deep(path, what)
    return data


def read_json(
    path: str | os.PathLike[str], limit: int = MAX_TEXT_BYTES
) -> dict[str, Any]:
    """A JSON object (every JSON file of a run is one) of at most ``limit``
    bytes, bounded in nesting before it is parsed."""
    path = Path(path)
    text = read_text(path, "JSON file", limit)
    if nesting(text) > MAX_NESTING:
        raise _too_deep(path, "JSON file")
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


def _members(
    path: Path, zf: zipfile.ZipFile, wanted: set[str], prefix: str | None
) -> dict[str, zipfile.ZipInfo]:
    """The members of ``zf`` by array name, each one that is ``wanted`` or
    starts with ``prefix``; any other is refused (never read)."""
    infos = zf.infolist()
    if len(infos) > MAX_NPZ_MEMBERS:
        raise UserError(f"{path}: holds {len(infos)} arrays, not a run's file")
    members: dict[str, zipfile.ZipInfo] = {}
    for info in infos:
        name = info.filename.removesuffix(".npy")
        known = name in wanted or (prefix is not None and name.startswith(prefix))
        if not (info.filename.endswith(".npy") and known) or name in members:
            what = "twice" if name in members else "which such a file does not"
            raise UserError(
                f"{path}: holds {info.filename[:60]!r}, {what} (nothing read)"
            )
        members[name] = info
    return members


def _declared(path: Path, zf: zipfile.ZipFile, info: zipfile.ZipInfo) -> int:
    """The bytes of data member ``info``'s header declares (nothing inflated)."""
    with zf.open(info) as f:
        shape, dtype = _npy_header(f)
    if dtype.hasobject:
        raise UserError(f"{path}: {info.filename} holds Python objects (not read)")
    if any(n < 0 for n in shape):
        raise UserError(f"{path}: {info.filename} declares the shape {shape}")
    declared = math.prod(shape) * dtype.itemsize
    if declared > info.file_size:
        raise UserError(
            f"{path}: {info.filename} declares {declared:,} bytes of data but "
            f"holds {info.file_size:,}"
        )
    return declared


def _read_npz(
    path: Path,
    f: BinaryIO,
    keys: tuple[str, ...],
    optional: tuple[str, ...],
    prefix: str | None,
    max_bytes: int,
) -> dict[str, np.ndarray]:
    with zipfile.ZipFile(f) as zf:
        members = _members(path, zf, {*keys, *optional}, prefix)
        missing = [k for k in keys if k not in members]
        if missing:
            raise UserError(f"{path}: missing {', '.join(missing)}")
        total = sum(_declared(path, zf, i) for i in members.values())
        if total > max_bytes:
            raise UserError(
                f"{path}: its arrays declare {total:,} bytes, more than such a "
                f"file holds ({max_bytes:,}; nothing inflated)"
            )
        require_memory(total, f"{path}: its arrays")
        out = {}
        for name, info in members.items():
            with zf.open(info) as m:
                out[name] = np.lib.format.read_array(m, allow_pickle=False)
        return out


def load_npz(
    path: str | os.PathLike[str],
    keys: tuple[str, ...],
    *,
    optional: tuple[str, ...] = (),
    prefix: str | None = None,
    max_bytes: int = MAX_NPZ_BYTES,
) -> dict[str, np.ndarray]:
    """The arrays ``keys`` (required), ``optional`` and those whose name
    starts with ``prefix`` of ``.npz`` file ``path`` (no pickle), if it holds
    no other and they declare at most ``max_bytes`` of data in all;
    ``UserError`` naming the file otherwise (missing, not a regular file,
    not an ``.npz``, larger than that or than memory allows)."""
    path = Path(path)
    with open_regular(path, ".npz file") as f:
        size = os.fstat(f.fileno()).st_size
        if size > max_bytes + NPZ_OVERHEAD:
            raise UserError(
                f"{path}: {size:,} bytes, more than such a file holds "
                f"({max_bytes + NPZ_OVERHEAD:,})"
            )
        try:
            return _read_npz(path, f, keys, optional, prefix, max_bytes)
        except zipfile.BadZipFile as e:
            raise UserError(f"{path}: not an .npz file ({e})") from None
        except (
            OSError,
            ValueError,
            EOFError,
            KeyError,
            MemoryError,
            RuntimeError,  # an encrypted member
            NotImplementedError,  # an unknown compression method
            zlib.error,  # damaged compressed data
        ) as e:
            raise UserError(f"{path}: not a readable .npz file ({e})") from None
