"""Every option of every command, and every key of ``config.toml``, given
extreme values (0, negatives, the smallest and largest floats, NaN, +-inf,
2**63, empty text, a path given twice): the command either passes its checks
(exit 0, or it reaches the simulation, here a sentinel) or ends in exit 2 with
exactly one line naming the option (or key), having written nothing.

The options are read from the parser itself, so a new option is walked too;
the config keys from the settings dataclasses. A command that gets as far as
simulating stops there (the sentinel): what it then does is tested elsewhere,
and each example takes milliseconds. ``-m slow`` walks every option with every
extreme value.
"""

import argparse
import atexit
import contextlib
import functools
import io
import os
import shutil
import tempfile
from pathlib import Path
from unittest import mock

import pytest
import tomli_w
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from locustjump.cli import main
from locustjump.cli.parser import build_parser
from locustjump.evo import optimizer_kinds, params_class
from locustjump.rundir.config import TrainConfig
from locustjump.sim.scene import Debris, Terrains

ROOT = Path(__file__).resolve().parents[1]
SHIPPED = ROOT / "results" / "quick-seed0"
RUN_FILES = ("config.toml", "metrics.csv", "checkpoint.npz", "best.npz")

#: text values of an option: the extremes the issue names and their kin
EXTREMES = ["0", "-0", "-1", "1", "5e-324", "-5e-324", "1.7976931348623157e+308",
            "-1.7976931348623157e+308", "nan", "inf", "-inf", "1e400",
            str(2**63), str(2**63 - 1), str(-(2**63)), "1.5", "0x10", "", " ",
            "1,1", "TWICE"]  # fmt: skip
#: ``TWICE``: a path the command line already holds (its run, its --out)
TWICE = "TWICE"


class Simulated(BaseException):
    """The command got as far as simulating (not an Exception: the CLI's
    last-resort handler lets it through)."""


def _simulate(*args, **kwargs):
    raise Simulated


#: each command as it passes every check, in a sandbox holding ``kick`` and
#: ``getup`` (copies of shipped runs) and ``study.toml``
TEMPLATES = {
    "model": ["model", "--out", "m.xml"],
    "rules": ["rules", "--out", "r", "--steps", "5"],
    "train": ["train", "kick", "--out", "run", "--quiet"],
    "evaluate": ["evaluate", "kick"],
    "sweep-getup": ["sweep-getup", "getup"],
    "reproduce": ["reproduce", "--out", "rep", "--quiet", "--no-videos"],
    "replay": ["replay", str(SHIPPED), "--out", "replayed"],
    "render": ["render", "kick", "--out", "v.gif", "--quiet"],
    "view": ["view", "kick"],
    "report": ["report", "kick"],
    "compare": ["compare", "kick"],
    "study": ["study", "study.toml", "--status"],
}


def _commands() -> dict[str, argparse.ArgumentParser]:
    for action in build_parser()._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    raise AssertionError("no subcommands")


def _valued_options(parser: argparse.ArgumentParser) -> list[str]:
    """The options of ``parser`` that take a value of their own (not a choice
    among names, which argparse checks)."""
    return [
        max(a.option_strings, key=len)
        for a in parser._actions
        if a.option_strings and a.nargs != 0 and a.choices is None
        and not isinstance(a, argparse._HelpAction | argparse._VersionAction)
    ]  # fmt: skip


COMMANDS = _commands()
OPTIONS = {name: _valued_options(p) for name, p in COMMANDS.items()}


def test_every_command_has_a_template_and_passes_as_it_is():
    assert set(TEMPLATES) == set(COMMANDS), "a new command needs a template here"
    assert sum(map(len, OPTIONS.values())) > 40  # the walk sees the options
    for name, argv in TEMPLATES.items():
        with _sandbox() as d:
            code, _, err = _run(argv, d)
            assert code in (0, "simulated"), (name, code, err)


