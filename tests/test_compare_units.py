"""``present/compare.py`` function by function: each group's label, the
table's every cell and line, when a pair gets no test, the frozen runs a
total budget counts, and each refusal's exact words. (``tests/test_compare.py``
tries them through the command, on runs of both kinds.)"""

import shutil
from pathlib import Path

import numpy as np
import pytest

from helpers import user_error
from locustjump import rundir
from locustjump.evo import params_class
from locustjump.present.compare import (
    BUDGET_TOLERANCE,
    KEYS,
    Group,
    budget_note,
    frozen_evaluations,
    load_groups,
    optimizer_label,
    scene_label,
    table,
)
from locustjump.ranges import SettingValueError
from locustjump.rundir.config import TrainConfig
from locustjump.runs.trainer import train
from locustjump.sim.scene import Debris, Flat, Terrains

ROOT = Path(__file__).resolve().parent.parent
DEBRIS = ROOT / "results" / "debris" / "long-seed0"


@pytest.fixture(scope="module")
def kicks(tmp_path_factory) -> list[Path]:
    """Two kick runs of one generation, on two engines."""
    root = tmp_path_factory.mktemp("kicks")
    out = []
    for seed, engine in ((0, "numba"), (1, "numpy")):
        d = root / f"kick-{seed}"
        cfg = TrainConfig("kick", seed, 1, params_class("rcga")(population=4),
                          engine=engine)  # fmt: skip
        train(cfg, d, progress=False)
        out.append(d)
    return out


def group(label: str, best, evaluations=100) -> Group:
    best = np.asarray(best, dtype=float)
    runs = tuple(Path(f"{label}-{i}") for i in range(best.size))
    evals = np.broadcast_to(np.asarray(evaluations), best.shape).copy()
    return Group(label, runs, best, evals, ())


def test_groups_by_engine_keep_their_runs_in_order(kicks):
    groups = load_groups(kicks, "engine")
    assert [(g.label, g.runs) for g in groups] == [("numba", (kicks[0],)),
                                                   ("numpy", (kicks[1],))]  # fmt: skip
    (both,) = load_groups(kicks[::-1], "behaviour")
    assert both.runs == tuple(kicks[::-1])
    assert [g.label for g in load_groups(kicks, "seed")] == ["0", "1"]
    assert KEYS == ("optimizer", "engine", "behaviour", "seed", "scene")


def test_what_load_groups_refuses(kicks, tmp_path):
    assert user_error(load_groups, kicks, "colour") == (
        "by 'colour': choose from optimizer, engine, behaviour, seed, scene, or "
        "several joined by commas"
    )
    assert user_error(load_groups, []) == "compare needs at least one run directory"
    empty = tmp_path / "empty"
    shutil.copytree(kicks[0], empty)
    header = (empty / rundir.METRICS).read_text().splitlines()[0]
    (empty / rundir.METRICS).write_text(header + "\n")
    assert user_error(load_groups, [empty]) == (
        f"{empty / rundir.METRICS}: holds no generation yet"
    )
    legs = tmp_path / "legs"
    train(TrainConfig("return-legs", 0, 1, params_class("rcga")(population=4)),
          legs, progress=False)  # fmt: skip
    assert user_error(load_groups, [kicks[0], legs]) == (
        "the runs are of several behaviours (kick, return-legs); compare runs of one"
    )
    flat, debris = Terrains(Flat()), Terrains(Debris(seed=3))
    rough = tmp_path / "rough"
    train(TrainConfig("kick", 0, 1, params_class("rcga")(population=4),
                      scene=debris), rough, progress=False)  # fmt: skip
    assert scene_label(flat) == "flat"
    assert user_error(load_groups, [kicks[0], rough]) == (
        "the runs trained in several scenes (debris, flat): their fitness is not "
        "one sample; compare runs of one, or group them with by scene"
    )


def test_labels_name_each_setting_that_differs():
    rcga = params_class("rcga")
    assert optimizer_label(rcga(crossover="sbx", elite=3)) == (
        "rcga(elite=3, crossover=sbx)"
    )
    assert scene_label(Terrains(Debris(seed=9))) == "debris"  # the seed is not one
    assert scene_label(Terrains(Debris(friction=0.5, spacing=0.3), count=2,
                                aggregate="min")) == (
        "debris(spacing=0.3, friction=0.5) min"
    )  # fmt: skip
    assert (
        scene_label(Terrains(Debris(friction=0.5), count=2)) == "debris(friction=0.5)"
    )


