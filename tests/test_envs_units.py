"""The Gymnasium environment's contract, piece by piece (``envs.py``): the
ids and their registration, each argument's check and its error, the action's
clipping, the end of an episode, and what an unstable step returns. Every test
here runs without drawing a frame (``scripts/mutation.py`` runs them with
MuJoCo's rendering off); ``tests/test_envs.py`` draws and checks the fitness."""

import warnings

import numpy as np
import pytest

gym = pytest.importorskip("gymnasium", reason="extra locustjump[gym] not installed")

from locustjump import envs  # noqa: E402
from locustjump.envs import LocustEnv  # noqa: E402
from locustjump.tasks import behaviour_class  # noqa: E402

IDS = {
    "LocustKick-v0": "kick",
    "LocustGetUp-v0": "getup",
    "LocustReturnLegs-v0": "return-legs",
    "LocustSuccessiveJump-v0": "monolithic",
}


def test_the_four_ids_and_their_behaviours():
    assert envs.tasks() == IDS
    assert envs.TASKS == IDS


@pytest.fixture
def unregistered():
    """The four ids taken out of Gymnasium's registry (and put back after)."""
    saved = {env_id: gym.registry.pop(env_id) for env_id in IDS}
    yield
    gym.registry.update(saved)


def test_each_id_is_registered_once_with_its_task_and_length(unregistered):
    envs.register_envs()
    for env_id, task in IDS.items():
        spec = gym.spec(env_id)
        assert spec.entry_point == "locustjump.envs:LocustEnv"
        assert spec.kwargs == {"task": task}
        assert spec.max_episode_steps == behaviour_class(task).n_steps
        assert gym.make(env_id).unwrapped.task == task
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # gymnasium warns when an id is overridden
        envs.register_envs()


def test_defaults_the_kick_and_a_640_x_480_frame():
    env = LocustEnv()
    assert env.task == "kick" and env.render_mode is None
    assert env._size == (640, 480)  # the frame's size (drawn in test_envs.py)
    assert env.render() is None  # no render mode: no frame
    assert LocustEnv(render_mode="rgb_array").render_mode == "rgb_array"


def test_a_behaviour_object_is_taken_as_it_is():
    getup = behaviour_class("getup")()
    env = LocustEnv(getup)
    assert env.task == "getup" and env.n_starts == 5


def test_spaces():
    env = LocustEnv("kick")
    a = env.action_space
    assert a.shape == (4,) and a.dtype == np.float64
    np.testing.assert_array_equal(a.low, -1.0)
    np.testing.assert_array_equal(a.high, 1.0)
    o = env.observation_space
    np.testing.assert_array_equal(o.low, [0, 0, 0, 0, -1, 0, -1, -1, -1])
    np.testing.assert_array_equal(o.high, [2 * np.pi] * 4 + [1] * 5)


@pytest.mark.parametrize(
    ("kwargs", "error", "message"),
    [
        ({"render_mode": "human"}, ValueError, "unsupported render_mode 'human'"),
        ({"width": 0}, ValueError, "width must be an integer in [1, 1280], got 0"),
        ({"width": 1281}, ValueError, "width must be an integer in [1, 1280], got"),
        ({"width": 1.5}, TypeError, "width must be an integer in [1, 1280], got 1.5"),
        ({"height": 0}, ValueError, "height must be an integer in [1, 720], got 0"),
        ({"height": 721}, ValueError, "height must be an integer in [1, 720], got"),
        ({"height": 2.5}, TypeError, "height must be an integer in [1, 720], got"),
        ({"camera": "top"}, ValueError, "camera must be one of track, side, got 'top'"),
    ],
)
def test_a_bad_argument_is_named(kwargs, error, message):
    with pytest.raises(error) as got:
        LocustEnv("kick", **kwargs)
    assert str(got.value).startswith(message)


def test_the_frames_limits_are_the_offscreen_buffers():
    assert LocustEnv(width=1, height=1)._size == (1, 1)
    assert LocustEnv(width=1280, height=720, camera="side")._size == (1280, 720)


def test_a_composition_has_no_environment():
    with pytest.raises(ValueError) as got:
        LocustEnv("composed")
    assert str(got.value) == (
        "composed builds on frozen runs (kick, getup, return-legs); "
        "it has no environment of its own"
    )


def test_a_start_out_of_range_or_not_an_integer_is_named():
    env = LocustEnv("getup")
    for bad, kind in [(1.7, TypeError), (True, TypeError), ("0", TypeError)]:
        with pytest.raises(kind, match=r"^options\['start'\] must be an integer"):
            env.reset(options={"start": bad})
    assert env.reset(options={"start": np.int64(0)})[1] == {"start": 0}
    for bad in (-1, 5):
        with pytest.raises(ValueError) as got:
            env.reset(options={"start": bad})
        assert (
            str(got.value)
            == f"options['start'] must be an integer in [0, 4], got {bad}"
        )
    assert env.reset(options={"start": 4})[1] == {"start": 4}


