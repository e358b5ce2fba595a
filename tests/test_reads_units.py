"""``rundir.reads`` function by function: each refusal's exact words, each
bound at its edge (``tests/test_reads.py`` tries them through the commands)."""

import io
import os
import zipfile
from pathlib import Path

import numpy as np
import pytest

from locustjump.errors import UserError
from locustjump.rundir import reads


def _refused(call, *args, **kw) -> str:
    with pytest.raises(UserError) as e:
        call(*args, **kw)
    return str(e.value)


# -- regular files only --------------------------------------------------------


def test_what_a_path_is_when_it_is_not_a_regular_file(tmp_path):
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    for path, kind in (
        (tmp_path, "a directory"),
        (fifo, "a FIFO (named pipe)"),
        (Path("/dev/null"), "a character device"),
    ):
        assert _refused(reads.read_bytes, path, "TOML file", 10) == (
            f"{path}: is {kind}, not a regular file; expected a TOML file"
        )
    # "an" before a vowel or a dot
    assert _refused(reads.load_npz, tmp_path, ("a",)).endswith("expected an .npz file")
    assert _refused(reads.read_text, tmp_path, "image").endswith("expected an image")


def test_a_mode_of_no_known_kind_is_something_else(tmp_path):
    err = reads._not_regular(tmp_path / "f", 0, "file")
    assert (
        str(err)
        == f"{tmp_path / 'f'}: is something else, not a regular file; expected a file"
    )
    assert reads._not_regular(tmp_path / "f", 0o100644, "file") is None


def test_missing_files_and_broken_links_are_named(tmp_path):
    assert _refused(reads.read_text, tmp_path / "none") == (
        f"{tmp_path / 'none'}: no such file"
    )
    link = tmp_path / "link"
    link.symlink_to(tmp_path / "gone")
    assert _refused(reads.read_json, link) == f"{link}: a broken symbolic link"
    loop = tmp_path / "loop"
    loop.symlink_to(loop)
    assert _refused(reads.read_text, loop) == (
        f"{loop}: cannot be read (Too many levels of symbolic links)"
    )


def test_a_file_replaced_between_the_look_and_the_open_is_looked_at_again(
    tmp_path, monkeypatch
):
    """The first look sees a regular file; what is opened is a FIFO."""
    path = tmp_path / "f"
    os.mkfifo(path)
    real = os.stat

    def regular(p, *a, **kw):
        st = real(p, *a, **kw)
        if Path(p) == path:
            return os.stat_result((0o100644, *st[1:]))
        return st

    monkeypatch.setattr(reads.os, "stat", regular)
    assert _refused(reads.read_text, path) == (
        f"{path}: is a FIFO (named pipe), not a regular file; expected a text file"
    )


def test_a_file_that_vanishes_before_it_is_opened(tmp_path, monkeypatch):
    path = tmp_path / "f"
    path.write_text("x")

    def gone(p, flags):
        Path(p).unlink()
        raise FileNotFoundError(2, "No such file or directory")

    monkeypatch.setattr(reads.os, "open", gone)
    assert _refused(reads.read_text, path) == f"{path}: no such file"


# -- sizes -------------------------------------------------------------------------


def test_a_file_of_exactly_the_limit_is_read_one_byte_more_is_not(tmp_path):
    path = tmp_path / "f"
    path.write_bytes(b"x" * 1024)
    assert reads.read_bytes(path, "thing", 1024) == b"x" * 1024
    assert _refused(reads.read_bytes, path, "thing", 1023) == (
        f"{path}: larger than 1,023 bytes, not a thing"
    )
    path.write_bytes(b"x" * 1025)
    assert _refused(reads.read_bytes, path, "thing", 1024) == (
        f"{path}: larger than 1 KiB, not a thing"
    )


def _reads_through(monkeypatch, read) -> None:
    """Every file ``reads`` opens reads through ``read(file, n)``."""
    real = os.fdopen

    class Through:
        def __init__(self, f):
            self.f = f

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            self.f.close()

        def read(self, n=-1):
            return read(self.f, n)

    monkeypatch.setattr(reads.os, "fdopen", lambda fd, mode: Through(real(fd, mode)))


