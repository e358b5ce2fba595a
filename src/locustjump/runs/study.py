"""A study: every run of a study file (:mod:`~locustjump.runs.studyfile`)
trained into its own run directory, resumably, and what it costs.

``run_study`` trains each (arm, seed) in turn — seed by seed, every arm after
the arms it builds on — with :func:`~locustjump.runs.trainer.train`: a run
that is finished is kept, one that was stopped continues from its
checkpoint, so a killed study continues with the same command; several
processes started on one study share its runs (see ``run_study``). Each run is
an ordinary run directory (``evaluate``, ``report``, ``compare`` read it);
its result depends on its configuration only, so the same study gives
bit-identical runs on threads or on Ray (``backend``). What is done and what
is left, and what it costs: :mod:`~locustjump.runs.study_plan`.
"""

from __future__ import annotations

import logging
import os
import shutil
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from locustjump import rundir
from locustjump.errors import UserError
from locustjump.rundir import FrozenGenomes
from locustjump.rundir.config import TrainConfig
from locustjump.runs.studyarms import Arm
from locustjump.runs.studyfile import Study
from locustjump.runs.trainer import train
from locustjump.tasks import Behaviour, behaviour_class, get_behaviour

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend

#: seconds between looks at the runs other processes train (run_study)
POLL_S = 30.0

#: progress and diagnostics (the command line shows them; see logging)
_log = logging.getLogger(__name__)


@dataclass(frozen=True)
class RunState:
    """One (arm, seed) of a study: where, how far, and what it costs."""

    arm: str
    seed: int
    path: Path
    done: int  # generations completed
    generations: int  # the arm's budget
    steps_per_generation: int  # control steps of a generation (all evaluated)
    eval_steps: int  # control steps of scoring its best genome (the evaluation)

    @property
    def finished(self) -> bool:
        return self.done >= self.generations or (self.path / rundir.STOP).is_file()

    @property
    def status(self) -> str:
        if self.finished:
            return "done"
        return f"{self.done}/{self.generations}" if self.done else "to do"

    @property
    def steps_left(self) -> int:
        if self.finished:
            return 0
        return (self.generations - self.done) * self.steps_per_generation


def behaviour_for(cfg: TrainConfig) -> Behaviour:
    """``cfg``'s behaviour, with placeholder frozen genomes where it builds on
    runs (enough to know its episodes, not to score it)."""
    cls = behaviour_class(cfg.behaviour)
    frozen = None
    if cls.requires:
        names = cls.frozen_names(cfg.options)
        frozen = np.zeros((len(names), cls.frozen_num_params()))
    return get_behaviour(cfg.behaviour, frozen, cfg.options, cfg.scene)


def episode_steps(cfg: TrainConfig, beh: Behaviour | None = None) -> int:
    """Control steps to score one genome in training: start states x
    terrains x episode, once more at each resolution of the option
    ``score_substeps`` (the genome is scored as its worst of them)."""
    beh = behaviour_for(cfg) if beh is None else beh
    resolutions = 1 + len(beh.options.score_substeps)
    return (
        len(beh.start_states(cfg.model)) * cfg.scene.count * beh.n_steps * resolutions
    )


def score_steps(
    study: Study, cfg: TrainConfig, beh: Behaviour
) -> dict[int | None, int]:
    """Control steps of scoring one run of ``cfg`` at each of the study's
    resolutions: on the held-out terrains, or on its own (all of them); as
    trained (None), a run with ``score_substeps`` re-simulates those too."""
    ev = study.evaluation
    terrains = len(ev.terrain_seeds) if ev.terrain_seeds else cfg.scene.count
    one = len(beh.start_states(cfg.model)) * beh.n_steps * terrains
    extra = len(beh.options.score_substeps)
    return {s: one * (1 + extra * (s is None)) for s in ev.substeps}


def generations_done(path: Path) -> int:
    """Generations in the run directory ``path`` (0 if there is none)."""
    if not rundir.is_run(path) or not (path / rundir.METRICS).is_file():
        return 0
    return len(rundir.read_metrics(path / rundir.METRICS))


