"""Control steps per second of the rollout engine vs the physics alone.

The engine runs a population of random 9-10-4 networks from the start state
(sensors, batched network, actuation, recording, mujoco.batch stepping). The
physics-only baseline replays the very same controls open-loop with
``mujoco.rollout`` (same model, same substeps, same thread count), so the ratio
is the price of closing the loop in Python. Medians of --repeats rundir.

    python benchmarks/throughput.py [--episodes 50] [--steps 300]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import mujoco
import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from _physics import physics_only_seconds  # noqa: E402
from locustjump.sim import model as lm  # noqa: E402
from locustjump.sim.controller import MLP  # noqa: E402
from locustjump.sim.engine.backends import ThreadBackend  # noqa: E402
from locustjump.sim.engine.rollout import RolloutJob, StartStates  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--episodes", type=int, default=50)
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    args = ap.parse_args()

    p = lm.LocustParams()
    m = lm.load_model(p)
    net = MLP()
    genomes = net.random_genomes(np.random.default_rng(0), args.episodes, scale=2.0)
    starts = StartStates.ready(m).take([0] * args.episodes)
    job = RolloutJob(p, net, genomes, starts, args.steps, record=("qpos", "ctrl"))
    n_ctrl = args.episodes * args.steps
    print(
        f"{args.episodes} episodes x {args.steps} control steps, "
        f"{p.substeps} substeps of {p.timestep * 1e3:.3f} ms, mujoco "
        f"{mujoco.__version__}; medians of {args.repeats}"
    )

    ref = ThreadBackend(1).run(job)

    rates = {}
    for nthread in args.threads:
        backend = ThreadBackend(nthread)
        backend.run(job)  # warm-up: builds the batch
        engine = []
        for _ in range(args.repeats):
            t0 = time.perf_counter()
            backend.run(job)
            engine.append(time.perf_counter() - t0)
        f = physics_only_seconds(p, starts, ref["ctrl"], nthread, args.repeats)
        e = statistics.median(engine)
        rates[nthread] = n_ctrl / e
        print(
            f"threads={nthread}: engine {n_ctrl / e:9.0f} control steps/s, "
            f"physics only {n_ctrl / f:9.0f} control steps/s, "
            f"engine/physics rate {f / e:.3f}"
        )
    if 1 in rates and 2 in rates:
        print(f"engine speed-up 2 threads vs 1: {rates[2] / rates[1]:.2f}x")


if __name__ == "__main__":
    main()
