"""Before runs trained on another machine count in a study: does that machine
train what this one does? Retrains the first generations of finished runs of
a study and compares their metrics, to the last digit, with the runs'.

    python scripts/cross_check.py STUDY.toml --seed 7 [--generations 1]

For every arm of the study whose run of ``--seed`` is finished (the frozen
runs it builds on included), trains the arm's configuration for
``--generations`` generations (each arm at most its own budget) into a
temporary directory, with the run's own frozen genomes, and compares each
generation's best, mean, spread, evaluations and control steps with the
run's ``metrics.csv``. Prints one line an arm (SAME or DIFFERENT, with both
rows when they differ) and exits 0 only when every arm is the same, 1 when
one differs, 2 on bad input (no such study, seed or finished run).

Run it on the other machine with the finished runs of this one copied there
(docs/studies.md, "On a cluster"); and, the other way, here on runs trained
there. Matching first generations of every behaviour of the study are the
check the issue #45 study's seeds 10-14 passed before they counted.
"""

import argparse
import csv
import sys
import tempfile
from pathlib import Path

from locustjump.errors import UserError
from locustjump.runs.study import RunState, frozen_genomes, states
from locustjump.runs.studyfile import load_study
from locustjump.runs.trainer import train

#: the metrics that must match (wall time and throughput may not)
COLUMNS = ("generation", "best", "mean", "std", "evaluations", "control_steps")


def _rows(path: Path, n: int) -> list[list[str]]:
    with open(path, newline="") as f:
        return [[r[c] for c in COLUMNS] for r in csv.DictReader(f)][:n]


def check(study_file: str, seed: int, generations: int) -> bool:
    """Whether every finished run of ``seed`` retrains the same (printed)."""
    study = load_study(study_file, seeds=str(seed))
    done: list[RunState] = [s for s in states(study) if s.finished]
    if not done:
        raise UserError(f"{study_file}: no finished run of seed {seed}")
    same = True
    with tempfile.TemporaryDirectory(prefix="cross-check-") as tmp:
        for st in done:
            arm = study.arms[st.arm]
            n = min(generations, st.generations)
            out = Path(tmp) / st.arm
            frozen = frozen_genomes(study, arm, seed) if arm.frozen else None
            train(arm.config(seed), out, progress=False, frozen=frozen, stop_after=n)
            here = _rows(out / "metrics.csv", n)
            there = _rows(st.path / "metrics.csv", n)
            ok = here == there
            same &= ok
            print(f"{st.arm}, seed {seed}, {n} generation(s): "
                  + ("SAME" if ok else f"DIFFERENT: here {here}, the run {there}"),
                  flush=True)  # fmt: skip
    return same


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("study")
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--generations", type=int, default=1)
    a = ap.parse_args(argv)
    if a.generations < 1:
        ap.error("--generations must be at least 1")
    try:
        return 0 if check(a.study, a.seed, a.generations) else 1
    except UserError as e:
        print(f"cross_check: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
