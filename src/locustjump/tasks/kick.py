"""Behaviour Simple 1: kicking the ground (paper §3.1, Fig. 6–7).

* start: the settled ready-to-jump posture of Fig. 4 (keyframe ``ready``);
* episode: 300 control steps (2.5 s);
* fitness (Eq. 1, SPEC): ``E = max_t max(dx_t, 0) * max(dz_t, 0)``, with
  ``dx, dz`` the body centre's displacement from its start position: the area
  of the rectangle from the start point to the highest-and-furthest point of
  the jump. Unit: m^2.
* behaviour descriptors (quality diversity, :data:`KICK_DESCRIPTORS`), from
  the same body-centre trajectory (at the trained resolution: the option
  ``score_substeps`` changes the fitness, not them), at the apex (the step of greatest
  height): ``apex_rise``, its height over the start (body lengths, 0 to 5);
  ``apex_distance``, its distance ahead (body lengths, -5 to 15);
  ``apex_angle``, its direction from the start, ``atan2(rise, ahead)``
  (degrees, 0 to 180). Each is the mean over start states and terrains, as
  the fitness; an unstable episode counts at each descriptor's low end
  (``tasks.descriptors``), and an archive clips a value outside its range
  to the edge cell.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np

from locustjump.sim import model as lm
from locustjump.sim.analysis import find_jumps
from locustjump.sim.engine.job import RolloutResult, StartStates
from locustjump.sim.model import CONTROL_DT
from locustjump.sim.scene import Flat, Scene
from locustjump.tasks.base import Behaviour, StepReward
from locustjump.tasks.descriptors import Descriptor
from locustjump.tasks.reference import RulesRun
from locustjump.tasks.starts import ready_state


def ready_start(p: lm.LocustParams, scene: Scene = Flat()) -> StartStates:
    """The settled Fig. 4 start state (keyframe ``ready``; on a terrain, that
    posture settled on it)."""
    return ready_state(p, scene)


def kick_fitness(qpos: np.ndarray) -> np.ndarray:
    """Eq. 1 for trajectories ``qpos (n, T + 1, nq)``: (n,) in m^2."""
    d = qpos[:, :, :3] - qpos[:, :1, :3]
    dx = np.maximum(d[:, :, 0], 0.0)
    dz = np.maximum(d[:, :, 2], 0.0)
    area: np.ndarray = (dx * dz).max(axis=1)
    return area


def kick_descriptors(qpos: np.ndarray, body_length: float) -> dict[str, np.ndarray]:
    """The kick's behaviour descriptors (module docstring) of trajectories
    ``qpos (n, T + 1, nq)``: ``(n,)`` each, lengths in body lengths."""
    apex = np.argmax(qpos[:, :, 2], axis=1)
    at = qpos[np.arange(len(qpos)), apex, :3] - qpos[:, 0, :3]
    rise, ahead = at[:, 2], at[:, 0]
    return {
        "apex_rise": rise / body_length,
        "apex_distance": ahead / body_length,
        "apex_angle": np.degrees(np.arctan2(rise, ahead)),
    }


#: the kick's behaviour descriptors (module docstring)
KICK_DESCRIPTORS = (
    Descriptor("apex_rise", 0.0, 5.0, "L", "the apex's height over the start"),
    Descriptor("apex_distance", -5.0, 15.0, "L", "the apex's distance ahead"),
    Descriptor("apex_angle", 0.0, 180.0, "deg", "the apex's direction"),
)


def takeoff(qpos: np.ndarray, touch: np.ndarray, apex: int) -> tuple[int, float, float]:
    """Take-off of the jump peaking at ``apex``: (step, speed m/s, angle deg).

    Take-off is the last control step before the apex at which a hind tarsus
    touched the ground (``touch``, bool per step); the velocity is the body
    centre's finite difference over the next control step, in the x-z plane;
    the angle is measured from the ground (+x) upwards.
    """
    on = np.flatnonzero(touch[: apex + 1])
    t = int(on[-1]) if on.size else 0
    v = (qpos[t + 1, :3] - qpos[t, :3]) / CONTROL_DT
    return t, float(math.hypot(v[0], v[2])), float(math.degrees(math.atan2(v[2], v[0])))


class KickReward(StepReward):
    """Dense Eq. 1: the increase of ``max_{s<=t} dx_s^+ dz_s^+`` (m^2)."""

    def reset(self, qpos: np.ndarray, obs: np.ndarray) -> None:
        self._start, self._best = qpos[:3].copy(), 0.0

    def step(self, qpos: np.ndarray, obs: np.ndarray) -> float:
        d = qpos[:3] - self._start
        area: float = max(d[0], 0.0) * max(d[2], 0.0)
        gain = max(area - self._best, 0.0)
        self._best = max(self._best, area)
        return gain


class Kick(Behaviour):
    name = "kick"
    n_steps = 300
    #: its first jump may land after the kick's episode ends
    reference_steps = 2 * n_steps
    record = ("qpos",)
    worst_fitness = 0.0
    gym_id: ClassVar[str | None] = "LocustKick-v0"
    descriptors = KICK_DESCRIPTORS
    default_descriptors = ("apex_distance", "apex_rise")

    def start_states(self, p: lm.LocustParams) -> StartStates:
        return ready_start(p, self.scene)

    def episode_fitness(self, res: RolloutResult, p: lm.LocustParams) -> np.ndarray:
        return kick_fitness(res["qpos"])

    def episode_descriptors(
        self, res: RolloutResult, p: lm.LocustParams
    ) -> dict[str, np.ndarray]:
        return kick_descriptors(res["qpos"], p.body_length)

    def metrics(
        self,
        res: RolloutResult,
        p: lm.LocustParams,
        genome: np.ndarray,
        reference: RulesRun | None = None,
    ) -> dict[str, Any]:
        """Apex height/rise/distance, take-off speed/angle, and the rule-based
        first jump's apex for comparison (paper Fig. 7: about 2x;
        ``reference``: :meth:`reference`, simulated here if not given; no
        ``rules_*`` keys for a behaviour that compares with none)."""
        qpos, obs = res["qpos"][0], res["obs"][0]
        z0, x0 = qpos[0, 2], qpos[0, 0]
        apex = int(np.argmax(qpos[:, 2]))
        t_off, speed, angle = takeoff(qpos, obs[:, 4] < 0, apex)
        jumps = find_jumps(qpos, p)
        rules = self.reference(p) if reference is None else reference
        out: dict[str, Any] = {
            "fitness": float(self.fitness(res, p)[0]),
            "apex_height_m": float(qpos[apex, 2]),
            "apex_rise_m": float(qpos[apex, 2] - z0),
            "apex_step": apex,
            "distance_at_apex_m": float(qpos[apex, 0] - x0),
            "takeoff_step": t_off,
            "takeoff_speed_m_s": speed,
            "takeoff_angle_deg": angle,
            "jumps": len(jumps),
            "first_jump_apex_height_m": jumps[0].apex_height if jumps else None,
            "unstable": bool(res.unstable[0]),
        }
        if rules is None:  # reference_steps = 0: compares with none
            return out
        first = rules.jumps[0] if rules.jumps else None
        # the rule-based jumping's own fitness over the same 300 steps
        out["rules_fitness"] = float(
            kick_fitness(rules.qpos[None, : self.n_steps + 1])[0]
        )
        if first is not None:  # same start state, so the same z0
            rise = first.apex_height - z0
            out["rules_first_apex_height_m"] = first.apex_height
            out["rules_first_apex_rise_m"] = rise
            out["apex_height_ratio_to_rules"] = out["apex_height_m"] / first.apex_height
            out["apex_rise_ratio_to_rules"] = out["apex_rise_m"] / rise
        return out

    def reward(self, p: lm.LocustParams) -> StepReward:
        return KickReward(self, p)
