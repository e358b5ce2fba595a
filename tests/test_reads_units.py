"""``rundir.reads`` function by function: each refusal's exact words, each
bound at its edge (``tests/test_reads.py`` tries them through the commands)."""

import os
from pathlib import Path

import pytest

from helpers import user_error
from locustjump.errors import UserError
from locustjump.rundir import reads

# -- regular files only --------------------------------------------------------


def test_what_a_path_is_when_it_is_not_a_regular_file(tmp_path):
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    for path, kind in (
        (tmp_path, "a directory"),
        (fifo, "a FIFO (named pipe)"),
        (Path("/dev/null"), "a character device"),
    ):
        assert user_error(reads.read_bytes, path, "TOML file", 10) == (
            f"{path}: is {kind}, not a regular file; expected a TOML file"
        )
    # "an" before a vowel or a dot
    npz = user_error(reads.load_npz, tmp_path, ("a",))
    assert npz.endswith("expected an .npz file")
    assert user_error(reads.read_text, tmp_path, "image").endswith("expected an image")


def test_a_mode_of_no_known_kind_is_something_else(tmp_path):
    err = reads._not_regular(tmp_path / "f", 0, "file")
    assert (
        str(err)
        == f"{tmp_path / 'f'}: is something else, not a regular file; expected a file"
    )
    assert reads._not_regular(tmp_path / "f", 0o100644, "file") is None


def test_missing_files_and_broken_links_are_named(tmp_path):
    assert user_error(reads.read_text, tmp_path / "none") == (
        f"{tmp_path / 'none'}: no such file"
    )
    link = tmp_path / "link"
    link.symlink_to(tmp_path / "gone")
    assert user_error(reads.read_json, link) == f"{link}: a broken symbolic link"
    loop = tmp_path / "loop"
    loop.symlink_to(loop)
    assert user_error(reads.read_text, loop) == (
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
    assert user_error(reads.read_text, path) == (
        f"{path}: is a FIFO (named pipe), not a regular file; expected a text file"
    )


def test_a_file_that_vanishes_before_it_is_opened(tmp_path, monkeypatch):
    path = tmp_path / "f"
    path.write_text("x")

    def gone(p, flags):
        Path(p).unlink()
        raise FileNotFoundError(2, "No such file or directory")

    monkeypatch.setattr(reads.os, "open", gone)
    assert user_error(reads.read_text, path) == f"{path}: no such file"


# -- sizes -------------------------------------------------------------------------


def test_a_file_of_exactly_the_limit_is_read_one_byte_more_is_not(tmp_path):
    path = tmp_path / "f"
    path.write_bytes(b"x" * 1024)
    assert reads.read_bytes(path, "thing", 1024) == b"x" * 1024
    assert user_error(reads.read_bytes, path, "thing", 1023) == (
        f"{path}: larger than 1,023 bytes, not a thing"
    )
    path.write_bytes(b"x" * 1025)
    assert user_error(reads.read_bytes, path, "thing", 1024) == (
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
    assert user_error(reads.read_bytes, path, "thing", 10) == (
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
    assert user_error(reads.read_text, path, "config") == (
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
    assert user_error(reads.read_toml, path, "config") == (
        f"{path}: nested more than 32 deep, not a config"
    )
    # dotted keys: no bracket, 33 tables once parsed
    path.write_text(".".join(["a"] * 33) + " = 1\n")
    assert user_error(reads.read_toml, path) == (
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
    assert user_error(reads.read_toml, path) == (
        f"{path}: nested more than 32 deep, not a TOML file"
    )
    js.write_text("[" * 33 + "]" * 33)
    assert user_error(reads.read_json, js) == (
        f"{js}: nested more than 32 deep, not a JSON file"
    )


def test_toml_and_json_that_do_not_parse(tmp_path):
    path = tmp_path / "f.toml"
    path.write_bytes(b"a = '\xff'\n")
    assert user_error(reads.read_toml, path) == (
        f"{path}: not a TOML file (not UTF-8: invalid start byte)"
    )
    path.write_text("a = \n")
    assert user_error(reads.read_toml, path).startswith(f"{path}: not valid TOML (")
    js = tmp_path / "f.json"
    js.write_text("{")
    assert user_error(reads.read_json, js).startswith(f"{js}: not readable JSON (")
    js.write_text("[1, 2]")
    assert user_error(reads.read_json, js) == f"{js}: not a JSON object (list)"
    js.write_text('{"a": [1]}')
    assert reads.read_json(js) == {"a": [1]}
    assert user_error(reads.read_json, js, 9) == (
        f"{js}: larger than 9 bytes, not a JSON file"
    )
    assert reads.read_json(js, 10) == {"a": [1]}
