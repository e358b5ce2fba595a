"""A behaviour defined here, in the test, trains, evaluates, draws its figure,
re-simulates for a video and gets a Gymnasium environment without any other
module knowing it: the behaviour's hooks are the whole interface."""

from dataclasses import dataclass
from typing import Any

import numpy as np
import pytest

from helpers import run_cli
from locustjump import rundir
from locustjump import tasks as behaviours
from locustjump.errors import UserError
from locustjump.evo import RCGAParams
from locustjump.present.evaluate import evaluate_run
from locustjump.present.playback import playback_of
from locustjump.rundir.config import TrainConfig
from locustjump.runs.trainer import train
from locustjump.sim.controller import MLP
from locustjump.tasks import Behaviour, register_behaviour
from locustjump.tasks.base import CommonOptions, option
from locustjump.tasks.kick import ready_start


@dataclass(frozen=True)
class StandOptions(CommonOptions):
    #: control steps at the start that do not count
    settle_steps: int = option(0, "steps that do not count (default 0)", "STEPS")

    def __post_init__(self) -> None:
        super().__post_init__()
        if not 0 <= self.settle_steps < StandTall.n_steps:
            raise ValueError(
                f"settle_steps must be in [0, 200), got {self.settle_steps}"
            )


class StandTall(Behaviour):
    """Stand as tall as possible for 200 steps: fitness = mean body height
    (after ``settle_steps``)."""

    name = "stand-tall"
    n_steps = 200
    record = ("qpos",)
    Options = StandOptions

    def start_states(self, p):
        return ready_start(p)

    def episode_fitness(self, res, p):
        return res["qpos"][:, 1 + self.options.settle_steps :, 2].mean(axis=1)

    def metrics(self, res, p, genome, reference=None) -> dict[str, Any]:
        # Behaviour.metrics' signature: evaluate passes the reference (None
        # here: no reference_steps) positionally, whatever the behaviour
        assert reference is None
        return {"fitness": float(self.fitness(res, p)[0]),
                "max_height_m": float(res["qpos"][0, :, 2].max())}  # fmt: skip


@pytest.fixture
def stand(monkeypatch):
    monkeypatch.setattr(behaviours, "_REGISTRY", dict(behaviours._REGISTRY))
    register_behaviour(StandTall)
    return StandTall


def test_a_new_behaviour_runs_end_to_end(stand, tmp_path):
    cfg = TrainConfig(behaviour="stand-tall", generations=2,
                      optimizer=RCGAParams(population=4), seed=3)  # fmt: skip
    out = tmp_path / "stand"
    res = train(cfg, out, progress=False)
    assert res.generation == 2 and rundir.load_config(out / rundir.CONFIG) == cfg
    ev = evaluate_run(out)
    assert ev.matches and ev.metrics["max_height_m"] > 0
    assert (out / rundir.EVAL / "trajectory.png").is_file()  # the default figure
    pb = playback_of(out)  # what a video shows
    assert pb.qpos.shape[1] == 201 and pb.captions is None
    np.testing.assert_array_equal(pb.qpos[0, 1:, 2].mean(), ev.fitness)


@dataclass(frozen=True)
class TipToeOptions(StandOptions):
    # a switch of the behaviour's own, read from [options] (option() offers
    # no bool on the command line; a config file may hold one)
    on_toes: bool = False


class StandTallOnToes(StandTall):
    name = "stand-tall-on-toes"
    Options = TipToeOptions


def test_a_new_behaviours_switch_is_read_as_a_bool(monkeypatch):
    # no shipped setting is a bool: a behaviour's own [options] can be, and a
    # TOML true/false is then what it takes (not an integer, as for int fields)
    monkeypatch.setattr(behaviours, "_REGISTRY", dict(behaviours._REGISTRY))
    register_behaviour(StandTallOnToes)
    d = {"behaviour": "stand-tall-on-toes", "options": {"on_toes": True}}
    cfg = TrainConfig.from_dict(d, "c.toml")
    assert cfg.options.on_toes is True
    assert TrainConfig.from_dict(cfg.to_dict(), "again") == cfg
    d["options"]["on_toes"] = 1
    with pytest.raises(
        UserError, match="^c.toml: options.on_toes must be bool, got int 1$"
    ):
        TrainConfig.from_dict(d, "c.toml")


def test_a_new_behaviour_gets_an_environment(stand, tmp_path):
    gym = pytest.importorskip("gymnasium")
    from locustjump.envs import LocustEnv

    # the environment steps the user's NumPy policy: exact equality of return
    # and fitness holds for a run on the NumPy path (the compiled one differs
    # by ulps, tests/test_engine.py)
    cfg = TrainConfig(behaviour="stand-tall", generations=1,
                      optimizer=RCGAParams(population=4), seed=3,
                      engine="numpy")  # fmt: skip
    train(cfg, tmp_path / "s", progress=False)
    _, beh, best = rundir.load_run(tmp_path / "s")
    env = LocustEnv(StandTall())
    assert isinstance(env, gym.Env) and env.n_steps == 200
    net = MLP(output="linear")
    w = net.prepare(best.genome[None])
    obs, _ = env.reset(options={"start": 0})
    total, rewards, done = 0.0, [], False
    while not done:
        obs, r, terminated, truncated, _ = env.step(np.tanh(net.apply(w, obs[None]))[0])
        rewards.append(r)
        total += r
        done = terminated or truncated
    # the default reward is sparse: the episode's fitness at its last step
    assert all(r == 0.0 for r in rewards[:-1]) and len(rewards) == 200
    assert total == best.fitness


def test_a_new_behaviours_option_is_an_option_of_train(stand, tmp_path):
    """An option the behaviour declares (issue #48: the CLI special-cased the
    composed one's) is train's --NAME, checked by its Options, recorded."""
    out = tmp_path / "s"
    argv = ["train", "stand-tall", "--generations", "1", "--population", "4",
            "--quiet", "--out", str(out)]  # fmt: skip
    r = run_cli(*argv, "--settle-steps", "50")
    assert r.returncode == 0, r.stderr
    cfg = rundir.load_config(out / rundir.CONFIG)
    assert cfg.options == StandOptions(settle_steps=50)
    assert "\nsettle_steps = 50\n" in (out / rundir.CONFIG).read_text()
    bad = run_cli(*argv[:-1], str(tmp_path / "b"), "--settle-steps", "200")
    assert (bad.returncode, bad.stderr) == (
        2,
        "locustjump: error: --settle-steps: "
        "settle_steps must be in [0, 200), got 200\n",
    )
    other = run_cli(
        "train", "kick", "--settle-steps", "5", "--out", str(tmp_path / "k")
    )
    assert (other.returncode, other.stderr) == (
        2, "locustjump: error: --settle-steps: only the stand-tall behaviour "
        "takes it, not 'kick'\n")  # fmt: skip
    assert not (tmp_path / "b").exists() and not (tmp_path / "k").exists()
    help = run_cli("train", "--help").stdout
    assert "--settle-steps STEPS" in help and "stand-tall: steps that do not" in help
