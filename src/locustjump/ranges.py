"""Every setting's valid range, declared once beside the setting.

A :class:`Range` says what a numeric setting accepts (an integer or a finite
number, its bounds, its unit). A frozen dataclass declares a field's range with
:func:`setting` and checks every declared field with :func:`check_settings` in
its ``__post_init__``; a function's setting (a command's ``steps``, a video's
``fps``) is a module constant beside the function, checked with
:meth:`Range.check`. The command line reads the same ranges for its parser and
its help (:mod:`locustjump.cli.argtypes`), and ``config.toml`` is read through
the dataclasses, so the three never disagree.

A value that does not fit raises a :class:`SettingError` naming the setting:
a ``TypeError`` for the wrong kind of value (a ``float`` where an integer is
expected, a ``bool`` anywhere, as Python's own ``range(1.5)`` does), a
``ValueError`` for one outside the range (NaN, infinite, too small, too
large), as NumPy and SciPy do. Both are also a
:class:`~locustjump.errors.UserError`, which the command line prints on one
line, exit status 2, with the setting's name replaced by its option's.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
import re
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

from locustjump.errors import UserError, setting_ref

#: the largest integer a run records (TOML's integers are 64-bit)
INT64_MAX = 2**63 - 1
#: a setting's name ``setting_ref`` takes (others, ``options['start']``, are
#: named as they are)
_SETTING_NAME = re.compile(r"[a-z][a-z0-9_]*")


class SettingError(UserError):
    """A setting given a value it does not accept. ``name`` is the setting,
    ``expected`` what it accepts (``"an integer in [2, 100000]"``, which may
    name other settings with :func:`~locustjump.errors.setting_ref`) and
    ``value`` what it got. The message names the setting with ``setting_ref``:
    ``population`` in Python, ``--population`` where the command line prints
    it (:meth:`UserError.render`)."""

    def __init__(self, name: str, expected: str, value: Any) -> None:
        self.name, self.expected, self.value = name, expected, value
        named = setting_ref(name) if _SETTING_NAME.fullmatch(name) else name
        super().__init__(f"{named} must be {expected}, got {_shown(value)}")

    def renamed(self, name: str) -> SettingError:
        """The same error of the setting called ``name`` (a caller's name for
        what it passed on)."""
        return type(self)(name, self.expected, self.value)


class SettingTypeError(SettingError, TypeError):
    """A setting given the wrong kind of value (a ``bool``, a ``float`` where
    an integer is expected, text where a number is)."""


class SettingValueError(SettingError, ValueError):
    """A setting given a value of the right kind outside its range."""


def _shown(value: Any) -> str:
    if isinstance(value, bool) or not isinstance(value, numbers.Number):
        text = repr(value)
    else:
        text = str(value)
    return text if len(text) <= 80 else text[:77] + "..."


def _number(x: float) -> str:
    if x == INT64_MAX:
        return "2**63-1"
    if isinstance(x, int):
        return str(x)
    return f"{x:g}"


@dataclass(frozen=True)
class Range:
    """What one numeric setting accepts.

    Attributes:
      lo, hi: the bounds (``None``: none on that side; a number is still
        finite).
      integer: an integer (a Python or NumPy integer, never a ``bool``), else
        any finite real number, returned as ``float``.
      lo_open, hi_open: exclude that bound.
      unit: of the value, for the help (``"s"``, ``"body lengths"``).
      size: a sequence of exactly this many such numbers (returned as a tuple)
        instead of one.
    """

    lo: float | None = None
    hi: float | None = None
    integer: bool = False
    lo_open: bool = False
    hi_open: bool = False
    unit: str = ""
    size: int | None = None

    def interval(self) -> str:
        """The bounds as text: ``[2, 100000]``, ``>= 0``, ``(0, 120]``."""
        if self.lo is not None and self.hi is not None:
            return (
                f"{'(' if self.lo_open else '['}{_number(self.lo)}, "
                f"{_number(self.hi)}{')' if self.hi_open else ']'}"
            )
        if self.lo is not None:
            return f"{'>' if self.lo_open else '>='} {_number(self.lo)}"
        if self.hi is not None:
            return f"{'<' if self.hi_open else '<='} {_number(self.hi)}"
        return ""

    def __str__(self) -> str:
        """What the range accepts, e.g. ``an integer in [2, 100000]``."""
        bounds = self.interval()
        if bounds and bounds[0] in "[(":
            bounds = "in " + bounds
        unit = f" {self.unit}" if self.unit and bounds else ""
        if self.size is not None:
            what = f"{self.size} {'integers' if self.integer else 'finite numbers'}"
            return f"{what}{f' each {bounds}{unit}' if bounds else ''}"
        if self.integer:
            return f"an integer{f' {bounds}{unit}' if bounds else ''}"
        if self.lo is not None and self.hi is not None:
            return f"{bounds}{unit}"
        return f"a finite number{f' {bounds}{unit}' if bounds else ''}"

    def contains(self, v: float) -> bool:
        """Whether the number ``v`` (of the right kind) is in the range."""
        if isinstance(v, float) and not math.isfinite(v):
            return False
        if self.lo is not None and (v <= self.lo if self.lo_open else v < self.lo):
            return False
        return self.hi is None or (v < self.hi if self.hi_open else v <= self.hi)

    def check(self, name: str, value: Any) -> Any:
        """``value`` as this setting holds it (``int``, ``float`` or a tuple of
        them), or a :class:`SettingError` naming ``name``."""
        if self.size is None:
            return self._one(name, value, value)
        if (
            isinstance(value, str | bytes | Mapping)
            or not hasattr(value, "__len__")
            or len(value) != self.size
        ):
            raise SettingTypeError(name, self._typed(), value)
        return tuple(self._one(name, v, value) for v in value)

    def _typed(self) -> str:
        """What it accepts, saying it is a number where ``str`` does not."""
        text = str(self)
        return f"a number {text}" if text.startswith("in ") else text

    def _one(self, name: str, v: Any, whole: Any) -> int | float:
        out: int | float
        if isinstance(v, bool):
            raise SettingTypeError(name, self._typed(), whole)
        if self.integer and isinstance(v, numbers.Integral):
            out = int(v)  # compared exactly, however large
        elif not self.integer and isinstance(v, numbers.Real):
            try:
                out = float(v)
            except OverflowError:  # an integer beyond any float
                raise SettingValueError(name, str(self), whole) from None
        else:
            raise SettingTypeError(name, self._typed(), whole)
        if not self.contains(out):
            raise SettingValueError(name, str(self), whole)
        return out

    def parse(self, name: str, text: str) -> Any:
        """A value given as text (an option's), checked; ``SettingError``
        naming ``name`` (the option) if it is not one; for a sequence (numbers
        separated by commas) the error quotes the text as given."""
        number = int if self.integer else float
        if self.size is None:
            try:
                value = number(text)
            except ValueError:
                raise SettingTypeError(name, str(self), text) from None
            return self.check(name, value)
        try:
            return self.check(name, [number(t) for t in text.split(",")])
        except SettingError as e:
            raise type(e)(name, e.expected, text) from None
        except ValueError:
            raise SettingTypeError(name, str(self), text) from None


@contextmanager
def renamed(names: Mapping[str, str]) -> Iterator[None]:
    """Within: a :class:`SettingError` of a setting in ``names`` is raised as
    that of the setting it maps to (a function's parameter passed on under
    another name)."""
    try:
        yield
    except SettingError as e:
        if e.name in names:
            raise e.renamed(names[e.name]) from None
        raise


def setting(default: Any, valid: Range, **kwargs: Any) -> Any:
    """A dataclass field with default ``default`` whose values ``valid``
    accepts (``check_settings`` checks it); ``kwargs`` go to
    ``dataclasses.field``."""
    return dataclasses.field(default=default, metadata={"range": valid}, **kwargs)


def range_of(cls: Any, name: str) -> Range:
    """The range the dataclass ``cls`` (or an instance) declares for field
    ``name`` (``KeyError`` if it declares none)."""
    for f in dataclasses.fields(cls):
        if f.name == name and "range" in f.metadata:
            valid: Range = f.metadata["range"]
            return valid
    raise KeyError(f"{getattr(cls, '__name__', cls)} declares no range for {name!r}")


def check_settings(obj: Any) -> None:
    """Check every field of the frozen dataclass ``obj`` that declares a range,
    and store each as the range returns it (an ``int`` field's NumPy integer
    as ``int``, a float field's ``int`` as ``float``, a list as a tuple)."""
    for f in dataclasses.fields(obj):
        valid = f.metadata.get("range")
        if valid is not None:
            value = valid.check(f.name, getattr(obj, f.name))
            object.__setattr__(obj, f.name, value)


def check_type(name: str, value: Any, kind: type | tuple[type, ...], what: str) -> Any:
    """``value`` if it is a ``kind`` (a ``bool`` only if ``kind`` is), else a
    :class:`SettingTypeError` naming ``name``, that it must be ``what``."""
    kinds = kind if isinstance(kind, tuple) else (kind,)
    if not isinstance(value, kinds) or (isinstance(value, bool) and bool not in kinds):
        raise SettingTypeError(name, what, value)
    return value


def check_choice(name: str, value: Any, choices: tuple[str, ...]) -> str:
    """``value`` if it is one of the names ``choices``, else a
    :class:`SettingError` naming ``name`` (a ``TypeError`` if it is not text)."""
    what = f"one of {', '.join(choices)}"
    text: str = check_type(name, value, str, what)
    if text not in choices:
        raise SettingValueError(name, what, text)
    return text
