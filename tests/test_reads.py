"""Every file a command reads is read as what it is (issue #48, the third
adversarial trial): a regular file or nothing (a FIFO never blocks, a device
is never read), no more bytes than its kind can hold whatever size it
reports, no ``.npz`` member inflated past what such a file holds, nesting
bounded however it is spelled, and ``train --resume`` checks every file it
keeps as ``evaluate`` does. Each refusal: one line naming the file, exit 2,
nothing changed."""

import io
import os
import pickle
import shutil
import signal
import subprocess
import sys
import tracemalloc
import zipfile
from pathlib import Path

import numpy as np
import pytest

from helpers import assert_same_run, refused
from locustjump import rundir
from locustjump.cli import main
from locustjump.cli.dispatch import ERROR_LOG

ROOT = Path(__file__).resolve().parent.parent


def _argv(out: Path, generations: int = 2, *more: str) -> list[str]:
    return ["train", "kick", "--population", "4", "--generations",
            str(generations), "--seed", "1", "--threads", "1", "--quiet",
            "--out", str(out), *more]  # fmt: skip


def _resume(out: Path) -> list[str]:
    return _argv(out, 5, "--resume")


@pytest.fixture(scope="module")
def small_run(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("small") / "run"
    assert main(_argv(out)) == 0
    return out


@pytest.fixture
def run(small_run, tmp_path) -> Path:
    out = tmp_path / "run"
    shutil.copytree(small_run, out)
    return out


@pytest.fixture(autouse=True)
def _never_blocks():
    """A read that blocks fails the test instead of hanging the suite (a
    BaseException, so that no handler of the command takes it for its own)."""

    def blocked(signum, frame):
        pytest.fail("a read blocked")

    previous = signal.signal(signal.SIGALRM, blocked)
    signal.alarm(120)
    yield
    signal.alarm(0)
    signal.signal(signal.SIGALRM, previous)


# -- 1. regular files only -----------------------------------------------------

KINDS = {
    "fifo": (os.mkfifo, "is a FIFO (named pipe), not a regular file"),
    "directory": (Path.mkdir, "is a directory, not a regular file"),
    "/dev/zero": (lambda p: os.symlink("/dev/zero", p),
                  "is a character device, not a regular file"),
}  # fmt: skip

#: each file of a run, and the commands that read it
READERS = {
    rundir.CONFIG: ("evaluate", "report", "compare", "resume"),
    rundir.METRICS: ("report", "compare", "resume"),
    rundir.BEST: ("evaluate", "report", "resume"),
    rundir.CHECKPOINT: ("resume",),
}


def _command(name: str, out: Path) -> list[str]:
    if name == "resume":
        return _resume(out)
    return [name, str(out), *(["--json"] if name == "evaluate" else [])]


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize(
    ("name", "command"), [(f, c) for f, cs in READERS.items() for c in cs]
)
def test_a_runs_file_that_is_not_a_regular_file_is_refused(
    run, capsys, kind, name, command
):
    make, needle = KINDS[kind]
    (run / name).unlink()
    make(run / name)
    refused(_command(command, run), capsys, f"{run / name}: {needle}", run)


@pytest.mark.parametrize("kind", KINDS)
def test_files_given_or_found_that_are_not_regular_files_are_refused(
    tmp_path, capsys, monkeypatch, kind
):
    monkeypatch.chdir(tmp_path)
    make, needle = KINDS[kind]
    make(tmp_path / "f.toml")
    for argv in (
        ["train", "kick", "--config", "f.toml", "--out", "r"],
        ["train", "kick", "--scene", "f.toml", "--out", "r"],
        ["study", "f.toml", "--status"],
    ):
        refused(argv, capsys, f"f.toml: {needle}", tmp_path)
    rep = tmp_path / "rep"
    rep.mkdir()
    make(rep / rundir.MARKER)
    refused(["reproduce", "--budget", "quick", "--out", str(rep), "--no-videos"],
             capsys, f"{rep / rundir.MARKER}: {needle}", tmp_path)  # fmt: skip


def test_a_pipe_as_config_is_refused_at_once(tmp_path):
    """``sleep 60 | locustjump train kick --config /dev/stdin``: no wait."""
    sleep = subprocess.Popen(["sleep", "60"], stdout=subprocess.PIPE)
    try:
        r = subprocess.run(
            [sys.executable, "-m", "locustjump.cli", "train", "kick", "--config",
             "/dev/stdin", "--out", str(tmp_path / "r")],
            stdin=sleep.stdout, capture_output=True, text=True, timeout=50,
            env={**os.environ, "PYTHONPATH": str(ROOT / "src")},
        )  # fmt: skip
    finally:
        sleep.kill()
        sleep.wait()
    assert r.returncode == 2, r.stderr
    assert "/dev/stdin: is a FIFO (named pipe), not a regular file" in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1 and not (tmp_path / "r").exists()


# -- 2. sizes bounded by the bytes read, and by what .npz headers declare ----------


def _endless() -> Path:
    """A regular file that reports its size as 0 but holds megabytes."""
    path = Path("/proc/kallsyms")
    if not path.is_file() or len(path.read_bytes()[: 2 << 20]) < 2 << 20:
        pytest.skip("no /proc/kallsyms of over 2 MiB here")
    return path


def test_sizes_are_bounded_by_the_bytes_read(run, tmp_path, capsys, monkeypatch):
    endless = _endless()
    assert endless.stat().st_size == 0
    refused(["train", "kick", "--config", str(endless), "--out", str(tmp_path / "r")],
             capsys, f"{endless}: larger than 1 MiB", tmp_path)  # fmt: skip
    monkeypatch.setattr(rundir.metrics, "MAX_METRICS_BYTES", 1 << 20)
    (run / rundir.METRICS).unlink()
    (run / rundir.METRICS).symlink_to(endless)
    for command in READERS[rundir.METRICS]:
        refused(_command(command, run), capsys,
                 f"{run / rundir.METRICS}: larger than 1 MiB", run)  # fmt: skip


def _rewrite(path: Path, drop: str = "", **members: bytes | np.ndarray) -> None:
    """Rewrite ``.npz`` ``path`` with ``members`` (raw ``.npy`` bytes or
    arrays) in place of or beside its own (``drop``: one left out), deflated."""
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files if k != drop}
    arrays.update(members)
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zf:
        for k, v in arrays.items():
            if isinstance(v, np.ndarray):
                b = io.BytesIO()
                np.save(b, v)
                v = b.getvalue()
            zf.writestr(f"{k}.npy", v)


