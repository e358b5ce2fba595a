"""Issue #20: the references for "does composition help?", all on the composed
behaviour's fitness (Eq. 4, sum of the body's height z over 3000 control
steps):

* the rule-based jumper from its standing start (Fig. 4) and from the
  composed behaviour's start on its side (Fig. 11), where it cannot get up;
* the rules plus an evolved get-up network (``RuleGetupController``: the
  get-up network drives while U_z < below, and, for ``low`` = 0.8, only
  while the body centre is within ~0.11 m of the floor: I6 >= 0.8) from both
  starts, for the get-up network of every reproduction given;
* the evolved composed and monolithic controllers of those reproductions
  (their recorded Eq. 4 fitness, from the side).

Usage::

    .venv/bin/python scripts/study_references.py results/quick-seed0 \\
        results/long-seed0 results/paper-seed0 [--json FILE]
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from locustjump import rundir
from locustjump.sim import model as lm
from locustjump.sim.analysis import find_jumps
from locustjump.sim.controller import Controller
from locustjump.sim.engine.rollout import StartStates, rollout
from locustjump.tasks.composed import START_ROLL, overturns
from locustjump.tasks.getup import rolled_starts
from locustjump.tasks.rules import (
    DEFAULT_CHANGE_TIME,
    RuleController,
    RuleGetupController,
)

STEPS = 3000
#: (below, low): U_z under which, and I6 above which, the get-up network drives
HANDOVER = ((0.0, 0.0), (0.5, 0.8))


def episode(
    ctrl: Controller, params: np.ndarray, starts: StartStates, p: lm.LocustParams
) -> dict[str, float | int | bool]:
    """Sum of z over steps 1..3000, jumps, overturns of one episode."""
    res = rollout(ctrl, params, starts, STEPS, model_params=p, record=("qpos", "obs"))
    q, uz = res["qpos"][0], res["obs"][0, :, 8]
    over, rec = overturns(uz)
    jumps = find_jumps(q, p)
    return {
        "sum_z": float(q[1:, 2].sum()),
        "jumps": len(jumps),
        "mean_apex_m": float(np.mean([j.apex_height for j in jumps])) if jumps else 0.0,
        "overturned": over,
        "recovered": rec,
        "final_up_z": float(uz[-1]),
        "unstable": bool(res.unstable[0]),
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("reproductions", nargs="+", type=Path)
    ap.add_argument("--json", type=Path, help="also write the rows here")
    args = ap.parse_args(argv)
    for r in args.reproductions:
        if not rundir.is_run(r / "getup"):
            print(f"error: {r}: no getup run in it", file=sys.stderr)
            return 2
    p = lm.LocustParams()
    standing = StartStates.ready(lm.load_model(p))
    side = rolled_starts(p, (START_ROLL,))
    starts = {"standing": standing, "side": side}
    rules = RuleController.for_model(p)
    rows = []
    for name, st in starts.items():
        row = episode(rules, rules.params_for(DEFAULT_CHANGE_TIME), st, p)
        rows.append({"controller": "rule-based", "start": name, **row})
    for r in args.reproductions:
        _, _, best = rundir.load_run(r / "getup")
        for below, low in HANDOVER:
            hybrid = RuleGetupController(rules, below, low)
            params = hybrid.params_for(DEFAULT_CHANGE_TIME, best.genome)
            for name, st in starts.items():
                row = episode(hybrid, params, st, p)
                near = f", I6 >= {low:g}" if low else ""
                label = f"rules + {r.name} getup (U_z < {below:g}{near})"
                rows.append({"controller": label, "start": name, **row})
        for stage in ("composed", "monolithic"):
            f = r / stage / rundir.EVAL / "metrics.json"
            if f.is_file():
                m = json.loads(f.read_text())["metrics"]
                rows.append({
                    "controller": f"evolved {stage}, {r.name}",
                    "start": "side",
                    "sum_z": m["fitness"],
                    "jumps": m["jumps"],
                    "mean_apex_m": float(np.mean(m["apex_heights_m"] or [0.0])),
                    "overturned": m["overturned"],
                    "recovered": m["recovered"],
                    "final_up_z": m["final_up_z"],
                    "unstable": m["unstable"],
                })  # fmt: skip
    print("| controller | start | Σz (Eq. 4) | jumps | mean apex (m) | "
          "overturned / recovered | final U_z |")  # fmt: skip
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for x in rows:
        print(f"| {x['controller']} | {x['start']} | {x['sum_z']:.0f} | {x['jumps']} | "
              f"{x['mean_apex_m']:.2f} | {x['overturned']} / {x['recovered']} | "
              f"{x['final_up_z']:.2f} |")  # fmt: skip
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(rows, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