@pytest.mark.parametrize(
    ("action", "error", "message"),
    [
        (
            np.array([1j, 0, 0, 0]),
            TypeError,
            "action must be 4 finite real numbers, got",
        ),
        ("abcd", TypeError, "action must be 4 finite real numbers, got"),
        (np.array([True] * 4), TypeError, "action must be 4 finite real numbers, got"),
        (
            np.zeros((2, 2)),  # 4 numbers, but not a (4,) action
            ValueError,
            "action must be 4 finite real numbers (shape (4,)), got",
        ),
        (
            np.zeros(3),
            ValueError,
            "action must be 4 finite real numbers (shape (4,)), got",
        ),
        (
            np.array([np.nan, 0, 0, 0]),
            ValueError,
            "action must be 4 finite real numbers (shape (4,)), got",
        ),
    ],
)
def test_a_bad_action_is_named(action, error, message):
    env = LocustEnv("kick")
    env.reset(seed=0)
    with pytest.raises(error) as got:
        env.step(action)
    assert str(got.value) == f"{message} {action!r}"  # the value as given


def test_a_list_of_integers_is_an_action_of_floats():
    a, b = LocustEnv("kick"), LocustEnv("kick")
    a.reset(seed=0)
    b.reset(seed=0)
    np.testing.assert_array_equal(
        a.step([0, 1, 0, 1])[0], b.step(np.array([0.0, 1.0, 0.0, 1.0]))[0]
    )


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_an_action_beyond_one_is_clipped_to_one(sign):
    """3 (or -3) moves a servo's target as far as 1 (or -1), no farther; 0.5
    stays 0.5 (it moves less)."""
    runs = {}
    for size in (3.0, 1.0, 0.5):
        env = LocustEnv("kick")
        env.reset(seed=0)
        for _ in range(5):
            obs = env.step(sign * size * np.ones(4))[0]
        runs[size] = obs
    np.testing.assert_array_equal(runs[3.0], runs[1.0])
    assert not np.array_equal(runs[1.0], runs[0.5])


def test_step_before_reset_and_after_the_last_step_refuses():
    env = LocustEnv("kick")
    with pytest.raises(RuntimeError) as got:
        env.step(np.zeros(4))
    assert str(got.value) == "step() before reset() or after the episode ended"
    env.reset(seed=0)
    for t in range(env.n_steps):
        obs, reward, terminated, truncated, info = env.step(np.zeros(4))
        assert info == {"unstable": False} and terminated is False
        assert truncated == (t == env.n_steps - 1)
    with pytest.raises(RuntimeError, match="after the episode ended"):
        env.step(np.zeros(4))
    env.reset(seed=0)  # a new episode steps again
    assert env.step(np.zeros(4))[3] is False


def test_an_unstable_step_ends_the_episode_at_the_worst_fitness():
    """The simulation blown up after some steps: the last reward brings the
    return to the task's worst fitness, the episode terminates (not truncates)."""
    env = LocustEnv("getup")
    env.reset(options={"start": 2})
    rewards = [env.step(np.zeros(4))[1] for _ in range(10)]
    assert sum(rewards) != 0.0  # U_z / T each step
    env._episode.data.qvel[:] = 1e10
    obs, reward, terminated, truncated, info = env.step(np.zeros(4))
    assert (terminated, truncated, info) == (True, False, {"unstable": True})
    assert reward == pytest.approx(env._behaviour.worst_fitness - sum(rewards))
    assert env._return == pytest.approx(env._behaviour.worst_fitness)
    assert env.observation_space.contains(obs)
    with pytest.raises(RuntimeError, match="after the episode ended"):
        env.step(np.zeros(4))  # the episode is over


def test_an_unstable_steps_observation_is_put_inside_the_space(monkeypatch):
    """Whatever the blown-up state reads, the observation returned is finite
    and inside the observation space: NaN to 0, each value clipped to its
    bounds."""
    env = LocustEnv("getup")
    env.reset(options={"start": 0})
    raw = np.array([np.nan, -1.0, 7.0, np.inf, -np.inf, 2.0, 0.5, -3.0, 3.0])

    def blown_up(deltas):
        env._episode.unstable = True
        return raw[None].copy()

    monkeypatch.setattr(env._episode, "step", blown_up)
    obs = env.step(np.zeros(4))[0]
    np.testing.assert_array_equal(obs, [0, 0, 2 * np.pi, 2 * np.pi, -1, 1, 0.5, -1, 1])


def test_a_behaviour_without_a_dense_reward_gets_its_fitness_at_the_end():
    """kick-apex keeps the default sparse reward: 0 at every step but the
    last, which is the episode's fitness (the apex's rise of a kick)."""
    env = LocustEnv("kick-apex")
    env.reset(seed=0)
    rewards = [env.step(np.array([0.0, 1.0, 0.0, 1.0]))[1] for _ in range(env.n_steps)]
    assert all(r == 0.0 for r in rewards[:-1])
    assert rewards[-1] > 1.0  # metres of rise (1.48 m)
