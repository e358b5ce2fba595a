"""Videos and the interactive viewer of a run's best controller.

:func:`~locustjump.present.playback.playback_of` re-simulates what a
directory holds (the best genome of a training run, or a rule-based run)
with the engine and keeps every control step's ``qpos``; :func:`render_video`
draws it offscreen with MuJoCo's renderer (cameras ``track`` and ``side`` of
the MJCF) and encodes it (:mod:`~locustjump.present.video`: MP4 needs the
extra ``locustjump[video]``); :func:`locustjump.present.viewer.view` plays it
in ``mujoco.viewer``.

Headless Linux renders with EGL (``MUJOCO_GL=egl``, Debian package
``libegl1``, the default here when no display is set) or OSMesa
(``MUJOCO_GL=osmesa``, package ``libosmesa6``).
"""

from __future__ import annotations

import contextlib
import itertools
import os
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import TYPE_CHECKING

import mujoco
import numpy as np
from PIL import Image, ImageDraw, ImageFont
from tqdm import tqdm

from locustjump import opengl, rundir
from locustjump.errors import UserError, setting_ref
from locustjump.present.playback import Playback, playback_of

# their home before present/playback.py (the same objects)
from locustjump.present.playback import Source as Source  # noqa: I001
from locustjump.present.playback import acting as acting
from locustjump.present.playback import source_of as source_of
from locustjump.present.video import RenderUnavailable, write_video
from locustjump.ranges import Range, SettingValueError, check_choice
from locustjump.sim import model as lm
from locustjump.sim import names
from locustjump.sim.model import CONTROL_DT
from locustjump.sim.scene import Scene

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend

CAMERAS = (names.CAMERA_TRACK, names.CAMERA_SIDE)
VIDEO_SUFFIXES = (".mp4", ".gif")
#: ``fps``: frames per second of simulated time, at most one a control step
FPS = Range(0.0, 1 / CONTROL_DT, lo_open=True, unit="frames/s")
#: tile size (pixels) when several episodes play side by side
TILE = (320, 240)
#: frames per second of a reproduction's per-stage videos (a quarter of the
#: 120 Hz control rate)
VIDEO_FPS = 30.0


def check_rendering() -> None:
    """:class:`RenderUnavailable` where offscreen rendering was switched off
    (:data:`locustjump.opengl.PROBLEM` says what to install)."""
    if opengl.PROBLEM is not None:
        raise RenderUnavailable(f"cannot render offscreen: {opengl.PROBLEM}")


def make_renderer(m: mujoco.MjModel, width: int, height: int) -> mujoco.Renderer:
    """An offscreen renderer, or :class:`RenderUnavailable` saying what is missing."""
    check_rendering()
    try:
        return mujoco.Renderer(m, height=height, width=width)
    except Exception as e:  # GL back ends fail in many ways (ImportError, ...)
        gl = os.environ.get("MUJOCO_GL", "glfw")
        msg = str(e).splitlines()[0] if str(e) else type(e).__name__
        raise RenderUnavailable(
            f"cannot render offscreen with MUJOCO_GL={gl} ({msg}); headless Linux "
            "needs the Debian package libegl1 (MUJOCO_GL=egl) or libosmesa6 "
            "(MUJOCO_GL=osmesa), set before mujoco is first imported"
        ) from None


#: Pillow's default font: scalable (Pillow >= 10.1), else a bitmap
_Font = ImageFont.FreeTypeFont | ImageFont.ImageFont


def _font(size: int) -> _Font:
    try:
        return ImageFont.load_default(size=size)
    except TypeError:  # Pillow < 10.1: fixed-size bitmap font
        return ImageFont.load_default()


def _caption(img: np.ndarray, lines: list[str], font: _Font) -> np.ndarray:
    im = Image.fromarray(img)
    draw = ImageDraw.Draw(im)
    y = 4
    for line in lines:
        draw.text((6, y), line, fill=(255, 255, 255), font=font, stroke_width=2,
                  stroke_fill=(0, 0, 0))  # fmt: skip
        y += int(font.size * 1.25) if hasattr(font, "size") else 14
    return np.asarray(im)


