"""A study's plan and state: what is done and what is left, with the cost
in control steps and the time it would take at this machine's measured
throughput (``study --dry-run``, :func:`dry_run`), and at the pace of the
processes training it now (``study --status``, :func:`status`)."""

from __future__ import annotations

import heapq
import math
import os
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
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
    lines.append(
        f"Declared primary: {study.primary.describe()}; the table's other "
        "comparisons are secondary."
        if study.primary
        else "No primary comparison declared: the table takes all its "
        "comparisons as one family."
    )
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
    processes training the study now (:func:`pace`), each taking the runs
    left as :func:`~locustjump.runs.study.run_study` does (:func:`forecast`)."""
    rows = states(study)
    who = {r.path: None if r.finished else rundir.in_use(r.path) for r in rows}
    seeds = study.seeds
    lines = [
        "| arm | " + " | ".join(f"seed {s}" for s in seeds) + " |",
        "| --- " * (len(seeds) + 1) + "|",
    ]
    for arm in study.arms.values():
        cells = {r.seed: _cell(r, who[r.path]) for r in rows if r.arm == arm.name}
        row = [cells[arm.seed_of(s)] for s in seeds]
        lines.append(f"| {arm.name} | " + " | ".join(row) + " |")
    done = sum(r.finished for r in rows)
    left = sum(r.steps_left for r in rows)
    line = f"\n{done} of {len(rows)} runs done"
    if left:
        line += f", {format_steps(left)} control steps left"
        training = [r for r in rows if who[r.path]]
        rates = pace(training)
        n = len(training)
        who_n = f"{n} process{'es' if n > 1 else ''}"
        if rates and min(rates) > 0:
            each = sum(rates) / len(rates)  # an untimed process: at the others' pace
            todo = [r for r in rows if not r.finished]
            f = forecast(_jobs(study, todo, {r.path for r in training}, each), n)
            how = f"{each:,.0f} control steps/s"
            if n > 1:
                how += " each, taking the next run it may"
                if f.tail >= 60:
                    how += (f"; the last {format_duration(f.tail)} of it with "
                            f"fewer than {n} at work")  # fmt: skip
            line += (
                f": about {format_duration(f.seconds)} at the pace of the "
                f"{who_n} training it now ({how}; scoring not counted)"
            )
        elif n:
            line += f"; {who_n} training it now, no generation timed yet"
        else:
            line += "; no process is training it now"
    lines.append(line)
    return "\n".join(lines)


#: generations of a run whose pace :func:`pace` reads (its latest)
PACE_GENERATIONS = 10


def pace(training: list[RunState]) -> list[float]:
    """The control steps a second of each run of ``training`` (runs a process
    trains now) that has a generation timed: its median over its latest
    :data:`PACE_GENERATIONS` generations (``metrics.csv``)."""
    rates = []
    for r in training:
        if r.done:
            m = rundir.read_metrics(r.path / rundir.METRICS)
            rates.append(float(np.median(m["steps_per_s"][-PACE_GENERATIONS:])))
    return rates


@dataclass(frozen=True)
class Job:
    """A run left to train, for :func:`forecast`."""

    seconds: float  # to train what is left of it, on one process
    after: tuple[int, ...] = ()  # the jobs (indices) it builds on
    held: bool = False  # a process trains it now


@dataclass(frozen=True)
class Forecast:
    """What :func:`forecast` says, in seconds."""

    seconds: float  # until the last job is trained
    tail: float  # the end of that time, with fewer jobs training than processes


def forecast(jobs: Sequence[Job], processes: int) -> Forecast:
    """When ``processes`` processes have trained ``jobs`` (in the study's
    order), each taking them as :func:`~locustjump.runs.study.run_study`
    does: a process holding a job finishes it first; a free process takes the
    first job left whose jobs built on are finished, and waits for the next
    to finish when none is. ``tail``: how long, at the end, fewer jobs train
    at once than there are processes (the runs left are too few, or wait on
    others), all of it when there are never as many. ``ValueError`` if
    fewer processes than held jobs."""
    held = sum(job.held for job in jobs)
    if processes < max(held, 1):
        raise ValueError(f"processes: {processes}, fewer than the {held} held job(s)"
                         if held else f"processes: {processes}, not >= 1")  # fmt: skip
    end: dict[int, float] = {}
    start: dict[int, float] = {}
    for i, job in enumerate(jobs):
        if job.held:
            start[i], end[i] = 0.0, job.seconds
    free = sorted(end.values()) + [0.0] * (processes - held)
    heapq.heapify(free)
    todo = [i for i, job in enumerate(jobs) if not job.held]
    while todo:
        t = heapq.heappop(free)
        ready = (k for k in todo if all(end.get(d, math.inf) <= t
                                        for d in jobs[k].after))  # fmt: skip
        pick = next(ready, None)
        if pick is None:  # wait for the next job to finish
            later = [e for e in end.values() if e > t]
            if not later:
                raise ValueError(f"job {todo[0]} builds on a job never trained")
            heapq.heappush(free, min(later))
            continue
        todo.remove(pick)
        start[pick], end[pick] = t, t + jobs[pick].seconds
        heapq.heappush(free, end[pick])
    last = max(end.values(), default=0.0)
    # the last moment as many jobs train as there are processes
    full = 0.0
    for t in sorted(set(start.values()) | set(end.values())):
        if sum(start[i] <= t < end[i] for i in end) >= processes:
            full = min(e for e in end.values() if e > t)
    return Forecast(last, last - full)


def _jobs(
    study: Study, todo: list[RunState], held: set[Path], rate: float
) -> list[Job]:
    """The runs ``todo`` as :class:`Job` at ``rate`` control steps/s each."""
    index = {r.path.resolve(): i for i, r in enumerate(todo)}
    jobs = []
    for r in todo:
        built_on = study.arms[r.arm].frozen.values()
        dirs = (study.arms[a].run_dir(r.seed).resolve() for a in built_on)
        after = tuple(index[d] for d in dirs if d in index)
        jobs.append(Job(r.steps_left / rate, after, r.path in held))
    return jobs


def _cell(r: RunState, who: str | None) -> str:
    return f"{r.status}, {who}" if who else r.status
