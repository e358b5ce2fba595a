"""Wall time of a training generation vs the physics-only time of its episodes.

Trains ``--warmup + --generations`` generations of a behaviour at the paper's
population (a real run: GA, batched networks, fitness, metrics, atomic
checkpoint every generation) and takes the median per-generation wall time
from ``metrics.csv``. The baseline replays the episodes of a generation's worth
of genomes from the final population open-loop with ``mujoco.rollout`` (same
count, start states, threads). Issue target: ratio <= 1.15.

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
from locustjump.rcga import RCGAParams  # noqa: E402
from locustjump.rollout import ThreadBackend  # noqa: E402

TARGET = 1.15


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--behaviour", choices=BEHAVIOURS, default="kick")
    ap.add_argument("--population", type=int, default=50)
    ap.add_argument("--generations", type=int, default=10, help="measured")
    ap.add_argument("--warmup", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--repeats", type=int, default=5, help="physics-only repeats")
    args = ap.parse_args()

    cfg = runs.TrainConfig(
        behaviour=args.behaviour,
        generations=args.warmup + args.generations,
        rcga=RCGAParams(population=args.population),
    )
    beh, p = get_behaviour(args.behaviour), cfg.model
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "run"
        runs.train(cfg, out, progress=False, backend=ThreadBackend(args.threads))
        m = runs.read_metrics(out / runs.METRICS)[args.warmup :]
        with np.load(out / runs.CHECKPOINT) as z:
            genomes = z["population"][cfg.rcga.elite :]
    gen_s = statistics.median(m["wall_s"].tolist())
    steps = int(m["control_steps"][0])

    res = beh.simulate(genomes, p, record=("ctrl",), backend=ThreadBackend(1))
    starts = beh.start_states(p)
    starts = starts.take(np.tile(np.arange(len(starts)), len(genomes)))
    phys_s = physics_only_seconds(p, starts, res["ctrl"], args.threads, args.repeats)
    ratio = gen_s / phys_s
    print(
        f"{args.behaviour}: population {args.population}, {len(genomes)} new "
        f"genomes x {len(beh.start_states(p))} start states x {beh.n_steps} steps "
        f"per generation, {args.threads} threads, mujoco {mujoco.__version__}"
    )
    print(f"generation (median of {len(m)}): {gen_s * 1e3:8.1f} ms")
    print(f"physics only (median of {args.repeats}): {phys_s * 1e3:8.1f} ms")
    print(f"control steps/s in training: {steps / gen_s:,.0f}")
    verdict = "ok" if ratio <= TARGET else "OVER TARGET"
    print(f"generation / physics-only: {ratio:.3f} (target <= {TARGET}: {verdict})")


if __name__ == "__main__":
    main()
