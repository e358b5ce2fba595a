"""``rundir.reads`` on ``.npz`` files: the arrays asked for and no others, each
member's header checked before it is read, its memory asked for by name,
objects never unpickled, damaged files one error."""

import io
import zipfile
from pathlib import Path

import numpy as np
import pytest

from helpers import user_error
from locustjump.errors import UserError
from locustjump.rundir import reads


def _npy(a: np.ndarray) -> bytes:
    b = io.BytesIO()
    np.save(b, a, allow_pickle=True)
    return b.getvalue()


def _npz(path: Path, members: dict[str, bytes], **kw) -> Path:
    with zipfile.ZipFile(path, "w", **kw) as zf:
        for name, data in members.items():
            zf.writestr(name, data)
    return path


def test_an_npz_gives_the_arrays_asked_for(tmp_path):
    a, b, c = np.zeros((0, 3)), np.eye(2), np.array([7], dtype=np.int64)
    path = _npz(tmp_path / "f.npz", {"a.npy": _npy(a), "b.npy": _npy(b),
                                     "opt_c.npy": _npy(c)})  # fmt: skip
    got = reads.load_npz(path, ("a",), optional=("b", "z"), prefix="opt_")
    assert sorted(got) == ["a", "b", "opt_c"]
    for k, v in (("a", a), ("b", b), ("opt_c", c)):
        np.testing.assert_array_equal(got[k], v)
        assert got[k].dtype == v.dtype
    assert user_error(reads.load_npz, path, ("a", "b", "x", "y"), prefix="opt_") == (
        f"{path}: missing x, y"
    )
    assert user_error(reads.load_npz, path, ("a", "b")) == (
        f"{path}: holds 'opt_c.npy', which such a file does not (nothing read)"
    )


def test_npz_members_that_such_a_file_does_not_hold(tmp_path):
    path = tmp_path / "f.npz"
    _npz(path, {"a.npy": _npy(np.zeros(1)), "a.txt": b"x"})
    assert user_error(reads.load_npz, path, ("a",), optional=("a.txt",)) == (
        f"{path}: holds 'a.txt', which such a file does not (nothing read)"
    )
    with pytest.warns(UserWarning, match="Duplicate name"):
        _npz(path, {"a.npy": _npy(np.zeros(1))})
        with zipfile.ZipFile(path, "a") as zf:
            zf.writestr("a.npy", _npy(np.ones(1)))
    assert user_error(reads.load_npz, path, ("a",)) == (
        f"{path}: holds 'a.npy', twice (nothing read)"
    )
    long = "x" * 70 + ".npy"
    _npz(path, {"a.npy": _npy(np.zeros(1)), long: b""})
    assert user_error(reads.load_npz, path, ("a",)) == (
        f"{path}: holds {'x' * 60!r}, which such a file does not (nothing read)"
    )
    many = {f"a{i}.npy": b"" for i in range(reads.MAX_NPZ_MEMBERS)}
    _npz(path, many)
    wanted = tuple(f"a{i}" for i in range(reads.MAX_NPZ_MEMBERS))
    with pytest.raises(UserError, match="not a readable .npz file"):  # empty .npy
        reads.load_npz(path, wanted)
    _npz(path, {**many, "b.npy": b""})
    assert user_error(reads.load_npz, path, wanted) == (
        f"{path}: holds 257 arrays, not a run's file"
    )


def _header(shape: tuple[int, ...], descr: str = "<f8") -> bytes:
    b = io.BytesIO()
    np.lib.format.write_array_header_1_0(
        b, {"descr": descr, "fortran_order": False, "shape": shape}
    )
    return b.getvalue()


