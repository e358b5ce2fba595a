"""locustjump: a simulated locust learns successive jumping by neuroevolution.

Reproduces Umemura, Suzuki, Yamamoto & Furukawa (2011), *Acquisition of Jumping
Behavior on the Artificial Creature under Virtual Physical Environment*, with
MuJoCo and a real-coded genetic algorithm.
"""

# Offscreen rendering: choose MuJoCo's OpenGL back end before anything imports
# mujoco (EGL on a headless Linux machine; a back end whose library is missing
# is switched off, so that only rendering fails, in one line).
# Importing it has the back end chosen when mujoco is first imported.
from locustjump import opengl as _opengl  # noqa: F401

# isort: split

import importlib as _importlib
from typing import Any as _Any

from locustjump.version import __version__

#: the public names, and the module each comes from: loaded when first used
#: (``import locustjump`` stays light, so that ``locustjump``'s command line
#: can answer Ctrl-C while MuJoCo, Numba and Matplotlib load)
_FROM = {
    "locustjump.evo": ("CMAES", "RCGA", "CMAParams", "Optimizer", "RandomSearch",
                       "RandomSearchParams", "RCGAParams", "make_optimizer",
                       "register"),
    "locustjump.present.evaluate": ("evaluate_run",),
    "locustjump.rundir": ("load_run",),
    "locustjump.rundir.config": ("TrainConfig",),
    "locustjump.runs.loop": ("Trainer",),
    "locustjump.runs.study": ("run_study",),
    "locustjump.runs.study_table": ("study_table",),
    "locustjump.runs.studyfile": ("Study", "load_study"),
    "locustjump.runs.trainer": ("train",),
    "locustjump.sim.controller": ("MLP", "Controller"),
    "locustjump.sim.engine.backends": ("ThreadBackend", "make_backend"),
    "locustjump.sim.engine.episode": ("reference_rollout",),
    "locustjump.sim.engine.rollout": ("RolloutJob", "RolloutResult", "StartStates",
                                      "rollout"),
    "locustjump.sim.model": ("CONTROL_DT", "LocustParams", "load_model", "to_mjcf"),
    "locustjump.tasks": ("BEHAVIOURS", "Behaviour", "get_behaviour",
                         "register_behaviour"),
    "locustjump.tasks.reference": ("run_rules",),
    "locustjump.tasks.rules": ("RuleController",),
}  # fmt: skip
_MODULE_OF = {name: module for module, names in _FROM.items() for name in names}


def __getattr__(name: str) -> _Any:
    if name in _MODULE_OF:
        value = getattr(_importlib.import_module(_MODULE_OF[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'locustjump' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_MODULE_OF})


__all__ = [
    "__version__",
    "BEHAVIOURS",
    "CMAES",
    "CONTROL_DT",
    "MLP",
    "RCGA",
    "Behaviour",
    "CMAParams",
    "Controller",
    "LocustParams",
    "Optimizer",
    "RCGAParams",
    "RandomSearch",
    "RandomSearchParams",
    "RolloutJob",
    "RolloutResult",
    "RuleController",
    "StartStates",
    "Study",
    "ThreadBackend",
    "TrainConfig",
    "evaluate_run",
    "get_behaviour",
    "load_model",
    "load_run",
    "load_study",
    "make_backend",
    "make_optimizer",
    "register",
    "register_behaviour",
    "reference_rollout",
    "rollout",
    "run_rules",
    "run_study",
    "study_table",
    "to_mjcf",
    "Trainer",
    "train",
]
