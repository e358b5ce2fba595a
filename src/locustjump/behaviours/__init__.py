"""The paper's behaviours: start states + episode length + fitness, one module each.

``get_behaviour(name)`` returns a :class:`Behaviour`; ``BEHAVIOURS`` lists the
names the command line accepts.
"""

from __future__ import annotations

from locustjump.behaviours.base import Behaviour
from locustjump.behaviours.kick import Kick

_REGISTRY: dict[str, type[Behaviour]] = {Kick.name: Kick}
BEHAVIOURS: tuple[str, ...] = tuple(_REGISTRY)


def get_behaviour(name: str) -> Behaviour:
    """The behaviour called ``name`` (``ValueError`` if there is none)."""
    try:
        return _REGISTRY[name]()
    except KeyError:
        raise ValueError(
            f"unknown behaviour {name!r}; choose from {', '.join(BEHAVIOURS)}"
        ) from None


__all__ = ["BEHAVIOURS", "Behaviour", "Kick", "get_behaviour"]
