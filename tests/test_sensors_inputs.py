"""The 9 inputs of sensors.paper_inputs, column by column, on a hand-made batch
(no simulation): what each input is for a pose whose answer is known.

Written against the mutants the suite let through (issue #48,
scripts/mutation.py): a touch threshold above zero, touch reduced over the
whole batch, the batch size read from the wrong axis, I7-I9 never written, and
the height clamp at the floor removed.
"""

import numpy as np

from locustjump.sim import sensors

BODY_LENGTH = 2.0  # (m)
JOINTS = np.array([7, 8, 9, 10])
TOUCH = np.array([1, 3])


def pose(z: float, quat, joints=(1.0, 2.0, 3.0, 4.0)) -> np.ndarray:
    """One row of qpos: free joint (x, y, z, quaternion wxyz), then 4 hinges."""
    return np.array([0.0, 0.0, z, *quat, *joints])


def test_each_input_of_a_known_batch():
    s = np.sqrt(0.5)
    qpos = np.stack(
        [
            pose(1.0, (1.0, 0.0, 0.0, 0.0)),  # upright, 1 m up
            pose(0.5, (s, 0.0, -s, 0.0), joints=(0.5, 0.6, 0.7, 0.8)),  # nose up 90
            pose(-0.3, (0.0, 1.0, 0.0, 0.0)),  # on its back, below the floor
        ]
    )
    # touch sensors at columns 1 and 3: a small force counts; others do not
    sensordata = np.array(
        [
            [9.0, 0.0, 9.0, 0.0],  # no touch (forces elsewhere)
            [0.0, 0.25, 0.0, 0.0],  # left tarsus touches
            [0.0, 0.0, 0.0, 1e-9],  # right tarsus, barely
        ]
    )
    # the inputs go to a new array: leave a freed one of its size full of NaN
    # where NumPy's allocator would hand it out, so that a column left
    # unwritten shows (it could otherwise hold a previous call's numbers)
    poison = np.full((3, sensors.N_INPUTS), np.nan)
    del poison
    obs = sensors.paper_inputs(
        qpos, sensordata, joint_adr=JOINTS, touch_adr=TOUCH, body_length=BODY_LENGTH
    )
    assert obs.shape == (3, sensors.N_INPUTS)
    np.testing.assert_array_equal(obs[:, 0:4], qpos[:, 7:11])
    np.testing.assert_array_equal(obs[:, 4], [1.0, -1.0, -1.0])
    # I6 = 1 / (H + 1), H in body lengths; below the floor H counts as 0
    np.testing.assert_array_equal(obs[:, 5], [1 / 1.5, 1 / 1.25, 1.0])
    np.testing.assert_allclose(
        obs[:, 6:9], [[0, 0, 1], [1, 0, 0], [0, 0, -1]], atol=1e-15
    )


def test_touch_is_per_episode_and_the_batch_size_is_the_first_axis():
    qpos = np.stack([pose(0.2, (1.0, 0, 0, 0))] * 12)  # more episodes than qpos
    sensordata = np.zeros((12, 4))
    sensordata[5, 1] = 1.0
    obs = sensors.paper_inputs(
        qpos,
        sensordata,
        joint_adr=slice(7, 11),
        touch_adr=slice(1, 4, 2),
        body_length=BODY_LENGTH,
    )
    assert obs.shape == (12, 9)
    expected = np.ones(12)
    expected[5] = -1.0
    np.testing.assert_array_equal(obs[:, 4], expected)
