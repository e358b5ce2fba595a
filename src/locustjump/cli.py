"""``locustjump`` command line: thin wrappers over the library."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from locustjump import io
from locustjump import model as lm


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (``locustjump: error: ...``), exit 2."""

    def error(self, message: str):  # type: ignore[override]
        self.exit(2, f"locustjump: error: {message}\n")


def _positive_int(name: str):
    def parse(text: str) -> int:
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be an integer, got {text!r}")
        if v <= 0:
            raise argparse.ArgumentTypeError(f"{name} must be > 0, got {v}")
        return v

    return parse


def _positive_float(name: str, *, allow_zero: bool = False):
    def parse(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be a number, got {text!r}")
        if not (v >= 0 if allow_zero else v > 0) or v != v or v == float("inf"):
            bound = ">= 0" if allow_zero else "> 0"
            raise argparse.ArgumentTypeError(
                f"{name} must be finite and {bound}, got {text}"
            )
        return v

    return parse


def cmd_model(args: argparse.Namespace) -> int:
    out = io.prepare_out_file(args.out, force=args.force)
    p = lm.LocustParams(scale=args.scale)
    io.atomic_write_text(out, lm.to_mjcf(p))
    print(f"wrote {out} (scale {p.scale:g}, body length {p.body_length:.3g} m)")
    return 0


def cmd_rules(args: argparse.Namespace) -> int:
    from locustjump.plots import trajectory_figure
    from locustjump.rules import run_rules

    out = io.prepare_out_dir(args.out, force=args.force)
    run = run_rules(args.change_time, args.steps)
    io.write_trajectory_csv(out / "trajectory.csv", run.qpos, run.obs, run.ctrl)
    trajectory_figure(
        out / "trajectory.png",
        [("rule-based", run.qpos, run.jumps)],
        title=f"Rule-based successive jumping (change time {run.change_time:.3f} s)",
    )
    apexes = ", ".join(f"{j.apex_height:.2f}" for j in run.jumps) or "none"
    print(f"{len(run.jumps)} jumps in {args.steps} steps; apex heights [m]: {apexes}")
    if run.unstable:
        print("warning: the simulation went unstable", file=sys.stderr)
    print(f"wrote {out / 'trajectory.csv'} and {out / 'trajectory.png'}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    from locustjump import __version__
    from locustjump.rules import DEFAULT_CHANGE_TIME

    ap = _Parser(
        prog="locustjump",
        description=(
            "Evolve successive jumping of a simulated locust (Umemura et al. 2011)."
        ),
    )
    ap.add_argument("--version", action="version", version=f"locustjump {__version__}")
    sub = ap.add_subparsers(dest="command", required=True, parser_class=_Parser)

    p = sub.add_parser("model", help="write the MJCF model of the creature")
    p.add_argument(
        "--scale",
        type=_positive_float("--scale"),
        default=lm.LocustParams().scale,
        help="size over a real locust",
    )
    p.add_argument("--out", required=True, help="MJCF file to write")
    p.add_argument("--force", action="store_true", help="overwrite --out")
    p.set_defaults(func=cmd_model)

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
        type=_positive_int("--steps"),
        default=3000,
        help="control steps of 1/120 s (default 3000)",
    )
    p.add_argument("--out", required=True, help="output directory")
    p.add_argument("--force", action="store_true", help="write into a non-empty --out")
    p.set_defaults(func=cmd_rules)
    return ap


def main(argv: Sequence[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except (io.UserError, ValueError) as e:
        print(f"locustjump: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
