"""Every behaviour's presentation (:class:`~.base.Reporter`), looked up by
behaviour class: ``reporter_of(beh)`` walks the class's bases, so a variant
of a behaviour (``kick-apex`` of the kick) is shown like it unless it has a
reporter of its own, and a behaviour nobody registered gets the default (a
trajectory figure, no claims)."""

from __future__ import annotations

from locustjump.present.stages.base import Claim, Episodes, Reporter, fmt, yes
from locustjump.present.stages.getup import GetUpReporter
from locustjump.present.stages.kick import CeilingReporter, KickReporter
from locustjump.present.stages.return_legs import ReturnLegsReporter
from locustjump.present.stages.successive import (
    ComposedReporter,
    MonolithicReporter,
    SuccessiveReporter,
)
from locustjump.tasks import Behaviour, behaviour_class
from locustjump.tasks.ceiling import CEILING
from locustjump.tasks.composed import Composed, Successive
from locustjump.tasks.getup import GetUp
from locustjump.tasks.kick import Kick
from locustjump.tasks.monolithic import Monolithic
from locustjump.tasks.return_legs import ReturnLegs

_REPORTERS: dict[type[Behaviour], Reporter] = {}


def register_reporter(cls: type[Behaviour], reporter: Reporter) -> None:
    """Show behaviour class ``cls`` (and its subclasses without a reporter of
    their own) with ``reporter``."""
    if not (isinstance(cls, type) and issubclass(cls, Behaviour)):
        raise TypeError(f"{cls!r} is not a Behaviour subclass")
    _REPORTERS[cls] = reporter


def reporter_of(beh: Behaviour | type[Behaviour] | str) -> Reporter:
    """The reporter of a behaviour (an object, a class or a registered name)."""
    cls = behaviour_class(beh) if isinstance(beh, str) else beh
    if not isinstance(cls, type):
        cls = type(cls)
    for base in cls.__mro__:
        if base in _REPORTERS:
            return _REPORTERS[base]
    return _DEFAULT


_DEFAULT = Reporter()
for _cls, _reporter in (
    (Kick, KickReporter()),
    (GetUp, GetUpReporter()),
    (ReturnLegs, ReturnLegsReporter()),
    (Successive, SuccessiveReporter()),
    (Composed, ComposedReporter()),
    (Monolithic, MonolithicReporter()),
    *((c, CeilingReporter()) for c in CEILING),
):
    register_reporter(_cls, _reporter)

__all__ = [
    "Claim",
    "Episodes",
    "Reporter",
    "fmt",
    "register_reporter",
    "reporter_of",
    "yes",
]
