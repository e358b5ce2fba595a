"""Figures (Matplotlib ``Figure`` objects, without pyplot: no display needed,
and importing this module leaves the user's Matplotlib backend alone)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import numpy as np
from matplotlib import colormaps
from matplotlib.axes import Axes
from matplotlib.colors import ListedColormap
from matplotlib.figure import Figure
from matplotlib.projections.polar import PolarAxes

from locustjump.evo.archive import Archive
from locustjump.rundir import atomic_write_bytes
from locustjump.sim.analysis import Jump
from locustjump.sim.model import CONTROL_DT
from locustjump.sim.names import ACTUATED_JOINTS
from locustjump.tasks.getup import Sweep

if TYPE_CHECKING:
    from matplotlib.typing import LegendLocType  # Matplotlib 3.9


def _save(fig: Figure, path: Path) -> None:
    """Write ``fig`` as PNG with the run directory's atomic writer; close it."""

    atomic_write_bytes(path, lambda f: fig.savefig(f, dpi=120, format="png"))


def subplots(*args: Any, figsize: tuple[float, float], **kw: Any) -> tuple[Figure, Any]:
    """``(Figure, axes)``: ``pyplot.subplots`` without pyplot (a figure no
    backend knows of, so nothing to close and no display needed). The axes
    are one ``Axes`` or an array of them, as the arguments ask (Matplotlib
    types them ``Any``)."""
    layout = kw.pop("constrained_layout", None)
    fig = Figure(figsize=figsize, constrained_layout=layout)
    return fig, fig.subplots(*args, **kw)


def _finish(
    fig: Figure, ax: Axes, path: Path, title: str, *, legend: LegendLocType
) -> None:
    """Grid, legend, title; save as PNG and close."""
    ax.grid(alpha=0.3)
    ax.legend(loc=legend, fontsize=8)
    if title:
        ax.set_title(title)
    _save(fig, path)


#: (x, h): the ground's height (m) under a path (:func:`ground_profile`).
Ground = tuple[np.ndarray, np.ndarray]


def _plot_trajectories(
    ax: Axes,
    curves: list[tuple[str, np.ndarray, list[Jump]]],
    lw: float = 1.4,
    ground: Ground | None = None,
) -> None:
    """Height z vs distance x per curve, apexes marked; under them, filled,
    the terrain's profile if there is one."""
    if ground is not None:
        ax.fill_between(*ground, color="0.55", alpha=0.6, lw=0, step="mid",
                        label="ground under the path")  # fmt: skip
    for label, qpos, jumps in curves:
        (line,) = ax.plot(qpos[:, 0], qpos[:, 2], lw=lw, label=label)
        if jumps:
            ax.plot(
                [j.apex_x for j in jumps],
                [qpos[j.apex_step, 2] for j in jumps],
                "v",
                color=line.get_color(),
                ms=6,
                label=f"{label}: {len(jumps)} jump{'s' * (len(jumps) != 1)} (apex)",
            )
    ax.set_xlabel("distance x [m]")
    ax.set_ylabel("height z [m]")
    ax.set_ylim(bottom=0)


def trajectory_figure(
    path: Path,
    curves: list[tuple[str, np.ndarray, list[Jump]]],
    *,
    title: str = "",
    ground: Ground | None = None,
) -> None:
    """Height z vs distance x (the paper's Fig. 5/7), apexes marked.

    Args:
      path: the PNG to write.
      curves: (label, qpos (T, nq), jumps) per trajectory.
      title: figure title.
      ground: the terrain's profile under the first path (drawn filled), or
        None on the flat floor.
    """
    fig, ax = subplots(figsize=(9, 3.6), constrained_layout=True)
    _plot_trajectories(ax, curves, ground=ground)
    _finish(fig, ax, path, title, legend="upper right")


def fitness_curves(path: Path, metrics: np.ndarray, *, title: str = "") -> None:
    """Best and mean (+- std) fitness per generation from a metrics table."""
    g = metrics["generation"]
    fig, ax = subplots(figsize=(6.4, 3.6), constrained_layout=True)
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
    _finish(fig, ax, path, title, legend="lower right")


def composed_figure(
    path: Path,
    curves: list[tuple[str, np.ndarray, list[Jump]]],
    selected: np.ndarray | None,
    names: tuple[str, ...],
    *,
    title: str = "",
    ground: Ground | None = None,
) -> None:
    """The paper's Fig. 12: trajectories (z vs x) and, under them, the simple
    behaviour selected at each control step of the first curve.

    Args:
      path: the PNG to write.
      curves: (label, qpos (T + 1, nq), jumps) per trajectory, first the
        controlled one.
      selected: (T,) index into ``names`` per control step, or None.
      names: the simple behaviours' names.
      title: figure title.
      ground: the terrain's profile under the first path, or None.
    """

    rows = 2 if selected is not None else 1
    fig, axes = subplots(
        rows,
        1,
        figsize=(9, 4.6 if rows == 2 else 3.6),
        constrained_layout=True,
        height_ratios=[4, 1] if rows == 2 else None,
        squeeze=False,
    )
    ax = axes[0, 0]
    _plot_trajectories(ax, curves, lw=1.2, ground=ground)
    ax.grid(alpha=0.3)
    ax.legend(loc="upper right", fontsize=8)
    if title:
        ax.set_title(title)
    if selected is not None:
        selection_strip(axes[1, 0], selected, names)
    _save(fig, path)


