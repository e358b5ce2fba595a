"""What makes a directory a run, a reproduction or a rule-based run, and where
what is derived from one goes (:mod:`locustjump.rundir.layout`)."""

import os
from pathlib import Path

import pytest

from locustjump.rundir import layout as L


def test_a_marker_marks_whatever_it_is(tmp_path):
    for test, name in ((L.is_run, "config.toml"), (L.is_reproduction, "reproduce.toml"),
                       (L.is_multiseed, "seeds.toml")):  # fmt: skip
        d = tmp_path / name
        d.mkdir()
        assert not test(d)
        (d / name).mkdir()  # a directory where the file should be: still marked
        assert test(d) and test(str(d))
    broken = tmp_path / "broken"
    broken.mkdir()
    os.symlink(tmp_path / "nowhere", broken / "config.toml")
    assert L.is_run(broken)


def test_a_rule_based_run_holds_its_summary_and_trajectory(tmp_path):
    assert not L.is_rules_run(tmp_path)
    (tmp_path / "summary.json").touch()
    assert not L.is_rules_run(tmp_path)
    (tmp_path / "trajectory.csv").mkdir()
    assert not L.is_rules_run(tmp_path)  # files, both
    os.rmdir(tmp_path / "trajectory.csv")
    (tmp_path / "trajectory.csv").touch()
    assert L.is_rules_run(tmp_path) and L.is_rules_run(str(tmp_path))


@pytest.mark.parametrize(
    "names",
    [
        [],
        ["frozen.npz"],
        [".frozen.tmp.npz", ".config.tmp.toml", ".metrics.tmp.csv"],
        ["frozen.npz", ".config.tmp.toml"],
    ],
)
def test_a_run_stopped_before_its_config_can_start_again(tmp_path, names):
    for n in names:
        (tmp_path / n).touch()
    assert L.is_unstarted(tmp_path) and L.is_unstarted(str(tmp_path))


@pytest.mark.parametrize(
    "names",
    [
        ["config.toml"],
        ["metrics.csv"],  # the file itself, not its temporary
        ["frozen.npz", "best.npz"],
        [".frozen.npz"],
        [".frozen.tmp.toml"],
        ["notes.txt"],
    ],
)
def test_anything_else_is_not_a_fresh_start(tmp_path, names):
    for n in names:
        (tmp_path / n).touch()
    assert not L.is_unstarted(tmp_path)


def test_where_a_runs_parts_are():
    run = Path("r")
    assert L.seed_dir(run, 3) == Path("r/seed-3")
    assert L.eval_metrics_path("r") == Path("r/eval/metrics.json")
    assert L.elite_dir(run, (4, 12)) == Path("r/elites/cell-4-12")
    assert L.elite_dir(run, (7,)) == Path("r/elites/cell-7")


def test_what_is_derived_from_a_shipped_run_goes_under_runs(tmp_path):
    assert (
        L.SHIPPED.name == "results" and (L.SHIPPED.parent / "pyproject.toml").is_file()
    )
    assert L.SHIPPED_DERIVED == L.SHIPPED.parent / "runs" / "shipped"
    shipped = L.SHIPPED / "study" / "x"
    assert L.derived_dir(shipped) == L.SHIPPED_DERIVED / "study" / "x"
    assert L.derived_dir(L.SHIPPED) == L.SHIPPED_DERIVED
    assert L.derived_dir(tmp_path / "r") == tmp_path / "r"
    assert L.derived_dir("rel/r") == Path("rel/r")
    assert L.elite_dir(shipped, (1, 2)) == (
        L.SHIPPED_DERIVED / "study" / "x" / "elites" / "cell-1-2"
    )
