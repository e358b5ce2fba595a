"""What the engine runs and returns: start states, a rollout job (picklable,
splittable by episode), its result, and what every engine strategy shares:
the name of the job's strategy, the per-step recording, the rule deciding
which episodes went unstable, and the progress bar."""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, cast, overload

import mujoco
import numpy as np
from numpy.typing import NDArray
from tqdm.auto import tqdm

from locustjump.ranges import INT64_MAX, Range
from locustjump.sim import actuation, sensors
from locustjump.sim import model as lm
from locustjump.sim.controller import Controller
from locustjump.sim.scene import Flat, Scene

#: What a control step records (:class:`Recorder`; the compiled kernels'
#: ``Records``, in this order).
STEP_RECORDS = ("qpos", "obs", "ctrl", "memory")
#: What the engine's loop records from the contact sensors (``names``:
#: ``DEEPEST_CONTACT``, ``WALL_CONTACT``) after every physics call, over the
#: control step's substeps (:func:`contact_maxima`): ``penetration``, the
#: deepest penetration (m, >= 0) of any contact of the creature, the maximum
#: over the substeps (into a geom's face: a contact inside a wall's margin,
#: short of the face, is none); ``wall_contact``, 1.0 when the creature
#: touched a wall of the scene at any substep (inside its margin counts),
#: else 0.0. Row 0: at the start state. Like the
#: touch input, a substep's value is of the state at its start (MuJoCo's
#: contacts of that ``mj_step``). Observations only: recording them changes
#: nothing else.
CONTACT_RECORDS = ("penetration", "wall_contact")
#: What can be recorded per control step (:func:`record_shapes`: its shape).
RECORDABLE = STEP_RECORDS + CONTACT_RECORDS
#: MuJoCo warnings that end an episode: all of them. Bad qpos/qvel/qacc mean
#: the simulation went unstable (MuJoCo resets its data); ``Batch.rollout``
#: stops stepping a simulation whose warning counters rise, whichever warning.
UNSTABLE = slice(0, int(mujoco.mjtWarning.mjNWARNING))
#: How the sensors, networks and actuation are computed between two physics
#: calls (the engine's strategies): NumPy, or compiled kernels
#: (:mod:`~locustjump.sim.kernels`). They agree bit for bit but for the
#: networks' sums and tanh (a few ulp a step, docs/performance.md), so a run
#: records its engine (``engine`` in ``config.toml``) and is re-simulated on it.
ENGINES = ("numpy", "numba")
#: The engine of new runs.
DEFAULT_ENGINE = "numba"
#: ``n_steps`` of an episode: control steps (whether they fit in memory is
#: checked apart: :func:`locustjump.sim.resources.require_memory`)
N_STEPS = Range(1, INT64_MAX, integer=True, unit="control steps")


def went_unstable(
    qpos: np.ndarray, warnings: np.ndarray, errors: np.ndarray | None = None
) -> np.ndarray:
    """The one rule deciding which episodes failed: (n,) bool.

    An episode failed when a MuJoCo warning of :data:`UNSTABLE` was counted
    (``warnings (n, mjNWARNING)``, the counts: ``Batch.warning[..., 1]`` or
    ``MjData.warning.number``), its ``qpos (n, nq)`` is not finite, or MuJoCo
    raised an error for it (``errors``: episode indices, ``SimulationError.ids``).
    The compiled kernels apply the same rule (``kernels.sense_and_check``).
    """
    counts = warnings[:, UNSTABLE]
    if errors is None and not counts.any() and np.isfinite(qpos).all():
        return np.zeros(qpos.shape[0], bool)  # one reduction each, nearly always
    bad: np.ndarray = (counts > 0).any(axis=1) | ~np.isfinite(qpos).all(axis=1)
    if errors is not None:
        bad[errors] = True
    return bad


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
        return int(self.qpos.shape[0])

    def take(self, idx: np.ndarray | Sequence[int] | slice) -> StartStates:
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
    #: the engine strategy (a key of ``strategies.STRATEGIES``: one of a
    #: run's ``ENGINES``, or another strategy such as ``numba-loop``)
    engine: str = DEFAULT_ENGINE
    #: the world the creature is in (``load_model(model_params, scene)``)
    scene: Scene = Flat()

    def __post_init__(self) -> None:
        object.__setattr__(self, "n_steps", N_STEPS.check("n_steps", self.n_steps))
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
        return int(self.params.shape[0])

    def split(self, k: int) -> list[RolloutJob]:
        """At most ``k`` contiguous sub-jobs covering all episodes, in order,
        none empty: the bounds are at least one episode apart before rounding,
        so they stay strictly increasing after it."""
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
                self.engine,
                self.scene,
            )
            for a, b in zip(bounds[:-1], bounds[1:], strict=True)
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

    def head(self, n: int) -> RolloutResult:
        """Its first ``n`` episodes (``control_steps``: all of them)."""
        return RolloutResult(
            {k: v[:n] for k, v in self.records.items()},
            self.unstable[:n],
            self.steps[:n],
            self.control_steps,
        )

    @classmethod
    def concat(cls, parts: Sequence[RolloutResult]) -> RolloutResult:
        names = parts[0].records.keys()
        return cls(
            {k: np.concatenate([p.records[k] for p in parts]) for k in names},
            np.concatenate([p.unstable for p in parts]),
            np.concatenate([p.steps for p in parts]),
            sum(p.control_steps for p in parts),
        )