def test_no_more_than_one_byte_past_the_limit_is_read(tmp_path, monkeypatch):
    """Whatever a file holds (``/proc`` files report 0 bytes and hold
    megabytes), a read asks for ``limit + 1`` bytes, once."""
    path = tmp_path / "f"
    path.write_bytes(b"x" * 100)
    asked = []
    _reads_through(monkeypatch, lambda f, n: (asked.append(n), f.read(n))[1])
    with pytest.raises(UserError, match="larger than 10 bytes"):
        reads.read_bytes(path, "thing", 10)
    assert reads.read_bytes(path, "thing", 200) == b"x" * 100
    assert asked == [11, 201]


def test_a_read_that_fails_is_named(tmp_path, monkeypatch):
    path = tmp_path / "f"
    path.write_bytes(b"abc")

    def failing(f, n):
        raise OSError(5, "Input/output error")

    _reads_through(monkeypatch, failing)
    assert _refused(reads.read_bytes, path, "thing", 10) == (
        f"{path}: cannot be read (Input/output error)"
    )


@pytest.mark.parametrize(
    "n, text",
    [
        (1 << 30, "1 GiB"),
        (3 << 30, "3 GiB"),
        (1 << 20, "1 MiB"),
        (5 << 20, "5 MiB"),
        (1 << 10, "1 KiB"),
        (1536, "1,536 bytes"),
        ((1 << 20) + 1024, "1025 KiB"),
        (1023, "1,023 bytes"),
        (1, "1 bytes"),
        (0, "0 bytes"),
    ],
)
def test_sizes_in_their_largest_whole_unit(n, text):
    assert reads._size(n) == text


def test_text_that_is_not_utf8(tmp_path):
    path = tmp_path / "f"
    path.write_bytes(b"a = \xff\n")
    assert _refused(reads.read_text, path, "config") == (
        f"{path}: not a config (not UTF-8: invalid start byte)"
    )


# -- nesting -----------------------------------------------------------------------


@pytest.mark.parametrize(
    "text, deep",
    [
        ("", 0),
        ("a = 1", 0),
        ("a = [1, [2, [3]]]", 3),
        ("a = {b = {c = [1]}}", 3),
        ('[[x]]\na = "[[[[["', 2),  # brackets in a string do not count
        ("a = 1 # [[[[[\nb = [1]", 1),  # nor in a comment
        ("a = 1 # [[[[[", 0),  # a comment to the end of the text
        ('a = """[[\n[[[""" \nb = [1]', 1),  # nor in a multi-line string
        ("a = '''[[[''' \nb = {}", 1),
        ("a = '[[[' \nb = {}", 1),
        ('a = "\\"[[[" \nb = [1]', 1),  # an escaped quote ends nothing
        ("a = '\\'\nb = [[1]]", 2),  # no escapes in a literal string
        ('a = "[[\nb = [1]', 1),  # unterminated: its line ends it
        ('{"a": [{"b": "]]]"}]}', 3),  # JSON too
        ("a = [1]\nb = [[1]]\nc = [1]", 2),  # depth falls back, the deepest kept
        ("a = 1 # c\nb = [[1]]\nc = 1", 2),  # a comment ends at its own line
        ('a = "b\\\\" [[1]]', 2),  # an escaped backslash, then the quote
        ('a = "abc', 0),  # unterminated at the end of the text
        ("X = [[1]]", 2),  # any other character is just a character
    ],
)
def test_nesting_counts_brackets_outside_strings_and_comments(text, deep):
    assert reads.nesting(text) == deep


def test_depth_of_a_parsed_value():
    assert reads.depth(1) == 0
    assert reads.depth("[[[") == 0
    assert reads.depth({}) == 1
    assert reads.depth([]) == 1
    assert reads.depth({"a": 1, "b": {"c": [1, [2]]}}) == 4
    assert reads.depth([{"a": {}}, 1]) == 3


