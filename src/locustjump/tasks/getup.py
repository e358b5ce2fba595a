"""Behaviour Simple 2: getting up after overturning (paper §3.2, Fig. 8–9).

* start: the Fig. 4 posture rolled about the body x-axis by 90, 135, 180, 225
  and 270 deg (one side -> upside down -> the other side) and settled on the
  ground for 3 s (:func:`~locustjump.tasks.starts.settle`). On our creature
  the round body cannot rest on its side: every roll in [90, 270] deg settles
  on its back, tilted towards the side it started on (``docs/behaviours.md``);
* episode: 1000 control steps from each of the 5 states (one engine call);
* fitness (our reading of Eq. 2, SPEC): the mean over states and steps of
  U_z(t), the world z of the body's up-axis (input I9): 1 upright, -1 on its
  back. Success from a state: U_z >= 0.9 at the end of the episode.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from tqdm.auto import tqdm

from locustjump.errors import setting_ref
from locustjump.ranges import Range, SettingValueError
from locustjump.sim import model as lm
from locustjump.sim.engine.job import (
    DEFAULT_ENGINE,
    RolloutResult,
    StartStates,
    rollout_bytes,
)
from locustjump.sim.engine.rollout import rollout
from locustjump.sim.model import CONTROL_DT
from locustjump.sim.resources import require_memory
from locustjump.sim.scene import Flat, Scene
from locustjump.tasks.base import Behaviour, StepReward
from locustjump.tasks.reference import RulesRun
from locustjump.tasks.starts import settle

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend

TRAIN_ROLLS: tuple[float, ...] = (90.0, 135.0, 180.0, 225.0, 270.0)  # (deg)
SUCCESS_UZ = 0.9
SETTLE_SECONDS = 3.0  # rocking on the back dies out by then (docs/behaviours.md)


@functools.lru_cache(maxsize=16)
def rolled_starts(
    p: lm.LocustParams, rolls: tuple[float, ...], scene: Scene = Flat()
) -> StartStates:
    """Settled start states for roll angles ``rolls`` (degrees), in order, in
    ``scene``."""
    for r in rolls:
        if not 0.0 <= r < 360.0:
            raise ValueError(f"roll angle must be in [0, 360) degrees, got {r:g}")
    return StartStates.concat(
        [settle(p, roll_deg=r, seconds=SETTLE_SECONDS, scene=scene) for r in rolls]
    )


def _settled(p: lm.LocustParams, rolls: tuple[float, ...], scene: Scene) -> StartStates:
    """:func:`rolled_starts` of many states, with a progress bar (terminal)."""
    if len(rolls) <= 2 * len(TRAIN_ROLLS):
        return rolled_starts(p, rolls, scene)

    return StartStates.concat(
        [
            rolled_starts(p, (r,), scene)
            for r in tqdm(
                rolls, desc="settling start states", unit="state", disable=None
            )  # fmt: skip
        ]
    )


def up_z(res: RolloutResult) -> np.ndarray:
    """(n, T + 1) U_z of every episode."""
    return res["obs"][:, :, 8]


def getup_summary(uz: np.ndarray) -> dict[str, np.ndarray]:
    """Per episode: final U_z, success, time to get up (s; NaN if never)."""
    final = uz[:, -1]
    success = final >= SUCCESS_UZ
    reached = uz >= SUCCESS_UZ
    first = np.where(reached.any(axis=1), reached.argmax(axis=1), -1)
    t_up = np.where(first >= 0, first * CONTROL_DT, np.nan)
    return {"final_uz": final, "success": success, "time_to_get_up_s": t_up}


class UpReward(StepReward):
    """Dense Eq. 2: ``U_z(t) / T``."""

    def reset(self, qpos: np.ndarray, obs: np.ndarray) -> None:
        pass

    def step(self, qpos: np.ndarray, obs: np.ndarray) -> float:
        return float(obs[8]) / self.behaviour.n_steps


class GetUp(Behaviour):
    name = "getup"
    n_steps = 1000
    record = ("obs",)
    worst_fitness = -1.0
    rolls = TRAIN_ROLLS
    gym_id = "LocustGetUp-v0"

    def start_states(self, p: lm.LocustParams) -> StartStates:
        return rolled_starts(p, self.rolls, self.scene)

    def episode_fitness(self, res: RolloutResult, p: lm.LocustParams) -> np.ndarray:
        fitness: np.ndarray = up_z(res)[:, 1:].mean(axis=1)
        return fitness

    def state_labels(self) -> list[str]:
        return [f"roll{r:03.0f}" for r in self.rolls]

    def metrics(
        self,
        res: RolloutResult,
        p: lm.LocustParams,
        genome: np.ndarray,
        reference: RulesRun | None = None,
    ) -> dict[str, Any]:
        s = getup_summary(up_z(res))
        return {
            "fitness": float(self.fitness(res, p)[0]),
            "got_up_from": f"{int(s['success'].sum())} of {len(self.rolls)}",
            "roll_deg": list(self.rolls),
            "start_uz": [round(float(u), 4) for u in up_z(res)[:, 0]],
            "final_uz": [round(float(u), 4) for u in s["final_uz"]],
            "success": [bool(b) for b in s["success"]],
            "time_to_get_up_s": [
                None if np.isnan(t) else round(float(t), 4)
                for t in s["time_to_get_up_s"]
            ],
            "unstable": int(res.unstable.sum()),
        }

    def reward(self, p: lm.LocustParams) -> StepReward:
        return UpReward(self, p)


#: ``step_deg``: (degrees) between two start states of the sweep; a
#: thousandth of a degree is far finer than any controller can tell apart
STEP_DEG = Range(1.0e-3, 360.0, unit="degrees")
#: ``from_deg``, ``to_deg``: (degrees) a start state's roll angle in the sweep
ROLL_DEG = Range(0.0, 360.0, unit="degrees")


def sweep_angles(
    step_deg: float = 1.0, from_deg: float = 90.0, to_deg: float = 270.0
) -> np.ndarray:
    """The generalisation test's roll angles: the centres of ``step_deg`` bins
    from ``from_deg`` to ``to_deg`` (1 deg: 90.5, 91.5, ..., 269.5, i.e. 180
    states from one side to the other, none equal to a training state)."""
    step_deg = STEP_DEG.check("step_deg", step_deg)
    from_deg = ROLL_DEG.check("from_deg", from_deg)
    to_deg = ROLL_DEG.check("to_deg", to_deg)
    if not from_deg < to_deg:  # named by both: either may be the one to change
        raise SettingValueError(
            "from_deg", f"below {setting_ref('to_deg')} ({to_deg:g})", from_deg
        )
    n = int(np.floor((to_deg - from_deg) / step_deg + 1e-9))
    if n < 1:
        raise SettingValueError(
            "step_deg",
            f"at most {setting_ref('to_deg')} - {setting_ref('from_deg')} "
            f"({to_deg - from_deg:g})",
            step_deg,
        )
    require_memory(
        rollout_bytes(lm.load_model(), n + len(TRAIN_ROLLS), GetUp.n_steps, ("obs",)),
        f"a sweep of {n:,} start states",
        setting=("step_deg", step_deg),
    )
    return from_deg + step_deg * (np.arange(n) + 0.5)


@dataclass(frozen=True)
class Sweep:
    """Outcome of the get-up generalisation test, one entry per start state."""

    roll_deg: np.ndarray
    training: np.ndarray  # bool: one of the five training states
    start_uz: np.ndarray
    final_uz: np.ndarray
    success: np.ndarray
    time_to_get_up_s: np.ndarray

    @property
    def got_up(self) -> int:
        """States of the sweep proper (not the training ones) got up from."""
        return int(self.success[~self.training].sum())

    @property
    def n_sweep(self) -> int:
        return int((~self.training).sum())


def sweep_getup(
    genome: np.ndarray,
    p: lm.LocustParams,
    angles: np.ndarray,
    *,
    backend: Backend | None = None,
    engine: str = DEFAULT_ENGINE,
    scene: Scene = Flat(),
) -> Sweep:
    """Evaluate one get-up controller from ``angles`` plus the training states
    (in ``scene``)."""
    rolls = tuple(float(a) for a in angles) + TRAIN_ROLLS
    res = rollout(
        GetUp().controller,
        genome[None],
        _settled(p, rolls, scene),
        GetUp.n_steps,
        model_params=p,
        record=("obs",),
        backend=backend,
        label=f"sweep: {len(rolls)} states",
        engine=engine,
        scene=scene,
    )
    uz = np.where(res.unstable[:, None], -1.0, up_z(res))
    s = getup_summary(uz)
    training = np.arange(len(rolls)) >= len(angles)
    return Sweep(
        np.array(rolls), training, uz[:, 0], s["final_uz"], s["success"],
        s["time_to_get_up_s"],
    )  # fmt: skip
