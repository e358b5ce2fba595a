"""The compiled control step (strategy ``numba-loop``): everything between two
``Batch.rollout`` calls — touch reduction, the unstable rule, inputs, records,
networks, actuation — in one call of a compiled kernel of
:mod:`locustjump.sim.kernels`, from the engine's one loop
(:func:`~.loop.run_steps`).

A controller joins the compiled path by offering ``kernel(prepared)``
(``MLP`` and the composed switcher do); any other controller runs its own
NumPy ``act`` between the kernels, with the same result as on the NumPy path.
"""

from __future__ import annotations

import numpy as np
from mujoco.batch import Batch

from locustjump.sim import actuation, sensors
from locustjump.sim import model as lm
from locustjump.sim.controller import CompiledController
from locustjump.sim.engine.job import (
    STEP_RECORDS,
    UNSTABLE,
    Recorder,
    RolloutJob,
    RolloutResult,
)
from locustjump.sim.engine.loop import run_steps
from locustjump.sim.kernels import (
    MLPAct,
    Records,
    Rollout,
    SwitchAct,
    actuate,
    post_step,
    step_mlp,
    step_switch,
)


class CompiledStep:
    """:class:`~.loop.ControlStep` in one kernel call: :attr:`rollout` holds
    what every call reads and writes, :attr:`act` the controller's part
    (:class:`~locustjump.sim.kernels.MLPAct`, ``SwitchAct``, or None: the
    controller's NumPy ``act`` between the kernels)."""

    def __init__(self, batch: Batch, job: RolloutJob, sens: np.ndarray):
        m, ctl, n = batch.model, job.controller, job.n_episodes
        idx = lm.ModelIndex.of(m)
        self.unstable = np.zeros(n, bool)
        self.newly = np.zeros(n, bool)
        self.ctrl, self.memory = batch.bind("ctrl"), np.zeros((n, ctl.memory_size))
        self.recorder = Recorder.of(job, m.nq)
        self.lo = np.ascontiguousarray(idx.ranges[:, 0])
        self.hi = np.ascontiguousarray(idx.ranges[:, 1])
        none = np.empty((0, 0, 0))
        records = Records(*(self.recorder.arrays.get(k, none) for k in STEP_RECORDS))
        self.rollout = Rollout(
            sens=sens,
            qpos=batch.bind("qpos"),
            warning=batch.warning[:, UNSTABLE],  # the one rule's warnings
            unstable=self.unstable,
            newly=self.newly,
            joints=np.asarray(idx.qpos_joints, dtype=np.intp),
            touch=np.asarray(idx.touch, dtype=np.intp),
            body_length=job.model_params.body_length,
            obs=np.empty((sensors.N_INPUTS, n)),
            ctrl=self.ctrl,
            memory=self.memory,
            records=records,
        )
        self.ctl, self.prepared = ctl, ctl.prepare(job.params)
        spec = (
            ctl.kernel(self.prepared) if isinstance(ctl, CompiledController) else None
        )
        self.deltas = np.empty((actuation.N_ACTUATORS, n))
        self.act: MLPAct | SwitchAct | None = None
        if spec is not None and spec[0] == "mlp":
            _, net, output = spec
            hidden = np.empty((net[0].shape[0], n))
            self.act = MLPAct(net, output, self.deltas, hidden, self.lo, self.hi)
        elif spec is not None and spec[0] == "switch":
            _, sw, nets, every = spec
            h = max(sw[0].shape[0], nets[0].shape[1])
            self.act = SwitchAct(
                every=every,
                sw=sw,
                nets=nets,
                deltas=self.deltas,
                choice=np.empty((sw[2].shape[0], n)),
                scratch=np.empty((nets[2].shape[1], n)),
                hidden=np.empty((h, n)),
                lo=self.lo,
                hi=self.hi,
            )

    def __call__(
        self,
        t: int,
        check: bool,
        sub: np.ndarray,
        ids: np.ndarray,
        stopped: bool,
        act: bool,
    ) -> int:
        r, a = self.rollout, self.act
        if isinstance(a, MLPAct):
            return step_mlp(t, check, sub, ids, stopped, act, r, a)
        if isinstance(a, SwitchAct):
            return step_switch(t, check, sub, ids, stopped, act, r, a)
        failed = post_step(t, check, sub, ids, stopped, r)
        if not failed and act:
            d, mem = self.ctl.act(self.prepared, self.memory, r.obs.T, self.ctrl, t)
            self.deltas[:] = np.asarray(d).T
            self.memory[:] = mem
            actuate(self.ctrl, self.deltas, self.lo, self.hi, self.unstable, stopped)
        return failed


def run_compiled(batch: Batch, job: RolloutJob) -> RolloutResult:
    """Every episode of ``job`` on ``batch``, the compiled control step
    between two physics calls (:func:`~.loop.run_steps`)."""
    return run_steps(batch, job, CompiledStep)
