"""The one exception the command line turns into a one-line message.

A library layer names the *settings* an error is about, never how the command
line spells them: ``setting_ref("out")`` in a message reads ``out`` in
``str(error)`` (the Python API's name) and ``--out`` where the command line
prints it, which maps each setting to its option
(:meth:`UserError.render`).
"""

from __future__ import annotations

import re
from collections.abc import Callable

#: a setting named in a message: ``⟦name⟧`` or ``⟦name=value⟧``
_SETTING = re.compile(r"⟦([a-z][a-z0-9_]*)(?:=([^⟧]*))?⟧")


def setting_ref(name: str, value: bool | None = None) -> str:
    """Setting ``name`` as a message names it; ``value``: the setting turned
    on or off (``force`` on: ``force=True`` in Python, ``--force`` on the
    command line)."""
    if not re.fullmatch(r"[a-z][a-z0-9_]*", name):
        raise ValueError(f"setting names are lower-case identifiers, got {name!r}")
    return f"⟦{name}⟧" if value is None else f"⟦{name}={bool(value)}⟧"


def _keyword(name: str, value: str | None) -> str:
    return name if value is None else f"{name}={value}"


class UserError(Exception):
    """Bad input from the user: the CLI prints it on one line and exits 2.

    Its message may name settings with :func:`setting_ref`; :attr:`settings`
    lists them, :attr:`setting` is the first (the one at fault)."""

    @property
    def message(self) -> str:
        """The message with its settings still marked (for a ``UserError``
        that wraps this one)."""
        return str(self.args[0]) if self.args else ""

    def render(self, spell: Callable[[str, bool | None], str] | None = None) -> str:
        """The message, each setting named by ``spell(name, value)`` (``value``
        ``True``/``False`` for a setting turned on/off, else ``None``);
        default: as Python names it (``out``, ``force=True``)."""
        text = self.message
        if spell is None:
            return _SETTING.sub(lambda m: _keyword(m[1], m[2]), text)
        on = {None: None, "True": True, "False": False}
        return _SETTING.sub(lambda m: spell(m[1], on[m[2]]), text)

    def __str__(self) -> str:
        return self.render()

    @property
    def settings(self) -> tuple[str, ...]:
        """The settings the message names, in order."""
        return tuple(m[1] for m in _SETTING.finditer(self.message))

    @property
    def setting(self) -> str | None:
        """The setting at fault (the first named), if any."""
        return next(iter(self.settings), None)
