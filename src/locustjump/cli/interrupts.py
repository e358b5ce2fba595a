"""Ctrl-C and SIGTERM from the first line of the command line to its exit.

:func:`install` makes both raise ``KeyboardInterrupt`` (SIGTERM stops as
Ctrl-C does) and records that one came: a ``KeyboardInterrupt`` raised
inside C code can come out as another exception (MuJoCo's extension, while
it initialises, turns it into ``ImportError: initialization failed``), and
:func:`received` tells the command line that it was an interrupt all the
same. Once the command has ended (:func:`finished`), a signal no longer
interrupts anything: during the interpreter's exit it would have killed the
process without a word (SIGTERM) or printed a traceback (Ctrl-C); now it
says in one line that the command had ended and exits at once with the
command's status (its files are complete by then). The program's last exit
handler ignores both signals: in the last steps of its exit Python puts back
their default actions, which end a process without a word.
"""

from __future__ import annotations

import atexit
import os
import signal
from collections.abc import Callable
from types import FrameType

#: the signals that stop a command
SIGNALS = (signal.SIGINT, signal.SIGTERM)

_received: list[int] = []
_status: list[int] = []  # the command's exit status, once it has ended
_Handler = Callable[[int, FrameType | None], object] | int | None
_previous: dict[int, _Handler] = {}


def _handler(signum: int, frame: FrameType | None) -> None:
    if _status:
        os.write(
            2,
            b"locustjump: signal received while exiting; the command had ended "
            + f"(exit status {_status[0]})\n".encode(),
        )
        os._exit(_status[0])
    _received.append(signum)
    raise KeyboardInterrupt


def _block() -> None:
    # ignored, not blocked: a mask is the main thread's only, and a signal
    # another thread takes would end the process by its default action
    for s in _previous:
        signal.signal(s, signal.SIG_IGN)


def install(*, program: bool = False) -> None:
    """Handle :data:`SIGNALS` as above, until :func:`restore` (a signal the
    process was started ignoring, as a shell's background job ignores
    Ctrl-C, stays ignored); ``program``: this process is the command line,
    and from its last exit handler on, both are ignored."""
    _received.clear()
    _status.clear()
    for s in SIGNALS:
        if signal.getsignal(s) is not signal.SIG_IGN:
            _previous[s] = signal.signal(s, _handler)
    if program:
        atexit.unregister(_block)
        atexit.register(_block)  # the first registered runs last


def received() -> bool:
    """Whether a signal came since :func:`install`."""
    return bool(_received)


def finished(status: int) -> None:
    """The command has ended with ``status``: a signal now only ends the exit,
    with that status."""
    _status[:] = [status]


def restore() -> None:
    """The handlers before :func:`install` (for a caller that goes on)."""
    for s, handler in _previous.items():
        signal.signal(s, handler)
    _previous.clear()
    _status.clear()
