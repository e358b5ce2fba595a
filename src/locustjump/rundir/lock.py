"""One writer per directory: an exclusive ``flock`` on the directory itself.

The lock is held for the life of any command that writes into a run or a
reproduction directory; a second writer gets a one-line error naming the
process that holds it. The kernel drops the lock when its process dies, however
it dies (``kill -9`` included), so a stale lock never blocks, and no lock file
is left in the directory.
"""

from __future__ import annotations

import contextlib
import os
import time
from collections.abc import Iterator
from pathlib import Path

from locustjump.errors import UserError

try:
    import fcntl
except ImportError:  # pragma: no cover - not POSIX: no locking
    fcntl = None  # type: ignore[assignment]


def _holder(fd: int) -> int | None:
    """PID of the process holding a flock on the file of ``fd`` (Linux)."""
    st = os.fstat(fd)
    dev = f"{os.major(st.st_dev):02x}:{os.minor(st.st_dev):02x}:{st.st_ino}"
    try:
        with open("/proc/locks") as f:
            for line in f:
                parts = line.split()
                if "FLOCK" in parts and len(parts) > 5 and parts[5] == dev:
                    return int(parts[4])
    except (OSError, ValueError):
        pass
    return None


class InUse(UserError):
    """The directory is locked by another process (a study's workers skip
    such a run: another worker trains it)."""


#: times a held lock is asked for again, 5 ms apart, before its holder is
#: taken for a writer (a look holds it for microseconds)
LOOK_TRIES = 10

#: directories this process holds (re-entrant: a command that locks a
#: reproduction may call one that locks it again)
_held: dict[str, int] = {}


def _in_use_message(d: Path, who: str | None) -> str:
    who = who or "another process"
    return f"{d} is in use by {who} (one writer at a time; wait for it or stop it)"


def check_not_in_use(directory: str | os.PathLike[str]) -> None:
    """Raise :class:`InUse` if another process holds the lock of ``directory``:
    what a validation says before it judges the directory's contents, which
    that writer may be changing (a marker half-written is not a stranger's
    file)."""
    who = in_use(directory)
    if who:
        raise InUse(_in_use_message(Path(directory), who))


def _take(d: Path, fd: int) -> None:
    """Take the lock of ``d`` (open as ``fd``) or raise :class:`InUse` naming
    its holder. A holder may be a look (:func:`in_use` takes the lock for a
    moment), not a writer: the lock is asked for again for a while first."""
    for attempt in range(LOOK_TRIES + 1):
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            return
        except BlockingIOError:
            if attempt == LOOK_TRIES:
                pid = _holder(fd)
                who = f"process {pid}" if pid else None
                raise InUse(_in_use_message(d, who)) from None
            time.sleep(0.005)
        except OSError as e:  # a file system without locks
            raise UserError(f"{d}: cannot be locked ({e.strerror or e})") from None


@contextlib.contextmanager
def locked(directory: str | os.PathLike[str]) -> Iterator[None]:
    """Hold the write lock of an existing ``directory`` (``UserError`` if another
    process holds it). Re-entrant within a process."""
    d = Path(directory)
    key = os.path.realpath(d)
    if fcntl is None or key in _held:
        _held[key] = _held.get(key, 0) + 1
        try:
            yield
        finally:
            _held[key] -= 1
            if not _held[key]:
                del _held[key]
        return
    try:
        fd = os.open(d, os.O_RDONLY | os.O_DIRECTORY)
    except OSError as e:
        raise UserError(f"{d}: cannot be locked ({e.strerror or e})") from None
    try:
        _take(d, fd)
        _held[key] = 1
        try:
            yield
        finally:
            del _held[key]
    finally:
        os.close(fd)  # releases the lock


def in_use(directory: str | os.PathLike[str]) -> str | None:
    """Who holds the lock of ``directory`` if another process does ("process
    1234", or "another process" where the holder cannot be named); ``None`` if
    no one, this process, or no such directory. A look, not a promise: the
    lock may be taken a moment later (:func:`locked` raises :class:`InUse`)."""
    d = Path(directory)
    if fcntl is None or os.path.realpath(d) in _held or not d.is_dir():
        return None
    try:
        fd = os.open(d, os.O_RDONLY | os.O_DIRECTORY)
    except OSError:
        return None
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            pid = _holder(fd)
            return f"process {pid}" if pid else "another process"
        except OSError:
            return None
        return None
    finally:
        os.close(fd)  # releases the lock if this look took it
