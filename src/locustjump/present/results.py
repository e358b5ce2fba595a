"""``results.md`` of a reproduction: the paper's claims against ours.

Every row and section comes from the behaviours' reporters
(:meth:`~locustjump.present.stages.Reporter.claims`,
:meth:`~locustjump.present.stages.Reporter.report_section`, ``figures``)
and every number from the files of the reproduction directory: this module
only reads.
"""

from __future__ import annotations

import os
import platform
from pathlib import Path
from typing import Any

import mujoco
import numpy as np

from locustjump import rundir
from locustjump.present.render import VIDEO_FPS
from locustjump.present.stages import Claim, reporter_of
from locustjump.rundir.migrations import check_marker


def stage_summary(d: Path) -> dict[str, Any]:
    """What ``results.md`` needs of a finished stage: its budget, wall times
    (from ``metrics.csv``) and its ``eval/metrics.json``."""
    m = rundir.read_metrics(d / rundir.METRICS)
    ev = rundir.read_json(rundir.eval_metrics_path(d))
    return {
        "generations": int(m["generation"][-1]),
        "evaluations": int(m["evaluations"].sum()),
        "control_steps": int(m["control_steps"].sum()),
        "train_wall_s": float(m["wall_s"].sum()),
        "eval_wall_s": float(ev.get("eval_wall_s", 0.0)),
        "fitness": float(ev["fitness"]),
        "metrics": ev["metrics"],
        "record": ev,
    }


def minutes(s: float) -> str:
    return f"{s / 60:.1f} min" if s >= 60 else f"{s:.0f} s"


def results_markdown(out: Path) -> str:
    """``results.md`` of reproduction ``out``: its trained stages are the
    keys of ``reproduce.toml``'s ``generations`` table, in order."""

    out = Path(out)
    marker = check_marker(rundir.read_toml(out / rundir.MARKER), out / rundir.MARKER)
    stages = list(marker["generations"])
    videos = [rundir.RULES_DIR, *stages]
    rules = rundir.read_json(out / rundir.RULES_DIR / rundir.RULES_SUMMARY)
    info = {
        s: stage_summary(out / s)
        for s in stages
        if rundir.eval_metrics_path(out / s).is_file()
    }
    missing = [s for s in stages if s not in info]
    behaviours = {s: reporter_of(s) for s in stages}
    lines = [
        f"# Reproduction of Umemura et al.: budget `{marker['budget']}`, "
        f"seed {marker['seed']}",
        "",
        f"Produced by `{marker['command']}` (locustjump {marker['locustjump']}, "
        f"MuJoCo {mujoco.__version__}, {platform.machine()}, "
        f"{os.cpu_count()} CPUs). Every number below is read from the files of "
        "this directory; `locustjump replay DIR --out OUT` re-simulates the best "
        "genomes and checks that their fitness is the recorded one.",
        "",
    ]
    if missing == ["monolithic"] and "--no-monolithic" in marker["command"]:
        lines += [
            "**Left out:** the monolithic baseline (`--no-monolithic`; rerun the "
            "command above without it to add it).",
            "",
        ]
    elif missing:
        lines += [
            f"**Not finished:** stage{'s' * (len(missing) > 1)} "
            f"{', '.join(missing)} not run yet (rerun the command above, without "
            "`--no-monolithic`, to continue; the rows and sections that need "
            "them say so).",
            "",
        ]
    if marker["budget"] != "paper":
        lines += [
            f"**This is not the paper's budget** (population 50, 1000 generations "
            f"per stage): it is the `{marker['budget']}` budget below. Numbers at "
            "the paper's budget need `--budget paper`.",
            "",
        ]
    lines += [
        "## The paper's claims",
        "",
        "| claim (paper) | paper | ours | reproduced? (our criterion) |",
        "| --- | --- | --- | --- |",
    ]
    failed = []
    for s, beh in behaviours.items():
        record = info[s]["record"] if s in info else None
        claims = beh.claims(record)
        lines += [claim.row() for claim in claims]
        failed += [c for c in claims if c.ok is False]
    lines += ["", *_whys(failed)]
    for beh in behaviours.values():
        lines += beh.report_section(info)
    lines += held_out_markdown(
        {
            s: i["record"]["held_out"]
            for s, i in info.items()
            if "held_out" in i["record"]
        }
    )
    lines += _budget_table(marker, rules, info)
    lines += ["## Figures", ""]
    figures = [
        (
            "Rule-based successive jumping (Fig. 5):",
            "rule-based",
            f"{rundir.RULES_DIR}/{rundir.TRAJECTORY_PNG}",
        )
    ]
    for s, beh in behaviours.items():
        figures += [(caption, alt, f"{s}/{f}") for f, alt, caption in beh.figures]
    for caption, alt, fig in figures:
        if (out / fig).is_file():
            lines += [caption, ""] if caption else []
            lines += [f"![{alt}]({fig})", ""]
    for s in info:
        lines += [
            f"Fitness per generation, {s}:",
            "",
            f"![{s}]({s}/{rundir.FITNESS_PNG})",
            "",
        ]
    vids = [
        f"`{s}/{rundir.VIDEO}`" for s in videos if (out / s / rundir.VIDEO).is_file()
    ]
    if vids:
        lines += [
            "## Videos",
            "",
            f"Each stage's best controller ({VIDEO_FPS:g} fps, tracking camera; "
            "`locustjump render` makes more, `locustjump report` embeds them): "
            + ", ".join(vids)
            + ".",
            "",
        ]
    return "\n".join(lines)


