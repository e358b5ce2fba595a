"""File and directory names of runs and reproductions (see the package doc)."""

from __future__ import annotations

import os
from pathlib import Path

CONFIG = "config.toml"
METRICS = "metrics.csv"
CHECKPOINT = "checkpoint.npz"
BEST = "best.npz"
FITNESS_PNG = "fitness.png"
STOP = "stop.json"  # why the optimizer stopped before the budget, if it did
FROZEN = "frozen.npz"  # the frozen genomes a behaviour builds on
ARCHIVE = "archive.npz"  # a quality-diversity run's elites (rundir.archive)
ARCHIVE_PNG = "archive.png"  # its heatmap: fitness over the descriptor grid
ELITES = "elites"  # directory: evaluate/render of one elite, cell-<i>-<j>/
EVAL = "eval"  # directory
EVAL_METRICS = "metrics.json"  # in EVAL
SWEEP = "sweep"  # directory of a behaviour's extra evaluation
SWEEP_CSV = "sweep.csv"  # in SWEEP
SWEEP_PNG = "sweep.png"  # in SWEEP
RULES_DIR = "rules"  # a reproduction's rule-based baseline
VIDEO = "video.mp4"
REPORT = "report.html"
RULES_SUMMARY = "summary.json"
TRAJECTORY_CSV = "trajectory.csv"
TRAJECTORY_PNG = "trajectory.png"
MARKER = "reproduce.toml"  # what makes a directory a reproduction
SEEDS_MARKER = "seeds.toml"  # ... a reproduction over several seeds
RESULTS = "results.md"
FORMAT = 1  # version of checkpoint.npz / best.npz

#: the columns of every metrics.csv; an optimizer's diagnostics follow them
#: (CMA-ES: sigma, condition), named in the header
METRICS_COLUMNS = (
    "generation",
    "best",
    "mean",
    "std",
    "wall_s",
    "evaluations",
    "control_steps",
    "steps_per_s",
)


# a marker that is there but not a regular file (a directory, a FIFO) still
# marks: reading it then names what it is


def is_run(d: Path) -> bool:
    return os.path.lexists(Path(d) / CONFIG)


#: what a new run writes before its config.toml, and their temporary files
_BEFORE_CONFIG = (FROZEN, CONFIG, METRICS)


def is_unstarted(d: Path) -> bool:
    """Whether directory ``d`` holds no run but what a new run writes before
    its ``config.toml`` (a run stopped then: it can be started again)."""
    d = Path(d)
    if is_run(d):
        return False
    leftovers = {FROZEN}
    for name in _BEFORE_CONFIG:
        stem, dot, suffix = name.partition(".")
        leftovers.add(f".{stem}.tmp{dot}{suffix}")
    return all(p.name in leftovers for p in d.iterdir())


def is_reproduction(d: Path) -> bool:
    return os.path.lexists(Path(d) / MARKER)


def is_multiseed(d: Path) -> bool:
    return os.path.lexists(Path(d) / SEEDS_MARKER)


def seed_dir(d: Path, seed: int) -> Path:
    """Where a reproduction over several seeds keeps seed ``seed``'s."""
    return Path(d) / f"seed-{seed}"


def is_rules_run(d: Path) -> bool:
    d = Path(d)
    return (d / RULES_SUMMARY).is_file() and (d / TRAJECTORY_CSV).is_file()


def elite_dir(run: Path, cell: tuple[int, ...]) -> Path:
    """Where evaluate and render write what they derive from the elite in
    grid cell ``cell`` of run ``run``'s archive (under :func:`derived_dir`)."""
    return derived_dir(run) / ELITES / ("cell-" + "-".join(map(str, cell)))


def eval_metrics_path(run: Path) -> Path:
    return Path(run) / EVAL / EVAL_METRICS


#: The shipped runs: the repository's ``results/``, tracked in git. What the
#: reading commands (evaluate, sweep-getup, report) derive from a run inside
#: it goes to the same path under :data:`SHIPPED_DERIVED` instead (ignored by
#: git, as ``runs/`` is), so that a checkout stays clean.
SHIPPED = Path(__file__).resolve().parents[3] / "results"
SHIPPED_DERIVED = SHIPPED.parent / "runs" / "shipped"


def derived_dir(d: Path) -> Path:
    """Where evaluate, sweep-getup and report write what they derive from
    directory ``d`` when not told where: ``d`` itself, or for a shipped run
    (inside :data:`SHIPPED`) the same path under :data:`SHIPPED_DERIVED`."""
    try:
        inside = Path(d).resolve().relative_to(SHIPPED.resolve())
    except ValueError:
        return Path(d)
    return SHIPPED_DERIVED / inside
