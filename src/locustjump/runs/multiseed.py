"""The whole paper over several seeds, on this machine or a Ray cluster.

A reproduction over seeds is a directory (names in :mod:`locustjump.rundir`)::

    DIR/seeds.toml      budget, optimizer, seeds, command
    DIR/seed-<s>/       one reproduction per seed, the same as
                        ``locustjump reproduce --seed s --out DIR/seed-<s>``
    DIR/results.md      per claim: median, range, how many seeds reproduce it;
                        per-stage fitness; per-seed tables
    DIR/report.html

With the thread backend the seeds run one after another. With Ray every
(seed, stage) is a task that starts as soon as its inputs exist: the rule-based
run, kick, getup, return-legs and the monolithic baseline of every seed at
once, each seed's composed stage when its three simple stages are done. A task
asks Ray for ``threads`` CPUs (default: the CPUs of the cluster's smallest
node) and steps its episodes on as many threads. Results are the same either
way, bit for bit: a stage's result depends on its seed and budget only.

Rerunning the same command continues: finished stages are kept, interrupted
ones resume from their checkpoints. On a cluster ``DIR`` must be on a file
system every node sees (the tasks write their stages there).
"""

from __future__ import annotations

import contextlib
import logging
import os
import re
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING, Any

from tqdm.auto import tqdm

from locustjump import rundir
from locustjump.errors import UserError, setting_ref
from locustjump.evo.base import SEED
from locustjump.present.report import write_report
from locustjump.present.results import minutes, seeds_markdown
from locustjump.ranges import INT64_MAX
from locustjump.runs.reproduce import finish_reproduction, reproduce
from locustjump.runs.reproduction import Budget, Reproduction, requires, stages_of
from locustjump.sim.engine.backends import ThreadBackend
from locustjump.sim.engine.ray_backend import connect
from locustjump.sim.scene import Terrains

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend

_SEEDS = re.compile(r"^\d+(-\d+)?$")
#: the most seeds one command takes (a typo like 0-99999 is caught)
MAX_SEEDS = 1000

#: progress and diagnostics (the command line shows them; see logging)
_log = logging.getLogger(__name__)


def parse_seeds(text: str) -> list[int]:
    """``"0-9"``, ``"0,3,7"``, ``"0-4,10"`` → the seeds, in order.

    ``ValueError`` (with a message naming the problem) for anything else, an
    empty list, a seed given twice or more than :data:`MAX_SEEDS` seeds."""
    seeds: list[int] = []
    for part in text.replace(" ", "").split(","):
        if not _SEEDS.match(part):
            raise ValueError(
                f"{text!r}: expected seeds like 0-9 or 0,3,7 (non-negative "
                f"integers and ranges), not {part!r}"
            )
        lo, _, hi = part.partition("-")
        a, b = int(lo), int(hi or lo)
        if b < a:
            raise ValueError(f"{text!r}: the range {part} is empty")
        if b > INT64_MAX:
            raise ValueError(f"{text!r}: a seed must be {SEED}, not {b}")
        if b - a + len(seeds) >= MAX_SEEDS:
            raise ValueError(f"{text!r}: more than {MAX_SEEDS} seeds")
        seeds += range(a, b + 1)
    repeated = sorted({s for s in seeds if seeds.count(s) > 1})
    if repeated:
        raise ValueError(f"{text!r}: seed {repeated[0]} is given twice")
    return seeds


def reproduce_seeds(
    out: str | os.PathLike[str],
    seeds: Sequence[int],
    *,
    budget: str | Budget = "quick",
    optimizer: str = "rcga",
    engine: str | None = None,
    backend: str = "threads",
    threads: int | None = None,
    address: str | None = None,
    progress: bool = True,
    log: Callable[[str], None] | None = None,
    command: str = "",
    videos: bool = True,
    monolithic: bool = True,
    terrains: Terrains | None = None,
) -> Path:
    """Run (or continue) the whole paper for every seed in ``seeds`` into
    ``out/seed-<s>/``; write ``out/results.md`` across seeds (also after every
    finished seed) and ``out/report.html``; return the path of ``results.md``.

    ``backend`` is ``"threads"`` (here, seed after seed, ``threads`` threads)
    or ``"ray"`` (every stage a task on the cluster at ``address``, default a
    local instance, ``threads`` CPUs each). ``engine``: as for
    :func:`~locustjump.runs.reproduce.reproduce`, and ``terrains``. A rerun
    may add seeds. ``log`` takes each line of progress (default: this
    module's logger, at INFO)."""
    log = log or _log.info
    if backend not in ("threads", "ray"):
        raise UserError(f"unknown backend {backend!r}; choose from threads, ray")
    rep = Reproduction.open(
        out, budget, seeds, optimizer=optimizer, engine=engine, many=True,
        terrains=terrains,
    )  # fmt: skip
    ray = None
    if backend == "ray":
        ray = connect(address)
        threads = _task_threads(ray, threads)

    here = ThreadBackend(threads)
    rep.out.mkdir(parents=True, exist_ok=True)
    with contextlib.ExitStack() as held:
        held.enter_context(rundir.locked(rep.out))
        rep.check()  # another process may have been first
        for s in rep.seeds:
            rep.seed_dir(s).mkdir(exist_ok=True)
            held.enter_context(rundir.locked(rep.seed_dir(s)))
        rep.start(command or rep.command(backend, monolithic=monolithic))
        if ray is None:
            for i, s in enumerate(rep.seeds, 1):
                log(f"[seed {s}] {i} of {len(rep.seeds)} seeds, on this machine")
                reproduce(
                    rep.seed_dir(s), budget=rep.budget, seed=s,
                    optimizer=rep.optimizer, engine=rep.engine, backend=here,
                    progress=progress, log=_tagged(log, s),
                    videos=videos, monolithic=monolithic, terrains=rep.terrains,
                )  # fmt: skip
                _write_results(rep.out, here)
        else:
            assert threads is not None  # _task_threads set it when Ray connected
            _run_on_ray(ray, rep, threads, monolithic, here, progress, log, videos)
        path = _write_results(rep.out, here)
        log(f"wrote {path} and {rep.out / rundir.REPORT}")
        return path


