"""``locustjump`` command line: thin wrappers over the library.

Every error a user can cause ends in one line on stderr and exit status 2;
Ctrl-C (or SIGTERM) ends with status 130 and a line saying how to continue,
also while the command is still loading; anything unexpected (a bug) ends in
one line naming the command and the log file that holds its traceback, exit
status 1 (``--debug``: the traceback on stderr). See
:mod:`locustjump.cli.dispatch`.
"""

from __future__ import annotations

import signal
import sys
from collections.abc import Sequence

from locustjump.cli import console


def _interrupt(signum, frame) -> None:
    raise KeyboardInterrupt


#: Ctrl-Cs that landed inside a callback from C (Numba's compiler calls
#: llvmlite's object cache through ctypes), where Python can only report them
_swallowed: list[BaseException] = []


def _unraisable(info) -> None:
    if isinstance(info.exc_value, KeyboardInterrupt):
        _swallowed.append(info.exc_value)  # seen after the loading, below
        return
    sys.__unraisablehook__(info)


def main(argv: Sequence[str] | None = None) -> int:
    # before the library loads: what it logs while loading is shown too
    console.configure(debug="--debug" in (sys.argv[1:] if argv is None else argv))
    previous = signal.signal(signal.SIGTERM, _interrupt)  # stop as on Ctrl-C
    hook, sys.unraisablehook = sys.unraisablehook, _unraisable
    try:
        # imported on call, not at the top: loading MuJoCo, Numba and
        # Matplotlib takes a second or more, and a Ctrl-C meanwhile must end
        # like any other, in one line, not in a traceback
        from locustjump.cli.dispatch import dispatch

        if _swallowed:
            raise KeyboardInterrupt
        return dispatch(argv)
    except KeyboardInterrupt:  # before the command began
        print("locustjump: interrupted (nothing was written)", file=sys.stderr)
        return 130
    finally:
        signal.signal(signal.SIGTERM, previous)
        sys.unraisablehook = hook


if __name__ == "__main__":
    sys.exit(main())
