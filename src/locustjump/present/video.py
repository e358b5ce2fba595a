"""Frames encoded into a video file, complete or not at all.

MP4 (H.264) through the ffmpeg binary that ``imageio-ffmpeg`` ships (extra
``locustjump[video]``), run here with its exit status and error log kept:
imageio's writer drops both, so a disk that fills up while ffmpeg writes the
file's index (the ``moov`` atom, last) left an unplayable file and exit 0.
GIF through Pillow, closed here: imageio's GIF writer retries its failed
flush from every ``__del__``, one traceback each. Both write a temporary
file beside the target, renamed onto it only once the encoder has succeeded
(:func:`locustjump.rundir.atomic_path`); any failure is one ``UserError``
naming the target, and the temporary file is removed.
"""

from __future__ import annotations

import contextlib
import errno
import itertools
import os
import re
import subprocess
import tempfile
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path

import numpy as np
from PIL import Image

from locustjump import rundir
from locustjump.errors import UserError

#: H.264 constant rate factor (0 lossless .. 51): imageio's ``quality=7``
CRF = 15


class RenderUnavailable(UserError):
    """Offscreen rendering or video encoding is not possible here."""


def ffmpeg_exe() -> str:
    """The ffmpeg binary of ``imageio-ffmpeg``."""
    try:
        import imageio_ffmpeg
    except ImportError:
        raise RenderUnavailable(
            "mp4 needs imageio-ffmpeg: pip install -e '.[video]' in the clone "
            "(or use .gif)"
        ) from None
    exe: str = imageio_ffmpeg.get_ffmpeg_exe()
    return exe


def write_video(
    out: Path,
    frames: Iterator[np.ndarray],
    fps: float,
    progress: Callable[[int], object] | None = None,
) -> None:
    """Encode RGB ``frames`` (h, w, 3 uint8) at ``fps`` into ``out`` (``.mp4``
    or ``.gif`` by its suffix) atomically; ``progress(n)`` after the n-th."""
    out = Path(out)
    encode = _gif if out.suffix.lower() == ".gif" else _mp4
    if encode is _mp4:
        ffmpeg_exe()  # before a file is made
    with rundir.atomic_path(out, partial=".partial") as tmp:
        open(tmp, "wb").close()  # an unwritable place is named before encoding
        encode(tmp, frames, fps, progress or (lambda n: None))


def _gif(
    tmp: Path,
    frames: Iterable[np.ndarray],
    fps: float,
    progress: Callable[[int], object],
) -> None:
    images = []
    for n, frame in enumerate(frames, start=1):
        images.append(Image.fromarray(frame))
        progress(n)
    with open(tmp, "wb") as f:
        images[0].save(
            f, format="GIF", save_all=True, append_images=images[1:],
            duration=1000.0 / fps, loop=0,
        )  # fmt: skip


def _mp4(
    tmp: Path,
    frames: Iterable[np.ndarray],
    fps: float,
    progress: Callable[[int], object],
) -> None:
    frames = iter(frames)
    first = next(frames)
    height, width = first.shape[:2]
    cmd = [
        ffmpeg_exe(), "-y", "-f", "rawvideo", "-vcodec", "rawvideo",
        "-s", f"{width}x{height}", "-pix_fmt", "rgb24", "-r", f"{fps:.02f}",
        "-i", "-", "-an", "-vcodec", "libx264", "-pix_fmt", "yuv420p",
        "-crf", str(CRF), "-v", "error", str(tmp),
    ]  # fmt: skip
    # its log in a file, not a pipe: a full pipe would stop it mid-video
    with tempfile.TemporaryFile() as log:
        p = subprocess.Popen(
            cmd, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=log
        )
        assert p.stdin is not None
        try:
            for n, frame in enumerate(itertools.chain([first], frames), start=1):
                p.stdin.write(np.ascontiguousarray(frame, dtype=np.uint8).tobytes())
                progress(n)
            p.stdin.close()
        except BrokenPipeError:  # ffmpeg stopped: its status and log say why
            with contextlib.suppress(BrokenPipeError):
                p.stdin.close()
        except BaseException:  # Ctrl-C, a frame that cannot be drawn
            p.kill()
            p.wait()
            raise
        status = p.wait()
        if status != 0:
            log.seek(0)
            raise _failure(status, log.read().decode(errors="replace"))


def _failure(status: int, text: str) -> OSError:
    """ffmpeg's failure as an ``OSError``: the system's error where its last
    line names one (a full disk), else that line and its exit status."""
    lines = [re.sub(r"^\[[^]]*\]\s*", "", s).strip() for s in text.splitlines()]
    last = next((s for s in reversed(lines) if s), "no message")
    for code in errno.errorcode:
        if last.endswith(os.strerror(code)):
            return OSError(code, os.strerror(code))
    return OSError(f"ffmpeg exit status {status}: {last}")
