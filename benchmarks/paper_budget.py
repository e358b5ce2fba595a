"""Wall time of ``locustjump reproduce --budget paper``, estimated per stage.

For each trained stage (kick, getup, return-legs, composed; the monolithic
baseline is beyond the paper and reported separately) a real run at the
paper's settings (population 50) is timed for a few generations after a
warm-up (``generation.measure``: each generation of ``train`` followed at
once by an open-loop ``mujoco.rollout`` replay of its very episodes), and the
median generation is extrapolated to the paper's 1000 generations. The
composed stage switches between the best genomes of a reproduction directory
(``--simple-from DIR``) or, without one, random simple genomes (seeded).

Prints per stage: the median generation, the estimate for 1000 generations,
control steps/s and the ratio engine / physics-only. The last line reads
``paper budget estimate: <minutes> min on <N> threads``.

    python benchmarks/paper_budget.py [--threads 2] [--simple-from results/quick-seed0]
    python benchmarks/paper_budget.py --scene debris --terrains 2

``--scene debris --terrains K``: the stages train on K debris terrains (the
debris study's ``studies/debris-composition-5seeds.toml``: K = 2), so a
generation simulates K times the episodes among the boxes; the physics-only
replay is of every terrain's episodes, each in its own scene.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import mujoco

sys.path.insert(0, str(Path(__file__).parent))
from generation import measure, simple_genomes  # noqa: E402
from locustjump.sim.scene import Terrains, scene_class  # noqa: E402

PAPER_GENERATIONS = 1000
STAGES = ("kick", "getup", "return-legs", "composed")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--generations", type=int, default=4, help="measured per stage")
    ap.add_argument("--warmup", type=int, default=1)
    ap.add_argument("--repeats", type=int, default=2, help="physics-only repeats")
    ap.add_argument("--simple-from", metavar="DIR", help="a reproduction directory")
    ap.add_argument("--stages", nargs="+", choices=STAGES, default=list(STAGES))
    ap.add_argument(
        "--engine",
        choices=("numpy", "numba", "numba-loop"),
        default="numba",
        help="numba-loop: the compiled path's step-by-step loop (the controllers "
        "called from Python once a control step, not inside MuJoCo's threads)",
    )
    ap.add_argument("--scene", choices=("flat", "debris"), default="flat")
    ap.add_argument("--terrains", type=int, default=1, help="training terrains")
    args = ap.parse_args()
    terrains = Terrains(scene_class(args.scene)(), args.terrains)
    engine = args.engine
    if engine == "numba-loop":
        from locustjump.sim.engine import incallback

        # run_batch then runs the step loop. The flag set is incallback's own
        # binding of the name it imports from callback (the one run_batch
        # reads), which incallback does not re-export: hence the ignore
        incallback.AVAILABLE = False  # type: ignore[attr-defined]
        engine = "numba"

    print(
        f"mujoco {mujoco.__version__}, {args.threads} threads, engine {args.engine}, "
        f"scene {args.scene} x {args.terrains} terrains, population 50, "
        f"{args.generations} measured generations per stage after {args.warmup}"
    )
    print(
        f"{'stage':<12} {'generation':>11} {'x1000':>10} {'steps/s':>9} "
        f"{'engine/physics':>15}"
    )
    total = 0.0
    simple = simple_genomes(args.simple_from) if "composed" in args.stages else None
    for stage in args.stages:
        t = measure(
            stage,
            warmup=args.warmup,
            generations=args.generations,
            threads=args.threads,
            repeats=args.repeats,
            simple=simple,
            engine=engine,
            terrains=terrains,
        )
        est = t.median_wall_s * PAPER_GENERATIONS
        total += est
        print(
            f"{stage:<12} {t.median_wall_s:>10.3f}s {est / 60:>8.1f}min "
            f"{t.steps_per_s:>9,.0f} {t.ratio:>15.3f}",
            flush=True,
        )
    print(f"paper budget estimate: {total / 60:.1f} min on {args.threads} threads")


if __name__ == "__main__":
    main()
