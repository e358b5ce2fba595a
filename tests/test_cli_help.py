"""``--help`` explains everything: every subcommand has a description, every
argument a help text, every option with a default says it, every behaviour of
``train`` is explained; the synopsis of docs/guide/commands.md names every
option."""

import argparse
import re
from pathlib import Path

from locustjump.cli.parser import build_parser
from locustjump.tasks import behaviour_names

COMMANDS = Path(__file__).resolve().parents[1] / "docs" / "guide" / "commands.md"


def _subparsers(parser: argparse.ArgumentParser):
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            yield from action.choices.items()


def _arguments(parser: argparse.ArgumentParser):
    for action in parser._actions:
        if isinstance(action, argparse._HelpAction | argparse._VersionAction):
            continue
        yield action


def test_every_subcommand_and_argument_is_explained():
    commands = dict(_subparsers(build_parser()))
    assert "model" in commands and "reproduce" in commands
    missing = []
    for name, parser in commands.items():
        if not (parser.description or "").strip():
            missing.append(f"{name}: no description")
        for action in _arguments(parser):
            what = f"{name} {'/'.join(action.option_strings) or action.dest}"
            text = action.help or ""
            if not text.strip() or text == argparse.SUPPRESS:
                missing.append(f"{what}: no help")
            elif action.default not in (None, False) and "default" not in text:
                missing.append(f"{what}: default {action.default!r} not stated")
    assert not missing, "\n".join(missing)


def test_every_behaviour_of_train_is_explained():
    train = dict(_subparsers(build_parser()))["train"]
    for name in behaviour_names():
        assert f"\n  {name}: " in train.epilog


def test_the_synopsis_names_every_option():
    text = COMMANDS.read_text()
    synopsis = text.split("## Synopsis", 1)[1].split("## ", 1)[0]
    # options many commands share, described once below the synopsis
    shared = {"--backend", "--threads", "--address", "--actors", "--help",
              "--scene", "--terrain-seed", "--terrains", "--terrain-seeds"}  # fmt: skip
    assert all(f"`{o}" in text for o in shared - {"--help"}), "shared options"
    missing = []
    for name, parser in _subparsers(build_parser()):
        line = re.search(rf"^locustjump {re.escape(name)}\b.*?(?=^locustjump |\Z)",
                         synopsis, re.M | re.S)  # fmt: skip
        if name == "train":  # train's lines cover every behaviour
            line = re.search(r"^locustjump train \{kick.*?(?=^locustjump [a-su-z])",
                             synopsis, re.M | re.S)  # fmt: skip
        assert line, f"{name} missing from the synopsis"
        for action in _arguments(parser):
            for opt in action.option_strings:
                if opt.startswith("--") and opt not in shared:
                    if opt not in line.group(0):
                        missing.append(f"{name} {opt}")
    assert not missing, "not in the synopsis: " + ", ".join(missing)
