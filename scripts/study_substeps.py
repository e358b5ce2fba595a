"""Issue #20: do the evolved controllers' scores survive finer physics?

Every run's best genome re-simulated with 3 (the default), 6, 12 and 24
physics substeps per control step, everything else as the run's config;
printed per group of runs (``--by``, as ``locustjump compare``): the median
[min, max] fitness at each, so that an optimizer, a fitness or a setting is
judged on what holds when the simulation converges, not on what only the
3-substep discretisation gives.

    .venv/bin/python scripts/study_substeps.py runs/study/kick-rcga-s* \\
        runs/study/kick-cma-s* [--by optimizer] [--runs] [--reference rcga]

``--reference LABEL`` adds, per other group and resolution, the two-sided
Mann–Whitney U (of the other group) and its p against that group.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

import numpy as np

from locustjump import rundir
from locustjump.present.compare import _key
from locustjump.present.ranktests import mann_whitney
from locustjump.rundir.config import TrainConfig

SUBSTEPS = (3, 6, 12, 24)


def fitness_at(run: Path) -> tuple[TrainConfig, list[float]]:
    """(config, fitness of the best genome at each of SUBSTEPS)."""
    cfg, beh, best = rundir.load_run(run)
    out = []
    for n in SUBSTEPS:
        p = dataclasses.replace(cfg.model, substeps=n)
        res = beh.simulate(best.genome[None], p, record=beh.record, engine=cfg.engine)
        out.append(float(beh.fitness(res, p)[0]))
    return cfg, out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs", nargs="+", type=Path)
    ap.add_argument("--by", default="optimizer", help="as locustjump compare --by")
    ap.add_argument("--runs", dest="each", action="store_true", help="a row per run")
    ap.add_argument(
        "--rule", action="store_true", help="also the rule-based jumper's Σz"
    )
    ap.add_argument("--reference", metavar="LABEL", help="rank tests against it")
    args = ap.parse_args(argv)
    groups: dict[str, list[list[float]]] = {}
    head = " | ".join(f"{n} substeps" for n in SUBSTEPS)
    if args.each:
        print(f"| run | {head} | at 12 / at 3 |")
        print("| --- " * (len(SUBSTEPS) + 2) + "|")
    for run in args.runs:
        if not rundir.is_run(run):
            print(f"error: {run}: holds no run", file=sys.stderr)
            return 2
        cfg, f = fitness_at(run)
        groups.setdefault(_key(cfg, args.by), []).append(f)
        if args.each:
            cells = " | ".join(f"{x:.4g}" for x in f)
            print(f"| {run.as_posix()} | {cells} | {f[2] / f[0]:.2f} |")
    if args.rule:
        from locustjump.sim import model as lm
        from locustjump.tasks.reference import run_rules

        z = []
        for n in SUBSTEPS:
            q = run_rules(steps=3000, model_params=lm.LocustParams(substeps=n)).qpos
            z.append(f"{q[1:, 2].sum():.4g}")
        print(f"| rule-based jumper, Σz from standing | {' | '.join(z)} | |")
    if args.each or args.rule:
        print()
    print(f"| group: median [min, max] | runs | {head} |")
    print("| --- " * (len(SUBSTEPS) + 2) + "|")
    for label, rows in groups.items():
        a = np.array(rows)
        cells = " | ".join(
            f"{np.median(c):.4g} [{c.min():.4g}, {c.max():.4g}]" for c in a.T
        )
        print(f"| {label} | {len(rows)} | {cells} |")
    if args.reference is not None:
        if args.reference not in groups:
            print(f"error: --reference {args.reference!r}: no such group",
                  file=sys.stderr)  # fmt: skip
            return 2
        ref = np.array(groups[args.reference])
        print(f"\nMann–Whitney U, p against {args.reference} (two-sided):\n")
        print(f"| group | {head} |")
        print("| --- " * (len(SUBSTEPS) + 1) + "|")
        for label, rows in groups.items():
            if label != args.reference:
                a = np.array(rows)
                if min(len(a), len(ref)) < 2:  # no test of a single run
                    cells = " | ".join("-" for _ in SUBSTEPS)
                else:
                    tests = (
                        mann_whitney(a[:, j], ref[:, j]) for j in range(len(SUBSTEPS))
                    )
                    cells = " | ".join(f"{u:g}, {pv:.3g}" for u, pv in tests)
                print(f"| {label} | {cells} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
