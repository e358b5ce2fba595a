"""The engine's one control loop: many episodes stepped together on a
``mujoco.batch.Batch``, with what runs between two physics calls plugged in
(a :class:`ControlStep`).

One control step for every live episode::

    batch.rollout(nstep=substeps, record=sensordata)    # mujoco.batch, C threads
    step(t + 1, check=True, sub, ids, ...)              # a ControlStep:
        touch  = max over the substeps of sensordata    #   I5 sees any contact
        failed = went_unstable(qpos, warnings)          #   the one rule
        obs    = paper_inputs(qpos, touch)              #   (n, 9)
        record row t + 1                                #   job.Recorder
        deltas = controller(obs); ctrl += deltas        #   the next action
    contacts of row t + 1 from sensordata               # job.contact_maxima

The last line only when the job records ``penetration`` or ``wall_contact``
(:data:`~.job.CONTACT_RECORDS`): the loop reduces the contact sensors over
the substeps itself, so every control step records them alike.

The control steps plugged in: the NumPy reference
(:class:`~.numpy_step.NumpyStep`, a fixed number of whole-batch NumPy calls)
and the compiled one (:class:`~.compiled.CompiledStep`, one call of a
compiled kernel). Both do the same operations in the same order; the loop owns
everything else: the start state, the physics calls, MuJoCo's errors, the
failed episodes' bookkeeping and the progress bar.

Episodes are independent rows, so a job can be split anywhere (threads,
processes, hosts) and give bit-identical results;
:func:`~.episode.reference_rollout` is the plain one-``MjData``-per-episode
loop the engine is tested against.

An episode whose simulation goes unstable (:func:`~.job.went_unstable`: a
MuJoCo warning, a non-finite state or a MuJoCo error) stops stepping: it is
flagged in ``RolloutResult.unstable`` and its remaining records repeat its
last ones (with its last state made finite); the behaviours give it the worst
fitness.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol, TypeVar

import mujoco
import numpy as np
from mujoco.batch import Batch, SimulationError

from locustjump.sim import model as lm
from locustjump.sim.engine.job import (
    Recorder,
    RolloutJob,
    RolloutResult,
    contact_maxima,
    progress,
    records_contacts,
)


class ControlStep(Protocol):
    """What runs between two physics calls, for every episode of one rollout.

    Built by :func:`begin` as ``make(batch, job, sens)`` once the batch is at
    the job's start states (``sens``: a copy of the sensors there, the touch
    maxima it keeps from then on); it holds the rollout's state.
    """

    #: (n,) bool, the episodes that failed (the loop sets them)
    unstable: np.ndarray
    #: (n,) bool, the episodes the last checking call found newly failed
    newly: np.ndarray
    #: the records of the rollout
    recorder: Recorder

    def __call__(
        self,
        t: int,
        check: bool,
        sub: np.ndarray,
        ids: np.ndarray,
        stopped: bool,
        act: bool,
    ) -> int:
        """After the physics of control step ``t - 1`` (``t == 0``: the start
        state).

        With ``check``: reduce ``sub (len(ids), substeps, nsensordata)``, the
        sensors of simulations ``ids`` after each substep (empty after a
        MuJoCo error: the touch maxima stay as they were), to their maxima,
        then flag in :attr:`newly` the episodes not yet :attr:`unstable` that
        :func:`~.job.went_unstable`, and if any, return how many and do
        nothing else. Then observe, record row ``t`` (``stopped``: some
        episode failed, and those repeat row ``t - 1``) and, with ``act``,
        compute the next action and write it into the ``ctrl`` of the
        episodes not :attr:`unstable`. Returns 0.
        """
        ...


#: builds a :class:`ControlStep`: ``make(batch, job, sens)``
StepMaker = Callable[[Batch, RolloutJob, np.ndarray], ControlStep]
Step = TypeVar("Step", bound=ControlStep)


def begin(
    batch: Batch, job: RolloutJob, make: Callable[[Batch, RolloutJob, np.ndarray], Step]
) -> Step:
    """Every simulation of ``batch`` at its start state, the control step
    built, row 0 recorded and the first action applied."""
    m = batch.model
    batch.reset(stage=mujoco.mjtStage.mjSTAGE_NONE)  # forward() follows the writes
    batch.bind("qpos")[:] = job.starts.qpos
    batch.bind("qvel")[:] = job.starts.qvel
    batch.bind("ctrl")[:] = job.starts.ctrl
    batch.forward()  # sensors at the start state, for every simulation
    step = make(batch, job, np.array(batch.bind("sensordata")))
    no_sub = np.empty((0, job.model_params.substeps, m.nsensordata))
    step(0, False, no_sub, np.arange(job.n_episodes), False, True)
    return step


def run_steps(batch: Batch, job: RolloutJob, make: StepMaker) -> RolloutResult:
    """Every episode of ``job`` on ``batch``, the control step ``make`` builds
    run between two physics calls: the engine's one control loop."""
    m = batch.model
    n, T, S = job.n_episodes, job.n_steps, job.model_params.substeps
    step = begin(batch, job, make)
    qpos = batch.bind("qpos")
    unstable, newly = step.unstable, step.newly
    rec = step.recorder
    idx = lm.ModelIndex.of(m) if records_contacts(job) else None
    if idx is not None:  # the start state's contacts (forward() in begin)
        start = np.array(batch.bind("sensordata"))[:, None]
        rec.write_contacts(0, np.arange(n), *contact_maxima(start, idx))
    empty = np.empty(0)
    steps = np.full(n, T)
    ids = np.arange(n)
    # sensordata after every substep (MuJoCo computes it at the substep's
    # start), reduced to its maximum over the control step by the step: I5
    # sees a contact at any substep, not only at the last one
    sub = {"sensordata": np.empty((n, S, m.nsensordata))}
    no_sub = np.empty((0, S, m.nsensordata))
    stopped = False  # some episode failed: ids are the others; records freeze
    done = 0
    bar = progress(job)
    for t in range(T):
        if bar is not None and t % 100 == 0:
            bar.update(min(100, T - t))
        errors = None
        try:
            if not stopped:
                out = batch.rollout(S, record=("sensordata",), out=sub)["sensordata"]
            else:
                out = batch.rollout(S, record=("sensordata",), ids=ids)["sensordata"]
        except SimulationError as e:  # those sims kept their state; the touch
            errors, out = e.ids, no_sub  # maxima stay as they were
        done += len(ids)
        live = ids  # the simulations of this call, the rows of out
        act = t + 1 < T
        # a failed call: check only, then mark its simulations too
        failed = step(t + 1, True, out, ids, stopped, act and errors is None)
        if errors is not None:
            newly[errors] |= ~unstable[errors]  # went_unstable's errors
        if failed or errors is not None:
            if newly.any():
                unstable |= newly
                steps[newly] = t + 1
                ids = np.flatnonzero(~unstable)
                # keep the last finite state of a failed episode in the records
                qpos[newly] = np.nan_to_num(qpos[newly])
                stopped = True
                if ids.size == 0:
                    rec.fill_from(t + 1)
                    break
            step(t + 1, False, no_sub, ids, stopped, act)
        if idx is not None and len(out):
            frozen = unstable if stopped else None
            rec.write_contacts(t + 1, live, *contact_maxima(out, idx), frozen)
        elif idx is not None:  # a MuJoCo error: like the touch maxima, row t
            rec.write_contacts(t + 1, live[:0], empty, empty, np.ones(n, bool))
    if bar is not None:
        bar.close()
    return RolloutResult(rec.arrays, unstable, steps, done)
