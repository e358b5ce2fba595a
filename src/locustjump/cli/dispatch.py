"""Parse a command line, run its command, and end every failure in one line.

* bad input (``UserError``, an invalid value, an OS error naming its file):
  ``locustjump: error: ...``, exit 2;
* Ctrl-C or SIGTERM: ``locustjump: interrupted (how to continue)``, exit 130;
* anything else is a bug: one line naming the command and a log file with the
  traceback (``locustjump-error.log`` in the directory the command writes,
  else a temporary file), exit 1; ``--debug`` prints the traceback too.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import traceback
from collections.abc import Callable, Sequence
from pathlib import Path

from locustjump import plugins, rundir
from locustjump.cli import interrupts
from locustjump.cli.flags import speller
from locustjump.cli.parser import build_parser
from locustjump.errors import UserError
from locustjump.version import __version__

#: the log of an unexpected error, in the directory the command writes
ERROR_LOG = "locustjump-error.log"
#: the option naming the directory each command writes into
_WRITES_INTO = {"train": "out", "rules": "out", "replay": "out",
                "reproduce": "out", "evaluate": "run", "sweep-getup": "run",
                "report": "dir", "render": "dir"}  # fmt: skip


def _os_error(e: OSError) -> str:
    where = f"{e.filename}: " if e.filename else ""
    return f"{where}{e.strerror or e}"


def _how_to_continue(args: argparse.Namespace | None) -> str:
    """What the interrupted command's user does next."""
    if args is None:
        return "nothing was written"
    if args.command == "train":
        if rundir.is_run(Path(args.out)):
            return "rerun it with --resume to continue"
        return "nothing was written; rerun the same command"
    if args.command == "reproduce":
        return "rerun the same command to continue"
    return "nothing was half-written"


def _log(args: argparse.Namespace | None, argv: Sequence[str]) -> str:
    """Write the current exception's traceback to a log file; its path."""
    text = (
        f"locustjump {__version__}: locustjump {' '.join(argv)}\n"
        + traceback.format_exc()
        + "\n"
    )
    key = _WRITES_INTO.get(getattr(args, "command", None) or "", "")
    d = getattr(args, key, None) if key else None
    if d and Path(d).is_dir():
        try:
            with open(Path(d) / ERROR_LOG, "a") as f:
                f.write(text)
            return str(Path(d) / ERROR_LOG)
        except OSError:
            pass
    try:
        fd, path = tempfile.mkstemp(prefix="locustjump-error-", suffix=".log")
        with os.fdopen(fd, "w") as f:
            f.write(text)
        return path
    except OSError:
        return "nowhere (no writable directory; rerun with --debug)"


def plugin_modules(argv: list[str]) -> tuple[list[str], list[str]]:
    """``--plugin MODULE`` (or ``--plugin=MODULE``), anywhere on the command
    line and as often as needed, taken out of ``argv``: (modules, the rest).
    They are imported before the parser is built, since what they register
    makes its choices (behaviours, optimizers, scenes, options)."""
    modules, rest = [], []
    it = iter(argv)
    for a in it:
        if a == "--plugin":
            module = next(it, None)
            if module is None:
                raise UserError("--plugin: expected a module name (e.g. mypkg.mod)")
            modules.append(module)
        elif a.startswith("--plugin="):
            modules.append(a.removeprefix("--plugin="))
        else:
            rest.append(a)
    return modules, rest


def dispatch(argv: Sequence[str] | None = None) -> int:
    """``locustjump ARGV``: the exit status."""
    argv = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in argv
    argv = [a for a in argv if a != "--debug"]
    args = parser = None
    try:
        modules, argv = plugin_modules(argv)
        for module in modules:
            plugins.load_module(module)
        parser = build_parser()
        # an unknown option before the command: name it (argparse would first
        # complain that the command is missing)
        if (
            argv
            and argv[0].startswith("-")
            and argv[0] not in ("-h", "--help", "--version")
        ):
            parser.error(f"unrecognized arguments: {argv[0]}")
        args = parser.parse_args(argv)
        status: int = args.func(args)
        return status
    except SystemExit:
        raise
    except KeyboardInterrupt:
        print(f"locustjump: interrupted ({_how_to_continue(args)})", file=sys.stderr)
        return 130
    except Exception as e:
        if interrupts.received():  # a Ctrl-C that C code turned into an error
            print(
                f"locustjump: interrupted ({_how_to_continue(args)})", file=sys.stderr
            )
            return 130
        if debug:
            traceback.print_exc()
        if isinstance(e, UserError):  # the settings it names as our options
            print(f"locustjump: error: {_flat(e.render(_spell(parser)))}",
                  file=sys.stderr)  # fmt: skip
        elif isinstance(e, ValueError | ImportError):
            print(f"locustjump: error: {_flat(str(e))}", file=sys.stderr)
        elif isinstance(e, OSError):
            print(f"locustjump: error: {_flat(_os_error(e))}", file=sys.stderr)
        elif isinstance(e, OverflowError | MemoryError):
            print(
                "locustjump: error: a number is too large for this command "
                f"({_flat(str(e))})",
                file=sys.stderr,
            )
        else:
            command = getattr(args, "command", None) or "locustjump"
            print(
                f"locustjump: error: {command} failed unexpectedly "
                f"({type(e).__name__}: {_one_line(e)}); the traceback is in "
                f"{_log(args, argv)} (please report it)",
                file=sys.stderr,
            )
            return 1
        return 2


def _spell(
    parser: argparse.ArgumentParser | None,
) -> Callable[[str, bool | None], str] | None:
    """How the error names a setting: our option for it (the parser is built
    here if the error came before it was)."""
    try:
        return speller(parser if parser is not None else build_parser())
    except Exception:  # a registry a plugin broke: the settings' own names
        return None


def _flat(text: str) -> str:
    """``text`` on one line."""
    return " ".join(line.strip() for line in text.splitlines() if line.strip())


def _one_line(e: BaseException) -> str:
    text = _flat(str(e))
    return text if len(text) <= 200 else text[:197] + "..."
