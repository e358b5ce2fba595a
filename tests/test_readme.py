"""The README and the documentation are executable: every command a page
shows runs as written, in a fresh clone after ``make demo``.

Each page's fenced ``sh`` and ``python`` blocks run one after another (a
later block may use what an earlier one made) in a fresh directory laid out
as a fresh clone after ``make demo``: the repository's files, a copy of
``results/`` and ``docs/``, ``demo/reproduce/`` (what ``make demo`` makes:
the shipped ``results/demo-seed0``) and a ``.venv/bin`` whose
``locustjump`` and ``python`` are this interpreter's, on ``PATH`` as after
``. .venv/bin/activate``. Blocks marked ``slow`` (minutes) run under
``pytest -m slow``; blocks marked ``parse`` (hours of training, a cluster,
installing into the environment or the system) are parsed, like every
``locustjump`` command of the prose: each must be one the command line
accepts. How a block is marked: ``tests/docpages.py``.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import shutil
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from docpages import (
    PAGES,
    ROOT,
    Block,
    all_blocks,
    blocks,
    command_lines,
    inline_commands,
    out_dirs,
)
from locustjump.cli.parser import build_parser

#: the repository's files a fresh clone has, read only here
LINKED = ("src", "scripts", "benchmarks", "studies", "tests", "pyproject.toml",
          "Makefile", "mkdocs.yml", "README.md", "CHANGELOG.md")  # fmt: skip
#: what the pages' commands may write into (regenerating a shipped table)
COPIED = ("results", "docs")
TIMEOUT = 1800  # (Seconds) one block
#: what a page's blocks (not marked slow) leave behind, beyond their --out
MADE = {
    "README.md": ("replay-tour/composed/composed.png", "runs/tour-kick/report.html"),
    "docs/getting-started.md": ("replay/composed/composed.png",
                                "runs/first-kick/report.html"),
    "docs/guide/python-api.md": ("runs/kick/report.html", "runs/composed/best.npz",
                                 "kick.gif", "kick.png",
                                 "runs/studies/example/table.md"),
    "docs/guide/optimizers.md": ("runs/kick-hc/best.npz",),
    "docs/guide/scenes.md": ("rubble.xml", "rubble-low.xml",
                             "runs/kick-debris-api/best.npz"),
    "docs/studies.md": ("runs/studies/example",),
}  # fmt: skip


def _runnable(page: Path, slow: bool) -> list[Block]:
    modes = ("run", "slow") if slow else ("run",)
    return [b for b in blocks(page)
            if b.lang in ("sh", "python") and b.mode in modes]  # fmt: skip


def _pages(slow: bool) -> list:
    marks = [pytest.mark.slow] if slow else []
    return [
        pytest.param(p, id=str(p.relative_to(ROOT)), marks=marks)
        for p in PAGES
        if _runnable(p, slow)
        and (not slow or _runnable(p, True) != _runnable(p, False))
    ]


def _fresh_clone(tmp: Path) -> Path:
    demo = ROOT / "results" / "demo-seed0"
    if not (demo / "reproduce.toml").is_file():
        pytest.skip(f"{demo} not present")
    clone = tmp / "clone"
    clone.mkdir()
    for name in LINKED:
        if (ROOT / name).exists():
            (clone / name).symlink_to(ROOT / name)
    for name in COPIED:
        shutil.copytree(ROOT / name, clone / name, symlinks=True)
    shutil.copytree(demo, clone / "demo" / "reproduce")
    venv = clone / ".venv" / "bin"
    venv.mkdir(parents=True)
    # as an editable install: this tree's src/ importable whatever PYTHONPATH
    # a command sets (tests/plugin for a plugin, say)
    sh = f'#!/bin/sh\nexport PYTHONPATH="{ROOT / "src"}${{PYTHONPATH:+:$PYTHONPATH}}"\n'
    scripts = {
        "python": f'{sh}exec "{sys.executable}" "$@"\n',
        "locustjump": f'{sh}exec "{sys.executable}" -m locustjump.cli "$@"\n',
        "activate": f'PATH="{venv}:$PATH"; export PATH\n',
    }
    for name, text in scripts.items():
        (venv / name).write_text(text)
        (venv / name).chmod(stat.S_IRWXU)
    return clone


def _requirements(runnable: list[Block]) -> None:
    """Skip, with the reason, where a page needs what this machine lacks."""
    text = "\n".join(b.code for b in runnable)
    if "render" in text:
        from locustjump.present.render import RenderUnavailable, make_renderer
        from locustjump.sim import model as lm

        try:
            make_renderer(lm.load_model(lm.LocustParams()), 32, 24).close()
        except RenderUnavailable as e:
            pytest.skip(f"no offscreen rendering here: {e}")
    if "gymnasium" in text:
        pytest.importorskip("gymnasium", reason="extra locustjump[gym] not installed")


def _run(block: Block, clone: Path) -> None:
    path = f"{clone / '.venv' / 'bin'}{os.pathsep}{os.environ['PATH']}"
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src"), "PATH": path}
    if block.lang == "sh":
        argv = ["bash", "-e", "-o", "pipefail", "-c", block.code]
    else:
        code = f"exec(compile({block.code!r}, {block.where!r}, 'exec'), {{}})"
        argv = [sys.executable, "-c", code]
    r = subprocess.run(argv, cwd=clone, env=env, capture_output=True, text=True,
                       timeout=TIMEOUT)  # fmt: skip
    assert r.returncode == 0, f"{block.where}\n{r.stdout[-3000:]}\n{r.stderr[-3000:]}"
    printed = r.stdout.splitlines()
    for row in block.table:
        assert row in printed, f"{block.where}: the page's row is not printed: {row}"
    if block.lang == "sh":
        for argv in command_lines(block.code):
            for out in out_dirs(argv):
                assert (clone / out).exists(), f"{block.where}: made no {out}"


def _run_page(page: Path, slow: bool, tmp_path: Path) -> None:
    runnable = _runnable(page, slow)
    _requirements(runnable)
    clone = _fresh_clone(tmp_path)
    for block in runnable:
        _run(block, clone)
    for made in MADE.get(str(page.relative_to(ROOT)), ()):
        assert (clone / made).exists(), f"{page.relative_to(ROOT)} made no {made}"


@pytest.mark.parametrize("page", _pages(slow=False))
def test_every_page_runs_as_written(page, tmp_path):
    """Each page's blocks not marked ``slow`` or ``parse``, in order."""
    _run_page(page, False, tmp_path)


