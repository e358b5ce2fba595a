"""``checkpoint.npz``: the optimizer's state after the last generation, with
the run's best genome and that generation's metrics row, so that a kill
between two writes loses nothing. Read back only once every array is what
was written and agrees with the run's ``config.toml``."""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from locustjump.errors import UserError
from locustjump.evo import QDParams
from locustjump.rundir.arrays import genomes, plain, scalar
from locustjump.rundir.config import TrainConfig
from locustjump.rundir.files import save_npz
from locustjump.rundir.layout import BEST, CHECKPOINT, CONFIG, FORMAT
from locustjump.rundir.migrations import (
    RCGA_STATE_BEFORE,
    STATE_PREFIX,
    checkpoint_optimizer,
    checkpoint_state,
)
from locustjump.rundir.reads import load_npz
from locustjump.rundir.run import BestGenome, load_best

#: what a checkpoint holds beside its numbers, at most (bytes: names, the
#: generator's state and the metrics row as text, headers)
_TEXT = 1 << 16

_CHECKPOINT_KEYS = (
    "format",
    "behaviour",
    "config_hash",
    "best_genome",
    "best_fitness",
    "best_generation",
    "metrics_row",
)


def write_checkpoint(
    path: Path,
    cfg: TrainConfig,
    best: BestGenome,
    metrics_row: str,
    state: dict[str, np.ndarray],
) -> None:
    """The optimizer's ``state`` plus the run's best genome and the metrics row
    of the checkpointed generation (a kill between two writes loses nothing)."""
    save_npz(
        path,
        format=np.array(FORMAT),
        behaviour=np.array(cfg.behaviour),
        config_hash=np.array(cfg.hash()),
        optimizer=np.array(cfg.optimizer.kind),
        best_genome=best.genome,
        best_fitness=np.array(best.fitness),
        best_generation=np.array(best.generation),
        metrics_row=np.array(metrics_row),
        **{STATE_PREFIX + k: v for k, v in state.items()},
    )


def checkpoint_bytes(cfg: TrainConfig, num_params: int) -> int:
    """The most bytes of arrays a checkpoint of configuration ``cfg`` holds:
    genomes of ``num_params`` genes (the best, and a population of them, as
    the RCGA keeps), the fitness (and a QD optimizer's descriptors) of every
    genome told, as CMA-ES and QD keep to replay, a QD optimizer's archive
    (a genome, its descriptors, fitness, index and generation a cell), and
    small text (names, the generator's state, the metrics row)."""
    n, g, p = cfg.population, cfg.generations, num_params
    cells = d = 0
    if isinstance(cfg.optimizer, QDParams):
        cells, d = math.prod(cfg.optimizer.cells), len(cfg.optimizer.descriptors)
    told = g * n * (1 + d)
    return _TEXT + 8 * (n * (p + 1) + 2 * p + told + cells * (p + d + 3))


def read_checkpoint(
    path: Path,
    cfg: TrainConfig,
    num_params: int,
    state_keys: tuple[str, ...] | None = None,
) -> tuple[BestGenome, str, dict[str, np.ndarray]]:
    """``(best, metrics_row, state)`` of ``checkpoint.npz``, checked against the
    configuration ``cfg`` (``UserError`` naming the file): no array beyond
    those written (the optimizer's ``state_keys``, if given; else any
    prefixed as its state), none larger than such a checkpoint holds
    (:func:`checkpoint_bytes`, checked before any is inflated), every one of
    the dtype and shape written, finite, of this run, the best genome and the
    metrics row of a generation it has done. Older checkpoints through
    :mod:`~locustjump.rundir.migrations`; the optimizer checks its own state
    (``Optimizer.load_state``)."""
    own = () if state_keys is None else tuple(STATE_PREFIX + k for k in state_keys)
    z = load_npz(
        path,
        _CHECKPOINT_KEYS,
        optional=("optimizer", *RCGA_STATE_BEFORE, *own),
        prefix=STATE_PREFIX if state_keys is None else None,
        max_bytes=checkpoint_bytes(cfg, num_params),
    )
    state = checkpoint_state(z, path)
    if state_keys is not None and "optimizer" in z:
        missing = sorted(set(state_keys) - set(state))
        if missing:
            raise UserError(
                f"{path}: missing {', '.join(STATE_PREFIX + k for k in missing)}"
            )
    behaviour = scalar(z, "behaviour", path, "U")
    if behaviour != cfg.behaviour:
        raise UserError(f"{path}: holds a {behaviour!r} run, not {cfg.behaviour!r}")
    kind = checkpoint_optimizer(z)
    if kind != cfg.optimizer.kind:
        raise UserError(
            f"{path}: was written by the {kind!r} optimizer, the run's "
            f"{CONFIG} names {cfg.optimizer.kind!r}"
        )
    if scalar(z, "config_hash", path, "U") != cfg.hash():
        raise UserError(
            f"{path}: was written by another configuration (hash "
            f"{z['config_hash']}, {CONFIG} has {cfg.hash()})"
        )
    if "generation" not in state:
        raise UserError(f"{path}: missing {STATE_PREFIX}generation")
    plain(state, sorted(state), path)
    generation = scalar(state, "generation", path, "i")
    best = BestGenome(
        genomes(z, "best_genome", path, (num_params,)),
        scalar(z, "best_fitness", path, "f"),
        scalar(z, "best_generation", path, "i"),
        cfg.behaviour,
        cfg.hash(),
    )
    if not 1 <= best.generation <= generation:
        raise UserError(
            f"{path}: best_generation {best.generation} is not one of the "
            f"{generation} generations it has done"
        )
    row = scalar(z, "metrics_row", path, "U")
    if not row.endswith("\n") or row.split(",")[0] != str(generation):
        raise UserError(
            f"{path}: metrics_row is not the row of generation {generation}: "
            f"{row.strip()[:60]!r}"
        )
    return best, row, state


def check_kept_best(
    out: Path, cfg: TrainConfig, num_params: int, held: BestGenome | None, done: int
) -> None:
    """``best.npz`` of run directory ``out``, which a resumed run keeps,
    checked as ``evaluate`` checks it (:func:`~.run.load_best`): it must be
    the best genome ``held`` by the checkpoint of generation ``done``, or a
    better one of the generation after it (saved before a checkpoint that a
    kill stopped; the resumed run recomputes and rewrites it). Without a
    checkpoint (``done`` 0) there may be none yet."""
    path = out / BEST
    if not os.path.lexists(path):
        if done == 0:
            return
        raise UserError(f"{path}: missing, but {CHECKPOINT} holds {done} generations")
    best = load_best(out, cfg, num_params)
    same = held is not None and (
        best.generation == held.generation
        and best.fitness == held.fitness
        and np.array_equal(best.genome, held.genome)
    )
    better = held is None or best.fitness > held.fitness
    if not (same or (best.generation == done + 1 and better)):
        had = "none" if held is None else f"generation {held.generation}'s"
        raise UserError(
            f"{path}: generation {best.generation}'s best (fitness "
            f"{best.fitness:.6g}) is not the best genome {CHECKPOINT} holds "
            f"({had}; nothing changed)"
        )
