"""Get-up and return-legs behaviours: start states, fitness readings, sweep, CLI."""

import json
from pathlib import Path

import numpy as np
import pytest

from helpers import exit_status
from locustjump.cli import main
from locustjump.errors import UserError
from locustjump.evo.rcga import RCGAParams
from locustjump.rundir.config import TrainConfig
from locustjump.runs.trainer import train
from locustjump.sim.engine.rollout import RolloutResult
from locustjump.sim.sensors import up_axis_in_body
from locustjump.tasks import get_behaviour
from locustjump.tasks.getup import TRAIN_ROLLS, rolled_starts, sweep_angles
from locustjump.tasks.return_legs import extended_start
from locustjump.tasks.starts import settle


def test_settle_is_deterministic(params):
    a = settle(params, roll_deg=135.0)
    b = settle(params, roll_deg=135.0)
    for f in ("qpos", "qvel", "ctrl"):
        np.testing.assert_array_equal(getattr(a, f), getattr(b, f))


def test_rolled_starts_lie_on_the_ground_overturned(params):
    s = rolled_starts(params, TRAIN_ROLLS)
    uz = up_axis_in_body(s.qpos[:, 3:7])[:, 2]
    # our round-bodied creature rolls onto its back from every side (docs)
    assert (uz < -0.8).all()
    np.testing.assert_allclose(s.qpos[:, :2], 0.0)
    assert (s.qpos[:, 2] < 0.2 * params.body_length).all()
    # mirror images: 90 and 270 deg, 135 and 225 deg settle symmetric
    roll_y = up_axis_in_body(s.qpos[:, 3:7])[:, 1]
    assert roll_y[0] == pytest.approx(-roll_y[4], abs=1e-6)
    assert roll_y[1] == pytest.approx(-roll_y[3], abs=1e-6)


def test_extended_start_stands_with_legs_extended(params):
    s = extended_start(params)
    from locustjump.sim import model as lm

    idx = lm.ModelIndex.of(lm.load_model(params))
    err = np.degrees(np.abs(s.qpos[0, idx.qpos_joints] - params.kick_angles()))
    assert (err < 5).all()
    assert up_axis_in_body(s.qpos[:, 3:7])[0, 2] > 0.9


def fake_result(obs: np.ndarray) -> RolloutResult:
    n = obs.shape[0]
    return RolloutResult({"obs": obs}, np.zeros(n, bool), np.full(n, obs.shape[1] - 1))


def test_getup_fitness_is_the_mean_up_z_over_states_and_steps(params):
    beh = get_behaviour("getup")
    obs = np.zeros((10, 4, 9))  # 2 controllers x 5 states, 3 steps
    obs[:, 0, 8] = -1.0  # row 0 (the start) does not count
    obs[:5, 1:, 8] = np.linspace(-1, 1, 15).reshape(5, 3)
    obs[5:, 1:, 8] = 0.5
    f = beh.fitness(fake_result(obs), params)
    np.testing.assert_allclose(f, [0.0, 0.5], atol=1e-15)


def test_return_legs_fitness_is_minus_the_mean_summed_error(params):
    beh = get_behaviour("return-legs")
    phi = params.ready_angles()
    obs = np.zeros((1, 3, 9))
    obs[0, :, 0:4] = phi
    obs[0, 1, 0] += 0.2  # step 1: one joint off by 0.2 rad
    obs[0, 2, 1] -= 0.1  # step 2: another off by 0.1 rad
    obs[0, 0, 0:4] += 1.0  # the start does not count
    assert beh.fitness(fake_result(obs), params)[0] == pytest.approx(-(0.2 + 0.1) / 2)


def test_sweep_angles():
    a = sweep_angles()
    assert len(a) == 180 and a[0] == 90.5 and a[-1] == 269.5
    assert not set(a) & set(TRAIN_ROLLS)
    assert len(sweep_angles(45.0)) == 4
    for bad in ({"step_deg": 0}, {"step_deg": -1}, {"to_deg": 400}, {"from_deg": -5}):
        with pytest.raises(UserError, match=f"^{next(iter(bad))} must be") as e:
            sweep_angles(**bad)
        assert e.value.setting == next(iter(bad))  # the CLI prints its option


@pytest.fixture(scope="module")
def getup_run(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("getup") / "run"
    cfg = TrainConfig(
        behaviour="getup", generations=1, optimizer=RCGAParams(population=4)
    )
    train(cfg, out, progress=False)
    return out


def test_getup_evaluate_and_sweep(getup_run, capsys):
    assert main(["evaluate", str(getup_run)]) == 0
    out = capsys.readouterr().out
    assert "matches training" in out and "got_up_from" in out
    assert (getup_run / "eval" / "getup.png").is_file()
    assert len(list((getup_run / "eval").glob("trajectory_roll*.csv"))) == 5
    assert main(["sweep-getup", str(getup_run), "--step-deg", "45"]) == 0
    out = capsys.readouterr().out
    assert "of 4 (the paper: 65 of 180)" in out
    table = np.loadtxt(getup_run / "sweep" / "sweep.csv", delimiter=",", skiprows=1)
    assert table.shape == (9, 6)
    np.testing.assert_array_equal(table[:4, 0], [112.5, 157.5, 202.5, 247.5])
    assert table[4:, 1].all() and not table[:4, 1].any()
    assert (getup_run / "sweep" / "sweep.png").is_file()


@pytest.mark.parametrize(
    "args, match",
    [
        (["--step-deg", "0"], "--step-deg must be in [0.001, 360] degrees"),
        (["--step-deg", "-2"], "--step-deg must be in [0.001, 360] degrees"),
        (["--from-deg", "-10"], "--from-deg must be in [0, 360] degrees"),
        (["--to-deg", "365"], "--to-deg must be in [0, 360] degrees"),
        (["--from-deg", "300"], "--from-deg must be below --to-deg (270), got 300"),
        (["--to-deg", "10"], "--from-deg must be below --to-deg (10), got 90"),
        (["--from-deg", "10", "--to-deg", "10.5"],
         "--step-deg must be at most --to-deg - --from-deg (0.5), got 1"),
    ],
)  # fmt: skip
def test_sweep_bad_input(getup_run, capsys, args, match):
    assert exit_status(["sweep-getup", str(getup_run), *args]) == 2
    err = capsys.readouterr().err.strip()
    assert match in err and len(err.splitlines()) == 1


def test_sweep_and_resume_refuse_another_behaviour(getup_run, tmp_path, capsys):
    kick = tmp_path / "kick"
    cfg = TrainConfig(generations=1, optimizer=RCGAParams(population=4))
    train(cfg, kick, progress=False)
    assert main(["sweep-getup", str(kick)]) == 2
    assert "needs a getup run" in capsys.readouterr().err
    assert main(["train", "getup", "--resume", "--out", str(kick)]) == 2
    assert "holds a 'kick' run, not 'getup'" in capsys.readouterr().err
    assert main(["train", "kick", "--resume", "--out", str(getup_run)]) == 2
    assert "holds a 'getup' run, not 'kick'" in capsys.readouterr().err


def test_return_legs_trains_and_evaluates(tmp_path, capsys):
    out = tmp_path / "run"
    assert main(["train", "return-legs", "--population", "4", "--generations", "2",
                 "--quiet", "--out", str(out)]) == 0  # fmt: skip
    capsys.readouterr()
    assert main(["evaluate", str(out), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["fitness_matches"] and set(d["metrics"]["final_error_deg"]) == {
        "hip_l", "knee_l", "hip_r", "knee_r"
    }  # fmt: skip
    assert (out / "eval" / "return_legs.png").is_file()
