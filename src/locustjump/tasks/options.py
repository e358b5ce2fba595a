"""A behaviour's settings beyond the paper (``[options]`` of a run's
``config.toml``): :func:`option` declares a field of a behaviour's ``Options``
dataclass that training offers by name, with its help and range, and
:class:`CommonOptions` holds those every behaviour takes. Importable from
:mod:`~.base` too, beside the ``Behaviour`` whose ``Options`` they are."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

from locustjump.ranges import Range, SettingError, SettingTypeError, SettingValueError

#: the finest physics a fitness may also be scored at (substeps a control step)
MAX_SCORE_SUBSTEPS = 48
#: each of ``score_substeps``
SCORE_SUBSTEPS = Range(1, MAX_SCORE_SUBSTEPS, integer=True)

#: the metadata key of a behaviour's option that training offers by name
OPTION_HELP = "help"


def option(default: Any, help: str, metavar: str, valid: Range | None = None) -> Any:
    """A field of a behaviour's ``Options`` that training offers by name (the
    command line as ``--NAME``, dashes for underscores): ``help`` says what
    it is and its default, ``metavar`` what its value looks like; its type is
    the default's (an int, a float, a str, or a tuple of ints); the
    ``Options`` class checks its value (``ValueError``). ``valid``: the range
    of a number (of each number of a tuple), declared here for the parser and
    its help; the ``Options`` class checks a number's with ``check_settings``
    (metadata ``range``), a tuple's itself (metadata ``each``)."""
    ok = isinstance(default, int | float | str) and not isinstance(default, bool)
    if not (ok or _ints(default)):
        raise TypeError(
            f"an option's default is an int, a float, a str or a tuple of ints, "
            f"not {default!r}"
        )
    meta: dict[str, Any] = {OPTION_HELP: help, "metavar": metavar}
    if valid is not None:
        meta["each" if isinstance(default, tuple) else "range"] = valid
    return dataclasses.field(default=default, metadata=meta)


def _ints(value: Any) -> bool:
    return isinstance(value, tuple) and all(
        isinstance(v, int) and not isinstance(v, bool) for v in value
    )


def option_fields(options: type) -> tuple[dataclasses.Field[Any], ...]:
    """The fields of ``Options`` class ``options`` declared with :func:`option`."""
    return tuple(f for f in dataclasses.fields(options) if OPTION_HELP in f.metadata)


@dataclass(frozen=True)
class CommonOptions:
    """Settings beyond the paper that every behaviour takes (``[options]``)."""

    #: also score every genome with the physics at these substeps a control
    #: step; its fitness is then the worst over them and the model's own (a
    #: controller that only works at one resolution of the physics scores low)
    score_substeps: tuple[int, ...] = option(
        (),
        "beyond the paper: also score every genome with the physics at these "
        "substeps a control step; its fitness is the worst of all resolutions "
        "(default: the model's substeps only)",
        "S,S",
        SCORE_SUBSTEPS,
    )

    def __post_init__(self) -> None:
        given = self.score_substeps
        what = f"distinct integers each in {SCORE_SUBSTEPS.interval()}"
        if isinstance(given, str | bytes) or not isinstance(given, tuple | list):
            raise SettingTypeError("score_substeps", what, given)
        try:
            substeps = tuple(SCORE_SUBSTEPS.check("score_substeps", s) for s in given)
        except SettingError as e:
            raise type(e)("score_substeps", what, list(given)) from None
        if len(set(substeps)) != len(substeps):
            raise SettingValueError("score_substeps", what, list(given))
        object.__setattr__(self, "score_substeps", substeps)
