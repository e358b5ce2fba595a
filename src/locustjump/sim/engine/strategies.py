"""Engine strategies: how a rollout's control steps run on a batch, by name.

==============  ===============================================================
name            what runs between two physics calls
==============  ===============================================================
``numpy``       the NumPy control step from Python
                (:mod:`~.numpy_step`; the reference)
``numba-loop``  one compiled kernel call from Python (:mod:`~.compiled`)
``numba``       the compiled control step inside MuJoCo's control callback,
                on the batch's threads (:mod:`~.incallback`; falls back to
                ``numba-loop``)
==============  ===============================================================

The first two are the engine's one loop (:func:`~.loop.run_steps`) with a
:class:`~.loop.ControlStep` plugged in; the third moves that step into the
physics. A job names its strategy (:func:`~.job.strategy_name`) and
:func:`run_batch` runs it; a new strategy (an accelerator's, say) is a
function following :class:`Strategy`, added to :data:`STRATEGIES`.
"""

from __future__ import annotations

from typing import Protocol

from mujoco.batch import Batch

from locustjump.sim.engine.compiled import run_compiled
from locustjump.sim.engine.incallback import run_incallback
from locustjump.sim.engine.job import RolloutJob, RolloutResult, strategy_name
from locustjump.sim.engine.numpy_step import run_numpy


class Strategy(Protocol):
    """Runs every episode of a job: ``strategy(batch, job) -> RolloutResult``.

    Receives ``batch``, a ``mujoco.batch.Batch`` of ``job.n_episodes``
    simulations of the job's model (``load_model(job.model_params)``), cached
    by the backend and left in any state by the last rollout: the strategy
    puts episode ``e`` at start state ``e`` of ``job.starts`` itself. It may
    step the batch's simulations on its threads or use only ``batch.model``
    (an accelerator's copy). ``job`` says what to run and record.

    Returns a :class:`~.job.RolloutResult`: ``records`` (``job.Recorder``:
    each name of ``job.record`` as ``(n, n_steps + 1, ...)``, row 0 the start
    state, row ``t`` the state after control step ``t`` and the inputs seen
    there), ``unstable`` (the episodes :func:`~.job.went_unstable` stopped:
    records repeating their last row, its ``qpos`` made finite), ``steps``
    (control steps each episode simulated) and ``control_steps`` (their sum).

    Determinism: the same job gives the same result, bit for bit, whatever
    the batch's threads or however the job is split by episode (episodes are
    independent). It equals :func:`~.episode.reference_rollout`'s: bit for bit
    where it does the same arithmetic (``numpy``; any strategy without
    networks), else within a tolerance the strategy states and a test checks
    (the compiled networks: ``tests/test_engine.py``'s ``NETWORK_TOL`` a step).
    ``tests/test_rollout.py`` runs every strategy of :data:`STRATEGIES`
    against ``numpy``.
    """

    def __call__(self, batch: Batch, job: RolloutJob) -> RolloutResult: ...


#: the engine strategies, by name (``RolloutJob.engine`` picks one; a run's
#: are :data:`~.job.ENGINES`)
STRATEGIES: dict[str, Strategy] = {
    "numpy": run_numpy,
    "numba-loop": run_compiled,
    "numba": run_incallback,
}


def run_batch(batch: Batch, job: RolloutJob) -> RolloutResult:
    """Every episode of ``job`` on ``batch``, on the job's engine strategy
    (``ValueError`` naming the choices if there is none of that name)."""
    name = strategy_name(job)
    if name not in STRATEGIES:
        raise ValueError(
            f"unknown engine strategy {name!r}; choose from {', '.join(STRATEGIES)}"
        )
    return STRATEGIES[name](batch, job)
