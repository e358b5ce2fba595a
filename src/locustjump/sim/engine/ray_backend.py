"""The Ray backend: the episodes of a rollout split across Ray actors
(extra ``locustjump[ray]``), for a cluster or a big machine.

Each actor holds a :class:`~locustjump.sim.engine.backends.ThreadBackend` — a compiled
model and a ``mujoco.batch.Batch`` per episode count — alive across
generations, and steps its contiguous share of the episodes on the CPUs Ray
gives it. Results are put back by episode index, so arrival order does not
matter, and since episodes are independent rows the result is bit-identical to
the thread backend's for any number of actors (tested). An actor that dies is
replaced and its share resubmitted.

Connecting: ``address=None`` starts a local Ray instance (or uses the one this
process already has); ``"auto"`` or ``"HOST:PORT"`` joins a running cluster
(``ray start --head`` there; token authentication stays on, see
docs/guide/ray.md).
"""

from __future__ import annotations

import os
import socket
from types import ModuleType
from typing import Any

from locustjump.errors import UserError, setting_ref
from locustjump.ranges import Range
from locustjump.sim.engine.job import RolloutJob, RolloutResult
from locustjump.sim.engine.threads import THREADS, ThreadBackend

#: ``actors``: Ray actors of one backend (several may share a CPU)
ACTORS = Range(1, 1 << 16, integer=True)

#: seconds to wait for a cluster address to answer before giving up
CONNECT_TIMEOUT = 5.0


def _ray() -> ModuleType:
    try:
        import ray
    except ImportError:
        raise UserError(
            f"{setting_ref('backend')} ray needs Ray: "
            "pip install -e '.[ray]' in the clone"
        ) from None
    return ray


def _check_address(address: str) -> None:
    """Fail fast (seconds, not Ray's minutes) if nobody listens at HOST:PORT."""
    if address in ("auto", "local") or address.startswith("ray://"):
        return
    host, _, port = address.rpartition(":")
    try:
        with socket.create_connection((host, int(port)), timeout=CONNECT_TIMEOUT):
            pass
    except (OSError, ValueError) as e:
        raise UserError(
            f"{setting_ref('address')} {address}: no Ray cluster answers there ({e}); "
            "start one "
            "with `ray start --head` or check HOST:PORT"
        ) from None


class _Worker:
    """A Ray actor's body: one thread backend kept across generations."""

    def __init__(self, threads: int):
        self.backend = ThreadBackend(threads)
        self._pid = os.getpid()

    def pid(self) -> int:
        return self._pid

    def run(self, job: RolloutJob) -> RolloutResult:
        return self.backend.run(job)


def connect(address: str | None = None) -> ModuleType:
    """The ``ray`` module, connected: to this process's instance if it has one,
    else a new local one (``address=None``) or the cluster at ``address``."""
    ray = _ray()
    if ray.is_initialized():
        return ray
    if address is not None:
        _check_address(address)
    try:
        ray.init(
            address=address,
            include_dashboard=False,
            log_to_driver=False,
            configure_logging=False,
        )
    except (ConnectionError, RuntimeError, ValueError) as e:
        msg = str(e).strip().splitlines()[0] if str(e).strip() else repr(e)
        raise UserError(
            f"{setting_ref('address')} {address}: cannot join Ray ({msg})"
        ) from None
    return ray


class RayBackend:
    """Runs each rollout's episodes on Ray actors.

    Args:
      address: ``None`` (a local instance, or this process's), ``"auto"`` or
        ``"HOST:PORT"`` of a running cluster.
      actors: how many actors (default: the cluster's CPUs divided by
        ``threads``, at least 1).
      threads: CPUs (simulation threads) per actor.
    """

    def __init__(
        self,
        address: str | None = None,
        *,
        actors: int | None = None,
        threads: int | None = None,
    ):
        self.threads = THREADS.check("threads", 1 if threads is None else threads)
        if actors is not None:
            actors = ACTORS.check("actors", actors)
        ray = connect(address)
        cpus = int(ray.cluster_resources().get("CPU", 0))
        if cpus < self.threads:
            raise UserError(
                f"the Ray cluster has {cpus} CPUs; an actor asks for {self.threads} "
                f"({setting_ref('threads')} per actor)"
            )
        self.n_actors = actors if actors is not None else max(1, cpus // self.threads)
        # more actors than the cluster has CPUs for share them (Ray allows a
        # fraction): every actor is placed, none waits for a CPU forever
        share = min(float(self.threads), cpus / self.n_actors)
        self._remote = ray.remote(num_cpus=share, max_restarts=0)(_Worker)
        self._actors: list[Any] = []
        #: how many dead actors were replaced so far
        self.replaced = 0

    def _ensure(self) -> list[Any]:
        """Actors are made on the first rollout (EvoTorch's pattern)."""
        while len(self._actors) < self.n_actors:
            self._actors.append(self._remote.remote(self.threads))
        return self._actors

    def _replace(self, i: int) -> Any:
        """A new actor in slot ``i`` for one that died (its node, its process)."""
        self._actors[i] = self._remote.remote(self.threads)
        self.replaced += 1
        return self._actors[i]

    def pids(self) -> list[int]:
        """Process IDs of the live actors (dead ones replaced, missing made)."""
        ray = _ray()
        out = []
        for i, actor in enumerate(self._ensure()):
            try:
                out.append(ray.get(actor.pid.remote()))
            except ray.exceptions.RayActorError:
                out.append(ray.get(self._replace(i).pid.remote()))
        return out

    def close(self) -> None:
        """End the actors now and give their CPUs back to the cluster (they
        also end when this backend is garbage-collected); a later rollout
        makes new ones."""
        ray = _ray()
        for actor in self._actors:
            ray.kill(actor)
        self._actors = []

    def __enter__(self) -> RayBackend:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def run(self, job: RolloutJob) -> RolloutResult:
        ray = _ray()
        actors = self._ensure()
        parts = job.split(len(actors))
        results: list[RolloutResult | None] = [None] * len(parts)
        pending = {actors[i].run.remote(p): i for i, p in enumerate(parts)}
        while pending:
            ready, _ = ray.wait(list(pending), num_returns=1)
            ref = ready[0]
            i = pending.pop(ref)
            try:
                results[i] = ray.get(ref)
            except ray.exceptions.RayActorError:
                # the actor died: a new one gets the same share of episodes
                pending[self._replace(i).run.remote(parts[i])] = i
        return RolloutResult.concat(results)  # type: ignore[arg-type]
