"""The argument parser of ``locustjump``: every command, option and check
(the shared options: options.py; render, view, report, compare: showing.py)."""

from __future__ import annotations

import argparse
from typing import Any, NoReturn

from locustjump.cli import commands as cmd
from locustjump.cli.argtypes import (
    _seeds,
    _terrain_seeds,
    accepts,
    out_path,
    ranged,
)
from locustjump.cli.options import (
    add_backend,
    add_behaviour_options,
    add_elite,
    add_optimizer,
    add_scene,
    behaviours_help,
    strut_stiffness_arg,
)
from locustjump.cli.showing import add_showing_commands
from locustjump.cli.study import add_study_command
from locustjump.evo.base import POPULATION, SEED
from locustjump.ranges import range_of
from locustjump.rundir.config import GENERATIONS
from locustjump.runs.reproduce import BUDGETS
from locustjump.sim import model as lm
from locustjump.sim.engine.job import N_STEPS
from locustjump.tasks import behaviour_names
from locustjump.tasks.getup import ROLL_DEG, STEP_DEG
from locustjump.tasks.rules import CHANGE_TIME, DEFAULT_CHANGE_TIME
from locustjump.version import __version__


class _Formatter(argparse.HelpFormatter):
    """Wraps each line of a description or epilog on its own (a list stays a
    list); argparse's default joins them into one paragraph."""

    def _fill_text(self, text: str, width: int, indent: str) -> str:
        return "\n".join(
            super(_Formatter, self)._fill_text(line, width, indent)
            for line in text.splitlines()
        )


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (``locustjump: error: ...``), exit 2."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        kwargs.setdefault("formatter_class", _Formatter)
        super().__init__(*args, **kwargs)

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"locustjump: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:

    ap = _Parser(
        prog="locustjump",
        description=(
            "Evolve successive jumping of a simulated locust (Umemura et al. 2011)."
        ),
    )
    ap.add_argument("--version", action="version", version=f"locustjump {__version__}")
    ap.add_argument(
        "--debug",
        action="store_true",
        help="on an unexpected error, also print its traceback (anywhere on the "
        "command line)",
    )
    ap.add_argument(
        "--plugin",
        metavar="MODULE",
        help="import MODULE first: the optimizers, behaviours and scenes it "
        "registers are then known (anywhere on the command line, repeatable; "
        "installed plugins' entry points need none: docs/architecture.md, "
        "Plugins)",
    )
    sub: argparse._SubParsersAction[argparse.ArgumentParser] = ap.add_subparsers(
        dest="command", required=True, parser_class=_Parser
    )

    p = sub.add_parser(
        "model",
        help="write the MJCF model of the creature",
        description=(
            "Write the complete MJCF model (the creature in its scene: the flat "
            "floor, or --scene's) that training simulates; stock MuJoCo loads it "
            "(python -m mujoco.viewer --mjcf=FILE)."
        ),
    )
    valid = range_of(lm.LocustParams, "scale")
    p.add_argument(
        "--scale",
        type=ranged("--scale", valid),
        default=lm.LocustParams().scale,
        metavar="FACTOR",
        help=f"size over a real desert locust, a factor {accepts(valid)} "
        f"(default {lm.LocustParams().scale:g})",
    )
    strut_stiffness_arg(p)
    add_scene(p)
    p.add_argument(
        "--out", type=out_path, required=True, metavar="FILE",
        help="the MJCF file to write (required)",
    )  # fmt: skip
    p.add_argument(
        "--force", action="store_true", help="overwrite --out (default: refuse)"
    )
    p.set_defaults(func=cmd.cmd_model)

    p = sub.add_parser(
        "rules",
        help="run the rule-based successive jumping (Fig. 5)",
        description=(
            "Run the paper's rule-based successive jumping (section 2.2) and write "
            "DIR/trajectory.csv (one row per control step), DIR/trajectory.png "
            "and DIR/summary.json (change time, steps, creature, engine, apexes)."
        ),
    )
    p.add_argument(
        "--change-time",
        type=ranged("--change-time", CHANGE_TIME),
        default=DEFAULT_CHANGE_TIME,
        metavar="SECONDS",
        help=f"touch time before a kick, {accepts(CHANGE_TIME)} (default "
        f"{DEFAULT_CHANGE_TIME})",
    )
    p.add_argument(
        "--steps",
        type=ranged("--steps", N_STEPS),
        default=3000,
        metavar="STEPS",
        help=f"episode length, {accepts(N_STEPS)} of 1/120 s (default 3000: 25 s)",
    )
    strut_stiffness_arg(p)
    add_scene(p)
    add_backend(p)
    p.add_argument(
        "--out", type=out_path, required=True, metavar="DIR",
        help="output directory (required)",
    )  # fmt: skip
    p.add_argument(
        "--force",
        action="store_true",
        help="write into a non-empty --out (default: refuse)",
    )
    p.set_defaults(func=cmd.cmd_rules)

    p = sub.add_parser(
        "train",
        help="evolve a behaviour into a run directory",
        description=(
            "Evolve a behaviour. DIR receives config.toml, metrics.csv, best.npz, "
            "checkpoint.npz (every generation) and fitness.png."
        ),
        epilog=behaviours_help(),
    )
    p.add_argument(
        "behaviour",
        choices=behaviour_names(),
        metavar="BEHAVIOUR",
        help="what to evolve: " + ", ".join(behaviour_names()) + " (see below)",
    )
    add_optimizer(p, None)
    p.add_argument(
        "--population",
        type=ranged("--population", POPULATION),
        metavar="N",
        help=f"genomes per generation, {accepts(POPULATION)} (default 50, the paper's)",
    )
    p.add_argument(
        "--generations",
        type=ranged("--generations", GENERATIONS),
        metavar="N",
        help=f"generations to train, {accepts(GENERATIONS)} (default 1000, the "
        "paper's)",
    )
    p.add_argument(
        "--seed",
        type=ranged("--seed", SEED),
        metavar="N",
        help=f"random seed of the optimizer, {accepts(SEED)} (default 0); same "
        "seed, same run",
    )
    add_scene(p, train=True)
    add_backend(p)
    p.add_argument(
        "--config",
        metavar="FILE",
        help="TOML file of settings (a run's config.toml is one); options override "
        "it (default: none, the paper's settings)",
    )
    p.add_argument(
        "--out",
        type=out_path,
        required=True,
        metavar="DIR",
        help="run directory (required; a new run refuses a non-empty one)",
    )
    p.add_argument(
        "--resume",
        action="store_true",
        help="continue the run in DIR (a larger --generations extends it)",
    )
    p.add_argument(
        "--quiet", action="store_true", help="no progress bar (default: shown)"
    )
    for name in cmd.frozen_options():
        p.add_argument(
            f"--{name}",
            dest=cmd.frozen_dest(name),
            metavar="DIR",
            help=f"composed: the {name} run whose best network it switches to "
            "(required for composed)",
        )
    add_behaviour_options(p)
    p.set_defaults(func=cmd.cmd_train)

    p = sub.add_parser(
        "evaluate",
        help="re-simulate a run's best genome, print its metrics",
        description=(
            "Re-simulate the best genome of run DIR; print its fitness (checked "
            "against the recorded one) and behaviour metrics; write trajectories "
            "and figures into DIR/eval/ (for a shipped run under results/: "
            "runs/shipped/<same path>/eval/) or --out."
        ),
    )
    p.add_argument("run", metavar="DIR", help="a training run directory")
    p.add_argument(
        "--json", action="store_true", help="print JSON (default: readable text)"
    )
    p.add_argument(
        "--out",
        type=out_path,
        metavar="OUT",
        help="write the trajectories and figures here (default: DIR/eval, "
        "rewritten on every call; a shipped run's: runs/shipped/<path>/eval)",
    )
    p.add_argument(
        "--force",
        action="store_true",
        help="write into a non-empty --out (default: refuse)",
    )
    add_elite(p)
    add_scene(p, of_run=True)
    p.add_argument(
        "--terrain-seeds",
        type=_terrain_seeds,
        metavar="A-B",
        help="re-score the best genome on these terrains (e.g. 100-119 or "
        "100,105), print each, their mean and the generalisation gap to the "
        "training fitness (terrains it trained on are marked; default: none)",
    )
    add_backend(p)
    p.set_defaults(func=cmd.cmd_evaluate)

    p = sub.add_parser(
        "sweep-getup",
        help="get-up generalisation test over start roll angles",
        description=(
            "Evaluate a getup run's best controller from start states rolled in "
            "--step-deg steps between --from-deg and --to-deg (plus the 5 "
            "training states); write DIR/sweep/sweep.csv and sweep.png (for a "
            "shipped run under results/: runs/shipped/<same path>/sweep/)."
        ),
    )
    p.add_argument("run", metavar="DIR", help="a getup training run directory")
    p.add_argument(
        "--step-deg",
        type=ranged("--step-deg", STEP_DEG),
        default=1.0,
        metavar="DEG",
        help=f"roll angle between two start states, {accepts(STEP_DEG)} (default 1)",
    )
    p.add_argument(
        "--from-deg",
        type=ranged("--from-deg", ROLL_DEG),
        default=90.0,
        metavar="DEG",
        help=f"where the sweep starts: start states lie at the centres of the "
        f"--step-deg bins from here to --to-deg, {accepts(ROLL_DEG)} (default 90: "
        "on its side)",
    )
    p.add_argument(
        "--to-deg",
        type=ranged("--to-deg", ROLL_DEG),
        default=270.0,
        metavar="DEG",
        help=f"where the sweep ends: the whole --step-deg bins that fit before "
        f"it hold start states, {accepts(ROLL_DEG)} (default 270)",
    )
    add_scene(p, of_run=True)
    add_backend(p)
    p.set_defaults(func=cmd.cmd_sweep_getup)

    p = sub.add_parser(
        "reproduce",
        help="run every experiment of the paper in order, write results.md",
        description=(
            "Rule-based baseline, kick, getup (+ sweep), return-legs, composed and "
            "a monolithic baseline, each in DIR/<stage>/; DIR/results.md compares "
            "each claim of the paper with ours. With --seeds, one such reproduction "
            "per seed in DIR/seed-<s>/ and DIR/results.md across seeds (with "
            "--backend ray, every stage of every seed is a task on the cluster). "
            "Rerun the same command to continue after an interruption."
        ),
    )
    p.add_argument(
        "--budget",
        choices=tuple(BUDGETS),
        default="quick",
        help=(
            "quick (the default): population 50 x 30/10/20/30 generations "
            "(kick/getup/return-legs/composed; its composed controller of seed "
            "0 does not jump); demo: 50 x 100/20/60/30 (what `make demo` runs, "
            "with --no-monolithic); long: 50 x 100/20/60/120; paper: 50 x 1000 "
            "per stage, the paper's (the monolithic baseline gets the sum of "
            "the four)"
        ),
    )
    which = p.add_mutually_exclusive_group()
    which.add_argument(  # no default: argparse takes a given default for none
        "--seed",
        type=ranged("--seed", SEED),
        metavar="N",
        help=f"the random seed of every stage, {accepts(SEED)} (default 0)",
    )
    which.add_argument(
        "--seeds",
        type=_seeds,
        metavar="LIST",
        help="several seeds, e.g. 0-9 or 0,3,7: DIR/seed-<s>/ each, results "
        "across seeds in DIR/results.md (a rerun may add seeds)",
    )
    add_optimizer(p, "rcga")
    add_scene(p, train=True)
    add_backend(p)
    p.add_argument(
        "--out",
        type=out_path,
        required=True,
        metavar="DIR",
        help="reproduction directory (required; rerun into it to continue)",
    )
    p.add_argument(
        "--quiet", action="store_true", help="no progress bars (default: shown)"
    )
    p.add_argument(
        "--no-videos",
        action="store_true",
        help="skip the per-stage videos (default: made when offscreen rendering works)",
    )
    p.add_argument(
        "--no-monolithic",
        action="store_true",
        help="leave out the monolithic baseline (beyond the paper; at the paper's "
        "budget it takes as long as the other stages together); rerun without "
        "this flag to add it (default: included)",
    )
    p.set_defaults(func=cmd.cmd_reproduce)

    p = sub.add_parser(
        "replay",
        help="re-simulate a reproduction's best genomes, write figures",
        description=(
            "Re-simulate the best genome of every stage of a reproduction "
            "directory (e.g. the shipped results/), check each fitness against "
            "the recorded one, and write figures and trajectories into OUT."
        ),
    )
    p.add_argument("dir", metavar="DIR", help="a reproduction directory")
    p.add_argument(
        "--out",
        type=out_path,
        required=True,
        metavar="OUT",
        help="output directory (required; DIR itself is never written)",
    )
    p.add_argument(
        "--force",
        action="store_true",
        help="write into a non-empty OUT (default: refuse)",
    )
    add_scene(p, of_run=True)
    add_backend(p)
    p.set_defaults(func=cmd.cmd_replay)
    add_showing_commands(sub)
    add_study_command(sub)
    return ap
