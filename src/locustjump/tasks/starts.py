"""Start states: the creature settled on the ground of a scene before t = 0."""

from __future__ import annotations

import functools

import mujoco
import numpy as np

from locustjump.sim import model as lm
from locustjump.sim.engine.job import StartStates
from locustjump.sim.scene import Flat, Scene

#: (Seconds) settling on a terrain of the Fig. 4 posture (the keyframe's own)
READY_SETTLE = lm.SETTLE_TIME


def ground_top(p: lm.LocustParams, scene: Scene) -> float:
    """The highest point of the ground within a body length of the origin (m)."""
    if scene.is_flat:
        return 0.0
    bl = p.body_length
    g = np.linspace(-bl, bl, 101)
    return float(scene.heights(g[:, None], g[None, :], bl).max())


@functools.lru_cache(maxsize=16)
def ready_state(p: lm.LocustParams, scene: Scene = Flat()) -> StartStates:
    """The Fig. 4 start state: keyframe ``ready`` on the flat floor; on a
    terrain, that posture settled on it (:func:`settle`). Cached and shared:
    its arrays are read-only (copy them to change a start)."""
    if scene.is_flat:
        s = StartStates.ready(lm.load_model(p))
    else:
        s = settle(p, seconds=READY_SETTLE, scene=scene)
    for a in (s.qpos, s.qvel, s.ctrl):
        a.flags.writeable = False
    return s


def settle(
    p: lm.LocustParams,
    *,
    roll_deg: float = 0.0,
    angles: np.ndarray | None = None,
    seconds: float = 3.0,
    scene: Scene = Flat(),
) -> StartStates:
    """A start state settled on the ground before t = 0 (deterministic).

    The Fig. 4 posture (keyframe ``ready``) is rolled by ``roll_deg`` about the
    body's x-axis, its hind joints and servo targets set to ``angles`` (4,
    radians; default phi), lifted until its bounding spheres clear the ground
    (on a terrain: the highest point within a body length of the start), and
    simulated in ``scene`` for ``seconds`` with the servos holding their
    targets. On the flat floor the body is then moved back over the origin
    (heading and height kept); on a terrain it stays where it came to rest.
    """
    m = lm.load_model(p, scene)
    idx = lm.ModelIndex.of(m)
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, m.key(lm.READY_KEY).id)
    if angles is not None:
        d.qpos[idx.qpos_joints] = angles
        d.ctrl[:] = angles
    q_roll = np.empty(4)
    mujoco.mju_axisAngle2Quat(q_roll, np.array([1.0, 0.0, 0.0]), np.radians(roll_deg))
    q = np.empty(4)
    mujoco.mju_mulQuat(q, d.qpos[3:7].copy(), q_roll)  # rotation in the body frame
    d.qpos[3:7] = q
    mujoco.mj_forward(m, d)
    creature = m.geom_bodyid != 0
    low = (d.geom_xpos[creature, 2] - m.geom_rbound[creature]).min()
    d.qpos[2] += 1e-3 * p.scale - low + ground_top(p, scene)
    mujoco.mj_forward(m, d)
    mujoco.mj_step(m, d, nstep=round(seconds / m.opt.timestep))
    if scene.is_flat:
        d.qpos[:2] = 0.0
    return StartStates(d.qpos[None].copy(), d.qvel[None].copy(), d.ctrl[None].copy())
