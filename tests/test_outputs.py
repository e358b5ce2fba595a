"""``rundir.outputs`` function by function: where a command writes is
checked before anything is made, nothing already there is overwritten
unless ``force`` allows it (a run's own files never), and what a failing
command made is removed again (the commands are tried in
``tests/test_hardening.py`` and the others)."""

import os
from pathlib import Path

import pytest

from helpers import held_lock, tree_snapshot
from locustjump.errors import UserError
from locustjump.rundir import layout, outputs


def _refused(call, *args, **kw) -> str:
    with pytest.raises(UserError) as e:
        call(*args, **kw)
    return str(e.value)


# -- checked before anything is made -------------------------------------------


def test_an_out_dir_that_is_new_or_empty_is_taken_and_nothing_made(tmp_path):
    new = tmp_path / "a" / "b"
    assert outputs.check_out_dir(str(new)) == new and not new.parent.exists()
    (tmp_path / "empty").mkdir()
    assert outputs.check_out_dir(tmp_path / "empty") == tmp_path / "empty"


def test_an_out_dir_that_holds_anything_needs_force(tmp_path):
    (tmp_path / "f").write_text("mine")
    assert _refused(outputs.check_out_dir, tmp_path, setting="dest") == (
        f"dest {tmp_path}: directory exists and is not empty (use force=True "
        "to write into it)"
    )
    assert outputs.check_out_dir(tmp_path, force=True) == tmp_path
    assert _refused(outputs.check_out_dir, tmp_path / "f") == (
        f"out {tmp_path / 'f'}: exists and is not a directory"
    )


def test_paths_that_cannot_be_looked_at_are_named(tmp_path):
    broken = tmp_path / "broken"
    broken.symlink_to(tmp_path / "gone")
    assert _refused(outputs.check_out_dir, broken) == (
        f"out {broken}: a broken symbolic link"
    )
    (tmp_path / "file").write_text("x")
    under = tmp_path / "file" / "sub"
    assert _refused(outputs.check_out_dir, under) == f"out {under}: Not a directory"
    loop = tmp_path / "loop"
    loop.symlink_to(loop)
    assert _refused(outputs.check_out_dir, loop / "x") == (
        f"out {loop / 'x'}: Too many levels of symbolic links"
    )
    # a broken link on the way is named as the parent it is
    assert _refused(outputs.check_out_dir, broken / "x") == (
        f"out {broken}: a broken symbolic link"
    )
    assert not outputs._exists(tmp_path / "none", "out")
    assert outputs._exists(tmp_path, "out")


def test_an_unreadable_out_dir_is_named(tmp_path, monkeypatch):
    def denied(self):
        raise PermissionError(13, "Permission denied")

    (tmp_path / "d").mkdir()
    monkeypatch.setattr(Path, "iterdir", denied)
    assert _refused(outputs.check_out_dir, tmp_path / "d") == (
        f"out {tmp_path / 'd'}: Permission denied"
    )


def test_an_out_file_new_or_forced(tmp_path):
    f = tmp_path / "v.mp4"
    assert outputs.prepare_out_file(str(f)) == f
    f.write_text("mine")
    assert _refused(outputs.prepare_out_file, f, setting="figure") == (
        f"figure {f}: file exists (use force=True to overwrite)"
    )
    assert outputs.prepare_out_file(f, force=True) == f
    assert _refused(outputs.prepare_out_file, tmp_path, force=True) == (
        f"out {tmp_path}: is a directory, expected a file"
    )
    missing = tmp_path / "none" / "v.mp4"
    assert _refused(outputs.prepare_out_file, missing) == (
        f"out {missing}: directory {missing.parent} does not exist"
    )
    broken = tmp_path / "broken"
    broken.symlink_to(tmp_path / "gone")
    assert _refused(outputs.prepare_out_file, broken / "v.mp4", setting="figure") == (
        f"figure {broken}: a broken symbolic link"
    )
    on_a_file = f / "v.mp4"
    assert _refused(outputs.prepare_out_file, on_a_file) == (
        f"out {on_a_file}: Not a directory"
    )


