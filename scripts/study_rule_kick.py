"""Issue #20: which rule-based kick would make the paper's "2x" true?

The rule-based jumper's first jump from the Fig. 4 start (the reference of
the paper's Fig. 7 and of our claim row), for

1. kick rates below the paper's maximum of 10 deg per control step, at the
   model's kick posture, and
2. every kick posture of a grid (hip x knee, degrees) at the maximum rate,

printed as apex rise (m above the start) and as the fraction of the ceiling:
the highest apex rise any of the given ``kick-apex``/``kick-apex-open`` runs
reached (``docs/science.md``). A rule whose first rise is at most half the
ceiling is one against which "the evolved kick jumps 2x as high" can be true.

    .venv/bin/python scripts/study_rule_kick.py runs/study/kick-apex*
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

from locustjump import rundir
from locustjump.sim import analysis
from locustjump.sim import model as lm
from locustjump.sim.engine.rollout import StartStates, rollout
from locustjump.tasks.rules import DEFAULT_CHANGE_TIME, RuleController

RATES = (10, 8, 6, 5, 4, 3, 2)  # deg per control step
HIPS = range(60, 131, 10)
KNEES = range(40, 161, 20)


def first_rise(rc: RuleController, p: lm.LocustParams) -> float:
    """Apex rise (m) of the first jump in 600 control steps; 0 if none."""
    res = rollout(rc, rc.params_for(DEFAULT_CHANGE_TIME),
                  StartStates.ready(lm.load_model(p)), 600, model_params=p,
                  record=("qpos",))  # fmt: skip
    q = res["qpos"][0]
    jumps = analysis.find_jumps(q, p)
    return jumps[0].apex_height - q[0, 2] if jumps else 0.0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs", nargs="+", type=Path, help="kick-apex run directories")
    args = ap.parse_args()
    best: dict[Path, float] = {}
    for d in args.runs:
        cfg, _, b = rundir.load_run(d)
        if not cfg.behaviour.startswith("kick-apex"):
            sys.exit(f"error: {d}: a {cfg.behaviour} run, not an apex run")
        best[d] = b.fitness
    top = max(best, key=best.__getitem__)
    ceiling = best[top]
    print(f"ceiling: apex rise {ceiling:.3f} m ({top}, best of {len(best)} runs)\n")
    p = lm.LocustParams()
    base = RuleController.for_model(p)

    def frac(h: float) -> str:
        return f"{h / ceiling:.2f}" + (" (≤ ½)" if h <= ceiling / 2 else "")

    print("| rule-based kick rate (deg/step) | first apex rise (m) | "
          "fraction of the ceiling |")  # fmt: skip
    print("| --- | --- | --- |")
    for rate in RATES:
        rc = RuleController(base.ready, base.extended, math.radians(rate))
        h = first_rise(rc, p)
        print(f"| {rate} | {h:.3f} | {frac(h)} |")
    print(f"\nKick posture at 10 deg/step: fraction of the ceiling (model's: hip "
          f"{p.kick_hip:g}, knee {p.kick_knee:g})\n")  # fmt: skip
    print("| hip \\ knee (deg) | " + " | ".join(map(str, KNEES)) + " |")
    print("| --- " * (len(KNEES) + 1) + "|")
    for hip in HIPS:
        cells = []
        for knee in KNEES:
            kick = np.radians([hip, knee, hip, knee])
            cells.append(frac(first_rise(RuleController(base.ready, tuple(kick)), p)))
        print(f"| {hip} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
