"""Gymnasium environments: the API checker, and an evolved genome gets the
engine's fitness through them."""

import numpy as np
import pytest

gym = pytest.importorskip("gymnasium", reason="extra locustjump[gym] not installed")

from gymnasium.utils.env_checker import check_env  # noqa: E402

from locustjump import rundir  # noqa: E402
from locustjump.envs import TASKS, LocustEnv  # noqa: E402
from locustjump.sim.controller import MLP  # noqa: E402


@pytest.mark.parametrize("env_id", list(TASKS))
def test_check_env(env_id, render_problem):
    if render_problem is not None:  # the API still gets checked, without frames
        # (the checker would make an rgb_array copy of the env and render it)
        check_env(gym.make(env_id).unwrapped, skip_render_check=True)
        pytest.skip("no offscreen rendering here (Debian package libegl1)")
    env = gym.make(env_id, render_mode="rgb_array", width=64, height=48).unwrapped
    check_env(env, skip_render_check=False)
    frame = env.render()
    assert frame.shape == (48, 64, 3) and frame.dtype == np.uint8
    env.close()


def test_registered_ids_and_time_limit():
    import locustjump.envs  # noqa: F401

    env = gym.make("LocustKick-v0")
    assert env.spec.max_episode_steps == 300
    env.reset(seed=0)
    for t in range(300):
        _, _, terminated, truncated, _ = env.step(np.zeros(4))
        assert not terminated
        assert truncated == (t == 299)
    env.close()
    for env_id in TASKS:
        assert gym.spec(env_id).max_episode_steps in (300, 1000, 3000)


def test_reset_start_option():
    env = LocustEnv("getup")
    assert env.n_starts == 5
    obs0, info = env.reset(options={"start": 0})
    obs4, _ = env.reset(options={"start": 4})
    assert info["start"] == 0 and not np.array_equal(obs0, obs4)
    with pytest.raises(ValueError, match="start"):
        env.reset(options={"start": 5})
    with pytest.raises(ValueError, match="unknown behaviour"):
        LocustEnv("fly")


def _env_fitness(task: str, genome: np.ndarray, scene=None) -> float:
    """Mean return over the task's start states of the genome's network, run
    through the environment (the action is the network's tanh output)."""
    net = MLP(output="linear")
    w = net.prepare(genome[None])
    env = LocustEnv(task, scene=scene)
    returns = []
    for i in range(env.n_starts):
        obs, _ = env.reset(options={"start": i})
        total, done = 0.0, False
        while not done:
            action = np.tanh(net.apply(w, obs[None]))[0]
            obs, r, terminated, truncated, _ = env.step(action)
            total += r
            done = terminated or truncated
        returns.append(total)
    return float(np.mean(returns))


@pytest.mark.parametrize(
    ("stage", "task"),
    [
        ("kick", "kick"),
        ("getup", "getup"),
        ("return-legs", "return-legs"),
        ("monolithic", "monolithic"),
    ],
)
def test_evolved_genome_gets_engine_fitness(shipped, stage, task):
    cfg, beh, best = rundir.load_run(shipped / stage)
    engine = float(beh.evaluate(best.genome[None], cfg.model, engine=cfg.engine)[0][0])
    assert engine == best.fitness  # the engine reproduces the recorded fitness
    np.testing.assert_allclose(_env_fitness(task, best.genome), engine, rtol=1e-9)


def test_debris_genome_gets_engine_fitness_on_each_terrain():
    """On a terrain the successive jump's return is the debris fitness (height
    above the ground under the body plus progress): a monolithic network
    trained on debris terrains 0 and 1 (results/debris-open) gets, through the
    environment on each of them, the NumPy engine's fitness there (the
    environment steps as that engine does; the compiled one it was trained on
    differs by a few ulp a step, which 3000 chaotic steps among rubble can
    grow into another trajectory, docs/performance.md)."""
    from pathlib import Path

    run = Path(__file__).resolve().parent.parent / "results/debris-open/quick-seed0"
    cfg, beh, best = rundir.load_run(run / "monolithic")
    scenes = beh.terrains.scenes
    assert len(scenes) == 2 and not scenes[1].is_flat
    per = []
    for scene in scenes:
        one = beh.on(scene)
        fit = one.evaluate(best.genome[None], cfg.model, engine="numpy")[0][0]
        env = LocustEnv("monolithic", scene=scene, model_params=cfg.model)
        assert env.scene == scene
        got = _env_fitness("monolithic", best.genome, scene=scene)
        np.testing.assert_allclose(got, fit, rtol=1e-9)
        per.append(fit)
    assert per[0] != per[1]  # the terrains differ
