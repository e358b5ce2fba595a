"""A study's plan and state: what is done and what is left, with the cost
in control steps and the time it would take at this machine's measured
throughput (``study --dry-run``, :func:`dry_run`), and at the pace of the
processes training it now (``study --status``, :func:`status`)."""

from __future__ import annotations

import os
import time
from typing import TYPE_CHECKING

import numpy as np

from locustjump import rundir
from locustjump.rundir.config import TrainConfig
from locustjump.runs.study import (
    RunState,
    behaviour_for,
    format_duration,
    format_steps,
    score_steps,
    states,
)
from locustjump.runs.studyfile import Study
from locustjump.sim.engine.rollout import rollout

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend

#: control steps of the throughput probe per episode (``--dry-run``)
PROBE_STEPS = 240


def throughput(
    cfg: TrainConfig, backend: Backend, substeps: int | None = None
) -> float:
    """Control steps per second of ``cfg``'s episodes on ``backend``, measured:
    a population of random genomes from its start states for
    :data:`PROBE_STEPS` steps (after one untimed call that compiles)."""
    beh = behaviour_for(cfg)
    p = cfg.model if substeps is None else cfg.model.replace(substeps=substeps)
    rng = np.random.default_rng(0)
    n = min(cfg.population, 32)
    genomes = rng.normal(0.0, 0.5, (n, beh.controller.num_params))
    starts = beh.start_states(p)

    def go(steps: int) -> float:
        t = time.perf_counter()
        rollout(beh.controller, genomes, starts, steps, model_params=p,
                scene=beh.scene, backend=backend, engine=cfg.engine,
                record=())  # fmt: skip
        return time.perf_counter() - t

    go(8)
    return n * len(starts) * PROBE_STEPS / go(PROBE_STEPS)


def dry_run(study: Study, backend: Backend, where: str = "threads") -> str:
    """The plan of ``study`` as text: each arm's runs (done, partial, to do),
    control steps left to train and to score, and the time at this machine's
    throughput (measured per arm, :func:`throughput`)."""
    rows = states(study)
    busy = _load()
    lines = [
        f"study {study.name} ({study.source}): {len(study.arms)} arms x "
        f"{len(study.seeds)} seeds, runs under {study.root}",
        "",
        "| arm | behaviour | scene | generations x population | control steps a "
        "run | runs done / partial / to do | steps left | steps/s here | time left |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    train_s = score_s = 0.0
    for arm in study.arms.values():
        mine = [r for r in rows if r.arm == arm.name]
        cfg = arm.base
        rate = throughput(cfg, backend)
        left = sum(r.steps_left for r in mine)
        scoring = 0.0
        if arm.score:  # each resolution at its own rate (12 substeps: ~4x slower)
            beh = behaviour_for(cfg)
            for sub, steps in score_steps(study, cfg, beh).items():
                same = sub is None or sub == cfg.model.substeps
                at = rate if same else throughput(cfg, backend, sub)
                scoring += len(mine) * steps / at
        train_s += left / rate
        score_s += scoring
        partial = sum(0 < r.done and not r.finished for r in mine)
        done = sum(r.finished for r in mine)
        run_steps = cfg.generations * mine[0].steps_per_generation
        lines.append(
            f"| {arm.name} | {cfg.behaviour} | {cfg.scene.scene.name} x "
            f"{cfg.scene.count} | {cfg.generations} x {cfg.population} | "
            f"{format_steps(run_steps)} | {done} / {partial} / "
            f"{len(mine) - done - partial} | {format_steps(left)} | {rate:,.0f} | "
            f"{format_duration(left / rate)} |"
        )
    ev = study.evaluation
    lines += [
        "",
        f"Training left: {format_duration(train_s)}; scoring every run's best genome "
        f"({len(ev.terrain_seeds) if ev.terrain_seeds else 'its own scene'}"
        f"{' terrains' if ev.terrain_seeds else ''} x "
        f"{len(ev.substeps)} physics): {format_duration(score_s)} (estimates: the "
        f"throughput of {PROBE_STEPS}-step episodes of random genomes on this "
        f"machine, {where}; a generation evaluates the whole population).",
    ]
    if busy >= BUSY_LOAD:
        lines.append(
            f"The machine was busy when they were measured (load average {busy:.1f} "
            f"over the last minute, {os.cpu_count()} CPUs): idle, it runs faster."
        )
    return "\n".join(lines)


#: a 1-minute load average from which :func:`dry_run` says its rates were
#: measured beside other work
BUSY_LOAD = 0.5


def _load() -> float:
    """This machine's load average over the last minute (0 where the system
    does not tell)."""
    try:
        return os.getloadavg()[0]
    except (AttributeError, OSError):
        return 0.0


def status(study: Study) -> str:
    """What is done: per arm, each seed's generations done of its budget, and
    which runs a process is training now (``102/120, process 1234``); then
    the control steps left and how long they take at the pace of the
    processes training the study now (:func:`pace`)."""
    rows = states(study)
    seeds = study.seeds
    lines = [
        "| arm | " + " | ".join(f"seed {s}" for s in seeds) + " |",
        "| --- " * (len(seeds) + 1) + "|",
    ]
    for arm in study.arms.values():
        cells = {r.seed: _cell(r) for r in rows if r.arm == arm.name}
        row = [cells[arm.seed_of(s)] for s in seeds]
        lines.append(f"| {arm.name} | " + " | ".join(row) + " |")
    done = sum(r.finished for r in rows)
    left = sum(r.steps_left for r in rows)
    line = f"\n{done} of {len(rows)} runs done"
    if left:
        line += f", {format_steps(left)} control steps left"
        n, rate = pace(rows)
        who = f"{n} process{'es' if n > 1 else ''}"
        if rate:
            line += (f": about {format_duration(left / rate)} at the pace of the {who} "
                     f"training it now ({rate:,.0f} control steps/s; scoring "
                     "not counted)")  # fmt: skip
        elif n:
            line += f"; {who} training it now, no generation timed yet"
        else:
            line += "; no process is training it now"
    lines.append(line)
    return "\n".join(lines)


#: generations of a run whose pace :func:`pace` reads (its latest)
PACE_GENERATIONS = 10


def pace(rows: list[RunState]) -> tuple[int, float]:
    """The processes training runs of ``rows`` now, and their control steps a
    second together: each one's median over its run's latest
    :data:`PACE_GENERATIONS` generations (``metrics.csv``; 0 for a run
    that has none yet)."""
    n, rate = 0, 0.0
    for r in rows:
        if r.finished or not rundir.in_use(r.path):
            continue
        n += 1
        if r.done:
            m = rundir.read_metrics(r.path / rundir.METRICS)
            rate += float(np.median(m["steps_per_s"][-PACE_GENERATIONS:]))
    return n, rate


def _cell(r: RunState) -> str:
    who = None if r.finished else rundir.in_use(r.path)
    return f"{r.status}, {who}" if who else r.status
