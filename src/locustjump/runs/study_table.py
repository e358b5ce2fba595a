"""A study's table: every scored run's best genome re-scored, the arms
compared with effect sizes and intervals, at budgets shown in both
currencies (``locustjump study FILE --table``).

Per run (one sample per arm and seed): its best genome in its behaviour's
episode, on each held-out terrain of the study's evaluation (or its own
scene), at each physics resolution asked for; the sample is the mean over
terrains. Beside it, per arm: the budget each run spent in all — genome
evaluations and control steps, the frozen runs it builds on included — the
training fitness and the gap to the held-out score, the share of its whole
improvement made in the last third of its generations (near 0: its learning
curve had flattened), and, from the episodes (:mod:`locustjump.present.
episodes`), what can reveal an exploit: the height and distance terms of
the fitness apart, the share of steps touching a wall, the deepest
penetration. Each pair of arms: the Hodges–Lehmann shift with its 95 %
interval, the Mann–Whitney p, the equivalence test against the study's
margin and the seeds 80 % power would need (:mod:`locustjump.present.stats`),
and the verdict those numbers allow.

Scores are kept in ``OUT/scores.json``, keyed by each run's configuration
hash, best genome and the evaluation (not by its path: a shipped run keeps
its scores), so that a table is rescored only for what changed.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable, Sequence
from dataclasses import asdict
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from locustjump import rundir
from locustjump.errors import UserError
from locustjump.present.compare import BUDGET_TOLERANCE
from locustjump.present.episodes import score_run
from locustjump.present.stats import pairs_table
from locustjump.present.study_figure import (
    SCORES_PNG,
    resolution_label,
    scores_figure,
)
from locustjump.runs.learning import flat_note, late_gain, learning_figure, spent
from locustjump.runs.study import check_run, states
from locustjump.runs.study_pairs import compared, families
from locustjump.runs.studyfile import Study

if TYPE_CHECKING:
    from locustjump.sim.engine.backends import Backend

SCORES = "scores.json"
#: the largest scores.json read (a cache: ~15 KB a run and physics resolution
#: on 40 terrains; the 15-seed debris study's holds about 0.9 MB)
MAX_SCORES_BYTES = 64 << 20
#: part of every score's key: raise it when what an episode's score holds,
#: or how it is computed, changes (the cached scores are then recomputed)
SCORES_VERSION = 1
TABLE_MD = "table.md"
TABLE_JSON = "table.json"
FIGURE = "learning.png"


def _key(path: Path, substeps: int | None, terrains: tuple[int, ...] | None) -> str:
    cfg = rundir.load_config(path / rundir.CONFIG)
    best = rundir.BestGenome.load(path / rundir.BEST)
    genome = hashlib.sha256(
        np.ascontiguousarray(best.genome, "<f8").tobytes()
    ).hexdigest()[:16]
    key: list[Any] = [SCORES_VERSION, cfg.hash(), genome, substeps,
                      None if terrains is None else list(terrains)]  # fmt: skip
    robust = bool(getattr(cfg.options, "score_substeps", None))
    if substeps is not None and robust:
        key.append("alone")  # since 2026-11-26 (no longer the worst of them)
    return json.dumps(key)


def scores(
    study: Study,
    backend: Backend | None = None,
    log: Callable[[str], None] | None = None,
    out: Path | None = None,
) -> dict[tuple[str, int, int | None], list[dict[str, Any]]]:
    """Per (arm, seed, substeps) of every scored run, its episodes' scores (one
    dict per terrain), from ``out/scores.json`` (default: the study's
    ``out``) or the study's own cache where they hold them."""
    cache_path = (out or study.out) / SCORES
    cache: dict[str, Any] = {}
    for kept in dict.fromkeys((study.out / SCORES, cache_path)):
        if kept.is_file():
            cache.update(rundir.read_json(kept, MAX_SCORES_BYTES))
    found = {}
    todo = [(a, s) for a, s in study.runs() if a.score]
    for k, (arm, seed) in enumerate(todo, 1):
        path = arm.run_dir(seed)
        for sub in study.evaluation.substeps:
            key = _key(path, sub, study.evaluation.terrain_seeds)
            if key not in cache:
                if log:
                    log(f"scoring [{k}/{len(todo)}] {arm.name}, seed {seed}"
                        + ("" if sub is None else f", {sub} substeps"))  # fmt: skip
                eps = score_run(path, terrain_seeds=study.evaluation.terrain_seeds,
                                substeps=sub, backend=backend)  # fmt: skip
                cache[key] = [asdict(e) for e in eps]
                cache_path.parent.mkdir(parents=True, exist_ok=True)
                rundir.write_json(cache_path, cache)
            found[arm.name, seed, sub] = cache[key]
    return found


def _mean(eps: list[dict[str, Any]], key: str) -> float | None:
    v = [e[key] for e in eps if e.get(key) is not None]
    return float(np.mean(v)) if v else None


def _max(eps: list[dict[str, Any]], key: str) -> float | None:
    v = [e[key] for e in eps if e.get(key) is not None]
    return float(np.max(v)) if v else None


