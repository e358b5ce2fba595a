"""`locustjump study FILE`: a declared grid of runs, trained resumably, its
plan, its status, its table; bad study files refused before anything runs."""

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from helpers import EXAMPLE, assert_same_run, example_study, run_cli, tree_snapshot
from locustjump import rundir
from locustjump.runs.study_table import TABLE_JSON, TABLE_MD
from locustjump.runs.studyfile import load_study
from locustjump.runs.trainer import train

REPO = Path(__file__).resolve().parents[1]


def test_dry_run_prints_the_plan_and_its_cost_and_writes_nothing(tmp_path):
    path = example_study(tmp_path)
    r = run_cli("study", str(path), "--dry-run", "--threads", "1")
    assert r.returncode == 0, r.stderr
    assert "| rcga | kick | flat x 1 | 4 x 8 |" in r.stdout
    assert "0 / 0 / 5" in r.stdout  # done / partial / to do
    assert "Training left:" in r.stdout and "steps/s here" in r.stdout
    assert not (tmp_path / "runs").exists()


@pytest.mark.parametrize("load", [0.0, 0.49, 0.5, 3.0])
def test_dry_run_says_when_its_rates_were_measured_on_a_busy_machine(
    tmp_path, monkeypatch, load
):
    """Rates measured beside other work are low: the plan says so, with the
    load it saw (a study's own workers make the machine busy)."""
    import locustjump.runs.study_plan as st
    from locustjump.sim.engine.backends import ThreadBackend

    monkeypatch.setattr(st.os, "getloadavg", lambda: (load, 0.0, 0.0))
    with ThreadBackend(1) as backend:
        text = st.dry_run(load_study(example_study(tmp_path)), backend)
    note = f"busy when they were measured (load average {load:.1f} over"
    assert (note in text) == (load >= 0.5), text.splitlines()[-1]


def test_dry_run_times_each_scoring_resolution_at_its_own_rate(tmp_path, monkeypatch):
    """Scoring at 12 substeps is slower than at the 3 a run trained at: the
    plan measures each resolution's rate and times its share at that rate."""
    import locustjump.runs.study_plan as st

    rates = {None: 1000.0, 12: 250.0}
    seen = []

    def rate(cfg, backend, substeps=None):
        seen.append(substeps)
        return rates[substeps]

    monkeypatch.setattr(st, "throughput", rate)
    path = example_study(tmp_path)
    path.write_text(path.read_text() + "\n[evaluation]\nsubsteps = [3, 12]\n")
    study = load_study(path)
    text = st.dry_run(study, backend=None)
    arm = study.arms["rcga"]
    steps = st.score_steps(study, arm.base, st.behaviour_for(arm.base))
    assert set(steps) == {3, 12} and steps[3] == steps[12]
    per_arm = 5 * steps[3] / 1000.0 + 5 * steps[12] / 250.0  # 5 seeds
    assert f"(its own scene x 2 physics): {st.format_duration(2 * per_arm)} " in text
    assert seen == [None, 12, None, 12]  # each arm: as trained, then at 12


def test_each_run_is_the_run_train_makes(finished_study, tmp_path):
    path, r, _ = finished_study
    study = load_study(path)
    assert "10 of 10 runs done" in r.stdout
    arm = study.arms["random"]
    alone = tmp_path / "alone"
    train(arm.config(1), alone, progress=False)
    assert_same_run(arm.run_dir(1), alone)
    assert rundir.load_config(arm.run_dir(1) / rundir.CONFIG) == arm.config(1)


def test_status_after_the_runs(finished_study):
    path, _, _ = finished_study
    r = run_cli("study", str(path), "--status")
    assert r.returncode == 0
    assert "| rcga | done | done | done | done | done |" in r.stdout
    assert "10 of 10 runs done" in r.stdout


