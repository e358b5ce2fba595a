"""Figures (Matplotlib, Agg backend: no display needed)."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from locustjump.analysis import Jump  # noqa: E402


def trajectory_figure(
    path: Path,
    curves: list[tuple[str, np.ndarray, list[Jump]]],
    *,
    title: str = "",
) -> None:
    """Height z vs distance x (the paper's Fig. 5/7), apexes marked.

    Args:
      path: the PNG to write.
      curves: (label, qpos (T, nq), jumps) per trajectory.
      title: figure title.
    """
    fig, ax = plt.subplots(figsize=(9, 3.6), constrained_layout=True)
    for label, qpos, jumps in curves:
        (line,) = ax.plot(qpos[:, 0], qpos[:, 2], lw=1.4, label=label)
        if jumps:
            ax.plot(
                [j.apex_x for j in jumps],
                [j.apex_height for j in jumps],
                "v",
                color=line.get_color(),
                ms=6,
                label=f"{label}: {len(jumps)} jumps (apex)",
            )
    ax.set_xlabel("distance x [m]")
    ax.set_ylabel("height z [m]")
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(loc="upper right", fontsize=8)
    if title:
        ax.set_title(title)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def fitness_curves(path: Path, metrics: np.ndarray, *, title: str = "") -> None:
    """Best and mean (+- std) fitness per generation from a metrics table."""
    g = metrics["generation"]
    fig, ax = plt.subplots(figsize=(6.4, 3.6), constrained_layout=True)
    ax.fill_between(
        g,
        metrics["mean"] - metrics["std"],
        metrics["mean"] + metrics["std"],
        alpha=0.2,
        lw=0,
        label="mean +- std",
    )
    ax.plot(g, metrics["mean"], lw=1.0, label="mean")
    ax.plot(g, metrics["best"], lw=1.6, label="best")
    ax.set_xlabel("generation")
    ax.set_ylabel("fitness")
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right", fontsize=8)
    if title:
        ax.set_title(title)
    fig.savefig(path, dpi=120)
    plt.close(fig)