def run_rows(
    study: Study, sc: dict[tuple[str, int, int | None], list[dict[str, Any]]]
) -> list[dict[str, Any]]:
    """One row per scored run: its budget, training fitness, late gain and,
    per physics resolution, its score and diagnostics."""
    rows = []
    for arm, seed in study.runs():
        if not arm.score:
            continue
        path = arm.run_dir(seed)
        best = rundir.BestGenome.load(path / rundir.BEST)
        m = rundir.read_metrics(path / rundir.METRICS)
        row: dict[str, Any] = {
            "arm": arm.name, "seed": seed, "path": str(path),
            "generations": len(m), **spent(study, arm, seed),
            "train_fitness": best.fitness, "late_gain": late_gain(m["best"]),
            "at": {},
        }  # fmt: skip
        for sub in study.evaluation.substeps:
            eps = sc[arm.name, seed, sub]
            row["at"][str(sub)] = {
                "score": _mean(eps, "fitness"),
                "height_term": _mean(eps, "height_term"),
                "distance_term": _mean(eps, "distance_term"),
                "distance_m": _mean(eps, "distance_m"),
                "jumps": _mean(eps, "jumps"),
                "wall_contact": _max(eps, "wall_contact"),
                "penetration_m": _max(eps, "penetration_m"),
                "highest_m": _max(eps, "highest_m"),
            }
        rows.append(row)
    return rows


def _fmt(v: float | None, spec: str = ".4g") -> str:
    return "-" if v is None else format(v, spec)


def _label(sub: int | None) -> str:
    return resolution_label(str(sub))  # table.json's key for it


