"""The rollout engine's ``numba`` path: the control loop of
:func:`locustjump.rollout.run_batch` with the work between two
``Batch.rollout`` calls done by the compiled kernels of
:mod:`locustjump.kernels` (one or two calls per control step)."""

from __future__ import annotations

import numpy as np
from mujoco.batch import Batch, SimulationError

from locustjump import model as lm
from locustjump import sensors
from locustjump.kernels import act_mlp, act_switch, actuate, post_step
from locustjump.rollout import (
    _UNSTABLE,
    RolloutJob,
    RolloutResult,
    _progress,
    record_shapes,
)


class _Act:
    """A controller's step on the compiled path: its own kernel when it offers
    one (``controller.kernel(prepared)``), else its NumPy ``act``."""

    def __init__(self, ctl, prepared, n: int, lo, hi):
        self.ctl, self.prepared, self.lo, self.hi = ctl, prepared, lo, hi
        self.spec = ctl.kernel(prepared) if hasattr(ctl, "kernel") else None
        self.deltas = np.empty((4, n))
        self.hidden = np.empty((64, n))
        if self.spec is not None and self.spec[0] == "switch":
            nets = self.spec[2]
            self.choice = np.empty((self.spec[1][2].shape[0], n))
            self.scratch = np.empty((nets[2].shape[1], n))
            self.hidden = np.empty((max(self.spec[1][0].shape[0], nets[0].shape[1]), n))
        elif self.spec is not None:
            self.hidden = np.empty((self.spec[1][0].shape[0], n))

    def __call__(self, t, obs, ctrl, memory, unstable, any_unstable) -> None:
        spec = self.spec
        if spec is None:
            d, mem = self.ctl.act(self.prepared, memory, obs.T, ctrl, t)
            self.deltas[:] = np.asarray(d).T
            memory[:] = mem
            actuate(ctrl, self.deltas, self.lo, self.hi, unstable, any_unstable)
        elif spec[0] == "mlp":
            act_mlp(*spec[1], spec[2], obs, self.deltas, self.hidden, ctrl,
                    self.lo, self.hi, unstable, any_unstable)  # fmt: skip
        else:
            act_switch(t, spec[3], spec[1], spec[2], memory, obs, self.deltas,
                       self.choice, self.scratch, self.hidden, ctrl, self.lo,
                       self.hi, unstable, any_unstable)  # fmt: skip


def run_compiled(batch: Batch, job: RolloutJob) -> RolloutResult:
    """:func:`locustjump.rollout.run_batch` on the compiled path."""
    m = batch.model
    p = job.model_params
    idx = lm.ModelIndex.of(m)
    n, T = job.n_episodes, job.n_steps
    batch.reset()
    qpos, qvel, ctrl = batch.bind("qpos"), batch.bind("qvel"), batch.bind("ctrl")
    qpos[:] = job.starts.qpos
    qvel[:] = job.starts.qvel
    ctrl[:] = job.starts.ctrl
    batch.forward()
    sens = np.array(batch.bind("sensordata"))
    warn_bad = batch.warning[:, _UNSTABLE, 1]
    ctl = job.controller
    memory = np.zeros((n, ctl.memory_size))
    shapes = record_shapes(m.nq, ctl.memory_size)
    rec = {k: np.empty((n, T + 1, *shapes[k])) for k in job.record}
    none = np.empty((0, 0, 0))
    rq, ro, rc, rm = (rec.get(k, none) for k in ("qpos", "obs", "ctrl", "memory"))
    joints = np.asarray(idx.qpos_joints, dtype=np.intp)
    touch = np.asarray(idx.touch, dtype=np.intp)
    lo = np.ascontiguousarray(idx.ranges[:, 0])
    hi = np.ascontiguousarray(idx.ranges[:, 1])
    act = _Act(ctl, ctl.prepare(job.params), n, lo, hi)
    obs = np.empty((sensors.N_INPUTS, n))
    unstable = np.zeros(n, bool)
    newly = np.zeros(n, bool)
    steps = np.full(n, T)
    ids = np.arange(n)
    S = p.substeps
    sub = {"sensordata": np.empty((n, S, m.nsensordata))}
    frozen = False  # some episode failed: the records of those repeat
    post = (joints, touch, p.body_length, obs, ctrl, memory, rq, ro, rc, rm)
    post_step(0, False, sub["sensordata"], ids, sens, qpos, warn_bad, unstable,
              newly, *post, False)  # fmt: skip
    done = 0
    bar = _progress(job)
    for t in range(T):
        if bar is not None and t % 100 == 0:
            bar.update(min(100, T - t))
        act(t, obs, ctrl, memory, unstable, frozen)
        try:
            if not frozen:
                batch.rollout(S, record=("sensordata",), out=sub)
                out = sub["sensordata"]
            else:
                out = batch.rollout(S, record=("sensordata",), ids=ids)["sensordata"]
        except SimulationError as e:  # those sims kept their state
            warn_ids, out = e.ids, None
        else:
            warn_ids = None
        done += len(ids)
        if out is None:  # sensors of the failed call: as they are now
            out = np.array(batch.bind("sensordata"))[ids][:, None, :]
        failed = post_step(t + 1, True, out, ids, sens, qpos, warn_bad, unstable,
                           newly, *post, frozen)  # fmt: skip
        if failed or warn_ids is not None:
            if warn_ids is not None:
                newly[warn_ids] |= ~unstable[warn_ids]
            unstable |= newly
            steps[newly] = t + 1
            ids = np.flatnonzero(~unstable)
            qpos[newly] = np.nan_to_num(qpos[newly])
            frozen = True
            if ids.size == 0:
                for a in rec.values():
                    a[:, t + 1 :] = a[:, t : t + 1]
                break
            post_step(t + 1, False, out, ids, sens, qpos, warn_bad, unstable,
                      newly, *post, frozen)  # fmt: skip
    if bar is not None:
        bar.close()
    return RolloutResult(rec, unstable, steps, done)
