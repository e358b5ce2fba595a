"""The parsers of the commands that show a finished run: render, view, report
and compare (they train nothing)."""

from __future__ import annotations

import argparse

from locustjump.cli import commands as cmd
from locustjump.cli.argtypes import accepts, out_path, ranged
from locustjump.cli.options import add_backend, add_elite, add_scene
from locustjump.present.compare import KEYS, MARGIN
from locustjump.present.render import CAMERAS, FPS
from locustjump.present.viewer import DURATION


def add_showing_commands(
    sub: argparse._SubParsersAction[argparse.ArgumentParser],
) -> None:
    """Add ``render``, ``view``, ``report`` and ``compare`` to ``sub``."""
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
    p.add_argument(
        "dir", metavar="DIR", help="a training run or a rule-based run directory"
    )
    p.add_argument(
        "--out",
        type=out_path,
        metavar="VIDEO",
        help="a .mp4 or .gif (default DIR/video.mp4)",
    )
    p.add_argument(
        "--fps",
        type=ranged("--fps", FPS),
        default=60.0,
        help=f"frames of simulated time, {accepts(FPS)} (default 60)",
    )
    p.add_argument(
        "--camera",
        choices=CAMERAS,
        default=CAMERAS[0],
        help=f"{CAMERAS[0]}: follows the creature; {CAMERAS[1]}: fixed, shows the "
        f"distance travelled (default {CAMERAS[0]})",
    )
    p.add_argument(
        "--force", action="store_true", help="overwrite --out (default: refuse)"
    )
    p.add_argument(
        "--quiet", action="store_true", help="no progress bar (default: shown)"
    )
    add_elite(p)
    add_scene(p, of_run=True)
    add_backend(p)
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
    p.add_argument(
        "dir", metavar="DIR", help="a training run or a rule-based run directory"
    )
    p.add_argument(
        "--duration",
        type=ranged("--duration", DURATION),
        metavar="SECONDS",
        help=f"close after this long, {accepts(DURATION)} (default: when the "
        "window is closed)",
    )
    add_scene(p, of_run=True)
    p.set_defaults(func=cmd.cmd_view)

    p = sub.add_parser(
        "report",
        help="write DIR/report.html, one self-contained page about a run",
        description=(
            "Write DIR/report.html for a training run or a reproduction: config, "
            "fitness curves, metrics, figures and videos embedded (no network "
            "needed); for a reproduction also the results table against the paper. "
            "Only the page is written: DIR/report.html by default (for a shipped "
            "run under results/: runs/shipped/<same path>/report.html)."
        ),
    )
    p.add_argument(
        "dir", metavar="DIR", help="a training run or a reproduction directory"
    )
    p.add_argument(
        "--out",
        type=out_path,
        metavar="FILE",
        help="the page to write (default: DIR/report.html, rewritten on every "
        "call; a shipped run's: runs/shipped/<path>/report.html)",
    )
    p.add_argument(
        "--force", action="store_true", help="overwrite --out (default: refuse)"
    )
    add_backend(p)
    p.set_defaults(func=cmd.cmd_report)

    p = sub.add_parser(
        "compare",
        help="compare training runs as samples (e.g. optimizers at equal budget)",
        description=(
            "Group run directories by a config key (default the optimizer) and "
            "print a table, a row per group: its runs, evaluations per run, the "
            "best fitness median [q1, q3] and range; then against the reference "
            "group (fitness maximised): the Hodges-Lehmann shift (group minus "
            "reference, the median of the pairwise differences) with its exact "
            "95 % confidence interval, the two-sided Mann-Whitney p, and a "
            "verdict that follows the interval ('A better than B' where it "
            "excludes 0, else 'equivalent within +-M' where the TOST p < 0.05, "
            "else 'no evidence either way'). --margin M adds the TOST p of "
            "equivalence within +-M and the seeds per arm for 80 % power to "
            "detect a shift of M at the observed spread. Needs SciPy "
            "(locustjump[study]). --figure draws the convergence curves (median "
            "and interquartile band against genome evaluations)."
        ),
    )
    p.add_argument("dirs", nargs="+", metavar="DIR", help="training run directories")
    p.add_argument("--by", default="optimizer", metavar="KEY[,KEY]",
                   help=f"group by ({', '.join(KEYS)}, or several joined by "
                   "commas; default optimizer)")  # fmt: skip
    p.add_argument("--reference", help="the group the others are tested against "
                   "(default: the first)")  # fmt: skip
    p.add_argument("--margin", type=ranged("--margin", MARGIN), metavar="M",
                   help="equivalence margin in fitness units, "
                   f"{accepts(MARGIN)}: adds the TOST p of equivalence "
                   "within +-M and the seeds per arm for 80 %% power against "
                   "a shift of M (default: none)")  # fmt: skip
    p.add_argument("--figure", metavar="FILE", help="write the convergence curves "
                   "to FILE (default: no figure)")  # fmt: skip
    p.add_argument("--title", default="", help="the figure's title (default: what "
                   "its lines and bands are)")  # fmt: skip
    p.add_argument("--total-budget", action="store_true",
                   help="count the evaluations of the frozen runs a run builds on "
                   "(a composed run's simple behaviours: found where its "
                   "frozen.npz says, or beside it), so that composed and "
                   "monolithic runs compare at the budget each spent in "
                   "all")  # fmt: skip
    p.add_argument("--force", action="store_true",
                   help="overwrite FILE (default: refuse)")  # fmt: skip
    p.set_defaults(func=cmd.cmd_compare)
