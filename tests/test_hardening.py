"""Bad input and OS errors end in one line and exit 2 with nothing left behind;
one writer per run directory."""

import contextlib
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from helpers import assert_same_run, wait_for_rows
from locustjump import rundir
from locustjump.cli import main
from locustjump.sim import resources


def _fails_cleanly(argv, capsys, needle: str, cwd: Path) -> None:
    before = sorted(p.name for p in cwd.iterdir())
    try:
        code = main(argv)
    except SystemExit as e:  # refused by the parser
        code = e.code
    err = capsys.readouterr().err
    assert code == 2, err
    assert needle in err and len(err.strip().splitlines()) == 1, err
    assert sorted(p.name for p in cwd.iterdir()) == before  # nothing half-made
    assert not (cwd / "MUJOCO_LOG.TXT").exists()


@pytest.mark.parametrize(
    ("config", "needle"),
    [
        ("[model]\nscale = inf\n", "scale must be in [0.01, 1000], got inf"),
        ("[model]\ndensity = -300.0\n", "density must be in [1, 100000]"),
        ("[model]\nfemur_length = 0.0\n", "femur_length must be in [1e-05, 1]"),
        ("[model]\nscale = 1e9\n", "scale must be in [0.01, 1000]"),
        ('[model]\nintegrator = "leapfrog"\n', "integrator must be one of"),
        ("[optimizer]\ninit_scale = 1e308\n", "init_scale must be in"),
        ("[rcga]\nmutation_sigma = nan\n", "mutation_sigma"),
    ],
)
def test_bad_model_or_optimizer_values_leave_nothing(
    tmp_path, capsys, monkeypatch, config, needle
):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "c.toml").write_text(config)
    argv = ["train", "kick", "--config", "c.toml", "--quiet", "--out", "run"]
    _fails_cleanly(argv, capsys, needle, tmp_path)


def test_os_errors_and_overflow_are_one_line(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "afile.txt").write_text("x")
    (tmp_path / "somedir").mkdir()
    _fails_cleanly(["train", "kick", "--out", "afile.txt/run"], capsys,
                   "Not a directory", tmp_path)  # fmt: skip
    _fails_cleanly(["train", "kick", "--config", "somedir", "--out", "x"], capsys,
                   "--config: somedir: is a directory", tmp_path)  # fmt: skip
    _fails_cleanly(["model", "--scale", "1e300", "--out", "m.xml"], capsys,
                   "scale must be in", tmp_path)  # fmt: skip


def test_unknown_option_before_the_command_is_named(capsys):
    with pytest.raises(SystemExit) as e:
        main(["--frobnicate"])
    err = capsys.readouterr().err
    assert e.value.code == 2 and "--frobnicate" in err and len(err.splitlines()) == 1


def test_interrupted_reproduce_says_how_to_continue(tmp_path, capsys, monkeypatch):
    import locustjump.cli.commands as commands

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    # the command's own name for it (an interrupt during any stage)
    monkeypatch.setattr(commands, "reproduce", interrupted)
    assert main(["reproduce", "--out", str(tmp_path / "r")]) == 130
    assert "rerun the same command" in capsys.readouterr().err


def _small_run(out: Path, generations: int) -> list[str]:
    return ["train", "kick", "--population", "4", "--generations", str(generations),
            "--seed", "1", "--threads", "1", "--quiet", "--out", str(out)]  # fmt: skip


def test_resume_validates_before_it_writes(tmp_path, capsys):
    out = tmp_path / "run"
    assert main(_small_run(out, 2)) == 0
    config = (out / rundir.CONFIG).read_bytes()
    # shortening a finished run is refused, and config.toml keeps its budget
    assert main([*_small_run(out, 1), "--resume"]) == 2
    assert "extended, not shortened" in capsys.readouterr().err
    assert (out / rundir.CONFIG).read_bytes() == config
    # a damaged metrics.csv is named, and config.toml is not rewritten
    (out / rundir.METRICS).write_text("generation,best\nnot a row\n")
    assert main([*_small_run(out, 3), "--resume"]) == 2
    assert rundir.METRICS in capsys.readouterr().err
    assert (out / rundir.CONFIG).read_bytes() == config


def test_one_writer_per_run_directory_and_a_killed_one_does_not_block(tmp_path, capsys):
    out = tmp_path / "run"
    cmd = [sys.executable, "-m", "locustjump.cli", *_small_run(out, 500)]
    first = subprocess.Popen(cmd)
    try:
        wait_for_rows(out, 2, timeout=60)
        assert main([*_small_run(out, 600), "--resume"]) == 2
        err = capsys.readouterr().err
        assert f"is in use by process {first.pid}" in err and len(err.splitlines()) == 1
        assert rundir.load_config(out / rundir.CONFIG).generations == 500
    finally:
        first.send_signal(signal.SIGKILL)
        first.wait()
    done = rundir.generations_done(out)
    assert main([*_small_run(out, done + 1), "--resume"]) == 0
    assert rundir.generations_done(out) == done + 1


