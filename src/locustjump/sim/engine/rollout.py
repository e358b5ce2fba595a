"""``rollout``: every controller from every start state, on a backend.

The entry point of the engine: it checks the memory a rollout needs, builds
the :class:`~.job.RolloutJob` (controller-major episodes) and hands it to a
backend (:mod:`~.backends`), which steps it with :func:`~.strategies.run_batch`
(the job's engine strategy).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from locustjump.sim import model as lm
from locustjump.sim.controller import Controller
from locustjump.sim.engine.backends import Backend, ThreadBackend
from locustjump.sim.engine.job import (
    DEFAULT_ENGINE,
    ENGINES,
    N_STEPS,
    RECORDABLE,
    RolloutJob,
    RolloutResult,
    StartStates,
    observer,
    rollout_bytes,
)
from locustjump.sim.engine.strategies import run_batch
from locustjump.sim.resources import require_memory
from locustjump.sim.scene import Flat, Scene

__all__ = [
    "DEFAULT_ENGINE",
    "ENGINES",
    "RECORDABLE",
    "RolloutJob",
    "RolloutResult",
    "StartStates",
    "observer",
    "rollout",
    "rollout_bytes",
    "run_batch",
]


def rollout(
    controller: Controller,
    params: np.ndarray,
    starts: StartStates,
    n_steps: int,
    *,
    model_params: lm.LocustParams = lm.LocustParams(),
    record: Sequence[str] = ("qpos", "obs"),
    backend: Backend | None = None,
    label: str = "",
    engine: str = DEFAULT_ENGINE,
    scene: Scene = Flat(),
) -> RolloutResult:
    """Evaluate every controller from every start state.

    Args:
      controller: the batched controller (e.g. ``MLP()``).
      params: (n_ctrl, num_params) one parameter row per controller.
      starts: k start states.
      n_steps: control steps per episode (1/120 s each).
      model_params: the creature.
      record: fields to record per control step (see ``RECORDABLE``).
      backend: where to run (:mod:`locustjump.sim.engine.backends`); default: a new
        thread backend on every CPU, for this call only.
      label: show a progress bar over the control steps with this label
        (on a terminal).
      engine: how the controllers are computed between physics calls
        (``ENGINES``).
      scene: the world (:mod:`locustjump.sim.scene`; default: the flat floor).

    Raises:
      UserError: the rollout would not fit in the memory available.

    Returns:
      A :class:`RolloutResult` with ``n_ctrl * k`` episodes, controller-major:
      episode ``c * k + s`` is controller ``c`` from start state ``s``.
    """
    n_steps = N_STEPS.check("n_steps", n_steps)
    params = np.atleast_2d(np.asarray(params, dtype=np.float64))
    k = len(starts)
    require_memory(
        rollout_bytes(
            lm.load_model(model_params, scene), params.shape[0] * k, n_steps,
            record,
            controller.memory_size,
        ),
        f"a rollout of {params.shape[0] * k:,} episodes x {n_steps:,} steps",
        setting=("n_steps", n_steps),
    )  # fmt: skip
    job = RolloutJob(
        model_params,
        controller,
        np.repeat(params, k, axis=0),
        starts.take(np.tile(np.arange(k), params.shape[0])),
        n_steps,
        tuple(record),
        label,
        engine,
        scene,
    )
    if backend is None:
        with ThreadBackend() as own:
            return own.run(job)
    return backend.run(job)
