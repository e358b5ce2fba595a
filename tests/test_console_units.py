"""Where the command line shows the library's log records
(``cli/console.py``): progress on stdout, warnings on stderr in one prefixed
line, MuJoCo's and DEBUG records with ``--debug`` only, one handler however
often configured."""

import logging

import pytest

from locustjump.cli import console


@pytest.fixture
def root():
    """The package's logger as configure() leaves it, put back after."""
    logger = logging.getLogger(console.ROOT)
    mujoco = logging.getLogger(console.MUJOCO)
    saved = (logger.handlers[:], logger.level, mujoco.level)
    yield logger
    logger.handlers[:] = saved[0]
    logger.setLevel(saved[1])
    mujoco.setLevel(saved[2])


def test_the_loggers_names():
    assert (console.ROOT, console.MUJOCO) == ("locustjump", "locustjump.mujoco")


def test_progress_on_stdout_warnings_on_stderr(root, capsys):
    console.configure()
    logging.getLogger("locustjump.runs.train").info("generation %d of %d", 3, 10)
    logging.getLogger("locustjump.sim").warning("slow: %s", "debris")
    logging.getLogger("locustjump.sim").error("worse")
    logging.getLogger("locustjump.sim").debug("hidden")
    out, err = capsys.readouterr()
    assert out == "generation 3 of 10\n"
    assert err == "locustjump: warning: slow: debris\nlocustjump: warning: worse\n"


def test_mujocos_warnings_and_debug_with_debug_only(root, capsys):
    console.configure()
    assert root.level == logging.INFO
    assert logging.getLogger(console.MUJOCO).level == logging.WARNING
    logging.getLogger(console.MUJOCO).info("unstable at step 3")
    assert capsys.readouterr().out == ""
    console.configure(debug=True)
    assert root.level == logging.DEBUG
    assert logging.getLogger(console.MUJOCO).level == logging.NOTSET
    logging.getLogger(console.MUJOCO).info("unstable at step 3")
    logging.getLogger("locustjump.sim").debug("shown")
    assert capsys.readouterr().out == "unstable at step 3\nshown\n"


def test_one_console_handler_however_often_configured(root):
    other = logging.NullHandler()
    root.addHandler(other)
    for _ in range(3):
        console.configure()
    mine = [h for h in root.handlers if isinstance(h, console.Console)]
    assert len(mine) == 1 and other in root.handlers  # another's is left alone


def test_a_record_that_cannot_be_formatted_does_not_end_the_command(
    root, capsys, monkeypatch
):
    monkeypatch.setattr(root, "propagate", False)  # not to pytest's handlers
    console.configure()
    errors = []
    handler = next(h for h in root.handlers if isinstance(h, console.Console))
    handler.handleError = errors.append
    logging.getLogger("locustjump.sim").info("%d", "not a number")
    assert len(errors) == 1 and errors[0].msg == "%d"
    assert capsys.readouterr().out == ""
