"""``rundir.trajectory``: one episode's records as a table and a CSV file,
column by column, on made-up records."""

import numpy as np

from locustjump.rundir.trajectory import (
    TRAJECTORY_COLUMNS,
    trajectory_table,
    write_trajectory_csv,
)
from locustjump.sim.model import CONTROL_DT

JOINTS = ["hip_l", "knee_l", "hip_r", "knee_r"]


def _records(T=3):
    qpos = np.arange(T * 7, dtype=float).reshape(T, 7) + 0.5  # x y z at 0-2
    obs = 100 + np.arange(T * 10, dtype=float).reshape(T, 10)
    obs[1, 4] = -0.25  # a hind tarsus touches at step 1 (I5 below 0)
    obs[0, 4] = 0.0  # not at 0
    obs[2:, 4] = 0.5  # nor above it
    ctrl = -np.arange(T * 4, dtype=float).reshape(T, 4) / 8
    return qpos, obs, ctrl


def test_the_columns_are_named_in_order():
    assert TRAJECTORY_COLUMNS == (
        ["step", "t", "x", "y", "z", "up_z", "touch"] + JOINTS
        + [f"target_{j}" for j in JOINTS] + ["pitch", "roll"]
    )  # fmt: skip


def test_each_column_holds_its_record():
    qpos, obs, ctrl = _records()
    table = trajectory_table(qpos, obs, ctrl)
    assert table.shape == (3, len(TRAJECTORY_COLUMNS))
    col = {n: table[:, i] for i, n in enumerate(TRAJECTORY_COLUMNS)}
    assert col["step"].tolist() == [0, 1, 2]
    assert col["t"].tolist() == [0.0, CONTROL_DT, 2 * CONTROL_DT]
    for i, n in enumerate("xyz"):
        assert col[n].tolist() == qpos[:, i].tolist()
    assert col["up_z"].tolist() == obs[:, 8].tolist()
    assert col["touch"].tolist() == [0, 1, 0]
    for i, j in enumerate(JOINTS):
        assert col[j].tolist() == obs[:, i].tolist()
        assert col[f"target_{j}"].tolist() == ctrl[:, i].tolist()
    assert col["pitch"].tolist() == obs[:, 6].tolist()
    assert col["roll"].tolist() == obs[:, 7].tolist()


def test_the_csv_file(tmp_path):
    qpos, obs, ctrl = _records(2)
    qpos[1, 0] = 1 / 3  # x to 9 significant digits
    qpos[0, 1] = 1.5e-12  # y in exponent notation
    obs[0, 0] = 100.25  # a joint angle is not rounded
    path = tmp_path / "trajectory.csv"
    write_trajectory_csv(path, qpos, obs, ctrl)
    lines = path.read_text().splitlines()
    assert lines[0] == ",".join(TRAJECTORY_COLUMNS)
    assert len(lines) == 3
    assert lines[1] == ("0,0.000000,0.5,1.5e-12,2.5,108,0,100.25,101,102,103,"
                        "-0,-0.125,-0.25,-0.375,106,107")  # fmt: skip
    assert lines[2] == ("1,0.008333,0.333333333,8.5,9.5,118,1,110,111,112,113,"
                        "-0.5,-0.625,-0.75,-0.875,116,117")  # fmt: skip
    assert list(tmp_path.iterdir()) == [path]  # nothing else left behind
