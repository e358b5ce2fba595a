"""How far a run's learning got, for a study's table: the share of its
improvement made late (:func:`late_gain`) and the rule a study declares for
when a learning curve counts as flat (``flat_gain`` in the study file,
:func:`flat_note`); what a run spent, its frozen runs included
(:func:`spent`), and the study's learning curves (:func:`learning_figure`)."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from locustjump import rundir
from locustjump.present.compare import Group, convergence_figure

if TYPE_CHECKING:
    from locustjump.runs.studyarms import Arm
    from locustjump.runs.studyfile import Study


def late_gain(best: np.ndarray) -> float:
    """The share of a run's whole improvement made in its last third of
    generations: of its best so far, (last - at two thirds) / (last -
    first); 0 where it was flat by then or never improved, 1 where all of it
    came late. ``best`` is each generation's best; the curve is the best so
    far, as the learning figure draws it, so an optimizer that keeps no
    elite (random search, CMA-ES) gains no less than 0; a share of the
    improvement, not of the final fitness, reads the same for fitness below
    0 (return-legs) or offset by a constant."""
    so_far = np.maximum.accumulate(np.asarray(best, dtype=float))
    whole = so_far[-1] - so_far[0] if len(so_far) >= 3 else 0.0
    if whole <= 0:
        return 0.0
    return float((so_far[-1] - so_far[len(so_far) * 2 // 3 - 1]) / whole)


def flat_note(limit: float, arms: Mapping[str, dict[str, Any]]) -> str:
    """The study's declared flattening rule applied: an arm's learning curves
    are flat when the median over its seeds of :func:`late_gain` is at most
    ``limit``. Each arm of ``arms`` (a table's ``arms``: its ``label`` and
    its median ``budget["late_gain"]``) gets ``flat`` (bool); the sentence
    says which are."""
    parts = []
    for arm in arms.values():
        gain = arm["budget"]["late_gain"]
        arm["flat"] = bool(gain <= limit)
        parts.append(f"{arm['label']} {'yes' if arm['flat'] else 'no'} ({gain:.2%})")
    return (
        "Flat by the study's declared rule (the median gain in the last third "
        f"at most {limit:.2%}): " + "; ".join(parts) + "."
    )


#: columns of the metrics that count a run's budget, per currency
CURRENCY_COLUMN = {"evaluations": "evaluations", "control-steps": "control_steps"}


def spent(study: Study, arm: Arm, seed: int) -> dict[str, int]:
    """Genome evaluations and control steps (``evaluations``,
    ``control_steps``) of the run of ``arm`` and ``seed``
    and of every run it builds on, in the study."""
    m = rundir.read_metrics(arm.run_dir(seed) / rundir.METRICS)
    out = {col: int(m[col].sum()) for col in CURRENCY_COLUMN.values()}
    for other in arm.frozen.values():
        for c, v in spent(study, study.arms[other], seed).items():
            out[c] += v
    return out


def curve(study: Study, arm: Arm, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """(spent so far in the study's currency, frozen runs first; best so far)."""
    m = rundir.read_metrics(arm.run_dir(seed) / rundir.METRICS)
    col = CURRENCY_COLUMN[study.currency]
    offset = sum(spent(study, study.arms[o], seed)[col] for o in arm.frozen.values())
    return np.cumsum(m[col]) + offset, np.maximum.accumulate(m["best"])


def learning_figure(study: Study, path: Path) -> Path:
    """Each scored arm's best training fitness so far against what it spent
    in the study's currency: median and interquartile band over seeds."""
    groups = []
    for a in study.scored:
        curves = tuple(curve(study, a, s) for s in study.seeds)
        groups.append(Group(
            a.label, tuple(a.run_dir(s) for s in study.seeds),
            np.array([c[1][-1] for c in curves]),
            np.array([int(c[0][-1]) for c in curves]), curves,
        ))  # fmt: skip
    return convergence_figure(
        groups, path,
        title=f"{study.name}: best training fitness, median and IQR over seeds",
        xlabel=f"{study.currency}, the frozen runs' included",
    )  # fmt: skip
