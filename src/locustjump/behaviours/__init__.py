"""The paper's behaviours: start states + episode length + fitness, one module each.

``get_behaviour(name)`` returns a :class:`Behaviour`; ``BEHAVIOURS`` lists the
names the command line accepts.
"""

from __future__ import annotations

import numpy as np

from locustjump.behaviours.base import Behaviour
from locustjump.behaviours.composed import SIMPLE, Composed, Monolithic
from locustjump.behaviours.getup import GetUp
from locustjump.behaviours.kick import Kick
from locustjump.behaviours.return_legs import ReturnLegs

_REGISTRY: dict[str, type[Behaviour]] = {
    b.name: b for b in (Kick, GetUp, ReturnLegs, Composed, Monolithic)
}
BEHAVIOURS: tuple[str, ...] = tuple(_REGISTRY)
#: The three simple behaviours the composed one switches between.
SIMPLE_BEHAVIOURS: tuple[str, ...] = SIMPLE


def get_behaviour(name: str, simple: np.ndarray | None = None) -> Behaviour:
    """The behaviour called ``name`` (``ValueError`` if there is none).

    ``simple`` (3, 144): the frozen kick, getup and return-legs genomes the
    composed behaviour switches between (ignored by the others).
    """
    try:
        cls = _REGISTRY[name]
    except KeyError:
        raise ValueError(
            f"unknown behaviour {name!r}; choose from {', '.join(BEHAVIOURS)}"
        ) from None
    return Composed(simple) if cls is Composed else cls()


__all__ = [
    "BEHAVIOURS",
    "SIMPLE_BEHAVIOURS",
    "Behaviour",
    "Composed",
    "GetUp",
    "Kick",
    "Monolithic",
    "ReturnLegs",
    "get_behaviour",
]
