"""Atomic writes of the files of a run directory (reads: :mod:`.reads`)."""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import tomli_w

from locustjump.errors import UserError


def temporary_path(path: Path, partial: str = ".tmp") -> Path:
    """Where :func:`atomic_path` writes ``path`` first: ``.<stem><partial>
    <suffix>`` beside it, or, where that name would be longer than the
    directory allows a name (``path``'s own may be as long), a digest of
    ``path``'s name in place of its stem."""
    name = f".{path.stem}{partial}{path.suffix}"
    try:
        limit = os.pathconf(path.parent, "PC_NAME_MAX")
    except (OSError, ValueError):
        limit = 255  # Linux's NAME_MAX
    if len(os.fsencode(name)) > limit:
        digest = hashlib.sha256(os.fsencode(path.name)).hexdigest()[:16]
        suffix = path.suffix if len(os.fsencode(path.suffix)) <= 32 else ""
        name = f".{digest}{partial}{suffix}"
    return path.with_name(name)


@contextlib.contextmanager
def atomic_path(path: Path, *, partial: str = ".tmp") -> Iterator[Path]:
    """A temporary path beside ``path`` to write into; on success it is
    fsynced and renamed onto ``path`` (readers see the old file or the new one,
    never half of one), on failure removed."""
    path = Path(path)
    tmp = temporary_path(path, partial)
    try:
        yield tmp
        with open(tmp, "rb+") as f:
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except OSError as e:
        # named as the file the user knows, not the temporary one
        intact = "; the previous version is intact" if path.exists() else ""
        raise UserError(
            f"{path}: cannot be written ({e.strerror or e}){intact}"
        ) from None
    finally:
        with contextlib.suppress(OSError):
            tmp.unlink(missing_ok=True)


def atomic_write_bytes(path: Path, write: Callable[[Any], None] | bytes) -> None:
    """``write(file)`` (or the bytes) into ``path`` atomically (:func:`atomic_path`)."""
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        if isinstance(write, bytes):
            f.write(write)
        else:
            write(f)


def append_line(path: Path, line: str) -> None:
    """Append ``line`` to ``path`` with one unbuffered write (a failed write is
    named like any other; a partial line is dropped on resume)."""
    try:
        fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
        try:
            os.write(fd, line.encode())
        finally:
            os.close(fd)
    except OSError as e:
        raise UserError(f"{path}: cannot be written ({e.strerror})") from None


def atomic_write_text(path: Path, text: str) -> None:
    atomic_write_bytes(path, text.encode())


def write_json(path: Path, data: Any) -> None:
    atomic_write_text(path, json.dumps(data, indent=2) + "\n")


def write_toml(path: Path, data: dict[str, Any], header: str = "") -> None:
    atomic_write_text(path, header + tomli_w.dumps(data))


def save_npz(path: Path, **arrays: Any) -> None:
    atomic_write_bytes(path, lambda f: np.savez(f, **arrays))
