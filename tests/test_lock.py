"""``rundir.lock`` function by function: who holds a directory's lock, the
one line a second writer gets, a look's lock waited out, re-entrance, and
what is released when. A lock is held here by a second open file description
of the directory in this process (``flock`` locks conflict between open files,
not only between processes); ``tests/test_writers.py`` tries other processes."""

import contextlib
import fcntl
import io
import os
from pathlib import Path
from types import SimpleNamespace

import pytest

from helpers import user_error
from locustjump.errors import UserError
from locustjump.rundir import lock
from locustjump.rundir.lock import InUse, check_not_in_use, in_use, locked


@contextlib.contextmanager
def held(d: Path):
    """``d``'s lock held by another open file description (as a writer's)."""
    fd = os.open(d, os.O_RDONLY | os.O_DIRECTORY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        yield fd
    finally:
        os.close(fd)


def patch_os(monkeypatch, **names) -> None:
    """``lock``'s view of ``os`` with ``names`` replaced, the module itself
    untouched (other threads of the test process go on using it)."""
    monkeypatch.setattr(lock, "os", SimpleNamespace(**{**vars(os), **names}))


def message(d: Path, who: str) -> str:
    return f"{d} is in use by {who} (one writer at a time; wait for it or stop it)"


def test_the_holder_is_named_by_its_process(tmp_path):
    with held(tmp_path) as fd:
        assert lock._holder(fd) == os.getpid()
        assert in_use(tmp_path) == f"process {os.getpid()}"
        with pytest.raises(InUse) as e:
            check_not_in_use(tmp_path)
        assert str(e.value) == message(tmp_path, f"process {os.getpid()}")
        with pytest.raises(InUse) as e, locked(tmp_path):
            pass
        assert str(e.value) == message(tmp_path, f"process {os.getpid()}")
    assert in_use(tmp_path) is None
    check_not_in_use(tmp_path)


def test_a_directory_no_one_holds_has_no_holder(tmp_path):
    other = tmp_path / "other"
    other.mkdir()
    fd = os.open(tmp_path, os.O_RDONLY | os.O_DIRECTORY)
    try:
        with held(other):  # a lock on another directory is not this one's
            assert lock._holder(fd) is None
    finally:
        os.close(fd)


def _proc_locks(monkeypatch, lines) -> None:
    """``lock``'s ``/proc/locks`` holds ``lines`` (or cannot be read)."""

    def fake(path, *a, **kw):
        assert path == "/proc/locks"
        if isinstance(lines, Exception):
            raise lines
        return io.StringIO("".join(line + "\n" for line in lines))

    monkeypatch.setattr(lock, "open", fake, raising=False)  # over the builtin


def _dev(fd: int) -> str:
    st = os.fstat(fd)
    return f"{os.major(st.st_dev):02x}:{os.minor(st.st_dev):02x}:{st.st_ino}"


def test_proc_locks_is_read_line_by_line(tmp_path, monkeypatch):
    fd = os.open(tmp_path, os.O_RDONLY | os.O_DIRECTORY)
    try:
        dev = _dev(fd)
        cases = [
            ([f"1: FLOCK  ADVISORY  WRITE 4242 {dev} 0 EOF"], 4242),
            ([f"1: POSIX  ADVISORY  WRITE 4242 {dev} 0 EOF"], None),  # not a flock
            (
                [
                    "1: FLOCK  ADVISORY  WRITE 4242 00:01:1 0 EOF",
                    f"2: FLOCK  ADVISORY  WRITE 77 {dev} 0 EOF",
                ],
                77,
            ),  # fmt: skip
            (["1: FLOCK ADVISORY WRITE 4242", f"2: FLOCK A W 5 {dev}"], 5),
            (["FLOCK a b c d"], None),  # too short to name a file
            ([f"1: FLOCK  ADVISORY  WRITE x {dev} 0 EOF"], None),  # not a PID
            (OSError(13, "Permission denied"), None),
        ]
        for lines, pid in cases:
            _proc_locks(monkeypatch, lines)
            assert lock._holder(fd) == pid, lines
    finally:
        os.close(fd)


def test_the_device_and_inode_are_as_proc_locks_writes_them(tmp_path, monkeypatch):
    """``MAJOR:MINOR:INODE``, the device numbers in hex of two digits at least."""
    inode = 1234567
    patch_os(
        monkeypatch,
        fstat=lambda fd: os.stat_result((0, inode) + (0,) * 8),
        major=lambda dev: 0x8,
        minor=lambda dev: 0x1F3,
    )
    _proc_locks(monkeypatch, [f"1: FLOCK  ADVISORY  WRITE 9 08:1f3:{inode} 0 EOF"])
    assert lock._holder(3) == 9
    _proc_locks(monkeypatch, [f"1: FLOCK  ADVISORY  WRITE 9 8:1f3:{inode} 0 EOF"])
    assert lock._holder(3) is None


def test_an_unnamed_holder_is_another_process(tmp_path, monkeypatch):
    monkeypatch.setattr(lock, "_holder", lambda fd: None)
    with held(tmp_path):
        assert in_use(tmp_path) == "another process"
        with pytest.raises(InUse) as e, locked(tmp_path):
            pass
        assert str(e.value) == message(tmp_path, "another process")
        with pytest.raises(InUse) as e:
            check_not_in_use(tmp_path)
        assert str(e.value) == message(tmp_path, "another process")


def test_a_look_is_waited_out_a_writer_is_not(tmp_path, monkeypatch):
    """A lock held for fewer than LOOK_TRIES tries is taken; one held longer
    is a writer's. The tries are 5 ms apart."""
    slept: list[float] = []
    fd_box: list[int] = []

    def sleep(s):
        slept.append(s)
        if len(slept) == lock.LOOK_TRIES:  # released just before the last try
            os.close(fd_box.pop())

    monkeypatch.setattr(lock, "time", SimpleNamespace(sleep=sleep))
    fd = os.open(tmp_path, os.O_RDONLY | os.O_DIRECTORY)
    fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    fd_box.append(fd)
    try:
        with locked(tmp_path):
            assert in_use(tmp_path) is None  # this process's own
    finally:
        for left in fd_box:  # not released: the lock was not taken
            os.close(left)
    assert slept == [0.005] * lock.LOOK_TRIES and lock.LOOK_TRIES == 10
    slept.clear()
    monkeypatch.setattr(lock, "time", SimpleNamespace(sleep=slept.append))
    with held(tmp_path), pytest.raises(InUse), locked(tmp_path):
        pass
    assert slept == [0.005] * lock.LOOK_TRIES  # then it gives up


def test_a_directory_that_cannot_be_locked(tmp_path, monkeypatch):
    missing = tmp_path / "nothing"
    assert user_error(lambda: locked(missing).__enter__()) == (
        f"{missing}: cannot be locked (No such file or directory)"
    )
    assert in_use(missing) is None

    def no_locks(fd, op):
        raise OSError(37, "No locks available")

    flocks = SimpleNamespace(**vars(fcntl))
    monkeypatch.setattr(lock, "fcntl", flocks)
    flocks.flock = no_locks
    assert user_error(lambda: locked(tmp_path).__enter__()) == (
        f"{tmp_path}: cannot be locked (No locks available)"
    )
    assert in_use(tmp_path) is None  # a look: nothing to say

    def no_errno(fd, op):
        raise OSError("no errno")

    flocks.flock = no_errno
    assert user_error(lambda: locked(tmp_path).__enter__()) == (
        f"{tmp_path}: cannot be locked (no errno)"
    )


def test_a_file_is_not_a_directory_to_lock_or_look_at(tmp_path, monkeypatch):
    f = tmp_path / "f"
    f.write_text("x")
    assert in_use(f) is None
    assert user_error(lambda: locked(f).__enter__()) == (
        f"{f}: cannot be locked (Not a directory)"
    )
    opened: list[str] = []
    real = os.open
    patch_os(monkeypatch, open=lambda p, *a: opened.append(p) or real(p, *a))
    assert in_use(tmp_path / "none") is None and opened == []  # not even opened


def test_a_directory_replaced_by_a_file_is_not_looked_at(tmp_path, monkeypatch):
    """Between ``is_dir`` and the open: a locked file there is no writer's."""
    f = tmp_path / "f"
    f.write_text("x")
    fd = os.open(f, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        real = Path.is_dir
        monkeypatch.setattr(Path, "is_dir", lambda self: self == f or real(self))
        assert in_use(f) is None
    finally:
        os.close(fd)


def test_a_directory_that_cannot_be_opened_to_look_at(tmp_path, monkeypatch):
    def refuse(path, flags):
        raise PermissionError(13, "Permission denied")

    patch_os(monkeypatch, open=refuse)
    assert in_use(tmp_path) is None


def test_re_entrant_within_a_process_and_released_at_the_last_exit(tmp_path):
    key = os.path.realpath(tmp_path)
    with locked(tmp_path):
        assert lock._held == {key: 1}
        with locked(tmp_path / "."):  # the same directory by another name
            assert lock._held == {key: 2}
            assert in_use(tmp_path) is None
        assert lock._held == {key: 1}
        with pytest.raises(BlockingIOError), held(tmp_path):  # still held
            pass
    assert lock._held == {}
    with held(tmp_path):  # released: another can take it
        pass


def test_the_lock_is_released_when_the_body_fails(tmp_path):
    for _ in range(2):
        with pytest.raises(ValueError), locked(tmp_path):
            with locked(tmp_path):
                raise ValueError
    assert lock._held == {}
    with held(tmp_path):
        pass


def test_a_lock_not_taken_leaves_nothing_held(tmp_path):
    with held(tmp_path), pytest.raises(InUse), locked(tmp_path):
        pass
    assert lock._held == {}
    assert not any(tmp_path.iterdir())  # no lock file


def test_without_fcntl_only_this_process_counts(tmp_path, monkeypatch):
    monkeypatch.setattr(lock, "fcntl", None)
    with locked(tmp_path):
        assert lock._held == {os.path.realpath(tmp_path): 1}
        assert in_use(tmp_path) is None
    assert lock._held == {}


def test_in_use_is_a_user_error():
    assert issubclass(InUse, UserError)
