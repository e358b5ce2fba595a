"""Property tests: random command lines and random config files never end in a
traceback; only exit 0 or 2, and a command that exits 2 leaves nothing behind.

The simulation itself is replaced by a sentinel: reaching it means every check
passed (what a command then does is tested elsewhere); this keeps each example
to milliseconds.
"""

import contextlib
import os
import tempfile
from pathlib import Path
from unittest import mock

import tomli_w
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from locustjump import rundir
from locustjump.cli import main
from locustjump.errors import UserError


class Simulated(BaseException):
    """The command got as far as simulating (not an Exception: the CLI's
    last-resort handler lets it through)."""


def _simulate(self, job):
    raise Simulated


COMMANDS = ["model", "rules", "train", "evaluate", "sweep-getup", "reproduce",
            "replay", "render", "view", "report"]  # fmt: skip
OPTIONS = ["--out", "--config", "--generations", "--population", "--seed",
           "--threads", "--backend", "--optimizer", "--resume", "--quiet",
           "--force", "--steps", "--change-time", "--scale", "--step-deg",
           "--from-deg", "--to-deg", "--budget", "--fps", "--camera", "--json",
           "--strut-stiffness", "--kick", "--getup", "--return-legs",
           "--duration", "--no-videos", "-h", "--version"]  # fmt: skip
VALUES = ["kick", "getup", "return-legs", "composed", "monolithic", "out",
          "out/sub", "c.toml", "threads", "rcga", "cma", "random", "quick",
          "0", "1", "-1", "3", "1e300", "1e-300", "nan", "inf", "-inf", "1e9",
          "0.5", "x.mp4", "y.gif", "track", "side", ""]  # fmt: skip
TOKENS = st.one_of(
    st.sampled_from(COMMANDS + OPTIONS + VALUES),
    st.text(max_size=8),
)
FAST = settings(
    max_examples=int(os.environ.get("LOCUSTJUMP_FUZZ_EXAMPLES", "120")),
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)


@contextlib.contextmanager
def _sandbox():
    """An empty working directory, and no simulation."""
    here = os.getcwd()
    with tempfile.TemporaryDirectory() as d:
        os.chdir(d)
        try:
            with mock.patch(
                "locustjump.sim.engine.backends.ThreadBackend.run", _simulate
            ):
                yield Path(d)
        finally:
            os.chdir(here)


#: the commands that simulate (any other reaching the engine is a bug)
SIMULATING = {"rules", "train", "evaluate", "sweep-getup", "reproduce", "replay",
              "render", "view"}  # fmt: skip


def _run(argv: list[str], cwd: Path, keep: set[str]) -> None:
    try:
        code = main(argv)
    except SystemExit as e:  # argparse: --help, --version, usage errors
        code = e.code
    except Simulated:
        # every check passed: a command that simulates, having written at most
        # into the directory its --out names (or a rule-based/evaluation dir)
        assert argv[0] in SIMULATING, argv
        outs = {
            Path(argv[i + 1]).parts[0]
            for i, a in enumerate(argv[:-1])
            if a == "--out" and argv[i + 1] and not Path(argv[i + 1]).is_absolute()
        }
        left = {p.name for p in cwd.iterdir()} - keep
        assert left <= outs, (argv, left)
        return
    assert code in (0, 2), (argv, code)
    if code == 2:
        left = {p.name for p in cwd.iterdir()} - keep
        assert not left, (argv, left)


#: commands that pass every check as they are; random options are added
TEMPLATES = [
    ["train", "kick", "--out", "run", "--quiet"],
    ["train", "getup", "--out", "run", "--quiet", "--optimizer", "cma"],
    ["rules", "--out", "r", "--steps", "5"],
    ["model", "--out", "m.xml"],
    ["reproduce", "--out", "rep", "--quiet", "--no-videos"],
]
PAIRS = st.lists(
    st.tuples(st.sampled_from(OPTIONS), st.sampled_from(VALUES) | st.text(max_size=6)),
    max_size=3,
).map(lambda pairs: [t for pair in pairs for t in pair])


@FAST
@given(st.one_of(
    st.lists(TOKENS, max_size=8),
    st.tuples(st.sampled_from(TEMPLATES), PAIRS).map(lambda t: t[0] + t[1]),
    st.tuples(st.sampled_from(COMMANDS), st.lists(TOKENS, max_size=7)).map(
        lambda t: [t[0], *t[1]]
    ),
))  # fmt: skip
def test_random_command_lines(argv):
    with _sandbox() as d:
        _run(argv, d, set())


SCALARS = st.one_of(
    st.integers(min_value=-(2**63), max_value=2**63 - 1),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([1e308, -1e308, 1e-308, 0.0, -0.0, 1e9, 50, 2, 1]),
    st.text(max_size=6),
    st.booleans(),
)
KEYS = st.sampled_from(
    ["behaviour", "seed", "generations", "simple", "frozen_digest", "engine",
     "format", "optimizer", "rcga", "model",
     "kind", "population", "elite", "crossover", "sigma0", "init_scale", "scale",
     "density", "femur_length", "substeps", "solref", "integrator", "hip_range",
     "mutation_rate", "nope"]
) | st.text(min_size=1, max_size=6)  # fmt: skip
TABLES = st.recursive(
    SCALARS | st.lists(SCALARS, max_size=3),
    lambda inner: st.dictionaries(KEYS, inner, max_size=5),
    max_leaves=12,
)


def _perturbed(section_key_value) -> bytes:
    """A valid config with one key set to a random value."""
    from locustjump.rundir.config import TrainConfig

    section, key, value = section_key_value
    d = TrainConfig().to_dict()
    (d if section is None else d[section])[key] = value
    return tomli_w.dumps(d).encode()


PERTURBED = st.one_of(
    st.tuples(st.none(), st.sampled_from(["seed", "generations", "behaviour"]),
              SCALARS),
    st.tuples(st.just("optimizer"), st.sampled_from(
        ["population", "elite", "crossover", "mutation_sigma", "init_scale", "kind",
         "blx_alpha"]), SCALARS),
    st.tuples(st.just("model"), st.sampled_from(
        ["scale", "density", "femur_length", "substeps", "friction", "solref",
         "integrator", "hip_range", "ready_hip", "strut_stiffness"]), SCALARS),
).map(_perturbed)  # fmt: skip


@FAST
@given(st.one_of(
    PERTURBED,
    st.dictionaries(KEYS, TABLES, max_size=6).map(lambda d: tomli_w.dumps(d).encode()),
    st.binary(max_size=64),
))  # fmt: skip
def test_random_config_files(content):
    with _sandbox() as d:
        (d / "c.toml").write_bytes(content)
        try:
            rundir.load_config(d / "c.toml")
        except UserError:
            pass
        _run(["train", "kick", "--config", "c.toml", "--quiet", "--out", "run"], d,
             {"c.toml"})  # fmt: skip
