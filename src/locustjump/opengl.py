"""The OpenGL back end MuJoCo renders with, chosen before MuJoCo is imported.

MuJoCo reads ``MUJOCO_GL`` when it is first imported and, for ``osmesa`` and
``egl``, imports PyOpenGL on that platform there and then. Where the platform's
library is missing (``MUJOCO_GL=osmesa`` without ``libosmesa6``), PyOpenGL
fails with an ``AttributeError`` that MuJoCo does not catch, so *every* import
of ``mujoco`` would die — every command, even ``locustjump --help``, though
only rendering needs OpenGL. :func:`choose` runs when ``mujoco`` is first
imported, wherever that is (a finder on ``sys.meta_path`` that this module
installs, and the package's ``__init__`` imports it first): it picks EGL on a
headless Linux machine where the user chose nothing, and it tries the chosen
back end's OpenGL imports itself; if they fail, it switches MuJoCo's rendering
off (``MUJOCO_GL=disable``) and keeps the reason in :data:`PROBLEM`, which
rendering reports in one line.
"""

from __future__ import annotations

import ctypes
import importlib
import os
import sys
from collections.abc import Sequence
from types import ModuleType

#: why offscreen rendering is off (set by :func:`choose`), else None
PROBLEM: str | None = None

#: what MuJoCo imports for each back end that goes through PyOpenGL
#: (``mujoco/osmesa/__init__.py``, ``mujoco/egl/egl_ext.py``)
_PYOPENGL_IMPORTS = {
    "osmesa": ("OpenGL.GL", "OpenGL.osmesa", "OpenGL.GL.arrays"),
    "egl": ("OpenGL.EGL", "OpenGL.error"),
}

#: the Debian package that provides each back end's library
PACKAGES = {"osmesa": "libosmesa6", "egl": "libegl1", "glx": "libgl1"}


def _headless_linux() -> bool:
    return sys.platform.startswith("linux") and not (
        os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
    )


def _purge_pyopengl() -> None:
    """Forget a half-imported PyOpenGL, so that nothing uses it later."""
    for name in [n for n in sys.modules if n == "OpenGL" or n.startswith("OpenGL.")]:
        del sys.modules[name]


def _loads(name: str) -> bool:
    """Whether shared library ``name`` can be loaded (as PyOpenGL loads it;
    ``ctypes.util.find_library`` runs ``ldconfig`` in a subprocess, which
    took up to 0.2 s of the command line's start, before it can answer
    Ctrl-C)."""
    try:
        ctypes.CDLL(name)
    except OSError:
        return False
    return True


def choose() -> str | None:
    """Set ``MUJOCO_GL`` before MuJoCo is imported; returns :data:`PROBLEM`.

    Unset on a headless Linux machine: ``egl`` if its library is installed.
    ``osmesa`` or ``egl`` whose OpenGL library cannot be loaded: ``disable``
    (MuJoCo imports, every command that does not render works) and
    :data:`PROBLEM` says what to install. A no-op once MuJoCo is imported.
    """
    global PROBLEM
    if "mujoco" in sys.modules:
        return PROBLEM
    if "MUJOCO_GL" not in os.environ and _headless_linux():
        if _loads("libEGL.so.1"):
            os.environ["MUJOCO_GL"] = "egl"
    gl = os.environ.get("MUJOCO_GL", "").lower().strip()
    platform = os.environ.get("PYOPENGL_PLATFORM", "")
    if gl not in _PYOPENGL_IMPORTS or platform.lower() not in ("", gl):
        return PROBLEM  # MuJoCo itself turns these failures into ImportError
    os.environ.setdefault("PYOPENGL_PLATFORM", gl)  # as MuJoCo would
    try:
        for module in _PYOPENGL_IMPORTS[gl]:
            importlib.import_module(module)
    except Exception as e:  # PyOpenGL fails as AttributeError, OSError, ...
        _purge_pyopengl()
        os.environ["MUJOCO_GL"] = "disable"
        if not platform:
            del os.environ["PYOPENGL_PLATFORM"]
        detail = str(e).splitlines()[0] if str(e) else type(e).__name__
        PROBLEM = (
            f"MUJOCO_GL={gl}: its OpenGL library cannot be loaded ({detail}); "
            f"install the Debian package {PACKAGES[gl]}"
            + (
                " or unset MUJOCO_GL to render with EGL (libegl1)"
                if gl != "egl"
                else ""
            )
        )
    return PROBLEM


class _BeforeMuJoCo:
    """A meta path finder (``importlib.abc.MetaPathFinder``, whose import
    costs more than the rest of ``import locustjump``) that runs
    :func:`choose` when ``mujoco`` is first imported, and finds nothing
    itself: the import goes on as if it were not there."""

    def find_spec(
        self,
        name: str,
        path: Sequence[str] | None = None,
        target: ModuleType | None = None,
    ) -> None:
        if name == "mujoco":
            choose()
        return None


def install() -> None:
    """:func:`choose` before MuJoCo is first imported, wherever that import
    is: not when ``locustjump`` is imported, so that ``import locustjump``
    stays light (the command line handles Ctrl-C only once it runs, and
    choosing takes PyOpenGL's imports)."""
    if "mujoco" in sys.modules:
        choose()  # too late to choose: records the problem, if any
    elif not any(isinstance(f, _BeforeMuJoCo) for f in sys.meta_path):
        sys.meta_path.insert(0, _BeforeMuJoCo())


install()
