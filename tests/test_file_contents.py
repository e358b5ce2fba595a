"""Every file a command reads is checked before anything is written: a
damaged, tampered or hostile one ends in one line naming it, exit 2, and the
run directory as it was (issue #32)."""

import io
import os
import shutil
import zipfile
from pathlib import Path

import numpy as np
import pytest

from helpers import refused
from locustjump import rundir
from locustjump.cli import main


def _argv(out: Path, generations: int = 2, *more: str) -> list[str]:
    return ["train", "kick", "--population", "4", "--generations",
            str(generations), "--seed", "1", "--threads", "1", "--quiet",
            "--out", str(out), *more]  # fmt: skip


@pytest.fixture(scope="module")
def small_run(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("small") / "run"
    assert main(_argv(out)) == 0
    return out


def _rewrite_npz(path: Path, **changes) -> None:
    with np.load(path) as z:
        arrays = dict(z)
    arrays.update(changes)
    np.savez(path, **arrays)


def _resume(out: Path) -> list[str]:
    return _argv(out, 5, "--resume")


CHECKPOINTS = [
    ("opt_population", lambda a: np.full_like(a, np.nan), "population holds NaN"),
    ("opt_population", lambda a: a * np.inf, "population is not finite"),
    ("opt_fitness", lambda a: a[:2], "fitness has the wrong shape"),
    ("opt_rng_state", lambda a: np.array('{"bit_generator": "seed"}'),
     "unknown bit generator"),
    ("opt_generation", lambda a: np.array(2.5), "generation must be an integer"),
    ("metrics_row", lambda a: np.array("99" + str(a)[1:]),
     "metrics_row is not the row of generation 2"),
    ("best_genome", lambda a: a.astype(np.float32), "best_genome must be float64"),
    ("best_fitness", lambda a: np.array(np.nan), "best_fitness must be finite"),
    ("best_generation", lambda a: np.array(7), "best_generation 7"),
    ("behaviour", lambda a: np.array(["kick", "kick"]), "behaviour must be text"),
]  # fmt: skip


@pytest.mark.parametrize(("key", "change", "needle"), CHECKPOINTS)
def test_a_tampered_checkpoint_is_refused_before_any_write(
    small_run, tmp_path, capsys, key, change, needle
):
    out = tmp_path / "run"
    shutil.copytree(small_run, out)
    with np.load(out / rundir.CHECKPOINT) as z:
        _rewrite_npz(out / rundir.CHECKPOINT, **{key: change(z[key])})
    refused(_resume(out), capsys, needle, out)


BEST = [
    ("genome", lambda a: a.astype(np.float32), "genome must be float64, got float32"),
    ("genome", lambda a: a.astype(np.int64), "genome must be float64, got int64"),
    ("genome", lambda a: a.astype(complex), "genome must be float64, got complex"),
    ("genome", lambda a: a * np.nan, "genome must be finite"),
    ("fitness", lambda a: np.array(np.nan), "fitness must be finite"),
    ("fitness", lambda a: np.array([a, a]), "fitness must be a float64 number"),
    ("generation", lambda a: np.array(0), "generation must be >= 1"),
    ("generation", lambda a: np.array(10**6), "beyond the run's 2"),
]


@pytest.mark.parametrize(("key", "change", "needle"), BEST)
def test_a_tampered_best_genome_is_refused_before_any_write(
    small_run, tmp_path, capsys, key, change, needle
):
    out = tmp_path / "run"
    shutil.copytree(small_run, out)
    with np.load(out / rundir.BEST) as z:
        _rewrite_npz(out / rundir.BEST, **{key: change(z[key])})
    for argv in (["evaluate", str(out), "--json"], ["report", str(out)]):
        refused(argv, capsys, needle, out)


def _npz_with(path: Path, name: str, header: dict, data: bytes) -> None:
    """Replace member ``name`` of ``path`` by an .npy of ``header`` and ``data``."""
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files if k != name}
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zf:
        for k, v in arrays.items():
            b = io.BytesIO()
            np.save(b, v)
            zf.writestr(f"{k}.npy", b.getvalue())
        with zf.open(f"{name}.npy", "w", force_zip64=True) as f:
            h = io.BytesIO()
            np.lib.format.write_array_header_1_0(h, header)
            f.write(h.getvalue())
            f.write(data)


