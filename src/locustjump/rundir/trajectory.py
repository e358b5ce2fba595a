"""One episode's records as a CSV table."""

from __future__ import annotations

from pathlib import Path
from typing import IO

import numpy as np

from locustjump.rundir.files import atomic_write_bytes
from locustjump.sim import names
from locustjump.sim.model import CONTROL_DT

TRAJECTORY_COLUMNS = (
    ["step", "t", "x", "y", "z", "up_z", "touch"]
    + list(names.ACTUATED_JOINTS)
    + [f"target_{j}" for j in names.ACTUATED_JOINTS]
    + ["pitch", "roll"]
)


def trajectory_table(qpos: np.ndarray, obs: np.ndarray, ctrl: np.ndarray) -> np.ndarray:
    """(T, len(TRAJECTORY_COLUMNS)) table of one episode's records.

    ``touch`` is 1 when a hind tarsus touches, ``up_z`` the body up-axis' world
    z (I9), ``pitch``/``roll`` the body x/y axes' world z (I7, I8); angles in
    radians, lengths in metres, time in seconds.
    """
    T = qpos.shape[0]
    steps = np.arange(T)
    return np.column_stack(
        [
            steps,
            steps * CONTROL_DT,
            qpos[:, 0:3],
            obs[:, 8],
            obs[:, 4] < 0,
            obs[:, 0:4],
            ctrl,
            obs[:, 6],
            obs[:, 7],
        ]
    )


def write_trajectory_csv(
    path: Path, qpos: np.ndarray, obs: np.ndarray, ctrl: np.ndarray
) -> None:
    """Write one episode as CSV, one row per control step (row 0: the start)."""
    table = trajectory_table(qpos, obs, ctrl)
    fmt = ["%d", "%.6f"] + ["%.9g"] * (table.shape[1] - 2)
    fmt[6] = "%d"

    def write(f: IO[bytes]) -> None:
        np.savetxt(
            f,
            table,
            delimiter=",",
            header=",".join(TRAJECTORY_COLUMNS),
            comments="",
            fmt=fmt,
        )

    atomic_write_bytes(path, write)
