"""``locustjump study FILE``: a declared grid of runs, trained, shown, tabled."""

from __future__ import annotations

import argparse
import contextlib
import sys

from locustjump import rundir
from locustjump.cli.argtypes import _seeds, out_path
from locustjump.cli.options import add_backend
from locustjump.errors import UserError
from locustjump.runs.study import run_study
from locustjump.runs.study_plan import dry_run, status
from locustjump.runs.study_table import FIGURE, study_table
from locustjump.runs.studyfile import load_study
from locustjump.sim.engine.backends import make_backend


def add_study_command(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add ``study`` to ``sub``."""
    p = sub.add_parser(
        "study",
        help="run a study file: arms x seeds, each an ordinary run directory",
        description=(
            "Train every run a study file declares (named arms x seeds; "
            "docs/studies.md says how to write one), each into its own run "
            "directory; finished runs are kept and stopped ones continue, so a "
            "killed study continues with the same command; started more than "
            "once (here, or on machines sharing its directories), the "
            "processes share its runs. --dry-run prints the "
            "plan and its cost, --status what is done, --table scores every run "
            "and writes the study's table (effect sizes with 95 % intervals)."
        ),
    )
    p.add_argument("file", metavar="FILE.toml", help="the study file")
    what = p.add_mutually_exclusive_group()
    what.add_argument(
        "--dry-run",
        action="store_true",
        help="print the plan: each arm's runs done and to do, the control steps "
        "left and the time at this machine's measured throughput; train nothing",
    )
    what.add_argument(
        "--status", action="store_true", help="print each run's generations done"
    )
    what.add_argument(
        "--table",
        action="store_true",
        help="score every run's best genome as the study's [evaluation] says and "
        "write OUT/table.md, table.json, learning.png and scores.png into the "
        "study's out or --out (the runs must be finished)",
    )
    p.add_argument(
        "--out",
        type=out_path,
        metavar="DIR",
        help="with --table: write the table, its figures and its score cache "
        "into DIR instead of the study's out (e.g. a look at the seeds done "
        "so far, with --seeds); refused if DIR holds anything, unless --force",
    )
    p.add_argument(
        "--force",
        action="store_true",
        help="with --out: write into DIR although it holds files (a table "
        "there before is replaced)",
    )
    p.add_argument(
        "--seeds",
        type=_seeds,
        metavar="SEEDS",
        help="only these of the study's seeds (e.g. 0-2)",
    )
    p.add_argument(
        "--quiet",
        action="store_true",
        help="no progress bars (a line per run is still printed)",
    )
    add_backend(p)
    p.set_defaults(func=cmd_study)


def cmd_study(args: argparse.Namespace) -> int:
    seeds = None if args.seeds is None else ",".join(map(str, args.seeds))
    if args.out is not None and not args.table:
        raise UserError("--out is where --table writes; it needs --table")
    if args.force and args.out is None:
        raise UserError("--force lets --table --out write into a full directory; "
                        "it needs --out")  # fmt: skip
    study = load_study(args.file, seeds)
    out = None
    if args.out is not None:
        out = rundir.check_out_dir(args.out, force=args.force)
    if args.status:
        print(status(study))
        return 0
    backend = make_backend(
        args.backend, threads=args.threads, address=args.address, actors=args.actors
    )
    if args.dry_run:
        print(dry_run(study, backend, args.backend))
        return 0

    def log(line: str) -> None:
        print(line, file=sys.stderr)

    if args.table:
        # --out: made, locked, and removed again if the table fails
        with (
            contextlib.nullcontext(None)
            if out is None
            else rundir.output_dir(out, force=args.force)
        ) as where:
            md, js = study_table(study, backend, log=log, out=where)
        print(rundir.read_text(md), end="")
        print(f"wrote {md}, {js}, {md.parent / FIGURE}")
        return 0
    final = run_study(study, backend=backend, progress=not args.quiet, log=log)
    done = sum(st.finished for st in final)
    print(f"study {study.name}: {done} of {len(final)} runs done under {study.root}; "
          f"the table: locustjump study {args.file} --table")  # fmt: skip
    return 0
