"""Plugins: optimizers, behaviours and scenes from another package.

A distribution installed beside locustjump names what it adds under one of
three entry point groups, each entry a module (whose import registers what it
defines with :func:`locustjump.evo.register`,
:func:`locustjump.tasks.register_behaviour` or
:func:`locustjump.sim.scene.register_scene`) or a class (registered for it)::

    # the plugin's pyproject.toml
    [project.entry-points."locustjump.optimizers"]
    hillclimb = "myplugin.hill:HillClimb"
    [project.entry-points."locustjump.tasks"]
    stand-tall = "myplugin.stand"
    [project.entry-points."locustjump.scenes"]
    steps = "myplugin.steps:Steps"

Each registry loads its group the first time it is asked for a name it does
not hold, or for every name (the command line's choices): lazily, and once
per process. A plugin that fails to load is skipped with one warning naming
it (logger ``locustjump.plugins``); ``locustjump --plugin MODULE`` imports a
module that is not an entry point (:func:`load_module`), and fails in one
line if it cannot. A run's ``config.toml`` names the modules its optimizer,
behaviour and scene came from (:func:`provenance`), so that reading it where
they are missing says which to install (:func:`check_loaded`).
"""

from __future__ import annotations

import functools
import importlib
import importlib.metadata
import logging
import re
import sys
import threading
from collections.abc import Callable, Iterable, Mapping
from typing import Any

from locustjump.errors import UserError, setting_ref

#: the entry point groups, by what they hold
OPTIMIZERS = "locustjump.optimizers"
TASKS = "locustjump.tasks"
SCENES = "locustjump.scenes"

log = logging.getLogger(__name__)

_lock = threading.RLock()  # a plugin's import may ask a registry again
_loaded: set[str] = set()  # groups loaded (or being loaded) in this process
#: module -> the distribution that named it (entry points only)
_distributions: dict[str, str] = {}
_MODULE = re.compile(r"[A-Za-z_]\w*(\.[A-Za-z_]\w*)*")


def load(group: str, register: Callable[[Any], Any]) -> None:
    """Load every entry point of ``group`` once: import its module, and pass
    an entry that names a class to ``register``. One that fails is skipped
    with a warning naming it and its distribution."""
    with _lock:
        if group in _loaded:
            return
        _loaded.add(group)  # before loading: a plugin's import may ask again
        for ep in importlib.metadata.entry_points(group=group):
            dist = ep.dist.name if ep.dist is not None else ""
            if dist:
                _distributions.setdefault(ep.module, dist)
            try:
                obj = ep.load()
                if isinstance(obj, type):
                    register(obj)
            except Exception as e:  # anything a foreign import may raise
                of = f" of distribution {dist}" if dist else ""
                log.warning(
                    "plugin %r%s (%s in %s) failed to load "
                    "and is skipped: %s: %s",
                    ep.name, of, ep.value, group, type(e).__name__, _one_line(e),
                )  # fmt: skip


def load_module(name: str) -> None:
    """Import module ``name`` (``--plugin``), whose import registers what it
    defines; a ``UserError`` naming it if it cannot be imported."""
    if not _MODULE.fullmatch(name):
        raise UserError(
            f"{setting_ref('plugin')}: {name!r} is not a module name (e.g. mypkg.mod)"
        )
    try:
        importlib.import_module(name)
    except Exception as e:  # anything a foreign import may raise
        raise UserError(
            f"{setting_ref('plugin')} {name}: cannot import it "
            f"({type(e).__name__}: {_one_line(e)})"
        ) from None


def provenance(classes: Iterable[type]) -> dict[str, str]:
    """The plugin modules that define ``classes`` (those outside locustjump),
    each with the distribution that installed it ("" if none is known)."""
    found = {}
    for cls in classes:
        module = cls.__module__
        if module.split(".")[0] != "locustjump":
            found[module] = _distribution(module)
    return found


def check_loaded(plugins: Mapping[str, str], source: str) -> None:
    """A ``UserError`` naming the first module of ``plugins`` (module ->
    distribution, as :func:`provenance` gives) that is not imported here:
    what ``source`` (a run's ``config.toml``) was made with."""
    for module, dist in plugins.items():
        if module in sys.modules:
            continue
        if module == "__main__":
            raise UserError(
                f"{source}: made with classes defined in a script or notebook "
                "(__main__), which cannot be loaded here: make them a plugin "
                "module (docs/architecture.md, Plugins)"
            )
        install = f"install {dist}" if dist else "install it"
        of = f" (distribution {dist})" if dist else ""
        raise UserError(
            f"{source}: made with the plugin {module}{of}, which is not "
            f"loaded here: {install}, or give {setting_ref('plugin')} {module}"
        )


def _distribution(module: str) -> str:
    """The distribution that installed ``module``, if known."""
    if module in _distributions:
        return _distributions[module]
    dists = _packages().get(module.split(".")[0], [])
    return dists[0] if len(dists) == 1 else ""


@functools.cache
def _packages() -> Mapping[str, list[str]]:
    """Top-level package -> distributions (read once: it reads every
    installed distribution's file list, a second or more)."""
    try:
        return importlib.metadata.packages_distributions()
    except Exception:  # a broken installation elsewhere: none known
        return {}


def _one_line(e: BaseException) -> str:
    text = " ".join(str(e).split())
    return text if len(text) <= 200 else text[:197] + "..."