def _bomb(shape: tuple[int, ...]) -> bytes:
    """An ``.npy`` of float64 zeros of ``shape`` (deflates to a thousandth)."""
    b = io.BytesIO()
    np.lib.format.write_array_header_1_0(
        b, {"descr": "<f8", "fortran_order": False, "shape": shape}
    )
    return b.getvalue() + bytes(8 * int(np.prod(shape)))


def _peak_of(argv: list[str], capsys, needle: str, d: Path) -> float:
    """``_refused``, and the peak of memory NumPy and Python took meanwhile (MB)."""
    tracemalloc.start()
    try:
        refused(argv, capsys, needle, d)
        return tracemalloc.get_traced_memory()[1] / 1e6
    finally:
        tracemalloc.stop()


def test_a_checkpoint_bomb_is_refused_before_it_inflates(run, capsys):
    ckpt = run / rundir.CHECKPOINT
    with np.load(ckpt) as z:
        n, p = z["opt_population"].shape
    # 46 MB of population (40 000 individuals where the run has 4) in 46 KB
    _rewrite(ckpt, opt_population=_bomb((40_000, p)))
    assert ckpt.stat().st_size < 1 << 20
    peak = _peak_of(_resume(run), capsys, "more than such a file holds", run)
    assert peak < 10, f"{peak:.0f} MB"  # the population alone is 46 MB (1.2 MB seen)
    # the same bomb beside the arrays the checkpoint holds, prefixed as the
    # optimizer's state or not
    for name in ("opt_extra", "extra"):
        _rewrite(ckpt, **{name: _bomb((40_000, p))})
        refused(_resume(run), capsys, f"holds '{name}.npy', which such a file", run)
        _rewrite(ckpt, drop=name)


def test_npz_members_are_only_those_written(run, capsys):
    best = run / rundir.BEST
    original = best.read_bytes()
    _rewrite(best, extra=np.zeros(3))
    refused(["evaluate", str(run)], capsys, "holds 'extra.npy', which such", run)
    with zipfile.ZipFile(best, "w") as zf:
        for i in range(300):
            zf.writestr(f"a{i}.npy", b"")
    refused(["evaluate", str(run)], capsys, "holds 300 arrays", run)
    for content in (b"genome = 1\n", pickle.dumps({"genome": [1.0]})):
        best.write_bytes(content)
        refused(["evaluate", str(run)], capsys,
                 f"{best}: not an .npz file (File is not a zip file)", run)  # fmt: skip
    best.write_bytes(original)
    # JSON nested too deep where the checkpoint keeps the generator's state
    _rewrite(run / rundir.CHECKPOINT, opt_rng_state=np.array("[" * 5000))
    refused(_resume(run), capsys, "malformed checkpoint", run)


# -- 3. nesting bounded however it is spelled ---------------------------------------

DEEP = ".".join(["a"] * 3000)