def strategy_name(job: RolloutJob) -> str:
    """The name of the engine strategy that runs ``job`` (a key of
    :data:`~locustjump.sim.engine.strategies.STRATEGIES`); read here only."""
    return job.engine


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
    per_step = sum(int(np.prod(dims[k])) for k in record) * 8.0
    per_episode = (n_steps + 1) * per_step + m.narena + 64 * 1024
    total: float = float(n) * per_episode
    return total


def record_shapes(nq: int, nmem: int) -> dict[str, tuple[int, ...]]:
    """Per-step shape of each recordable field."""
    return {"qpos": (nq,), "obs": (sensors.N_INPUTS,), "ctrl": (actuation.N_ACTUATORS,),
            "memory": (nmem,), "penetration": (), "wall_contact": ()}  # fmt: skip


def records_contacts(job: RolloutJob) -> bool:
    """Whether ``job`` records any of :data:`CONTACT_RECORDS`."""
    return not set(job.record).isdisjoint(CONTACT_RECORDS)


@overload
def depth(min_dist: float) -> np.float64: ...
@overload
def depth(min_dist: np.ndarray) -> NDArray[np.float64]: ...
def depth(min_dist: float | np.ndarray) -> np.float64 | NDArray[np.float64]:
    """Penetration (m, >= 0) of a smallest signed contact distance (m)."""
    return np.maximum(-np.asarray(min_dist, dtype=np.float64), 0.0)


def contact_maxima(
    sub: np.ndarray, idx: lm.ModelIndex
) -> tuple[np.ndarray, np.ndarray]:
    """``(penetration (k,), wall_contact (k,))`` of one control step from the
    sensordata after each of its substeps, ``sub (k, substeps, nsensordata)``
    (:data:`CONTACT_RECORDS`)."""
    pen = depth(sub[:, :, idx.deepest].min(axis=1))
    wall = (sub[:, :, idx.walls] > 0).any(axis=(1, 2)).astype(np.float64)
    return pen, cast(np.ndarray, wall)  # (k,): any() over two of sub's three axes


def progress(job: RolloutJob) -> tqdm[Any] | None:
    """A progress bar over the control steps of a labelled job (shown on a
    terminal only)."""
    if not job.label:
        return None

    return tqdm(total=job.n_steps, desc=job.label, unit="step", disable=None,
                dynamic_ncols=True)  # fmt: skip


class Recorder:
    """Per-step copies of the requested fields; failed episodes repeat their last.

    The records of every engine strategy: ``arrays`` maps each recorded name
    to an ``(n, T + 1, ...)`` array (row 0 the start state), which the NumPy
    path fills with :meth:`write` and the compiled kernels fill in place
    (:data:`STEP_RECORDS`); the loop writes :data:`CONTACT_RECORDS` with
    :meth:`write_contacts`.
    """

    def __init__(
        self, names: Sequence[str], n: int, T: int, shape: dict[str, tuple[int, ...]]
    ):
        self.arrays = {k: np.empty((n, T + 1, *shape[k])) for k in names}
        step = [k for k in names if k in STEP_RECORDS]
        self._order = tuple(STEP_RECORDS.index(k) for k in step)
        self._step = tuple(self.arrays[k] for k in step)

    @classmethod
    def of(cls, job: RolloutJob, nq: int) -> Recorder:
        """The records of ``job`` on a model with ``nq`` position coordinates."""
        shapes = record_shapes(nq, job.controller.memory_size)
        return cls(job.record, job.n_episodes, job.n_steps, shapes)

    def write(
        self,
        t: int,
        qpos: np.ndarray,
        obs: np.ndarray,
        ctrl: np.ndarray,
        memory: np.ndarray,
        stopped: np.ndarray | None = None,
    ) -> None:
        """Row ``t``; episodes flagged in ``stopped`` repeat row ``t - 1``."""
        src = (qpos, obs, ctrl, memory)
        for i, a in zip(self._order, self._step, strict=True):
            a[:, t] = src[i]
            if stopped is not None:
                a[stopped, t] = a[stopped, t - 1]

    def write_contacts(
        self,
        t: int,
        ids: np.ndarray | int,
        penetration: np.ndarray | float,
        wall: np.ndarray | float,
        stopped: np.ndarray | None = None,
    ) -> None:
        """Row ``t`` of :data:`CONTACT_RECORDS` for episodes ``ids``; episodes
        flagged in ``stopped`` repeat row ``t - 1``."""
        for name, v in (("penetration", penetration), ("wall_contact", wall)):
            a = self.arrays.get(name)
            if a is not None:
                a[ids, t] = v
                if stopped is not None:
                    a[stopped, t] = a[stopped, t - 1]

    def fill_from(self, t: int) -> None:
        """Rows ``t`` on repeat row ``t - 1`` (every episode stopped)."""
        for a in self.arrays.values():
            a[:, t:] = a[:, t - 1 : t]