def _budget_table(
    marker: dict[str, Any], rules: dict[str, Any], info: dict[str, dict[str, Any]]
) -> list[str]:
    lines = [
        "## Budget and wall time",
        "",
        "| stage | population | generations | genome evaluations | control steps | "
        "training wall time | evaluation |",
        "| --- | --- | --- | --- | --- | --- | --- |",
        f"| rules | - | - | - | 3,000 | - | {minutes(rules['wall_s'])} |",
    ]
    total = rules["wall_s"]
    for s, i in info.items():
        total += i["train_wall_s"] + i["eval_wall_s"]
        lines.append(
            f"| {s} | {marker['population']} | {i['generations']} | "
            f"{i['evaluations']:,} | {i['control_steps']:,} | "
            f"{minutes(i['train_wall_s'])} | {minutes(i['eval_wall_s'])} |"
        )
    return lines + [
        f"| **total** | | | | | {minutes(total)} | |",
        "",
        "Training wall time is the sum of the per-generation times in each "
        "stage's `metrics.csv` (exact across interruptions).",
        "",
    ]


def _whys(failed: list[Claim], *, this_run: bool = True) -> list[str]:
    """Why these claims fail, once per claim: this run's own reason (where
    ``this_run``) and what a study measured beyond it."""
    whys = {}
    for c in failed:
        parts = [f"this run: {c.reason}" if this_run and c.reason else ""]
        parts.append(f"beyond this run: {c.why}" if c.why else "")
        if any(parts):
            whys[c.text] = "; ".join(p for p in parts if p)
    if not whys:
        return []
    return [
        "Why the failing claims fail:",
        "",
        *(f"- **{text}**: {why}." for text, why in whys.items()),
        "",
    ]


def _num(x: float) -> str:
    return f"{x:.0f}" if float(x).is_integer() else f"{x:.2f}"


def _spread(values: list[float]) -> str:
    """``median [min, max]`` of ``values`` (``n/a`` when empty)."""
    if not values:
        return "n/a"
    v = np.asarray(values, dtype=float)
    return f"{_num(float(np.median(v)))} [{_num(v.min())}, {_num(v.max())}]"


def _seeds(seeds: list[int]) -> str:
    """``100-119`` for a contiguous range, else the seeds listed."""
    if seeds == list(range(seeds[0], seeds[0] + len(seeds))) and len(seeds) > 2:
        return f"{seeds[0]}-{seeds[-1]}"
    return ", ".join(map(str, seeds))


