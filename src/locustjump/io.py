"""Files: output directories that are never silently clobbered, trajectory CSVs."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from locustjump import names
from locustjump.model import CONTROL_DT


class UserError(Exception):
    """Bad input from the user: the CLI prints it on one line and exits 2."""


def prepare_out_dir(path: str | os.PathLike, *, force: bool = False) -> Path:
    """Create ``path``; refuse an existing non-empty one unless ``force``."""
    out = Path(path)
    if out.exists() and not out.is_dir():
        raise UserError(f"--out {out}: exists and is not a directory")
    if out.is_dir() and any(out.iterdir()) and not force:
        raise UserError(
            f"--out {out}: directory exists and is not empty (use --force to "
            "write into it)"
        )
    out.mkdir(parents=True, exist_ok=True)
    return out


def prepare_out_file(path: str | os.PathLike, *, force: bool = False) -> Path:
    """Check that ``path`` can be written without overwriting, unless ``force``."""
    out = Path(path)
    if out.is_dir():
        raise UserError(f"--out {out}: is a directory, expected a file")
    if out.exists() and not force:
        raise UserError(f"--out {out}: file exists (use --force to overwrite)")
    if not out.parent.exists():
        raise UserError(f"--out {out}: directory {out.parent} does not exist")
    return out


def atomic_write_text(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` via a temporary file and a rename."""
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


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
    np.savetxt(
        path,
        table,
        delimiter=",",
        header=",".join(TRAJECTORY_COLUMNS),
        comments="",
        fmt=fmt,
    )
