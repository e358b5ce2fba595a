"""The runs shipped in results/ — the study's (issue #20, docs/science.md), the
debris study's (issue #30: results/debris/, and results/debris-open/ from the
open field before the walls) and every stage of the shipped reproductions:
every best genome re-simulates to its recorded fitness, bit for bit, on the
engine path its config.toml names."""

from pathlib import Path

import numpy as np
import pytest

from locustjump import rundir

RESULTS = Path(__file__).resolve().parent.parent / "results"
SHIPPED = ("*/*", "study/long/seed-*/*", "debris*/*-seed*/*")
RUNS = sorted(d for p in SHIPPED for d in RESULTS.glob(p) if rundir.is_run(d))


@pytest.mark.parametrize("run", RUNS, ids=[str(d.relative_to(RESULTS)) for d in RUNS])
def test_shipped_run_replays(run):
    cfg, beh, best = rundir.load_run(run)
    fitness, _ = beh.evaluate(best.genome[None], cfg.model, engine=cfg.engine)
    assert fitness[0] == best.fitness
    m = rundir.read_metrics(run / rundir.METRICS)
    assert len(m["best"]) == cfg.generations
    assert np.max(m["best"]) == best.fitness


def test_study_substeps_script_rescores_a_run_at_each_resolution(capsys):
    """scripts/study_substeps.py: its 3-substep column is the run's own
    fitness, the finer ones re-simulate, and the rank test needs its group."""
    import importlib.util

    path = RESULTS.parent / "scripts" / "study_substeps.py"
    spec = importlib.util.spec_from_file_location("study_substeps", path)
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    run = RESULTS / "quick-seed0" / "getup"
    _, _, best = rundir.load_run(run)
    assert script.main([str(run), "--runs", "--by", "behaviour"]) == 0
    rows = [r for r in capsys.readouterr().out.splitlines() if r.startswith("|")]
    cells = rows[2].split("|")[2:6]  # the run's row: 3, 6, 12, 24 substeps
    assert float(cells[0]) == float(f"{best.fitness:.4g}")
    assert rows[3].startswith("| group: median [min, max] | runs |")
    one = [f" {c.strip()} [{c.strip()}, {c.strip()}] " for c in cells]
    assert rows[5].split("|")[3:7] == one  # a group of one: median = min = max
    assert script.main([str(run), "--reference", "nope"]) == 2
    assert "--reference 'nope': no such group" in capsys.readouterr().err


def test_debris_table_scores_shipped_runs_on_held_out_terrains(tmp_path, capsys):
    """scripts/debris_table.py (docs/science.md, debris): a run's held-out
    mean is its behaviour's fitness on those terrains, its training E the
    recorded one, and the flat-floor table beside it re-scores the flat
    reproductions to their recorded fitness."""
    import importlib.util
    import json

    from locustjump.sim.engine.rollout import rollout
    from locustjump.sim.scene import Debris

    path = RESULTS.parent / "scripts" / "debris_table.py"
    spec = importlib.util.spec_from_file_location("debris_table", path)
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    runs = [RESULTS / "debris-open" / f"quick-seed{s}" / "monolithic" for s in (0, 1)]
    out = tmp_path / "t.json"
    flat_run = str(RESULTS / "long-seed0")
    fig = tmp_path / "curves.png"
    argv = ["--terrain-seeds", "100", "--runs", *map(str, runs), "--flat-study",
            flat_run, "--json", str(out), "--figure", str(fig)]  # fmt: skip
    assert script.main(argv) == 0
    assert fig.read_bytes().startswith(b"\x89PNG")  # the learning curves
    got = json.loads(out.read_text())
    cfg, beh, best = rundir.load_run(runs[0])
    # held out: terrain 100 of the run's own field (the open one: no walls)
    here = beh.on(beh.terrains.scene.with_seed(100))
    assert here.scene == Debris(seed=100, wall_height=0)
    fit = here.evaluate(best.genome[None], cfg.model)[0][0]
    assert got["held_out"]["monolithic (debris)"][0] == fit
    row = next(r for r in got["table"] if str(runs[0]) in r["controller"])
    assert row["train_fitness"] == best.fitness and row["gap"] == best.fitness - fit
    # the highest the body rose above the ground under it in that episode
    res = rollout(here.controller, best.genome[None], here.start_states(cfg.model),
                  script.STEPS, model_params=cfg.model, record=("qpos",),
                  scene=here.scene)  # fmt: skip
    q = res["qpos"][0]
    ground = here.scene.heights(q[:, 0], q[:, 1], cfg.model.body_length)
    assert row["highest_m"] == (q[:, 2] - ground).max()
    flat = {s: rundir.load_run(RESULTS / "long-seed0" / s)[2].fitness
            for s in ("composed", "monolithic")}  # fmt: skip
    assert got["flat_floor"] == {f"{s} (flat floor)": [flat[s]] for s in flat}
    text = capsys.readouterr().out
    assert "| monolithic (debris) | 2 |" in text
    assert "The flat floor beside it" in text


@pytest.mark.parametrize(
    ("study", "n"),
    [
        ("debris-composition-5seeds", 5),
        ("debris-composition", 15),
        ("debris-composition-height", 5),
        ("repertoire-composition", 10),
        ("repertoire-composition-debris", 15),
    ],
)
def test_science_md_tables_are_the_shipped_studies(study, n):
    """docs/science.md's table of a study per arm (median [min, max] as
    trained and at 12 substeps) and its pairs (Hodges-Lehmann shifts with
    their intervals) are `locustjump study studies/STUDY.toml --table`'s,
    results/studies/STUDY/table.json, rounded: the doc cannot drift from the
    runs it cites."""
    import json

    doc = (RESULTS.parent / "docs" / "science.md").read_text()
    table = json.loads((RESULTS / "studies" / study / "table.json").read_text())

    def cell(x):
        return f"{x['median']:.0f} [{x['min']:.0f}, {x['max']:.0f}]"

    for arm in table["arms"].values():
        row = f"| {arm['label']} | {n} | "
        assert row in doc, arm["label"]
        line = doc[doc.index(row) :].splitlines()[0]
        assert f"| {cell(arm['3'])} | {cell(arm['12'])} |" in line, line
    for sub, pairs in table["pairs"].items():
        for c in pairs:
            text = f"{c['shift']:.0f} [{c['low']:.0f}, {c['high']:.0f}]"
            assert text.replace("-", "−") in doc, (sub, text)


def test_results_table_script_reads_todays_runs(capsys):
    """scripts/results_table.py (the README's tables) on a shipped run: its
    budget column is the run's population x generations (it read the
    configuration's 0.1 spelling, ``cfg.rcga``, and failed)."""
    import importlib.util

    path = RESULTS.parent / "scripts" / "results_table.py"
    spec = importlib.util.spec_from_file_location("results_table", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    module.main([str(RESULTS / "demo-seed0" / "kick")])
    assert "| 50 x 90/100 |" in capsys.readouterr().out


def test_a_shipped_studys_figure_draws_its_table():
    """scores.png from the flat repertoire study's table.json, as shipped:
    its first panel's first dots are the reference arm's scores."""
    import json

    from locustjump.present.study_figure import draw_scores, shift_rows

    table = RESULTS / "studies" / "repertoire-composition" / "table.json"
    data = json.loads(table.read_text())
    fig = draw_scores(data)
    assert len(fig.axes) == 3 and len(shift_rows(data)) == 4  # 2 pairs x 2 physics
    assert (
        fig.axes[0].lines[0].get_ydata().tolist()
        == (data["arms"]["repertoire"]["3"]["values"])
    )