@pytest.mark.parametrize(
    "text", [f"length.{DEEP} = 1\n", f"[{DEEP}]\nx = 1\n"], ids=["dotted", "header"]
)
def test_nesting_is_bounded_however_it_is_spelled(
    run, tmp_path, capsys, monkeypatch, text
):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "deep.toml").write_text(text)
    (tmp_path / "scene.toml").write_text("[scene]\n" + text)
    for argv in (["train", "kick", "--config", "deep.toml", "--out", "r"],
                 ["train", "kick", "--scene", "scene.toml", "--out", "r"]):  # fmt: skip
        refused(argv, capsys, "nested more than 32 deep", tmp_path)
    config = run / rundir.CONFIG
    config.write_text(config.read_text() + text)  # into its last table, [scene]
    for command in READERS[rundir.CONFIG]:
        refused(_command(command, run), capsys,
                 f"{config}: nested more than 32 deep", run)  # fmt: skip
    assert not list(run.rglob(ERROR_LOG)) and not (tmp_path / "r").exists()
    # 32 levels are read (and refused for what they hold, not how deep)
    assert rundir.reads.depth({"a": [[1]]}) == 3
    assert rundir.reads.depth(rundir.reads.tomllib.loads(text)) == 3001


# -- 4. train --resume checks every file it keeps -------------------------------------


def _another_runs_best(tmp_path: Path) -> Path:
    other = tmp_path / "other"
    assert main([*_argv(other, 1)[:-2], "--out", str(other), "--seed", "2"]) == 0
    return other / rundir.BEST


BEST_DAMAGE = {
    "truncated": lambda p, t: p.write_bytes(p.read_bytes()[:200]),
    "NaN": lambda p, t: _rewrite(p, genome=np.full(np.load(p)["genome"].shape, np.nan)),
    "another run's": lambda p, t: shutil.copy(_another_runs_best(t), p),
    "directory": lambda p, t: (p.unlink(), p.mkdir()),
    "FIFO": lambda p, t: (p.unlink(), os.mkfifo(p)),
    "/dev/zero": lambda p, t: (p.unlink(), p.symlink_to("/dev/zero")),
    "pickle": lambda p, t: p.write_bytes(pickle.dumps(np.zeros(3))),
    "bomb": lambda p, t: _rewrite(p, genome=_bomb((4 << 20,))),
    "missing": lambda p, t: p.unlink(),
    "not the checkpoint's": lambda p, t: _rewrite(p, fitness=np.array(123.0)),
}  # fmt: skip


@pytest.mark.parametrize("damage", BEST_DAMAGE)
def test_resume_checks_the_best_genome_it_keeps(run, tmp_path, capsys, damage):
    BEST_DAMAGE[damage](run / rundir.BEST, tmp_path)
    refused(_resume(run), capsys, str(run / rundir.BEST), run)


def test_resume_without_its_checkpoint_does_not_restart(run, capsys):
    (run / rundir.CHECKPOINT).unlink()
    refused(_resume(run), capsys,
             f"{run / rundir.METRICS}: holds 2 generations but checkpoint.npz is "
             "missing", run)  # fmt: skip


def test_a_best_genome_saved_before_a_lost_checkpoint_is_kept(tmp_path, capsys):
    """A kill between best.npz and the checkpoint of its generation leaves the
    best genome one generation ahead: --resume goes on, bit-identically."""
    ref = tmp_path / "ref"
    assert main(_argv(ref, 6)) == 0
    g = rundir.BestGenome.load(ref / rundir.BEST).generation
    assert g >= 2  # the seed is chosen so that there is a generation before
    out = tmp_path / "run"
    assert main(_argv(out, g - 1)) == 0
    shutil.copy(ref / rundir.BEST, out / rundir.BEST)
    assert main(_argv(out, 6, "--resume")) == 0
    assert_same_run(ref, out)


# -- a reproduction's marker is one a locustjump wrote ---------------------------


@pytest.mark.parametrize(
    ("marker", "text", "needle"),
    [
        (rundir.MARKER, 'budget = "quick"\n',
         "missing seed, population, generations, command, locustjump"),
        (rundir.SEEDS_MARKER, 'budget = "quick"\n', "missing population"),
        (rundir.MARKER, 'budget = "quick"\nseed = 0\npopulation = 50\n'
         'generations = 5\ncommand = ""\nlocustjump = ""\n',
         "generations must be a table of each stage's generations, got '5'"),
    ],
)  # fmt: skip
def test_a_marker_no_reproduction_wrote_is_refused(
    tmp_path, capsys, marker, text, needle
):
    """``budget = "demo"`` alone ran every stage and then failed on a
    KeyError (exit 1)."""
    rep = tmp_path / "rep"
    rep.mkdir()
    (rep / marker).write_text(text)
    seeds = ["--seeds", "0,1"] if marker == rundir.SEEDS_MARKER else []
    refused(["reproduce", "--budget", "quick", "--out", str(rep), *seeds],
             capsys, f"{rep / marker}: {needle}", tmp_path)  # fmt: skip
