"""A missing or broken OpenGL back end breaks only rendering, in one line.

MuJoCo imports PyOpenGL on its first import for ``MUJOCO_GL=osmesa`` or
``egl``; where the back end's library is missing, PyOpenGL raises an
``AttributeError`` that MuJoCo does not catch, which used to kill every
command, even ``--help`` (locustjump/opengl.py). The commands run in a
subprocess, as a user runs them: the back end is chosen once per process.
"""

import ctypes.util
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import locustjump

SRC = Path(locustjump.__file__).resolve().parents[1]
ROOT = SRC.parent
KICK = ROOT / "results" / "quick-seed0" / "kick"

#: PyOpenGL as it fails where its platform's library is missing
BROKEN = "raise AttributeError(\"'NoneType' object has no attribute 'glGetError'\")\n"


def _cli(args, tmp_path, *, gl, pythonpath=()):
    env = {k: v for k, v in os.environ.items() if k != "PYOPENGL_PLATFORM"}
    env.update(
        MUJOCO_GL=gl, PYTHONPATH=os.pathsep.join([*map(str, pythonpath), str(SRC)])
    )
    return subprocess.run(
        [sys.executable, "-m", "locustjump.cli", *args],
        cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300,
    )  # fmt: skip


@pytest.fixture
def broken_pyopengl(tmp_path):
    """A PyOpenGL whose GL and EGL modules fail as a missing library makes them."""
    pkg = tmp_path / "fake" / "OpenGL"
    for sub in ("GL", "EGL"):
        (pkg / sub).mkdir(parents=True)
        (pkg / sub / "__init__.py").write_text(BROKEN)
    (pkg / "__init__.py").write_text("")
    return tmp_path / "fake"


def _one_line_render_error(r, package):
    assert r.returncode == 2, r.stderr
    assert r.stderr.count("\n") == 1 and "Traceback" not in r.stderr, r.stderr
    assert package in r.stderr and "cannot render offscreen" in r.stderr


@pytest.mark.parametrize("gl, package", [("osmesa", "libosmesa6"), ("egl", "libegl1")])
def test_a_broken_backend_breaks_only_rendering(broken_pyopengl, tmp_path, gl, package):
    r = _cli(["--help"], tmp_path, gl=gl, pythonpath=[broken_pyopengl])
    assert r.returncode == 0 and "reproduce" in r.stdout, r.stderr
    if gl == "osmesa":  # a command that loads and simulates the model
        r = _cli(["model", "--out", "m.xml"], tmp_path, gl=gl,
                 pythonpath=[broken_pyopengl])  # fmt: skip
        assert r.returncode == 0 and (tmp_path / "m.xml").is_file(), r.stderr
    video = tmp_path / "v.gif"
    r = _cli(["render", str(KICK), "--out", str(video), "--quiet"], tmp_path, gl=gl,
             pythonpath=[broken_pyopengl])  # fmt: skip
    _one_line_render_error(r, package)
    assert not video.exists()


def test_osmesa_on_this_machine(tmp_path):
    """MUJOCO_GL=osmesa as the README suggests: --help always works; render
    works where libOSMesa is installed, and says to install it where not."""
    r = _cli(["--help"], tmp_path, gl="osmesa")
    assert r.returncode == 0, r.stderr
    video = tmp_path / "v.gif"
    args = ["render", str(KICK), "--out", str(video), "--fps", "4", "--quiet"]
    r = _cli(args, tmp_path, gl="osmesa")
    if ctypes.util.find_library("OSMesa") is None:
        _one_line_render_error(r, "libosmesa6")
    elif r.returncode != 0:  # installed but unusable: still one line
        assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
    else:
        assert video.is_file()


def test_reproduce_skips_its_videos_in_one_line(monkeypatch, shipped, tmp_path):
    """Where the back end was switched off, reproduce's videos are skipped with
    one log line naming the package (in-process: the reason as choose() keeps
    it)."""
    from locustjump import opengl
    from locustjump.runs.reproduce import render_videos

    problem = "MUJOCO_GL=osmesa: ... ; install the Debian package libosmesa6"
    monkeypatch.setattr(opengl, "PROBLEM", problem)
    d = shutil.copytree(shipped, tmp_path / "r")
    (d / "kick" / "video.mp4").unlink()  # the first stage without a video
    logs: list[str] = []
    assert render_videos(d, log=logs.append) == []
    assert logs == [f"videos skipped: cannot render offscreen: {problem}"]
    assert not (d / "kick" / "video.mp4").exists()
