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
(:mod:`locustjump.sim.engine.rollout`), stepped on one ``MjData`` with the same
operations in the same order (:class:`~locustjump.sim.engine.episode.Episode`), so a
genome run through it gets the engine's fitness (``tests/test_envs.py``).
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from locustjump.present.render import make_renderer
from locustjump.ranges import (
    Range,
    SettingTypeError,
    SettingValueError,
    check_choice,
)
from locustjump.sim import model as lm
from locustjump.sim import names
from locustjump.sim.actuation import MAX_DELTA, N_ACTUATORS
from locustjump.sim.engine.episode import Episode
from locustjump.sim.model import CONTROL_DT
from locustjump.sim.scene import Scene
from locustjump.sim.sensors import N_INPUTS
from locustjump.tasks import Behaviour, behaviour_class, behaviour_names


def tasks() -> dict[str, str]:
    """Environment id -> behaviour, for every behaviour that declares a
    ``gym_id``."""
    found = {}
    for name in behaviour_names():
        env_id = behaviour_class(name).gym_id
        if env_id is not None:
            found[env_id] = name
    return found


#: environment id -> behaviour whose start states, length and fitness it has
TASKS: dict[str, str] = tasks()

_OBS_LOW = np.array([0.0] * 4 + [-1.0, 0.0, -1.0, -1.0, -1.0])
_OBS_HIGH = np.array([2 * np.pi] * 4 + [1.0] * 5)


