"""Wall time of a training generation vs the physics-only time of its episodes.

A real run (``runs.train``: GA, batched networks, fitness, metrics, atomic
checkpoint) at the paper's population is advanced one generation at a time
with ``--resume``. Before each measured generation the benchmark asks a copy of
the checkpointed GA for that generation's genomes (the GA is deterministic, so
they are exactly the ones the run will evaluate), records their servo targets
once, and times an open-loop ``mujoco.rollout`` replay of the same episodes
(same start states, substeps, threads). The generation's wall time is the one
``metrics.csv`` records. Prints medians; issue target: ratio <= 1.15.

    python benchmarks/generation.py [--behaviour kick] [--threads 2]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
from pathlib import Path

import mujoco
import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from _physics import physics_only_seconds  # noqa: E402
from locustjump import runs  # noqa: E402
from locustjump.behaviours import BEHAVIOURS, get_behaviour  # noqa: E402
from locustjump.rcga import RCGA, RCGAParams  # noqa: E402
from locustjump.rollout import ThreadBackend  # noqa: E402

TARGET = 1.15


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--behaviour", choices=BEHAVIOURS, default="kick")
    ap.add_argument("--population", type=int, default=50)
    ap.add_argument("--generations", type=int, default=10, help="measured")
    ap.add_argument("--warmup", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--repeats", type=int, default=3, help="physics-only repeats")
    args = ap.parse_args()

    cfg = runs.TrainConfig(
        behaviour=args.behaviour,
        generations=args.warmup + args.generations,
        rcga=RCGAParams(population=args.population),
    )
    beh, p = get_behaviour(args.behaviour), cfg.model
    backend = ThreadBackend(args.threads)
    starts = beh.start_states(p)
    gen_s, phys_s = [], []
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "run"
        runs.train(cfg.replace(generations=args.warmup), out, progress=False,
                   backend=backend)  # fmt: skip
        for g in range(args.warmup, cfg.generations):
            with np.load(out / runs.CHECKPOINT) as z:
                ga = RCGA.from_state(beh.controller.num_params, cfg.rcga, dict(z))
            genomes = ga.ask()
            res = beh.simulate(genomes, p, record=("ctrl",), backend=backend)
            ep_starts = starts.take(np.tile(np.arange(len(starts)), len(genomes)))
            phys_s.append(physics_only_seconds(
                p, ep_starts, res["ctrl"], args.threads, args.repeats))  # fmt: skip
            runs.train(cfg.replace(generations=g + 1), out, progress=False,
                       backend=backend, resume=True)  # fmt: skip
            gen_s.append(float(runs.read_metrics(out / runs.METRICS)["wall_s"][-1]))
        steps = int(runs.read_metrics(out / runs.METRICS)["control_steps"][-1])
    gen, phys = statistics.median(gen_s), statistics.median(phys_s)
    ratios = [a / b for a, b in zip(gen_s, phys_s, strict=True)]
    ratio = statistics.median(ratios)
    print(
        f"{args.behaviour}: population {args.population}, {len(genomes)} new "
        f"genomes x {len(starts)} start states x {beh.n_steps} steps per "
        f"generation, {args.threads} threads, mujoco {mujoco.__version__}"
    )
    print(f"generation (median of {len(gen_s)}): {gen * 1e3:8.1f} ms")
    print(f"physics only, same episodes (median): {phys * 1e3:8.1f} ms")
    print(f"control steps/s in training: {steps / gen:,.0f}")
    verdict = "ok" if ratio <= TARGET else "OVER TARGET"
    print(
        f"generation / physics-only (median of per-generation ratios): {ratio:.3f} "
        f"(target <= {TARGET}: {verdict})"
    )


if __name__ == "__main__":
    main()
