"""Property tests: random command lines and random config files never end in a
traceback; only exit 0 or 2, and a command that exits 2 leaves nothing behind.

The simulation itself is replaced by a sentinel: reaching it means every check
passed (what a command then does is tested elsewhere); this keeps each example
to milliseconds.
"""

import atexit
import contextlib
import functools
import io
import os
import shutil
import tempfile
import tomllib
from pathlib import Path
from unittest import mock

import numpy as np
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
              "render", "view", "report"}  # fmt: skip


def _run(argv: list[str], cwd: Path, keep: set[str]) -> int | None:
    """``argv``'s exit status (``None``: it got as far as simulating)."""
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
        return None
    assert code in (0, 2), (argv, code)
    if code == 2:
        left = {p.name for p in cwd.iterdir()} - keep
        assert not left, (argv, left)
    return code


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
    # the library's reading and the CLI's agree: a file load_config refuses
    # (one line) is refused by train (exit 2); one it reads as a kick config
    # trains (or is refused for the memory it would need), and writes back as
    # the same config
    with _sandbox() as d:
        (d / "c.toml").write_bytes(content)
        try:
            cfg = rundir.load_config(d / "c.toml")
        except UserError as e:
            cfg = None
            assert "\n" not in str(e), str(e)
        err = io.StringIO()
        with contextlib.redirect_stderr(err):
            code = _run(["train", "kick", "--config", "c.toml", "--quiet",
                         "--out", "run"], d, {"c.toml"})  # fmt: skip
        if cfg is None or cfg.behaviour != "kick":
            assert code == 2, (content, code)
        else:  # it trains, unless a population too large for this machine
            assert code is None or "of memory; the limit is" in err.getvalue(), (
                content, cfg, err.getvalue())  # fmt: skip
            rundir.write_config(d / "back.toml", cfg)
            assert rundir.load_config(d / "back.toml") == cfg


# --- the files of a run: random and adversarial contents -------------------------

#: what each command reads of a run (``{run}``: the run, ``{rep}``: a
#: reproduction holding it as a stage)
READERS = {
    "resume": ["train", "{beh}", "--resume", "--generations", "9", "--quiet",
               "--out", "{run}"],
    "evaluate": ["evaluate", "{run}", "--json"],
    "report": ["report", "{run}"],
    "replay": ["replay", "{rep}", "--out", "replayed"],
    "compare": ["compare", "{run}", "{run}"],
}  # fmt: skip
RUN_FILES = (rundir.CONFIG, rundir.METRICS, rundir.CHECKPOINT, rundir.BEST, "frozen")


@functools.cache
def _runs() -> dict[str, Path]:
    """A small kick run trained here, and the shipped composed run (its frozen
    genomes in ``simple.npz``, as runs made before config format 2 hold them)."""
    base = Path(tempfile.mkdtemp(prefix="locustjump-fuzz-"))
    atexit.register(shutil.rmtree, base, True)
    kick = base / "kick"
    argv = ["train", "kick", "--population", "4", "--generations", "2", "--seed",
            "1", "--threads", "1", "--quiet", "--out", str(kick)]  # fmt: skip
    assert main(argv) == 0
    runs = {"kick": kick}
    shipped = Path(__file__).resolve().parent.parent / "results" / "quick-seed0"
    if (shipped / "composed" / rundir.CONFIG).is_file():
        composed = base / "composed"
        composed.mkdir()
        for name in (rundir.CONFIG, rundir.METRICS, rundir.CHECKPOINT, rundir.BEST,
                     "simple.npz"):  # fmt: skip
            shutil.copy(shipped / "composed" / name, composed / name)
        runs["composed"] = composed
    return runs


CELLS = st.sampled_from(["nan", "inf", "-inf", "-1", "x", "", "1e400", "3", " 2",
                         "0x10", "1_0", "9" * 30, "\x00", "é"])  # fmt: skip


@st.composite
def _metrics(draw, text: str) -> bytes:
    """``metrics.csv`` ``text`` with rows dropped, repeated, swapped, cells
    replaced, a line cut short, or random bytes."""
    lines = text.splitlines(keepends=True)
    for _ in range(draw(st.integers(1, 3))):
        op = draw(st.sampled_from(["cell", "drop", "repeat", "swap", "cut", "junk"]))
        i = draw(st.integers(0, max(len(lines) - 1, 0)))
        if not lines:
            break
        if op == "cell":
            cells = lines[i].rstrip("\n").split(",")
            cells[draw(st.integers(0, len(cells) - 1))] = draw(CELLS)
            lines[i] = ",".join(cells) + "\n"
        elif op == "drop":
            del lines[i]
        elif op == "repeat":
            lines.insert(i, lines[i])
        elif op == "swap":
            j = draw(st.integers(0, len(lines) - 1))
            lines[i], lines[j] = lines[j], lines[i]
        elif op == "cut":
            lines[i] = lines[i][: draw(st.integers(0, len(lines[i])))]
        else:
            lines.insert(i, draw(st.text(max_size=20)) + "\n")
    if draw(st.booleans()) and not draw(st.booleans()):
        return draw(st.binary(max_size=64))
    return "".join(lines).encode()


