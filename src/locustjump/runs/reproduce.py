"""The whole paper in one call: every stage in order, resumable, with a results
table. A reproduction is a directory (names in :mod:`locustjump.rundir`)::

    DIR/reproduce.toml    budget, seed, optimizer, generations per stage, command
    DIR/rules/            the rule-based baseline (Fig. 5): trajectory + summary
    DIR/kick/             a run directory + eval/
    DIR/getup/            ... + sweep/ (the 180-state generalisation test)
    DIR/return-legs/
    DIR/composed/         builds on the three runs above (simple.npz)
    DIR/monolithic/       beyond the paper: one network, same evaluation budget
    DIR/results.md        one row per claim of the paper, figures, wall times

Rerunning the same command continues where it stopped: finished stages are
kept, an interrupted training resumes from its checkpoint (bit-identical).
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from locustjump import rundir
from locustjump.errors import UserError
from locustjump.evo import params_class
from locustjump.present.evaluate import Evaluation, evaluate_run
from locustjump.present.render import VIDEO_FPS, RenderUnavailable, render_run
from locustjump.present.report import write_report
from locustjump.present.results import results_markdown
from locustjump.present.rules import write_rules_run
from locustjump.present.stages import reporter_of
from locustjump.rundir.config import TrainConfig
from locustjump.rundir.migrations import reproduction_marker
from locustjump.runs.trainer import train
from locustjump.sim import model as lm
from locustjump.sim.engine.backends import ThreadBackend
from locustjump.sim.engine.job import DEFAULT_ENGINE, ENGINES
from locustjump.tasks import behaviour_class
from locustjump.version import __version__

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend

#: The paper's trained stages, in order (each a subdirectory).
PAPER_STAGES = ("kick", "getup", "return-legs", "composed")
#: Beyond the paper: one network evolved directly on the composed task.
BASELINES = ("monolithic",)
TRAINED = PAPER_STAGES + BASELINES
STAGES = (rundir.RULES_DIR, *TRAINED)


@dataclass(frozen=True)
class Budget:
    """Population and generations per trained stage."""

    name: str
    population: int
    generations: dict[str, int]  # of the paper's stages; baselines are added

    def __post_init__(self) -> None:
        # a baseline gets as many genome evaluations as the four paper stages
        # together
        paper = {s: self.generations[s] for s in PAPER_STAGES}
        total = sum(paper.values())
        gens = {**paper, **{b: self.generations.get(b, total) for b in BASELINES}}
        object.__setattr__(self, "generations", gens)

    def of(self, stage: str) -> int:
        return self.generations[stage]


BUDGETS: dict[str, Budget] = {
    "quick": Budget(
        "quick", 50, {"kick": 30, "getup": 10, "return-legs": 20, "composed": 30}
    ),
    "long": Budget(
        "long", 50, {"kick": 100, "getup": 20, "return-legs": 60, "composed": 120}
    ),
    "paper": Budget("paper", 50, dict.fromkeys(PAPER_STAGES, 1000)),
}


def _check_dir(out: Path, want: dict[str, Any]) -> None:
    """A new reproduction needs an absent or empty directory; an existing one
    must have been started with the same budget, seed and optimizer."""
    if out.exists() and not out.is_dir():
        raise UserError(f"--out {out}: exists and is not a directory")
    if rundir.is_reproduction(out):
        have = reproduction_marker(rundir.read_toml(out / rundir.MARKER))
        for k, v in want.items():
            if have.get(k) != v:
                raise UserError(
                    f"--out {out}: holds a reproduction with {k} {have.get(k)!r}, "
                    f"not {v!r} (choose another --out)"
                )
    elif out.is_dir() and any(out.iterdir()):
        raise UserError(
            f"--out {out}: directory is not empty and holds no reproduction "
            f"(no {rundir.MARKER}); choose another --out"
        )


def run_rules_stage(
    out: Path, *, backend: Backend | None = None, engine: str = DEFAULT_ENGINE
) -> dict[str, Any]:
    """The rule-based baseline: ``rules/trajectory.{csv,png}``, ``summary.json``."""
    t0 = time.perf_counter()
    r = write_rules_run(out, steps=3000, backend=backend, engine=engine)
    summary = rundir.read_json(out / rundir.RULES_SUMMARY)
    summary["first_apex_height_m"] = r.jumps[0].apex_height if r.jumps else None
    summary["final_up_z"] = float(r.obs[-1, 8])
    summary["wall_s"] = time.perf_counter() - t0
    rundir.write_json(out / rundir.RULES_SUMMARY, summary)
    return summary


def budget_of(budget: str | Budget) -> Budget:
    """The budget called ``budget`` (``UserError`` naming the choices if none)."""
    if isinstance(budget, Budget):
        return budget
    if budget in BUDGETS:
        return BUDGETS[budget]
    raise UserError(f"unknown budget {budget!r}; choose from {', '.join(BUDGETS)}")


def single_seed_command(
    budget: str,
    seed: int,
    optimizer: str,
    out: str | os.PathLike,
    engine: str | None = None,
) -> str:
    """The command that makes (and continues) reproduction ``out`` alone."""
    flags = "" if optimizer == "rcga" else f" --optimizer {optimizer}"
    if engine not in (None, DEFAULT_ENGINE):
        flags += f" --engine {engine}"
    return f"locustjump reproduce --budget {budget} --seed {seed}{flags} --out {out}"


def reproduce(
    out: str | os.PathLike,
    *,
    budget: str | Budget = "quick",
    seed: int = 0,
    optimizer: str = "rcga",
    engine: str | None = None,
    backend: Backend | None = None,
    progress: bool = True,
    log: Callable[[str], None] = print,
    command: str = "",
    videos: bool = True,
    monolithic: bool = True,
) -> Path:
    """Run (or continue) every stage of the paper into ``out``; write
    ``results.md``, a video per stage (``videos``, when rendering is
    available here) and ``report.html``; return the path of ``results.md``.

    ``results.md`` is rewritten after every finished stage, so a long
    reproduction shows its results so far. ``monolithic=False`` leaves out the
    baseline beyond the paper (as long as the four paper stages together at the
    paper's budget); a later call with it continues and adds it. ``optimizer``
    (a kind of :mod:`locustjump.evo`) trains every stage; ``engine``
    (:data:`~locustjump.sim.engine.job.ENGINES`; default: the one ``out`` was
    started with, else the default) computes every stage's controllers. Several seeds
    at once, on a cluster too: :func:`locustjump.runs.multiseed.reproduce_seeds`."""
    b = budget_of(budget)
    out = Path(out)
    params_class(optimizer)  # a clear error for an unknown kind, before mkdir
    check_reproduction(out, b, seed, optimizer, engine)
    if backend is None:
        backend = ThreadBackend()
    out.mkdir(parents=True, exist_ok=True)
    with rundir.locked(out):
        engine = start_reproduction(out, b, seed, optimizer, command, engine)
        for stage in stages_of(monolithic):
            if not stage_done(out, stage, b):
                run_stage(out, stage, b, seed, optimizer, backend, progress, log,
                          engine)  # fmt: skip
                rundir.atomic_write_text(out / rundir.RESULTS, results_markdown(out))
            elif stage != rundir.RULES_DIR:
                log(f"[{stage}] done ({b.of(stage)} generations)")
        return finish_reproduction(out, backend=backend, log=log, videos=videos)


def stages_of(monolithic: bool = True) -> tuple[str, ...]:
    """Every stage of a reproduction, in order (the rule-based one first)."""
    return (rundir.RULES_DIR, *(TRAINED if monolithic else PAPER_STAGES))


def check_reproduction(
    out: Path, b: Budget, seed: int, optimizer: str, engine: str | None = None
) -> None:
    """``out`` may hold this reproduction or nothing (``UserError`` otherwise);
    ``engine=None`` accepts the one it was started with."""
    if engine is not None and engine not in ENGINES:
        raise UserError(f"unknown engine {engine!r}; choose from {', '.join(ENGINES)}")
    want = {"budget": b.name, "seed": seed, "optimizer": optimizer}
    _check_dir(out, want if engine is None else {**want, "engine": engine})


def start_reproduction(
    out: Path,
    b: Budget,
    seed: int,
    optimizer: str,
    command: str = "",
    engine: str | None = None,
) -> str:
    """Write ``out``'s marker, unless it has one (then it must match); the
    reproduction's engine (``engine``, or the marker's; default:
    :data:`~locustjump.sim.engine.job.DEFAULT_ENGINE`)."""
    check_reproduction(out, b, seed, optimizer, engine)
    if rundir.is_reproduction(out):
        return reproduction_marker(rundir.read_toml(out / rundir.MARKER))["engine"]
    engine = engine or DEFAULT_ENGINE
    rundir.write_toml(
        out / rundir.MARKER,
        {
            "budget": b.name,
            "seed": seed,
            "optimizer": optimizer,
            "engine": engine,
            "population": b.population,
            "generations": {s: b.of(s) for s in TRAINED},
            "command": command
            or single_seed_command(b.name, seed, optimizer, out, engine),
            "locustjump": __version__,
        },
    )
    return engine


def stage_done(out: Path, stage: str, b: Budget) -> bool:
    """Whether ``stage`` of reproduction ``out`` is trained (its budget done,
    or its optimizer stopped early) and evaluated."""
    d = out / stage
    if stage == rundir.RULES_DIR:
        return (d / rundir.RULES_SUMMARY).is_file()
    if not rundir.eval_metrics_path(d).is_file():
        return False
    return (d / rundir.STOP).is_file() or rundir.generations_done(d) >= b.of(stage)


def run_stage(
    out: Path,
    stage: str,
    b: Budget,
    seed: int,
    optimizer: str,
    backend: Backend,
    progress: bool = False,
    log: Callable[[str], None] = print,
    engine: str = DEFAULT_ENGINE,
) -> float | None:
    """Run (or continue) one stage of reproduction ``out``, whose marker exists
    (``engine``: the one it holds) and whose required stages are done; returns
    the best fitness (``None`` for the rule-based stage)."""
    if stage == rundir.RULES_DIR:
        log("[rules] rule-based successive jumping, 3000 steps")
        run_rules_stage(out / rundir.RULES_DIR, backend=backend, engine=engine)
        return None
    d = out / stage
    gens = b.of(stage)
    cfg = TrainConfig(
        stage,
        seed,
        gens,
        params_class(optimizer)(population=b.population),
        lm.LocustParams(),
        engine=engine,
    )
    requires = behaviour_class(stage).requires
    frozen = None
    if requires:
        frozen = rundir.FrozenGenomes.from_runs(
            requires, {s: out / s for s in requires}, cfg.model
        )
    resume = rundir.is_run(d)
    log(f"[{stage}] {'resuming' if resume else 'training'}: {gens} generations")
    res = train(
        cfg, d, resume=resume, backend=backend, progress=progress, frozen=frozen
    )
    if res.stopped:
        why = ", ".join(f"{k} {v}" for k, v in res.stopped.items())
        log(f"[{stage}] the optimizer stopped at generation {res.generation}: {why}")
    t0 = time.perf_counter()
    ev = evaluate_run(d, backend=backend)
    run_cfg, beh, best = rundir.load_run(d)
    extra = reporter_of(beh).extra_evaluation(
        beh, d, best.genome, run_cfg.model, backend=backend, engine=run_cfg.engine
    )
    rundir.write_json(
        rundir.eval_metrics_path(d),
        {**ev.to_dict(), **extra, "eval_wall_s": time.perf_counter() - t0},
    )
    log(f"[{stage}] best fitness {ev.fitness:.6g}")
    return ev.fitness


def finish_reproduction(
    out: Path,
    *,
    backend: Backend | None = None,
    log: Callable[[str], None] = print,
    videos: bool = True,
) -> Path:
    """Videos (``videos``), ``results.md`` and ``report.html`` of ``out``."""
    path = out / rundir.RESULTS
    if videos:
        render_videos(out, backend=backend, log=log)
    rundir.atomic_write_text(path, results_markdown(out))
    log(f"wrote {path}")
    log(f"wrote {write_report(out)}")
    return path


def render_videos(
    out: Path,
    *,
    fps: float = VIDEO_FPS,
    backend: Backend | None = None,
    log: Callable[[str], None] = print,
) -> list[Path]:
    """``<stage>/video.mp4`` for every stage of reproduction ``out`` that has
    none yet; skipped, with the reason logged, where rendering is unavailable."""
    made = []
    for stage in STAGES:
        d = Path(out) / stage
        if not d.is_dir() or (d / rundir.VIDEO).is_file():
            continue
        try:
            made.append(render_run(d, fps=fps, backend=backend))
        except RenderUnavailable as e:
            log(f"videos skipped: {e}")
            break
        log(f"[{stage}] wrote {made[-1]}")
    return made


def replay(
    src: str | os.PathLike,
    out: str | os.PathLike,
    *,
    backend: Backend | None = None,
    force: bool = False,
) -> list[tuple[str, Evaluation]]:
    """Re-simulate the best genome of every stage of reproduction ``src``; write
    the figures and trajectories into ``out/<stage>/`` (``src`` is not
    touched). Returns (stage, evaluation) per stage found."""
    src = Path(src)
    if not rundir.is_reproduction(src):
        raise UserError(f"{src}: not a reproduction directory (no {rundir.MARKER})")
    found = [s for s in TRAINED if (src / s / rundir.BEST).is_file()]
    if not found:
        raise UserError(f"{src}: holds no trained stage yet")
    dest = rundir.check_out_dir(out, force=force)  # made as it is written
    return [
        (s, evaluate_run(src / s, backend=backend, eval_dir=dest / s)) for s in found
    ]
