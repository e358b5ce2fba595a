"""The actuation rule (sim/actuation.py) on hand-made numbers: each change is
clipped to +-MAX_DELTA on either side, then each target to its joint's range
on either side; ``out`` receives the result, the targets are left alone
otherwise (issue #48, scripts/mutation.py)."""

import numpy as np

from locustjump.sim.actuation import N_ACTUATORS, apply_deltas
from locustjump.sim.kernels import MAX_DELTA

RANGES = np.array([[0.0, 1.0], [0.5, 2.0], [-1.0, 1.0], [1.0, 3.0]])


def test_changes_are_clipped_to_the_rate_limit_on_both_sides():
    targets = np.array([[0.5, 1.0, 0.0, 2.0]])
    deltas = np.array([[0.5, -0.5, 0.01, -0.01]])
    out = apply_deltas(targets, deltas, RANGES)
    np.testing.assert_array_equal(
        out, [[0.5 + MAX_DELTA, 1.0 - MAX_DELTA, 0.01, 2.0 - 0.01]]
    )
    np.testing.assert_array_equal(targets, [[0.5, 1.0, 0.0, 2.0]])
    assert MAX_DELTA == np.radians(10.0) and N_ACTUATORS == 4


def test_targets_are_clipped_to_each_joint_s_range_on_both_sides():
    targets = np.array([[0.05, 1.95, -0.95, 2.95], [0.95, 0.55, 0.95, 1.05]])
    deltas = np.array([[-0.1, 0.1, -0.1, 0.1], [0.1, -0.1, 0.1, -0.1]])
    out = apply_deltas(targets, deltas, RANGES)
    np.testing.assert_array_equal(out, [[0.0, 2.0, -1.0, 3.0], [1.0, 0.5, 1.0, 1.0]])


def test_out_receives_the_result_and_may_be_the_targets():
    targets = np.array([[0.5, 1.0, 0.0, 2.0]])
    deltas = np.full((1, 4), 0.01)
    out = np.zeros((1, 4))
    got = apply_deltas(targets, deltas, RANGES, out=out)
    assert got is out
    np.testing.assert_array_equal(out, targets + 0.01)
    same = apply_deltas(targets, deltas, RANGES, out=targets)
    assert same is targets
    np.testing.assert_array_equal(targets, [[0.51, 1.01, 0.01, 2.01]])