def behaviour_colours(n: int) -> ListedColormap:
    """The colour of each of ``n`` simple behaviours a switcher selects: the
    paper's three, or a repertoire's elites and the rest (tab20)."""
    palette: list[str | tuple[float, float, float, float]] = [
        "tab:red", "tab:green", "tab:blue"]  # fmt: skip
    if n > len(palette):
        tab20 = colormaps["tab20"]
        palette = [tab20(i % 20) for i in range(n)]
    return ListedColormap(palette[:n])


def selection_strip(
    ax: Axes,
    selected: np.ndarray,
    names: tuple[str, ...],
    *,
    legend_ax: Axes | None = None,
) -> None:
    """On ``ax``: the behaviour selected at each control step, one colour each
    (:func:`behaviour_colours`), over time, with a legend of ``names`` to the
    right of ``legend_ax`` (default: ``ax``)."""
    colors = behaviour_colours(len(names))
    ax.imshow(
        selected[None, :],
        aspect="auto",
        cmap=colors,
        vmin=-0.5,
        vmax=len(names) - 0.5,
        interpolation="nearest",
        extent=(0, len(selected) * CONTROL_DT, 0, 1),
    )
    ax.set_yticks([])
    ax.set_xlabel("time [s]")
    ax.set_title("selected simple behaviour", fontsize=9)
    legend_ax = ax if legend_ax is None else legend_ax
    for i, n in enumerate(names):
        legend_ax.plot([], [], "s", color=colors(i), label=n)
    legend_ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8)


def getup_figure(
    path: Path, uz: np.ndarray, rolls: tuple[float, ...], success: float
) -> None:
    """U_z over time from each start state (the paper's Fig. 9)."""

    t = np.arange(uz.shape[1]) * CONTROL_DT
    fig, ax = subplots(figsize=(7, 3.6), constrained_layout=True)
    for u, r in zip(uz, rolls, strict=True):
        ax.plot(t, u, lw=1.3, label=f"rolled {r:g} deg")
    ax.axhline(success, color="k", ls=":", lw=1, label=f"success (U_z >= {success})")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("U_z (body up-axis . world z)")
    ax.set_ylim(-1.05, 1.05)
    _finish(
        fig, ax, path, "Getting up from the five start states", legend="lower right"
    )


def joint_angles_figure(path: Path, angles: np.ndarray, target: np.ndarray) -> None:
    """The four hind joint angles over time and their ready angles phi (Fig. 10)."""

    t = np.arange(angles.shape[0]) * CONTROL_DT
    fig, ax = subplots(figsize=(7, 3.6), constrained_layout=True)
    for i, name in enumerate(ACTUATED_JOINTS):
        (line,) = ax.plot(t, np.degrees(angles[:, i]), lw=1.3, label=name)
        ax.axhline(np.degrees(target[i]), color=line.get_color(), ls="--", lw=0.8)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("joint angle [deg] (dashed: phi)")
    _finish(
        fig, ax, path, "Returning the legs to the ready posture", legend="center right"
    )


def sweep_figure(path: Path, sweep: Sweep, *, title: str = "") -> None:
    """Polar plot of get-up success over the start roll angle."""
    fig = Figure(figsize=(5.2, 5.2), constrained_layout=True)
    ax = cast(PolarAxes, fig.add_subplot(projection="polar"))
    ax.set_theta_zero_location("N")  # 0 deg = upright, at the top
    ax.set_theta_direction(-1)
    theta = np.radians(sweep.roll_deg)
    r = np.where(sweep.training, 1.15, 1.0)
    ok = sweep.success
    ax.scatter(theta[ok], r[ok], s=14, color="tab:green", label="got up")
    ax.scatter(theta[~ok], r[~ok], s=14, color="tab:red", label="did not")
    tr = sweep.training
    ax.scatter(theta[tr], r[tr], s=60, facecolors="none", edgecolors="k",
               label="training states")  # fmt: skip
    ax.set_rticks([])
    ax.set_ylim(0, 1.3)
    ax.legend(loc="lower center", bbox_to_anchor=(0.5, -0.02), fontsize=8, ncol=3)
    ax.set_title(title or f"Got up from {sweep.got_up} of {sweep.n_sweep}")
    _save(fig, path)


def archive_heatmap(
    path: Path,
    archive: Archive,
    *,
    units: dict[str, str] | None = None,
    title: str = "",
    qd_offset: float = 0.0,
) -> None:
    """A grid archive's elites (:class:`~locustjump.evo.archive.Archive`) as a
    heatmap (:func:`draw_archive`), written to ``path``."""
    fig, ax = subplots(figsize=(6.4, 5.0))
    draw_archive(fig, ax, archive, units=units, title=title, qd_offset=qd_offset)
    _save(fig, path)


