"""The interactive viewer: a run's best controller live in ``mujoco.viewer``.

What it plays is what :func:`locustjump.present.playback.source_of` finds in a
directory; the controller acts every 1/120 s of simulated time, in real time.
"""

from __future__ import annotations

import os
import sys
import threading
import time

import mujoco
import numpy as np

from locustjump.errors import UserError
from locustjump.present.playback import Source, source_of
from locustjump.ranges import Range
from locustjump.sim import names
from locustjump.sim.engine.episode import Episode
from locustjump.sim.model import CONTROL_DT
from locustjump.sim.scene import Scene

#: ``duration``: (s) of a live view
DURATION = Range(0.0, lo_open=True, unit="s")


def view(
    path: str | os.PathLike[str],
    *,
    duration: float | None = None,
    scene: Scene | None = None,
) -> None:
    """Play what ``path`` holds live in MuJoCo's interactive viewer: the
    controller acts every 1/120 s of simulated time, in real time, looping over
    the start states until the window is closed (or ``duration`` seconds have
    passed). Drag the body with the mouse to perturb it."""
    if duration is not None:
        duration = DURATION.check("duration", duration)
    src = source_of(path, scene)  # what was asked for, before what this has
    if sys.platform.startswith("linux") and not (
        os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
    ):
        raise UserError(
            "no display (DISPLAY is not set): the viewer needs a desktop session; "
            "use `locustjump render` to make a video instead"
        )
    import mujoco.viewer

    ep = Episode(src.model_params, src.scene)
    ep.reset(src.starts, 0)
    before = set(threading.enumerate())
    try:
        handle = mujoco.viewer.launch_passive(ep.model, ep.data)
    except Exception as e:
        raise UserError(f"cannot open the MuJoCo viewer: {e}") from None
    end = None if duration is None else time.perf_counter() + duration
    try:
        _play(handle, ep, src, end)
    finally:
        handle.close()
        # let the viewer's thread tear its window down before the interpreter
        # does (GLFW's atexit terminate racing it crashes or hangs)
        for th in set(threading.enumerate()) - before:
            th.join(timeout=10)


def _play(
    handle: mujoco.viewer.Handle, ep: Episode, src: Source, end: float | None
) -> None:
    ctl = src.controller
    prepared = ctl.prepare(src.params)
    with handle as v:
        with v.lock():  # follow the body, from the side, 3 body lengths away
            v.cam.type = mujoco.mjtCamera.mjCAMERA_TRACKING
            v.cam.trackbodyid = ep.model.body(names.BODY).id
            v.cam.distance = 3 * src.model_params.body_length
            v.cam.azimuth, v.cam.elevation = 90.0, -10.0
        while v.is_running():
            for e in range(len(src.starts)):
                with v.lock():
                    obs = ep.reset(src.starts, e)
                memory = np.zeros((1, ctl.memory_size))
                for t in range(src.n_steps):
                    start = time.perf_counter()
                    if not v.is_running() or (end is not None and start > end):
                        return
                    deltas, memory = ctl.act(
                        prepared, memory, obs, ep.data.ctrl[None], t
                    )
                    with v.lock():
                        obs = ep.step(deltas)
                    v.sync()
                    if ep.unstable:
                        break
                    time.sleep(max(0.0, CONTROL_DT - (time.perf_counter() - start)))