def test_a_killed_study_continues_with_the_same_command(finished_study, tmp_path):
    """A run stopped after one generation (as a kill leaves it) continues from
    its checkpoint; the finished runs are kept as they are."""
    path, _, _ = finished_study
    mine = example_study(tmp_path, **{'seeds = "0-4"': 'seeds = "0-1"'})
    study = load_study(mine)
    arm = study.arms["rcga"]
    train(arm.config(0), arm.run_dir(0), progress=False, stop_after=1)
    done = study.arms["random"].run_dir(0)
    train(study.arms["random"].config(0), done, progress=False)
    before = (done / rundir.METRICS).read_bytes()
    r = run_cli("study", str(mine), "--quiet")
    assert r.returncode == 0, r.stderr
    assert "1 of 4 runs done, 3 to train" in r.stderr
    assert (done / rundir.METRICS).read_bytes() == before
    assert_same_run(arm.run_dir(0), load_study(path).arms["rcga"].run_dir(0))


def test_the_table(finished_study):
    path, _, t = finished_study
    study = load_study(path)
    data = json.loads((study.out / TABLE_JSON).read_text())
    assert (study.out / TABLE_MD).read_text() in t.stdout
    # as trained, a run's score is its best genome's training fitness
    for row in data["runs"]:
        best = rundir.BestGenome.load(Path(row["path"]) / rundir.BEST)
        assert row["at"]["None"]["score"] == pytest.approx(best.fitness, rel=1e-12)
        m = rundir.read_metrics(Path(row["path"]) / rundir.METRICS)
        assert row["evaluations"] == m["evaluations"].sum()
        assert row["control_steps"] == m["control_steps"].sum()
    (pair,) = data["pairs"]["None"]
    rcga = [r["at"]["None"]["score"] for r in data["runs"] if r["arm"] == "rcga"]
    rand = [r["at"]["None"]["score"] for r in data["runs"] if r["arm"] == "random"]
    shift = np.median(np.subtract.outer(rand, rcga))
    assert pair["shift"] == pytest.approx(shift)
    assert pair["low"] <= pair["shift"] <= pair["high"]
    assert pair["margin"] == 0.1 and pair["verdict"]
    # the RCGA keeps its 2 elites unevaluated: 8 + 3 x 6 genomes against 4 x 8
    assert "**not equal**" in t.stdout
    assert (study.out / "learning.png").stat().st_size > 1000
    assert (study.out / "scores.png").read_bytes().startswith(b"\x89PNG")


def test_a_table_of_one_seed_compares_nothing_and_says_why(finished_study, tmp_path):
    path, _, _ = finished_study
    study = load_study(path)
    before = tree_snapshot(study.out)
    look = tmp_path / "look"  # the same runs, this table elsewhere
    t = run_cli("study", str(path), "--table", "--seeds", "2", "--out", str(look))
    assert t.returncode == 0, t.stderr
    labels = "; ".join(a.label for a in study.arms.values())
    assert f"No comparison: {labels} each have fewer than 2 runs." in t.stdout
    pairs = json.loads((look / TABLE_JSON).read_text())["pairs"]
    assert all(rows == [] for rows in pairs.values())
    assert (look / "scores.png").is_file() and (look / "learning.png").is_file()
    assert tree_snapshot(study.out) == before  # the study's own table untouched
    assert "scoring [" not in t.stderr  # its scores read from the study's cache


def test_out_is_for_the_table_and_an_empty_directory(finished_study, tmp_path):
    path, _, _ = finished_study
    for argv, message in (
        (("--status", "--out", str(tmp_path / "t")),
         "--out is where --table writes; it needs --table"),
        (("--table", "--force"), "--force lets --table --out write into a full"),
    ):  # fmt: skip
        r = run_cli("study", str(path), *argv)
        assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1
        assert message in r.stderr, r.stderr
    mine = tmp_path / "notes.txt"
    mine.write_text("mine")
    r = run_cli("study", str(path), "--table", "--out", str(mine))
    assert r.returncode == 2 and "exists and is not a directory" in r.stderr
    r = run_cli("study", str(path), "--table", "--out", str(tmp_path))
    assert r.returncode == 2 and "is not empty (use --force" in r.stderr
    assert mine.read_text() == "mine" and sorted(tmp_path.iterdir()) == [mine]
    r = run_cli("study", str(path), "--table", "--out", str(tmp_path), "--force")
    assert r.returncode == 0, r.stderr
    assert mine.read_text() == "mine" and (tmp_path / TABLE_MD).is_file()


