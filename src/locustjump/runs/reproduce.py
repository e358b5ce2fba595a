"""The whole paper in one call: every stage in order, resumable, with a results
table. A reproduction (:class:`~locustjump.runs.reproduction.Reproduction`)
is a directory (names in :mod:`locustjump.rundir`)::

    DIR/reproduce.toml    budget, seed, optimizer, generations per stage, command
    DIR/rules/            the rule-based baseline (Fig. 5): trajectory + summary
    DIR/kick/             a run directory + eval/
    DIR/getup/            ... + sweep/ (the 180-state generalisation test)
    DIR/return-legs/
    DIR/composed/         builds on the three runs above (frozen.npz)
    DIR/monolithic/       beyond the paper: one network, same evaluation budget
    DIR/results.md        one row per claim of the paper, figures, wall times

Rerunning the same command continues where it stopped: finished stages are
kept, an interrupted training resumes from its checkpoint (bit-identical).
"""

from __future__ import annotations

import logging
import os
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

from locustjump import rundir
from locustjump.errors import UserError
from locustjump.present.evaluate import Evaluation, evaluate_run
from locustjump.present.render import VIDEO_FPS, check_rendering, render_run
from locustjump.present.report import write_report
from locustjump.present.results import results_markdown
from locustjump.present.video import RenderUnavailable
from locustjump.runs.reproduction import (
    BASELINES,
    BUDGETS,
    PAPER_STAGES,
    STAGES,
    TRAINED,
    Budget,
    Reproduction,
    budget_of,
    stages_of,
)
from locustjump.sim.engine.backends import ThreadBackend
from locustjump.sim.scene import Scene, Terrains

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend

__all__ = [
    "BASELINES",
    "BUDGETS",
    "PAPER_STAGES",
    "STAGES",
    "TRAINED",
    "Budget",
    "Reproduction",
    "budget_of",
    "finish_reproduction",
    "render_videos",
    "replay",
    "reproduce",
    "stages_of",
]

#: progress and diagnostics (the command line shows them; see logging)
_log = logging.getLogger(__name__)


def reproduce(
    out: str | os.PathLike[str],
    *,
    budget: str | Budget = "quick",
    seed: int = 0,
    optimizer: str = "rcga",
    engine: str | None = None,
    backend: Backend | None = None,
    progress: bool = True,
    log: Callable[[str], None] | None = None,
    command: str = "",
    videos: bool = True,
    monolithic: bool = True,
    terrains: Terrains | None = None,
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
    started with, else the default) computes every stage's controllers;
    ``terrains`` (default: the ones ``out`` was started with, else the flat
    floor) is where every stage trains. Several seeds at once, on a cluster
    too: :func:`locustjump.runs.multiseed.reproduce_seeds`. ``log`` takes each
    line of progress (default: this module's logger, at INFO)."""
    log = log or _log.info
    rep = Reproduction.open(
        out, budget, (seed,), optimizer=optimizer, engine=engine, terrains=terrains
    )
    if backend is None:
        backend = ThreadBackend()
    rep.out.mkdir(parents=True, exist_ok=True)
    with rundir.locked(rep.out):
        rep.check()  # another process may have been first
        rep.start(command or rep.command(monolithic=monolithic))
        stages = stages_of(monolithic)
        for k, stage in enumerate(stages, 1):
            if not rep.stage_done(stage):
                rep.run_stage(stage, backend, progress=progress, log=log,
                              of=(k, len(stages)))  # fmt: skip
                rundir.atomic_write_text(
                    rep.out / rundir.RESULTS, results_markdown(rep.out)
                )
            elif stage != rundir.RULES_DIR:
                log(f"[{stage}] done ({rep.budget.of(stage)} generations)")
        return finish_reproduction(
            rep.out, backend=backend, log=log, videos=videos, progress=progress
        )


def finish_reproduction(
    out: Path,
    *,
    backend: Backend | None = None,
    log: Callable[[str], None] | None = None,
    videos: bool = True,
    progress: bool = False,
) -> Path:
    """Videos (``videos``; ``progress``: a bar for each), ``results.md`` and
    ``report.html`` of ``out``; ``log`` takes each line of progress (default:
    this module's logger, at INFO)."""
    log = log or _log.info
    path = out / rundir.RESULTS
    if videos:
        render_videos(out, backend=backend, log=log, progress=progress)
    log(f"writing {rundir.RESULTS} and {rundir.REPORT}")
    rundir.atomic_write_text(path, results_markdown(out))
    log(f"wrote {path}")
    log(f"wrote {write_report(out, out=out / rundir.REPORT)}")
    return path


def render_videos(
    out: Path,
    *,
    fps: float = VIDEO_FPS,
    backend: Backend | None = None,
    log: Callable[[str], None] | None = None,
    progress: bool = False,
) -> list[Path]:
    """``<stage>/video.mp4`` for every stage of reproduction ``out`` that has
    none yet, each announced (``video k of n``) before it is made, with a bar
    over its frames (``progress``; its estimate of the time left); skipped,
    with the reason logged (default: a warning of this module's logger), where
    rendering is unavailable."""
    warn = log or _log.warning
    log = log or _log.info
    todo = [
        s for s in STAGES
        if (Path(out) / s).is_dir() and not (Path(out) / s / rundir.VIDEO).is_file()
    ]  # fmt: skip
    made: list[Path] = []
    try:
        if todo:
            check_rendering()  # before the first re-simulation
    except RenderUnavailable as e:
        warn(f"videos skipped: {e}")
        return made
    for k, stage in enumerate(todo, 1):
        d = Path(out) / stage
        what = f"video {k} of {len(todo)}"
        log(f"[{stage}] rendering {what} (re-simulating its best genome first)")
        try:
            video = render_run(d, d / rundir.VIDEO, fps=fps, backend=backend,
                               progress=progress, label=f"{what}, {stage}")  # fmt: skip
        except RenderUnavailable as e:
            warn(f"videos skipped: {e}")
            break
        made.append(video)
        log(f"[{stage}] wrote {video}")
    return made


def replay(
    src: str | os.PathLike[str],
    out: str | os.PathLike[str],
    *,
    backend: Backend | None = None,
    force: bool = False,
    scene: Scene | None = None,
) -> list[tuple[str, Evaluation]]:
    """Re-simulate the best genome of every stage of reproduction ``src``; write
    the figures and trajectories into ``out/<stage>/`` (``src`` is not
    touched), each in its own scene or in ``scene``. Returns (stage,
    evaluation) per stage found."""
    src = Path(src)
    if not rundir.is_reproduction(src):
        raise UserError(f"{src}: not a reproduction directory (no {rundir.MARKER})")
    found = [s for s in TRAINED if (src / s / rundir.BEST).is_file()]
    if not found:
        raise UserError(f"{src}: holds no trained stage yet")
    with rundir.output_dir(out, force=force) as dest:
        return [
            (s, evaluate_run(src / s, backend=backend, eval_dir=dest / s, scene=scene))
            for s in found
        ]
