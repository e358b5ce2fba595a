"""A run directory's files written whole or not at all
(:mod:`locustjump.rundir.files`), and the arrays read back from its ``.npz``
files checked as written, never converted (:mod:`locustjump.rundir.arrays`)."""

import hashlib
import os
import tomllib

import numpy as np
import pytest

from helpers import exactly
from locustjump.errors import UserError
from locustjump.rundir import arrays
from locustjump.rundir import files as rf


def test_a_temporary_path_sits_beside_the_file_hidden(tmp_path):
    assert rf.temporary_path(tmp_path / "best.npz") == tmp_path / ".best.tmp.npz"
    assert rf.temporary_path(tmp_path / "a", ".part") == tmp_path / ".a.part"


def _digest(name):
    return hashlib.sha256(name.encode()).hexdigest()[:16]


def test_a_temporary_name_too_long_for_the_directory_is_a_digest(tmp_path):
    limit = os.pathconf(tmp_path, "PC_NAME_MAX")
    fits = "x" * (limit - len("..tmp.toml")) + ".toml"  # its temporary just fits
    assert rf.temporary_path(tmp_path / fits).name == f".{fits[:-5]}.tmp.toml"
    long = "y" * (limit - 5) + ".toml"  # its temporary is 5 bytes too long
    assert rf.temporary_path(tmp_path / long).name == f".{_digest(long)}.tmp.toml"
    odd = "z" * 220 + "." + "s" * 32  # a suffix of 33 bytes, dot included: dropped
    assert rf.temporary_path(tmp_path / odd).name == f".{_digest(odd)}.tmp"
    ok = "z" * 220 + "." + "s" * 31  # one of 32 is kept
    assert rf.temporary_path(tmp_path / ok).name == f".{_digest(ok)}.tmp.{'s' * 31}"


def test_a_temporary_name_is_held_to_the_directorys_own_limit(tmp_path, monkeypatch):
    def pathconf(path, name):
        assert (path, name) == (tmp_path, "PC_NAME_MAX")
        return 16

    monkeypatch.setattr(rf.os, "pathconf", pathconf)
    assert rf.temporary_path(tmp_path / "abcdefg.npz").name == ".abcdefg.tmp.npz"
    assert rf.temporary_path(tmp_path / "abcdefgh.npz").name == (
        f".{_digest('abcdefgh.npz')}.tmp.npz"
    )


def test_a_temporary_name_where_the_limit_cannot_be_read(tmp_path, monkeypatch):
    def fails(path, name):
        raise OSError("no")

    monkeypatch.setattr(rf.os, "pathconf", fails)
    name = "n" * 248  # with ".", ".tmp" and ".a": 255 bytes, Linux's limit
    assert rf.temporary_path(tmp_path / f"{name}.a").name == f".{name}.tmp.a"
    longer = f"n{name}.a"
    assert rf.temporary_path(tmp_path / longer).name == f".{_digest(longer)}.tmp.a"


def test_an_atomic_write_replaces_the_file_whole(tmp_path):
    p = tmp_path / "x.txt"
    rf.atomic_write_text(p, "one")
    rf.atomic_write_text(p, "two")
    assert p.read_text() == "two" and os.listdir(tmp_path) == ["x.txt"]
    rf.atomic_write_bytes(p, lambda f: f.write(b"\x00\x01"))
    assert p.read_bytes() == b"\x00\x01"
    rf.write_json(p, {"a": [1, 2]})
    assert p.read_text() == '{\n  "a": [\n    1,\n    2\n  ]\n}\n'
    rf.write_toml(p, {"a": 1})
    assert p.read_text() == "a = 1\n"
    rf.write_toml(p, {"a": 1}, header="# h\n")
    assert p.read_text() == "# h\na = 1\n" and tomllib.loads(p.read_text()) == {"a": 1}
    rf.save_npz(tmp_path / "z.npz", g=np.arange(3.0))
    with np.load(tmp_path / "z.npz") as z:
        assert z["g"].tolist() == [0.0, 1.0, 2.0]
    assert sorted(os.listdir(tmp_path)) == ["x.txt", "z.npz"]


def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path):
    p = tmp_path / "x.txt"
    p.write_text("old")

    def fails(f):
        f.write(b"half")
        raise OSError(28, "No space left on device")

    with pytest.raises(UserError, match=exactly(
        f"{p}: cannot be written (No space left on device); the previous "
        "version is intact"
    )):  # fmt: skip
        rf.atomic_write_bytes(p, fails)
    assert p.read_text() == "old" and os.listdir(tmp_path) == ["x.txt"]
    new = tmp_path / "new.txt"
    with pytest.raises(UserError, match=exactly(
        f"{new}: cannot be written (No space left on device)"
    )):  # fmt: skip
        rf.atomic_write_bytes(new, fails)
    assert os.listdir(tmp_path) == ["x.txt"]
    with pytest.raises(RuntimeError):  # any other failure: still nothing left
        with rf.atomic_path(new) as tmp:
            tmp.write_text("half")
            raise RuntimeError
    assert os.listdir(tmp_path) == ["x.txt"]