@pytest.mark.parametrize("page", _pages(slow=True))
def test_every_page_runs_as_written_slow(page, tmp_path):
    """Each page with ``slow`` blocks: all its runnable blocks, in order."""
    _run_page(page, True, tmp_path)


def test_the_readme_and_the_guide_have_runnable_blocks():
    """What the fast suite runs, so that the marks cannot hollow it out: the
    README's tour, the getting-started page, the guide's examples."""
    for name in MADE:
        assert _runnable(ROOT / name, False), name
    tour = "\n".join(b.code for b in _runnable(ROOT / "README.md", False))
    for command in ("locustjump replay", "locustjump train", "locustjump report"):
        assert command in tour


def test_every_mark_says_why():
    for lang in ("sh", "python"):
        for b in all_blocks(lang):
            if b.mode != "run":
                assert b.reason, f"{b.where}: '{b.mode}' without a reason"
    printing = [b for b in all_blocks("sh") if b.table]
    assert len(printing) >= 3 and all(b.table for b in printing)


def _commands() -> list[tuple[str, list[str]]]:
    """(where, argv) of every ``locustjump`` command of the blocks and the prose."""
    found = [(b.where, a) for b in all_blocks("sh") for a in command_lines(b.code)]
    for page in PAGES:
        found += [(str(page.relative_to(ROOT)), a) for a in inline_commands(page)]
    return found


def test_every_command_line_is_accepted():
    """Every ``locustjump`` line of every block and every concrete command
    of the prose parses, with options that exist; the scripts they name
    exist."""
    parser = build_parser()
    checked = 0
    for where, argv in _commands():
        try:
            with contextlib.redirect_stdout(io.StringIO()):
                parser.parse_args(argv)
        except SystemExit as e:  # --help and --version exit 0
            assert e.code == 0, f"{where}: locustjump {' '.join(argv)}"
        checked += 1
    assert checked >= 50, checked
    for page in PAGES:
        text = page.read_text()
        for script in set(re.findall(r"\b((?:scripts|benchmarks)/\w+\.py)", text)):
            assert (ROOT / script).is_file(), f"{page.relative_to(ROOT)}: {script}"


def test_every_output_directory_is_distinct():
    """Run one after another as written, no command finds the directory an
    earlier one made: every ``--out`` of the README and the docs is its own
    (continuing or overwriting, ``--resume`` and ``--force``, aside)."""
    seen: dict[str, str] = {}
    for where, argv in _commands():
        for out in out_dirs(argv):
            assert out not in seen, f"--out {out}: {seen.get(out)} and {where}"
            seen[out] = where
    assert len(seen) >= 10, seen
