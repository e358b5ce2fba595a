"""Price of the debris scene: control steps per second of the same episodes on
the flat floor and on debris, in the same process, and the engine against
the physics alone on each.

Rule-based controllers (20 change times, 3000 steps, so that the creature
jumps, lands and overturns among the boxes) run through the engine on one
thread, on the flat floor and on debris terrains (walls included); the ratio
of medians over --repeats is what the rubble costs. Each engine rollout is
followed at once by an open-loop ``mujoco.rollout`` replay of its recorded
servo targets in the same scene (``_physics.py``): engine / physics near 1
means the engine runs at the physics rate there too. One warm-up rollout per
scene goes untimed.

With --touched-only each debris terrain's model is the bound of
``debris_collision.py`` (the engine's model less every box and wall these
episodes never touch, found by a first rollout): the most that culling work
which can never produce a contact could give, in this benchmark's currency.

    python benchmarks/scene_cost.py [--repeats 5] [--terrains 3] [--touched-only]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from collections.abc import Sequence
from pathlib import Path

import mujoco
import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from _physics import physics_only_seconds  # noqa: E402
from debris_collision import touched_only  # noqa: E402
from locustjump.sim import model as lm  # noqa: E402
from locustjump.sim.engine.backends import ThreadBackend  # noqa: E402
from locustjump.sim.engine.rollout import rollout  # noqa: E402
from locustjump.sim.scene import Debris, Flat, Scene  # noqa: E402
from locustjump.tasks.rules import RuleController  # noqa: E402
from locustjump.tasks.starts import ready_state  # noqa: E402


def _use_touched_only(
    p: lm.LocustParams,
    rc: RuleController,
    params: np.ndarray,
    scenes: Sequence[Scene],
    steps: int,
) -> None:
    """From here on, the engine and the replay load each debris scene's bound."""
    bound: dict[Scene, mujoco.MjModel] = {}
    with ThreadBackend(1) as backend:
        for scene in scenes:
            start = ready_state(p, scene)
            res = rollout(rc, params, start, steps, model_params=p,
                          record=("ctrl",), backend=backend, scene=scene)  # fmt: skip
            bound[scene] = touched_only(p, scene, start, res["ctrl"])
    load = lm.load_model
    # the stand-in takes the parameters always (no default): a narrower
    # signature than load_model's, and a lambda mypy cannot type from it
    lm.load_model = lambda q, scene=Flat(): (  # type: ignore[assignment,misc]
        lm.copy_model(bound[scene]) if scene in bound and q == p else load(q, scene)
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--terrains", type=int, default=3)
    ap.add_argument("--steps", type=int, default=3000)
    ap.add_argument("--touched-only", action="store_true")
    args = ap.parse_args()
    p = lm.LocustParams()
    rc = RuleController.for_model(p)
    params = rc.params_for(np.linspace(0.0, 1.0, 20))
    scenes = [Flat()] + [Debris(seed=s) for s in range(args.terrains)]
    if args.touched_only:
        _use_touched_only(p, rc, params, scenes[1:], args.steps)
    rate: dict[str, list[float]] = {"flat": [], "debris": []}
    ratio: dict[str, list[float]] = {"flat": [], "debris": []}
    with ThreadBackend(1) as backend:
        for scene in scenes:  # warm-up: compiled models, the engine's kernels
            rollout(rc, params, ready_state(p, scene), 10, model_params=p,
                    backend=backend, scene=scene)  # fmt: skip
        for _ in range(args.repeats):
            for scene in scenes:
                start = ready_state(p, scene)
                t0 = time.perf_counter()
                res = rollout(
                    rc, params, start, args.steps, model_params=p,
                    record=("ctrl",), backend=backend, scene=scene,
                )  # fmt: skip
                wall = time.perf_counter() - t0
                starts = start.take(np.zeros(len(params), dtype=int))
                phys = physics_only_seconds(p, starts, res["ctrl"], 1, 1, scene)
                rate[scene.name].append(res.control_steps / wall)
                ratio[scene.name].append(wall / phys)
    flat, debris = (statistics.median(rate[k]) for k in ("flat", "debris"))
    r_flat, r_debris = (statistics.median(ratio[k]) for k in ("flat", "debris"))
    print(f"flat floor: {flat:,.0f} control steps/s (median of {len(rate['flat'])}); "
          f"engine / physics {r_flat:.2f}")  # fmt: skip
    print(f"debris:     {debris:,.0f} control steps/s (median of "
          f"{len(rate['debris'])}, {args.terrains} terrains); "
          f"engine / physics {r_debris:.2f}")  # fmt: skip
    print(f"debris / flat: {debris / flat:.2f} of the flat floor's throughput")


if __name__ == "__main__":
    main()
