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

from locustjump.errors import UserError, setting_ref
from locustjump.sim.engine.ray_backend import ACTORS, RayBackend
from locustjump.sim.engine.threads import (
    THREADS,
    Backend,
    ThreadBackend,
    default_threads,
)

#: backend names the command line accepts
BACKENDS: tuple[str, ...] = ("threads", "ray")


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
            raise UserError(
                f"{setting_ref('address')} and {setting_ref('actors')} are for "
                f"{setting_ref('backend')} ray"
            )
        return ThreadBackend(threads)
    if name == "ray":
        return RayBackend(address, actors=actors, threads=threads)
    raise ValueError(f"unknown backend {name!r}; choose from {', '.join(BACKENDS)}")


__all__ = ["ACTORS", "BACKENDS", "THREADS", "Backend", "RayBackend",
           "ThreadBackend", "default_threads", "make_backend"]  # fmt: skip
