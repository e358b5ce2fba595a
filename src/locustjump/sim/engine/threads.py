"""The thread backend: every episode of a job in one ``mujoco.batch.Batch``,
stepped on C threads; the :class:`Backend` protocol every backend follows."""

from __future__ import annotations

import os
from typing import Protocol

from mujoco.batch import Batch

from locustjump.ranges import Range
from locustjump.sim import model as lm
from locustjump.sim.engine.job import RolloutJob, RolloutResult
from locustjump.sim.engine.strategies import run_batch
from locustjump.sim.scene import Scene


class Backend(Protocol):
    """Runs a :class:`~locustjump.sim.engine.job.RolloutJob`; every backend
    gives bit-identical results. It holds its workers until :meth:`close`
    (also a context manager)."""

    def run(self, job: RolloutJob) -> RolloutResult: ...

    def close(self) -> None: ...

    def __enter__(self) -> Backend: ...

    def __exit__(self, *exc: object) -> None: ...


def default_threads() -> int:
    """Threads to use by default: the CPUs this process may run on."""
    return (
        len(os.sched_getaffinity(0))
        if hasattr(os, "sched_getaffinity")
        else (os.cpu_count() or 1)
    )


#: ``threads``: simulation threads of a process (more than its episodes or
#: its CPUs gain nothing)
THREADS = Range(1, 1 << 16, integer=True)


class ThreadBackend:
    """Steps all episodes in one ``mujoco.batch.Batch`` on ``threads`` C threads.

    Batches are cached per episode count, so a GA that evaluates the same
    population size every generation builds its batch once.
    """

    def __init__(self, threads: int | None = None):
        if threads is None:
            threads = default_threads()
        self.threads = THREADS.check("threads", threads)
        self._batches: dict[tuple[lm.LocustParams, Scene, int], Batch] | None = {}

    def _batch(self, p: lm.LocustParams, scene: Scene, n: int) -> Batch:
        assert self._batches is not None  # run() refuses a closed backend
        key = (p, scene, n)
        if key not in self._batches:
            self._batches[key] = Batch(
                lm.load_model(p, scene), n, min(self.threads, n), persistent=True
            )
        return self._batches[key]

    def run(self, job: RolloutJob) -> RolloutResult:
        if self._batches is None:
            raise RuntimeError("this ThreadBackend is closed")
        return run_batch(self._batch(job.model_params, job.scene, job.n_episodes), job)

    def close(self) -> None:
        """Release the cached batches (their simulations and threads); a
        closed backend runs nothing more."""
        self._batches = None

    def __enter__(self) -> ThreadBackend:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
