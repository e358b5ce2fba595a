"""Price of the debris scene: control steps per second of the same episodes on
the flat floor and on debris, in the same process.

Rule-based controllers (20 change times, 3000 steps, so that the creature
jumps, lands and overturns among the boxes) run through the engine on one
thread, on the flat floor and on debris terrains; the ratio of medians over
--repeats is what the rubble costs.

    python benchmarks/scene_cost.py [--repeats 5] [--terrains 3]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from locustjump.sim import model as lm
from locustjump.sim.engine.backends import ThreadBackend
from locustjump.sim.engine.rollout import rollout
from locustjump.sim.scene import Debris, Flat
from locustjump.tasks.rules import RuleController
from locustjump.tasks.starts import ready_state


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--terrains", type=int, default=3)
    ap.add_argument("--steps", type=int, default=3000)
    args = ap.parse_args()
    p = lm.LocustParams()
    rc = RuleController.for_model(p)
    params = rc.params_for(np.linspace(0.0, 1.0, 20))
    scenes = [Flat()] + [Debris(seed=s) for s in range(args.terrains)]
    rate: dict[str, list[float]] = {"flat": [], "debris": []}
    with ThreadBackend(1) as backend:
        for _ in range(args.repeats):
            for scene in scenes:
                start = ready_state(p, scene)
                t0 = time.perf_counter()
                res = rollout(
                    rc, params, start, args.steps, model_params=p,
                    record=("qpos",), backend=backend, scene=scene,
                )  # fmt: skip
                wall = time.perf_counter() - t0
                rate[scene.name].append(res.control_steps / wall)
    flat, debris = (statistics.median(rate[k]) for k in ("flat", "debris"))
    print(f"flat floor: {flat:,.0f} control steps/s (median of {len(rate['flat'])})")
    print(f"debris:     {debris:,.0f} control steps/s (median of "
          f"{len(rate['debris'])}, {args.terrains} terrains)")  # fmt: skip
    print(f"debris / flat: {debris / flat:.2f} of the flat floor's throughput")


if __name__ == "__main__":
    main()
