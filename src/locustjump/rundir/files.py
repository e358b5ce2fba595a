"""Atomic writes and pickle-free reads of the files of a run directory."""

from __future__ import annotations

import contextlib
import errno
import json
import os
import tomllib
import zipfile
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
        if e.errno in (errno.ENOSPC, errno.EIO, errno.EDQUOT, errno.EROFS):
            raise UserError(
                f"{path}: cannot be written ({e.strerror}); the previous version "
                "is intact"
            ) from None
        raise
    finally:
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


def read_json(path: Path) -> Any:
    try:
        return json.loads(Path(path).read_text())
    except (OSError, ValueError) as e:
        raise UserError(f"{path}: not readable JSON ({e})") from None


def write_toml(path: Path, data: dict[str, Any], header: str = "") -> None:
    atomic_write_text(path, header + tomli_w.dumps(data))


def read_toml(path: Path) -> dict[str, Any]:
    try:
        with open(path, "rb") as f:
            return tomllib.load(f)
    except FileNotFoundError:
        raise UserError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise UserError(f"{path}: is a directory, expected a TOML file") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as e:
        raise UserError(f"{path}: not valid TOML ({e})") from None


def load_npz(path: Path, keys: tuple[str, ...]) -> dict[str, np.ndarray]:
    """The arrays ``keys`` of ``path`` (no pickle); ``UserError`` naming it."""
    try:
        with np.load(path, allow_pickle=False) as z:
            missing = [k for k in keys if k not in z.files]
            if missing:
                raise UserError(f"{path}: missing {', '.join(missing)}")
            return {k: z[k] for k in z.files}
    except FileNotFoundError:
        raise UserError(f"{path}: no such file") from None
    except UserError:
        raise
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, KeyError) as e:
        raise UserError(f"{path}: not a readable .npz file ({e})") from None


def save_npz(path: Path, **arrays: Any) -> None:
    atomic_write_bytes(path, lambda f: np.savez(f, **arrays))


# --- output locations given by the user -----------------------------------------


def check_out_dir(path: str | os.PathLike, *, force: bool = False) -> Path:
    """Refuse (``UserError``) an existing non-empty ``path`` unless ``force``;
    create nothing."""
    out = Path(path)
    if out.exists() and not out.is_dir():
        raise UserError(f"--out {out}: exists and is not a directory")
    if out.is_dir() and any(out.iterdir()) and not force:
        raise UserError(
            f"--out {out}: directory exists and is not empty (use --force to "
            "write into it)"
        )
    return out


def prepare_out_file(
    path: str | os.PathLike, *, force: bool = False, option: str = "--out"
) -> Path:
    """Check that ``path`` (given as ``option``) can be written without
    overwriting, unless ``force``."""
    out = Path(path)
    if out.is_dir():
        raise UserError(f"{option} {out}: is a directory, expected a file")
    if out.exists() and not force:
        raise UserError(f"{option} {out}: file exists (use --force to overwrite)")
    if not out.parent.exists():
        raise UserError(f"{option} {out}: directory {out.parent} does not exist")
    return out
