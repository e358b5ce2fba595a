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


def _interrupt(signum, frame) -> None:
    raise KeyboardInterrupt


def main(argv: Sequence[str] | None = None) -> int:
    previous = signal.signal(signal.SIGTERM, _interrupt)  # stop as on Ctrl-C
    try:
        # imported on call, not at the top: loading MuJoCo, Numba and
        # Matplotlib takes a second or more, and a Ctrl-C meanwhile must end
        # like any other, in one line, not in a traceback
        from locustjump.cli.dispatch import dispatch

        return dispatch(argv)
    except KeyboardInterrupt:  # before the command began
        print("locustjump: interrupted (nothing was written)", file=sys.stderr)
        return 130
    finally:
        signal.signal(signal.SIGTERM, previous)


if __name__ == "__main__":
    sys.exit(main())
