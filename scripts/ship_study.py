"""Ship a finished study's runs into ``results/``: what the table and
``tests/test_study.py`` need, no checkpoints.

    python scripts/ship_study.py STUDY.toml --to results/study --prefix debris

copies every run of the study (each arm, each seed) to
``TO/PREFIX-ARM-s<seed>/``: ``config.toml``, ``metrics.csv``, ``best.npz``,
a composed run's frozen genomes (``frozen.npz``, ``simple.npz`` in older runs)
and a quality-diversity run's archive (``archive.npz``) — what
``locustjump evaluate`` re-simulates. It then prints the ``path = ...`` line
each arm's table in the study file takes so that the study names its shipped
runs. Runs the study already names under ``TO`` are left as they are.

    python scripts/ship_study.py STUDY.toml --prefix debris --finished

ships only the runs that are finished and leaves the others, for a study that
is still training: each arm's ``paths = { "SEED" = "DIR", ... }`` line then
names its shipped seeds, and the study trains the rest where it did (a study
moved to another machine continues from what was shipped; docs/studies.md,
Publishing a finished study).

Everything is checked before anything is written: every run must have its
configuration's generations, and a run already shipped must be the same run
(the same ``best.npz`` and ``metrics.csv``); otherwise one line names what is
wrong and the script exits 2. Each run is copied into a temporary directory
beside its destination and renamed, so no half-copied run is left behind.
"""

import argparse
import filecmp
import shutil
import sys
import tempfile
from pathlib import Path

from locustjump.errors import UserError
from locustjump.runs.study import generations_done
from locustjump.runs.studyfile import load_study

#: the files a shipped run keeps, where the run has them
FILES = ("config.toml", "metrics.csv", "best.npz", "frozen.npz", "simple.npz",
         "archive.npz")  # fmt: skip
#: the files that must match when a run was shipped before
SAME = ("best.npz", "metrics.csv")


def plan(
    study_file: str, to: Path, prefix: str, finished: bool = False
) -> list[tuple[Path, Path]]:
    """(run directory, destination) of every run to copy; ``UserError`` if a
    run is unfinished (skipped instead when ``finished``) or differs from what
    is already shipped there."""
    study = load_study(study_file)
    out = []
    for arm, seed in study.runs():
        src = arm.run_dir(seed)
        if src.resolve().is_relative_to(to.resolve()):
            continue  # the study names it where it is shipped
        want = arm.base.generations
        have = generations_done(src)
        if have != want:
            if finished:
                continue
            raise UserError(
                f"{src}: {have} of {want} generations; only a finished study ships"
            )
        dest = to / f"{prefix}-{arm.name}-s{seed}"
        if dest.exists():
            for f in SAME:
                if not (dest / f).is_file() or not filecmp.cmp(
                    src / f, dest / f, shallow=False
                ):
                    raise UserError(f"{dest} holds another run than {src} ({f})")
            continue
        out.append((src, dest))
    return out


def ship(pairs: list[tuple[Path, Path]]) -> None:
    """Copy each run's kept files into its destination, atomically per run."""
    for src, dest in pairs:
        dest.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{dest.name}.", dir=dest.parent))
        try:
            for f in FILES:
                if (src / f).is_file():
                    shutil.copy2(src / f, tmp / f)
            tmp.rename(dest)
        except BaseException:
            shutil.rmtree(tmp, ignore_errors=True)
            raise


def path_lines(study_file: str, to: Path, prefix: str) -> list[str]:
    """The ``[arms.NAME]`` header and ``path`` line of each arm: where its
    runs are shipped (the arm's own path if it names them under ``to``)."""
    out = []
    for name, arm in load_study(study_file).arms.items():
        path = arm.path
        if not Path(path).resolve().is_relative_to(to.resolve()):
            path = f"{to}/{prefix}-{name}-s{{seed}}"
        out.append(f'[arms.{name}]\npath = "{path}"')
    return out


def paths_lines(study_file: str, to: Path, prefix: str) -> list[str]:
    """The ``[arms.NAME]`` header and ``paths`` line of each arm with shipped
    runs: every seed whose run is under ``to``, shipped before or now."""
    study = load_study(study_file)
    shipped: dict[str, dict[int, Path]] = {}
    for arm, seed in study.runs():
        run = arm.run_dir(seed)
        if not run.resolve().is_relative_to(to.resolve()):
            run = to / f"{prefix}-{arm.name}-s{seed}"
        if run.is_dir():
            shipped.setdefault(arm.name, {})[seed] = run
    return [
        f"[arms.{name}]\npaths = {{ "
        + ", ".join(f'"{s}" = "{d}"' for s, d in seeds.items())
        + " }"
        for name, seeds in shipped.items()
    ]


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("study", help="the study file (.toml)")
    p.add_argument("--to", type=Path, default=Path("results/study"),
                   help="where shipped runs live (default: results/study)")  # fmt: skip
    p.add_argument("--prefix", required=True,
                   help="names the runs PREFIX-ARM-s<seed>")  # fmt: skip
    p.add_argument("--finished", action="store_true",
                   help="ship the finished runs of a study still training")  # fmt: skip
    args = p.parse_args(argv)
    try:
        pairs = plan(args.study, args.to, args.prefix, args.finished)
    except UserError as e:
        print(f"ship_study: {e}", file=sys.stderr)
        return 2
    ship(pairs)
    print(f"shipped {len(pairs)} runs to {args.to}; the study file's arms:")
    lines = paths_lines if args.finished else path_lines
    print("\n".join(lines(args.study, args.to, args.prefix)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
