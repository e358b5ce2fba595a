"""scripts/ship_study.py: a finished study's runs copied into results/ (no
checkpoints), each atomically; an unfinished or conflicting study refused
before anything is written. scripts/cross_check.py: the first generations of
a study's finished runs retrained and compared to the last digit."""

import importlib.util
import re
import shutil
from pathlib import Path

import pytest

from helpers import run_cli, tree_snapshot
from locustjump import rundir
from locustjump.runs.studyfile import load_study

REPO = Path(__file__).resolve().parents[1]
EXAMPLE = REPO / "studies" / "example.toml"
_spec = importlib.util.spec_from_file_location(
    "ship_study", REPO / "scripts" / "ship_study.py"
)
ship_study = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(ship_study)
_spec = importlib.util.spec_from_file_location(
    "cross_check", REPO / "scripts" / "cross_check.py"
)
cross_check = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(cross_check)


def _study(tmp: Path, name: str, seeds: str = "0-1") -> Path:
    text = EXAMPLE.read_text()
    text = text.replace('root = "runs/studies/example"', f'root = "{tmp / "runs"}"')
    path = tmp / f"{name}.toml"
    path.write_text(text.replace('seeds = "0-4"', f'seeds = "{seeds}"'))
    return path


@pytest.fixture(scope="module")
def trained(tmp_path_factory) -> Path:
    tmp = tmp_path_factory.mktemp("ship")
    path = _study(tmp, "s")
    r = run_cli("study", str(path), "--quiet", "--threads", "2")
    assert r.returncode == 0, r.stderr
    return path


def test_a_finished_study_ships_its_runs_and_names_them(trained, tmp_path, capsys):
    to = tmp_path / "results"
    assert ship_study.main([str(trained), "--to", str(to), "--prefix", "ex"]) == 0
    study = load_study(trained)
    for arm, seed in study.runs():
        dest = to / f"ex-{arm.name}-s{seed}"
        assert sorted(p.name for p in dest.iterdir()) == [
            "best.npz", "config.toml", "metrics.csv"]  # fmt: skip
        for f in ("best.npz", "metrics.csv", "config.toml"):
            assert (dest / f).read_bytes() == (arm.run_dir(seed) / f).read_bytes()
    assert not list(to.glob(".*"))  # no temporary directory left
    out = capsys.readouterr().out
    assert "shipped 4 runs" in out
    # the printed path lines make the study name its shipped runs
    text = trained.read_text()
    for name, path in re.findall(r'\[arms\.(\S+)\]\npath = "(.+)"', out):
        text = text.replace(f"[arms.{name}]\n", f'[arms.{name}]\npath = "{path}"\n')
    named = tmp_path / "named.toml"
    named.write_text(text)
    for arm, seed in load_study(named).runs():
        assert arm.run_dir(seed) == to / f"ex-{arm.name}-s{seed}"
    # shipping again copies nothing: the same runs are there
    before = tree_snapshot(to)
    assert ship_study.main([str(trained), "--to", str(to), "--prefix", "ex"]) == 0
    assert ship_study.main([str(named), "--to", str(to), "--prefix", "ex"]) == 0
    assert tree_snapshot(to) == before