def _task_threads(ray: Any, threads: int | None) -> int:
    """CPUs (and simulation threads) per stage task: default and limit are
    the CPUs of the smallest and of the largest node."""
    cpus = [
        int(n["Resources"].get("CPU", 0))
        for n in ray.nodes()
        if n.get("Alive") and n["Resources"].get("CPU", 0) >= 1
    ]
    if not cpus:
        raise UserError("the Ray cluster has no node with a CPU")
    if threads is None:
        return min(cpus)
    if threads > max(cpus):
        raise UserError(
            f"{setting_ref('threads')} {threads}: the largest node of the Ray "
            f"cluster has {max(cpus)} CPUs"
        )
    return threads


def _stage_task(
    rep: Reproduction, seed: int, stage: str, threads: int, *_inputs: Any
) -> tuple[float | None, float]:
    """One (seed, stage) on a Ray worker; ``_inputs`` are the tasks it waits for."""

    d = rep.seed_dir(seed)
    if not rundir.is_reproduction(d):
        raise UserError(
            f"{d}: not visible on this node (on a cluster, {setting_ref('out')} "
            "must be on a file system every node sees)"
        )
    t0 = time.perf_counter()
    with ThreadBackend(threads) as backend:
        fitness = rep.run_stage(stage, backend, seed, log=lambda m: None)
    return fitness, time.perf_counter() - t0


def _run_on_ray(
    ray: ModuleType,
    rep: Reproduction,
    threads: int,
    monolithic: bool,
    here: Backend,
    progress: bool,
    log: Callable[[str], None],
    videos: bool,
) -> None:
    task = ray.remote(num_cpus=threads)(_stage_task)
    pending: dict[Any, tuple[int, str]] = {}
    left = {s: 0 for s in rep.seeds}
    for s in rep.seeds:
        refs: dict[str, Any] = {}
        for stage in stages_of(monolithic):
            if rep.stage_done(stage, s):
                continue
            needs = [refs[r] for r in requires(stage) if r in refs]
            refs[stage] = task.remote(rep, s, stage, threads, *needs)
            pending[refs[stage]] = (s, stage)
            left[s] += 1

    log(
        f"{len(pending)} stage tasks over {len(rep.seeds)} seeds on Ray "
        f"({threads} CPUs each)"
    )
    bar = tqdm(total=len(pending), desc="stages", unit="stage", disable=not progress)
    done_seeds = [s for s, n in left.items() if n == 0]
    try:
        while pending or done_seeds:
            for s in done_seeds:
                finish_reproduction(
                    rep.seed_dir(s), backend=here, videos=videos, log=_tagged(log, s)
                )
                _write_results(rep.out, here)
            done_seeds = []
            if not pending:
                break
            ready, _ = ray.wait(list(pending), num_returns=1)
            s, stage = pending.pop(ready[0])
            try:
                fitness, wall = ray.get(ready[0])
            except ray.exceptions.RayTaskError as e:
                cause = getattr(e, "cause", None) or e
                why = cause.message if isinstance(cause, UserError) else cause
                raise UserError(f"[seed {s}] {stage}: {why}") from None
            bar.update()
            shown = "" if fitness is None else f"best fitness {fitness:.6g}, "
            with tqdm.external_write_mode():  # the line above the bar
                log(f"[seed {s}] {stage}: {shown}{minutes(wall)}")
            left[s] -= 1
            if left[s] == 0:
                done_seeds.append(s)
    finally:
        bar.close()


def _tagged(log: Callable[[str], None], seed: int) -> Callable[[str], None]:
    """``log`` with each line tagged with its seed."""
    return lambda m: log(f"[seed {seed}] {m}")


def _write_results(out: Path, backend: Backend) -> Path:

    path = out / rundir.RESULTS
    rundir.atomic_write_text(path, seeds_markdown(out))
    write_report(out, backend=backend, out=out / rundir.REPORT)
    return path
