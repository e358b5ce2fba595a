"""The kick's ceiling (:mod:`locustjump.tasks.ceiling`) on made-up genomes and
trajectories: the open-loop controller's blocks of target changes, and the
apex rise its fitness is."""

import numpy as np
import pytest

from helpers import exactly
from locustjump.sim.actuation import MAX_DELTA
from locustjump.tasks.ceiling import OPEN_LOOP_BLOCK, OpenLoop, apex_rise


def test_blocks_enough_for_an_episode():
    assert OPEN_LOOP_BLOCK == 5
    assert OpenLoop.covering(10) == OpenLoop(2, 5)
    assert OpenLoop.covering(11) == OpenLoop(3, 5)
    assert OpenLoop.covering(11, block=4) == OpenLoop(3, 4)
    assert OpenLoop.covering(1) == OpenLoop(1)
    c = OpenLoop(3, 4)
    assert (c.num_params, c.memory_size) == (12, 0)
    for blocks, block in ((0, 5), (2, 0), (-1, 5)):
        with pytest.raises(ValueError, match=exactly("blocks and block must be >= 1")):
            OpenLoop(blocks, block)
    assert OpenLoop(1, 1).num_params == 4


def test_a_genome_is_a_target_change_per_block_and_joint():
    c = OpenLoop(2, 3)
    g = np.array([[0.0, 1.0, -1.0, 2.0, 0.5, -0.5, 3.0, -3.0]])
    d = c.prepare(g)
    assert d.shape == (1, 3, 4)
    np.testing.assert_array_equal(d[0, :2], np.tanh(g[0]).reshape(2, 4) * MAX_DELTA)
    assert not d[0, 2].any()  # after the last block the targets stay put
    assert c.prepare([[1] * 8]).dtype == np.float64
    for bad in (np.zeros(8), np.zeros((1, 7)), np.zeros((1, 2, 4))):
        with pytest.raises(ValueError) as e:
            c.prepare(bad)
        assert str(e.value) == f"genome has shape {bad.shape}, expected (n, 8)"


def test_each_step_plays_its_block():
    c = OpenLoop(2, 3)
    g = np.arange(16.0).reshape(2, 8) / 10
    d = c.prepare(g)
    memory = np.zeros((2, 0))
    for step, block in ((0, 0), (2, 0), (3, 1), (5, 1), (6, 2), (100, 2)):
        deltas, mem = c.act(d, memory, np.zeros((2, 9)), np.zeros((2, 4)), step)
        np.testing.assert_array_equal(deltas, d[:, block])
        assert mem is memory


def test_the_apex_rise_is_above_the_start():
    q = np.zeros((2, 4, 7))
    q[0, :, 2] = [0.1, 0.3, 0.2, 0.05]
    q[1, :, 2] = [0.2, 0.1, 0.15, 0.0]
    q[:, :, 0] = 5.0  # along x: not counted
    np.testing.assert_allclose(apex_rise(q), [0.2, 0.0], rtol=0, atol=1e-15)