def held_out_markdown(records: dict[str, dict[str, Any]]) -> list[str]:
    """The section on terrains training never saw: per stage (name ->
    :meth:`TerrainEvaluation.to_dict`) the training fitness, the held-out one
    and the generalisation gap, and over the held-out terrains the median and
    range of the fitness, of the jumps and of the falls and recoveries."""
    if not records:
        return []
    first = next(iter(records.values()))
    seeds = [t["seed"] for t in first["terrains"] if not t["trained"]]
    if not seeds:
        return []
    lines = [
        "## On terrains training never saw",
        "",
        f"Each best genome re-scored on {first['scene']} terrains "
        f"{_seeds(seeds)}, none of them a training terrain (`locustjump evaluate "
        f"DIR --terrain-seeds {_seeds(seeds).replace(', ', ',')}` prints them "
        "one by one). Held out: the training aggregate "
        f"({first['aggregate']}) over them; gap: the training fitness minus it.",
        "",
        "| controller | training fitness | held out | per terrain: median [min, max] "
        "| gap | jumps | overturned / recovered |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for stage, r in records.items():
        held = [t for t in r["terrains"] if not t["trained"]]
        ms = [t["metrics"] for t in held]

        def spread(key: str, ms: list[dict[str, Any]] = ms) -> str:
            v = [m[key] for m in ms if isinstance(m.get(key), int | float)]
            return _spread(v) if len(v) == len(ms) else "n/a"

        falls = (
            f"{spread('overturned')} / {spread('recovered')}"
            if all("overturned" in m for m in ms)
            else "n/a"
        )
        lines.append(
            f"| {stage} | {r['train_fitness']:.4g} | {r['held_out_fitness']:.4g} | "
            f"{_spread([t['fitness'] for t in held])} | "
            f"{r['generalisation_gap']:+.4g} | {spread('jumps')} | {falls} |"
        )
    return [
        *lines,
        "",
        "Jumps and falls: median [min, max] over the held-out terrains.",
        "",
    ]


def seeds_markdown(out: Path) -> str:
    """``results.md`` of a reproduction over several seeds: per claim of the
    paper the median, range and count of seeds that reproduce it; per stage the
    best fitness; the behaviours' own sections; each seed's claims."""
    out = Path(out)
    path = out / rundir.SEEDS_MARKER
    marker = check_marker(rundir.read_toml(path), path)
    seeds, stages = marker["seeds"], list(marker["generations"])
    behaviours = {s: reporter_of(s) for s in stages}
    info: dict[int, dict[str, dict[str, Any]]] = {
        seed: {
            s: stage_summary(rundir.seed_dir(out, seed) / s)
            for s in stages
            if rundir.eval_metrics_path(rundir.seed_dir(out, seed) / s).is_file()
        }
        for seed in seeds
    }
    unfinished = [seed for seed in seeds if len(info[seed]) < len(stages)]
    lines = [
        f"# Reproduction of Umemura et al. over {len(seeds)} seeds: budget "
        f"`{marker['budget']}`, optimizer `{marker['optimizer']}`",
        "",
        f"Produced by `{marker['command']}` (locustjump {marker['locustjump']}). "
        "Seed *s* is a reproduction of its own in `seed-<s>/`, the same as "
        "`locustjump reproduce --seed s` writes, with its `results.md`; every "
        "number below is read from those directories.",
        "",
    ]
    if unfinished:
        lines += [
            f"**Not finished:** seed{'s' * (len(unfinished) > 1)} "
            f"{', '.join(map(str, unfinished))} (rerun the command to continue).",
            "",
        ]
    lines += [
        "## The paper's claims across seeds",
        "",
        "| claim (paper) | paper | ours: median [min, max] | measure | reproduced in |",
        "| --- | --- | --- | --- | --- |",
    ]
    failed = []
    for s, beh in behaviours.items():
        runs = [
            beh.claims(info[seed][s]["record"]) for seed in seeds if s in info[seed]
        ]
        failed += [c for claims in runs for c in claims if c.ok is False]
        # across seeds, each seed's own reason is in its results.md
        for i, claim in enumerate(beh.claims(None)):
            got = [c[i] for c in runs]
            values = [c.value for c in got if c.value is not None]
            count = (
                f"{sum(bool(c.ok) for c in got)} of {len(got)} seeds" if got else "-"
            )
            measure = got[0].measure if got else ""
            lines.append(
                f"| {claim.text} | {claim.paper} | {_spread(values)} | {measure} | "
                f"{count} |"
            )
    lines += ["", *_whys(failed, this_run=False)]
    lines += [
        "## Best fitness per stage",
        "",
        "| stage | seeds done | median [min, max] | per seed |",
        "| --- | --- | --- | --- |",
    ]
    for s in stages:
        best = {seed: info[seed][s]["fitness"] for seed in seeds if s in info[seed]}
        per = ", ".join(f"{seed}: {f:.4g}" for seed, f in best.items()) or "-"
        lines.append(
            f"| {s} | {len(best)} of {len(seeds)} | {_spread(list(best.values()))} | "
            f"{per} |"
        )
    lines.append("")
    for beh in behaviours.values():
        lines += beh.across_seeds(info)
    lines += ["## Per seed", ""]
    for seed in seeds:
        d = rundir.seed_dir(out, seed).name
        lines += [
            f"### Seed {seed} ([results]({d}/{rundir.RESULTS}))",
            "",
            "| claim (paper) | paper | ours | reproduced? (our criterion) |",
            "| --- | --- | --- | --- |",
        ]
        for s, beh in behaviours.items():
            record = info[seed][s]["record"] if s in info[seed] else None
            lines += [claim.row() for claim in beh.claims(record)]
        lines.append("")
    return "\n".join(lines)
