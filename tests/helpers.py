"""Helpers shared by the tests (importable: tests/ is on sys.path)."""

import contextlib
import io
import os
import subprocess
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from locustjump import rundir
from locustjump.evo import Optimizer

#: the smallest budget that runs every stage of a reproduction (conftest's
#: tiny_reproduction)
TINY_GENERATIONS = {"kick": 1, "getup": 1, "return-legs": 1, "composed": 1}

#: Hollander & Wolfe (1973, p. 69): permeability of the human chorioamnion at
#: term (x) and at 12-26 weeks (y), the example of R's ?wilcox.test
HW_X = [0.80, 0.83, 1.89, 1.04, 1.45, 1.38, 1.91, 1.64, 0.73, 1.46]
HW_Y = [1.15, 0.88, 0.90, 0.74, 1.21]

#: the example study (studies/example.toml), trained in seconds
EXAMPLE = Path(__file__).resolve().parents[1] / "studies" / "example.toml"

EXACT = ("generation", "best", "mean", "std", "evaluations", "control_steps")


def assert_same_run(a: Path, b: Path) -> None:
    """Same genomes, fitness, GA state and metrics, bit for bit (not wall time)."""
    for name in (rundir.CHECKPOINT, rundir.BEST):
        with np.load(a / name) as za, np.load(b / name) as zb:
            assert za.files == zb.files
            for k in set(za.files) - {"metrics_row"}:  # holds the wall time
                np.testing.assert_array_equal(za[k], zb[k], err_msg=f"{name}:{k}")
    ma, mb = (
        rundir.read_metrics(a / rundir.METRICS),
        rundir.read_metrics(b / rundir.METRICS),
    )
    for k in EXACT:
        np.testing.assert_array_equal(ma[k], mb[k])


def exit_status(argv: list[str]) -> int:
    """``locustjump.cli.main``'s exit status, also for argparse's errors."""
    from locustjump.cli import main

    try:
        return main(argv)
    except SystemExit as e:
        return e.code


def wait_for_rows(out: Path, rows: int, timeout: float = 60.0) -> None:
    """Wait until run ``out`` (written by another process) has more than
    ``rows`` lines in ``metrics.csv`` (its header included)."""
    deadline = time.monotonic() + timeout
    m = out / rundir.METRICS
    while time.monotonic() < deadline:
        if m.exists() and len(m.read_text().splitlines()) > rows:
            return
        time.sleep(0.02)
    raise AssertionError(f"{m}: not {rows} rows after {timeout:.0f} s")


def run_cli(*argv: str) -> SimpleNamespace:
    """``locustjump ARGV`` in this process: its exit status and output."""
    from locustjump.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(list(argv))
        except SystemExit as e:
            code = e.code
    return SimpleNamespace(
        returncode=code, stdout=out.getvalue(), stderr=err.getvalue()
    )


def _content(p: Path) -> bytes | str | None:
    if p.is_symlink():
        return os.readlink(p)
    return p.read_bytes() if p.is_file() else None  # a FIFO is never read


def tree_snapshot(d: Path) -> dict[str, bytes | str | None]:
    """Everything under ``d``: each file's bytes, each link's target, None
    for a directory or anything else (never opened)."""
    return {str(p.relative_to(d)): _content(p) for p in d.rglob("*")}


def refused(argv: list[str], capsys, needle: str, d: Path) -> str:
    """``argv`` exits 2 with one line holding ``needle``; ``d`` unchanged.
    Returns that line."""
    from locustjump.cli import main

    before = tree_snapshot(d)
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2, err
    assert needle in err and len(err.strip().splitlines()) == 1, err
    assert tree_snapshot(d) == before
    return err


_HOLD = """
import fcntl, os, sys, time
fd = os.open(sys.argv[1], os.O_RDONLY)
fcntl.flock(fd, fcntl.LOCK_EX)
print("locked", flush=True)
time.sleep(120)
"""


def held_lock(directory: Path) -> subprocess.Popen:
    """Another process holding the write lock of ``directory`` (kill it when
    done)."""
    holder = subprocess.Popen([sys.executable, "-c", _HOLD, str(directory)],
                              stdout=subprocess.PIPE, text=True)  # fmt: skip
    assert holder.stdout.readline().strip() == "locked"
    return holder


def main_while_held(directory: Path, argv: list[str], capsys) -> tuple[int, str, int]:
    """``locustjump ARGV`` here while another process holds ``directory``'s
    lock: (exit status, stderr, the holder's pid)."""
    from locustjump.cli import main

    holder = held_lock(directory)
    try:
        code = main(argv)
    finally:
        holder.kill()
        holder.wait()
    return code, capsys.readouterr().err, holder.pid


def example_study(tmp_path: Path, **changes: str) -> Path:
    """The example study with its runs and table under ``tmp_path``."""
    text = EXAMPLE.read_text().replace(
        'root = "runs/studies/example"', f'root = "{tmp_path / "runs"}"'
    )
    for old, new in changes.items():
        assert old in text
        text = text.replace(old, new)
    path = tmp_path / "example.toml"
    path.write_text(text)
    return path


def user_error(call, *args, **kw) -> str:
    """The words of the ``UserError`` that ``call(*args, **kw)`` raises."""
    import pytest

    from locustjump.errors import UserError

    with pytest.raises(UserError) as e:
        call(*args, **kw)
    return str(e.value)


def exactly(message: str) -> str:
    """A ``match=`` pattern for exactly ``message``, nothing before or after."""
    import re

    return "^" + re.escape(message) + "$"


class Fixed(Optimizer):
    """An optimizer on the base's own ``__init__`` that asks the rows it was
    given and learns nothing."""

    rows = np.zeros((1, 3), dtype=np.int64)

    def _ask(self):
        return self.rows

    def _tell(self, genomes, fitness):
        return None

    def _state(self):
        return {}

    def _set_state(self, state):
        pass


#: a study file's simple arms that a composed arm builds on (getup: one run,
#: seed 5, for every seed of the study)
SIMPLE_ARMS = """[arms.kick]
behaviour = "kick"
score = false
[arms.getup]
behaviour = "getup"
score = false
seed = 5
[arms.legs]
behaviour = "return-legs"
score = false
"""
