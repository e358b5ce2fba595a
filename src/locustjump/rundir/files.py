"""Atomic writes of the files of a run directory (reads: :mod:`.reads`)."""

from __future__ import annotations

import contextlib
import json
import os
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import tomli_w

from locustjump.errors import UserError


@contextlib.contextmanager
def atomic_path(path: Path, *, partial: str = ".tmp") -> Iterator[Path]:
    """A temporary path beside ``path`` to write into; on success it is
    fsynced and renamed onto ``path`` (readers see the old file or the new one,
    never half of one), on failure removed."""
    path = Path(path)
    tmp = path.with_name(f".{path.stem}{partial}{path.suffix}")
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
