"""The compiled path with no Python between substeps (strategy ``numba``):
each episode's control step runs inside MuJoCo's control callback
(``mjcb_control``, :mod:`~locustjump.sim.engine.callback`), on the batch's own
C threads, and a whole rollout is one ``Batch.rollout`` call: the engine's
loop (:func:`~.loop.run_steps`) with its per-control-step work moved into the
physics.

What stays in Python, once a rollout: the start state's inputs and the first
action (:func:`~.loop.begin` with :class:`~.compiled.CompiledStep`), the last
record, and the episodes that went unstable (:func:`~.job.went_unstable`) —
MuJoCo resets a simulation's state when it detects a blow-up, before the
callback could record the state that caused it, so those episodes (rare) are
simulated again, alone, on the step-by-step loop, whose records and step
counts are the reference. A MuJoCo error sends the whole rollout there, and so
does a MuJoCo whose ``mjData`` layout is not the one the callback was built
for (:data:`~.callback.AVAILABLE`).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from mujoco.batch import Batch, SimulationError

from locustjump.sim import model as lm
from locustjump.sim.controller import CompiledController
from locustjump.sim.engine.callback import (
    AVAILABLE,
    NUSERDATA,
    USERDATA_MARK,
    context,
    installed,
)

# the guard of the callback's cached code, importable from here as before
from locustjump.sim.engine.callback import KERNELS_SHA256 as KERNELS_SHA256
from locustjump.sim.engine.callback import OFFSETS as OFFSETS
from locustjump.sim.engine.callback import kernels_digest as kernels_digest
from locustjump.sim.engine.compiled import CompiledStep, run_compiled
from locustjump.sim.engine.job import (
    RolloutJob,
    RolloutResult,
    progress,
    records_contacts,
    went_unstable,
)
from locustjump.sim.engine.loop import begin

_CHUNK = 100  # control steps per Batch.rollout call when a progress bar shows


def run_incallback(batch: Batch, job: RolloutJob) -> RolloutResult:
    """:func:`~.compiled.run_compiled`'s result, with the controllers
    stepped inside the batch's threads. Controllers without a compiled kernel,
    a model without the userdata, another control callback already
    installed, or a job recording contacts (:data:`~.job.CONTACT_RECORDS`,
    which the loop reduces over the substeps): the step-by-step loop."""
    ctl = job.controller
    if (
        not AVAILABLE
        or batch.model.nuserdata < NUSERDATA
        or not isinstance(ctl, CompiledController)
        or records_contacts(job)
    ):
        return run_compiled(batch, job)
    m, n, T, S = batch.model, job.n_episodes, job.n_steps, job.model_params.substeps
    step = begin(batch, job, CompiledStep)
    rec, qpos = step.recorder.arrays, batch.bind("qpos")
    no_sub = np.empty((0, S, m.nsensordata))
    # keep: every array ctx points into, alive until this function returns
    ctx, tmax, keep = context(batch, job, step, rec, ctl.kernel(step.prepared))
    user = batch.bind("userdata")
    user[:, 0] = USERDATA_MARK
    user[:, 1] = float(ctx.ctypes.data)
    user[:, 2] = np.arange(n)
    try:
        with installed() as ok:
            if not ok:
                return run_compiled(batch, job)
            _step_all(batch, job, T * S)
    except SimulationError:  # a MuJoCo error: the reference loop decides
        return run_compiled(batch, job)
    finally:
        user[:, 0] = 0.0
    # the last row, on the step-by-step loop's own kernel
    unstable, newly = step.unstable, step.newly
    failed = went_unstable(qpos, batch.warning[..., 1])
    unstable |= failed
    now = np.array(batch.bind("sensordata"))
    sub = now[:, None] if S == 1 else np.stack([tmax, now], axis=1)
    alive = np.flatnonzero(~unstable)
    steps = np.full(n, T)
    if step(T, True, sub[alive], alive, bool(failed.any()), False):
        unstable |= newly
        steps[newly] = T
        qpos[newly] = np.nan_to_num(qpos[newly])
        step(T, False, no_sub, np.flatnonzero(~unstable), True, False)
    result = RolloutResult(rec, unstable, steps, 0)
    if failed.any():
        _redo(job, np.flatnonzero(failed), result)
    result.control_steps = int(result.steps.sum())
    return result


def _step_all(batch: Batch, job: RolloutJob, substeps: int) -> None:
    """Every substep of the rollout: one call, or calls of 100 control steps
    under a progress bar; a simulation with a warning is stepped no further."""
    bar = progress(job)
    if bar is None:
        batch.rollout(substeps, record=())
        return
    every = _CHUNK * job.model_params.substeps
    ids = None
    for done in range(0, substeps, every):
        batch.rollout(min(every, substeps - done), record=(), ids=ids)
        bar.update(min(_CHUNK, job.n_steps - done // job.model_params.substeps))
        bad = went_unstable(batch.bind("qpos"), batch.warning[..., 1])
        ids = np.flatnonzero(~bad) if bad.any() else None
        if ids is not None and ids.size == 0:
            break
    bar.close()


def _redo(job: RolloutJob, failed: np.ndarray, result: RolloutResult) -> None:
    """Episodes ``failed`` of ``result`` simulated again on the step-by-step
    loop, alone (episodes are independent: the same as in the whole batch)."""
    sub = replace(job, params=job.params[failed], starts=job.starts.take(failed),
                  label="")  # fmt: skip
    batch = Batch(
        lm.load_model(job.model_params, job.scene), len(failed), 1, persistent=True
    )
    again = run_compiled(batch, sub)
    for k, a in result.records.items():
        a[failed] = again.records[k]
    result.unstable[failed], result.steps[failed] = again.unstable, again.steps
