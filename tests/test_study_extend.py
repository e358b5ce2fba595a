"""``extends``: a study whose arms continue copies of another study's finished
runs to a longer budget, bit for bit the runs the longer budget makes from the
start; each run to extend checked before anything runs."""

import shutil
from pathlib import Path

import pytest

from helpers import assert_same_run, run_cli, tree_snapshot
from locustjump import rundir
from locustjump.runs.studyfile import load_study
from locustjump.runs.trainer import train


def _longer(finished_study, tmp_path: Path, generations: int = 6, **arm: str) -> Path:
    """A study whose arms extend the finished example's seeds 0-1."""
    src = load_study(finished_study[0])
    rcga = {"optimizer": '{ kind = "rcga" }', "extends": f'"{src.arms["rcga"].path}"'}
    rcga.update(arm)
    table = "".join(f"{k} = {v}\n" for k, v in rcga.items())
    text = f'''name = "longer"
root = "{tmp_path / "runs"}"
seeds = "0-1"
reference = "rcga"
[defaults]
behaviour = "kick"
generations = {generations}
optimizer = {{ population = 8 }}
[arms.rcga]
{table}[arms.random]
optimizer = {{ kind = "random" }}
extends = "{src.arms["random"].path}"
'''
    path = tmp_path / "longer.toml"
    path.write_text(text)
    return path


def test_a_longer_budget_continues_copies_of_finished_runs(finished_study, tmp_path):
    """``extends``: each run starts as a copy of the finished one and trains
    on; it is the run a longer budget makes from the start, bit for bit, and
    the runs it extends are left as they were."""
    longer = _longer(finished_study, tmp_path)
    study = load_study(longer)
    sources = [study.arms[a].source_dir(s) for a in ("rcga", "random") for s in (0, 1)]
    before = [(d / rundir.METRICS).read_bytes() for d in sources]
    status = run_cli("study", str(longer), "--status")
    assert status.returncode == 0, status.stderr
    assert "| rcga | 4/6 | 4/6 |" in status.stdout  # the copies will bring 4
    r = run_cli("study", str(longer), "--quiet")
    assert r.returncode == 0, r.stderr
    # 2 generations x 8 genomes x 300 steps a run: only what the copies lack
    assert "0 of 4 runs done, 4 to train (19,200 control steps)" in r.stderr
    assert [(d / rundir.METRICS).read_bytes() for d in sources] == before
    for d, old in zip(sources[:2], before[:2], strict=True):  # copied, wall times too
        assert (study.arms["rcga"].run_dir(int(d.name[-1])) / rundir.METRICS
                ).read_bytes().startswith(old)  # fmt: skip
    arm = study.arms["rcga"]
    alone = tmp_path / "alone"
    train(arm.config(1), alone, progress=False)
    assert_same_run(arm.run_dir(1), alone)
    assert not list((tmp_path / "runs" / "rcga").glob(".*"))  # no copy left over


@pytest.mark.parametrize(
    "case",
    ["missing", "no-checkpoint", "unfinished", "stopped", "not-longer", "template",
     "other-config"],
)  # fmt: skip
def test_a_run_to_extend_is_checked_before_anything_runs(
    finished_study, tmp_path, case
):
    done = load_study(finished_study[0]).arms["rcga"].run_dir(0)
    if case == "missing":
        longer = _longer(finished_study, tmp_path, extends='"nowhere/{seed}"')
        want = "extends nowhere/0: no run there"
    elif case == "no-checkpoint":
        mine = tmp_path / "mine"
        shutil.copytree(done, mine / "0")
        (mine / "0" / rundir.CHECKPOINT).unlink()
        longer = _longer(finished_study, tmp_path, extends=f'"{mine}/{{seed}}"')
        want = f"holds no {rundir.CHECKPOINT} to continue from"
    elif case == "unfinished":
        mine = tmp_path / "mine"
        cfg = load_study(_longer(finished_study, tmp_path)).arms["rcga"].config(0)
        train(cfg.replace(generations=4), mine / "0", progress=False, stop_after=1)
        longer = _longer(finished_study, tmp_path, extends=f'"{mine}/{{seed}}"')
        want = "not finished (1 of 4 generations)"
    elif case == "stopped":  # an optimizer that stopped has nothing to go on with
        mine = tmp_path / "mine"
        shutil.copytree(done, mine / "0")
        (mine / "0" / rundir.STOP).write_text("{}")
        longer = _longer(finished_study, tmp_path, extends=f'"{mine}/{{seed}}"')
        want = f"its optimizer stopped it early ({rundir.STOP})"
    elif case == "not-longer":
        longer = _longer(finished_study, tmp_path, generations=4)
        want = "it has 4 generations; the arm's 4 must be more"
    elif case == "template":
        longer = _longer(finished_study, tmp_path, extends='"x/{sed}"')
        want = "extends 'x/{sed}': the only field is {seed}"
    else:
        longer = _longer(
            finished_study, tmp_path, optimizer="{ kind = 'rcga', population = 6 }"
        )
        want = "optimizer.population differ"
    r = run_cli("study", str(longer), "--quiet")
    assert r.returncode == 2 and want in r.stderr, r.stderr
    assert len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert not (tmp_path / "runs").exists()


def test_a_copy_that_fails_leaves_nothing(finished_study, tmp_path, monkeypatch):
    """A full disk (or Ctrl-C) half-way through copying a run to extend: no
    half copy is left, under any name, and the source is untouched."""
    from locustjump.runs import study as study_mod

    study = load_study(_longer(finished_study, tmp_path))
    source = study.arms["rcga"].source_dir(0)
    before = tree_snapshot(source)
    real = shutil.copytree

    def half(src, dst, **kw):
        real(src, dst, **{**kw, "ignore": lambda d, names: names[1:]})
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(study_mod.shutil, "copytree", half)
    with pytest.raises(OSError, match="No space left"):
        study_mod.run_study(study, progress=False, log=lambda m: None)
    assert list((tmp_path / "runs" / "rcga").iterdir()) == []
    assert tree_snapshot(source) == before
