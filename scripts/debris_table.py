"""Issue #30: successive jumping across debris, on terrains training never saw.

Every controller runs the composed behaviour's episode (3000 control steps,
from its start on its side; the rules also from their standing start) on each
debris terrain of ``--terrain-seeds`` (default 100-119; training used 0 and
1) and is scored by the debris fitness E (Eq. 4 with the height above the
ground under the body, plus 200 control steps per metre of forward
progress: ``successive_fitness`` in ``tasks/composed.py``). Rows:

* the rule-based jumper (paper §2.2), standing and on its side: its jumps
  before it lies overturned for good (U_z < 0 for 1 s), the share of the
  episode it spends upright (U_z >= 0), beside the rubble (|y| beyond the
  field's half width: it went round the debris), how far it got and how
  high its body rose above the ground under it on any terrain (a check on
  the physics and the walls: no jump should rise far above the rule's
  1.6 m);
* the rules plus an evolved get-up network (``RuleGetupController``; the
  get-up network drives while U_z < 0, or while U_z < 0.5 and I6 >= 0.8, as
  in ``scripts/study_references.py``) for the flat-evolved get-up of each
  reproduction given with ``--flat``;
* the composed and monolithic controllers of those flat reproductions,
  zero-shot on debris;
* every debris-trained composed or monolithic run given with ``--runs``
  (``scripts/debris_study.sh``), with its training fitness (the mean over its
  2 training terrains) and the generalisation gap;
* a two-sided Mann-Whitney U test (SciPy) between groups of runs: composed
  (flat simples), composed (debris simples) and monolithic, each run's
  held-out mean as one sample;
* with ``--flat-study``, the same group table on the flat floor beside it:
  the composed and monolithic networks of those flat reproductions, each
  scored on the flat floor (Eq. 4, no terrain) at the same physics;
* with ``--figure FILE``, the groups' learning curves (training fitness,
  median and interquartile band over runs) against the genome evaluations
  each spent in all: a composed run's curve starts after its frozen simple
  runs' evaluations (``locustjump compare --total-budget``).

Usage::

    .venv/bin/python scripts/debris_table.py --flat results/long-seed0 \\
        results/study/long/seed-{1,2} --runs runs/debris/*/composed \\
        runs/debris/*/monolithic runs/debris/flat-simples-composed-s* \\
        [--flat-study results/long-seed0 results/study/long/seed-*] \\
        [--substeps 12] [--json FILE] [--figure FILE]

Every row also shows (``present.episodes.episode_score``, issue #44) the
two terms of E, each the mean over the terrains (they add up to the mean E):
the height term (Eq. 4 above the ground) and the distance term (200 x
forward progress); the share of control steps the creature touched a wall
(mean over the terrains; "time beside the rubble" is 0 by construction once
the field has walls, this is not) and the deepest penetration of any of its
contacts, floor, rubble or walls (m, the maximum over the terrains and every
physics substep; ``tests/test_debris.py`` holds rule-based and random
controllers under 5 % of a body length, 0.025 m; ``scripts/contact_audit.py``
names the geoms).

The held-out mean of a run is the mean of its fitness over the terrains
(as ``locustjump evaluate RUN --terrain-seeds`` computes, which it equals at
the training physics); the gap is its training fitness minus that, at the
training physics only. "Gain in the last third": the share of a run's whole
improvement made in its last third of generations (near 0: its learning
curve had flattened; ``runs.study_table.late_gain``; the tables shipped in
results/debris*/ before 2026-11-26 give the share of the final fitness).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
from pathlib import Path
from typing import Any, cast

import numpy as np
from scipy.stats import mannwhitneyu

from locustjump import rundir
from locustjump.present.compare import TOTAL_LABEL, convergence_figure, load_groups
from locustjump.present.episodes import episode_score
from locustjump.runs.learning import late_gain
from locustjump.runs.multiseed import parse_seeds
from locustjump.sim import model as lm
from locustjump.sim.analysis import find_jumps, stuck_overturned
from locustjump.sim.controller import Controller
from locustjump.sim.engine.backends import Backend, ThreadBackend
from locustjump.sim.engine.job import CONTACT_RECORDS
from locustjump.sim.engine.rollout import RolloutResult, StartStates, rollout
from locustjump.sim.scene import Debris, Scene
from locustjump.tasks import get_behaviour
from locustjump.tasks.composed import OVERTURNED_UZ, START_ROLL, overturns
from locustjump.tasks.getup import rolled_starts
from locustjump.tasks.rules import (
    DEFAULT_CHANGE_TIME,
    RuleController,
    RuleGetupController,
)
from locustjump.tasks.starts import ready_state

STEPS = 3000
#: the field the rules and the flat-evolved runs are scored on: the walled
#: field of the shipped studies (wall margin 0, as those runs' own;
#: ``--wall-margin`` for today's default)
FIELD = Debris(wall_margin=0.0)


def episodes(
    ctrl: Controller,
    params: np.ndarray,
    starts: StartStates,
    p: lm.LocustParams,
    scene: Scene,
    backend: Backend,
) -> list[dict[str, Any]]:
    """Debris fitness and its terms, jumps, overturns, wall contact and
    deepest penetration of each controller row of ``params``
    (``present.episodes.episode_score`` in the composed behaviour's episode)."""
    record = ("qpos", "obs", *CONTACT_RECORDS)
    res = rollout(ctrl, params, starts, STEPS, model_params=p, scene=scene,
                  record=record, backend=backend)  # fmt: skip
    here = get_behaviour("monolithic").on(scene)  # the composed one's episode
    # the rubble's half width (m); a debris field here (FIELD's, or a run's own)
    half = cast(Debris, scene).width / 2 * p.body_length
    rows = []
    for e, (q, obs) in enumerate(zip(res["qpos"], res["obs"], strict=True)):
        one = RolloutResult({k: v[e : e + 1] for k, v in res.records.items()},
                            res.unstable[e : e + 1], res.steps[e : e + 1])  # fmt: skip
        score = episode_score(here, one, p, float(here.fitness(one, p)[0]))
        uz = obs[:, 8]
        over, rec = overturns(uz)
        jumps = find_jumps(q, p, scene)
        stuck = stuck_overturned(uz)
        end = len(q) - 1 if stuck is None else stuck
        rows.append({
            "fitness": score.fitness,
            "height_term": score.height_term,
            "distance_term": score.distance_term,
            "jumps": score.jumps,
            "jumps_before_stuck": sum(j.start < end for j in jumps),
            "overturned": over,
            "recovered": rec,
            "distance_m": score.distance_m,
            "highest_m": score.highest_m,
            "upright": float(np.mean(uz[1:] >= OVERTURNED_UZ)),
            "off_field": float(np.mean(np.abs(q[1:, 1]) > half)),
            "wall_contact": score.wall_contact,
            "penetration_m": score.penetration_m,
        })  # fmt: skip
    return rows


def references(
    flat: list[Path], seeds: list[int], p: lm.LocustParams, backend: Backend
) -> dict[str, list[dict[str, Any]]]:
    """Per controller label, its row on every terrain of ``seeds``."""
    rules = RuleController.for_model(p)
    hybrids = {
        "U_z < 0": RuleGetupController(rules, 0.0, 0.0),
        "U_z < 0.5, I6 >= 0.8": RuleGetupController(rules, 0.5, 0.8),
    }
    getups = [rundir.load_run(r / "getup")[2].genome for r in flat]
    out: dict[str, list[dict[str, Any]]] = {}
    for s in seeds:
        scene = FIELD.with_seed(s)
        starts = {"standing": ready_state(p, scene),
                  "side": rolled_starts(p, (START_ROLL,), scene)}  # fmt: skip
        for name, st in starts.items():
            out.setdefault(f"rules ({name})", []).append(
                episodes(
                    rules, rules.params_for(DEFAULT_CHANGE_TIME), st, p, scene, backend
                )[0]  # fmt: skip
            )
            for how, hybrid in hybrids.items() if getups else ():
                params = np.concatenate(
                    [hybrid.params_for(DEFAULT_CHANGE_TIME, g) for g in getups]
                )
                rows = episodes(hybrid, params, st, p, scene, backend)
                for r, row in zip(flat, rows, strict=True):
                    label = f"rules + flat getup {r.name}, {how} ({name})"
                    out.setdefault(label, []).append(row)
        for r in flat:
            for stage in ("composed", "monolithic"):
                row = run_rows(r / stage, [s], p, backend)[0]
                out.setdefault(f"flat {stage} {r.name}, zero-shot", []).append(row)
    return out


def run_rows(
    run: Path, seeds: list[int], p: lm.LocustParams, backend: Backend
) -> list[dict[str, Any]]:
    """A run's best genome in its behaviour's episode on each debris terrain
    of ``seeds`` (of its own debris parameters; the default ones for a run
    trained on the flat floor), simulated with ``p``'s physics."""
    _, beh, best = rundir.load_run(run)
    base = beh.terrains.scene
    base = FIELD if base.is_flat else base
    rows = []
    for s in seeds:
        here = beh.on(base.with_seed(s))
        rows += episodes(here.controller, best.genome[None], here.start_states(p), p,
                         here.scene, backend)  # fmt: skip
    return rows


def summary(label: str, rows: list[dict[str, Any]]) -> dict[str, Any]:
    f = np.array([r["fitness"] for r in rows])
    return {
        "controller": label,
        "median_fitness": float(np.median(f)),
        "mean_fitness": float(f.mean()),
        "jumps": float(np.mean([r["jumps"] for r in rows])),
        "jumps_before_stuck": float(np.mean([r["jumps_before_stuck"] for r in rows])),
        "overturned": float(np.mean([r["overturned"] for r in rows])),
        "recovered": float(np.mean([r["recovered"] for r in rows])),
        "distance_m": float(np.median([r["distance_m"] for r in rows])),
        "highest_m": float(max(r["highest_m"] for r in rows)),  # any terrain
        "upright": float(np.mean([r["upright"] for r in rows])),
        "off_field": float(np.mean([r["off_field"] for r in rows])),
        "height_term": float(np.mean([r["height_term"] for r in rows])),
        "distance_term": float(np.mean([r["distance_term"] for r in rows])),
        "wall_contact": float(np.mean([r["wall_contact"] for r in rows])),
        "penetration_m": float(max(r["penetration_m"] for r in rows)),  # any terrain
    }


def flat_floor(
    reproductions: list[Path], p: lm.LocustParams
) -> tuple[dict[str, list[float]], dict[str, list[float]]]:
    """Per group (composed, monolithic on the flat floor), each reproduction's
    fitness on the flat floor at ``p``'s physics and its gain in the last
    third."""
    held: dict[str, list[float]] = {}
    late: dict[str, list[float]] = {}
    for r in reproductions:
        for stage in ("composed", "monolithic"):
            cfg, beh, best = rundir.load_run(r / stage)
            model = dataclasses.replace(cfg.model, substeps=p.substeps)
            fit = beh.evaluate(best.genome[None], model, engine=cfg.engine)[0][0]
            held.setdefault(f"{stage} (flat floor)", []).append(float(fit))
            curve = rundir.read_metrics(r / stage / rundir.METRICS)["best"]
            late.setdefault(f"{stage} (flat floor)", []).append(late_gain(curve))
    return held, late


def group_table(
    what: str, held: dict[str, list[float]], late: dict[str, list[float]]
) -> list[dict[str, str | float]]:
    """Print per group its runs' ``what`` (one sample each), median and range,
    and a two-sided Mann-Whitney U test between every two groups; return the
    tests."""
    groups = sorted(held)
    print(f"\n| group | runs | {what} per run | median [min, max] | "
          "gain in the last third (median) |")  # fmt: skip
    print("| --- | --- | --- | --- | --- |")
    for g in groups:
        v = held[g]
        print(f"| {g} | {len(v)} | {', '.join(f'{x:.0f}' for x in v)} | "
              f"{np.median(v):.0f} [{min(v):.0f}, {max(v):.0f}] | "
              f"{np.median(late[g]):.0%} |")  # fmt: skip
    tests: list[dict[str, str | float]] = []
    for i, a in enumerate(groups):
        for b in groups[i + 1 :]:
            if len(held[a]) > 1 and len(held[b]) > 1:
                t = mannwhitneyu(held[a], held[b], alternative="two-sided")
                tests.append({"a": a, "b": b, "U": float(t.statistic),
                              "p": float(t.pvalue)})  # fmt: skip
                print(f"\nMann-Whitney U (two-sided), {a} vs {b}: "
                      f"U = {t.statistic:.0f}, p = {t.pvalue:.3f}")  # fmt: skip
    return tests


def group_of(run: Path) -> str:
    cfg = rundir.load_config(run / rundir.CONFIG)
    if cfg.behaviour == "monolithic":
        return "monolithic (debris)"
    if "flat-simples" in str(run):
        return "composed, flat simples"
    k = len(rundir.load_run(run)[1].terrains.scenes)
    return "composed, debris simples" + ("" if k == 2 else f", {k} terrains")


def learning_curves(runs: list[Path], path: Path) -> None:
    """The groups' training curves against the evaluations spent in all."""
    by_group: dict[str, list[Path]] = {}
    for r in runs:
        by_group.setdefault(group_of(r), []).append(r)
    groups = [
        dataclasses.replace(load_groups(rs, "behaviour", total_budget=True)[0], label=g)
        for g, rs in sorted(by_group.items())
    ]
    title = "debris: best training fitness, median and interquartile range over seeds"
    convergence_figure(groups, path, title=title, xlabel=TOTAL_LABEL)
    print(f"wrote {path}", file=sys.stderr)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--flat", nargs="*", type=Path, default=[],
                    help="flat-floor reproductions (their getup, composed, "
                    "monolithic)")  # fmt: skip
    ap.add_argument(
        "--runs",
        nargs="*",
        type=Path,
        default=[],
        help="debris-trained composed or monolithic runs",
    )
    ap.add_argument("--flat-study", nargs="*", type=Path, default=[],
                    help="flat-floor reproductions whose composed and "
                    "monolithic networks make the flat-floor group table")  # fmt: skip
    ap.add_argument("--terrain-seeds", default="100-119")
    ap.add_argument("--wall-margin", type=float, default=0.0,
                    help="the walls' contact margin (body lengths) of the field "
                    "the rules and flat runs are scored on (default 0: the "
                    "shipped studies' field; new scenes have 0.1)")  # fmt: skip
    ap.add_argument("--substeps", type=int, default=lm.LocustParams().substeps,
                    help="physics substeps per control step (training: 3; "
                    "12: converged physics)")  # fmt: skip
    ap.add_argument("--json", type=Path)
    ap.add_argument("--figure", type=Path, help="learning curves of the --runs")
    args = ap.parse_args(argv)
    seeds = parse_seeds(args.terrain_seeds)
    runs = [r for r in args.runs if rundir.is_run(r) and (r / rundir.BEST).is_file()]
    backend = ThreadBackend()
    p = lm.LocustParams(substeps=args.substeps)
    global FIELD
    FIELD = Debris(wall_margin=args.wall_margin)
    refs = references(args.flat, seeds, p, backend)
    table = [summary(k, v) for k, v in refs.items()]
    held: dict[str, list[float]] = {}
    gains: dict[str, list[float]] = {}
    for r in runs:
        rows = run_rows(r, seeds, p, backend)
        row = summary(f"{group_of(r)}: {r}", rows)
        train = rundir.load_run(r)[2].fitness
        mean = float(np.mean([x["fitness"] for x in rows]))
        as_trained = args.substeps == lm.LocustParams().substeps
        best = rundir.read_metrics(r / rundir.METRICS)["best"]
        row.update(
            train_fitness=train,
            gap=train - mean if as_trained else None,
            generations=len(best),
            late_gain=late_gain(best),
        )
        table.append(row)
        held.setdefault(group_of(r), []).append(mean)
        gains.setdefault(group_of(r), []).append(row["late_gain"])
    print(f"Debris terrains {args.terrain_seeds} (never trained on), "
          f"{args.substeps} physics substeps; fitness E: Eq. 4 above the ground "
          "under the body + 200 x forward progress (m x steps)\n")  # fmt: skip
    print(
        "| controller | median E | mean E | height term | distance term | jumps | "
        "jumps before stuck | overturned / recovered | time upright | "
        "time beside the rubble | wall contact | deepest penetration (m) | "
        "distance (m) | highest (m) | training E | gap | gain in the last third |"
    )
    print("| --- " * 17 + "|")
    for x in table:
        trained = f"{x['train_fitness']:.0f}" if "train_fitness" in x else ""
        gap = f"{x['gap']:.0f}" if x.get("gap") is not None else ""
        late = f"{x['late_gain']:.0%}" if "late_gain" in x else ""
        print(f"| {x['controller']} | {x['median_fitness']:.0f} | "
              f"{x['mean_fitness']:.0f} | {x['height_term']:.0f} | "
              f"{x['distance_term']:.0f} | {x['jumps']:.1f} | "
              f"{x['jumps_before_stuck']:.1f} | {x['overturned']:.1f} / "
              f"{x['recovered']:.1f} | {x['upright']:.0%} | {x['off_field']:.0%} | "
              f"{x['wall_contact']:.1%} | {x['penetration_m']:.4f} | "
              f"{x['distance_m']:.2f} | {x['highest_m']:.2f} | {trained} | "
              f"{gap} | {late} |")  # fmt: skip
    out = {"table": table, "held_out": held, "late_gain": gains}
    if held:
        print("\nDebris, held-out terrains:")
        out["tests"] = group_table("held-out mean E", held, gains)
    if args.flat_study:
        flat, flat_late = flat_floor(args.flat_study, p)
        print(f"\nThe flat floor beside it (Eq. 4, m x steps; {args.substeps} "
              "substeps):")  # fmt: skip
        out["flat_floor"] = flat
        out["flat_floor_late_gain"] = flat_late
        out["flat_floor_tests"] = group_table("E on the flat floor", flat, flat_late)
    if args.figure:
        learning_curves(runs, args.figure)
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
