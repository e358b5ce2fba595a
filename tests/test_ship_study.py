"""scripts/ship_study.py: a finished study's runs copied into results/ (no
checkpoints), each atomically; an unfinished or conflicting study refused
before anything is written. scripts/cross_check.py: the first generations of
a study's finished runs retrained and compared to the last digit."""

import importlib.util
import re
import shutil
import subprocess
import tarfile
from pathlib import Path

import pytest

from helpers import held_lock, run_cli, tree_snapshot
from locustjump import rundir
from locustjump.runs.studyfile import load_study
from locustjump.runs.trainer import train

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


def test_a_study_banked_on_one_machine_continues_on_another(
    trained, tmp_path, monkeypatch, capsys
):
    """--finished --update-file --carry, as at the end of a session on a
    machine that may be lost: the finished runs shipped and named in the
    study file (nothing else in it changed), rcga's seed 2, stopped after 2
    of 4 generations, packed with its checkpoint; on a machine with only the
    checkout and the archive, the study continues it from generation 2 and
    trains random's seed 2. Refused, with nothing written, while a process
    trains a run it would pack. The rcga arm's own ``path`` stays (its seed
    2 trains there), and so do the file's CRLF line ends."""
    monkeypatch.chdir(tmp_path)
    shutil.copytree(trained.parent / "runs", "runs")
    Path("runs/mine").mkdir()
    for s in (0, 1):
        shutil.move(f"runs/rcga/seed-{s}", f"runs/mine/rcga-{s}")
    text = (
        trained.read_text()
        .replace('seeds = "0-1"', 'seeds = "0-2"')
        .replace(str(trained.parent / "runs"), "runs")
        .replace("[arms.random]\n", "[arms.random]  # the baseline\n")
        .replace("[arms.rcga]\n", '[arms.rcga]\npath = "runs/mine/rcga-{seed}"\n')
        .replace("\n", "\r\n")
    )
    Path("s.toml").write_bytes(text.encode())
    arm = load_study("s.toml").arms["rcga"]
    train(arm.config(2), arm.run_dir(2), progress=False, stop_after=2)
    stopped = (arm.run_dir(2) / rundir.METRICS).read_text()
    args = ["s.toml", "--to", "results", "--prefix", "ex", "--finished",
            "--update-file", "--carry", "carry/s.tar.gz"]  # fmt: skip
    holder = held_lock(arm.run_dir(2))
    try:
        before = tree_snapshot(tmp_path)
        assert ship_study.main(args) == 2
    finally:
        holder.kill()
        holder.wait()
    err = capsys.readouterr().err
    assert f"in use by process {holder.pid}" in err and len(err.splitlines()) == 1
    assert "stop the study's workers first" in err
    assert tree_snapshot(tmp_path) == before
    assert ship_study.main(args) == 0
    out = capsys.readouterr().out
    assert "shipped 4 runs to results; s.toml names them" in out
    assert "packed 1 unfinished runs into carry/s.tar.gz" in out
    named = Path("s.toml").read_bytes().decode()
    assert re.sub(r"paths = .*\r\n", "", named) == text
    assert 'paths = { "0" = "results/ex-rcga-s0", "1" = "results/ex-rcga-s1" }' in named
    assert load_study("s.toml").arms["rcga"].run_dir(2) == Path("runs/mine/rcga-2")
    with tarfile.open("carry/s.tar.gz") as tf:
        assert sorted(tf.getnames()) == sorted(
            ["runs/mine/rcga-2"] + [f"runs/mine/rcga-2/{p.name}"
                                    for p in arm.run_dir(2).iterdir()
                                    if p.name != rundir.FITNESS_PNG])  # fmt: skip
    assert (arm.run_dir(2) / rundir.FITNESS_PNG).is_file()  # drawn again
    assert (arm.run_dir(2) / rundir.CHECKPOINT).is_file()
    # another machine: the checkout (study file, results/) and the archive
    shutil.rmtree("runs")
    subprocess.run(["tar", "xzf", "carry/s.tar.gz", "--skip-old-files"], check=True)
    r = run_cli("study", "s.toml", "--quiet", "--threads", "2")
    assert r.returncode == 0, r.stderr
    assert "4 of 6 runs done, 2 to train" in r.stdout + r.stderr
    metrics = (arm.run_dir(2) / rundir.METRICS).read_text()
    assert metrics.startswith(stopped) and len(metrics.splitlines()) == 5
    assert not Path("runs/mine/rcga-0").exists()  # the shipped runs counted
    # banked again at the end: each arm's paths line replaced, not repeated
    assert ship_study.main(args) == 0
    assert "packed 0 unfinished runs" in capsys.readouterr().out
    named = Path("s.toml").read_bytes().decode()
    assert re.sub(r"paths = .*\r\n", "", named) == text
    assert named.count("paths = ") == 2 and '"2" = "results/ex-random-s2" }' in named


def test_a_finished_study_file_names_every_shipped_run(trained, tmp_path, capsys):
    """--update-file on a finished study: an arm's path template, and the
    seed a ``paths`` line named elsewhere shipped beside the others, its line
    gone: the file names every run where it is shipped."""
    rcga = load_study(trained).arms["rcga"]
    moved = tmp_path / "rcga-1"
    shutil.copytree(rcga.run_dir(1), moved)
    f = tmp_path / "f.toml"
    f.write_text(trained.read_text().replace(
        "[arms.rcga]\n", f'[arms.rcga]\npaths = {{ "1" = "{moved}" }}\n'))  # fmt: skip
    to = tmp_path / "results"
    args = [str(f), "--to", str(to), "--prefix", "ex", "--update-file"]
    assert ship_study.main(args) == 0
    assert f"shipped 4 runs to {to}; {f} names them" in capsys.readouterr().out
    assert "paths" not in f.read_text()
    for arm, seed in load_study(f).runs():
        assert arm.run_dir(seed) == to / f"ex-{arm.name}-s{seed}"
        assert (arm.run_dir(seed) / rundir.BEST).is_file()


def test_a_study_file_it_cannot_update_is_refused_before_anything_is_shipped(
    trained, tmp_path, capsys
):
    """An arm's table it cannot find (``[arms."rcga"]``, valid TOML): one
    line, exit 2, nothing shipped, the file as it was."""
    quoted = tmp_path / "quoted.toml"
    quoted.write_text(trained.read_text().replace("[arms.rcga]", '[arms."rcga"]'))
    before = tree_snapshot(tmp_path)
    args = [str(quoted), "--to", str(tmp_path / "results"), "--prefix", "ex",
            "--finished", "--update-file"]  # fmt: skip
    assert ship_study.main(args) == 2
    err = capsys.readouterr().err
    assert "no [arms.rcga] table" in err and len(err.splitlines()) == 1
    assert tree_snapshot(tmp_path) == before


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