def _nested(n: int) -> str:
    return "a = " + "[" * n + "]" * n + "\n"


def test_toml_and_json_nested_to_the_limit_and_past_it(tmp_path, monkeypatch):
    path = tmp_path / "f.toml"
    # the file's own table is a level: 31 arrays in it are 32
    path.write_text(_nested(reads.MAX_NESTING - 1))
    assert reads.depth(reads.read_toml(path)) == reads.MAX_NESTING
    path.write_text(_nested(reads.MAX_NESTING))  # 32 brackets, 33 once parsed
    assert _refused(reads.read_toml, path, "config") == (
        f"{path}: nested more than 32 deep, not a config"
    )
    # dotted keys: no bracket, 33 tables once parsed
    path.write_text(".".join(["a"] * 33) + " = 1\n")
    assert _refused(reads.read_toml, path) == (
        f"{path}: nested more than 32 deep, not a TOML file"
    )
    path.write_text(".".join(["a"] * 32) + " = 1\n")
    assert reads.depth(reads.read_toml(path)) == 32
    js = tmp_path / "f.json"
    js.write_text('{"a": ' + "[" * 31 + "]" * 31 + "}")
    assert reads.read_json(js)
    # past the limit in brackets: refused before the parser sees it
    monkeypatch.setattr(reads.tomllib, "loads", lambda t: pytest.fail("parsed"))
    monkeypatch.setattr(reads.json, "loads", lambda t: pytest.fail("parsed"))
    path.write_text(_nested(reads.MAX_NESTING + 1))
    assert _refused(reads.read_toml, path) == (
        f"{path}: nested more than 32 deep, not a TOML file"
    )
    js.write_text("[" * 33 + "]" * 33)
    assert _refused(reads.read_json, js) == (
        f"{js}: nested more than 32 deep, not a JSON file"
    )


def test_toml_and_json_that_do_not_parse(tmp_path):
    path = tmp_path / "f.toml"
    path.write_bytes(b"a = '\xff'\n")
    assert _refused(reads.read_toml, path) == (
        f"{path}: not a TOML file (not UTF-8: invalid start byte)"
    )
    path.write_text("a = \n")
    assert _refused(reads.read_toml, path).startswith(f"{path}: not valid TOML (")
    js = tmp_path / "f.json"
    js.write_text("{")
    assert _refused(reads.read_json, js).startswith(f"{js}: not readable JSON (")
    js.write_text("[1, 2]")
    assert _refused(reads.read_json, js) == f"{js}: not a JSON object (list)"
    js.write_text('{"a": [1]}')
    assert reads.read_json(js) == {"a": [1]}
    assert _refused(reads.read_json, js, 9) == (
        f"{js}: larger than 9 bytes, not a JSON file"
    )
    assert reads.read_json(js, 10) == {"a": [1]}


# -- .npz ----------------------------------------------------------------------------


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
    assert _refused(reads.load_npz, path, ("a", "b", "x", "y"), prefix="opt_") == (
        f"{path}: missing x, y"
    )
    assert _refused(reads.load_npz, path, ("a", "b")) == (
        f"{path}: holds 'opt_c.npy', which such a file does not (nothing read)"
    )


