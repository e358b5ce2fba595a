"""Execution backends: where the episodes of a rollout run, chosen by name.

A backend has one method, ``run(job) -> RolloutResult``; episodes are
independent rows, so every backend gives bit-identical results whatever it
splits or however many workers it uses (tests check it).

===========  ================================================================
name         what
===========  ================================================================
``threads``  one ``mujoco.batch.Batch`` stepped on C threads (the default)
``ray``      the episodes split across Ray actors, each holding a thread
             backend (:mod:`locustjump.sim.engine.ray_backend`, extra ``[ray]``)
===========  ================================================================

Commands take ``--backend NAME`` and ``--threads N`` and build the backend
once with :func:`make_backend`, then pass it down explicitly.
"""

from __future__ import annotations

import os
from typing import Protocol

from mujoco.batch import Batch

from locustjump.sim import model as lm
from locustjump.sim.engine.rollout import RolloutJob, RolloutResult, run_batch

#: backend names the command line accepts
BACKENDS: tuple[str, ...] = ("threads", "ray")


class Backend(Protocol):
    """Runs a :class:`~locustjump.sim.engine.rollout.RolloutJob`; every backend gives
    bit-identical results."""

    def run(self, job: RolloutJob) -> RolloutResult: ...


def default_threads() -> int:
    """Threads to use by default: the CPUs this process may run on."""
    return (
        len(os.sched_getaffinity(0))
        if hasattr(os, "sched_getaffinity")
        else (os.cpu_count() or 1)
    )


class ThreadBackend:
    """Steps all episodes in one ``mujoco.batch.Batch`` on ``threads`` C threads.

    Batches are cached per episode count, so a GA that evaluates the same
    population size every generation builds its batch once.
    """

    def __init__(self, threads: int | None = None):
        self.threads = default_threads() if threads is None else int(threads)
        if self.threads < 1:
            raise ValueError(f"threads must be >= 1, got {threads}")
        self._batches: dict[tuple[lm.LocustParams, int], Batch] = {}

    def _batch(self, p: lm.LocustParams, n: int) -> Batch:
        key = (p, n)
        if key not in self._batches:
            self._batches[key] = Batch(
                lm.load_model(p), n, min(self.threads, n), persistent=True
            )
        return self._batches[key]

    def run(self, job: RolloutJob) -> RolloutResult:
        return run_batch(self._batch(job.model_params, job.n_episodes), job)


def make_backend(
    name: str = "threads",
    *,
    threads: int | None = None,
    address: str | None = None,
    actors: int | None = None,
) -> Backend:
    """The backend called ``name`` (``ValueError`` naming the choices if none).

    Args:
      name: one of :data:`BACKENDS`.
      threads: simulation threads per process (threads: default every CPU
        here; ray: per actor, default 1).
      address: ray: the cluster to join (default: a local instance).
      actors: ray: how many actors (default: the cluster's CPUs / threads).
    """
    if name == "threads":
        if address is not None or actors is not None:
            raise ValueError("--address and --actors are for --backend ray")
        return ThreadBackend(threads)
    if name == "ray":
        from locustjump.sim.engine.ray_backend import RayBackend

        return RayBackend(address, actors=actors, threads=threads)
    raise ValueError(f"unknown backend {name!r}; choose from {', '.join(BACKENDS)}")
