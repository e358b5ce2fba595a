"""Training into a run directory: :func:`train` checks a new run (before it
writes anything) or a resumed one (its configuration must continue the run),
makes its directory or restores its checkpoint, and runs the training loop
(:class:`~.loop.Trainer`, importable from here).

A new run leaves no half-made directory behind whatever stops it; a resumed
one records a changed budget only once every check has passed.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from locustjump import rundir
from locustjump.errors import UserError, setting_ref
from locustjump.evo import Optimizer, make_optimizer
from locustjump.ranges import INT64_MAX, Range
from locustjump.rundir import FrozenGenomes
from locustjump.rundir.config import TrainConfig
from locustjump.runs.loop import Trainer as Trainer
from locustjump.runs.loop import TrainResult as TrainResult
from locustjump.runs.loop import fitness_figure as fitness_figure
from locustjump.sim import model as lm
from locustjump.sim.engine.backends import ThreadBackend
from locustjump.sim.engine.rollout import rollout_bytes
from locustjump.sim.resources import require_memory
from locustjump.tasks import Behaviour, behaviour_class, get_behaviour

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend

#: the settings the errors here name (the command line prints its options)
OUT, RESUME = setting_ref("out"), setting_ref("resume", True)
#: ``stop_after``: generations of one call (a run stopped before its first has
#: no best genome to return)
STOP_AFTER = Range(1, INT64_MAX, integer=True)


def train(
    cfg: TrainConfig,
    out: str | os.PathLike[str],
    *,
    resume: bool = False,
    backend: Backend | None = None,
    progress: bool = True,
    stop_after: int | None = None,
    frozen: FrozenGenomes | None = None,
) -> TrainResult:
    """Evolve ``cfg.behaviour`` with ``cfg.optimizer`` into run directory ``out``.

    Args:
      cfg: the configuration; with ``resume`` it must equal the run's
        ``config.toml`` except for ``generations`` (a run can be extended).
      out: the run directory; a new run needs it absent or empty.
      resume: continue the run in ``out`` from its checkpoint.
      backend: where episodes run (default: a thread backend on every CPU).
      progress: show a progress bar (on stderr).
      stop_after: stop after this many generations in this call, at least 1
        (the run stays resumable; used to test interruption).
      frozen: behaviours that build on other runs (composed): the frozen
        genomes of those runs (required for a new run; on resume, if given,
        they must be the run's own).

    Returns:
      The directory, the generations completed and the best genome.
    """
    out = Path(out)
    if stop_after is not None:
        STOP_AFTER.check("stop_after", stop_after)
    cls = behaviour_class(cfg.behaviour)
    if cls.requires and frozen is not None:
        if cfg.frozen_digest not in ("", frozen.digest):
            raise UserError(
                f"the frozen genomes (digest {frozen.digest}) are not the ones the "
                f"configuration names ({cfg.frozen_digest})"
            )
        cfg = cfg.replace(frozen_digest=frozen.digest)
    if backend is None:
        backend = ThreadBackend()
    if resume:
        if not rundir.is_run(out):
            raise UserError(f"{RESUME}: {out} holds no run (no {rundir.CONFIG})")
        with rundir.locked(out):
            run = _resume(out, cfg, backend, bool(cls.requires))
            return run.run(progress=progress, stop_after=stop_after)
    run = _check_new(out, cfg, cls, frozen, backend)
    made = rundir.make_dir(out)
    with rundir.locked(out):
        _check_new(out, cfg, cls, frozen, backend)  # another process was first?
        try:
            _create(run, frozen)
        except BaseException:  # a full disk, Ctrl-C: no half-made run is left
            rundir.remove_made(made)
            raise
        return run.run(progress=progress, stop_after=stop_after)


def _check_new(
    out: Path,
    cfg: TrainConfig,
    cls: type[Behaviour],
    frozen: FrozenGenomes | None,
    backend: Backend,
) -> Trainer:
    """Check everything a new run needs, writing nothing. A directory that
    holds only what a new run writes before its ``config.toml`` (one stopped
    then) counts as empty: the same command starts it again."""
    rundir.check_out_dir(out, force=True)  # a directory, or nothing yet
    if out.is_dir() and any(out.iterdir()) and not rundir.is_unstarted(out):
        what = "holds a run" if rundir.is_run(out) else "is not empty"
        raise UserError(
            f"{OUT} {out}: directory {what} (use {RESUME} to continue a run, or "
            f"choose another {OUT})"
        )
    if cls.requires and frozen is None:
        raise UserError(
            f"train {cfg.behaviour} needs the runs it builds on ("
            + " ".join(
                f"{setting_ref(rundir.frozen_setting(r))} DIR" for r in cls.requires
            )
            + ")"
        )
    lm.check_model(cfg.model)
    built_on = frozen.genomes if frozen is not None and cls.requires else None
    beh = get_behaviour(cfg.behaviour, built_on, cfg.options, cfg.scene)

    require_memory(
        rollout_bytes(
            lm.load_model(cfg.model, beh.scene),
            cfg.population * len(beh.start_states(cfg.model)) * cfg.scene.count,
            beh.n_steps, beh.record,
        ),
        f"a generation of {cfg.population:,} genomes",
        setting=("population", cfg.population),
    )  # fmt: skip
    # the controller and optimizer are checked here
    run = Trainer(beh, _optimizer(cfg, beh), backend, out, cfg)
    try:  # the first genomes (ask() holds them until tell())
        genomes = run.opt.ask()
    except (ValueError, OverflowError, FloatingPointError) as e:
        raise UserError(f"[optimizer]: cannot make the first genomes ({e})") from None
    if not np.isfinite(genomes).all():
        raise UserError("[optimizer]: the first genomes are not finite")
    return run


def _optimizer(cfg: TrainConfig, task: Behaviour) -> Optimizer:
    return make_optimizer(cfg.optimizer, task.controller.num_params, cfg.seed)


def _create(run: Trainer, frozen: FrozenGenomes | None) -> None:
    """The files of a new run directory (in place of what one stopped before
    its ``config.toml`` left, :func:`~locustjump.rundir.is_unstarted`)."""
    for leftover in run.out.iterdir():
        leftover.unlink()
    if run.beh.requires:
        assert frozen is not None  # _check_new refused a run without them
        frozen.save(run.out / rundir.FROZEN)
    rundir.write_config(run.out / rundir.CONFIG, run.cfg)
    rundir.truncate_metrics(run.out / rundir.METRICS, 0, "", run.diagnostics)


def _resume(out: Path, cfg: TrainConfig, backend: Backend, builds_on: bool) -> Trainer:
    """Check that ``cfg`` continues the run in ``out``, restore it, and only
    then record a changed budget."""
    stored = rundir.load_config(out / rundir.CONFIG)
    if builds_on and not cfg.frozen_digest:
        cfg = cfg.replace(frozen_digest=stored.frozen_digest)
    if stored.behaviour != cfg.behaviour:
        raise UserError(
            f"{RESUME}: {out} holds a {stored.behaviour!r} run, not {cfg.behaviour!r}"
        )
    if stored.optimizer.kind != cfg.optimizer.kind:
        raise UserError(
            f"{RESUME}: {out} was trained with the {stored.optimizer.kind!r} "
            f"optimizer, not {cfg.optimizer.kind!r}"
        )
    diff = _differences(cfg.to_dict(), stored.to_dict())
    if diff:
        key, mine, theirs = diff[0]
        more = f" (and {len(diff) - 1} more)" if len(diff) > 1 else ""
        raise UserError(
            f"{RESUME}: {key} {_shown(mine)} differs from the run's {key} "
            f"{_shown(theirs)} ({out / rundir.CONFIG}){more}"
        )
    beh = rundir.behaviour_of(cfg, out)
    run = Trainer(beh, _optimizer(cfg, beh), backend, out, cfg)
    if os.path.lexists(out / rundir.CHECKPOINT):
        run.restore()
    if cfg.generations < run.opt.generation:
        raise UserError(
            f"{setting_ref('generations')} {cfg.generations}: the run in {out} has "
            "already done "
            f"{run.opt.generation} (a run can be extended, not shortened)"
        )
    rundir.check_kept_best(
        out, cfg, run.num_params, run.best, run.opt.generation
    )  # as evaluate checks it
    _keep_metrics_columns(run)
    rundir.truncate_metrics(
        out / rundir.METRICS, run.opt.generation, run.metrics_row, run.diagnostics
    )
    if stored.generations != cfg.generations:
        rundir.write_config(out / rundir.CONFIG, cfg)
    return run


def _differences(
    mine: dict[str, Any], theirs: dict[str, Any], prefix: str = ""
) -> list[tuple[str, Any, Any]]:
    """(key, mine, theirs) of every config value that differs but the
    budget, tables flattened to dotted keys."""
    out = []
    for k in sorted({*mine, *theirs} - {"generations", "format"}):
        a, b = mine.get(k), theirs.get(k)
        if isinstance(a, dict) and isinstance(b, dict):
            out += _differences(a, b, f"{prefix}{k}.")
        elif a != b:
            out.append((f"{prefix}{k}", a, b))
    return out


def _shown(v: Any) -> str:
    if isinstance(v, list):
        return ",".join(map(str, v)) or "none"
    return "none" if v is None else str(v)


def _keep_metrics_columns(run: Trainer) -> None:
    """A resumed run goes on with the columns its metrics.csv has (one
    started before its optimizer had diagnostics has none, and so has the
    checkpoint's metrics row if the file is gone)."""
    path = run.out / rundir.METRICS
    columns = rundir.metrics_extra_columns(path)
    if columns is None:
        if run.metrics_row.count(",") + 1 == len(rundir.METRICS_COLUMNS):
            run.diagnostics = ()
        return
    unknown = [c for c in columns if c not in run.diagnostics]
    if unknown:
        raise UserError(
            f"{path}: column {unknown[0]!r} is not a diagnostic of the "
            f"{run.cfg.optimizer.kind!r} optimizer"
        )
    run.diagnostics = columns
