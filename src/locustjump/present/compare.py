"""Runs compared as samples: optimizers (or any config key) at equal budget.

``compare(dirs)`` groups training runs by a key of their configuration (the
optimizer's kind by default), and reports per group the best fitness of each
run as a sample — median, quartiles, range — and, against the reference
group, the Hodges–Lehmann shift with its 95 % interval, the two-sided
Mann–Whitney p and a verdict that follows the interval; with an equivalence
margin also the TOST p and the seeds per arm for 80 % power
(:mod:`locustjump.present.stats`; SciPy, extra ``locustjump[study]``). It
draws convergence curves: the best fitness so far against genome
evaluations, median and interquartile band over the group's runs.
``locustjump compare DIR... [--by KEY] [--margin M] [--figure FILE]`` prints
the table. With ``total_budget`` (``--total-budget``) a run built on frozen
networks (the composed switcher) counts their evaluations too, so that a
composition and a monolithic network compare at the budget each spent in all.
"""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, cast

import numpy as np
from matplotlib.backend_bases import FigureCanvasBase

from locustjump import rundir
from locustjump.errors import UserError, setting_ref
from locustjump.evo.base import OptimizerParams
from locustjump.present.plots import subplots
from locustjump.present.ranktests import Sample
from locustjump.present.stats import compare_samples, interval_text, p_text
from locustjump.ranges import Range, SettingValueError
from locustjump.rundir.config import TrainConfig
from locustjump.sim.scene import Terrains

if TYPE_CHECKING:
    from _typeshed import DataclassInstance

#: the x axis when a composed run's frozen runs are counted (total_budget)
TOTAL_LABEL = "genome evaluations, the frozen simple runs' included"

#: config keys a comparison may group by
KEYS = ("optimizer", "engine", "behaviour", "seed", "scene")
#: ``margin``: of equivalence, in fitness units
MARGIN = Range(0.0, lo_open=True)
#: runs whose budgets differ by more than this (ratio) are flagged (a
#: study's table flags its arms by it too)
BUDGET_TOLERANCE = 0.02


@dataclass(frozen=True)
class Group:
    """The runs of one value of the grouping key."""

    label: str
    runs: tuple[Path, ...]
    best: np.ndarray  # best fitness of each run
    evaluations: np.ndarray  # genome evaluations of each run
    curves: tuple[tuple[np.ndarray, np.ndarray], ...]  # (evaluations, best so far)

    def quartiles(self) -> tuple[float, float, float]:
        with np.errstate(invalid="ignore"):  # an infinite best: nan, said so
            q = np.percentile(self.best, [25, 50, 75])
        return float(q[0]), float(q[1]), float(q[2])


def optimizer_label(params: OptimizerParams) -> str:
    """The optimizer's kind, with the settings that differ from its defaults
    (population aside): ``rcga``, ``rcga(crossover=sbx)``, ``cma(sigma0=1)``."""
    changed = [
        f"{f.name}={getattr(params, f.name)}"
        for f in dataclasses.fields(cast("DataclassInstance", params))  # a dataclass
        if f.name != "population" and getattr(params, f.name) != f.default
    ]
    return params.kind + (f"({', '.join(changed)})" if changed else "")


def scene_label(terrains: Terrains) -> str:
    """The world a run trained in, its terrain seeds aside: the scene's kind
    with the parameters that differ from its defaults, and ``min`` when its
    terrains' fitness was their worst: ``flat``, ``debris``,
    ``debris(wall_height=0.1)``, ``debris min``."""
    scene = terrains.scene
    changed = [
        f"{f.name}={getattr(scene, f.name)}"
        for f in dataclasses.fields(scene)
        if f.name != "seed" and getattr(scene, f.name) != f.default
    ]
    label = scene.name + (f"({', '.join(changed)})" if changed else "")
    return label + ("" if terrains.aggregate == "mean" else f" {terrains.aggregate}")


def _key(cfg: TrainConfig, by: str) -> str:
    if "," in by:
        return " / ".join(_key(cfg, k) for k in by.split(","))
    if by == "optimizer":
        return optimizer_label(cfg.optimizer)
    if by == "scene":
        return scene_label(cfg.scene)
    return str(getattr(cfg, by))