def test_what_cannot_fit_in_memory_is_refused_before_anything(
    tmp_path, capsys, monkeypatch, shipped
):
    monkeypatch.chdir(tmp_path)
    # a machine of 4 GiB: the same refusals on any machine
    monkeypatch.setattr(resources, "available_bytes", lambda: 4 << 30)
    import shutil

    shutil.copytree(shipped / "getup", tmp_path / "getup")
    before = sorted(str(p) for p in (tmp_path / "getup").rglob("*"))
    _fails_cleanly(["sweep-getup", "getup", "--step-deg", "0.001"], capsys,
                   "--step-deg must be smaller: a sweep of 180,000 start states "
                   "needs about", tmp_path)  # fmt: skip
    assert sorted(str(p) for p in (tmp_path / "getup").rglob("*")) == before
    _fails_cleanly(["train", "kick", "--population", "1000000", "--out", "big"],
                   capsys, "--population must be smaller: a generation of "
                   "1,000,000 genomes needs about", tmp_path)  # fmt: skip
    _fails_cleanly(["rules", "--steps", "2000000000", "--out", "r"], capsys,
                   "GiB of memory; the limit is", tmp_path)  # fmt: skip


@contextlib.contextmanager
def _tmpfs(mnt: Path, options: str):
    """A tmpfs mounted at ``mnt`` (needs root: CI runs as root)."""
    import os

    mnt.mkdir()
    if os.geteuid() != 0:
        pytest.skip("mounting a tmpfs needs root (CI runs as root)")
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(mnt)],
                       capture_output=True, text=True)  # fmt: skip
    if r.returncode != 0:
        pytest.skip(f"cannot mount a tmpfs here: {r.stderr.strip()}")
    try:
        yield mnt
    finally:
        subprocess.run(["umount", "-l", str(mnt)], check=False)


@pytest.fixture
def small_disk(tmp_path):
    """A 2 MiB tmpfs."""
    with _tmpfs(tmp_path / "disk", "size=2m") as mnt:
        yield mnt


def _fill(d: Path) -> Path:
    """Take every free byte of the filesystem of ``d``."""
    filler = d / "filler"
    with open(filler, "wb", buffering=0) as f:
        try:
            while True:
                f.write(b"\0" * 4096)
        except OSError:
            pass
    return filler


def test_a_full_disk_loses_nothing_and_resume_is_bit_identical(
    small_disk, tmp_path, capsys
):
    argv = _small_run(small_disk / "run", 12)
    ref = tmp_path / "ref"
    assert main(_small_run(ref, 12)) == 0
    capsys.readouterr()
    # 4 generations, then the disk fills up
    cfg = rundir.load_config(ref / rundir.CONFIG).replace(generations=12)
    from locustjump.runs.trainer import train

    train(cfg, small_disk / "run", progress=False, stop_after=4)
    checkpoint = (small_disk / "run" / rundir.CHECKPOINT).read_bytes()
    filler = _fill(small_disk)
    assert main([*argv, "--resume"]) == 2
    err = capsys.readouterr().err
    assert "No space left on device" in err and len(err.strip().splitlines()) == 1
    assert "run/" in err  # names the file
    # the last complete checkpoint is intact, no temporary file is left
    assert (small_disk / "run" / rundir.CHECKPOINT).read_bytes() == checkpoint
    assert not [p for p in (small_disk / "run").iterdir() if p.name.startswith(".")]
    filler.unlink()  # space freed: --resume continues bit-identically
    assert main([*argv, "--resume"]) == 0
    assert_same_run(ref, small_disk / "run")


def test_a_new_run_on_a_full_disk_leaves_nothing(small_disk, capsys):
    filler = _fill(small_disk)
    try:
        assert main(_small_run(small_disk / "run", 2)) == 2
        err = capsys.readouterr().err
        assert "No space left on device" in err and len(err.strip().splitlines()) == 1
        assert sorted(p.name for p in small_disk.iterdir()) == ["filler"]
    finally:
        filler.unlink()


def test_evaluate_on_a_full_disk_leaves_no_directory(small_disk, tmp_path, capsys):
    run = tmp_path / "run"
    assert main(_small_run(run, 1)) == 0
    filler = _fill(small_disk)
    try:
        for out in (small_disk / "ev", small_disk / "a" / "b"):
            assert main(["evaluate", str(run), "--out", str(out)]) == 2
            err = capsys.readouterr().err
            assert "No space left on device" in err and len(err.splitlines()) == 1
            assert sorted(p.name for p in small_disk.iterdir()) == ["filler"]
    finally:
        filler.unlink()


def _can_render() -> None:
    from locustjump.present import render
    from locustjump.sim import model as lm

    try:
        render.make_renderer(lm.load_model(lm.LocustParams()), 32, 24).close()
        from locustjump.present.video import ffmpeg_exe

        ffmpeg_exe()
    except render.RenderUnavailable as e:
        pytest.skip(f"no offscreen rendering or encoding here: {e}")