def test_what_an_npz_member_declares_is_checked_before_it_is_read(tmp_path):
    path = tmp_path / "f.npz"
    _npz(path, {"a.npy": _npy(np.array([{"x": 1}], dtype=object))})
    assert user_error(reads.load_npz, path, ("a",)) == (
        f"{path}: a.npy holds Python objects (not read)"
    )
    _npz(path, {"a.npy": _header((-1, 2))})
    assert user_error(reads.load_npz, path, ("a",)) == (
        f"{path}: a.npy declares the shape (-1, 2)"
    )
    member = _header((100,)) + bytes(8 * 3)
    _npz(path, {"a.npy": member})
    assert user_error(reads.load_npz, path, ("a",)) == (
        f"{path}: a.npy declares 800 bytes of data but holds {len(member):,}"
    )
    # declaring as many bytes as the member holds, header and all, passes
    # this check (and fails where the data ends)
    n = next(n for n in range(1, 100) if 8 * n - len(_header((n,))) >= 0)
    member = _header((n,)) + bytes(8 * n - len(_header((n,))))
    _npz(path, {"a.npy": member})
    assert len(member) == 8 * n
    assert user_error(reads.load_npz, path, ("a",)).startswith(
        f"{path}: not a readable .npz file ("
    )
    exact = _header((4,)) + bytes(8 * 4)
    _npz(path, {"a.npy": exact, "b.npy": exact})
    assert reads.load_npz(path, ("a", "b"), max_bytes=64)["b"].shape == (4,)
    assert user_error(reads.load_npz, path, ("a", "b"), max_bytes=63) == (
        f"{path}: its arrays declare 64 bytes, more than such a file holds "
        "(63; nothing inflated)"
    )


def test_the_memory_an_npz_needs_is_asked_for_by_name(tmp_path, monkeypatch):
    path = _npz(tmp_path / "f.npz", {"a.npy": _npy(np.zeros(4)),
                                     "b.npy": _npy(np.zeros(2))})  # fmt: skip
    asked = []
    monkeypatch.setattr(
        reads, "require_memory", lambda n, what: asked.append((n, what))
    )
    reads.load_npz(path, ("a", "b"))
    assert asked == [(48, f"{path}: its arrays")]


def test_objects_are_not_unpickled_even_past_the_header_check(tmp_path, monkeypatch):
    """The header check refuses object arrays; were it to miss one, NumPy is
    still told not to unpickle it."""
    path = _npz(tmp_path / "f.npz", {"a.npy": _npy(np.array([{"x": 1}], dtype=object))})
    monkeypatch.setattr(reads, "_declared", lambda path, zf, info: 0)
    assert user_error(reads.load_npz, path, ("a",)) == (
        f"{path}: not a readable .npz file (Object arrays cannot be loaded when "
        "allow_pickle=False)"
    )


def test_an_npz_larger_than_such_a_file_is_refused_unread(tmp_path):
    path = tmp_path / "f.npz"
    path.write_bytes(bytes(reads.NPZ_OVERHEAD + 11))
    assert user_error(reads.load_npz, path, ("a",), max_bytes=10) == (
        f"{path}: {reads.NPZ_OVERHEAD + 11:,} bytes, more than such a file holds "
        f"({reads.NPZ_OVERHEAD + 10:,})"
    )
    path.write_bytes(bytes(reads.NPZ_OVERHEAD + 10))
    assert user_error(reads.load_npz, path, ("a",), max_bytes=10).startswith(
        f"{path}: not an .npz file ("
    )


def test_damaged_npz_files_are_one_error(tmp_path):
    path = tmp_path / "f.npz"
    _npz(path, {"a.npy": b"\x93NUMPY\x03\x00"})  # an unknown .npy version
    assert user_error(reads.load_npz, path, ("a",)) == (
        f"{path}: not a readable .npz file (unsupported .npy version (3, 0))"
    )
    _npz(path, {"a.npy": _npy(np.arange(1000.0))}, compression=zipfile.ZIP_DEFLATED)
    data = bytearray(path.read_bytes())
    data[200:260] = bytes(60)  # into the deflated stream
    path.write_bytes(bytes(data))
    assert user_error(reads.load_npz, path, ("a",)).startswith(f"{path}: not a")


def test_a_version_2_header_is_read():
    b = io.BytesIO()
    np.lib.format.write_array_header_2_0(
        b, {"descr": "<i4", "fortran_order": False, "shape": (2, 3)}
    )
    b.seek(0)
    shape, dtype = reads._npy_header(b)
    assert shape == (2, 3) and dtype == np.dtype("<i4")