def frames(
    pb: Playback,
    *,
    fps: float = 60.0,
    camera: str = names.CAMERA_TRACK,
    size: tuple[int, int] | None = None,
) -> Iterator[np.ndarray]:
    """RGB frames (h, w * k, 3) of ``pb`` at ``fps``, episodes side by side."""
    check_options(fps, camera)
    k = pb.qpos.shape[0]
    width, height = size or ((640, 480) if k == 1 else TILE)
    m = lm.load_model(pb.model_params, pb.scene)
    d = mujoco.MjData(m)
    renderer = make_renderer(m, width, height)
    font = _font(max(12, height // 20))
    n_frames = int(pb.n_steps * CONTROL_DT * fps) + 1
    try:
        for f in range(n_frames):
            t = min(round(f / (fps * CONTROL_DT)), pb.n_steps)
            tiles = []
            for e in range(k):
                d.qpos[:] = pb.qpos[e, t]
                mujoco.mj_forward(m, d)
                renderer.update_scene(d, camera=camera)
                lines = [f"{pb.labels[e]}  t = {t * CONTROL_DT:5.2f} s"]
                if pb.captions is not None:
                    lines.append(f"active: {pb.captions[e, t]}")
                tiles.append(_caption(renderer.render(), lines, font))
            yield np.concatenate(tiles, axis=1)
    finally:
        renderer.close()


def check_options(fps: float, camera: str) -> None:
    """One-line errors for a frame rate or camera that cannot be rendered
    (their declared ranges: :data:`FPS`, :data:`CAMERAS`)."""
    check_choice("camera", camera, CAMERAS)
    FPS.check("fps", fps)


def check_video_path(out: Path, *, force: bool = False) -> None:
    """One-line errors for an unsupported extension or an existing file."""
    if out.suffix.lower() not in VIDEO_SUFFIXES:
        raise SettingValueError(
            "out", f"a {' or '.join(VIDEO_SUFFIXES)} file", str(out)
        )
    if out.exists() and not force:
        raise UserError(
            f"{out} exists; use {setting_ref('force', True)} to overwrite it"
        )
    if not out.parent.is_dir():
        raise UserError(f"{out.parent}: no such directory")


def render_video(
    pb: Playback,
    out: str | os.PathLike[str],
    *,
    fps: float = 60.0,
    camera: str = names.CAMERA_TRACK,
    force: bool = False,
    progress: Callable[[int], object] | None = None,
) -> Path:
    """Encode ``pb`` into ``out`` (``.mp4`` or ``.gif``), written atomically."""
    out = Path(out)
    check_video_path(out, force=force)
    # GIF (256 colours, no inter-frame compression) is large: smaller frames
    size = TILE if out.suffix.lower() == ".gif" else None
    it = frames(pb, fps=fps, camera=camera, size=size)
    first = next(it)  # fails early (renderer) before a file is opened
    write_video(out, itertools.chain([first], it), fps, progress)
    return out


def render_run(
    path: str | os.PathLike[str],
    out: str | os.PathLike[str] | None = None,
    *,
    fps: float = 60.0,
    camera: str = names.CAMERA_TRACK,
    force: bool = False,
    progress: bool = False,
    backend: Backend | None = None,
    scene: Scene | None = None,
    label: str | None = None,
    elite: int | None = None,
    cell: tuple[int, ...] | None = None,
) -> Path:
    """Video of what directory ``path`` holds (default ``path/video.mp4``; a
    shipped run's under ``runs/shipped/``: :func:`locustjump.rundir.derived_dir`),
    in its own scene or ``scene``; ``progress``: a bar over the frames, called
    ``label`` (default ``render`` and the file's name); ``elite``/``cell``: an
    elite of a quality-diversity run's archive (default
    ``DIR/elites/cell-I-J/video.mp4``)."""
    check_options(fps, camera)  # before anything is made, simulated or shown
    made: contextlib.AbstractContextManager[Path | None] = contextlib.nullcontext()
    if out is None:
        if not Path(path).is_dir():
            raise UserError(f"{path}: no such directory")
        out = rundir.derived_dir(Path(path)) / rundir.VIDEO
        if elite is not None or cell is not None:  # it exists: before mkdir
            _, _, chosen = rundir.load_elite(path, elite=elite, cell=cell)
            assert isinstance(chosen, rundir.Elite)
            out = rundir.elite_dir(Path(path), chosen.cell) / rundir.VIDEO
        made = rundir.made_dir(out.parent)  # removed again if rendering fails
    out = Path(out)
    with made:
        check_video_path(out, force=force)
        with rundir.locked(out.parent):  # the directory written into
            check_video_path(out, force=force)  # another process was first?
            pb = playback_of(path, backend=backend, scene=scene, elite=elite, cell=cell)
            label = f"render {out.name}" if label is None else label
            return _encode(pb, out, fps, camera, force, label if progress else None)


def _encode(
    pb: Playback, out: Path, fps: float, camera: str, force: bool, desc: str | None
) -> Path:
    """``render_video``, with a progress bar called ``desc`` if not ``None``."""
    if desc is None:
        return render_video(pb, out, fps=fps, camera=camera, force=force)
    total = int(pb.n_steps * CONTROL_DT * fps) + 1
    with tqdm(total=total, unit="frame", desc=desc) as bar:
        return render_video(
            pb, out, fps=fps, camera=camera, force=force,
            progress=lambda n: bar.update(n - bar.n),
        )  # fmt: skip
