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
Publishing a finished study). ``--update-file`` writes those lines into the
study file itself (replacing each shipped arm's ``path``/``paths`` line;
nothing else in the file changes), and ``--carry ARCHIVE`` packs the runs
still training, checkpoints included, into a ``.tar.gz`` to continue them
elsewhere (``tar xzf ARCHIVE --skip-old-files`` there, from the same
directory; refused while a process trains one of them).

Everything is checked before anything is written: every run must have its
configuration's generations, and a run already shipped must be the same run
(the same ``best.npz`` and ``metrics.csv``); otherwise one line names what is
wrong and the script exits 2. Each run is copied into a temporary directory
beside its destination and renamed, so no half-copied run is left behind.
"""

import argparse
import filecmp
import re
import shutil
import sys
import tarfile
import tempfile
from pathlib import Path

from locustjump import rundir
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


def paths_lines(
    study_file: str, to: Path, prefix: str, coming: frozenset[Path] = frozenset()
) -> list[str]:
    """The ``[arms.NAME]`` header and ``paths`` line of each arm with shipped
    runs: every seed whose run is under ``to``, shipped before or about to be
    (``coming``: their destinations)."""
    study = load_study(study_file)
    shipped: dict[str, dict[int, Path]] = {}
    for arm, seed in study.runs():
        run = arm.run_dir(seed)
        if not run.resolve().is_relative_to(to.resolve()):
            run = to / f"{prefix}-{arm.name}-s{seed}"
        if run.is_dir() or run in coming:
            shipped.setdefault(arm.name, {})[seed] = run
    return [
        f"[arms.{name}]\npaths = {{ "
        + ", ".join(f'"{s}" = "{d}"' for s, d in seeds.items())
        + " }"
        for name, seeds in shipped.items()
    ]


def updated(text: str, lines: list[str]) -> str:
    """The study file's ``text`` with each arm's ``path``/``paths`` line
    replaced by its line in ``lines`` (``[arms.NAME]`` then the key line),
    placed right below the arm's header; everything else as it was."""
    for line in lines:
        head, key = line.split("\n")
        at = re.search(rf"^{re.escape(head)}[ \t]*(#.*)?\n", text, re.M)
        if at is None:
            raise UserError(f"no {head} table in the study file: write it by hand")
        start = at.end()
        nxt = re.search(r"^\[", text[start:], re.M)
        end = start + nxt.start() if nxt else len(text)
        body = re.sub(r"^paths? *=.*\n?", "", text[start:end], flags=re.M)
        text = text[:start] + key + "\n" + body + text[end:]
    return text


def update(study_file: str, lines: list[str]) -> str:
    """The study file's new text with ``lines`` written in, once it has loaded
    as a study (``UserError`` otherwise)."""
    path = Path(study_file)
    text = updated(path.read_text(), lines)
    with tempfile.TemporaryDirectory() as tmp:
        check = Path(tmp) / path.name
        check.write_text(text)
        load_study(check)
    return text


def to_carry(study_file: str, to: Path) -> list[Path]:
    """The run directories of the study that are started, unfinished and not
    under ``to``; ``UserError`` naming a run another process trains."""
    out = []
    for arm, seed in load_study(study_file).runs():
        d = arm.run_dir(seed)
        if d.resolve().is_relative_to(to.resolve()) or not rundir.is_run(d):
            continue
        if generations_done(d) == arm.base.generations:
            continue
        who = rundir.in_use(d)
        if who:
            raise UserError(f"{d}: {who} trains it; stop the study's workers first")
        out.append(d)
    return out


def carry(runs: list[Path], archive: Path) -> None:
    """Pack ``runs`` (every file, checkpoints included) into ``archive``,
    written whole or not at all."""
    archive.parent.mkdir(parents=True, exist_ok=True)
    with rundir.atomic_path(archive) as tmp, tarfile.open(tmp, "w:gz") as tf:
        for d in runs:
            tf.add(d)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("study", help="the study file (.toml)")
    p.add_argument("--to", type=Path, default=Path("results/study"),
                   help="where shipped runs live (default: results/study)")  # fmt: skip
    p.add_argument("--prefix", required=True,
                   help="names the runs PREFIX-ARM-s<seed>")  # fmt: skip
    p.add_argument("--finished", action="store_true",
                   help="ship the finished runs of a study still training")  # fmt: skip
    p.add_argument("--update-file", action="store_true",
                   help="write the path(s) lines into the study file")  # fmt: skip
    p.add_argument("--carry", type=Path, metavar="ARCHIVE",
                   help="pack the unfinished runs into ARCHIVE (.tar.gz)")  # fmt: skip
    args = p.parse_args(argv)
    try:
        if args.carry and args.carry.suffixes[-2:] != [".tar", ".gz"]:
            raise UserError(f"--carry {args.carry}: name a .tar.gz file")
        pairs = plan(args.study, args.to, args.prefix, args.finished)
        runs = to_carry(args.study, args.to) if args.carry else []
        if args.finished:
            coming = frozenset(dest for _, dest in pairs)
            lines = paths_lines(args.study, args.to, args.prefix, coming)
        else:
            lines = path_lines(args.study, args.to, args.prefix)
        text = update(args.study, lines) if args.update_file else None
    except UserError as e:
        print(f"ship_study: {e}", file=sys.stderr)
        return 2
    ship(pairs)
    if text is not None:
        rundir.atomic_write_text(Path(args.study), text)
        print(f"shipped {len(pairs)} runs to {args.to}; {args.study} names them")
    else:
        print(f"shipped {len(pairs)} runs to {args.to}; the study file's arms:")
        print("\n".join(lines))
    if args.carry:
        carry(runs, args.carry)
        print(f"packed {len(runs)} unfinished runs into {args.carry}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
