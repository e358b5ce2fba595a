"""The reference control step (strategy ``numpy``): everything between two
physics calls in a fixed number of whole-batch NumPy calls, on arrays bound
to the batch's own memory (no copies in or out of MuJoCo)::

    touch  = sub.max(axis=1)                            # over the substeps
    failed = went_unstable(qpos, warnings)              # the one rule
    obs    = paper_inputs(qpos, touch)                  # (n, 9)
    recorder.write(t, qpos, obs, ctrl, memory)
    deltas = controller.act(prepared, memory, obs, t)   # (n, 4), one batched call
    ctrl   = apply_deltas(ctrl, deltas, ranges)         # servo targets, in place

``prepared = controller.prepare(params)`` is computed once per rollout. Any
controller runs here; ~100 µs per control step whatever the batch size.
"""

from __future__ import annotations

import numpy as np
from mujoco.batch import Batch

from locustjump.sim import actuation
from locustjump.sim import model as lm
from locustjump.sim.engine.job import (
    Recorder,
    RolloutJob,
    RolloutResult,
    observer,
    went_unstable,
)
from locustjump.sim.engine.loop import run_steps


class NumpyStep:
    """:class:`~.loop.ControlStep` in NumPy: the controller's own ``act``."""

    def __init__(self, batch: Batch, job: RolloutJob, sens: np.ndarray):
        m, ctl, n = batch.model, job.controller, job.n_episodes
        idx = lm.ModelIndex.of(m)
        self.qpos, self.ctrl, self.sens = batch.bind("qpos"), batch.bind("ctrl"), sens
        self.warnings = batch.warning[..., 1]  # a view: the warning counts
        self.ranges = idx.ranges
        self.observe = observer(idx, job.model_params)
        self.ctl, self.prepared = ctl, ctl.prepare(job.params)
        self.memory = np.zeros((n, ctl.memory_size))
        self.recorder = Recorder.of(job, m.nq)
        self.unstable = np.zeros(n, bool)
        self.newly = np.zeros(n, bool)

    def __call__(
        self,
        t: int,
        check: bool,
        sub: np.ndarray,
        ids: np.ndarray,
        stopped: bool,
        act: bool,
    ) -> int:
        if check:
            if len(sub) and stopped:
                self.sens[ids] = sub.max(axis=1)
            elif len(sub):
                sub.max(axis=1, out=self.sens)
            bad = went_unstable(self.qpos, self.warnings)
            np.greater(bad, self.unstable, out=self.newly)  # bad, not yet stopped
            count = int(np.count_nonzero(self.newly))
            if count:
                return count
        obs = self.observe(self.qpos, self.sens)
        frozen = self.unstable if stopped else None
        self.recorder.write(t, self.qpos, obs, self.ctrl, self.memory, frozen)
        if act:
            deltas, self.memory = self.ctl.act(
                self.prepared, self.memory, obs, self.ctrl, t
            )
            if stopped:
                moved = actuation.apply_deltas(self.ctrl, deltas, self.ranges)
                self.ctrl[ids] = moved[ids]
            else:
                actuation.apply_deltas(self.ctrl, deltas, self.ranges, out=self.ctrl)
        return 0


def run_numpy(batch: Batch, job: RolloutJob) -> RolloutResult:
    """Every episode of ``job`` on ``batch``, the NumPy control step (the
    reference, bit for bit :func:`~.episode.reference_rollout`'s)."""
    return run_steps(batch, job, NumpyStep)