def states(study: Study) -> list[RunState]:
    """Every run of ``study``, in the order :func:`run_study` trains them."""
    per_eval: dict[str, tuple[int, int]] = {}
    out = []
    for arm, seed in study.runs():
        if arm.name not in per_eval:
            cfg = arm.config(seed)
            beh = behaviour_for(cfg)
            score = sum(score_steps(study, cfg, beh).values()) * arm.score
            per_eval[arm.name] = (cfg.population * episode_steps(cfg, beh), score)
        gen, score = per_eval[arm.name]
        path = arm.run_dir(seed)
        done = generations_done(path)
        source = arm.source_dir(seed)
        if source is not None and not rundir.is_run(path):
            done = generations_done(source)  # what its copy will bring
        out.append(RunState(arm.name, seed, path, done,
                            arm.base.generations, gen, score))  # fmt: skip
    return out


def check_run(study: Study, arm: Arm, seed: int) -> None:
    """``UserError`` if the run of ``arm`` and ``seed`` exists with another
    configuration than the study declares (every differing key named), or
    was built on other runs than the ones the study names; likewise the run
    it extends, if it extends one and has not copied it yet, which must be
    finished and hold its checkpoint."""
    path, source = arm.run_dir(seed), arm.source_dir(seed)
    if source is not None and not rundir.is_run(path):
        what = f"arm {arm.name!r}, seed {seed} extends {source}"
        if not rundir.is_run(source):
            raise UserError(f"{what}: no run there")
        if not (source / rundir.CHECKPOINT).is_file():
            raise UserError(
                f"{what}: it holds no {rundir.CHECKPOINT} to continue from "
                "(a shipped run keeps none)"
            )
        have = rundir.load_config(source / rundir.CONFIG).generations
        if (source / rundir.STOP).is_file():
            raise UserError(f"{what}: its optimizer stopped it early "
                            f"({rundir.STOP}): it cannot be continued")  # fmt: skip
        if generations_done(source) < have:
            raise UserError(f"{what}: not finished ({generations_done(source)} of "
                            f"{have} generations)")  # fmt: skip
        if have >= arm.base.generations:
            raise UserError(f"{what}: it has {have} generations; the arm's "
                            f"{arm.base.generations} must be more")  # fmt: skip
        _check_config(study, arm, seed, source)
    elif rundir.is_run(path):
        _check_config(study, arm, seed, path)


def _check_config(study: Study, arm: Arm, seed: int, path: Path) -> None:
    have = rundir.load_config(path / rundir.CONFIG)
    want = arm.config(seed)
    mine, theirs = want.to_dict(), have.to_dict()
    for d in (mine, theirs):
        d.pop("frozen_digest", None)
        d.pop("generations")
    diff = sorted(_differences(mine, theirs))
    if diff:
        raise UserError(
            f"{path}: not the run {study.source} declares for arm {arm.name!r}, "
            f"seed {seed}: {', '.join(diff)} differ"
        )
    if have.generations > want.generations:
        raise UserError(
            f"{path}: has {have.generations} generations, arm {arm.name!r} "
            f"declares {want.generations}"
        )
    if arm.frozen:
        frozen = frozen_genomes(study, arm, seed)
        if frozen.digest != have.frozen_digest:
            raise UserError(
                f"{path}: built on other runs than arm {arm.name!r} names for seed "
                f"{seed} (" + ", ".join(str(p) for p in frozen.sources) + ")"
            )


def _differences(a: dict[str, Any], b: dict[str, Any], prefix: str = "") -> list[str]:
    out: list[str] = []
    for k in sorted(set(a) | set(b)):
        x, y = a.get(k), b.get(k)
        if isinstance(x, dict) and isinstance(y, dict):
            out += _differences(x, y, f"{prefix}{k}.")
        elif x != y:
            out.append(f"{prefix}{k}")
    return out


def frozen_genomes(study: Study, arm: Arm, seed: int) -> FrozenGenomes:
    """The best genomes of the runs ``arm`` builds on, for ``seed``."""
    dirs = {}
    for behaviour, other in arm.frozen.items():
        path = study.arms[other].run_dir(seed)
        if not (path / rundir.BEST).is_file():
            raise UserError(
                f"arm {arm.name!r}, seed {seed}: the {behaviour} run it builds on "
                f"({path}, arm {other!r}) has no best genome yet"
            )
        dirs[behaviour] = path
    cfg = arm.config(seed)
    cls = behaviour_class(cfg.behaviour)
    return FrozenGenomes.from_runs(
        cls.requires, dirs, cfg.model, cls.frozen_num_params(),
        cls.frozen_elites(cfg.options),
    )  # fmt: skip


