"""Settings as the command line spells them: the option of each.

Library layers name the settings an error is about
(:func:`locustjump.errors.setting_ref`); the command line prints them as its
options, read from its own parser: the option whose destination is the
setting (``out``: ``--out``), its ``--no-`` form for a setting turned off
(``monolithic`` off: ``--no-monolithic``).
"""

from __future__ import annotations

import argparse
from collections.abc import Callable


def options_by_setting(parser: argparse.ArgumentParser) -> dict[str, str]:
    """Every option of ``parser`` and its subcommands, by destination (the
    long spelling)."""
    found: dict[str, str] = {}
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                found.update(options_by_setting(sub))
        else:
            longs = [o for o in action.option_strings if o.startswith("--")]
            if longs and action.dest != "help":
                found.setdefault(action.dest, max(longs, key=len))
    return found


def speller(parser: argparse.ArgumentParser) -> Callable[[str, bool | None], str]:
    """``spell(setting, value)``: the option that gives ``setting`` (turned
    off: its ``--no-`` option), for :meth:`UserError.render`."""
    options = options_by_setting(parser)

    def spell(name: str, value: bool | None = None) -> str:
        if value is False and f"no_{name}" in options:
            return options[f"no_{name}"]
        if name in options:
            return options[name]
        # not an option of this command line (tests/test_flags.py keeps every
        # setting the library names an option): the setting as it is named
        return name if value is None else f"{name}={value}"

    return spell
