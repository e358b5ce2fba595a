"""The shipped study files: each valid, each tabled one naming its shipped
runs, its table made again from its shipped scores, and those scores what
the runs score when simulated again."""

import json
from pathlib import Path

import pytest

from locustjump import rundir
from locustjump.runs.study import check_run
from locustjump.runs.study_table import TABLE_JSON, TABLE_MD
from locustjump.runs.studyfile import load_study

REPO = Path(__file__).resolve().parents[1]
EXAMPLE = REPO / "studies" / "example.toml"
SHIPPED = sorted(p for p in (REPO / "studies").glob("*.toml") if p != EXAMPLE)
TABLED = sorted(
    p for p in SHIPPED if (REPO / "results" / "studies" / p.stem / TABLE_MD).is_file()
)


@pytest.mark.parametrize("path", TABLED, ids=lambda p: p.stem)
def test_the_shipped_study_files_name_the_shipped_runs(path, monkeypatch):
    """Every run a shipped study file declares is there, finished, with the
    configuration the file declares and built on the runs it names."""
    monkeypatch.chdir(REPO)
    study = load_study(path.relative_to(REPO))
    for arm, seed in study.runs():
        assert (arm.run_dir(seed) / rundir.BEST).is_file(), arm.run_dir(seed)
        check_run(study, arm, seed)


@pytest.mark.parametrize("path", TABLED, ids=lambda p: p.stem)
def test_the_shipped_tables_are_made_from_the_shipped_scores(path, monkeypatch):
    """`study FILE --table` on the shipped runs gives the shipped table: every
    score is in results/studies/NAME/scores.json (nothing is re-simulated)."""
    import locustjump.runs.study_table as st

    monkeypatch.chdir(REPO)
    study = load_study(path.relative_to(REPO))

    def no_simulation(*args, **kwargs):
        raise AssertionError(f"{path.stem}: a score is missing from the cache")

    monkeypatch.setattr(st, "score_run", no_simulation)
    md, data = st.make_table(study, st.run_rows(study, st.scores(study)))
    assert md == (study.out / TABLE_MD).read_text()
    assert json.loads(json.dumps(data)) == json.loads(
        (study.out / TABLE_JSON).read_text()
    )


@pytest.mark.parametrize(
    "name, arm, seed, terrain",
    [
        ("optimizers-kick", "cma", 3, None),
        ("debris-composition-5seeds", "pipeline", 1, 0),
    ],
)
def test_the_shipped_scores_are_what_the_runs_score(
    name, arm, seed, terrain, monkeypatch
):
    """A cached score re-simulated (one run, one terrain, as trained)."""
    from locustjump.present.episodes import score_run
    from locustjump.runs.study_table import SCORES, _key

    monkeypatch.chdir(REPO)
    study = load_study(Path("studies") / f"{name}.toml")
    sub = study.evaluation.substeps[0]
    path = study.arms[arm].run_dir(seed)
    cache = json.loads((study.out / SCORES).read_text())
    cached = cache[_key(path, sub, study.evaluation.terrain_seeds)]
    seeds = study.evaluation.terrain_seeds
    (fresh,) = score_run(path, terrain_seeds=None if seeds is None else seeds[:1],
                         substeps=sub)  # fmt: skip
    assert fresh.to_dict() == cached[0 if terrain is None else terrain]


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: p.stem)
def test_every_study_file_is_valid(path, monkeypatch):
    """Studies still training (their runs not shipped) are valid files too."""
    monkeypatch.chdir(REPO)
    study = load_study(path.relative_to(REPO))
    assert study.scored and study.seeds


def test_the_plan_counts_what_a_generation_and_a_score_simulate(monkeypatch):
    """A run evolved on the worst of 3 and 6 substeps simulates each genome
    twice: the plan's control steps a generation are what its first
    generation logged (all 50 genomes evaluated); scored on its own scene
    at given substeps, once per resolution."""
    from locustjump.runs.study import states

    monkeypatch.chdir(REPO)
    study = load_study("studies/composed-robust.toml")
    robust = [st for st in states(study) if st.arm == "apex-robust6-p10"]
    m = rundir.read_metrics(robust[0].path / rundir.METRICS)
    assert robust[0].steps_per_generation == m["control_steps"][0] == 2 * 50 * 3000
    assert robust[0].eval_steps == 3 * 3000  # 3, 6 and 12 substeps, one episode
