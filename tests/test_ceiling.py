"""The kick's ceiling behaviours (issue #20): apex fitness, open-loop control."""

import numpy as np
import pytest

from locustjump.evo.rcga import RCGAParams
from locustjump.present.stages import reporter_of
from locustjump.rundir import load_run
from locustjump.rundir.config import TrainConfig
from locustjump.runs.trainer import train
from locustjump.sim.actuation import MAX_DELTA
from locustjump.sim.controller import MLP
from locustjump.tasks import behaviour_names
from locustjump.tasks.ceiling import OpenLoop, apex_rise


def test_open_loop_holds_each_block_then_stops():
    ctl = OpenLoop(blocks=3, block=2)
    assert ctl.num_params == 12 and ctl.memory_size == 0
    g = np.arange(24, dtype=float).reshape(2, 12) / 10 - 1
    prep = ctl.prepare(g)
    mem = np.zeros((2, 0))
    seen = [ctl.act(prep, mem, None, None, t)[0] for t in range(8)]
    for t in range(6):
        block = g[:, (t // 2) * 4 : (t // 2) * 4 + 4]
        np.testing.assert_array_equal(seen[t], np.tanh(block) * MAX_DELTA)
    assert not seen[6].any() and not seen[7].any()  # after the last block
    assert np.abs(np.array(seen)).max() <= MAX_DELTA
    assert OpenLoop.covering(300).blocks == 60
    with pytest.raises(ValueError, match="shape"):
        ctl.prepare(np.zeros((1, 5)))


def test_apex_rise_is_the_highest_point_above_the_start():
    q = np.zeros((2, 4, 7))
    q[0, :, 2] = [0.1, 0.5, 0.3, 0.2]
    q[1, :, 2] = [0.1, 0.05, 0.02, 0.1]
    np.testing.assert_allclose(apex_rise(q), [0.4, 0.0])


@pytest.mark.parametrize("name", ["kick-apex", "kick-open", "kick-apex-open"])
def test_ceiling_behaviours_train_and_score_what_they_say(name, tmp_path, params):
    assert name in behaviour_names()
    cfg = TrainConfig(name, 0, 2, RCGAParams(population=4))
    train(cfg, tmp_path / name, progress=False)
    _, beh, best = load_run(tmp_path / name)
    ctl = beh.controller
    assert ctl.num_params == (240 if "open" in name else MLP().num_params)
    res = beh.simulate(best.genome[None], params, record=("qpos",))
    q = res["qpos"]
    if "apex" in name:
        expected = q[:, :, 2].max(axis=1) - q[:, 0, 2]
    else:  # Eq. 1
        d = q[:, :, :3] - q[:, :1, :3]
        expected = (np.maximum(d[:, :, 0], 0) * np.maximum(d[:, :, 2], 0)).max(axis=1)
    np.testing.assert_array_equal(beh.fitness(res, params), expected)
    assert best.fitness == pytest.approx(float(expected[0]), abs=1e-12)
    assert reporter_of(name).claims(None) == []
