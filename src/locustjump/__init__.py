"""locustjump: a simulated locust learns successive jumping by neuroevolution.

Reproduces Umemura, Suzuki, Yamamoto & Furukawa (2011), *Acquisition of Jumping
Behavior on the Artificial Creature under Virtual Physical Environment*, with
MuJoCo and a real-coded genetic algorithm.
"""

from locustjump.controller import MLP, Controller
from locustjump.model import CONTROL_DT, LocustParams, load_model, to_mjcf
from locustjump.rollout import (
    RolloutJob,
    RolloutResult,
    StartStates,
    ThreadBackend,
    reference_rollout,
    rollout,
)
from locustjump.rules import RuleController, run_rules

__version__ = "0.1.0"

__all__ = [
    "CONTROL_DT",
    "MLP",
    "Controller",
    "LocustParams",
    "RolloutJob",
    "RolloutResult",
    "RuleController",
    "StartStates",
    "ThreadBackend",
    "load_model",
    "reference_rollout",
    "rollout",
    "run_rules",
    "to_mjcf",
]