def test_render_on_a_full_disk_is_one_line_and_leaves_nothing(tmp_path):
    """ffmpeg's failure (imageio dropped its exit status: exit 0, a truncated
    MP4) and Pillow's (imageio retried it in every __del__: 46 lines) end
    alike: one line, exit 2, no file."""
    _can_render()
    rules = tmp_path / "rules"
    assert main(["rules", "--steps", "120", "--out", str(rules)]) == 0
    # the videos: about 80 KB (MP4) and 190 KB (GIF)
    with _tmpfs(tmp_path / "disk", "size=64k") as disk:
        for ext in ("mp4", "gif"):
            r = subprocess.run(
                [sys.executable, "-m", "locustjump.cli", "render", str(rules),
                 "--out", str(disk / f"v.{ext}"), "--fps", "20", "--quiet"],
                capture_output=True, text=True,
            )  # fmt: skip
            assert r.returncode == 2 and r.stdout == "", r.stdout + r.stderr
            assert r.stderr == (
                f"locustjump: error: {disk / f'v.{ext}'}: cannot be written "
                "(No space left on device)\n"
            )
            assert not list(disk.iterdir())


def test_reading_a_shipped_reproduction_changes_none_of_its_files(
    shipped, tmp_path, capsys
):
    """evaluate, report and replay of a shipped reproduction leave every file
    it ships as it was (so a checkout stays clean)."""
    import shutil

    d = tmp_path / "repro"
    shutil.copytree(shipped, d)
    files = {p: p.read_bytes() for p in d.rglob("*") if p.is_file()}
    for stage in ("kick", "getup", "return-legs", "composed", "monolithic"):
        assert main(["evaluate", str(d / stage)]) == 0
    assert main(["report", str(d)]) == 0
    assert main(["replay", str(d), "--out", str(tmp_path / "rp")]) == 0
    capsys.readouterr()
    changed = [str(p.relative_to(d)) for p, b in files.items() if p.read_bytes() != b]
    # report.html is derived (not shipped: .gitignore)
    assert changed == [] or changed == ["report.html"], changed


def test_sigterm_stops_a_run_like_ctrl_c_and_it_resumes(tmp_path):
    out = tmp_path / "run"
    cmd = [sys.executable, "-m", "locustjump.cli", *_small_run(out, 500)]
    proc = subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True)
    wait_for_rows(out, 2, timeout=60)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130 and "rerun it with --resume" in err
    done = rundir.generations_done(out)
    assert main([*_small_run(out, done + 1), "--resume"]) == 0


def test_a_read_only_filesystem_is_one_line(tmp_path, capsys, shipped, render_problem):
    with _tmpfs(tmp_path / "ro", "ro,size=1m") as ro:
        for argv in (
            ["train", "kick", "--quiet", "--out", str(ro / "run")],
            ["model", "--out", str(ro / "m.xml")],
            ["replay", str(shipped), "--out", str(ro / "rp")],
            # named by us, before the video encoder prints anything
            ["render", str(shipped / "kick"), "--quiet", "--out", str(ro / "v.gif")],
        ):
            assert main(argv) == 2, argv
            err = capsys.readouterr().err
            assert len(err.splitlines()) == 1, err
            if argv[0] == "render" and render_problem is not None:
                assert render_problem in err  # where no frame can be drawn
                continue
            assert "Read-only file system" in err and str(ro) in err


def test_mujoco_warnings_go_to_the_log_not_into_the_working_directory(
    tmp_path, monkeypatch, caplog
):
    """An episode that blows up makes MuJoCo warn; the warning is logged
    (``locustjump.mujoco``, INFO), not printed into MUJOCO_LOG.TXT here."""
    import logging

    import numpy as np

    from locustjump.sim import model as lm
    from locustjump.sim.engine.rollout import StartStates, rollout
    from locustjump.tasks.rules import RuleController

    monkeypatch.chdir(tmp_path)
    rc = RuleController.for_model(lm.LocustParams())
    starts = StartStates.ready(lm.load_model()).take([0, 0])
    starts.qvel[1] = 1e30
    with caplog.at_level(logging.INFO, logger="locustjump.mujoco"):
        res = rollout(rc, rc.params_for(0.5), starts, 5)
    assert res.unstable.tolist() == [False, True]
    assert any("unstable" in r.getMessage() for r in caplog.records)
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()
    assert np.isfinite(res["qpos"]).all()


@pytest.mark.parametrize("command", [["train", "kick"], ["rules"], ["reproduce"]])
@pytest.mark.parametrize("out", ["", " ", "a\0b"])  # no path holds a null byte
def test_an_empty_out_is_refused_not_the_working_directory(
    tmp_path, monkeypatch, capsys, command, out
):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as e:
        main([*command, "--out", out])
    err = capsys.readouterr().err
    assert e.value.code == 2 and f"--out must be a path, got {out!r}" in err
    assert len(err.strip().splitlines()) == 1 and not any(tmp_path.iterdir())
