"""Module paths of locustjump 0.1, forwarded to where each module lives now.

Before the layer packages (docs/architecture.md) every module sat in
``locustjump/``; ``from locustjump.reproduce import reproduce`` and the like
still work, with a ``DeprecationWarning`` naming the new path. The module is
the new one itself (not a copy), so its state is shared; an old module whose
ideas went to several new ones is a module holding the public names of each.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
import types
import warnings

#: old module path -> new module path(s)
MOVED: dict[str, tuple[str, ...]] = {
    f"locustjump.{old}": tuple(f"locustjump.{n}" for n in new.split("+"))
    for old, new in {
        "names": "sim.names",
        "params": "sim.params",
        "model": "sim.model",
        "sensors": "sim.sensors+sim.actuation",
        "controller": "sim.controller",
        "analysis": "sim.analysis",
        "resources": "sim.resources",
        "kernels": "sim.kernels",
        "rollout": "sim.engine.rollout",
        "compiled": "sim.engine.compiled",
        "incallback": "sim.engine.incallback",
        "mjlayout": "sim.engine.mjlayout",
        "episode": "sim.engine.episode",
        "backends": "sim.engine.backends",
        "ray_backend": "sim.engine.ray_backend",
        "optimizers": "evo",
        "optimizers.base": "evo.base",
        "optimizers.rcga": "evo.rcga",
        "optimizers.cma": "evo.cma",
        "optimizers.random_search": "evo.random_search",
        "behaviours": "tasks",
        "behaviours.base": "tasks.base",
        "behaviours.kick": "tasks.kick",
        "behaviours.getup": "tasks.getup",
        "behaviours.return_legs": "tasks.return_legs",
        "behaviours.composed": "tasks.composed",
        "behaviours.monolithic": "tasks.monolithic",
        "behaviours.ceiling": "tasks.ceiling",
        "rules": "tasks.rules+tasks.reference",
        "config": "rundir.config",
        "plots": "present.plots",
        "results": "present.results",
        "report": "present.report",
        "render": "present.render",
        "compare": "present.compare",
        "evaluate": "present.evaluate",
        "trainer": "runs.trainer",
        "reproduce": "runs.reproduce",
        "multiseed": "runs.multiseed",
    }.items()
}


class MovedFinder(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Finds an old module path and hands out the module at its new one."""

    def find_spec(self, fullname: str, path=None, target=None):
        if fullname not in MOVED:
            return None
        return importlib.machinery.ModuleSpec(fullname, self)

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> types.ModuleType:
        new = MOVED[spec.name]
        warnings.warn(
            f"{spec.name} moved to {' and '.join(new)}; the old path will be removed",
            DeprecationWarning,
            stacklevel=2,
        )
        if len(new) == 1:
            return importlib.import_module(new[0])
        merged = types.ModuleType(spec.name, f"Forwards to {', '.join(new)}.")
        for name in new:
            module = importlib.import_module(name)
            merged.__dict__.update(
                (k, v) for k, v in vars(module).items() if not k.startswith("_")
            )
        return merged

    def exec_module(self, module: types.ModuleType) -> None:
        pass  # the new module is already executed


def install() -> None:
    """Forward the old paths (once per interpreter)."""
    if not any(isinstance(f, MovedFinder) for f in sys.meta_path):
        sys.meta_path.insert(0, MovedFinder())