def draw_archive(
    fig: Figure,
    ax: Axes,
    archive: Archive,
    *,
    units: dict[str, str] | None = None,
    title: str = "",
    qd_offset: float = 0.0,
) -> None:
    """On ``ax`` of ``fig``: a grid archive's elites as a heatmap, fitness
    colour per cell of the first two descriptors (x, y), empty cells blank;
    with one descriptor, one row; with more, each cell of the first two shows
    the best over the others. Top and right axes: the cell indices (``--cell
    i,j``). The title's QD score subtracts ``qd_offset`` per elite (the run's
    ``[optimizer] qd_offset``, as ``metrics.csv``'s)."""
    heat = archive.heat()
    if heat.ndim == 1:
        heat = heat[:, None]
    elif heat.ndim > 2:  # the best over the other descriptors' cells
        flat = heat.reshape(*heat.shape[:2], -1)
        best = np.where(np.isnan(flat), -np.inf, flat).max(axis=2)
        heat = np.where(np.isneginf(best), np.nan, best)
    units = units or {}
    xs = archive.edges(0)
    ys = archive.edges(1) if len(archive.dims) > 1 else np.array([0.0, 1.0])
    mesh = ax.pcolormesh(xs, ys, np.ma.masked_invalid(heat.T), cmap="viridis")
    fig.colorbar(mesh, ax=ax, label="fitness", pad=0.12)

    def label(i: int) -> str:
        name = archive.names[i]
        return f"{name} [{units[name]}]" if name in units else name

    ax.set_xlabel(label(0))
    if len(archive.dims) > 1:
        ax.set_ylabel(label(1))
    else:
        ax.set_yticks([])
    secondary = [(ax.secondary_xaxis("top"), xs)]
    if len(archive.dims) > 1:
        secondary.append((ax.secondary_yaxis("right"), ys))
    for sec, edges in secondary:
        cells = range(0, len(edges) - 1, max(1, (len(edges) - 1) // 10))
        sec.set_ticks(
            [(edges[i] + edges[i + 1]) / 2 for i in cells], [str(i) for i in cells]
        )
        sec.tick_params(labelsize=7)
    more = f"; more descriptors: best over {', '.join(archive.names[2:])}"
    ax.set_title(
        (title + "\n" if title else "")
        + f"{len(archive)} elites, coverage {archive.coverage:.0%}, "
        f"QD score {archive.qd_score(qd_offset):.4g}"
        + (more if len(archive.dims) > 2 else ""),
        fontsize=9,
    )


def repertoire_composition_figure(
    path: Path,
    archive: Archive,
    chosen: np.ndarray,
    height: np.ndarray,
    selected: np.ndarray,
    names: tuple[str, ...],
    *,
    units: dict[str, str] | None = None,
    title: str = "",
    suptitle: str = "",
    qd_offset: float = 0.0,
) -> None:
    """A composition over a repertoire in one figure: left, the kick archive
    (:func:`draw_archive`) with each elite the switcher chooses among
    numbered in its cell; right, one episode of the switcher: the body's
    height over time and, under it, the behaviour selected at each control
    step (:func:`selection_strip`), elite ``i`` in the colour of its number.

    Args:
      chosen: positions in ``archive`` of the elites, in the switcher's order.
      height: (T + 1,) the body's height (m) at each control step.
      selected: (T,) index into ``names`` per control step.
      names: the switcher's behaviours, the elites first.
    """
    fig = Figure(figsize=(13, 4.8), constrained_layout=True)
    grid = fig.add_gridspec(2, 2, width_ratios=[1.0, 1.45], height_ratios=[4, 1])
    ax = fig.add_subplot(grid[:, 0])
    draw_archive(fig, ax, archive, units=units, title="the kick repertoire",
                 qd_offset=qd_offset)  # fmt: skip
    colors = behaviour_colours(len(names))
    cells = archive.grid_index()[chosen]
    for i, cell in enumerate(cells):
        x = archive.edges(0)[cell[0] : cell[0] + 2].mean()
        y = archive.edges(1)[cell[1] : cell[1] + 2].mean() if len(cell) > 1 else 0.5
        circle = {"boxstyle": "circle,pad=0.2", "fc": colors(i), "ec": "white"}
        ax.text(x, y, str(i), ha="center", va="center", fontsize=8, color="white",
                bbox=circle)  # fmt: skip
    top = fig.add_subplot(grid[0, 1])
    t = np.arange(len(height)) * CONTROL_DT
    top.plot(t, height, color="k", lw=1.0)
    top.set_ylabel("height z [m]")
    top.set_xlim(0, t[-1])
    top.grid(alpha=0.3)
    if title:
        top.set_title(title, fontsize=9)
    if suptitle:
        fig.suptitle(suptitle, fontsize=10)
    strip = fig.add_subplot(grid[1, 1], sharex=top)
    selection_strip(strip, selected, names, legend_ax=top)
    _save(fig, path)
