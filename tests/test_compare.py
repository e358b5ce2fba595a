"""``locustjump compare``: runs grouped by a config key, as samples."""

import shutil
from pathlib import Path

import numpy as np
import pytest

from helpers import exit_status
from locustjump import rundir
from locustjump.evo import params_class
from locustjump.present.compare import Group, load_groups, table
from locustjump.present.ranktests import mann_whitney
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
    lines = table(groups, "rcga").splitlines()
    assert lines[0] == (
        "| group | runs | evaluations per run | best fitness: median [q1, q3] | "
        "range | HL shift vs rcga [95 % CI] | Mann–Whitney p | verdict |"
    )
    assert lines[2].endswith("| - | - | reference |")
    # 3 runs against 3: no 95 % interval exists, and the verdict says so
    shift = float(np.median(np.subtract.outer(groups[1].best, groups[0].best)))
    assert lines[3].startswith("| random | 3 |") and lines[3].endswith(
        f"| {shift:.4g} (no interval) | {p:.3g} | no evidence either way: too few "
        "runs for a 95 % interval (3 and 3) |"
    )
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


def _group(label: str, best) -> Group:
    best = np.asarray(best, dtype=float)
    runs = tuple(Path(f"{label}-{i}") for i in range(best.size))
    return Group(label, runs, best, np.full(best.size, 100), ())


def test_table_states_the_interval_and_the_verdict():
    base = np.array([10.0, 11, 12, 13, 14, 15, 16, 17])
    groups = [_group("rcga", base), _group("cma", base + 20),
              _group("random", base - 20), _group("sbx", base + 0.1),
              _group("lone", [12.0])]  # fmt: skip
    lines = table(groups, margin=5).splitlines()
    assert lines[0].endswith(
        "| HL shift vs rcga [95 % CI] | Mann–Whitney p | TOST p vs ±5 | "
        "seeds for 80 % power | verdict |"
    )
    assert lines[1].count("---") == 10
    assert lines[2].endswith("| - | - | - | - | reference |")
    # 8 vs 8: k = 14 (P(U <= 13) = 321/12870 = 0.0249 < 0.025 <= P(U <= 14)
    # = 0.0325), the interval [D(14), D(51)] of the 64 differences 20 + t,
    # t = i - j (i, j = 0..7), 8 - |t| times each: D(11..15) = 17, D(50..54)
    # = 23. TOST p 1 (20 is far outside +-5); the seeds per arm from the
    # pooled sd 2.449: 2 * 7.849 * 6 / 25 / 0.955 = 3.95, + 0.960 -> 5
    assert lines[3].endswith(
        "| 20 [17, 23] | 0.000155 | 1 | 5 | cma better than rcga |"
    )
    assert "| -20 [-23, -17] |" in lines[4] and lines[4].endswith(
        "| rcga better than random |"
    )
    # identical but for 0.1: within +-5, though 0.1 [-2.9, 3.1] at 95 %
    assert lines[5].endswith(
        "| 0.1 [-2.9, 3.1] | 0.721 | 0.00233 | 5 | equivalent within ±5 |"
    )
    assert lines[6].endswith("| - | - | - | - | no test: a group of one run |")
    assert "TOST" not in table(groups)  # without a margin, no such columns


def test_margin_on_the_command_line(runs, capsys):
    dirs = [*map(str, runs["rcga"] + runs["random"])]
    assert exit_status(["compare", *dirs, "--margin", "2.5"]) == 0
    out = capsys.readouterr().out
    assert "| TOST p vs ±2.5 | seeds for 80 % power | verdict |" in out
    for bad in ("0", "-1", "nan", "inf", "wide"):
        assert exit_status(["compare", *dirs, "--margin", bad]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "--margin must be" in err, bad


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


def test_runs_of_several_scenes_only_by_scene(runs, tmp_path, capsys):
    """A debris run and a flat run were pooled into one sample."""
    from locustjump.sim.scene import Terrains, scene_class

    debris = [tmp_path / f"debris-{s}" for s in (0, 1)]
    for seed, d in enumerate(debris):  # each on its own terrains: one scene
        scene = Terrains(scene_class("debris")(seed=1000 + 4 * seed))
        train(TrainConfig("kick", seed, 1, params_class("rcga")(population=4),
                          scene=scene), d, progress=False)  # fmt: skip
    assert len(load_groups(debris)[0].runs) == 2
    assert exit_status(["compare", str(runs["rcga"][0]), *map(str, debris)]) == 2
    err = capsys.readouterr().err
    assert "the runs trained in several scenes (debris, flat)" in err, err
    groups = load_groups([runs["rcga"][0], *debris], by="scene")
    assert [(g.label, len(g.runs)) for g in groups] == [("flat", 1), ("debris", 2)]


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


def test_total_budget_counts_a_repertoires_run_once(tmp_path, monkeypatch):
    """A switcher over 8 elites of one kick archive: the archive's run is
    spent once, not once per elite (the study table's count)."""
    study = ROOT / "results" / "study"
    src = tmp_path / "runs" / "studies" / "repertoire-composition"
    for arm in ("kick-repertoire", "getup", "return-legs"):
        shutil.copytree(study / f"repertoire-{arm}-s0", src / arm / "seed-0")
    monkeypatch.chdir(tmp_path)  # where frozen.npz says they came from
    run = study / "repertoire-s0"
    simples = sum(_evaluations(src / a / "seed-0")
                  for a in ("kick-repertoire", "getup", "return-legs"))  # fmt: skip
    (total,) = load_groups([run], "behaviour", total_budget=True)
    assert total.evaluations[0] == _evaluations(run) + simples
