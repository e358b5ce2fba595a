"""The rollout engine: many controllers x many start states, stepped together.

One control step for every live episode at once::

    obs    = paper_inputs(qpos, sensordata)             # (n, 9), batched NumPy
    deltas = controller.act(prepared, memory, obs, t)   # (n, 4), one batched call
    ctrl   = apply_deltas(ctrl, deltas, ranges)         # servo targets, in place
    batch.rollout(nstep=substeps, record=sensordata)   # mujoco.batch, C threads
    touch  = max over the substeps of sensordata        # I5 sees any contact

``prepared = controller.prepare(params)`` is computed once per rollout, and the
per-step work is a fixed number of whole-batch NumPy calls on arrays bound to
the batch's own memory (no copies in or out of MuJoCo).

Episodes are independent rows, so a job can be split anywhere (threads,
processes, hosts) and give bit-identical results;
:func:`~.episode.reference_rollout` is the plain one-``MjData``-per-episode
loop the engine is tested against.

An episode whose simulation goes unstable (non-finite state, a MuJoCo warning
such as bad qpos/qvel/qacc, or a MuJoCo error) stops stepping: it is flagged in
``RolloutResult.unstable`` and its remaining records repeat its last ones; the
behaviours give it the worst fitness.
"""

from __future__ import annotations

import mujoco
import numpy as np
from mujoco.batch import Batch, SimulationError

from locustjump.sim import model as lm
from locustjump.sim import sensors
from locustjump.sim.engine.incallback import run_incallback
from locustjump.sim.engine.job import (
    UNSTABLE,
    Recorder,
    RolloutJob,
    RolloutResult,
    observer,
    progress,
    record_shapes,
)


def run_batch(batch: Batch, job: RolloutJob) -> RolloutResult:
    """Every episode of ``job`` on ``batch``, on the job's engine path
    (``job.engine``): the NumPy loop below (the reference) or
    the compiled one, whose controllers run inside the batch's threads
    (:mod:`locustjump.sim.engine.incallback`; the same numbers as its step-by-step loop,
    :mod:`locustjump.sim.engine.compiled`)."""
    if job.engine == "numba":
        return run_incallback(batch, job)
    m = batch.model
    p = job.model_params
    idx = lm.ModelIndex.of(m)
    n, T = job.n_episodes, job.n_steps
    batch.reset(stage=mujoco.mjtStage.mjSTAGE_NONE)  # forward() follows the writes
    qpos, qvel, ctrl = batch.bind("qpos"), batch.bind("qvel"), batch.bind("ctrl")
    sens = batch.bind("sensordata")
    warn = batch.warning
    qpos[:] = job.starts.qpos
    qvel[:] = job.starts.qvel
    ctrl[:] = job.starts.ctrl
    batch.forward()  # sensors at the start state, for every simulation

    ctl = job.controller
    prepared = ctl.prepare(job.params)
    memory = np.zeros((n, ctl.memory_size))
    rec = Recorder(job.record, n, T, record_shapes(m.nq, ctl.memory_size))
    observe = observer(idx, p)
    obs = observe(qpos, sens)
    rec.write(0, qpos, obs, ctrl, memory)
    warn_bad = warn[:, UNSTABLE, 1]  # a view: warning counts of every sim
    # sensordata after every substep (MuJoCo computes it at the substep's
    # start), reduced to its maximum over the control step: I5 sees a contact
    # at any substep, not only at the last one
    sub = {"sensordata": np.empty((n, p.substeps, m.nsensordata))}
    sens = np.array(sens)
    unstable = np.zeros(n, bool)
    steps = np.full(n, T)
    alive: np.ndarray | None = None  # None: all alive (no index array per step)
    done = 0
    bar = progress(job)
    for t in range(T):
        if bar is not None and t % 100 == 0:
            bar.update(min(100, T - t))
        deltas, memory = ctl.act(prepared, memory, obs, ctrl, t)
        if alive is None:
            sensors.apply_deltas(ctrl, deltas, idx.ranges, out=ctrl)
        else:
            ctrl[alive] = sensors.apply_deltas(ctrl, deltas, idx.ranges)[alive]
        try:
            if alive is None:
                batch.rollout(p.substeps, record=("sensordata",), out=sub)
                sub["sensordata"].max(axis=1, out=sens)
            else:
                r = batch.rollout(p.substeps, record=("sensordata",), ids=alive)
                sens[alive] = r["sensordata"].max(axis=1)
        except SimulationError as e:  # MuJoCo errors: those sims kept their state
            warn_ids = e.ids
        else:
            warn_ids = None
        done += n if alive is None else len(alive)
        # fast path: one reduction each over the whole batch
        if warn_ids is not None or warn_bad.any() or not np.isfinite(qpos).all():
            bad = (warn_bad > 0).any(axis=1) | ~np.isfinite(qpos).all(axis=1)
            if warn_ids is not None:
                bad[warn_ids] = True
            newly = bad & ~unstable
            if newly.any():
                unstable |= newly
                steps[newly] = t + 1
                alive = np.flatnonzero(~unstable)
                # keep the last finite state of a failed episode in the records
                qpos[newly] = np.nan_to_num(qpos[newly])
                if alive.size == 0:
                    rec.fill_from(t + 1)
                    break
        obs = observe(qpos, sens)
        rec.write(
            t + 1,
            qpos,
            obs,
            ctrl,
            memory,
            stopped=unstable if alive is not None else None,
        )
    if bar is not None:
        bar.close()
    return RolloutResult(rec.arrays, unstable, steps, done)
