"""Where the library's log records go when ``locustjump`` runs them.

The library layers log progress (INFO) and diagnostics (WARNING) through
``logging`` and configure no handler (a program that imports them decides);
the command line prints a command's progress lines on stdout, as the rest of
its output, and warnings on stderr as ``locustjump: warning: ...``.
MuJoCo's own warnings (``locustjump.mujoco``, at INFO: an unstable episode,
which the engine flags anyway) and DEBUG records are shown with ``--debug``
only.
"""

from __future__ import annotations

import logging
import sys

#: the package's logger: every module's is below it
ROOT = "locustjump"
#: MuJoCo's warnings, as :mod:`locustjump.sim.model` logs them
MUJOCO = "locustjump.mujoco"


class Console(logging.Handler):
    """INFO and below on stdout, WARNING and above on stderr (the streams of
    the moment: a test's captured ones too)."""

    def emit(self, record: logging.LogRecord) -> None:
        try:
            text = self.format(record)
            if record.levelno >= logging.WARNING:
                print(f"locustjump: warning: {text}", file=sys.stderr)
            else:
                print(text, file=sys.stdout)
        except Exception:  # as logging.StreamHandler: never the command's end
            self.handleError(record)


def configure(*, debug: bool = False) -> None:
    """Show the package's records on the console (once, however often
    called): INFO and above, everything with ``debug``."""
    logger = logging.getLogger(ROOT)
    for h in [h for h in logger.handlers if isinstance(h, Console)]:
        logger.removeHandler(h)
    logger.addHandler(Console())
    logger.setLevel(logging.DEBUG if debug else logging.INFO)
    logging.getLogger(MUJOCO).setLevel(logging.NOTSET if debug else logging.WARNING)
