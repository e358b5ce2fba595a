"""The rule-based run directory (``locustjump rules``, a reproduction's
``rules/``): the rule-based jumping re-simulated, its trajectory, figure and
``summary.json``, which records the creature so that a video re-simulates
the same one."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import TYPE_CHECKING

from locustjump import rundir
from locustjump.present.plots import trajectory_figure
from locustjump.rundir.config import scene_table
from locustjump.sim import model as lm
from locustjump.sim.analysis import ground_profile
from locustjump.sim.engine.job import DEFAULT_ENGINE
from locustjump.sim.scene import Flat, Scene, Terrains
from locustjump.tasks.reference import RulesRun, rules_outcome, run_rules
from locustjump.tasks.rules import DEFAULT_CHANGE_TIME

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend


def write_rules_run(
    out: Path,
    change_time: float = DEFAULT_CHANGE_TIME,
    steps: int = 3000,
    *,
    model_params: lm.LocustParams = lm.LocustParams(),
    backend: Backend | None = None,
    engine: str = DEFAULT_ENGINE,
    scene: Scene = Flat(),
) -> RulesRun:
    """Run the rules and write a rule-based run directory ``out`` (created if
    absent): ``trajectory.csv``, ``trajectory.png`` and ``summary.json``, which
    records the creature, the scene and the engine so that a video
    re-simulates the same episode, and how far the rules got
    (:func:`rules_outcome`)."""
    run = run_rules(
        change_time, steps, model_params=model_params, backend=backend,
        label="rules", engine=engine, scene=scene,
    )  # fmt: skip
    out.mkdir(parents=True, exist_ok=True)
    rundir.write_trajectory_csv(
        out / rundir.TRAJECTORY_CSV, run.qpos, run.obs, run.ctrl
    )
    trajectory_figure(
        out / rundir.TRAJECTORY_PNG,
        [("rule-based", run.qpos, run.jumps)],
        title=f"Rule-based successive jumping (change time {run.change_time:.3f} s)",
        ground=ground_profile(run.qpos, model_params, scene),
    )
    model = {
        k: list(v) if isinstance(v, tuple) else v
        for k, v in dataclasses.asdict(model_params).items()
    }
    rundir.write_json(
        out / rundir.RULES_SUMMARY,
        {
            "change_time_s": run.change_time,
            "steps": steps,
            "apex_heights_m": [round(j.apex_height, 4) for j in run.jumps],
            "unstable": run.unstable,
            "engine": engine,
            "model": model,
            "scene": scene_table(Terrains(scene)),
            **rules_outcome(run, model_params),
        },
    )
    return run