def test_an_unfinished_study_is_refused_and_nothing_is_written(
    trained, tmp_path, capsys
):
    """Seed 2 has no runs yet: one line, exit 2, no destination made."""
    wider = trained.parent / "wider.toml"
    wider.write_text(trained.read_text().replace('seeds = "0-1"', 'seeds = "0-2"'))
    to = tmp_path / "results"
    assert ship_study.main([str(wider), "--to", str(to), "--prefix", "ex"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "0 of 4 generations" in err
    assert not to.exists()


def test_a_study_still_training_ships_its_finished_runs_and_continues(
    trained, tmp_path, capsys
):
    """--finished: seed 2 has no runs yet and is left; the printed ``paths``
    lines name the shipped seeds, and the study so named trains only seed 2,
    never writing into what was shipped (a study moved to another machine)."""
    runs = tmp_path / "runs"
    shutil.copytree(trained.parent / "runs", runs)
    wider = tmp_path / "wider.toml"
    wider.write_text(
        trained.read_text()
        .replace('seeds = "0-1"', 'seeds = "0-2"')
        .replace(str(trained.parent / "runs"), str(runs))
    )
    to = tmp_path / "results"
    args = [str(wider), "--to", str(to), "--prefix", "ex", "--finished"]
    assert ship_study.main(args) == 0
    out = capsys.readouterr().out
    assert "shipped 4 runs" in out
    assert sorted(p.name for p in to.iterdir()) == [
        "ex-random-s0", "ex-random-s1", "ex-rcga-s0", "ex-rcga-s1"]  # fmt: skip
    lines = re.findall(r"\[arms\.(\S+)\]\npaths = (\{.+\})", out)
    assert [n for n, _ in lines] == ["rcga", "random"]
    text = wider.read_text()
    for name, paths in lines:
        text = text.replace(f"[arms.{name}]\n", f"[arms.{name}]\npaths = {paths}\n")
    named = tmp_path / "named.toml"
    named.write_text(text)
    study = load_study(named)
    for arm, seed in study.runs():
        want = to / f"ex-{arm.name}-s{seed}" if seed < 2 else None
        assert arm.run_dir(seed) == (want or runs / arm.name / "seed-2")
    before = tree_snapshot(to)
    r = run_cli("study", str(named), "--quiet", "--threads", "2")
    assert r.returncode == 0, r.stderr
    assert "2 to train" in r.stdout + r.stderr
    assert tree_snapshot(to) == before
    # shipped again, the finished study's paths name all three seeds
    assert ship_study.main(args) == 0
    out = capsys.readouterr().out
    assert '"2" = "' in out and out.count('"0" = "') == 2


def test_another_run_under_the_same_name_is_refused(trained, tmp_path, capsys):
    to = tmp_path / "results"
    study = load_study(trained)
    arm = study.arms["random"]
    other = to / "ex-rcga-s1"  # holds random's run, not rcga's
    other.mkdir(parents=True)
    for f in (rundir.BEST, rundir.METRICS):
        (other / f).write_bytes((arm.run_dir(1) / f).read_bytes())
    before = tree_snapshot(to)
    assert ship_study.main([str(trained), "--to", str(to), "--prefix", "ex"]) == 2
    assert "holds another run" in capsys.readouterr().err
    assert tree_snapshot(to) == before


def test_cross_check_retrains_the_first_generations(trained, tmp_path, capsys):
    assert cross_check.main([str(trained), "--seed", "1", "--generations", "2"]) == 0
    out = capsys.readouterr().out
    assert out.count("SAME") == 2 and "rcga, seed 1, 2 generation(s): SAME" in out
    # a run whose second generation reads otherwise is named
    copy = tmp_path / "copy.toml"
    study = load_study(trained)
    moved = tmp_path / "rcga-1"
    shutil.copytree(study.arms["rcga"].run_dir(1), moved)
    lines = (moved / rundir.METRICS).read_text().splitlines(keepends=True)
    cells = lines[2].split(",")
    cells[2] = repr(float(cells[2]) + 1e-12)  # the mean, off in its last digits
    lines[2] = ",".join(cells)
    (moved / rundir.METRICS).write_text("".join(lines))
    copy.write_text(trained.read_text().replace(
        "[arms.rcga]\n", f'[arms.rcga]\npaths = {{ "1" = "{moved}" }}\n'))  # fmt: skip
    assert cross_check.main([str(copy), "--seed", "1", "--generations", "2"]) == 1
    out = capsys.readouterr().out
    assert "rcga, seed 1, 2 generation(s): DIFFERENT" in out
    assert "random, seed 1, 2 generation(s): SAME" in out
    # a seed without finished runs: one line, exit 2
    assert cross_check.main([str(trained), "--seed", "3"]) == 2
    assert "seed 3 is not one of the study's" in capsys.readouterr().err
