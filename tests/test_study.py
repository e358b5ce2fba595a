"""The study runs shipped in results/study (issue #20, docs/science.md): every
best genome re-simulates to its recorded fitness, bit for bit, on the engine
path its config.toml names."""

from pathlib import Path

import numpy as np
import pytest

from locustjump import rundir

STUDY = Path(__file__).resolve().parent.parent / "results" / "study"
RUNS = sorted(
    d for d in (*STUDY.glob("*"), *STUDY.glob("long/seed-*/*")) if rundir.is_run(d)
)


@pytest.mark.parametrize("run", RUNS, ids=[str(d.relative_to(STUDY)) for d in RUNS])
def test_shipped_study_run_replays(run):
    cfg, beh, best = rundir.load_run(run)
    res = beh.simulate(best.genome[None], cfg.model, record=beh.record)
    assert beh.score(best.genome[None], res, cfg.model)[0] == best.fitness
    m = rundir.read_metrics(run / rundir.METRICS)
    assert len(m["best"]) == cfg.generations
    assert np.max(m["best"]) == best.fitness
