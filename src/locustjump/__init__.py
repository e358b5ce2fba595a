"""locustjump: a simulated locust learns successive jumping by neuroevolution.

Reproduces Umemura, Suzuki, Yamamoto & Furukawa (2011), *Acquisition of Jumping
Behavior on the Artificial Creature under Virtual Physical Environment*, with
MuJoCo and a real-coded genetic algorithm.
"""

# Offscreen rendering: choose MuJoCo's OpenGL back end before anything imports
# mujoco (EGL on a headless Linux machine; a back end whose library is missing
# is switched off, so that only rendering fails, in one line).
# Importing it chooses the back end.
from locustjump import opengl as _opengl  # noqa: F401

# isort: split

from locustjump import moved
from locustjump.evo import (
    CMAES,
    RCGA,
    CMAParams,
    Optimizer,
    RandomSearch,
    RandomSearchParams,
    RCGAParams,
    make_optimizer,
    register,
)
from locustjump.present.evaluate import evaluate_run
from locustjump.rundir import load_run
from locustjump.rundir.config import TrainConfig
from locustjump.runs.trainer import Trainer, train
from locustjump.sim.controller import MLP, Controller
from locustjump.sim.engine.backends import ThreadBackend, make_backend
from locustjump.sim.engine.episode import reference_rollout
from locustjump.sim.engine.rollout import (
    RolloutJob,
    RolloutResult,
    StartStates,
    rollout,
)
from locustjump.sim.model import CONTROL_DT, LocustParams, load_model, to_mjcf
from locustjump.tasks import (
    BEHAVIOURS,
    Behaviour,
    get_behaviour,
    register_behaviour,
)
from locustjump.tasks.reference import run_rules
from locustjump.tasks.rules import RuleController
from locustjump.version import __version__

moved.install()  # the module paths of 0.1 (locustjump.reproduce, ...)

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
    "ThreadBackend",
    "TrainConfig",
    "evaluate_run",
    "get_behaviour",
    "load_model",
    "load_run",
    "make_backend",
    "make_optimizer",
    "register",
    "register_behaviour",
    "reference_rollout",
    "rollout",
    "run_rules",
    "to_mjcf",
    "Trainer",
    "train",
]
