"""Options are the command line's: the library layers name settings
(``setting_ref``), the command line prints them as its options. No string
below ``cli/`` spells an option, but for the few listed here, each a command
line by design (and each still an option of ours)."""

import ast
import re
from pathlib import Path

import pytest

from locustjump.cli import main
from locustjump.cli.flags import options_by_setting, speller
from locustjump.cli.parser import build_parser
from locustjump.errors import UserError, setting_ref
from locustjump.rundir import frozen_setting
from locustjump.tasks import behaviour_class, behaviour_names

SRC = Path(__file__).resolve().parent.parent / "src" / "locustjump"
#: an option as a string spells it (``--out``, ``--{name}``), not ``---`` or a
#: word's dash
FLAG = re.compile(r"(?<![\w-])--[a-z{][a-z0-9-]*")

#: strings outside cli/ that spell options, and why: each a command line the
#: user reads and runs, quoted whole
ALLOWED = {
    "runs/reproduction.py": "Reproduction.command(): the command line that makes "
    "and continues a reproduction, recorded in reproduce.toml as the shipped "
    "ones hold it (make demo runs it; tests/test_demo.py)",
    "present/results.py": "results.md tells its reader the commands to rerun "
    "(`--no-monolithic`, `--budget paper`, `replay DIR --out OUT`) and reads "
    "whether the recorded command left the baseline out",
    "rundir/run.py": "the comment at the top of every config.toml ('pass it "
    "with --config'), as every shipped run's holds it",
    "sim/engine/ray_backend.py": "Ray's own command, `ray start --head`",
}
#: options of other programs named in those strings
FOREIGN = {"--head"}


def _docstrings(tree: ast.AST) -> set[int]:
    """ids of the docstring nodes (documentation, not what a user is shown)."""
    found = set()
    for node in ast.walk(tree):
        if isinstance(
            node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef
        ):
            body = node.body
            if body and isinstance(body[0], ast.Expr):
                if isinstance(body[0].value, ast.Constant):
                    found.add(id(body[0].value))
    return found


def _spelled() -> dict[str, set[str]]:
    """Options spelled by string constants (f-strings' parts too) of every
    module outside cli/, by file."""
    found: dict[str, set[str]] = {}
    for path in sorted(SRC.rglob("*.py")):
        rel = path.relative_to(SRC).as_posix()
        if rel.startswith("cli/"):
            continue
        tree = ast.parse(path.read_text(), rel)
        skip = _docstrings(tree)
        texts = []
        for node in ast.walk(tree):
            if isinstance(node, ast.JoinedStr):  # an f-string: its parts joined
                skip.update(id(v) for v in node.values)
                texts.append("".join(v.value if isinstance(v, ast.Constant)
                                     else "{x}" for v in node.values))  # fmt: skip
        for node in ast.walk(tree):
            if (
                isinstance(node, ast.Constant)
                and isinstance(node.value, str)
                and id(node) not in skip
            ):
                texts.append(node.value)
        for text in texts:
            for flag in FLAG.findall(text):
                found.setdefault(rel, set()).add(flag)
    return found


def test_no_option_is_spelled_outside_the_command_line():
    spelled = _spelled()
    unlisted = {f: sorted(v) for f, v in spelled.items() if f not in ALLOWED}
    assert not unlisted, f"name the setting (setting_ref), not the option: {unlisted}"
    assert set(ALLOWED) <= set(spelled), "an allowance no longer needed"


def test_the_options_quoted_below_cli_are_ours():
    # a renamed option fails here rather than in a user's results.md
    ours = set(options_by_setting(build_parser()).values())
    quoted = set().union(*_spelled().values()) - FOREIGN
    assert "--no-monolithic" in quoted  # results.md's, found
    assert quoted <= ours, sorted(quoted - ours)


def _named_settings() -> set[tuple[str, bool | None]]:
    """Every ``setting_ref("name"[, value])`` with literal arguments in src/."""
    found = set()
    for path in SRC.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if (
                isinstance(node, ast.Call)
                and getattr(node.func, "id", None) == "setting_ref"
                and node.args
                and isinstance(node.args[0], ast.Constant)
            ):
                value = node.args[1].value if len(node.args) > 1 else None
                found.add((node.args[0].value, value))
    return found


def test_every_setting_the_library_names_is_an_option():
    options = options_by_setting(build_parser())
    named = _named_settings()
    assert len(named) >= 15  # the walk finds them (17 today)
    for name, value in named:
        key = f"no_{name}" if value is False else name
        assert key in options, (name, value)
    # the runs a behaviour builds on, named through frozen_setting
    for b in behaviour_names():
        for r in behaviour_class(b).requires:
            assert frozen_setting(r) in options, r
    # and those named through a variable (outputs.py's, the sweep's)
    assert {"out", "figure", "step_deg", "from_deg", "to_deg"} <= set(options)


def test_a_message_names_settings_in_python_and_options_on_the_command_line():
    e = UserError(
        f"{setting_ref('out')} runs/x: not empty (use {setting_ref('force', True)}; "
        f"{setting_ref('monolithic', False)} leaves the baseline out)"
    )
    assert e.setting == "out" and e.settings == ("out", "force", "monolithic")
    assert str(e) == (
        "out runs/x: not empty (use force=True; monolithic=False leaves the "
        "baseline out)"
    )
    assert e.render(speller(build_parser())) == (
        "--out runs/x: not empty (use --force; --no-monolithic leaves the baseline out)"
    )
    with pytest.raises(ValueError, match="lower-case identifiers"):
        setting_ref("--out")


def test_the_command_line_prints_a_library_error_with_its_options(tmp_path, capsys):
    # rundir.outputs names the settings out and force; `model` prints them
    (tmp_path / "m.xml").write_text("x")
    assert main(["model", "--out", str(tmp_path / "m.xml")]) == 2
    err = capsys.readouterr().err
    assert err == (
        f"locustjump: error: --out {tmp_path / 'm.xml'}: file exists (use --force "
        "to overwrite)\n"
    )
    # the library's own message names the settings as Python does
    from locustjump.rundir import prepare_out_file

    with pytest.raises(UserError, match=r"^out .*: file exists \(use force=True to "):
        prepare_out_file(tmp_path / "m.xml")


def test_the_command_a_reproduction_records_is_one_our_parser_reads_back(tmp_path):
    # Reproduction.command() spells options below cli/ (ALLOWED): what it
    # writes must parse to the same reproduction
    import shlex

    from locustjump.cli.resolve import terrains_arg
    from locustjump.runs.reproduction import Reproduction
    from locustjump.sim.scene import Debris, Terrains

    terrains = Terrains(Debris(seed=2), 3)
    rep = Reproduction.open(tmp_path / "r", "demo", (0, 3), optimizer="cma",
                            engine="numpy", many=True, terrains=terrains)  # fmt: skip
    argv = shlex.split(rep.command("ray", monolithic=False))
    assert argv[0] == "locustjump"
    args = build_parser().parse_args(argv[1:])
    assert (args.command, args.budget, args.seeds, args.optimizer, args.engine,
            args.backend, args.no_monolithic, args.out) == (
        "reproduce", "demo", [0, 3], "cma", "numpy", "ray", True, str(rep.out)
    )  # fmt: skip
    assert terrains_arg(args.scene, args.terrain_seed, args.terrains) == terrains
    one = Reproduction.open(tmp_path / "one", "quick", (5,))
    args = build_parser().parse_args(shlex.split(one.command())[1:])
    assert (args.seed, args.budget, args.no_monolithic) == (5, "quick", False)