@functools.cache
def _sources() -> Path:
    """Copies of two shipped runs' files and a study file, made once."""
    if not (SHIPPED / "kick" / "config.toml").is_file():
        pytest.skip(f"{SHIPPED} not present")
    base = Path(tempfile.mkdtemp(prefix="locustjump-ranges-"))
    atexit.register(shutil.rmtree, base, True)
    for run in ("kick", "getup"):
        (base / run).mkdir()
        for name in RUN_FILES:
            shutil.copy(SHIPPED / run / name, base / run / name)
    text = (ROOT / "studies" / "example.toml").read_text()
    (base / "study.toml").write_text(
        text.replace('root = "runs/studies/example"', 'root = "runs"')
    )
    return base


@contextlib.contextmanager
def _sandbox():
    """A working directory holding the sources; no simulation, no viewer."""
    here = os.getcwd()
    with tempfile.TemporaryDirectory() as d:
        shutil.copytree(_sources(), d, dirs_exist_ok=True)
        os.chdir(d)
        try:
            with (
                mock.patch(
                    "locustjump.sim.engine.backends.ThreadBackend.run", _simulate
                ),
                mock.patch("mujoco.viewer.launch_passive", _simulate),
                # the sweep settles its start states before it simulates them
                mock.patch("locustjump.tasks.getup._settled", _simulate),
                mock.patch.dict(os.environ, {"DISPLAY": ":0"}),
            ):
                yield Path(d)
        finally:
            os.chdir(here)


def _files(d: Path) -> dict[str, bytes | None]:
    return {
        str(p.relative_to(d)): p.read_bytes() if p.is_file() else None
        for p in sorted(d.rglob("*"))
    }


def _run(argv: list[str], d: Path) -> tuple[object, str, str]:
    """(exit status or ``"simulated"``, stdout, stderr) of ``argv`` in ``d``."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code: object = main(argv)
        except SystemExit as e:  # argparse
            code = e.code
        except Simulated:
            code = "simulated"
    return code, out.getvalue(), err.getvalue()


def _check(argv: list[str], named: tuple[str, ...]) -> None:
    """``argv`` passes its checks, or it ends in exit 2 with one line naming
    one of ``named`` (the options, or keys, given extreme values) and leaves
    the sandbox as it was."""
    with _sandbox() as d:
        before = _files(d)
        code, out, err = _run(argv, d)
        assert code in (0, 2, "simulated"), (argv, code, err)
        assert "Traceback" not in err, (argv, err)
        if code == 2:
            lines = err.splitlines()
            assert len(lines) == 1 and lines[0].startswith("locustjump: error: "), (
                argv, err)  # fmt: skip
            assert any(n in lines[0] for n in named), (argv, named, err)
            assert _files(d) == before, (argv, err)
        elif code == 0:  # a sane result: said what it did, no error
            assert out.strip() and not err.strip(), (argv, out, err)


def _argv(
    command: str, pairs: list[tuple[str, str]], debris: bool = False
) -> list[str]:
    """The command's template (``debris``: in the debris scene, where it has
    one) with ``(option, value)`` pairs appended; a ``TWICE`` value is a path
    the command line already holds."""
    argv = list(TEMPLATES[command])
    if debris and "--scene" in OPTIONS[command]:  # a scene with terrain seeds
        argv += ["--scene", "debris"]
    paths = [a for i, a in enumerate(argv) if argv[i - 1] == "--out"
             or a in ("kick", "getup", "study.toml", str(SHIPPED))]  # fmt: skip
    for i, (option, value) in enumerate(pairs):
        argv += [option, paths[i % len(paths)] if value == TWICE else value]
    return argv


VALUES = st.one_of(
    st.sampled_from(EXTREMES),
    st.integers().map(str),
    st.floats().map(repr),
    st.text(max_size=6),
)


@st.composite
def _cases(draw) -> tuple[list[str], tuple[str, ...]]:
    command = draw(st.sampled_from(sorted(TEMPLATES)))
    options = OPTIONS[command]
    if not options:
        return list(TEMPLATES[command]), ("",)
    pairs = draw(st.lists(st.tuples(st.sampled_from(options), VALUES),
                          min_size=1, max_size=2))  # fmt: skip
    return _argv(command, pairs, draw(st.booleans())), tuple(o for o, _ in pairs)


#: examples of each property in the default run (about 15 s each on 2 cores);
#: ``-m slow`` walks every option and key with every extreme value
EXAMPLES = int(os.environ.get("LOCUSTJUMP_RANGES_EXAMPLES", "110"))
FAST = settings(
    max_examples=EXAMPLES,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)


@FAST
@given(_cases())
def test_extreme_option_values_pass_or_are_named(case):
    argv, named = case
    _check(argv, named)


@pytest.mark.slow
@pytest.mark.parametrize("command", sorted(TEMPLATES))
def test_every_option_with_every_extreme_value(command):
    for option in OPTIONS[command]:
        for value in EXTREMES:
            for debris in (False, True):
                _check(_argv(command, [(option, value)], debris), (option,))


# --- config.toml: every key of every settings table -------------------------

#: TOML values of a key (TOML has no 2**63 integers, but a file may say so)
TOML_EXTREMES = [0, -1, 1, 5e-324, -5e-324, 1.7976931348623157e308, float("nan"),
                 float("inf"), float("-inf"), 2**63, 2**63 - 1, -(2**63), 1.5, "",
                 True, [], [1.5], "x"]  # fmt: skip


def _configs() -> dict[str, dict]:
    """A valid ``config.toml`` table for each kind of table a run may hold:
    every optimizer's settings (a new one is walked too), a seeded scene, a
    behaviour's options."""
    out = {k: TrainConfig(optimizer=params_class(k)()).to_dict()
           for k in optimizer_kinds()}  # fmt: skip
    out["debris"] = TrainConfig(scene=Terrains(Debris())).to_dict()
    out["composed"] = TrainConfig(behaviour="composed").to_dict()
    return out


