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
Publishing a finished study). ``--update-file`` writes the lines into the
study file itself (each changed arm's ``paths`` line, and its ``path`` line
when the whole study ships; nothing else, line endings kept), once the
changed file is checked to name every run where it will be. ``--carry
ARCHIVE`` (implies ``--finished``) packs the runs still training,
checkpoints included and each locked while packed, into a ``.tar.gz`` to
continue them elsewhere (``tar xzf ARCHIVE --skip-old-files`` there, from
the same directory; refused while a process trains one of them, or for a
run outside this directory).

Everything is checked before anything is written: every run must have its
configuration's generations, and a run already shipped must be the same run
(the same ``best.npz`` and ``metrics.csv``); otherwise one line names what is
wrong and the script exits 2. Each run is copied into a temporary directory
beside its destination and renamed, so no half-copied run is left behind.
"""

import argparse
import contextlib
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
from locustjump.runs.studyfile import Study, load_study

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


def final_dirs(
    study: Study, to: Path, prefix: str, coming: frozenset[Path]
) -> dict[tuple[str, int], Path]:
    """Where each (arm, seed) run of ``study`` is once the runs ``coming``
    (their destinations) are shipped: a run named under ``to`` stays, a run
    shipped now or before is at its destination, any other where it is."""
    out = {}
    for arm, seed in study.runs():
        run = arm.run_dir(seed)
        if not run.resolve().is_relative_to(to.resolve()):
            dest = to / f"{prefix}-{arm.name}-s{seed}"
            if dest in coming or dest.is_dir():
                run = dest
        out[arm.name, seed] = run
    return out


def naming(
    study: Study, to: Path, prefix: str, final: dict[tuple[str, int], Path],
    template: bool,
) -> dict[str, tuple[str | None, dict[int, Path]]]:  # fmt: skip
    """Per arm whose runs move: its new ``path`` template (``template``: the
    arm's shipped one, ``TO/PREFIX-ARM-s{seed}``, unless it names ``to``
    already; else None, the arm's ``path`` kept) and the seeds its template
    does not name, with their directories (its ``paths``)."""
    out = {}
    for name, arm in study.arms.items():
        runs = {s: d for (a, s), d in final.items() if a == name}
        path = None
        if template and not Path(arm.path).resolve().is_relative_to(to.resolve()):
            path = f"{to}/{prefix}-{name}-s{{seed}}"
        odd = {s: d for s, d in runs.items()
               if d != Path((path or arm.path).format(seed=s))}  # fmt: skip
        if path is not None or any(arm.run_dir(s) != d for s, d in runs.items()):
            out[name] = (path, odd)
    return out


def lines(named: dict[str, tuple[str | None, dict[int, Path]]]) -> list[str]:
    """The ``[arms.NAME]`` header, then the ``path`` and ``paths`` lines."""
    out = []
    for name, (path, odd) in named.items():
        text = [f"[arms.{name}]"]
        if path is not None:
            text.append(f'path = "{path}"')
        if odd:
            text.append(
                "paths = { "
                + ", ".join(f'"{s}" = "{d}"' for s, d in sorted(odd.items()))
                + " }"
            )
        out.append("\n".join(text))
    return out


def updated(text: str, named: dict[str, tuple[str | None, dict[int, Path]]]) -> str:
    """The study file's ``text`` with each named arm's ``paths`` line (and
    ``path`` line, where a template is given) replaced by the new ones, right
    below the arm's ``[arms.NAME]`` header; everything else as it was,
    line endings included."""
    nl = "\r\n" if "\r\n" in text else "\n"
    for (name, (path, _)), new in zip(named.items(), lines(named), strict=True):
        head = rf"^\[arms\.{re.escape(name)}\][ \t]*(#.*)?\r?\n"
        at = re.search(head, text, re.M)
        if at is None:
            raise UserError(
                f"no [arms.{name}] table in the study file: write it by hand"
            )
        start = at.end()
        nxt = re.search(r"^\[", text[start:], re.M)
        end = start + nxt.start() if nxt else len(text)
        keys = "paths?" if path is not None else "paths"
        body = re.sub(rf"^{keys} *=.*\r?\n?", "", text[start:end], flags=re.M)
        added = "".join(line + nl for line in new.split("\n")[1:])
        text = text[:start] + added + body + text[end:]
    return text


def update(study_file: str, final: dict[tuple[str, int], Path], text: str) -> str:
    """``text``, the study file rewritten, once it loads as a study whose
    every run is at its ``final`` directory (``UserError`` otherwise)."""
    path = Path(study_file)
    with tempfile.TemporaryDirectory() as tmp:
        check = Path(tmp) / path.name
        check.write_bytes(text.encode())
        study = load_study(check)
    for arm, seed in study.runs():
        if arm.run_dir(seed) != final[arm.name, seed]:
            raise UserError(
                f"{study_file}: rewritten, it would name {arm.run_dir(seed)} for "
                f"{arm.name} seed {seed}, not {final[arm.name, seed]}: write it by hand"
            )
    return text


def to_carry(study: Study, to: Path, stack: contextlib.ExitStack) -> list[Path]:
    """The run directories of the study that are started, unfinished and not
    under ``to``, each locked (in ``stack``) until they are packed;
    ``UserError`` naming a run another process trains, or one outside this
    directory (its name in the archive would not bring it back here)."""
    here = Path.cwd().resolve()
    out = []
    for arm, seed in study.runs():
        d = arm.run_dir(seed)
        if d.resolve().is_relative_to(to.resolve()) or not rundir.is_run(d):
            continue
        if generations_done(d) == arm.base.generations:
            continue
        if d.is_absolute() or not d.resolve().is_relative_to(here):
            raise UserError(f"{d}: --carry packs runs under this directory only")
        try:
            stack.enter_context(rundir.locked(d))
        except rundir.InUse as e:
            raise UserError(f"{e}; stop the study's workers first") from None
        out.append(d)
    return out


def carry(runs: list[Path], archive: Path) -> None:
    """Pack ``runs`` (every file, checkpoints included, but the figure of its
    learning curve, which the run draws again; relative names) into
    ``archive``, written whole or not at all."""

    def keep(member: tarfile.TarInfo) -> tarfile.TarInfo | None:
        return None if Path(member.name).name == rundir.FITNESS_PNG else member

    archive.parent.mkdir(parents=True, exist_ok=True)
    with rundir.atomic_path(archive) as tmp, tarfile.open(tmp, "w:gz") as tf:
        for d in runs:
            tf.add(d, filter=keep)


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
                   help="pack the unfinished runs into ARCHIVE (.tar.gz); "
                        "implies --finished")  # fmt: skip
    args = p.parse_args(argv)
    finished = args.finished or args.carry is not None
    with contextlib.ExitStack() as stack:
        try:
            if args.carry and args.carry.suffixes[-2:] != [".tar", ".gz"]:
                raise UserError(f"--carry {args.carry}: name a .tar.gz file")
            study = load_study(args.study)
            pairs = plan(args.study, args.to, args.prefix, finished)
            runs = to_carry(study, args.to, stack) if args.carry else []
            coming = frozenset(dest for _, dest in pairs)
            final = final_dirs(study, args.to, args.prefix, coming)
            named = naming(study, args.to, args.prefix, final, not finished)
            text = None
            if args.update_file:
                old = Path(args.study).read_bytes().decode()
                text = update(args.study, final, updated(old, named))
        except UserError as e:
            print(f"ship_study: {e}", file=sys.stderr)
            return 2
        ship(pairs)
        if text is not None:
            rundir.atomic_write_bytes(Path(args.study), text.encode())
            print(f"shipped {len(pairs)} runs to {args.to}; {args.study} names them")
        else:
            print(f"shipped {len(pairs)} runs to {args.to}; the study file's arms:")
            print("\n".join(lines(named)))
        if args.carry:
            carry(runs, args.carry)
            print(f"packed {len(runs)} unfinished runs into {args.carry}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
