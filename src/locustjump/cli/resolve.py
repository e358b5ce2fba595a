"""``locustjump train``'s options resolved into the configuration it runs."""

from __future__ import annotations

import dataclasses
import os
from pathlib import Path

from locustjump import rundir
from locustjump.errors import UserError
from locustjump.evo import params_class
from locustjump.rundir.config import TrainConfig


def resolve_config(
    behaviour: str,
    out: str | os.PathLike,
    *,
    resume: bool = False,
    config: str | os.PathLike | None = None,
    optimizer: str | None = None,
    seed: int | None = None,
    population: int | None = None,
    generations: int | None = None,
    engine: str | None = None,
    switch_every: int | None = None,
    score_substeps: tuple[int, ...] | None = None,
) -> TrainConfig:
    """The configuration ``locustjump train`` runs: a resumed run's own
    ``config.toml``, or the defaults overridden by a ``config`` file, and then
    by the options given (resuming, :func:`~locustjump.runs.trainer.train`
    refuses any that differ from the run's but ``generations``, which may
    extend it)."""

    if resume:  # the run's own config; the trainer checks what differs
        if config is not None:
            raise UserError("--resume reads the run's own config.toml; drop --config")
        path = Path(out) / rundir.CONFIG
        if not path.is_file():
            stopped = Path(out).is_dir() and rundir.is_unstarted(Path(out))
            raise UserError(
                f"--resume: {out} holds no run (no {rundir.CONFIG})"
                + ("; it was stopped before it started: rerun without --resume"
                   if stopped else "")
            )  # fmt: skip
        cfg = rundir.load_config(path)
        if cfg.behaviour != behaviour:  # the command's behaviour, not an option
            raise UserError(
                f"--resume: {out} holds a {cfg.behaviour!r} run, not {behaviour!r}"
            )
    else:
        cfg = TrainConfig(behaviour=behaviour)
        if config is not None:
            cfg = rundir.load_config(config, behaviour=behaviour)
            if cfg.behaviour != behaviour:
                raise UserError(
                    f"{config}: behaviour {cfg.behaviour!r} differs from the "
                    f"command's {behaviour!r}"
                )
    # the options given, over either
    if optimizer is not None and optimizer != cfg.optimizer.kind:
        try:
            cfg = cfg.replace(optimizer=params_class(optimizer)())
        except ValueError as e:
            raise UserError(f"--optimizer: {e}") from None
    if seed is not None:
        cfg = cfg.replace(seed=seed)
    if engine is not None:
        cfg = cfg.replace(engine=engine)
    if switch_every is not None:
        if not hasattr(cfg.options, "switch_every"):
            raise UserError(
                f"--switch-every: only the composed behaviour switches, "
                f"not {behaviour!r}"
            )
        opts = _checked("--switch-every", dataclasses.replace, cfg.options,
                        switch_every=switch_every)  # fmt: skip
        cfg = cfg.replace(options=opts)
    if score_substeps is not None:
        opts = _checked("--score-substeps", dataclasses.replace, cfg.options,
                        score_substeps=score_substeps)  # fmt: skip
        cfg = cfg.replace(options=opts)
    if population is not None:
        opt = _checked("--population", cfg.optimizer.replace, population=population)
        cfg = cfg.replace(optimizer=opt)
    if generations is not None:
        cfg = cfg.replace(generations=generations)
    return cfg


def _checked(option: str, make, *args, **changes):
    """``make(*args, **changes)``, its ``ValueError`` as a one-line error
    naming ``option``."""
    try:
        return make(*args, **changes)
    except ValueError as e:
        raise UserError(f"{option}: {e}") from None
