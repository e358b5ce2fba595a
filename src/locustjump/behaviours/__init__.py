"""The paper's behaviours: start states + episode length + fitness, one module each.

``get_behaviour(name)`` returns a :class:`Behaviour`; ``BEHAVIOURS`` lists the
names the command line accepts.
"""

from __future__ import annotations

from locustjump.behaviours.base import Behaviour
from locustjump.behaviours.getup import GetUp
from locustjump.behaviours.kick import Kick
from locustjump.behaviours.return_legs import ReturnLegs

_REGISTRY: dict[str, type[Behaviour]] = {b.name: b for b in (Kick, GetUp, ReturnLegs)}
BEHAVIOURS: tuple[str, ...] = tuple(_REGISTRY)


def get_behaviour(name: str) -> Behaviour:
    """The behaviour called ``name`` (``ValueError`` if there is none)."""
    try:
        return _REGISTRY[name]()
    except KeyError:
        raise ValueError(
            f"unknown behaviour {name!r}; choose from {', '.join(BEHAVIOURS)}"
        ) from None


__all__ = ["BEHAVIOURS", "Behaviour", "GetUp", "Kick", "ReturnLegs", "get_behaviour"]
