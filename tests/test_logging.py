"""Diagnostics go through ``logging``: the library layers log (and print
nothing, warn nothing); the command line shows progress on stdout and
warnings on stderr, MuJoCo's own messages only with ``--debug``."""

import ast
import logging
import shutil
from pathlib import Path

import pytest

from locustjump.cli import console

SRC = Path(__file__).resolve().parent.parent / "src" / "locustjump"


def _calls(tree: ast.AST) -> set[str]:
    """Names of what ``tree`` calls: ``print``, ``warnings.warn``, ..."""
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            f = node.func
            if isinstance(f, ast.Name):
                found.add(f.id)
            elif isinstance(f, ast.Attribute) and isinstance(f.value, ast.Name):
                found.add(f"{f.value.id}.{f.attr}")
    return found


def test_the_library_layers_neither_print_nor_warn():
    bad = {}
    for path in sorted(SRC.rglob("*.py")):
        rel = path.relative_to(SRC).as_posix()
        if rel.startswith("cli/"):
            continue  # the command line's output is its own
        calls = _calls(ast.parse(path.read_text())) & {"print", "warnings.warn"}
        if calls:
            bad[rel] = sorted(calls)
    assert not bad, f"log through logging.getLogger(__name__) instead: {bad}"


@pytest.fixture
def cli_logging():
    """The command line's logging, undone afterwards."""
    logger, mujoco = logging.getLogger("locustjump"), logging.getLogger(console.MUJOCO)
    before = (list(logger.handlers), logger.level, mujoco.level)
    yield
    logger.handlers[:] = before[0]
    logger.setLevel(before[1])
    mujoco.setLevel(before[2])


def test_the_command_line_shows_progress_on_stdout_and_warnings_on_stderr(
    cli_logging, capsys
):
    console.configure()
    console.configure()  # once, however often
    logging.getLogger("locustjump.runs.reproduce").info("[kick] training")
    logging.getLogger("locustjump.sim.engine.callback").warning("layout differs")
    logging.getLogger("locustjump.runs.reproduce").debug("detail")
    logging.getLogger(console.MUJOCO).info("MuJoCo: Nan in QACC")
    out, err = capsys.readouterr()
    assert out == "[kick] training\n"
    assert err == "locustjump: warning: layout differs\n"
    console.configure(debug=True)
    logging.getLogger("locustjump.runs.reproduce").debug("detail")
    logging.getLogger(console.MUJOCO).info("MuJoCo: Nan in QACC")
    assert capsys.readouterr().out == "detail\nMuJoCo: Nan in QACC\n"


def test_a_skipped_video_is_a_warning_of_the_library(
    shipped, tmp_path, monkeypatch, caplog
):
    # without a log callback of the caller's, the library's logger says it
    from locustjump import opengl
    from locustjump.runs.reproduce import render_videos

    monkeypatch.setattr(opengl, "PROBLEM", "no GL here")
    d = shutil.copytree(shipped, tmp_path / "r")
    (d / "kick" / "video.mp4").unlink()
    with caplog.at_level(logging.INFO, logger="locustjump"):
        assert render_videos(d) == []
    [record] = caplog.records
    assert record.name == "locustjump.runs.reproduce"
    assert record.levelno == logging.WARNING
    assert record.getMessage() == "videos skipped: cannot render offscreen: no GL here"
