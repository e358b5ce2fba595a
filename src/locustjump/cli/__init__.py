"""``locustjump`` command line: thin wrappers over the library.

Every error a user can cause ends in one line on stderr and exit status 2;
Ctrl-C (or SIGTERM) ends with status 130 and a line saying how to continue,
also while the command is still loading; anything unexpected (a bug) ends in
one line naming the command and the log file that holds its traceback, exit
status 1 (``--debug``: the traceback on stderr). See
:mod:`locustjump.cli.dispatch`.
"""

from __future__ import annotations

import contextlib
import sys
from collections.abc import Sequence

from locustjump.cli import console, interrupts

#: Ctrl-Cs that landed inside a callback from C (Numba's compiler calls
#: llvmlite's object cache through ctypes), where Python can only report them
_swallowed: list[BaseException] = []


def _unraisable(info: sys.UnraisableHookArgs) -> None:
    if isinstance(info.exc_value, KeyboardInterrupt):
        _swallowed.append(info.exc_value)  # seen after the loading, below
        return
    sys.__unraisablehook__(info)


def main(argv: Sequence[str] | None = None) -> int:
    """``locustjump ARGV`` (default: the program's arguments): its exit
    status. Called as the program (no ``argv``), a signal after the command
    ended only ends the exit (:mod:`.interrupts`); called with ``argv``, the
    signal handlers are put back on return."""
    program = argv is None
    interrupts.install(program=program)  # SIGTERM stops as Ctrl-C does
    hook, sys.unraisablehook = sys.unraisablehook, _unraisable
    status = 1
    try:
        # before the library loads: what it logs while loading is shown too
        console.configure(debug="--debug" in (sys.argv[1:] if argv is None else argv))
        # imported on call, not at the top: loading MuJoCo, Numba and
        # Matplotlib takes a second or more, and a Ctrl-C meanwhile must end
        # like any other, in one line, not in a traceback
        try:
            from locustjump.cli.dispatch import dispatch
        except Exception:
            if not interrupts.received():
                raise
            # a Ctrl-C inside an extension's initialisation comes out as its
            # ImportError
            raise KeyboardInterrupt from None
        if _swallowed:
            raise KeyboardInterrupt
        status = dispatch(argv)
    except SystemExit as e:  # argparse's errors and --help
        status = e.code if isinstance(e.code, int) else 1
        raise
    except KeyboardInterrupt:  # before the command began
        print("locustjump: interrupted (nothing was written)", file=sys.stderr)
        status = 130
    finally:
        interrupts.finished(status)
        sys.unraisablehook = hook
        if program:  # what it printed is out before the exit begins
            for stream in (sys.stdout, sys.stderr):
                with contextlib.suppress(OSError, ValueError):
                    stream.flush()
        else:
            interrupts.restore()
    return status


if __name__ == "__main__":
    sys.exit(main())
