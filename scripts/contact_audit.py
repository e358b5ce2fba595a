"""Issue #44: how deep trained controllers press into the world, and whether
they use the walls.

For every run given, its best genome in its behaviour's episode on each
terrain of ``--terrain-seeds`` (default 100-119, held out), at the physics it
trained with (``--substeps`` to change): per run, the share of control steps
touching a wall (mean over terrains, the largest, and on how many terrains
any), the deepest penetration of any contact (over every terrain and
substep) with its geoms, step and the speed they met at (along the contact
normal, and in all), the deepest into a wall,
and on how many terrains the deepest contact passes the 5 % body-length gate
``tests/test_debris.py`` applies to rule-based and random controllers. All
from :mod:`locustjump.present.episodes` (``score_run``, ``deepest_contact``).

Usage::

    .venv/bin/python scripts/contact_audit.py results/debris/long-seed*/composed \\
        results/debris/long-seed*/monolithic \\
        results/debris/long-flat-simples-composed-s* [--json FILE]
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

import numpy as np

from locustjump import rundir
from locustjump.present.episodes import deepest_contact, score_run
from locustjump.runs.multiseed import parse_seeds
from locustjump.sim import names
from locustjump.sim.engine.backends import Backend, ThreadBackend

#: the penetration gate of tests/test_debris.py (body lengths)
GATE_BL = 0.05


def audit(
    run: Path, seeds: list[int], substeps: int | None, backend: Backend
) -> dict[str, Any]:
    """One run's row (see the module's doc)."""
    cfg = rundir.load_config(run / rundir.CONFIG)
    p = cfg.model if substeps is None else cfg.model.replace(substeps=substeps)
    bl = p.body_length
    scores = score_run(run, terrain_seeds=seeds, substeps=substeps, backend=backend)
    worst = max(scores, key=lambda s: s.penetration_m)
    deep = deepest_contact(run, terrain=worst.terrain, substeps=substeps,
                           backend=backend)  # fmt: skip
    walls = [
        c for s in scores if s.wall_contact > 0
        for c in [deepest_contact(run, terrain=s.terrain, substeps=substeps,
                                  among=names.WALL, backend=backend)]
        if c is not None
    ]  # fmt: skip
    wall = max(walls, key=lambda c: c.depth_m, default=None)
    return {
        "run": str(run),
        "substeps": p.substeps,
        "body_length_m": bl,
        "terrains": [s.to_dict() for s in scores],
        "mean_fitness": float(np.mean([s.fitness for s in scores])),
        "mean_height_term": float(np.mean([s.height_term for s in scores])),
        "mean_distance_term": float(np.mean([s.distance_term for s in scores])),
        "wall_contact_mean": float(np.mean([s.wall_contact for s in scores])),
        "wall_contact_max": float(max(s.wall_contact for s in scores)),
        "terrains_touching_walls": sum(s.wall_contact > 0 for s in scores),
        "terrains_over_gate": sum(s.penetration_m > GATE_BL * bl for s in scores),
        "deepest": None if deep is None else deep.to_dict(),
        "deepest_wall": None if wall is None else wall.to_dict(),
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs", nargs="+", type=Path)
    ap.add_argument("--terrain-seeds", default="100-119")
    ap.add_argument("--substeps", type=int, help="default: as each run trained")
    ap.add_argument("--json", type=Path)
    args = ap.parse_args(argv)
    seeds = parse_seeds(args.terrain_seeds)
    rows = []
    with ThreadBackend() as backend:
        for run in args.runs:
            rows.append(audit(run, seeds, args.substeps, backend))
            print(f"done {run}", file=sys.stderr, flush=True)
    print(f"Terrains {args.terrain_seeds}; the gate: {GATE_BL:.0%} of a body length\n")
    print("| run | mean E | height term | distance term | wall contact: mean, "
          "max (terrains) | deepest (m, % BL): geoms, step, approach (speed) | "
          "deepest into a wall (m, % BL): geoms, approach (speed) | terrains over "
          "the gate |")  # fmt: skip
    print("| --- " * 8 + "|")
    for r in rows:
        bl, d, w = r["body_length_m"], r["deepest"], r["deepest_wall"]
        deep = (f"{d['depth_m']:.4f} ({d['depth_m'] / bl:.1%}): "
                f"{' / '.join(d['geoms'])}, terrain {d['terrain']} step {d['step']}, "
                f"{d['approach_speed']:.1f} ({d['speed']:.1f}) m/s")  # fmt: skip
        wall = "" if w is None else (
            f"{w['depth_m']:.4f} ({w['depth_m'] / bl:.1%}): {' / '.join(w['geoms'])}, "
            f"{w['approach_speed']:.1f} ({w['speed']:.1f}) m/s")  # fmt: skip
        walls = (f"{r['wall_contact_mean']:.1%}, {r['wall_contact_max']:.1%} "
                 f"({r['terrains_touching_walls']})")  # fmt: skip
        print(f"| {r['run']} | {r['mean_fitness']:.0f} | {r['mean_height_term']:.0f} | "
              f"{r['mean_distance_term']:.0f} | {walls} | {deep} | {wall} | "
              f"{r['terrains_over_gate']} |")  # fmt: skip
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