def test_npz_sizes_are_bounded_before_reading(small_run, tmp_path, capsys):
    out = tmp_path / "run"
    shutil.copytree(small_run, out)
    best = out / rundir.BEST
    # a header that declares 10**12 elements
    _npz_with(best, "genome", {"descr": "<f8", "fortran_order": False,
                               "shape": (10**12,)}, b"\0" * 64)  # fmt: skip
    refused(["evaluate", str(out)], capsys, f"{best}: genome.npy declares", out)
    # 64 MB of zeros (compressed to 64 KB): more than a genome file holds
    _npz_with(best, "genome", {"descr": "<f8", "fortran_order": False,
                               "shape": (8 << 20,)}, bytes(64 << 20))  # fmt: skip
    assert best.stat().st_size < 1 << 20
    refused(["evaluate", str(out)], capsys, "more than such a file holds", out)
    # a directory where best.npz should be
    best.unlink()
    best.mkdir()
    refused(["evaluate", str(out)], capsys, "is a directory, not a regular file", out)


METRICS = [
    ("garbage row here\n", "line 4: 1 columns, the header names 8"),
    ("3,nan,0,0,1,4,5,6\n", "line 4: best must be finite"),
    ("x,1,0,0,1,4,5,6\n", "line 4: generation must be an integer"),
]


@pytest.mark.parametrize(("line", "needle"), METRICS)
def test_a_malformed_metrics_row_is_named(small_run, tmp_path, capsys, line, needle):
    out = tmp_path / "run"
    shutil.copytree(small_run, out)
    with open(out / rundir.METRICS, "a") as f:
        f.write(line)
    for argv in (["report", str(out)], ["compare", str(out)], _resume(out)):
        refused(argv, capsys, f"{rundir.METRICS}: {needle}", out)


def test_metrics_out_of_order_or_not_the_checkpoints(small_run, tmp_path, capsys):
    out = tmp_path / "run"
    shutil.copytree(small_run, out)
    m = out / rundir.METRICS
    header, one, two = m.read_text().splitlines(keepends=True)
    m.write_text(header + two + one)
    refused(_resume(out), capsys, "generation 2, expected 1", out)
    cells = two.split(",")
    cells[1] = "123.0"  # another best fitness than the checkpoint's row
    m.write_text(header + one + ",".join(cells))
    refused(_resume(out), capsys, "not the checkpoint's", out)


def test_config_files_are_bounded_before_parsing(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    deep = tmp_path / "deep.toml"
    deep.write_text("a = " + "[" * 1000 + "]" * 1000 + "\n")
    refused(["train", "kick", "--config", "deep.toml", "--out", "r"], capsys,
             "deep.toml: nested more than 32 deep", tmp_path)  # fmt: skip
    refused(["train", "kick", "--config", "/dev/zero", "--out", "r"], capsys,
             "--config: /dev/zero: is a character device", tmp_path)  # fmt: skip
    # brackets inside strings and comments do not count
    assert rundir.reads.nesting('a = "[[[[" # ]]]]\nb = [[1], {c = 2}]\n') == 2
    # a seed beyond TOML's 64-bit integers is refused, not written
    (tmp_path / "s.toml").write_text(f"seed = {2**64}\n")
    refused(["train", "kick", "--config", "s.toml", "--out", "r"], capsys,
             "seed must be a 64-bit integer", tmp_path)  # fmt: skip
    with pytest.raises(SystemExit):
        main(["train", "kick", "--seed", str(2**63), "--out", "r"])
    assert "--seed must be an integer in [0, 2**63-1]" in capsys.readouterr().err


def test_output_paths_that_cannot_be_used_are_named(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    os.symlink("loop", tmp_path / "loop")
    for argv in (["train", "kick", "--quiet", "--out", "loop"],
                 ["rules", "--out", "loop"],
                 ["model", "--out", "loop/m.xml"]):  # fmt: skip
        refused(argv, capsys, "Too many levels of symbolic links", tmp_path)
    os.symlink("nowhere", tmp_path / "broken")
    refused(["rules", "--out", "broken"], capsys, "a broken symbolic link", tmp_path)


def test_a_run_stopped_before_its_config_starts_again(tmp_path, capsys, small_run):
    """What a new run writes before config.toml (a kill -9 then) does not
    block the same command; --resume says what to do."""
    out = tmp_path / "run"
    out.mkdir()
    (out / ".config.tmp.toml").write_text("half")
    shutil.copy(small_run / rundir.BEST, out / rundir.FROZEN)  # any bytes
    refused([*_argv(out), "--resume"], capsys, "rerun without --resume", out)
    assert main(_argv(out)) == 0
    assert rundir.generations_done(out) == 2
    assert not (out / ".config.tmp.toml").exists()
    assert not (out / rundir.FROZEN).exists()  # a kick run builds on none
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "mine.txt").write_text("x")  # anything else: refused
    refused(_argv(tmp_path / "other"), capsys, "is not empty", tmp_path / "other")
