"""``locustjump compare``: runs grouped by a config key, as samples."""

import shutil
from pathlib import Path

import numpy as np
import pytest

from helpers import exit_status
from locustjump import rundir
from locustjump.evo import params_class
from locustjump.present.compare import load_groups, mann_whitney, table
from locustjump.rundir.config import TrainConfig
from locustjump.runs.trainer import train


@pytest.fixture(scope="module")
def runs(tmp_path_factory) -> dict[str, list[Path]]:
    root = tmp_path_factory.mktemp("cmp")
    out: dict[str, list[Path]] = {}
    for kind in ("rcga", "random"):
        for seed in range(3):
            d = root / f"{kind}-{seed}"
            cfg = TrainConfig("kick", seed, 2, params_class(kind)(population=4))
            train(cfg, d, progress=False)
            out.setdefault(kind, []).append(d)
    return out


def test_groups_table_and_rank_test(runs, tmp_path, capsys):
    dirs = runs["rcga"] + runs["random"]
    groups = load_groups(dirs)
    assert [g.label for g in groups] == ["rcga", "random"]
    best = [rundir.load_run(d)[2].fitness for d in runs["random"]]
    np.testing.assert_array_equal(groups[1].best, best)
    u, p = mann_whitney(groups[1].best, groups[0].best)
    assert 0 <= u <= 9 and 0 < p <= 1
    text = table(groups, "rcga")
    assert "Mann–Whitney vs rcga" in text and f"{u:g}, {p:.3g}" in text
    fig = tmp_path / "conv.png"
    argv = ["compare", *map(str, dirs), "--reference", "rcga", "--figure", str(fig)]
    assert exit_status(argv) == 0 and fig.stat().st_size > 0
    assert "| random | 3 |" in capsys.readouterr().out
    # the figure is not overwritten without --force; bad input is one line
    before = fig.read_bytes()
    assert exit_status(argv) == 2 and fig.read_bytes() == before
    assert "--figure" in capsys.readouterr().err
    assert exit_status(["compare", str(tmp_path)]) == 2
    assert "holds no run" in capsys.readouterr().err
    assert exit_status(["compare", *map(str, dirs), "--reference", "cma"]) == 2
    assert "no such group" in capsys.readouterr().err
    # --force overwrites, with the title asked for
    assert exit_status([*argv, "--force", "--title", "getup: 3 seeds"]) == 0
    assert fig.read_bytes() != before


def test_runs_of_several_behaviours_only_by_behaviour(runs, tmp_path):
    other = tmp_path / "legs"
    train(TrainConfig("return-legs", 0, 1, params_class("rcga")(population=4)),
          other, progress=False)  # fmt: skip
    assert exit_status(["compare", str(runs["rcga"][0]), str(other)]) == 2
    groups = load_groups([runs["rcga"][0], other], by="behaviour")
    assert [g.label for g in groups] == ["kick", "return-legs"]
    groups = load_groups([runs["rcga"][0], other], by="behaviour,optimizer")
    assert [g.label for g in groups] == ["kick / rcga", "return-legs / rcga"]
    for bad in ("seed,seed", "colour", "behaviour,"):
        assert exit_status(["compare", str(other), "--by", bad]) == 2


def test_optimizer_labels_name_the_settings_that_differ():
    from locustjump.present.compare import optimizer_label

    rcga = params_class("rcga")
    assert optimizer_label(rcga(population=10)) == "rcga"
    assert optimizer_label(rcga(crossover="sbx")) == "rcga(crossover=sbx)"
    assert optimizer_label(params_class("cma")(sigma0=1.0)) == "cma(sigma0=1.0)"


ROOT = Path(__file__).resolve().parent.parent
DEBRIS = ROOT / "results" / "debris" / "long-seed0"


def _evaluations(run: Path) -> int:
    return int(rundir.read_metrics(run / rundir.METRICS)["evaluations"].sum())


def test_total_budget_counts_the_frozen_runs(tmp_path, monkeypatch, capsys):
    # the shipped debris reproduction: the composed switcher over its kick,
    # getup and return-legs, against the monolithic network at their budget
    monkeypatch.chdir(tmp_path)  # its frozen.npz's sources are not here
    simples = sum(_evaluations(DEBRIS / s) for s in ("kick", "getup", "return-legs"))
    own = _evaluations(DEBRIS / "composed")
    dirs = [DEBRIS / "composed", DEBRIS / "monolithic"]
    alone, total = (
        load_groups(dirs, "behaviour", total_budget=t) for t in (False, True)
    )
    assert alone[0].evaluations[0] == own
    assert total[0].evaluations[0] == own + simples  # found beside it
    assert total[0].curves[0][0][0] == simples + alone[0].curves[0][0][0]
    # the monolithic run builds on nothing; the two budgets agree to a generation
    assert total[1].evaluations[0] == alone[1].evaluations[0] == _evaluations(dirs[1])
    assert abs(int(total[0].evaluations[0]) - int(total[1].evaluations[0])) < 50
    np.testing.assert_array_equal(total[0].best, alone[0].best)
    # a run whose frozen runs are nowhere: one line naming the first, exit 2
    lone = tmp_path / "lone" / "composed"
    shutil.copytree(DEBRIS / "composed", lone)
    fig = tmp_path / "curves.png"
    argv = ["compare", str(lone), "--total-budget", "--figure", str(fig)]
    assert exit_status(argv) == 2 and not fig.exists()
    err = capsys.readouterr().err
    assert "needs the kick run it builds on" in err and err.count("\n") == 1
    assert exit_status(argv[:3]) == 2  # without a figure, too
    shutil.copytree(DEBRIS / "kick", lone.parent / "kick")
    err = (exit_status(argv), capsys.readouterr().err)
    assert err[0] == 2 and "getup run" in err[1] and not fig.exists()
