"""Ctrl-C and SIGTERM in one process (``cli/interrupts.py``), piece by
piece: both raise ``KeyboardInterrupt`` and are remembered, an ignored one
stays ignored, after the command's end a signal only ends the exit with its
status, and everything is put back. ``tests/test_hardening.py`` sends real
signals to real commands."""

import signal

import pytest

from locustjump.cli import interrupts


@pytest.fixture(autouse=True)
def clean():
    """Each test starts with Python's default handlers (whatever runs the
    tests may ignore Ctrl-C) and ends with the process's own."""
    before = {s: signal.getsignal(s) for s in interrupts.SIGNALS}
    signal.signal(signal.SIGINT, signal.default_int_handler)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    yield
    interrupts.restore()
    for s, h in before.items():
        signal.signal(s, h)


def test_the_signals_are_ctrl_c_and_sigterm():
    assert interrupts.SIGNALS == (signal.SIGINT, signal.SIGTERM)


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_each_raises_keyboard_interrupt_and_is_remembered(signum):
    interrupts.install()
    assert interrupts.received() is False
    with pytest.raises(KeyboardInterrupt):
        signal.raise_signal(signum)
    assert interrupts.received() is True
    interrupts.install()  # a new command forgets the last one's
    assert interrupts.received() is False


def test_restore_puts_back_the_handlers_before():
    def mine(signum, frame):
        pass

    signal.signal(signal.SIGTERM, mine)
    interrupts.install()
    assert signal.getsignal(signal.SIGTERM) is interrupts._handler
    assert signal.getsignal(signal.SIGINT) is interrupts._handler
    interrupts.restore()
    assert signal.getsignal(signal.SIGTERM) is mine
    assert interrupts._previous == {}


def test_a_signal_ignored_from_the_start_stays_ignored():
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # a shell's background job
    interrupts.install()
    assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    assert signal.getsignal(signal.SIGTERM) is interrupts._handler
    assert list(interrupts._previous) == [signal.SIGTERM]


def test_after_the_end_a_signal_ends_the_exit_with_the_status(monkeypatch):
    said, exits = [], []

    class Exited(Exception):
        pass

    def _exit(status):  # os._exit never returns
        exits.append(status)
        raise Exited

    monkeypatch.setattr(interrupts.os, "write", lambda fd, b: said.append((fd, b)))
    monkeypatch.setattr(interrupts.os, "_exit", _exit)
    interrupts.install()
    interrupts.finished(3)
    with pytest.raises(Exited):  # not KeyboardInterrupt now
        interrupts._handler(signal.SIGTERM, None)
    assert exits == [3] and interrupts.received() is False
    assert said == [
        (
            2,
            b"locustjump: signal received while exiting; the command had ended "
            b"(exit status 3)\n",
        )
    ]
    interrupts.finished(0)
    with pytest.raises(Exited):
        interrupts._handler(signal.SIGINT, None)
    assert exits == [3, 0]
    interrupts.restore()  # the status goes with the handlers
    interrupts.install()
    with pytest.raises(KeyboardInterrupt):
        interrupts._handler(signal.SIGINT, None)


def test_the_program_ignores_both_in_its_last_exit_handler(monkeypatch):
    registered, unregistered = [], []
    monkeypatch.setattr(interrupts.atexit, "register", registered.append)
    monkeypatch.setattr(interrupts.atexit, "unregister", unregistered.append)
    interrupts.install()
    assert registered == []  # a caller that goes on: no exit handler
    interrupts.install(program=True)
    assert registered == [interrupts._block] == unregistered  # once, whatever
    interrupts._block()
    for s in interrupts.SIGNALS:
        assert signal.getsignal(s) is signal.SIG_IGN