@pytest.mark.parametrize(
    "marker, holder",
    [
        (layout.CONFIG, "run"),
        (layout.MARKER, "reproduction"),
        (layout.SEEDS_MARKER, "reproduction"),
    ],
)
def test_a_runs_own_files_are_never_an_output(tmp_path, marker, holder):
    (tmp_path / marker).write_text("")
    for name in outputs.RECORDS:
        target = tmp_path / name
        assert _refused(outputs.prepare_out_file, target, force=True) == (
            f"out {target}: one of the files of the {holder} in {tmp_path} (never "
            "overwritten, even with force=True); choose another file"
        )
    # any other file there is an output like any other
    assert outputs.prepare_out_file(tmp_path / "video.mp4") == tmp_path / "video.mp4"


def test_a_rule_based_runs_files_and_a_plain_directorys(tmp_path):
    (tmp_path / layout.RULES_SUMMARY).write_text("{}")
    target = tmp_path / layout.TRAJECTORY_CSV
    # a summary alone is not a rule-based run: its name is free
    assert outputs.prepare_out_file(target) == target
    target.write_text("")
    assert "of the rule-based run in" in _refused(
        outputs.prepare_out_file, tmp_path / layout.CONFIG
    )
    plain = tmp_path / "plain"
    plain.mkdir()
    assert outputs.prepare_out_file(plain / layout.CONFIG) == plain / layout.CONFIG
    assert outputs._holder(plain) is None


# -- made, and removed again ----------------------------------------------------


def test_make_dir_returns_the_topmost_directory_it_made(tmp_path):
    assert outputs.make_dir(tmp_path) is None
    top = outputs.make_dir(tmp_path / "a" / "b" / "c")
    assert top == tmp_path / "a" and (tmp_path / "a" / "b" / "c").is_dir()
    assert outputs.make_dir(tmp_path / "a" / "d") == tmp_path / "a" / "d"
    outputs.remove_made(top)
    assert list(tmp_path.iterdir()) == []
    outputs.remove_made(None)  # nothing made: nothing removed
    assert tmp_path.is_dir()
    # gone already (another cleanup was first): nothing to complain about
    outputs.remove_made(tmp_path / "gone")


def test_make_dir_names_what_it_cannot_create(tmp_path):
    (tmp_path / "f").write_text("x")
    where = tmp_path / "f" / "d"
    assert _refused(outputs.make_dir, where, "dest") == (
        f"dest {where}: cannot be created (Not a directory)"
    )
    assert _refused(outputs.make_dir, where, None) == (
        f"{where}: cannot be created (Not a directory)"
    )
    assert _refused(outputs.make_dir, where) == (
        f"out {where}: cannot be created (Not a directory)"
    )


def test_made_dir_removes_what_it_made_when_the_body_fails(tmp_path):
    with pytest.raises(KeyboardInterrupt), outputs.made_dir(tmp_path / "a" / "b") as d:
        (d / "half").write_text("x")
        raise KeyboardInterrupt
    assert list(tmp_path.iterdir()) == []
    (tmp_path / "kept").mkdir()
    with pytest.raises(OSError), outputs.made_dir(tmp_path / "kept") as d:
        (d / "half").write_text("x")
        raise OSError(28, "No space left on device")
    assert (tmp_path / "kept" / "half").is_file()  # it was there: not removed
    with outputs.made_dir(tmp_path / "n" / "m") as d:
        (d / "whole").write_text("x")
    assert (tmp_path / "n" / "m" / "whole").is_file()


