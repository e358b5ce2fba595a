"""The README is executable: its Python blocks (the API sections) run as
written, its tour's command runs, and every `locustjump` command line in its
shell recipes is one the command line accepts.

The blocks run in a fresh directory laid out as a fresh clone after
``make demo``: ``results/`` (the shipped runs, read only) and
``demo/reproduce/`` (what ``make demo`` makes: the shipped
``results/demo-seed0``). Hour-long recipes (paper-budget training, a Ray
cluster) are checked by parsing their command lines, not run.
"""

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import locustjump
from locustjump.cli.parser import build_parser

SRC = Path(locustjump.__file__).resolve().parents[1]
ROOT = SRC.parent
README = ROOT / "README.md"
#: the sections whose Python blocks run (with their subsections)
API_SECTIONS = ("Python API",)


def _blocks(language: str) -> list[tuple[str, str]]:
    """(section heading, code) of every fenced block in ``language``."""
    found, heading, section = [], "", ""
    lines = README.read_text().splitlines()
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("## "):
            section = heading = line[3:]
        elif line.startswith("### "):
            heading = f"{section} / {line[4:]}"
        elif line.startswith("```"):
            lang = line[3:].strip()
            end = lines.index("```", i + 1)
            if lang == language:
                found.append((heading, "\n".join(lines[i + 1 : end])))
            i = end
        i += 1
    return found


@pytest.fixture
def fresh_clone(tmp_path):
    """A working directory as a fresh clone looks after ``make demo``."""
    demo = ROOT / "results" / "demo-seed0"
    if not (demo / "reproduce.toml").is_file():
        pytest.skip(f"{demo} not present")
    (tmp_path / "results").symlink_to(ROOT / "results", target_is_directory=True)
    shutil.copytree(demo, tmp_path / "demo" / "reproduce")
    return tmp_path


def _python(code: str, cwd: Path, timeout: float = 600) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(SRC)}
    return subprocess.run([sys.executable, "-c", code], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=timeout)  # fmt: skip


def test_the_python_blocks_run_as_written(fresh_clone):
    """Every Python block of the API sections, each in a fresh namespace, one
    after another (a later block may use the runs an earlier one trained)."""
    from locustjump.present.render import RenderUnavailable, make_renderer
    from locustjump.sim import model as lm

    try:  # the API block renders a video, the Gymnasium one a frame
        make_renderer(lm.load_model(lm.LocustParams()), 32, 24).close()
    except RenderUnavailable as e:
        pytest.skip(f"no offscreen rendering here: {e}")
    pytest.importorskip("gymnasium", reason="extra locustjump[gym] not installed")
    blocks = [(h, c) for h, c in _blocks("python") if h.startswith(API_SECTIONS)]
    assert len(blocks) >= 3, [h for h, _ in blocks]
    runner = "\n".join(
        f"print('--- {heading}', flush=True)\nexec(compile({code!r}, "
        f"{'README: ' + heading!r}, 'exec'), {{'__name__': '__main__'}})"
        for heading, code in blocks
    )
    r = _python(runner, fresh_clone)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    assert (fresh_clone / "runs" / "kick" / "report.html").is_file()
    assert (fresh_clone / "runs" / "composed" / "best.npz").is_file()
    assert (fresh_clone / "kick.gif").is_file() and (fresh_clone / "kick.png").is_file()
    assert (fresh_clone / "runs" / "kick-hc" / "best.npz").is_file()


def test_the_tour_command_runs(fresh_clone):
    """ "To see results at once": the replay of the shipped reproduction."""
    text = README.read_text()
    (command,) = re.findall(r"`\.venv/bin/(locustjump replay[^`]*)`", text)
    argv = shlex.split(command.replace("\n", " "))
    code = f"from locustjump.cli import main; raise SystemExit(main({argv[1:]!r}))"
    r = _python(code, fresh_clone)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    assert (fresh_clone / "replay" / "composed" / "composed.png").is_file()


def _command_lines(code: str):
    """Each `locustjump ...` command of a shell block, continuation lines
    joined, comments and a for loop's variable resolved."""
    code = re.sub(r"\\\n\s*", " ", code)
    for line in code.splitlines():
        line = re.sub(r"\s+#.*$", "", line).replace("$s", "0")
        for part in re.split(r";\s*(?:do|done)?\s*", line):
            part = part.strip()
            if part.startswith("locustjump "):
                yield shlex.split(part)[1:]


def test_every_shell_command_line_is_accepted():
    """The shell recipes outside the synopsis (hours of training, a cluster):
    every `locustjump` line parses, with options that exist."""
    parser = build_parser()
    checked = 0
    for heading, code in _blocks("sh"):
        if heading.startswith(("Command line", "The two commands")):
            continue  # the synopsis (tests/test_cli_help.py) and make/apt-get
        for argv in _command_lines(code):
            try:
                parser.parse_args(argv)
            except SystemExit:
                pytest.fail(f"README ({heading}): locustjump {' '.join(argv)}")
            checked += 1
    assert checked >= 5
    for script in re.findall(r"python (scripts/\S+\.py)", README.read_text()):
        assert (ROOT / script).is_file(), script


def test_the_readme_replays_write_distinct_directories():
    """Each `locustjump replay ... --out DIR` of the README writes its own
    DIR: run one after another as written, none finds the last one's."""
    text = (Path(__file__).resolve().parents[1] / "README.md").read_text()
    outs = re.findall(r"locustjump replay \S+ --out ([^\s`]+)", text)
    assert len(outs) >= 3 and len(set(outs)) == len(outs), outs
