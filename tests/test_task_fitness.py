"""The getting-up and leg-return fitness (paper Eqs. 2 and 3), their dense
per-step forms, and how a behaviour scores its episodes (unstable ones at
the worst fitness, the mean over start states), on hand-made records
(tasks/getup.py, tasks/return_legs.py, tasks/base.py; issue #48,
scripts/mutation.py)."""

import numpy as np
import pytest

from locustjump.sim import model as lm
from locustjump.sim.engine.job import RolloutResult
from locustjump.sim.model import CONTROL_DT
from locustjump.tasks.composed import (
    PROGRESS_WEIGHT,
    successive_fitness,
    successive_terms,
)
from locustjump.tasks.getup import (
    SUCCESS_UZ,
    GetUp,
    UpReward,
    getup_summary,
    up_z,
)
from locustjump.tasks.kick import Kick
from locustjump.tasks.return_legs import LegsReward, ReturnLegs, joint_errors

P = lm.LocustParams()


def result(obs, unstable=None, qpos=None):
    n, t = obs.shape[:2]
    records = {"obs": obs}
    if qpos is not None:
        records["qpos"] = qpos
    unstable = np.zeros(n, bool) if unstable is None else np.asarray(unstable)
    return RolloutResult(records, unstable, np.full(n, t - 1))


def obs_with_uz(rows):
    uz = np.asarray(rows, dtype=float)
    obs = np.zeros((*uz.shape, 9))
    obs[:, :, 8] = uz
    return obs


# --- getting up (Eq. 2) ---------------------------------------------------------


def test_eq2_is_the_mean_up_axis_after_the_start():
    obs = obs_with_uz([[-1.0, 0.0, 0.5, 1.0], [1.0, -1.0, -1.0, -1.0]])
    res = result(obs)
    np.testing.assert_array_equal(up_z(res), obs[:, :, 8])
    np.testing.assert_array_equal(GetUp().episode_fitness(res, P), [0.5, -1.0])


def test_the_summary_says_when_it_first_got_up_and_where_it_ended():
    uz = np.array([[-1.0, 0.95, 0.5, 0.9], [0.0, 0.2, 0.3, 0.4], [0.9, 0.9, 0.9, 0.89]])
    s = getup_summary(uz)
    np.testing.assert_array_equal(s["final_uz"], [0.9, 0.4, 0.89])
    np.testing.assert_array_equal(s["success"], [True, False, False])
    np.testing.assert_array_equal(s["time_to_get_up_s"][[0, 2]], [CONTROL_DT, 0.0])
    assert np.isnan(s["time_to_get_up_s"][1]) and SUCCESS_UZ == 0.9


def test_the_dense_getting_up_reward_is_the_up_axis_over_the_episode_length():
    r = UpReward(GetUp(), P)
    r.reset(np.zeros(7), np.zeros(9))
    obs = np.zeros(9)
    obs[8] = 0.5
    assert r.step(np.zeros(7), obs) == 0.5 / GetUp.n_steps


# --- returning the legs (Eq. 3) -----------------------------------------------------


def test_eq3_is_minus_the_mean_summed_joint_error_after_the_start():
    ready = P.ready_angles()
    obs = np.zeros((1, 3, 9))
    obs[0, :, 0:4] = ready
    obs[0, 0, 0:4] += 5.0  # the start is not scored
    obs[0, 1, 0:4] += [0.1, -0.2, 0.0, 0.3]
    obs[0, 2, 0:4] -= [0.1, 0.0, 0.0, 0.0]
    res = result(obs)
    err = joint_errors(res, P)
    assert err.shape == (1, 3, 4)
    np.testing.assert_allclose(err[0, 1], [0.1, 0.2, 0.0, 0.3], atol=1e-12)
    fitness = ReturnLegs().episode_fitness(res, P)
    np.testing.assert_allclose(fitness, [-(0.6 + 0.1) / 2], atol=1e-12)


def test_the_dense_leg_reward_is_minus_the_summed_error_over_the_episode_length():
    r = LegsReward(ReturnLegs(), P)
    r.reset(np.zeros(7), np.zeros(9))
    obs = np.zeros(9)
    obs[0:4] = P.ready_angles() + [0.1, -0.1, 0.2, 0.0]
    assert r.step(np.zeros(7), obs) == pytest.approx(-0.4 / ReturnLegs.n_steps)


# --- scoring episodes ---------------------------------------------------------


class TwoStarts(GetUp):
    """Getting up from two start states (without settling them)."""

    def start_states(self, p):
        return [0, 1]

    def episode_terms(self, res, p):
        f = self.episode_fitness(res, p)
        return {"up": f, "bonus": np.ones_like(f)}


def test_fitness_is_the_mean_over_start_states_with_unstable_episodes_worst():
    # two controllers x two start states; episode 1 went unstable
    obs = obs_with_uz([[0, 1.0, 1.0], [0, 0.5, 0.5], [0, -0.5, -0.5], [0, 0.0, 0.0]])
    res = result(obs, unstable=[False, True, False, False])
    beh = TwoStarts()
    np.testing.assert_array_equal(beh.fitness(res, P), [(1.0 - 1.0) / 2, -0.25])
    terms = beh.fitness_terms(res, P)
    assert list(terms) == ["up", "bonus"]
    np.testing.assert_array_equal(terms["up"], [0.0, -0.25])
    np.testing.assert_array_equal(terms["bonus"], [0.5, 1.0])  # unstable: 0
    assert Kick().worst_fitness == 0.0 and GetUp.worst_fitness == -1.0
    assert ReturnLegs.worst_fitness == -4 * np.pi
    assert GetUp().episode_terms(res, P) == {}