def run_study(
    study: Study,
    *,
    backend: Backend | None = None,
    progress: bool = True,
    log: Callable[[str], None] | None = None,
    poll: float = POLL_S,
) -> list[RunState]:
    """Train every run of ``study`` that is not finished (see the module's
    docstring); every existing run is checked first (:func:`check_run`), so
    a wrong study file stops before anything is trained. Returns the final
    states. ``log`` takes each line of progress (default: this module's
    logger, at INFO).

    Several processes may train one study at once (on one machine, or on
    several that share its directories): each takes, in order, the next run
    that no other process holds (:func:`~locustjump.rundir.in_use`) and whose
    frozen runs are finished, and when none is left to take but others are
    still training it looks again every ``poll`` seconds, so each returns
    when the whole study is done."""
    log = log or _log.info
    todo = states(study)
    for st in todo:
        check_run(study, study.arms[st.arm], st.seed)
    left = [st for st in todo if not st.finished]
    total = sum(st.steps_left for st in left)
    log(f"study {study.name}: {len(todo) - len(left)} of {len(todo)} runs done, "
        f"{len(left)} to train ({format_steps(total)} control steps)")  # fmt: skip
    t0, k, waiting, trained = time.perf_counter(), 0, False, set()
    while left:
        run, held = _next_run(study, left)
        if run is None:  # everything left is another process's, or waits on it
            if not waiting:
                log(f"waiting for {len(held)} run(s) other processes train: "
                    + ", ".join(held))  # fmt: skip
            waiting = True
            time.sleep(poll)
        else:
            st, waiting, k = run, False, k + 1
            arm = study.arms[st.arm]
            rest = sum(s.steps_left for s in left)
            eta = ""
            if rest < total:  # the study's pace, whoever trained
                rate = (total - rest) / (time.perf_counter() - t0)
                eta = f", about {format_duration(rest / rate)} left"
            log(f"[{k}] {st.arm}, seed {st.seed} -> {st.path} ({st.status}{eta})")
            if st.path in trained:  # train returned, yet the run is unfinished
                raise RuntimeError(f"{st.path}: not finished after training it")
            try:
                _copy_source(arm, st.seed, st.path)
                train(
                    arm.config(st.seed), st.path, resume=rundir.is_run(st.path),
                    backend=backend, progress=progress,
                    frozen=frozen_genomes(study, arm, st.seed) if arm.frozen else None,
                )  # fmt: skip
                trained.add(st.path)
            except UserError as e:  # InUse: another process took it first
                if not isinstance(e, rundir.InUse) and not rundir.in_use(st.path):
                    raise  # (or made it between our look and our lock)
                log(f"{st.arm}, seed {st.seed}: left to its trainer ({e})")
        left = [s for s in states(study) if not s.finished]
    return states(study)


def _copy_source(arm: Arm, seed: int, path: Path) -> None:
    """If ``arm`` extends runs and ``path`` is not made yet, make it a copy of
    the run it extends: whole (checkpoints included), or not at all."""
    source = arm.source_dir(seed)
    if source is None or os.path.lexists(path):
        return
    path.parent.mkdir(parents=True, exist_ok=True)
    # a finished run is not written but for derived files (eval/, a report),
    # which a reader may be making: their temporary files are left out
    tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.copy-", dir=path.parent))
    try:
        shutil.copytree(source, tmp, symlinks=True, dirs_exist_ok=True,
                        ignore=shutil.ignore_patterns(".*"))  # fmt: skip
        os.rename(tmp, path)
        return
    except OSError:
        if not rundir.is_run(path):  # not another process's copy, made first
            shutil.rmtree(tmp, ignore_errors=True)
            raise
    except BaseException:  # half a copy is never left (Ctrl-C included)
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    shutil.rmtree(tmp, ignore_errors=True)  # train takes the other's copy


def _next_run(study: Study, left: list[RunState]) -> tuple[RunState | None, list[str]]:
    """The first of ``left`` that no other process holds and whose frozen
    runs are finished, or ``None`` and the runs other processes hold."""
    todo = {s.path.resolve() for s in left}
    held = []
    for st in left:
        who = rundir.in_use(st.path)
        if who:
            held.append(f"{st.arm} seed {st.seed} ({who})")
            continue
        built_on = study.arms[st.arm].frozen.values()
        if all(study.arms[a].run_dir(st.seed).resolve() not in todo for a in built_on):
            return st, held
    return None, held


def format_steps(n: float) -> str:
    return f"{n / 1e6:.1f} M" if n >= 1e6 else f"{n:,.0f}"


def format_duration(seconds: float) -> str:
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 90 * 60:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"
