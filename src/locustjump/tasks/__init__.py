"""The behaviours as task specs: start states + episode length + controller
+ fitness, one module each (:class:`~locustjump.tasks.base.Behaviour` lists
the hooks); the rule-based jumper (:mod:`.rules`) is the reference they are
compared with.

``get_behaviour(name)`` returns one; ``behaviour_names()`` lists the names
the command line accepts. A new behaviour is a subclass registered with
:func:`register_behaviour`: training, evaluation, figures, videos, the
results table and the Gymnasium environment then work for it unchanged.
Another package's behaviours are found through the entry point group
``locustjump.tasks`` (:mod:`locustjump.plugins`), loaded the first time a
name is not known.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from locustjump import plugins
from locustjump.sim.scene import Terrains
from locustjump.tasks.base import Behaviour
from locustjump.tasks.ceiling import CEILING
from locustjump.tasks.composed import SIMPLE, Composed
from locustjump.tasks.getup import GetUp
from locustjump.tasks.height_only import HEIGHT_ONLY
from locustjump.tasks.kick import Kick
from locustjump.tasks.monolithic import Monolithic
from locustjump.tasks.repertoire import ComposedRepertoire
from locustjump.tasks.return_legs import ReturnLegs

_REGISTRY: dict[str, type[Behaviour]] = {}


def register_behaviour(cls: type[Behaviour]) -> type[Behaviour]:
    """Make behaviour class ``cls`` known by ``cls.name`` (usable as a decorator)."""
    for attr in ("name", "n_steps"):
        if not hasattr(cls, attr):
            raise TypeError(f"{cls.__name__} must set {attr!r}")
    _REGISTRY[cls.name] = cls
    return cls


for _cls in (Kick, GetUp, ReturnLegs, Composed, Monolithic):
    register_behaviour(_cls)

#: The paper's behaviours (the registry may hold more).
BEHAVIOURS: tuple[str, ...] = tuple(_REGISTRY)
#: Beyond the paper: the kick's ceiling (apex fitness, open-loop controller).
for _cls in CEILING:
    register_behaviour(_cls)
#: Beyond the paper: successive jumping by Eq. 4 alone on terrains too.
for _cls in HEIGHT_ONLY:
    register_behaviour(_cls)
#: Beyond the paper: the composed switcher over a kick repertoire's elites.
register_behaviour(ComposedRepertoire)

#: The three simple behaviours the composed one switches between.
SIMPLE_BEHAVIOURS: tuple[str, ...] = SIMPLE


def behaviour_names() -> tuple[str, ...]:
    """Every registered behaviour's name, the plugins' too."""
    plugins.load(plugins.TASKS, register_behaviour)
    return tuple(_REGISTRY)


def behaviour_class(name: str) -> type[Behaviour]:
    """The class registered as ``name`` (``ValueError`` if there is none)."""
    if name not in _REGISTRY:
        plugins.load(plugins.TASKS, register_behaviour)
    try:
        return _REGISTRY[name]
    except KeyError:
        raise ValueError(
            f"unknown behaviour {name!r}; choose from {', '.join(_REGISTRY)}"
        ) from None


def get_behaviour(
    name: str,
    frozen: np.ndarray | None = None,
    options: Any = None,
    terrains: Terrains | None = None,
) -> Behaviour:
    """The behaviour called ``name``.

    ``frozen`` (k, P): the genomes of the runs the behaviour builds on, in the
    order of its ``requires`` (the composed behaviour's kick, getup and
    return-legs networks); ignored by behaviours that build on none.
    ``options``: its ``Options`` (default: the paper's settings).
    ``terrains``: where it is scored (default: the flat floor).
    """
    return behaviour_class(name)(frozen, options, terrains)


__all__ = [
    "BEHAVIOURS",
    "SIMPLE_BEHAVIOURS",
    "Behaviour",
    "Composed",
    "ComposedRepertoire",
    "GetUp",
    "Kick",
    "Monolithic",
    "ReturnLegs",
    "behaviour_class",
    "behaviour_names",
    "get_behaviour",
    "register_behaviour",
]
