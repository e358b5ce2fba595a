"""The argument parser of ``locustjump``: every command, option and check."""

from __future__ import annotations

import argparse

from locustjump.cli import commands as cmd
from locustjump.cli.argtypes import (
    _finite_float,
    _int_at_least,
    _positive_float,
    _seeds,
    _substeps,
    _terrain_seeds,
    out_path,
)
from locustjump.evo import optimizer_kinds
from locustjump.present.compare import KEYS
from locustjump.present.render import CAMERAS
from locustjump.runs.reproduce import BUDGETS
from locustjump.sim import model as lm
from locustjump.sim.engine.backends import BACKENDS
from locustjump.sim.engine.job import ENGINES
from locustjump.sim.scene import scene_names
from locustjump.tasks import behaviour_names
from locustjump.tasks.rules import DEFAULT_CHANGE_TIME
from locustjump.version import __version__


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (``locustjump: error: ...``), exit 2."""

    def error(self, message: str):  # type: ignore[override]
        self.exit(2, f"locustjump: error: {message}\n")


def _strut_stiffness_arg(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--strut-stiffness",
        type=_positive_float("--strut-stiffness", allow_zero=True),
        default=0.0,
        metavar="NM_PER_RAD",
        help="fore and middle legs on sprung hinges of this stiffness at real "
        "scale, e.g. 2e-4 (default 0: rigid struts, the trained creature)",
    )


def _add_scene(
    p: argparse.ArgumentParser, *, of_run: bool = False, train: bool = False
) -> None:
    """``--scene`` and ``--terrain-seed`` (``train``: also ``--terrains``)."""
    own = "the run's own; " if of_run else ""
    p.add_argument(
        "--scene",
        metavar="NAME|FILE",
        help=f"the world: {' or '.join(scene_names())}, or a TOML file with a "
        f"[scene] table (a run's config.toml is one) for its parameters "
        f"(default: {own}flat, the paper's floor)",
    )
    p.add_argument(
        "--terrain-seed",
        type=_int_at_least("--terrain-seed", 0),
        metavar="N",
        help="the terrain of a seeded scene (debris), apart from the evolution's "
        "--seed (default 0" + (", or the run's first training terrain" if of_run
        else "") + (": training terrains N .. N+K-1" if train else "") + ")",
    )  # fmt: skip
    if train:
        p.add_argument(
            "--terrains",
            type=_int_at_least("--terrains", 1),
            metavar="K",
            help="score every genome on K terrains (seeds from --terrain-seed), "
            'fitness their mean ([scene] aggregate = "min": the worst); '
            "default 1",
        )


def _add_backend(p: argparse.ArgumentParser) -> None:

    p.add_argument(
        "--backend",
        choices=BACKENDS,
        default="threads",
        help="where episodes run (default threads; the result does not depend on it)",
    )
    p.add_argument(
        "--threads",
        type=_int_at_least("--threads", 1),
        help="simulation threads (threads: default all CPUs; ray: per actor, "
        "default 1); the result does not depend on it",
    )
    p.add_argument(
        "--address",
        metavar="HOST:PORT",
        help="ray: the cluster to join ('auto': the one `ray start` made here; "
        "default: a local Ray instance)",
    )
    p.add_argument(
        "--actors",
        type=_int_at_least("--actors", 1),
        help="ray: how many actors (default: the cluster's CPUs / --threads)",
    )


def _add_optimizer(p: argparse.ArgumentParser, default: str | None) -> None:

    p.add_argument(
        "--optimizer",
        choices=optimizer_kinds(),
        default=default,
        help="rcga: the paper's GA (default); cma: CMA-ES (pycma); random: "
        "random search",
    )
    p.add_argument(
        "--engine",
        choices=ENGINES,
        help="how the controllers are computed between physics steps: numba "
        "(compiled, the default for new runs) or numpy (the reference; runs "
        "made before the compiled path); recorded in config.toml",
    )


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
    sub = ap.add_subparsers(dest="command", required=True, parser_class=_Parser)

    p = sub.add_parser("model", help="write the MJCF model of the creature")
    p.add_argument(
        "--scale",
        type=_positive_float("--scale"),
        default=lm.LocustParams().scale,
        help="size over a real locust",
    )
    _strut_stiffness_arg(p)
    _add_scene(p)
    p.add_argument("--out", type=out_path, required=True, help="MJCF file to write")
    p.add_argument("--force", action="store_true", help="overwrite --out")
    p.set_defaults(func=cmd.cmd_model)

    p = sub.add_parser("rules", help="run the rule-based successive jumping (Fig. 5)")
    p.add_argument(
        "--change-time",
        type=_positive_float("--change-time", allow_zero=True),
        default=DEFAULT_CHANGE_TIME,
        metavar="SECONDS",
        help=f"touch time before a kick (default {DEFAULT_CHANGE_TIME})",
    )
    p.add_argument(
        "--steps",
        type=_int_at_least("--steps", 1),
        default=3000,
        help="control steps of 1/120 s (default 3000)",
    )
    _strut_stiffness_arg(p)
    _add_scene(p)
    _add_backend(p)
    p.add_argument("--out", type=out_path, required=True, help="output directory")
    p.add_argument("--force", action="store_true", help="write into a non-empty --out")
    p.set_defaults(func=cmd.cmd_rules)

    p = sub.add_parser(
        "train",
        help="evolve a behaviour into a run directory",
        description=(
            "Evolve a behaviour. DIR receives config.toml, metrics.csv, best.npz, "
            "checkpoint.npz (every generation) and fitness.png."
        ),
    )
    p.add_argument("behaviour", choices=behaviour_names())
    _add_optimizer(p, None)
    p.add_argument(
        "--population", type=_int_at_least("--population", 1), help="default 50"
    )
    p.add_argument(
        "--generations", type=_int_at_least("--generations", 1), help="default 1000"
    )
    p.add_argument("--seed", type=_int_at_least("--seed", 0), help="default 0")
    _add_scene(p, train=True)
    _add_backend(p)
    p.add_argument(
        "--config",
        metavar="FILE",
        help="TOML file of settings (a run's config.toml is one); options override it",
    )
    p.add_argument(
        "--out", type=out_path, required=True, metavar="DIR", help="run directory"
    )
    p.add_argument(
        "--resume",
        action="store_true",
        help="continue the run in DIR (a larger --generations extends it)",
    )
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    for name in cmd.frozen_options():
        p.add_argument(
            f"--{name}",
            dest=cmd.frozen_dest(name),
            metavar="DIR",
            help=f"composed: the {name} run whose best network it switches to",
        )
    p.add_argument(
        "--switch-every",
        type=_int_at_least("--switch-every", 1),
        metavar="STEPS",
        help="composed: control steps between two decisions of the switcher "
        "(default 120, the paper's; beyond the paper, recorded in config.toml)",
    )
    p.add_argument(
        "--score-substeps",
        type=_substeps,
        metavar="S,S",
        help="beyond the paper: also score every genome with the physics at these "
        "substeps a control step; its fitness is the worst of all resolutions",
    )
    p.set_defaults(func=cmd.cmd_train)

    p = sub.add_parser(
        "evaluate",
        help="re-simulate a run's best genome, print its metrics",
        description=(
            "Re-simulate the best genome of run DIR; print its fitness (checked "
            "against the recorded one) and behaviour metrics; write DIR/eval/."
        ),
    )
    p.add_argument("run", metavar="DIR")
    p.add_argument("--json", action="store_true", help="print JSON")
    _add_scene(p, of_run=True)
    p.add_argument(
        "--terrain-seeds",
        type=_terrain_seeds,
        metavar="A-B",
        help="re-score the best genome on these terrains (e.g. 100-119 or "
        "100,105), print each, their mean and the generalisation gap to the "
        "training fitness (terrains it trained on are marked)",
    )
    _add_backend(p)
    p.set_defaults(func=cmd.cmd_evaluate)

    p = sub.add_parser(
        "sweep-getup",
        help="get-up generalisation test over start roll angles",
        description=(
            "Evaluate a getup run's best controller from start states rolled in "
            "--step-deg steps between --from-deg and --to-deg (plus the 5 "
            "training states); write DIR/sweep/sweep.csv and sweep.png."
        ),
    )
    p.add_argument("run", metavar="DIR")
    p.add_argument("--step-deg", type=_finite_float("--step-deg"), default=1.0)
    p.add_argument("--from-deg", type=_finite_float("--from-deg"), default=90.0)
    p.add_argument("--to-deg", type=_finite_float("--to-deg"), default=270.0)
    _add_scene(p, of_run=True)
    _add_backend(p)
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
            "quick: about 8 min on 2 cores (5 of them training); long: about "
            "30 min; paper: population 50 x 1000 generations per stage (about "
            "2 h on 2 cores, plus about 2.5 h for the monolithic baseline)"
        ),
    )
    which = p.add_mutually_exclusive_group()
    which.add_argument("--seed", type=_int_at_least("--seed", 0), default=0)
    which.add_argument(
        "--seeds",
        type=_seeds,
        metavar="LIST",
        help="several seeds, e.g. 0-9 or 0,3,7: DIR/seed-<s>/ each, results "
        "across seeds in DIR/results.md (a rerun may add seeds)",
    )
    _add_optimizer(p, "rcga")
    _add_scene(p, train=True)
    _add_backend(p)
    p.add_argument("--out", type=out_path, required=True, metavar="DIR")
    p.add_argument("--quiet", action="store_true", help="no progress bars")
    p.add_argument(
        "--no-videos",
        action="store_true",
        help="skip the per-stage videos (made when offscreen rendering works)",
    )
    p.add_argument(
        "--no-monolithic",
        action="store_true",
        help="leave out the monolithic baseline (beyond the paper; at the paper's "
        "budget it takes as long as the other stages together); rerun without "
        "this flag to add it",
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
        "--out", type=out_path, required=True, metavar="OUT", help="output directory"
    )
    p.add_argument("--force", action="store_true", help="write into a non-empty OUT")
    _add_scene(p, of_run=True)
    _add_backend(p)
    p.set_defaults(func=cmd.cmd_replay)

    p = sub.add_parser(
        "render",
        help="render a run's best controller (or a rule-based run) to a video",
        description=(
            "Re-simulate the best controller of run DIR (or the rule-based run "
            "of a `locustjump rules` directory) and render it offscreen to an "
            "MP4 or GIF (needs the extra locustjump[video]). Episodes from "
            "several start states play side by side; the composed behaviour "
            "shows its active simple behaviour."
        ),
    )
    p.add_argument("dir", metavar="DIR")
    p.add_argument(
        "--out",
        type=out_path,
        metavar="VIDEO",
        help="a .mp4 or .gif (default DIR/video.mp4)",
    )
    p.add_argument(
        "--fps",
        type=_positive_float("--fps"),
        default=60.0,
        help="frames per second of simulated time, at most 120 (default 60)",
    )
    p.add_argument("--camera", choices=CAMERAS, default=CAMERAS[0])
    p.add_argument("--force", action="store_true", help="overwrite --out")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    _add_scene(p, of_run=True)
    _add_backend(p)
    p.set_defaults(func=cmd.cmd_render)

    p = sub.add_parser(
        "view",
        help="play a run's best controller live in MuJoCo's viewer",
        description=(
            "Open MuJoCo's interactive viewer and run the best controller of run "
            "DIR (or a rule-based run) live, in real time, looping over its start "
            "states. Needs a display."
        ),
    )
    p.add_argument("dir", metavar="DIR")
    p.add_argument(
        "--duration",
        type=_positive_float("--duration"),
        metavar="SECONDS",
        help="close after this many seconds (default: when the window is closed)",
    )
    _add_scene(p, of_run=True)
    p.set_defaults(func=cmd.cmd_view)

    p = sub.add_parser(
        "report",
        help="write DIR/report.html, one self-contained page about a run",
        description=(
            "Write DIR/report.html for a training run or a reproduction: config, "
            "fitness curves, metrics, figures and videos embedded (no network "
            "needed); for a reproduction also the results table against the paper."
        ),
    )
    p.add_argument("dir", metavar="DIR")
    _add_backend(p)
    p.set_defaults(func=cmd.cmd_report)

    p = sub.add_parser(
        "compare",
        help="compare training runs as samples (e.g. optimizers at equal budget)",
        description=(
            "Group run directories by a config key (default the optimizer) and "
            "print per group the best fitness median, quartiles and range, and a "
            "two-sided Mann-Whitney U test against the reference group (needs "
            "SciPy: locustjump[study]); --figure draws the convergence curves "
            "(median and interquartile band against genome evaluations)."
        ),
    )
    p.add_argument("dirs", nargs="+", metavar="DIR", help="training run directories")
    p.add_argument("--by", default="optimizer", metavar="KEY[,KEY]",
                   help=f"group by ({', '.join(KEYS)}, or several joined by "
                   "commas; default optimizer)")  # fmt: skip
    p.add_argument("--reference", help="the group the others are tested against "
                   "(default: the first)")  # fmt: skip
    p.add_argument("--figure", metavar="FILE", help="write the convergence curves")
    p.add_argument("--title", default="", help="the figure's title (default: what "
                   "its lines and bands are)")  # fmt: skip
    p.add_argument("--force", action="store_true", help="overwrite FILE")
    p.set_defaults(func=cmd.cmd_compare)
    return ap