def frozen_evaluations(run: Path, cfg: TrainConfig) -> int:
    """Genome evaluations of the runs whose best genomes ``run`` builds on
    (0 for a behaviour built on none). Each is found where ``frozen.npz``
    says it came from (relative to the working directory) or beside ``run``
    (``DIR/<behaviour>`` of one reproduction), and must have the config hash
    recorded there; ``UserError`` naming it when neither holds it. A run
    several frozen behaviours come from (a repertoire's elites) counts
    once."""
    frozen = rundir.frozen_of(cfg, run)
    if frozen is None:
        return 0
    total = 0
    counted: set[Path] = set()  # a repertoire's elites share one run
    recorded = zip(frozen.behaviours, frozen.sources, frozen.hashes, strict=True)
    for name, source, digest in recorded:
        places = (Path(source), run.parent / name)
        found = [d for d in places if rundir.is_run(d) and _hash(d) == digest]
        if not found:
            raise UserError(
                f"{run}: {setting_ref('total_budget', True)} needs the {name} run "
                f"it builds on (config hash {digest}), neither at {source} nor at "
                f"{run.parent / name}"
            )
        if found[0].resolve() in counted:
            continue
        counted.add(found[0].resolve())
        metrics = rundir.read_metrics(found[0] / rundir.METRICS)
        total += int(metrics["evaluations"].sum())
    return total


def _hash(run: Path) -> str:
    return rundir.load_config(run / rundir.CONFIG).hash()


def load_groups(
    dirs: Sequence[str | os.PathLike[str]], by: str = "optimizer",
    total_budget: bool = False,
) -> list[Group]:  # fmt: skip
    """The runs in ``dirs`` grouped by ``by`` (one of :data:`KEYS`, or several
    joined by commas: ``behaviour,optimizer``), in the order each value first
    appears. Every run must be of one behaviour, unless
    grouped by behaviour (then theirs must be one fitness: composed and
    monolithic, kick and kick-open, ...), and trained in one scene
    (:func:`scene_label`: its terrain seeds may differ), unless grouped by
    scene. With ``total_budget`` a run's
    evaluations include those of the frozen runs it builds on
    (:func:`frozen_evaluations`): its curve starts where they end."""
    keys = by.split(",")
    if not all(k in KEYS for k in keys) or len(set(keys)) != len(keys):
        raise UserError(
            f"{setting_ref('by')} {by!r}: choose from {', '.join(KEYS)}, or several "
            "joined by commas"
        )
    if not dirs:
        raise UserError("compare needs at least one run directory")
    # per value of the key: (run, best fitness, evaluations, its curve)
    found: dict[str, list[tuple[Path, float, int, tuple[np.ndarray, np.ndarray]]]] = {}
    behaviours, scenes = set(), set()
    for d in map(Path, dirs):
        if not rundir.is_run(d):
            raise UserError(f"{d}: holds no run (no {rundir.CONFIG})")
        cfg, _, best = rundir.load_run(d)
        behaviours.add(cfg.behaviour)
        scenes.add(scene_label(cfg.scene))
        m = rundir.read_metrics(d / rundir.METRICS)
        if not len(m):
            raise UserError(f"{d / rundir.METRICS}: holds no generation yet")
        evals = np.cumsum(m["evaluations"])
        if total_budget:
            evals += frozen_evaluations(d, cfg)
        found.setdefault(_key(cfg, by), []).append(
            (d, best.fitness, int(evals[-1]), (evals, np.maximum.accumulate(m["best"])))
        )
    if len(behaviours) > 1 and "behaviour" not in keys:
        raise UserError(
            f"the runs are of several behaviours ({', '.join(sorted(behaviours))}); "
            "compare runs of one"
        )
    if len(scenes) > 1 and "scene" not in keys:
        raise UserError(
            f"the runs trained in several scenes ({', '.join(sorted(scenes))}): "
            "their fitness is not one sample; compare runs of one, or group "
            f"them with {setting_ref('by')} scene"
        )
    return [
        Group(
            label,
            tuple(r[0] for r in rows),
            np.array([r[1] for r in rows]),
            np.array([r[2] for r in rows]),
            tuple(r[3] for r in rows),
        )  # fmt: skip
        for label, rows in found.items()
    ]