class LocustEnv(gym.Env):
    """The locust on the floor (or a terrain: ``scene``), one task of the paper.

    **Observation** ``Box(9,)`` float64, the paper's inputs
    (:mod:`locustjump.sim.sensors`):

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

    **Reward** per step t = 1..T (the behaviour's ``reward`` hook); the
    episode's return is the behaviour's fitness:

    =================  ==============================================  ==========
    task               reward r_t                                       return
    =================  ==============================================  ==========
    kick               increase of max_{s<=t} dx_s^+ dz_s^+ (m^2)      Eq. 1
    getup              U_z(t) / T                                      Eq. 2
    return-legs        -sum_i abs(phi_i - theta_i(t)) / T (rad)         Eq. 3
    successive jump    z_t, the body's height (m)                      Eq. 4
    =================  ==============================================  ==========

    On a terrain (``scene``) the successive jump's reward is z_t - h(x_t,
    y_t), the height above the ground under the body, plus 200 x (x_t -
    x_{t-1}) (m): its return is the debris fitness
    (:func:`~locustjump.tasks.composed.successive_fitness`).

    **Termination**: when the simulation goes unstable (``info["unstable"]``);
    the last reward then brings the return to the task's worst fitness, as in
    training. **Truncation**: after T steps (300, 1000, 1000, 3000). After
    either, and before the first ``reset()``, ``step()`` raises
    ``RuntimeError``. An action beyond +-1 moves a target by 10 deg, no more.

    Any registered behaviour has an environment: ``LocustEnv("name")`` or
    ``LocustEnv(behaviour_object)``; one without a dense reward of its own
    gets its fitness as the reward of the last step.

    **Reset** ``options``: ``{"start": i}`` picks start state ``i`` (the
    getup task has 5: rolled 90, 135, 180, 225, 270 deg); otherwise one is
    drawn with the seeded ``np_random``. The paper's fitness of a controller
    is the mean return over all start states.

    Args:
      task: a behaviour's name (``"kick"``, ``"getup"``, ``"return-legs"``,
        ``"monolithic"``, or one registered later) or a behaviour object.
      render_mode: ``None`` or ``"rgb_array"``.
      model_params: the creature.
      scene: where the episodes run (``locustjump.sim.scene.Debris(seed=3)``:
        one rubble field); default the behaviour's own, the flat floor for a
        name. Its start states are settled there.
      width: of the rendered frames (pixels).
      height: of the rendered frames (pixels).
      camera: of the rendered frames: ``track`` or ``side``.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": round(1 / CONTROL_DT)}

    def __init__(
        self,
        task: str | Behaviour = "kick",
        *,
        render_mode: str | None = None,
        model_params: lm.LocustParams = lm.LocustParams(),
        scene: Scene | None = None,
        width: int = 640,
        height: int = 480,
        camera: str = names.CAMERA_TRACK,
    ):
        if render_mode not in (None, *self.metadata["render_modes"]):
            raise ValueError(f"unsupported render_mode {render_mode!r}")
        beh = behaviour_class(task)() if isinstance(task, str) else task
        if scene is not None:
            beh = beh.on(scene)
        if beh.requires:
            raise ValueError(
                f"{beh.name} builds on frozen runs ({', '.join(beh.requires)}); "
                "it has no environment of its own"
            )
        self.task = beh.name
        self.render_mode = render_mode
        self._behaviour = beh
        self._episode = Episode(model_params, beh.scene)
        self._starts = beh.start_states(model_params)
        self._reward = beh.reward(model_params)
        self.n_steps = self._behaviour.n_steps
        self.observation_space = spaces.Box(_OBS_LOW, _OBS_HIGH, dtype=np.float64)
        self.action_space = spaces.Box(-1.0, 1.0, (N_ACTUATORS,), dtype=np.float64)
        vis = self._episode.model.vis.global_  # the offscreen buffer's size
        self._size = (
            Range(1, vis.offwidth, integer=True).check("width", width),
            Range(1, vis.offheight, integer=True).check("height", height),
        )
        self._camera = check_choice(
            "camera", camera, (names.CAMERA_TRACK, names.CAMERA_SIDE)
        )
        self._renderer: Any = None  # a mujoco.Renderer once rendering
        self._t = self.n_steps  # no episode until reset()
        self._return: float  # of the episode so far (set by reset())

    @property
    def model_params(self) -> lm.LocustParams:
        return self._episode.params

    @property
    def scene(self) -> Scene:
        return self._behaviour.scene

    @property
    def n_starts(self) -> int:
        return len(self._starts)

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        super().reset(seed=seed)
        options = options or {}
        if "start" in options:
            starts = Range(0, self.n_starts - 1, integer=True)
            i = starts.check("options['start']", options["start"])
        else:
            i = int(self.np_random.integers(self.n_starts))
        obs = self._episode.reset(self._starts, i)[0]
        self._t, self._return = 0, 0.0
        self._reward.reset(self._episode.data.qpos, obs)
        return obs, {"start": i}

    def step(
        self, action: np.ndarray
    ) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        if self._t >= self.n_steps:
            raise RuntimeError("step() before reset() or after the episode ended")
        # beyond +-1 the servo's step is clipped to +-10 deg (sim.actuation)
        a = _action(action)
        obs = self._episode.step(a.reshape(1, N_ACTUATORS) * MAX_DELTA)[0]
        self._t += 1
        info: dict[str, Any] = {"unstable": self._episode.unstable}
        if self._episode.unstable:
            reward = self._behaviour.worst_fitness - self._return
            obs = np.clip(np.nan_to_num(obs), _OBS_LOW, _OBS_HIGH)
            terminated = True
            self._t = self.n_steps  # the episode is over: step() refuses
        else:
            reward = self._reward.step(self._episode.data.qpos, obs)
            terminated = False
        self._return += reward
        truncated = not terminated and self._t >= self.n_steps
        return obs, reward, terminated, truncated, info

    def render(self) -> np.ndarray | None:
        if self.render_mode != "rgb_array":
            return None
        if self._renderer is None:
            self._renderer = make_renderer(self._episode.model, *self._size)
        self._renderer.update_scene(self._episode.data, camera=self._camera)
        frame: np.ndarray = self._renderer.render()
        return frame

    def close(self) -> None:
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None


def _action(action: Any) -> np.ndarray:
    """``action`` as the ``(N_ACTUATORS,)`` float64 array it must be: real,
    finite numbers (``TypeError`` for another kind, ``ValueError`` for
    another shape or a NaN)."""
    a = np.asarray(action)
    what = f"{N_ACTUATORS} finite real numbers"
    if a.dtype.kind not in "iuf":  # complex, bool, text, objects
        raise SettingTypeError("action", what, action)
    if a.shape != (N_ACTUATORS,) or not np.isfinite(a).all():
        raise SettingValueError("action", what + f" (shape ({N_ACTUATORS},))", action)
    return a.astype(np.float64)


def register_envs() -> None:
    """Register the four ids with Gymnasium (done on import)."""
    for env_id, task in tasks().items():
        if env_id not in gym.registry:
            gym.register(
                env_id,
                entry_point="locustjump.envs:LocustEnv",
                kwargs={"task": task},
                max_episode_steps=behaviour_class(task).n_steps,
            )


register_envs()

__all__ = ["TASKS", "LocustEnv", "N_INPUTS", "register_envs"]