def _keys() -> list[tuple[str, str | None, str]]:
    """(config, section or None, key) for every key of every config."""
    out = []
    for name, d in _configs().items():
        for key, value in d.items():
            if isinstance(value, dict):
                out += [(name, key, k) for k in value]
            else:
                out.append((name, None, key))
    return out


KEYS = _keys()


def _config_case(name: str, section: str | None, key: str, value) -> None:
    d = _configs()[name]
    behaviour = d["behaviour"]  # the command's, whatever the file says
    (d if section is None else d[section])[key] = value
    frozen = []
    if behaviour == "composed":  # the runs it builds on, read only
        frozen = [a for r in ("kick", "getup", "return-legs")
                  for a in (f"--{r}", str(SHIPPED / r))]  # fmt: skip
    argv = ["train", behaviour, "--config", "c.toml", "--out", "run", "--quiet",
            *frozen]  # fmt: skip
    with _sandbox() as box:
        (box / "c.toml").write_text(tomli_w.dumps(d))
        before = _files(box)
        code, out, err = _run(argv, box)
        assert code in (2, "simulated"), (key, value, code, err)
        if code == 2:
            lines = err.splitlines()
            assert len(lines) == 1 and key in lines[0], (section, key, value, err)
            assert _files(box) == before, (key, value, err)


@FAST
@given(
    st.sampled_from(KEYS),
    st.one_of(
        st.sampled_from(TOML_EXTREMES), st.integers(-(2**64), 2**64), st.floats()
    ),
)
def test_extreme_config_values_pass_or_are_named(where, value):
    _config_case(*where, value)


@pytest.mark.slow
def test_every_config_key_with_every_extreme_value():
    for where in KEYS:
        for value in TOML_EXTREMES:
            _config_case(*where, value)
