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

import functools
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import mujoco
import numpy as np
from mujoco.batch import Batch, SimulationError

from locustjump.sim import model as lm
from locustjump.sim import sensors
from locustjump.sim.controller import Controller
from locustjump.sim.resources import require_memory

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend

#: What can be recorded per control step, and its per-step shape.
RECORDABLE = ("qpos", "obs", "ctrl", "memory")
#: MuJoCo warnings that end an episode: all of them. Bad qpos/qvel/qacc mean
#: the simulation went unstable (MuJoCo resets its data); ``Batch.rollout``
#: stops stepping a simulation whose warning counters rise, whichever warning.
_UNSTABLE = slice(0, int(mujoco.mjtWarning.mjNWARNING))


@dataclass(frozen=True)
class StartStates:
    """Physical start states: ``qpos (k, nq)``, ``qvel (k, nv)``, ``ctrl (k, nu)``."""

    qpos: np.ndarray
    qvel: np.ndarray
    ctrl: np.ndarray

    def __post_init__(self) -> None:
        k = self.qpos.shape[0]
        if self.qvel.shape[0] != k or self.ctrl.shape[0] != k:
            raise ValueError("StartStates arrays must have the same first dimension")

    def __len__(self) -> int:
        return self.qpos.shape[0]

    def take(self, idx: np.ndarray | Sequence[int]) -> StartStates:
        return StartStates(self.qpos[idx], self.qvel[idx], self.ctrl[idx])

    @classmethod
    def ready(cls, m: mujoco.MjModel) -> StartStates:
        """The settled ready-to-jump start state of Fig. 4 (keyframe ``ready``)."""
        key = m.key(lm.READY_KEY)
        return cls(key.qpos[None].copy(), key.qvel[None].copy(), key.ctrl[None].copy())

    @classmethod
    def concat(cls, states: Sequence[StartStates]) -> StartStates:
        return cls(
            *(
                np.concatenate([getattr(s, f) for s in states])
                for f in ("qpos", "qvel", "ctrl")
            )
        )


@dataclass(frozen=True)
class RolloutJob:
    """Everything one rollout needs; picklable, so any backend can ship it.

    Episode ``e`` runs controller parameters ``params[e]`` from start state
    ``e`` of ``starts`` for ``n_steps`` control steps.
    """

    model_params: lm.LocustParams
    controller: Controller
    params: np.ndarray  # (n, num_params)
    starts: StartStates  # n states
    n_steps: int
    record: tuple[str, ...] = ("qpos", "obs")
    label: str = ""  # a progress bar over the control steps when not empty

    def __post_init__(self) -> None:
        if self.n_steps < 1:
            raise ValueError(f"n_steps must be >= 1, got {self.n_steps}")
        if self.params.ndim != 2 or self.params.shape[1] != self.controller.num_params:
            raise ValueError(
                f"params has shape {self.params.shape}, expected "
                f"(n, {self.controller.num_params})"
            )
        if self.params.shape[0] != len(self.starts):
            raise ValueError("params and starts must have one row per episode")
        unknown = set(self.record) - set(RECORDABLE)
        if unknown:
            raise ValueError(
                f"cannot record {sorted(unknown)}; choose from {RECORDABLE}"
            )

    @property
    def n_episodes(self) -> int:
        return self.params.shape[0]

    def split(self, k: int) -> list[RolloutJob]:
        """At most ``k`` contiguous sub-jobs covering all episodes, in order."""
        bounds = np.linspace(0, self.n_episodes, min(k, self.n_episodes) + 1)
        bounds = bounds.round().astype(int)
        return [
            RolloutJob(
                self.model_params,
                self.controller,
                self.params[a:b],
                self.starts.take(slice(a, b)),
                self.n_steps,
                self.record,
                self.label,
            )
            for a, b in zip(bounds[:-1], bounds[1:], strict=True)
            if b > a
        ]


@dataclass
class RolloutResult:
    """Per-episode arrays of a rollout.

    Attributes:
      records: name -> (n, n_steps + 1, ...) array; row 0 is the start state,
        row t the state after control step t.
      unstable: (n,) bool, the episode went unstable and stopped.
      steps: (n,) int, control steps actually simulated.
    """

    records: dict[str, np.ndarray]
    unstable: np.ndarray
    steps: np.ndarray
    control_steps: int = field(default=0)  # total control steps simulated

    def __getitem__(self, name: str) -> np.ndarray:
        return self.records[name]

    @classmethod
    def concat(cls, parts: Sequence[RolloutResult]) -> RolloutResult:
        names = parts[0].records.keys()
        return cls(
            {k: np.concatenate([p.records[k] for p in parts]) for k in names},
            np.concatenate([p.unstable for p in parts]),
            np.concatenate([p.steps for p in parts]),
            sum(p.control_steps for p in parts),
        )


def observer(
    idx: lm.ModelIndex, p: lm.LocustParams
) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
    """``observe(qpos (n, nq), sensordata (n, nsensor)) -> (n, 9)`` paper inputs
    of a model with addresses ``idx``."""
    return functools.partial(
        sensors.paper_inputs,
        joint_adr=_as_slice(idx.qpos_joints),
        touch_adr=_as_slice(idx.touch),
        body_length=p.body_length,
    )