def test_npz_members_that_such_a_file_does_not_hold(tmp_path):
    path = tmp_path / "f.npz"
    _npz(path, {"a.npy": _npy(np.zeros(1)), "a.txt": b"x"})
    assert _refused(reads.load_npz, path, ("a",), optional=("a.txt",)) == (
        f"{path}: holds 'a.txt', which such a file does not (nothing read)"
    )
    with pytest.warns(UserWarning, match="Duplicate name"):
        _npz(path, {"a.npy": _npy(np.zeros(1))})
        with zipfile.ZipFile(path, "a") as zf:
            zf.writestr("a.npy", _npy(np.ones(1)))
    assert _refused(reads.load_npz, path, ("a",)) == (
        f"{path}: holds 'a.npy', twice (nothing read)"
    )
    long = "x" * 70 + ".npy"
    _npz(path, {"a.npy": _npy(np.zeros(1)), long: b""})
    assert _refused(reads.load_npz, path, ("a",)) == (
        f"{path}: holds {'x' * 60!r}, which such a file does not (nothing read)"
    )
    many = {f"a{i}.npy": b"" for i in range(reads.MAX_NPZ_MEMBERS)}
    _npz(path, many)
    wanted = tuple(f"a{i}" for i in range(reads.MAX_NPZ_MEMBERS))
    with pytest.raises(UserError, match="not a readable .npz file"):  # empty .npy
        reads.load_npz(path, wanted)
    _npz(path, {**many, "b.npy": b""})
    assert _refused(reads.load_npz, path, wanted) == (
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
    assert _refused(reads.load_npz, path, ("a",)) == (
        f"{path}: a.npy holds Python objects (not read)"
    )
    _npz(path, {"a.npy": _header((-1, 2))})
    assert _refused(reads.load_npz, path, ("a",)) == (
        f"{path}: a.npy declares the shape (-1, 2)"
    )
    member = _header((100,)) + bytes(8 * 3)
    _npz(path, {"a.npy": member})
    assert _refused(reads.load_npz, path, ("a",)) == (
        f"{path}: a.npy declares 800 bytes of data but holds {len(member):,}"
    )
    # declaring as many bytes as the member holds, header and all, passes
    # this check (and fails where the data ends)
    n = next(n for n in range(1, 100) if 8 * n - len(_header((n,))) >= 0)
    member = _header((n,)) + bytes(8 * n - len(_header((n,))))
    _npz(path, {"a.npy": member})
    assert len(member) == 8 * n
    assert _refused(reads.load_npz, path, ("a",)).startswith(
        f"{path}: not a readable .npz file ("
    )
    exact = _header((4,)) + bytes(8 * 4)
    _npz(path, {"a.npy": exact, "b.npy": exact})
    assert reads.load_npz(path, ("a", "b"), max_bytes=64)["b"].shape == (4,)
    assert _refused(reads.load_npz, path, ("a", "b"), max_bytes=63) == (
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
    assert _refused(reads.load_npz, path, ("a",)) == (
        f"{path}: not a readable .npz file (Object arrays cannot be loaded when "
        "allow_pickle=False)"
    )


def test_an_npz_larger_than_such_a_file_is_refused_unread(tmp_path):
    path = tmp_path / "f.npz"
    path.write_bytes(bytes(reads.NPZ_OVERHEAD + 11))
    assert _refused(reads.load_npz, path, ("a",), max_bytes=10) == (
        f"{path}: {reads.NPZ_OVERHEAD + 11:,} bytes, more than such a file holds "
        f"({reads.NPZ_OVERHEAD + 10:,})"
    )
    path.write_bytes(bytes(reads.NPZ_OVERHEAD + 10))
    assert _refused(reads.load_npz, path, ("a",), max_bytes=10).startswith(
        f"{path}: not an .npz file ("
    )


def test_damaged_npz_files_are_one_error(tmp_path):
    path = tmp_path / "f.npz"
    _npz(path, {"a.npy": b"\x93NUMPY\x03\x00"})  # an unknown .npy version
    assert _refused(reads.load_npz, path, ("a",)) == (
        f"{path}: not a readable .npz file (unsupported .npy version (3, 0))"
    )
    _npz(path, {"a.npy": _npy(np.arange(1000.0))}, compression=zipfile.ZIP_DEFLATED)
    data = bytearray(path.read_bytes())
    data[200:260] = bytes(60)  # into the deflated stream
    path.write_bytes(bytes(data))
    assert _refused(reads.load_npz, path, ("a",)).startswith(f"{path}: not a")


def test_a_version_2_header_is_read():
    b = io.BytesIO()
    np.lib.format.write_array_header_2_0(
        b, {"descr": "<i4", "fortran_order": False, "shape": (2, 3)}
    )
    b.seek(0)
    shape, dtype = reads._npy_header(b)
    assert shape == (2, 3) and dtype == np.dtype("<i4")