def make_table(study: Study, rows: list[dict[str, Any]]) -> tuple[str, dict[str, Any]]:
    """The study's table (Markdown) and everything in it (JSON-able)."""
    arms = study.scored
    by_arm = {a.name: [r for r in rows if r["arm"] == a.name] for a in arms}
    ev = study.evaluation
    where = (f"held-out terrains {_seeds_text(ev.terrain_seeds)}"
             if ev.terrain_seeds else "each run's own scene")  # fmt: skip
    out: dict[str, Any] = {"study": study.name, "currency": study.currency,
                           "margin": study.margin, "runs": rows, "arms": {},
                           "pairs": {}}  # fmt: skip
    md = [
        f"# Study {study.name}",
        "",
        f"{len(study.seeds)} seeds ({_seeds_text(study.seeds)}); every run's best "
        f"genome scored on {where}; one sample per run (its mean over terrains). "
        f"Arms equalised in **{study.currency}** (the frozen runs a composition "
        "builds on counted in).",
        "",
        "## Budget per run (median over seeds)",
        "",
        "| arm | runs | generations | genome evaluations | control steps | "
        "training fitness | gain in the last third |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for a in arms:
        rs = by_arm[a.name]
        med = {k: float(np.median([r[k] for r in rs]))
               for k in ("generations", "evaluations", "control_steps",
                         "train_fitness", "late_gain")}  # fmt: skip
        out["arms"][a.name] = {"label": a.label, "runs": len(rs), "budget": med}
        md.append(
            f"| {a.label} | {len(rs)} | {med['generations']:.0f} | "
            f"{med['evaluations']:,.0f} | {med['control_steps'] / 1e6:.2f} M | "
            f"{med['train_fitness']:.4g} | {med['late_gain']:.0%} |"
        )
    md += ["", _budget_note(study, out["arms"])]
    if study.flat_gain is not None:
        md += ["", flat_note(study.flat_gain, out["arms"])]
    for sub in ev.substeps:
        s = str(sub)
        md += [
            "", f"## Scores, {_label(sub)}", "",
            "| arm | runs | score per run | median [min, max] | height term | "
            "distance term | gap (training - score) | wall contact (max share) | "
            "deepest penetration (m) | highest (m) |",
            "| --- " * 10 + "|",
        ]  # fmt: skip
        samples = {}
        for a in arms:
            rs = by_arm[a.name]
            v = np.array([r["at"][s]["score"] for r in rs])
            samples[a.name] = v
            cell = {k: [r["at"][s][k] for r in rs if r["at"][s][k] is not None]
                    for k in ("height_term", "distance_term", "wall_contact",
                              "penetration_m", "highest_m")}  # fmt: skip
            gap = [r["train_fitness"] - r["at"][s]["score"] for r in rs]
            summary = {
                "values": v.tolist(), "median": float(np.median(v)),
                "min": float(v.min()), "max": float(v.max()),
                "height_term": _med(cell["height_term"]),
                "distance_term": _med(cell["distance_term"]),
                "gap": float(np.median(gap)),
                "wall_contact": max(cell["wall_contact"], default=None),
                "penetration_m": max(cell["penetration_m"], default=None),
                "highest_m": max(cell["highest_m"], default=None),
            }  # fmt: skip
            out["arms"][a.name][s] = summary
            md.append(
                f"| {a.label} | {len(v)} | {', '.join(f'{x:.4g}' for x in v)} | "
                f"{summary['median']:.4g} [{summary['min']:.4g}, "
                f"{summary['max']:.4g}] | {_fmt(summary['height_term'])} | "
                f"{_fmt(summary['distance_term'])} | {summary['gap']:.4g} | "
                f"{_fmt(summary['wall_contact'], '.1%')} | "
                f"{_fmt(summary['penetration_m'], '.4f')} | "
                f"{_fmt(summary['highest_m'], '.2f')} |"
            )
        few = [a.label for a in arms if len(samples[a.name]) < 2]
        if few:
            verb = "has" if len(few) == 1 else "each have"
            md += ["", f"No comparison: {'; '.join(few)} {verb} fewer than 2 runs."]
        comps = [] if few else compared(study, samples)
        out["pairs"][s] = [c.row() for c in comps]
        if comps:
            md += ["", pairs_table(comps)]
        height = {a.name: [r["at"][s]["height_term"] for r in by_arm[a.name]]
                  for a in arms}  # fmt: skip
        added = any(r["at"][s]["distance_term"] for r in rows)
        if comps and added and all(None not in v for v in height.values()):
            # the fitness without the distance term we added: the paper's Eq. 4
            hc = compared(study, {k: np.array(v) for k, v in height.items()})
            out.setdefault("pairs_height_term", {})[s] = [c.row() for c in hc]
            md += ["", "On the height term alone (Eq. 4 above the ground, "
                   "without the distance term; the margin as above):", "",
                   pairs_table(hc)]  # fmt: skip
    md += families(study, out)
    md += ["", _reading(study)]
    return "\n".join(md) + "\n", out


def _med(v: Sequence[float]) -> float | None:
    return float(np.median(v)) if len(v) else None


def _seeds_text(seeds: Sequence[int]) -> str:
    s = list(seeds)
    if s == list(range(s[0], s[-1] + 1)) and len(s) > 2:
        return f"{s[0]}-{s[-1]}"
    return ", ".join(map(str, s))


def _budget_note(study: Study, arms: dict[str, Any]) -> str:
    """Whether the arms spent the same in the declared currency, and the
    ratio in the other."""
    names = list(arms)
    if len(names) < 2:
        return ""
    lines = []
    for cur, col in (("evaluations", "evaluations"),
                     ("control-steps", "control_steps")):  # fmt: skip
        v = {n: arms[n]["budget"][col] for n in names}
        lo, hi = min(v.values()), max(v.values())
        ratio = hi / lo if lo else float("inf")
        declared = " (the declared currency)" if cur == study.currency else ""
        flag = ""
        if ratio - 1 > BUDGET_TOLERANCE:
            flag = (" — **not equal**: the arms are not compared at equal budget"
                    if declared else " — unequal in this currency")  # fmt: skip
        lines.append(f"In {cur}{declared}: largest / smallest arm {ratio:.2f}{flag}.")
    return " ".join(lines)


def _reading(study: Study) -> str:
    margin = (f"against the declared margin ±{study.margin:g}" if study.margin
              else "(no equivalence margin declared: 'no difference' cannot "
              "be concluded)")  # fmt: skip
    return (
        "How to read it: the shift is the Hodges–Lehmann estimate of the first "
        "arm minus the second, with its 95 % interval (exact without ties); "
        "'better' needs the interval to exclude 0, 'equivalent' the two "
        f"one-sided tests {margin}; otherwise there is no evidence either way. "
        "Seeds for 80 % power: about how many per arm, to detect a shift of the "
        "margin at the spread observed."
    )


def study_table(
    study: Study,
    backend: Backend | None = None,
    log: Callable[[str], None] | None = None,
    figure: bool = True,
    out: Path | None = None,
) -> tuple[Path, Path]:
    """Score every scored run of ``study`` (every run must be finished), write
    ``OUT/table.md``, ``OUT/table.json``, the learning curves
    ``OUT/learning.png`` and the scores and shifts ``OUT/scores.png``
    (:mod:`~locustjump.present.study_figure`), OUT being ``out`` or else the
    study's ``out``; return the two table paths."""
    missing = [st for st in states(study) if not st.finished]
    if missing:
        st = missing[0]
        raise UserError(
            f"study {study.name}: {len(missing)} run(s) not finished, e.g. arm "
            f"{st.arm!r} seed {st.seed} ({st.path}: {st.status}); run "
            f"`locustjump study {study.source}` first"
        )
    for arm, seed in study.runs():
        check_run(study, arm, seed)
    where = out or study.out
    rows = run_rows(study, scores(study, backend, log, where))
    md, data = make_table(study, rows)
    where.mkdir(parents=True, exist_ok=True)
    rundir.atomic_write_text(where / TABLE_MD, md)
    rundir.write_json(where / TABLE_JSON, data)
    if figure:
        learning_figure(study, where / FIGURE)
        scores_figure(data, where / SCORES_PNG)
    return where / TABLE_MD, where / TABLE_JSON
