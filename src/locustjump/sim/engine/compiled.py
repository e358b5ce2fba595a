"""The rollout engine's ``numba`` path: the control loop of
:func:`locustjump.sim.engine.loop.run_batch` with everything between two
``Batch.rollout`` calls — touch reduction, checks, inputs, records, networks,
actuation — in one call of a compiled kernel of :mod:`locustjump.sim.kernels`.

A controller joins the compiled path by offering ``kernel(prepared)``
(``MLP`` and the composed switcher do); any other controller runs its own
NumPy ``act`` between the kernels, with the same result as on the NumPy path.
"""

from __future__ import annotations

import mujoco
import numpy as np
from mujoco.batch import Batch, SimulationError

from locustjump.sim import model as lm
from locustjump.sim import sensors
from locustjump.sim.engine.job import (
    RolloutJob,
    RolloutResult,
    progress,
    record_shapes,
)
from locustjump.sim.kernels import actuate, post_step, step_mlp, step_switch


class Step:
    """Everything between two physics calls, for one rollout: ``__call__``
    returns how many episodes newly failed (then it observed nothing)."""

    def __init__(self, batch: Batch, job: RolloutJob, sens, memory, records):
        m, ctl, n = batch.model, job.controller, job.n_episodes
        idx = lm.ModelIndex.of(m)
        none = np.empty((0, 0, 0))
        self.obs = np.empty((sensors.N_INPUTS, n))
        self.unstable = np.zeros(n, bool)
        self.newly = np.zeros(n, bool)
        self.ctrl, self.memory = batch.bind("ctrl"), memory
        self.lo = np.ascontiguousarray(idx.ranges[:, 0])
        self.hi = np.ascontiguousarray(idx.ranges[:, 1])
        recorded = (records.get(k, none) for k in ("qpos", "obs", "ctrl", "memory"))
        self.head = (sens, batch.bind("qpos"), batch.warning, self.unstable,
                     self.newly, np.asarray(idx.qpos_joints, dtype=np.intp),
                     np.asarray(idx.touch, dtype=np.intp),
                     job.model_params.body_length, self.obs, self.ctrl, memory,
                     *recorded)  # fmt: skip
        self.ctl, self.prepared = ctl, ctl.prepare(job.params)
        spec = ctl.kernel(self.prepared) if hasattr(ctl, "kernel") else None
        self.kind = None if spec is None else spec[0]
        self.deltas = np.empty((sensors.N_ACTUATORS, n))
        if self.kind == "mlp":
            _, net, output = spec
            self.tail = (net, output, self.deltas, np.empty((net[0].shape[0], n)),
                         self.lo, self.hi)  # fmt: skip
        elif self.kind == "switch":
            _, sw, nets, every = spec
            h = max(sw[0].shape[0], nets[0].shape[1])
            self.tail = (every, sw, nets, self.deltas, np.empty((sw[2].shape[0], n)),
                         np.empty((nets[2].shape[1], n)), np.empty((h, n)),
                         self.lo, self.hi)  # fmt: skip

    def __call__(self, t, check, sub, ids, stopped, act) -> int:
        if self.kind == "mlp":
            return step_mlp(t, check, sub, ids, *self.head, stopped, act, *self.tail)
        if self.kind == "switch":
            return step_switch(t, check, sub, ids, *self.head, stopped, act, *self.tail)
        failed = post_step(t, check, sub, ids, *self.head, stopped)
        if not failed and act:
            d, mem = self.ctl.act(self.prepared, self.memory, self.obs.T, self.ctrl, t)
            self.deltas[:] = np.asarray(d).T
            self.memory[:] = mem
            actuate(self.ctrl, self.deltas, self.lo, self.hi, self.unstable, stopped)
        return failed


def start(batch: Batch, job: RolloutJob) -> tuple[Step, dict, np.ndarray]:
    """Every simulation at its start state, row 0 of the records and the first
    action: the step (its state), the records and the batch's ``qpos``."""
    m, n = batch.model, job.n_episodes
    batch.reset(stage=mujoco.mjtStage.mjSTAGE_NONE)  # forward() follows the writes
    qpos = batch.bind("qpos")
    qpos[:] = job.starts.qpos
    batch.bind("qvel")[:] = job.starts.qvel
    batch.bind("ctrl")[:] = job.starts.ctrl
    batch.forward()  # sensors at the start state, for every simulation
    sens = np.array(batch.bind("sensordata"))
    memory = np.zeros((n, job.controller.memory_size))
    shapes = record_shapes(m.nq, job.controller.memory_size)
    rec = {k: np.empty((n, job.n_steps + 1, *shapes[k])) for k in job.record}
    step = Step(batch, job, sens, memory, rec)
    no_sub = np.empty((0, job.model_params.substeps, m.nsensordata))
    step(0, False, no_sub, np.arange(n), False, True)
    return step, rec, qpos


def run_compiled(batch: Batch, job: RolloutJob) -> RolloutResult:
    """:func:`locustjump.sim.engine.loop.run_batch` on the compiled path."""
    m = batch.model
    n, T, S = job.n_episodes, job.n_steps, job.model_params.substeps
    step, rec, qpos = start(batch, job)
    unstable, newly = step.unstable, step.newly
    steps = np.full(n, T)
    ids = np.arange(n)
    sub = {"sensordata": np.empty((n, S, m.nsensordata))}
    no_sub = np.empty((0, S, m.nsensordata))
    stopped = False  # some episode failed: ids are the others; records freeze
    done = 0
    bar = progress(job)
    for t in range(T):
        if bar is not None and t % 100 == 0:
            bar.update(min(100, T - t))
        warn_ids = None
        try:
            if not stopped:
                out = batch.rollout(S, record=("sensordata",), out=sub)["sensordata"]
            else:
                out = batch.rollout(S, record=("sensordata",), ids=ids)["sensordata"]
        except SimulationError as e:  # those sims kept their state; the sensors
            warn_ids, out = e.ids, no_sub  # stay as they were (the NumPy path)
        done += len(ids)
        act = t + 1 < T
        # a failed call: check only, then mark its simulations too
        failed = step(t + 1, True, out, ids, stopped, act and warn_ids is None)
        if warn_ids is not None:
            newly[warn_ids] |= ~unstable[warn_ids]
        if failed or warn_ids is not None:
            if newly.any():
                unstable |= newly
                steps[newly] = t + 1
                ids = np.flatnonzero(~unstable)
                qpos[newly] = np.nan_to_num(qpos[newly])
                stopped = True
                if ids.size == 0:
                    for a in rec.values():
                        a[:, t + 1 :] = a[:, t : t + 1]
                    break
            step(t + 1, False, no_sub, ids, stopped, act)
    if bar is not None:
        bar.close()
    return RolloutResult(rec, unstable, steps, done)
