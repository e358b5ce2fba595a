"""Evaluation: re-simulate a run's best genome; its fitness, metrics, figures."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from locustjump import rundir
from locustjump.present.stages import Episodes, reporter_of
from locustjump.sim.engine.backends import ThreadBackend

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend


@dataclass
class Evaluation:
    behaviour: str
    fitness: float
    recorded_fitness: float
    metrics: dict[str, Any]
    files: list[Path]

    @property
    def matches(self) -> bool:
        return self.fitness == self.recorded_fitness

    def to_dict(self) -> dict[str, Any]:
        return {
            "behaviour": self.behaviour,
            "fitness": self.fitness,
            "recorded_fitness": self.recorded_fitness,
            "fitness_matches": self.matches,
            "metrics": self.metrics,
            "files": [str(f) for f in self.files],
        }


def evaluate_run(
    path: str | os.PathLike,
    *,
    backend: Backend | None = None,
    eval_dir: str | os.PathLike | None = None,
) -> Evaluation:
    """Re-simulate a run's best genome; write its trajectory CSVs and the
    behaviour's figures into ``eval_dir``, by default ``DIR/eval/`` (for a
    shipped run under ``results/``: ``runs/shipped/<same path>/eval/``,
    :func:`locustjump.rundir.derived_dir`).

    ``eval/`` holds derived files only: they are rewritten on every call.
    """
    if backend is None:
        backend = ThreadBackend()
    out = Path(path)
    cfg, beh, best = rundir.load_run(out)
    p = cfg.model
    fit, res = beh.evaluate(
        best.genome[None], p, backend=backend, engine=cfg.engine,
        record=beh.eval_record, label=f"evaluate {cfg.behaviour}",
    )  # fmt: skip
    reference = beh.reference(p, backend=backend, engine=cfg.engine)
    metrics = (  # a behaviour without a reference need not take one
        beh.metrics(res, p, best.genome)
        if reference is None
        else beh.metrics(res, p, best.genome, reference)
    )
    episodes = Episodes(beh, res, p, reference)
    ev = rundir.derived_dir(out) / rundir.EVAL if eval_dir is None else Path(eval_dir)
    if ev.resolve().parent == out.resolve():  # inside the run: one writer
        with rundir.locked(out):
            return _write(cfg, best, episodes, float(fit[0]), metrics, ev)
    return _write(cfg, best, episodes, float(fit[0]), metrics, ev)


def _write(cfg, best, episodes: Episodes, fitness, metrics, ev: Path) -> Evaluation:
    """Trajectory CSVs and the behaviour's figures into ``ev``."""
    beh, res = episodes.behaviour, episodes.res
    ev.mkdir(parents=True, exist_ok=True)
    labels = beh.state_labels()
    files = []
    for e, label in enumerate(labels):
        stem, ext = rundir.TRAJECTORY_CSV.rsplit(".", 1)
        name = f"{stem}.{ext}" if len(labels) == 1 else f"{stem}_{label}.{ext}"
        files.append(ev / name)
        rundir.write_trajectory_csv(
            files[-1], res["qpos"][e], res["obs"][e], res["ctrl"][e]
        )
    files += reporter_of(beh).write_figures(episodes, ev)
    return Evaluation(cfg.behaviour, fitness, best.fitness, metrics, files)
