"""Videos (offscreen MuJoCo renderer + imageio), the viewer's error without a
display, and the bad-input errors of render/view."""

import json
import shutil

import numpy as np
import pytest

from helpers import exit_status
from locustjump.cli import main
from locustjump.present import render
from locustjump.sim import names

iio = pytest.importorskip("imageio.v2", reason="extra locustjump[test] not installed")


def _frames(path):
    if path.suffix == ".gif":
        return list(iio.mimread(path))
    with iio.get_reader(path) as r:  # imageio-ffmpeg
        return [r.get_data(i) for i in range(r.count_frames())]


@pytest.fixture
def can_render(render_problem):
    if render_problem is not None:
        pytest.skip(f"no offscreen rendering here: {render_problem}")


@pytest.fixture
def rules_dir(tmp_path):
    d = tmp_path / "rules"
    assert main(["rules", "--steps", "120", "--out", str(d)]) == 0
    assert json.loads((d / "summary.json").read_text())["steps"] == 120
    return d


def test_render_rules_mp4(can_render, rules_dir, capsys):
    out = rules_dir / "jump.mp4"
    rc = main(["render", str(rules_dir), "--out", str(out), "--fps", "20", "--quiet"])
    assert rc == 0 and out.is_file()
    frames = _frames(out)
    assert len(frames) == 21  # 1 s at 20 fps, both ends
    assert frames[0].shape == (480, 640, 3)
    assert frames[0].std() > 10  # not a blank image
    # the creature moves: frames differ
    assert np.abs(frames[0].astype(int) - frames[-1].astype(int)).mean() > 1
    assert not list(rules_dir.glob(".*partial*"))  # written atomically


def test_render_gif_side_camera(can_render, rules_dir):
    out = render.render_run(
        rules_dir, rules_dir / "jump.gif", fps=10, camera=names.CAMERA_SIDE
    )
    frames = _frames(out)
    assert len(frames) == 11 and frames[0].shape[:2] == (240, 320)


def test_getup_side_by_side_and_composed_captions(can_render, shipped):
    pb = render.playback_of(shipped / "getup")
    assert pb.qpos.shape[0] == 5 and pb.labels[0] == "roll090"
    frame = next(render.frames(pb, fps=1))
    assert frame.shape == (240, 5 * 320, 3)
    pb = render.playback_of(shipped / "composed")
    assert pb.captions is not None
    assert set(np.unique(pb.captions)) <= {"kick", "getup", "return-legs"}
    assert pb.captions.shape == pb.qpos.shape[:2]


def test_render_bad_input(tmp_path, rules_dir, capsys):
    cases = [
        ([str(tmp_path / "nope")], "no such directory"),
        ([str(tmp_path)], "holds no run"),
        (
            [str(rules_dir), "--out", str(tmp_path / "v.avi")],
            "--out must be a .mp4 or .gif file",
        ),
        ([str(rules_dir), "--camera", "top"], "invalid choice"),
        ([str(rules_dir), "--fps", "0"], "--fps"),
        # checked before anything is simulated or a progress bar shown
        (
            [str(rules_dir), "--fps", "1e9"],
            "fps must be in (0, 120] frames/s, got 1000000000.0",
        ),
    ]
    for args, msg in cases:
        capsys.readouterr()
        assert exit_status(["render", *args]) == 2
        err = capsys.readouterr().err
        assert msg in err and err.count("\n") == 1, err
        assert "%|" not in err and "\r" not in err, err  # no progress bar
    # an existing video is not overwritten without --force
    existing = tmp_path / "v.mp4"
    existing.write_bytes(b"precious")
    assert main(["render", str(rules_dir), "--out", str(existing)]) == 2
    assert existing.read_bytes() == b"precious"
    assert "--force" in capsys.readouterr().err


def test_render_reproduction_dir_points_at_stages(tmp_path, capsys):
    (tmp_path / "reproduce.toml").write_text("")
    assert main(["render", str(tmp_path)]) == 2
    assert "give one of its stages" in capsys.readouterr().err


def test_view_without_display(monkeypatch, rules_dir, capsys):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    assert main(["view", str(rules_dir)]) == 2
    err = capsys.readouterr().err
    assert "no display" in err and err.count("\n") == 1


def test_missing_renderer_is_a_one_line_error(monkeypatch, rules_dir, capsys):
    def broken(*args, **kwargs):
        raise RuntimeError("gladLoadGL error")

    monkeypatch.setattr(render.mujoco, "Renderer", broken)
    assert main(["render", str(rules_dir), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "libegl1" in err and err.count("\n") == 1
    assert not (rules_dir / "video.mp4").exists()


def test_reproduction_stage_copy_renders(can_render, shipped, tmp_path):
    # a run directory copied elsewhere still renders (the video goes there)
    d = shutil.copytree(
        shipped / "kick", tmp_path / "kick", ignore=shutil.ignore_patterns("*.mp4")
    )
    out = render.render_run(d, fps=10)
    assert out == d / "video.mp4" and len(_frames(out)) == 26


def test_view_plays_under_a_virtual_display(rules_dir):
    """The viewer opens and plays the controller (Debian package xvfb)."""
    import subprocess
    import sys

    xvfb = shutil.which("xvfb-run")
    if xvfb is None:
        pytest.skip("xvfb-run not installed (Debian package xvfb)")
    code = (
        "from locustjump.present.viewer import view; "
        f"view({str(rules_dir)!r}, duration=3)"
    )
    r = subprocess.run(
        [xvfb, "-a", "-s", "-screen 0 800x600x24", sys.executable, "-c", code],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    if "cannot open the MuJoCo viewer" in r.stderr:
        pytest.skip(f"no OpenGL under Xvfb here: {r.stderr.strip()[-200:]}")
    assert r.returncode == 0, r.stderr[-2000:]


def test_playback_names_still_import_from_render():
    """present/playback.py came out of render.py: the old import paths give
    the same objects."""
    from locustjump.present import playback

    for name in ("Playback", "Source", "source_of", "playback_of", "acting"):
        assert getattr(render, name) is getattr(playback, name)
