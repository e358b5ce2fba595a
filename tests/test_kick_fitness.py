"""The kick's fitness (paper Eq. 1), its dense per-step form and the take-off
measure, on hand-made trajectories (tasks/kick.py; issue #48,
scripts/mutation.py)."""

import math

import numpy as np
import pytest

from locustjump.sim import model as lm
from locustjump.sim.engine.job import RolloutResult
from locustjump.sim.model import CONTROL_DT
from locustjump.tasks.kick import Kick, KickReward, kick_fitness, takeoff


def path(points, nq=5):
    """qpos rows for body-centre positions ``(x, z)``; y and the rest 0."""
    q = np.zeros((len(points), nq))
    q[:, 0] = [p[0] for p in points]
    q[:, 2] = [p[1] for p in points]
    return q


def test_eq1_is_the_largest_forward_times_upward_displacement_from_the_start():
    # from (10, 1): (+1, +2) -> 2; (+3, +1) -> 3; (-1, +5) -> 0; (+2, -1) -> 0
    a = path([(10, 1), (11, 3), (13, 2), (9, 6), (12, 0)])
    # never forward and up at once: 0
    b = path([(10, 1), (9, 2), (12, 0.5), (10, 1), (10, 1)])
    np.testing.assert_array_equal(kick_fitness(np.stack([a, b])), [3.0, 0.0])


def test_an_episode_s_fitness_is_eq1_of_its_recorded_positions():
    a = path([(10, 1), (11, 3), (13, 2)])
    b = path([(0, 0), (1, 1), (0, 0)])
    res = RolloutResult(
        {"qpos": np.stack([a, b]), "obs": np.zeros((2, 3, 9))},
        np.zeros(2, bool),
        np.array([2, 2]),
    )
    fitness = Kick().episode_fitness(res, lm.LocustParams())
    np.testing.assert_array_equal(fitness, [3.0, 1.0])


def test_the_dense_reward_adds_up_to_eq1_and_is_never_negative():
    q = path([(10, 1), (11, 3), (13, 2), (9, 6), (14, 1.5), (12, 0)])
    r = KickReward(Kick(), lm.LocustParams())
    r.reset(q[0], np.zeros(9))
    gains = [r.step(row, np.zeros(9)) for row in q[1:]]
    assert gains == [2.0, 1.0, 0.0, 0.0, 0.0]
    assert sum(gains) == kick_fitness(q[None])[0]
    r.reset(q[2], np.zeros(9))  # a new episode starts from its own start
    assert r.step(q[2] + [2.0, 0, 0.5, 0, 0], np.zeros(9)) == 1.0


def test_takeoff_is_the_last_touch_before_the_apex_with_the_next_step_s_velocity():
    q = path([(0, 0), (0, 0), (0.01, 0.01), (0.03, 0.05), (0.05, 0.08), (0.07, 0.06)])
    touch = np.array([True, True, False, False, False, True])
    t, speed, angle = takeoff(q, touch, apex=4)
    v = (q[2, [0, 2]] - q[1, [0, 2]]) / CONTROL_DT
    assert t == 1
    assert speed == pytest.approx(math.hypot(*v))
    assert angle == pytest.approx(45.0)
    t, speed, angle = takeoff(q, np.zeros(6, bool), apex=4)  # never touched
    assert t == 0 and speed == 0.0 and angle == 0.0
    t, _, angle = takeoff(q, touch, apex=2)
    assert t == 1 and angle == pytest.approx(45.0)
    t, _, angle = takeoff(q, np.array([1, 1, 1, 0, 0, 0], bool), apex=3)
    assert t == 2 and angle == pytest.approx(math.degrees(math.atan2(0.04, 0.02)))
