"""What a directory holds, played again: :func:`source_of` finds the
controller and its episodes (a training run's best genome or an elite of its
archive, or a rule-based run) and :func:`playback_of` re-simulates them with
the engine, keeping every control step's ``qpos``, for a video
(:mod:`~locustjump.present.render`) or the viewer
(:mod:`~locustjump.present.viewer`)."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from locustjump import rundir
from locustjump.errors import UserError
from locustjump.rundir.config import from_table, terrains_from_table
from locustjump.rundir.migrations import rules_summary
from locustjump.sim import model as lm
from locustjump.sim.controller import Controller
from locustjump.sim.engine.rollout import DEFAULT_ENGINE, StartStates, rollout
from locustjump.sim.scene import Flat, Scene
from locustjump.tasks.rules import RuleController
from locustjump.tasks.starts import ready_state

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend


@dataclass(frozen=True)
class Playback:
    """What a video shows: episodes played side by side.

    Attributes:
      model_params: the creature.
      qpos: (k, T + 1, nq) per control step of each of k episodes.
      labels: a label per episode (e.g. the get-up start roll).
      captions: (k, T + 1) text per step (e.g. the active behaviour), or None.
      title: what it is.
      scene: the world they ran in.
    """

    model_params: lm.LocustParams
    qpos: np.ndarray
    labels: list[str]
    captions: np.ndarray | None
    title: str
    scene: Scene = Flat()

    @property
    def n_steps(self) -> int:
        steps: int = self.qpos.shape[1] - 1
        return steps


def _rules_run(path: Path) -> tuple[float, int, lm.LocustParams, str, Scene] | None:
    """(change time, steps, creature, engine, scene) of a rule-based run
    directory, else None. Summaries written before the creature was recorded
    are of the default one; before the engine was the run's, it was the
    creature's; before scenes, the flat floor."""
    if not rundir.is_rules_run(path):
        return None
    f = path / rundir.RULES_SUMMARY
    summary = rules_summary(rundir.read_json(f), DEFAULT_ENGINE)
    try:
        p = from_table(lm.LocustParams, summary["model"], "model", str(f))
        steps = int(summary.get("steps", 3000))
        scene = terrains_from_table(summary.get("scene", {}), str(f)).scene
        return (
            float(summary["change_time_s"]),
            steps,
            p,
            str(summary["engine"]),
            scene,
        )
    except (KeyError, TypeError, ValueError) as e:
        raise UserError(f"{f}: not a rule-based run summary ({e})") from None


@dataclass(frozen=True)
class Source:
    """A controller and its episodes, as a directory holds them."""

    model_params: lm.LocustParams
    engine: str  # the engine it was simulated on
    controller: Controller
    params: np.ndarray  # (1, num_params)
    starts: StartStates
    n_steps: int
    labels: list[str]
    title: str
    memory_names: tuple[str, ...] | None = None  # memory[0] indexes these
    scene: Scene = Flat()  # the world it runs in


def source_of(
    path: str | os.PathLike[str],
    scene: Scene | None = None,
    *,
    elite: int | None = None,
    cell: tuple[int, ...] | None = None,
) -> Source:
    """What directory ``path`` holds: a training run's best genome
    (``config.toml`` + ``best.npz``; ``elite``/``cell``: an elite of its
    archive instead, :func:`locustjump.rundir.load_elite`) or a rule-based
    run (``locustjump rules`` or a reproduction's ``rules/``:
    ``summary.json`` + ``trajectory.csv``), in its own scene (a run's first
    training terrain) or in ``scene``."""
    out = Path(path)
    if not out.is_dir():
        raise UserError(f"{out}: no such directory")
    if rundir.is_reproduction(out):
        raise UserError(
            f"{out}: a reproduction; give one of its stages, e.g. {out / 'kick'}"
        )
    if not rundir.is_run(out):
        if elite is not None or cell is not None:  # says it has no run
            rundir.load_elite(out, elite=elite, cell=cell)
        rules = _rules_run(out)
        if rules is None:
            raise UserError(
                f"{out}: holds no run (no {rundir.CONFIG}) and no rule-based run "
                f"(no {rundir.RULES_SUMMARY} + {rundir.TRAJECTORY_CSV})"
            )
        change_time, steps, p, engine, own = rules
        scene = own if scene is None else scene
        rc = RuleController.for_model(p)
        return Source(
            p,
            engine,
            rc,
            rc.params_for(change_time),
            ready_state(p, scene),
            steps,
            ["rule-based"],
            f"rule-based, change time {change_time:.3f} s",
            scene=scene,
        )
    cfg, beh, best = rundir.load_elite(out, elite=elite, cell=cell)
    if scene is not None:
        beh = beh.on(scene)
    labels = beh.state_labels()
    what = (
        f"{best.label}, found in generation {best.generation}"
        if isinstance(best, rundir.Elite)
        else f"best of generation {best.generation}"
    )
    return Source(
        cfg.model,
        cfg.engine,
        beh.controller,
        best.genome[None],
        beh.start_states(cfg.model),
        beh.n_steps,
        labels if len(labels) > 1 else [cfg.behaviour],
        f"{cfg.behaviour}, {what}, fitness {best.fitness:.4g}",
        beh.memory_labels,
        beh.scene,
    )


def playback_of(
    path: str | os.PathLike[str],
    *,
    backend: Backend | None = None,
    scene: Scene | None = None,
    elite: int | None = None,
    cell: tuple[int, ...] | None = None,
) -> Playback:
    """Re-simulate what directory ``path`` holds (:func:`source_of`; in
    ``scene`` if given; ``elite``/``cell``: an elite of its archive) with the
    engine, keeping every control step."""
    src = source_of(path, scene, elite=elite, cell=cell)
    record = ("qpos",) if src.memory_names is None else ("qpos", "memory")
    res = rollout(
        src.controller, src.params, src.starts, src.n_steps,
        model_params=src.model_params, record=record, backend=backend,
        engine=src.engine,
        scene=src.scene,
    )  # fmt: skip
    captions = None
    if src.memory_names is not None:
        captions = np.array(src.memory_names)[acting(res["memory"][:, :, 0])]
    return Playback(
        src.model_params, res["qpos"], src.labels, captions, src.title, src.scene
    )


def acting(selected: np.ndarray) -> np.ndarray:
    """(k, T + 1) index of the behaviour that acts from each recorded state
    on, from the memory recorded after each step (``selected[:, t]``: chosen
    for step t - 1; ``selected[:, 0]``, the initial memory, chose nothing).
    The last state shows the last step's."""
    idx = selected.astype(int)
    return np.concatenate([idx[:, 1:], idx[:, -1:]], axis=1)