def test_output_dir_made_locked_and_removed_on_failure(tmp_path):
    with outputs.output_dir(tmp_path / "o" / "p") as d:
        assert d == tmp_path / "o" / "p" and d.is_dir()
        (d / "done").write_text("x")
    assert (tmp_path / "o" / "p" / "done").is_file()
    with pytest.raises(RuntimeError), outputs.output_dir(tmp_path / "q" / "r") as d:
        (d / "half").write_text("x")
        raise RuntimeError
    assert not (tmp_path / "q").exists()
    # an existing, full one: refused unless forced, and then not removed
    before = tree_snapshot(tmp_path / "o")
    assert "is not empty" in _refused(
        lambda: outputs.output_dir(tmp_path / "o").__enter__()
    )
    with pytest.raises(RuntimeError), outputs.output_dir(tmp_path / "o", force=True):
        raise RuntimeError
    assert tree_snapshot(tmp_path / "o") == before


def _second_look_finds(monkeypatch, name, meanwhile) -> list:
    """``outputs.<name>`` (the check) watched: before its second look, another
    process does ``meanwhile(path)``. Returns the paths looked at."""
    real = getattr(outputs, name)
    looks = []

    def watched(path, **kw):
        looks.append(path)
        if len(looks) == 2:
            meanwhile(Path(path))
        return real(path, **kw)

    monkeypatch.setattr(outputs, name, watched)
    return looks


def test_output_dir_checks_again_under_the_lock(tmp_path, monkeypatch):
    """Another process filled the directory between the first look and the
    lock: the second look refuses it, and keeps what that process wrote."""
    d = tmp_path / "o"
    looks = _second_look_finds(
        monkeypatch, "check_out_dir", lambda p: (p / "theirs").write_text("x")
    )
    with pytest.raises(UserError, match="is not empty"):
        with outputs.output_dir(d):
            pass
    assert len(looks) == 2 and (d / "theirs").read_text() == "x"


def test_output_dir_and_file_wait_for_no_one_who_holds_the_lock(tmp_path):
    (tmp_path / "o").mkdir()
    holder = held_lock(tmp_path / "o")
    try:
        with pytest.raises(UserError, match="is in use by process"):
            with outputs.output_dir(tmp_path / "o"):
                pass
        with pytest.raises(UserError, match="is in use by process"):
            with outputs.output_file(tmp_path / "o" / "f.png"):
                pass
    finally:
        holder.kill()
        holder.wait()
    assert list((tmp_path / "o").iterdir()) == []


def test_output_file_checks_again_under_the_lock(tmp_path, monkeypatch):
    f = tmp_path / "f.png"
    looks = _second_look_finds(
        monkeypatch, "prepare_out_file", lambda p: p.write_text("theirs")
    )
    with pytest.raises(UserError, match="file exists"):
        with outputs.output_file(f):
            pass
    assert f.read_text() == "theirs"
    looks.clear()
    f.unlink()
    with outputs.output_file(f, force=True) as out:
        assert out == f
    assert len(looks) == 2


# -- where a run's derived files go ---------------------------------------------


def test_deriving_writes_into_the_run_itself(tmp_path):
    with outputs.deriving(tmp_path) as d:
        assert d == tmp_path


def test_deriving_from_a_shipped_run_makes_its_directory_and_removes_it_on_failure(
    tmp_path, monkeypatch
):
    monkeypatch.setattr(layout, "SHIPPED", tmp_path / "results")
    monkeypatch.setattr(layout, "SHIPPED_DERIVED", tmp_path / "runs" / "shipped")
    shipped = tmp_path / "results" / "demo" / "kick"
    shipped.mkdir(parents=True)
    dest = layout.derived_dir(shipped)
    assert dest == tmp_path / "runs" / "shipped" / "demo" / "kick"
    with pytest.raises(RuntimeError), outputs.deriving(shipped) as d:
        assert d == dest and d.is_dir()
        raise RuntimeError
    assert not dest.exists()
    with outputs.deriving(shipped) as d:
        (d / "eval.json").write_text("{}")
    with pytest.raises(RuntimeError), outputs.deriving(shipped) as d:
        raise RuntimeError  # not made this time: kept, with what it holds
    assert (dest / "eval.json").is_file()
    assert os.path.isdir(shipped)