def _as_slice(adr: np.ndarray) -> np.ndarray | slice:
    """Consecutive addresses as a slice (a view, no gather), else unchanged."""
    a = np.asarray(adr)
    if a.size and (np.diff(a) == 1).all():
        return slice(int(a[0]), int(a[-1]) + 1)
    return a


def rollout_bytes(
    m: mujoco.MjModel, n: int, n_steps: int, record: Sequence[str], nmem: int = 1
) -> float:
    """Estimated memory of a rollout of ``n`` episodes: the records, one
    simulation each (its arena dominates) and the per-episode arrays."""
    dims = record_shapes(m.nq, nmem)
    per_step = sum(dims[k][0] for k in record) * 8.0
    per_episode = (n_steps + 1) * per_step + m.narena + 64 * 1024
    return float(n) * per_episode


def record_shapes(nq: int, nmem: int) -> dict[str, tuple[int, ...]]:
    """Per-step shape of each recordable field."""
    return {"qpos": (nq,), "obs": (sensors.N_INPUTS,), "ctrl": (sensors.N_ACTUATORS,),
            "memory": (nmem,)}  # fmt: skip


def run_batch(batch: Batch, job: RolloutJob) -> RolloutResult:
    """Every episode of ``job`` on ``batch``, on the job's engine path
    (``job.model_params.engine``): the NumPy loop below (the reference) or
    the compiled one, whose controllers run inside the batch's threads
    (:mod:`locustjump.sim.engine.incallback`; the same numbers as its step-by-step loop,
    :mod:`locustjump.sim.engine.compiled`)."""
    if job.model_params.engine == "numba":
        from locustjump.sim.engine.incallback import run_incallback

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
    rec = _Recorder(job.record, n, T, record_shapes(m.nq, ctl.memory_size))
    observe = observer(idx, p)
    obs = observe(qpos, sens)
    rec.write(0, qpos, obs, ctrl, memory)
    warn_bad = warn[:, _UNSTABLE, 1]  # a view: warning counts of every sim
    # sensordata after every substep (MuJoCo computes it at the substep's
    # start), reduced to its maximum over the control step: I5 sees a contact
    # at any substep, not only at the last one
    sub = {"sensordata": np.empty((n, p.substeps, m.nsensordata))}
    sens = np.array(sens)
    unstable = np.zeros(n, bool)
    steps = np.full(n, T)
    alive: np.ndarray | None = None  # None: all alive (no index array per step)
    done = 0
    bar = _progress(job)
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
            frozen=unstable if alive is not None else None,
        )
    if bar is not None:
        bar.close()
    return RolloutResult(rec.arrays, unstable, steps, done)


def _progress(job: RolloutJob):
    """A progress bar over the control steps of a labelled job (shown on a
    terminal only)."""
    if not job.label:
        return None
    from tqdm.auto import tqdm

    return tqdm(total=job.n_steps, desc=job.label, unit="step", disable=None,
                dynamic_ncols=True)  # fmt: skip


class _Recorder:
    """Per-step copies of the requested fields; failed episodes repeat their last."""

    def __init__(self, names: Sequence[str], n: int, T: int, shape: dict):
        self.arrays = {k: np.empty((n, T + 1, *shape[k])) for k in names}
        self._order = tuple(RECORDABLE.index(k) for k in names)

    def write(self, t, qpos, obs, ctrl, memory, frozen=None) -> None:
        """Row ``t``; episodes flagged in ``frozen`` repeat row ``t - 1``."""
        src = (qpos, obs, ctrl, memory)
        for i, a in zip(self._order, self.arrays.values(), strict=True):
            a[:, t] = src[i]
            if frozen is not None:
                a[frozen, t] = a[frozen, t - 1]

    def fill_from(self, t: int) -> None:
        for a in self.arrays.values():
            a[:, t:] = a[:, t - 1 : t]


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

    Raises:
      UserError: the rollout would not fit in the memory available.

    Returns:
      A :class:`RolloutResult` with ``n_ctrl * k`` episodes, controller-major:
      episode ``c * k + s`` is controller ``c`` from start state ``s``.
    """
    params = np.atleast_2d(np.asarray(params, dtype=np.float64))
    k = len(starts)
    require_memory(
        rollout_bytes(
            lm.load_model(model_params), params.shape[0] * k, int(n_steps), record,
            controller.memory_size,
        ),
        f"a rollout of {params.shape[0] * k:,} episodes x {int(n_steps):,} steps",
    )  # fmt: skip
    job = RolloutJob(
        model_params,
        controller,
        np.repeat(params, k, axis=0),
        starts.take(np.tile(np.arange(k), params.shape[0])),
        int(n_steps),
        tuple(record),
        label,
    )
    if backend is None:
        from locustjump.sim.engine.backends import ThreadBackend

        backend = ThreadBackend()
    return backend.run(job)