def test_a_table_that_fails_leaves_no_out_behind(
    finished_study, tmp_path, monkeypatch, capsys
):
    """Scores written into a new --out, then the table fails: no half-made
    directory is left (the study's own cache keeps what was scored)."""
    import locustjump.cli.study as cli_study
    from locustjump.cli import main

    def half(study, backend, log=None, out=None):
        out.mkdir(parents=True, exist_ok=True)  # as study_table does
        (out / "scores.json").write_text("{}")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(cli_study, "study_table", half)
    path, _, _ = finished_study
    look = tmp_path / "a" / "look"
    assert main(["study", str(path), "--table", "--out", str(look)]) == 2
    assert "No space left on device" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_moved_runs_keep_their_scores(finished_study, tmp_path, monkeypatch):
    """The score cache is keyed by what a run is, not where it lies: the runs
    moved elsewhere (as shipping moves them into results/) are tabled from
    the scores kept, and two runs that differ have different keys."""
    import locustjump.runs.study_table as st

    path, _, _ = finished_study
    study = load_study(path)
    shutil.copytree(study.root, tmp_path / "moved")
    out = shutil.copytree(study.out, tmp_path / "out")
    moved = tmp_path / "moved.toml"
    moved.write_text(
        path.read_text()
        .replace(f'root = "{study.root}"', f'root = "{tmp_path / "moved"}"')
        .replace("seeds =", f'out = "{out}"\nseeds =', 1)
    )
    there = load_study(moved)
    assert there.arms["rcga"].run_dir(0) != study.arms["rcga"].run_dir(0)

    def no_simulation(*args, **kwargs):
        raise AssertionError("a moved run was re-simulated")

    monkeypatch.setattr(st, "score_run", no_simulation)
    md, _ = st.make_table(there, st.run_rows(there, st.scores(there)))
    assert md == (study.out / TABLE_MD).read_text()
    keys = {st._key(a.run_dir(s), None, None) for a, s in study.runs()}
    assert len(keys) == len(list(study.runs()))


@pytest.mark.parametrize(
    "change, message",
    [
        (("[arms.random]", "[arms.random]\npopulaton = 3"), "unknown key 'populaton'"),
        (('optimizer = { kind = "random" }', 'frozen = { kick = "rcga" }'),
         "kick builds on no runs"),
        (('seeds = "0-4"', "seeds = []"), "seeds must be a non-empty list"),
        (('currency = "evaluations"', 'currency = "dollars"'), "currency 'dollars'"),
        (('reference = "rcga"', 'reference = "cma"'), "reference 'cma'"),
        (("margin = 0.1 ", "margin = -1 "), "margin must be a finite number > 0"),
        (("[defaults]", "wat = 1\n[defaults]"), "unknown key 'wat'"),
        (('label = "random search"', 'label = "random search"\nseed = 3'),
         "a fixed seed is for an arm others build on"),
        (('label = "random search"', 'label = "RCGA (the paper\'s)"'),
         "[arms.random]: label \"RCGA (the paper's)\" is arm 'rcga''s already"),
    ],
)  # fmt: skip
def test_a_wrong_study_file_is_one_line_and_starts_nothing(tmp_path, change, message):
    path = example_study(tmp_path, **{change[0]: change[1]})
    for how in ((), ("--dry-run",), ("--table",), ("--status",)):
        r = run_cli("study", str(path), *how)
        assert r.returncode == 2, r.stderr
        assert message in r.stderr and len(r.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "runs").exists()


def test_frozen_arms_must_exist_and_not_build_in_a_circle(tmp_path):
    base = (
        'seeds = "0"\n[defaults]\noptimizer = { population = 4 }\n'
        '[arms.c]\nbehaviour = "composed"\n'
    )
    path = tmp_path / "s.toml"
    path.write_text(base + 'frozen = { kick = "k", getup = "g", return-legs = "r" }\n')
    r = run_cli("study", str(path))
    assert r.returncode == 2 and "frozen: no arm 'k'" in r.stderr
    path.write_text(base + 'frozen = { kick = "c", getup = "c", return-legs = "c" }\n')
    r = run_cli("study", str(path), "--dry-run")
    assert r.returncode == 2 and "in a circle: c -> c" in r.stderr