def test_every_line_of_a_table_without_a_margin():
    lines = table([group("a", [1.0, 2.0]), group("b", [2.0, 3.0], [1000, 1200])]).split(
        "\n"
    )
    assert lines[1] == "| --- " * 8 + "|"
    assert lines[2] == "| a | 2 | 100 | 1.5 [1.25, 1.75] | 1 - 2 | - | - | reference |"
    assert lines[3].startswith("| b | 2 | 1,000-1,200 | 2.5 [2.25, 2.75] | 2 - 3 | 1 ")
    assert "no test" not in lines[3]  # two runs a side are enough for a test


def test_when_a_pair_gets_no_test():
    lines = table([group("a", [1.0, 2.0, 3.0]), group("b", [1.0, np.inf, 2.0]),
                   group("c", [1.0]), group("d", [1.0, 1.0, 1.0])],
                  margin=1).split("\n")  # fmt: skip
    assert lines[3].endswith(
        "| - | - | - | - | no test: a best fitness is not finite |"
    )
    assert lines[4].endswith("| - | - | - | - | no test: a group of one run |")
    assert lines[5].split(" | ")[-2] == "10"  # seeds for 80 % power
    # no spread on either side: no seeds for power can be said
    flat = table([group("a", [1.0, 1.0, 1.0]), group("d", [1.0, 1.0, 1.0])], margin=1)
    assert flat.split("\n")[3].split(" | ")[-2] == "-"
    ref_inf = table([group("a", [1.0, np.nan]), group("b", [1.0, 2.0])]).split("\n")
    assert ref_inf[3].endswith("| - | - | no test: a best fitness is not finite |")


def test_a_margin_is_checked_by_its_name():
    with pytest.raises(SettingValueError) as e:
        table([group("a", [1.0, 2.0])], margin=-1)
    assert str(e.value) == "margin must be a finite number > 0, got -1"


def test_a_total_budget_names_the_run_it_cannot_find(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # the frozen.npz's sources are not here
    lone = tmp_path / "lone" / "composed"
    shutil.copytree(DEBRIS / "composed", lone)
    cfg = rundir.load_config(lone / rundir.CONFIG)
    frozen = rundir.frozen_of(cfg, lone)
    source, digest = frozen.sources[0], frozen.hashes[0]
    assert user_error(frozen_evaluations, lone, cfg) == (
        f"{lone}: total_budget=True needs the kick run it builds on (config hash "
        f"{digest}), neither at {source} nor at {lone.parent / 'kick'}"
    )
    monolithic = rundir.load_config(DEBRIS / "monolithic" / rundir.CONFIG)
    assert frozen_evaluations(DEBRIS / "monolithic", monolithic) == 0


def test_the_budget_counts_the_frozen_runs_only_when_asked(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (alone,) = load_groups([DEBRIS / "composed"])
    metrics = rundir.read_metrics(DEBRIS / "composed" / rundir.METRICS)
    assert alone.evaluations[0] == int(metrics["evaluations"].sum())


def test_the_budget_note_flags_runs_of_unequal_budgets():
    """Beyond 2 % apart (the study table's rule), largest over smallest run."""
    same = [group("a", [1.0, 2.0], [1000, 1019]), group("b", [1.0, 2.0], 1010)]
    assert budget_note(same) == "In genome evaluations: largest / smallest run 1.02."
    assert BUDGET_TOLERANCE == 0.02
    apart = [group("a", [1.0, 2.0], 1000), group("b", [1.0, 2.0], [1000, 1021])]
    assert budget_note(apart) == (
        "In genome evaluations: largest / smallest run 1.02 — **not equal**: the "
        "runs are not compared at equal budget."
    )
    assert budget_note([group("a", [1.0], 0), group("b", [1.0], 5)]).startswith(
        "In genome evaluations: largest / smallest run inf — **not equal**"
    )