# --- successive jumping (Eq. 4, and its terrain form) ----------------------------


class Level:
    """A terrain whose ground lies 0.5 m up everywhere."""

    is_flat = False

    def heights(self, x, y, body_length):
        return np.full(np.shape(x), 0.5)


def test_eq4_sums_the_height_after_the_start_and_a_terrain_adds_progress():
    q = np.zeros((2, 4, 7))
    q[0, :, 2] = [5.0, 1.0, 2.0, 3.0]  # the start is not scored
    q[1, :, 2] = [0.0, 0.5, 0.5, 0.5]
    q[:, :, 0] = [1.0, 1.1, 1.2, 1.25]
    height, distance = successive_terms(q, P)
    np.testing.assert_array_equal(height, [6.0, 1.5])
    np.testing.assert_array_equal(distance, [0.0, 0.0])
    np.testing.assert_array_equal(successive_fitness(q, P), [6.0, 1.5])
    height, distance = successive_terms(q, P, Level())
    np.testing.assert_allclose(height, [4.5, 0.0])
    np.testing.assert_allclose(distance, [PROGRESS_WEIGHT * 0.25] * 2)
    np.testing.assert_allclose(successive_fitness(q, P, Level()), [54.5, 50.0])
    assert PROGRESS_WEIGHT == 200.0


class LegsTwoStarts(ReturnLegs):
    """Returning the legs from two start states (without settling them)."""

    def start_states(self, p):
        return [0, 1]

    def episode_terms(self, res, p):
        return {"legs": self.episode_fitness(res, p)}


def test_scoring_reads_the_episodes_with_the_model_s_parameters():
    # each episode's error is its own: 0.4 and 0.2 rad summed over the joints
    obs = np.zeros((2, 2, 9))
    obs[:, :, 0:4] = P.ready_angles()
    obs[0, 1, 0:4] += 0.1
    obs[1, 1, 0] += 0.2
    res = result(obs)
    np.testing.assert_allclose(ReturnLegs().episode_fitness(res, P), [-0.4, -0.2])
    beh = LegsTwoStarts()
    np.testing.assert_allclose(beh.fitness(res, P), [-0.3])
    np.testing.assert_allclose(beh.fitness_terms(res, P)["legs"], [-0.3])


def test_eq4_takes_any_leading_shape_and_its_flat_distance_is_zeros_like_it():
    q = np.zeros((2, 3, 5, 7))
    q[..., 2] = [9.0, 1.0, 2.0, 3.0, 4.0]  # per step, the same for every episode
    q[1, 2, :, 2] *= 2.0
    height, distance = successive_terms(q, P)
    expected = np.full((2, 3), 10.0)
    expected[1, 2] = 20.0
    np.testing.assert_array_equal(height, expected)
    assert distance.shape == (2, 3) and distance.dtype == np.float64
    assert not distance.any()


def test_falls_and_recoveries_count_from_upright_to_overturned_and_back():
    from locustjump.tasks.composed import OVERTURNED_UZ, overturns

    assert (OVERTURNED_UZ, SUCCESS_UZ) == (0.0, 0.9)
    assert overturns(np.array([0.9, -1e-9])) == (1, 0)  # upright at 0.9 exactly
    assert overturns(np.array([0.9 - 1e-9, -1.0])) == (0, 0)  # never upright
    assert overturns(np.array([1.0, 0.0, 0.5])) == (0, 0)  # 0 is not overturned
    assert overturns(np.array([1.0, -0.5, -0.9, 0.9])) == (1, 1)  # back at 0.9
    assert overturns(np.array([1.0, -0.5, 0.9 - 1e-9])) == (1, 0)
    # a start on its side: upright first (not a recovery), then a fall and back
    assert overturns(np.array([0.0, 0.95, -0.2, 0.95])) == (1, 1)
    # lying overturned counts once; two falls, one recovery
    assert overturns(np.array([1.0, -0.5, -0.5, 0.95, -0.1, -0.3])) == (2, 1)
    assert overturns(np.array([1.0, -0.5, 0.95, -0.5, 0.95, -0.5, 0.95])) == (3, 3)


def test_the_dense_successive_reward_adds_height_and_progress_step_by_step():
    from locustjump.sim.scene import Debris, Terrains
    from locustjump.tasks import get_behaviour

    flat = get_behaviour("monolithic").reward(P)
    q0, q1 = np.zeros(7), np.zeros(7)
    q0[:3], q1[:3] = (0.1, 0.0, 0.2), (0.3, 0.0, 0.25)
    flat.reset(q0, np.zeros(9))
    assert flat.step(q1, np.zeros(9)) == 0.25  # Eq. 4's z, no progress term
    beh = get_behaviour("monolithic", terrains=Terrains(Debris(seed=0)))
    x, y, *_, h = beh.scene.boxes(P.body_length)[0]
    reward = beh.reward(P)
    q0[:3], q1[:3] = (x - 0.01, y, 0.3), (x, y, h + 0.2)
    reward.reset(q0, np.zeros(9))
    assert reward.step(q1, np.zeros(9)) == pytest.approx(0.2 + PROGRESS_WEIGHT * 0.01)
    q2 = q1.copy()
    q2[0] = x - 0.02  # back: the progress term is negative
    assert reward.step(q2, np.zeros(9)) == pytest.approx(
        float(h + 0.2 - beh.scene.heights(q2[0], y, P.body_length))
        - PROGRESS_WEIGHT * 0.02
    )
