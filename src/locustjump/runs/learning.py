"""How far a run's learning got, for a study's table: the share of its
improvement made late (:func:`late_gain`) and the rule a study declares for
when a learning curve counts as flat (``flat_gain`` in the study file,
:func:`flat_note`)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np


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
