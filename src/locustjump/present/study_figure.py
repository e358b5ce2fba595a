"""A study's answer as a figure: every run's score per arm, and each pair's
Hodges–Lehmann shift with its 95 % interval against the declared margin.

Drawn from what ``study --table`` writes to ``table.json`` (see
:mod:`locustjump.runs.study_table`), so ``scores.png`` shows exactly the
table's numbers: the left panels one column of dots per arm (a run each,
its score where the study scores it) with the arm's median, one panel per
physics resolution; the right panel each pair's shift, on the full fitness
and on the height term alone where the table gives it, at each resolution,
with 0 and the equivalence margin drawn (a pair too small for an interval
says so). An interval that excludes 0 is a difference,
one inside the margin band is equivalence only if the table's TOST says so;
the figure draws, the table decides.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from locustjump import rundir
from locustjump.present.compare import check_figure_path
from locustjump.present.plots import subplots

#: the figure ``study --table`` writes beside table.md
SCORES_PNG = "scores.png"


def resolution_label(key: str) -> str:
    """A physics resolution as table.json keys it (``"3"``; ``"None"``: the
    run's own) in words."""
    return "as trained" if key == "None" else f"{key} substeps"


def _resolutions(data: Mapping[str, Any]) -> list[str]:
    return list(data["pairs"])  # a key per resolution, compared or not


def shift_rows(data: Mapping[str, Any]) -> list[tuple[str, dict[str, Any]]]:
    """(label, pair row) of every comparison in ``data``, in the table's
    order: per resolution, the pairs on the full fitness, then on the height
    term alone; arms named by their keys in the study file (the labels are
    long), a pair too small for a 95 % interval said so."""
    name = {arm["label"]: key for key, arm in data["arms"].items()}
    terms = (("", data["pairs"]), (", height term", data.get("pairs_height_term", {})))
    out = []
    for key in _resolutions(data):
        where = resolution_label(key)
        for term, pairs in terms:
            for row in pairs.get(key, []):
                pair = f"{name[row['a']]} - {name[row['b']]}"
                label = f"{pair}, {where}{term}"
                if row["low"] is None or row["high"] is None:
                    label += " (no 95 % interval)"
                out.append((label, row))
    return out


def scores_figure(data: Mapping[str, Any], path: str | os.PathLike[str]) -> Path:
    """Write the study's figure (:func:`draw_scores`) to ``path``; return it."""
    path = check_figure_path(path)
    fig = draw_scores(data)
    with rundir.atomic_path(path) as tmp:
        fig.savefig(tmp, format=path.suffix.lstrip(".") or "png", dpi=120)
    return path


def draw_scores(data: Mapping[str, Any]) -> Figure:
    """The study's figure (module docstring) from ``data``, table.json's
    content."""
    keys = _resolutions(data)
    arms = list(data["arms"].values())
    rows = shift_rows(data)
    height = 1.2 + max(3.0, 0.45 * len(rows))
    fig, axes = subplots(
        1, len(keys) + 1, figsize=(3.2 * len(keys) + 5.5, height),
        constrained_layout=True, squeeze=False,
        gridspec_kw={"width_ratios": [1.0] * len(keys) + [1.4]},
    )  # fmt: skip
    axes = axes[0]
    for ax, key in zip(axes[:-1], keys, strict=True):
        for x, arm in enumerate(arms):
            v = np.asarray(arm[key]["values"], dtype=float)
            dx = np.linspace(-0.12, 0.12, len(v)) if len(v) > 1 else np.zeros(len(v))
            ax.plot(x + dx, v, "o", alpha=0.7, ms=5)  # runs side by side, in order
            ax.hlines(arm[key]["median"], x - 0.3, x + 0.3, colors="k", lw=2)
        names = list(data["arms"])
        turn = 25 if sum(map(len, names)) > 40 else 0  # many or long: slanted
        ax.set_xticks(range(len(arms)), names, fontsize=8, rotation=turn,
                      ha="right" if turn else "center")  # fmt: skip
        ax.set_xlim(-0.6, len(arms) - 0.4)
        ax.set_title(f"score, {resolution_label(key)}", fontsize=9)
        ax.grid(alpha=0.3, axis="y")
    axes[0].set_ylabel("score per run (bar: median)")
    ax = axes[-1]
    margin = data.get("margin")
    xlabel = "Hodges–Lehmann shift (95 % interval)"
    if margin:
        ax.axvspan(-margin, margin, color="tab:green", alpha=0.15)
        xlabel += f"\ngreen: the equivalence margin, ±{margin:g}"
    ax.axvline(0.0, color="k", lw=0.8)
    for y, (_, row) in enumerate(rows):
        lo, hi = row["low"], row["high"]
        if lo is not None and hi is not None:
            ax.hlines(y, lo, hi, colors="tab:blue", lw=2)
        ax.plot(row["shift"], y, "o", color="tab:blue")
    ax.set_yticks(range(len(rows)), [label for label, _ in rows], fontsize=7)
    ax.invert_yaxis()
    ax.set_xlabel(xlabel)
    ax.set_title("first arm - second", fontsize=9)
    fig.suptitle(f"study {data['study']}", fontsize=10)
    ax.grid(alpha=0.3, axis="x")
    return fig