def test_a_run_that_is_not_the_declared_one_is_named(finished_study, tmp_path):
    path, _, _ = finished_study
    study = load_study(path)
    numpy = {"generations = 4": 'generations = 4\nengine = "numpy"'}
    other = example_study(tmp_path, **numpy)
    text = other.read_text().replace(str(tmp_path / "runs"), str(study.root))
    other.write_text(text)
    before = tree_snapshot(study.root)  # other test files share these runs
    r = run_cli("study", str(other), "--quiet")
    assert r.returncode == 2
    assert "not the run" in r.stderr and "engine differ" in r.stderr
    assert tree_snapshot(study.root) == before


def test_a_missing_or_unfinished_run_stops_the_table(tmp_path):
    r = run_cli("study", str(example_study(tmp_path)), "--table")
    assert r.returncode == 2 and "not finished" in r.stderr
    assert not (tmp_path / "runs").exists()


def test_the_example_can_be_copied_elsewhere(tmp_path):
    """Paths are the working directory's: the study's files go under root."""
    shutil.copy(EXAMPLE, tmp_path / "e.toml")
    study = load_study(tmp_path / "e.toml")
    assert study.root == Path("runs/studies/example") and study.out == study.root


def test_on_ray_the_runs_are_the_same_bit_for_bit(finished_study, local_ray, tmp_path):
    path, _, _ = finished_study
    mine = example_study(tmp_path, **{'seeds = "0-4"': 'seeds = "2"'})
    r = run_cli("study", str(mine), "--quiet", "--backend", "ray", "--actors", "2")
    assert r.returncode == 0, r.stderr
    for arm in ("rcga", "random"):
        assert_same_run(
            load_study(mine).arms[arm].run_dir(2), load_study(path).arms[arm].run_dir(2)
        )


DEBRIS = """seeds = "0-2"
[defaults]
behaviour = "kick"
generations = 1
optimizer = { population = 4 }
scene = { kind = "debris", seed = 1000, terrains = 3 }
[evaluation]
terrain_seeds = "100-101"
[arms.a]
terrain_stride = 3
"""


def test_each_seed_trains_on_its_own_terrains(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(DEBRIS)
    study = load_study(path)
    firsts = [study.arms["a"].config(s).scene.scene.seed for s in study.seeds]
    assert firsts == [1000, 1003, 1006]
    assert study.arms["a"].config(2).scene.count == 3


@pytest.mark.parametrize(
    "change, message",
    [
        (("terrain_stride = 3", "terrain_stride = 2"), "would overlap"),
        (("terrain_stride = 3", "terrain_stride = -1"), "integer >= 0"),
        (('"100-101"', '"1003-1004"'), "evaluation terrain 1003 is a training"),
        (("seed = 1000, ", ""), "evaluation terrain 100"),
    ],
)
def test_training_terrains_are_checked(tmp_path, change, message):
    path = tmp_path / "s.toml"
    text = DEBRIS.replace(*change)
    if "seed = 1000" not in text:  # terrains from 0 + 3 s: seed 2 has 6-8
        text = text.replace('"100-101"', '"7-8"')
        message = "evaluation terrain 7 is a training terrain of arm 'a', seed 2"
    path.write_text(text)
    r = run_cli("study", str(path), "--status")
    assert r.returncode == 2 and message in r.stderr, r.stderr


def test_a_terrain_stride_on_the_flat_floor_is_refused(tmp_path):
    # the flat scene has no seed: this was an AttributeError (exit 1)
    path = tmp_path / "s.toml"
    text = DEBRIS.replace('scene = { kind = "debris", seed = 1000, terrains = 3 }', "")
    assert "debris" not in text
    path.write_text(text)
    r = run_cli("study", str(path), "--status")
    assert r.returncode == 2, r.stderr
    assert "terrain_stride: the flat scene has no terrains to choose from" in r.stderr


def test_a_study_file_that_is_not_a_file(tmp_path):
    for path, message in ((tmp_path / "none.toml", "no such study file"),
                          (tmp_path, "a study file is a .toml file")):  # fmt: skip
        r = run_cli("study", str(path), "--status")
        assert r.returncode == 2 and message in r.stderr
    (tmp_path / "dir.toml").mkdir()
    r = run_cli("study", str(tmp_path / "dir.toml"), "--status")
    assert r.returncode == 2 and "not a regular file" in r.stderr