def table(
    groups: Sequence[Group], reference: str | None = None, *,
    margin: float | None = None,
) -> str:  # fmt: skip
    """A Markdown table: per group the runs, evaluations per run, best
    fitness median [quartiles] and range, and against ``reference`` (default:
    the first group) the Hodges–Lehmann shift ``group - reference`` with its
    95 % interval, the two-sided Mann–Whitney p and the verdict
    (:func:`~locustjump.present.stats.compare_samples`; fitness units,
    maximised). With ``margin`` (> 0, fitness units) also the TOST p of
    equivalence within ``±margin`` and the seeds per arm for 80 % power
    against a shift of ``margin``. A group of one run gets no test."""
    ref = (
        next((g for g in groups if g.label == reference), None)
        if reference
        else groups[0]
    )
    if ref is None:
        raise UserError(f"{setting_ref('reference')} {reference!r}: no such group")
    if margin is not None:
        margin = MARGIN.check("margin", margin)
    head = [f"HL shift vs {ref.label} [95 % CI]", "Mann–Whitney p"]
    if margin is not None:
        head += [f"TOST p vs ±{margin:g}", "seeds for 80 % power"]
    head.append("verdict")
    lines = [
        "| group | runs | evaluations per run | best fitness: median [q1, q3] | "
        f"range | {' | '.join(head)} |",
        "| --- " * (5 + len(head)) + "|",
    ]
    for g in groups:
        q1, med, q3 = g.quartiles()
        ev = (f"{g.evaluations.min():,}" if g.evaluations.min() == g.evaluations.max()
              else f"{g.evaluations.min():,}-{g.evaluations.max():,}")  # fmt: skip
        lines.append(
            f"| {g.label} | {len(g.runs)} | {ev} | {med:.4g} [{q1:.4g}, {q3:.4g}] | "
            f"{g.best.min():.4g} - {g.best.max():.4g} | "
            f"{' | '.join(_tests(g, ref, margin))} |"
        )
    return "\n".join(lines)


def budget_note(groups: Sequence[Group]) -> str:
    """Whether the runs compared spent the same: the largest number of genome
    evaluations a run made over the smallest, flagged beyond
    :data:`BUDGET_TOLERANCE` (a comparison at unequal budgets favours the
    larger)."""
    evals = np.concatenate([g.evaluations for g in groups])
    lo, hi = int(evals.min()), int(evals.max())
    ratio = hi / lo if lo else float("inf")
    note = f"In genome evaluations: largest / smallest run {ratio:.2f}"
    if ratio - 1 > BUDGET_TOLERANCE:
        note += " — **not equal**: the runs are not compared at equal budget"
    return note + "."


def _tests(g: Group, ref: Group, margin: float | None) -> list[str]:
    """The table's cells comparing ``g`` with ``ref``."""
    blank = ["-", "-"] + (["-", "-"] if margin is not None else [])
    if g is ref:
        return [*blank, "reference"]
    if min(len(g.runs), len(ref.runs)) < 2:
        return [*blank, "no test: a group of one run"]
    if not (np.all(np.isfinite(g.best)) and np.all(np.isfinite(ref.best))):
        return [*blank, "no test: a best fitness is not finite"]
    c = compare_samples(Sample(g.label, g.best), Sample(ref.label, ref.best),
                        margin=margin)  # fmt: skip
    cells = [interval_text(c), p_text(c.p)]
    if margin is not None:
        power = "-" if c.seeds_for_power is None else str(c.seeds_for_power)
        cells += [p_text(c.p_equivalence), power]
    return [*cells, c.verdict]


def check_figure_path(path: str | os.PathLike[str]) -> Path:
    """``path`` if Matplotlib can write a figure in the format its suffix
    names (none: PNG), else a ``SettingError`` naming ``figure``."""
    path = Path(path)
    formats = FigureCanvasBase.get_supported_filetypes()
    if path.suffix and path.suffix.lstrip(".").lower() not in formats:
        raise SettingValueError(
            "figure", f"a file ending in one of .{', .'.join(sorted(formats))}",
            str(path),
        )  # fmt: skip
    return path


def convergence_figure(groups: Sequence[Group], path: str | os.PathLike[str],
                       title: str = "", xlabel: str = "genome evaluations",
                       ) -> Path:  # fmt: skip
    """Best fitness so far against genome evaluations: median line and
    interquartile band over each group's runs."""
    fig, ax = subplots(figsize=(7, 4.2))
    for g in groups:
        grid = np.unique(np.concatenate([c[0] for c in g.curves]))
        ys = np.array([
            np.interp(grid, ev, best, left=np.nan, right=best[-1])
            for ev, best in g.curves
        ])  # fmt: skip
        q1, med, q3 = np.nanpercentile(ys, [25, 50, 75], axis=0)
        (line,) = ax.plot(grid, med, label=f"{g.label} (n={len(g.runs)})")
        ax.fill_between(grid, q1, q3, color=line.get_color(), alpha=0.2)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("best fitness so far")
    ax.set_title(title or "best fitness: median and interquartile range over runs")
    ax.legend()
    fig.tight_layout()
    path = check_figure_path(path)
    with rundir.atomic_path(path) as tmp:
        fig.savefig(tmp, format=path.suffix.lstrip(".") or "png", dpi=120)
    return path
