"""Gymnasium environments of the paper's four tasks (extra ``locustjump[gym]``).

Importing this module registers them::

    import gymnasium as gym
    import locustjump.envs  # noqa: F401  (registers the Locust* ids)

    env = gym.make("LocustKick-v0", render_mode="rgb_array")
    obs, info = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())

(``gym.make("locustjump.envs:LocustKick-v0")`` imports it for you.)

==========================  ==================  ======  =====================
id                          task (paper)        steps   start states
==========================  ==================  ======  =====================
``LocustKick-v0``           kick (§3.1, Eq. 1)  300     1: ready, Fig. 4
``LocustGetUp-v0``          get up (§3.2)       1000    5: rolled 90–270 deg
``LocustReturnLegs-v0``     return legs (§3.3)  1000    1: legs extended
``LocustSuccessiveJump-v0`` successive (§4)     3000    1: lying on its side
==========================  ==================  ======  =====================

Each environment is one episode of the training engine
(:mod:`locustjump.rollout`), stepped on one ``MjData`` with the same
operations in the same order (:class:`~locustjump.rollout.Episode`), so a
genome run through it gets the engine's fitness (``tests/test_envs.py``).
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from locustjump import model as lm
from locustjump.behaviours import get_behaviour
from locustjump.model import CONTROL_DT
from locustjump.rollout import Episode
from locustjump.sensors import MAX_DELTA, N_ACTUATORS, N_INPUTS

#: environment id -> behaviour whose start states, length and fitness it has
TASKS: dict[str, str] = {
    "LocustKick-v0": "kick",
    "LocustGetUp-v0": "getup",
    "LocustReturnLegs-v0": "return-legs",
    "LocustSuccessiveJump-v0": "monolithic",
}

_OBS_LOW = np.array([0.0] * 4 + [-1.0, 0.0, -1.0, -1.0, -1.0])
_OBS_HIGH = np.array([2 * np.pi] * 4 + [1.0] * 5)


class LocustEnv(gym.Env):
    """The locust on the floor, one task of the paper.

    **Observation** ``Box(9,)`` float64, the paper's inputs
    (:mod:`locustjump.sensors`):

    =====  ====================================  ===========  ======
    index  meaning                               range        unit
    =====  ====================================  ===========  ======
    0–3    hip_l, knee_l, hip_r, knee_r angles   [0, 2 pi)    rad
    4      hind touch: +1 off, -1 on the floor   {-1, +1}     -
    5      1 / (H + 1), H height in body lengths  (0, 1]      -
    6–8    world up-axis in the body frame        [-1, 1]     -
    =====  ====================================  ===========  ======

    (index 8 is U_z: 1 upright, -1 on its back.)

    **Action** ``Box(-1, 1, (4,))`` float64: the change of each hind servo's
    target angle this control step, as a fraction of 10 deg (hip_l, knee_l,
    hip_r, knee_r). Targets are clipped to the joint ranges.

    **Step**: 1/120 s of simulated time (``model_params.substeps`` physics
    steps).

    **Reward** per step t = 1..T; the episode's return is the paper's fitness
    of the task:

    =================  ==============================================  ==========
    task               reward r_t                                       return
    =================  ==============================================  ==========
    kick               increase of max_{s<=t} dx_s^+ dz_s^+ (m^2)      Eq. 1
    getup              U_z(t) / T                                      Eq. 2
    return-legs        -sum_i abs(phi_i - theta_i(t)) / T (rad)         Eq. 3
    successive jump    z_t, the body's height (m)                      Eq. 4
    =================  ==============================================  ==========

    **Termination**: when the simulation goes unstable (``info["unstable"]``);
    the last reward then brings the return to the task's worst fitness, as in
    training. **Truncation**: after T steps (300, 1000, 1000, 3000).

    **Reset** ``options``: ``{"start": i}`` picks start state ``i`` (the
    getup task has 5: rolled 90, 135, 180, 225, 270 deg); otherwise one is
    drawn with the seeded ``np_random``. The paper's fitness of a controller
    is the mean return over all start states.

    Args:
      task: ``"kick"``, ``"getup"``, ``"return-legs"`` or ``"monolithic"``.
      render_mode: ``None`` or ``"rgb_array"``.
      model_params: the creature.
      width, height, camera: of the rendered frames (camera ``track``/``side``).
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": round(1 / CONTROL_DT)}

    def __init__(
        self,
        task: str = "kick",
        *,
        render_mode: str | None = None,
        model_params: lm.LocustParams = lm.LocustParams(),
        width: int = 640,
        height: int = 480,
        camera: str = "track",
    ):
        if task not in TASKS.values():
            raise ValueError(f"unknown task {task!r}; one of {sorted(TASKS.values())}")
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise ValueError(f"unsupported render_mode {render_mode!r}")
        self.task = task
        self.render_mode = render_mode
        self._behaviour = get_behaviour(task)
        self._episode = Episode(model_params)
        self._starts = self._behaviour.start_states(model_params)
        self._ready = np.asarray(model_params.ready_angles())
        self.n_steps = self._behaviour.n_steps
        self.observation_space = spaces.Box(_OBS_LOW, _OBS_HIGH, dtype=np.float64)
        self.action_space = spaces.Box(-1.0, 1.0, (N_ACTUATORS,), dtype=np.float64)
        self._size = (width, height)
        self._camera = camera
        self._renderer = None
        self._t = 0
        self._return = 0.0
        self._best = 0.0  # kick: max so far of dx+ dz+
        self._start_xyz = np.zeros(3)

    @property
    def model_params(self) -> lm.LocustParams:
        return self._episode.params

    @property
    def n_starts(self) -> int:
        return len(self._starts)

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        super().reset(seed=seed)
        options = options or {}
        if "start" in options:
            i = int(options["start"])
            if not 0 <= i < self.n_starts:
                raise ValueError(
                    f"options['start'] must be in [0, {self.n_starts}), got {i}"
                )
        else:
            i = int(self.np_random.integers(self.n_starts))
        obs = self._episode.reset(self._starts, i)[0]
        self._t, self._return, self._best = 0, 0.0, 0.0
        self._start_xyz = self._episode.data.qpos[:3].copy()
        return obs, {"start": i}

    def _reward(self, obs: np.ndarray) -> float:
        T = self.n_steps
        if self.task == "kick":
            d = self._episode.data.qpos[:3] - self._start_xyz
            area = max(d[0], 0.0) * max(d[2], 0.0)
            gain = max(area - self._best, 0.0)
            self._best = max(self._best, area)
            return gain
        if self.task == "getup":
            return float(obs[8]) / T
        if self.task == "return-legs":
            return -float(np.abs(obs[0:4] - self._ready).sum()) / T
        return float(self._episode.data.qpos[2])

    def step(
        self, action: np.ndarray
    ) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        if self._t >= self.n_steps:
            raise RuntimeError("step() after the episode ended; call reset()")
        a = np.clip(np.asarray(action, dtype=np.float64), -1.0, 1.0)
        obs = self._episode.step(a.reshape(1, N_ACTUATORS) * MAX_DELTA)[0]
        self._t += 1
        info: dict[str, Any] = {"unstable": self._episode.unstable}
        if self._episode.unstable:
            reward = self._behaviour.worst_fitness - self._return
            obs = np.clip(np.nan_to_num(obs), _OBS_LOW, _OBS_HIGH)
            terminated = True
        else:
            reward = self._reward(obs)
            terminated = False
        self._return += reward
        truncated = not terminated and self._t >= self.n_steps
        return obs, reward, terminated, truncated, info

    def render(self) -> np.ndarray | None:
        if self.render_mode != "rgb_array":
            return None
        if self._renderer is None:
            from locustjump.render import make_renderer

            self._renderer = make_renderer(self._episode.model, *self._size)
        self._renderer.update_scene(self._episode.data, camera=self._camera)
        return self._renderer.render()

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None


def register_envs() -> None:
    """Register the four ids with Gymnasium (done on import)."""
    for env_id, task in TASKS.items():
        if env_id not in gym.registry:
            gym.register(
                env_id,
                entry_point="locustjump.envs:LocustEnv",
                kwargs={"task": task},
                max_episode_steps=get_behaviour(task).n_steps,
            )


register_envs()

__all__ = ["TASKS", "LocustEnv", "N_INPUTS", "register_envs"]