ARRAYS = st.one_of(
    st.sampled_from([np.float32, np.int64, np.complex128, np.bool_, np.uint8]).map(
        lambda t: np.ones(3, dtype=t)),
    st.sampled_from([np.array(np.nan), np.array(np.inf), np.array(-1),
                     np.array("kick"), np.array(b"x"), np.zeros((2, 2)),
                     np.zeros(0), np.array([1.0, np.nan]), np.array(10**18),
                     np.array('{"bit_generator": "PCG64"}')]),
)  # fmt: skip


@st.composite
def _npz(draw, path: Path) -> bytes:
    """The ``.npz`` ``path`` with arrays replaced (other dtypes and shapes,
    NaN, a genome's values scaled), dropped or added, or its bytes cut short
    or random."""
    with np.load(path) as z:
        arrays = dict(z)
    how = draw(st.sampled_from(["replace", "replace", "nan", "drop", "add", "cut",
                                "bytes"]))  # fmt: skip
    key = draw(st.sampled_from(sorted(arrays)))
    if how == "replace":
        arrays[key] = draw(ARRAYS)
    elif how == "nan" and arrays[key].dtype.kind == "f" and arrays[key].size:
        a = arrays[key].copy()
        a.flat[draw(st.integers(0, a.size - 1))] = draw(
            st.sampled_from([np.nan, np.inf, -np.inf, 1e308])
        )
        arrays[key] = a
    elif how == "drop":
        del arrays[key]
    elif how == "add":
        arrays[draw(st.text(min_size=1, max_size=5))] = draw(ARRAYS)
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    data = buf.getvalue()
    if how == "cut":
        return data[: draw(st.integers(0, len(data) - 1))]
    if how == "bytes":
        return draw(st.binary(max_size=64))
    return data


def _config(draw, text: str) -> bytes:
    d = tomllib.loads(text)
    how = draw(st.sampled_from(["perturb", "table", "bytes"]))
    if how == "perturb":
        tables = sorted(k for k, v in d.items() if isinstance(v, dict))
        section = draw(st.sampled_from([None, *tables]))
        table = d if section is None else d[section]
        table[draw(st.sampled_from(sorted(table)))] = draw(SCALARS)
        return tomli_w.dumps(d).encode()
    if how == "table":
        return tomli_w.dumps(draw(st.dictionaries(KEYS, TABLES, max_size=6))).encode()
    return draw(st.binary(max_size=64))


@st.composite
def _damaged(draw) -> tuple[str, str, str, bytes]:
    """(run, command, file, new contents)."""
    runs = _runs()
    run = draw(st.sampled_from(sorted(runs)))
    command = draw(st.sampled_from(sorted(READERS)))
    name = draw(st.sampled_from(RUN_FILES))
    path = runs[run] / name if name != "frozen" else runs[run] / "simple.npz"
    if not path.exists():  # a run without frozen genomes: its best genome
        name, path = rundir.BEST, runs[run] / rundir.BEST
    if name == rundir.CONFIG:
        data = _config(draw, path.read_text())
    elif name == rundir.METRICS:
        data = draw(_metrics(path.read_text()))
    else:
        data = draw(_npz(path))
    return run, command, path.name, data


@FAST
@given(_damaged())
def test_damaged_run_files(case):
    run, command, name, data = case
    with _sandbox() as d:
        shutil.copytree(_runs()[run], d / "run")
        (d / "run" / name).write_bytes(data)
        (d / "rep").mkdir()
        (d / "rep" / rundir.MARKER).write_text('budget = "quick"\nseed = 0\n')
        os.symlink(d / "run", d / "rep" / run)
        argv = [a.format(beh=run, run="run", rep="rep") for a in READERS[command]]
        before = _files(d)
        code = _run(argv, d, {"run", "rep"})
        if code is not None or command != "resume":  # only a resumed run writes
            assert _files(d) == before, (argv, code)


def _files(d: Path) -> dict[str, bytes | None]:
    return {
        str(p): p.read_bytes() if p.is_file() else None
        for p in d.rglob("*")
        if not p.is_symlink()
    }