def test_a_write_into_a_missing_directory_is_named(tmp_path):
    p = tmp_path / "none" / "x.txt"
    with pytest.raises(UserError, match=exactly(
        f"{p}: cannot be written (No such file or directory)"
    )):  # fmt: skip
        rf.atomic_write_text(p, "a")
    with pytest.raises(UserError, match=exactly(
        f"{p}: cannot be written (No such file or directory)"
    )):  # fmt: skip
        rf.append_line(p, "a\n")


def test_a_line_is_appended(tmp_path):
    p = tmp_path / "m.csv"
    rf.append_line(p, "a,b\n")
    rf.append_line(p, "1,2\n")
    assert p.read_text() == "a,b\n1,2\n"
    assert oct(p.stat().st_mode & 0o777) == oct(0o644 & ~_umask())


def _umask():
    old = os.umask(0)
    os.umask(old)
    return old


P = "r/best.npz"


def _words(call, *args):
    with pytest.raises(UserError) as e:
        call(*args)
    return str(e.value)


def test_a_scalar_is_read_as_python_holds_it():
    z = {"f": np.float64(1.5), "i": np.int32(3), "u": np.uint8(4),
         "t": np.array("rcga"), "b": np.array(True)}  # fmt: skip
    assert (
        arrays.scalar(z, "f", P, "f") == 1.5
        and type(arrays.scalar(z, "f", P, "f")) is float
    )
    assert (
        arrays.scalar(z, "i", P, "i") == 3
        and type(arrays.scalar(z, "i", P, "i")) is int
    )
    assert arrays.scalar(z, "u", P, "i") == 4
    assert arrays.scalar(z, "t", P, "U") == "rcga"
    assert arrays.scalar(z, "b", P, "b") is True


@pytest.mark.parametrize(
    ("value", "kind", "words"),
    [
        (np.float32(1.5), "f", "a float64 number, got a float32 array of shape ()"),
        (np.zeros(1), "f", "a float64 number, got a float64 array of shape (1,)"),
        (np.float64(2), "i", "an integer, got a float64 array of shape ()"),
        (np.array(True), "i", "an integer, got a bool array of shape ()"),
        (np.array(1), "U", "text, got a int64 array of shape ()"),
        (np.array(["a"]), "U", "text, got a <U1 array of shape (1,)"),
        (np.array(1), "b", "a boolean, got a int64 array of shape ()"),
    ],
)
def test_a_scalar_of_another_kind_or_shape_is_named(value, kind, words):
    assert (
        _words(arrays.scalar, {"k": value}, "k", P, kind) == f"{P}: k must be {words}"
    )


def test_a_float_scalar_is_finite():
    for v in (np.nan, np.inf, -np.inf):
        assert _words(arrays.scalar, {"k": np.float64(v)}, "k", P, "f") == (
            f"{P}: k must be finite, got {v}"
        )


def test_genomes_are_finite_float64_of_their_shape():
    g = np.ones((2, 3))
    assert arrays.genomes({"g": g}, "g", P, (2, 3)) is g
    assert _words(arrays.genomes, {"g": g.astype(np.float32)}, "g", P, (2, 3)) == (
        f"{P}: g must be float64, got float32"
    )
    assert _words(arrays.genomes, {"g": g}, "g", P, (3, 2)) == (
        f"{P}: g has shape (2, 3), expected (3, 2)"
    )
    g[1, 2] = np.inf
    assert _words(arrays.genomes, {"g": g}, "g", P, (2, 3)) == f"{P}: g must be finite"


def test_plain_arrays_hold_numbers_or_text_without_nan():
    ok = {"a": np.arange(3), "b": np.array(["x"]), "c": np.ones(2), "d": np.bool_(1),
          "e": np.array([np.inf])}  # fmt: skip
    assert arrays.plain(ok, list(ok), P) is None
    for bad, words in ((np.ones(2, complex), "holds complex128 values, not numbers"),
                       (np.array([b"x"]), "holds |S1 values, not numbers"),
                       (np.array([1.0, np.nan]), "holds NaN")):  # fmt: skip
        assert (
            _words(arrays.plain, {**ok, "z": bad}, ["a", "z"], P) == f"{P}: z {words}"
        )
    assert arrays.plain({"z": np.array([np.nan])}, [], P) is None  # only those named
