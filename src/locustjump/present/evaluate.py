"""Evaluation: re-simulate a run's best genome; its fitness, metrics, figures."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from locustjump import rundir
from locustjump.errors import UserError, setting_ref
from locustjump.present.stages import Episodes, reporter_of
from locustjump.rundir.config import TrainConfig
from locustjump.sim.engine.backends import ThreadBackend
from locustjump.sim.scene import Scene, Terrains

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend


@dataclass
class Evaluation:
    behaviour: str
    fitness: float
    recorded_fitness: float
    metrics: dict[str, Any]
    files: list[Path]
    #: evaluated in another scene than the run trained in (``--scene``): its
    #: fitness is not expected to be the recorded one
    elsewhere: bool = False
    #: an elite of the run's archive (``--elite``/``--cell``): its behaviour
    #: descriptors re-simulated and as the archive holds them, by name
    descriptors: dict[str, float] | None = None
    recorded_descriptors: dict[str, float] | None = None

    @property
    def matches(self) -> bool:
        return self.elsewhere or (
            self.fitness == self.recorded_fitness
            and self.descriptors == self.recorded_descriptors
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "behaviour": self.behaviour,
            "fitness": self.fitness,
            "recorded_fitness": self.recorded_fitness,
            "fitness_matches": self.matches,
            "other_scene": self.elsewhere,
            **(
                {}
                if self.descriptors is None
                else {
                    "descriptors": self.descriptors,
                    "recorded_descriptors": self.recorded_descriptors,
                }
            ),  # fmt: skip
            "metrics": self.metrics,
            "files": [str(f) for f in self.files],
        }


def evaluate_run(
    path: str | os.PathLike[str],
    *,
    backend: Backend | None = None,
    eval_dir: str | os.PathLike[str] | None = None,
    scene: Scene | None = None,
    elite: int | None = None,
    cell: tuple[int, ...] | None = None,
) -> Evaluation:
    """Re-simulate a run's best genome; write its trajectory CSVs and the
    behaviour's figures into ``eval_dir``, by default ``DIR/eval/`` (for a
    shipped run under ``results/``: ``runs/shipped/<same path>/eval/``,
    :func:`locustjump.rundir.derived_dir`). On the run's training terrains,
    or in ``scene`` if given (then its fitness need not be the recorded one).
    Trained on several terrains, its fitness (and a quality-diversity
    elite's descriptors) are theirs combined (as recorded); its metrics and
    figures are of the first.

    ``elite``/``cell``: a quality-diversity run's ``elite``-th best elite, or
    the one in grid cell ``cell``, in place of the best genome (default
    directory ``DIR/elites/cell-I-J/``); its fitness and descriptors are
    checked against the archive's.

    ``eval/`` holds derived files only: they are rewritten on every call.
    """
    out = Path(path)
    if eval_dir is None:
        _, _, best = rundir.load_elite(out, elite=elite, cell=cell)  # before the lock
        into = rundir.derived_dir(out) / rundir.EVAL
        if isinstance(best, rundir.Elite):
            into = rundir.elite_dir(out, best.cell)
        with rundir.deriving(out):  # from reading to writing (a shipped run's
            return evaluate_run(  # eval/ is under runs/shipped/)
                out, backend=backend, eval_dir=into, scene=scene, elite=elite, cell=cell
            )
    if backend is None:
        backend = ThreadBackend()
    cfg, beh, best = rundir.load_elite(out, elite=elite, cell=cell)
    elsewhere = scene is not None and Terrains(scene) != beh.terrains
    if scene is not None:
        beh = beh.on(scene)
    p = cfg.model
    fit, res = beh.evaluate(
        best.genome[None], p, backend=backend, engine=cfg.engine,
        record=beh.eval_record, label=f"evaluate {cfg.behaviour}",
    )  # fmt: skip
    here = None
    if isinstance(best, rundir.Elite):  # where it sits, as re-simulated: over
        here = beh.describe(res, p, best.names)[0]  # every terrain, as trained
    # fitness, descriptors: over every training terrain; metrics, figures: the
    # first one's
    res = res.head(len(beh.start_states(p)))
    reference = beh.reference(p, backend=backend, engine=cfg.engine)
    metrics = beh.metrics(res, p, best.genome, reference)
    episodes = Episodes(beh, res, p, reference)
    done = _write(
        cfg, best, episodes, float(fit[0]), plain(metrics), Path(eval_dir), elsewhere
    )
    if isinstance(best, rundir.Elite) and here is not None:
        done.descriptors = dict(zip(best.names, map(float, here), strict=True))
        done.recorded_descriptors = dict(zip(best.names, best.descriptors, strict=True))
    return done


def plain(value: Any) -> Any:
    """``value`` with every NumPy scalar or array in it as Python's own
    (``float``, ``int``, ``bool``; an array a list), in dicts, lists and
    tuples alike: what a behaviour's metrics hold, whatever NumPy handed it."""
    if isinstance(value, dict):
        return {k: plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return type(value)(plain(v) for v in value)
    if isinstance(value, np.ndarray | np.generic):
        return value.tolist()
    return value


def _write(
    cfg: TrainConfig,
    best: rundir.BestGenome,
    episodes: Episodes,
    fitness: float,
    metrics: dict[str, Any],
    ev: Path,
    elsewhere: bool,
) -> Evaluation:
    """Trajectory CSVs and the behaviour's figures into ``ev``."""
    beh, res = episodes.behaviour, episodes.res
    labels = beh.state_labels()
    files = []
    with rundir.made_dir(ev):  # removed again if a write fails
        for e, label in enumerate(labels):
            stem, ext = rundir.TRAJECTORY_CSV.rsplit(".", 1)
            name = f"{stem}.{ext}" if len(labels) == 1 else f"{stem}_{label}.{ext}"
            files.append(ev / name)
            rundir.write_trajectory_csv(
                files[-1], res["qpos"][e], res["obs"][e], res["ctrl"][e]
            )
        files += reporter_of(beh).write_figures(episodes, ev)
    return Evaluation(cfg.behaviour, fitness, best.fitness, metrics, files, elsewhere)


#: Terrain seeds a reproduction and a run's report score the best genome on
#: when it trained on a terrain (none of them a training terrain by default:
#: training uses seeds from 0).
HELD_OUT_SEEDS: tuple[int, ...] = tuple(range(100, 120))


@dataclass
class TerrainEvaluation:
    """A run's best genome re-scored terrain by terrain (:func:`evaluate_terrains`)."""

    behaviour: str
    scene: str  #: the scene's kind
    seeds: list[int]  #: terrain seeds, in order
    fitness: list[float]  #: on each
    trained: list[bool]  #: whether training scored genomes on it
    metrics: list[dict[str, Any]]  #: the behaviour's metrics on each
    train_fitness: float  #: recorded: the aggregate over the training terrains
    aggregate: str  #: how training combined its terrains (mean or min)

    @property
    def held_out(self) -> float | None:
        """The aggregate (as in training) over the terrains training never saw."""
        f = [f for f, t in zip(self.fitness, self.trained, strict=True) if not t]
        if not f:
            return None
        return float(np.min(f) if self.aggregate == "min" else np.mean(f))

    @property
    def gap(self) -> float | None:
        """Generalisation gap: training fitness minus :attr:`held_out`."""
        h = self.held_out
        return None if h is None else self.train_fitness - h

    def to_dict(self) -> dict[str, Any]:
        return {
            "behaviour": self.behaviour,
            "scene": self.scene,
            "aggregate": self.aggregate,
            "train_fitness": self.train_fitness,
            "held_out_fitness": self.held_out,
            "generalisation_gap": self.gap,
            "terrains": [
                {"seed": s, "fitness": f, "trained": t, "metrics": m}
                for s, f, t, m in zip(
                    self.seeds, self.fitness, self.trained, self.metrics, strict=True
                )
            ],
        }


def evaluate_terrains(
    path: str | os.PathLike[str],
    seeds: list[int],
    *,
    scene: Scene | None = None,
    backend: Backend | None = None,
    elite: int | None = None,
    cell: tuple[int, ...] | None = None,
) -> TerrainEvaluation:
    """Re-score run ``path``'s best genome on each terrain seed of ``seeds``
    (of ``scene``'s kind and parameters, default the run's own scene): its
    fitness and metrics there, and the generalisation gap to the training
    fitness (``elite``/``cell``: an elite of its archive in place of the best
    genome, :func:`evaluate_run`). Writes nothing."""
    if backend is None:
        backend = ThreadBackend()
    cfg, beh, best = rundir.load_elite(Path(path), elite=elite, cell=cell)
    base = beh.terrains.scene if scene is None else scene
    if not base.seeded:
        raise UserError(
            f"{setting_ref('terrain_seeds')}: the {base.name} scene has one terrain "
            f"(e.g. {setting_ref('scene')} debris)"
        )
    trained = set(beh.terrains.scenes)
    p = cfg.model
    fits, marks, metrics = [], [], []
    for s in seeds:
        here = beh.on(base.with_seed(s))
        fit, res = here.evaluate(
            best.genome[None], p, backend=backend, engine=cfg.engine,
            record=beh.eval_record, label=f"terrain {s}",
        )  # fmt: skip
        ref = here.reference(p, backend=backend, engine=cfg.engine)
        m = here.metrics(res, p, best.genome, ref)
        fits.append(float(fit[0]))
        marks.append(here.scene in trained)
        metrics.append(plain(m))
    return TerrainEvaluation(
        cfg.behaviour, base.name, list(seeds), fits, marks, metrics,
        best.fitness, beh.terrains.aggregate,
    )  # fmt: skip
