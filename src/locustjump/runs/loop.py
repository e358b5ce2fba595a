"""The training loop: an optimizer evolves a behaviour's controllers into a
run directory, one generation after another (:class:`Trainer`).

The loop is the EvoJAX ``Trainer(policy, solver, task)`` shape: the optimizer
(:mod:`locustjump.evo`) asks for genomes, the behaviour
(:mod:`locustjump.tasks`) evaluates them on a backend
(:mod:`~locustjump.sim.engine.backends`), the optimizer is told their
fitness, and the run directory (:mod:`locustjump.rundir`) receives a
metrics row, the best genome and a checkpoint every generation.

Resuming from ``checkpoint.npz`` gives a bit-identical result to an
uninterrupted run: the optimizer's whole state is in the checkpoint, the
simulation is deterministic, and what the optimizer keeps (elites) keeps its
fitness. Which run directory a loop may write, new or resumed, is
:func:`~.trainer.train`'s to check.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from tqdm.auto import tqdm

from locustjump import rundir
from locustjump.errors import UserError
from locustjump.evo import Optimizer, QDOptimizer
from locustjump.present.plots import fitness_curves
from locustjump.present.repertoire import archive_figure
from locustjump.rundir import BestGenome
from locustjump.rundir.config import TrainConfig
from locustjump.tasks import Behaviour

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend


@dataclass
class TrainResult:
    out: Path
    generation: int  # generations completed
    best: BestGenome
    wall_s: float  # wall time of this call
    #: why the optimizer stopped before the budget (``Optimizer.stop()``,
    #: also in ``DIR/stop.json``); empty if it did not
    stopped: dict[str, Any] = field(default_factory=dict)


class Trainer:
    """Evolves ``task``'s controllers with ``optimizer``, simulated on
    ``backend``, into run directory ``run_dir`` whose configuration is
    ``cfg`` (EvoJAX's ``Trainer(policy, solver, task)`` shape: the
    collaborators are made by the caller, :func:`train`, and passed in).
    :meth:`run` trains; a checkpoint after every generation makes it
    resumable (:meth:`restore`)."""

    def __init__(
        self,
        task: Behaviour,
        optimizer: Optimizer,
        backend: Backend,
        run_dir: str | os.PathLike[str],
        cfg: TrainConfig,
    ):
        self.beh, self.opt, self.backend = task, optimizer, backend
        self.out, self.cfg = Path(run_dir), cfg
        self.num_params = task.controller.num_params
        self.hash = cfg.hash()
        self.best: BestGenome | None = None
        self.metrics_row = ""  # of the checkpointed generation
        # the optimizer's columns in metrics.csv (a resumed run keeps its own)
        self.diagnostics = tuple(self.opt.diagnostics())

    def checkpoint(self, metrics_row: str) -> None:
        """The optimizer's state, the best genome and this metrics row."""
        assert self.best is not None
        rundir.write_checkpoint(
            self.out / rundir.CHECKPOINT,
            self.cfg,
            self.best,
            metrics_row,
            self.opt.state(),
        )

    def write_archive(self) -> None:
        """``archive.npz``: a QD optimizer's elites (others keep none)."""
        if isinstance(self.opt, QDOptimizer):
            rundir.write_archive(
                self.out / rundir.ARCHIVE, self.cfg, self.opt.archive()
            )

    def restore(self) -> None:
        """Back to the last checkpoint (and the archive of its generation)."""
        path = self.out / rundir.CHECKPOINT
        self.best, self.metrics_row, state = rundir.read_checkpoint(
            path, self.cfg, self.num_params, tuple(self.opt.state())
        )
        try:
            self.opt.load_state(state)
        except (
            ValueError,
            KeyError,
            TypeError,
            AttributeError,
            OverflowError,
            RecursionError,  # the generator's state is JSON text
        ) as e:
            raise UserError(f"{path}: malformed checkpoint ({e})") from None
        self.write_archive()  # killed between the two writes: one behind

    def run(
        self, *, progress: bool = True, stop_after: int | None = None
    ) -> TrainResult:
        """Train to ``cfg.generations`` (``stop_after``: at most this many
        generations in this call; the run stays resumable), or until the
        optimizer stops; ``progress``: a progress bar on stderr."""
        run, backend = self, self.backend
        cfg, opt, beh, p = run.cfg, run.opt, run.beh, run.cfg.model
        t_start = time.perf_counter()
        bar = tqdm(
            total=cfg.generations,
            initial=opt.generation,
            desc=f"{cfg.behaviour}",
            unit="gen",
            disable=not progress,
            dynamic_ncols=True,
        )
        done = 0
        stopped = opt.stop() if opt.generation else {}
        failed = True
        metrics = run.out / rundir.METRICS
        try:
            while (
                not stopped
                and opt.generation < cfg.generations
                and (stop_after is None or done < stop_after)
            ):
                t0 = time.perf_counter()
                x = opt.ask()
                fit, res = beh.evaluate(x, p, backend=backend, engine=cfg.engine)
                names = (
                    opt.descriptor_names
                )  # quality diversity: how, not only how well
                opt.tell(fit, beh.describe(res, p, names) if names else None)
                g = opt.generation
                i = int(np.argmax(fit))
                if run.best is None or fit[i] > run.best.fitness:
                    run.best = BestGenome(
                        x[i].copy(), float(fit[i]), g, cfg.behaviour, run.hash
                    )
                    run.best.save(run.out / rundir.BEST)
                f = opt.fitness
                # floats as shortest round-trip text: the CSV holds exact values
                row = [g, float(f[int(np.argmax(f))]), float(f.mean()), float(f.std())]
                row += [len(x), res.control_steps]
                d = opt.diagnostics()
                diag = [d[k] for k in run.diagnostics]
                # the checkpoint carries its own metrics row (a kill between the
                # two writes loses nothing); wall time covers the whole
                # generation but for this last small write
                wall = time.perf_counter() - t0
                run.checkpoint(
                    rundir.metrics_line(row, wall, res.control_steps / wall, diag)
                )
                run.write_archive()  # after the checkpoint, which can replay it
                wall = time.perf_counter() - t0
                rate = res.control_steps / wall
                # the checkpoint already holds this row: a failed append loses
                # nothing (resume restores it)
                rundir.append_line(metrics, rundir.metrics_line(row, wall, rate, diag))
                done += 1
                stopped = opt.stop()
                bar.set_postfix(
                    best=f"{row[1]:.4g}",
                    mean=f"{row[2]:.4g}",
                    steps_s=f"{rate:,.0f}",
                    refresh=False,
                )
                bar.update(1)
            if stopped:
                rundir.write_json(
                    run.out / rundir.STOP,
                    {"generation": opt.generation, "reasons": stopped},
                )
            failed = False
        finally:
            bar.close()
            try:
                fitness_figure(run.out)
                archive_figure(run.out)
            except Exception:
                if not failed:  # else the first error is the one to report
                    raise
        assert run.best is not None
        return TrainResult(
            run.out, opt.generation, run.best, time.perf_counter() - t_start, stopped
        )


def fitness_figure(out: Path) -> Path:
    """``DIR/fitness.png`` from ``DIR/metrics.csv`` (none before a first row)."""

    m = rundir.read_metrics(out / rundir.METRICS)
    if not len(m):  # stopped within its first generation: nothing to draw
        return out / rundir.FITNESS_PNG
    cfg = rundir.load_config(out / rundir.CONFIG)
    path = out / rundir.FITNESS_PNG
    fitness_curves(
        path, m, title=f"{cfg.behaviour}: fitness per generation (seed {cfg.seed})"
    )
    return path
