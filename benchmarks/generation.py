"""Wall time of a training generation vs the physics-only time of its episodes.

A real run (``train``: GA, batched networks, fitness, metrics, atomic
checkpoint) at the paper's population is trained for ``warmup`` generations,
then resumed one generation at a time (the same backend and its cached
``Batch``); each generation's wall time is the one its ``metrics.csv``
records. From a copy of the GA checkpointed after the warm-up (the GA is
deterministic), the benchmark asks for the very genomes each generation
evaluated, records their servo targets, and right after that generation
times an open-loop ``mujoco.rollout`` replay of the same episodes (same
start states, substeps, threads): the physics-only time, measured under the
same load of the machine as its generation. Prints medians; issue
target: ratio <= 1.15. With ``--optimizer`` another optimizer trains (a
quality-diversity one is told the episodes' behaviour descriptors too, as
in training): its own cost (asking, telling, an archive, a checkpoint that
grows with every generation told) is in the generation's wall time.

    python benchmarks/generation.py [--behaviour kick] [--threads 2]
    python benchmarks/generation.py --behaviour composed --simple-from DIR
    python benchmarks/generation.py --optimizer map-elites
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from _physics import physics_only_seconds  # noqa: E402
from locustjump import rundir  # noqa: E402
from locustjump.evo import make_optimizer, optimizer_kinds, params_class  # noqa: E402
from locustjump.rundir.config import TrainConfig  # noqa: E402
from locustjump.runs.trainer import train  # noqa: E402
from locustjump.sim import model as lm  # noqa: E402
from locustjump.sim.controller import MLP  # noqa: E402
from locustjump.sim.engine.backends import ThreadBackend  # noqa: E402
from locustjump.sim.scene import Terrains  # noqa: E402
from locustjump.tasks import (  # noqa: E402
    BEHAVIOURS,
    SIMPLE_BEHAVIOURS,
    Behaviour,
    get_behaviour,
)

TARGET = 1.15


def _digest(simple: rundir.FrozenGenomes | None) -> str:
    return "" if simple is None else simple.digest


def simple_genomes(src: str | None) -> rundir.FrozenGenomes:
    """The composed stage's frozen networks: the best genomes of the simple
    stages of reproduction directory ``src``, or random ones (seeded)."""
    if src is not None:
        return rundir.FrozenGenomes.from_runs(
            SIMPLE_BEHAVIOURS,
            {s: Path(src) / s for s in SIMPLE_BEHAVIOURS},
            TrainConfig().model,
        )
    g = MLP().random_genomes(np.random.default_rng(0), len(SIMPLE_BEHAVIOURS))
    return rundir.FrozenGenomes(SIMPLE_BEHAVIOURS, g, ("random",) * 3, ("",) * 3)


@dataclass(frozen=True)
class GenerationTimes:
    """Per measured generation: wall seconds, physics-only seconds, steps."""

    behaviour: str
    wall_s: list[float]
    physics_s: list[float]
    control_steps: list[int]
    new_genomes: int
    start_states: int
    n_steps: int

    @property
    def median_wall_s(self) -> float:
        return statistics.median(self.wall_s)

    @property
    def median_physics_s(self) -> float:
        return statistics.median(self.physics_s)

    @property
    def ratio(self) -> float:
        """Median of the per-generation ratios engine / physics-only (NaN
        where the physics-only replay was not timed)."""
        if not self.physics_s:
            return float("nan")
        return statistics.median(
            a / b for a, b in zip(self.wall_s, self.physics_s, strict=True)
        )

    @property
    def steps_per_s(self) -> float:
        return statistics.median(
            n / w for n, w in zip(self.control_steps, self.wall_s, strict=True)
        )


def measure(
    behaviour: str,
    *,
    population: int = 50,
    warmup: int = 3,
    generations: int = 10,
    threads: int = 2,
    repeats: int = 3,
    simple: rundir.FrozenGenomes | None = None,
    engine: str | None = None,
    terrains: Terrains | None = None,
    optimizer: str = "rcga",
) -> GenerationTimes:
    """Train ``warmup + generations`` generations, then time physics-only
    replays of the measured generations' episodes. With ``terrains`` the run
    trains on them, and the replay is of every terrain's episodes, each in
    its own scene (their times summed)."""
    cfg = TrainConfig(
        behaviour=behaviour,
        generations=warmup + generations,
        optimizer=params_class(optimizer)(population=population),
    )
    if terrains is not None:
        cfg = cfg.replace(scene=terrains)
    if engine is not None:
        cfg = cfg.replace(engine=engine)
    simple = simple if get_behaviour(behaviour, None).requires else None
    beh = get_behaviour(behaviour, None if simple is None else simple.genomes,
                        terrains=cfg.scene)  # fmt: skip
    p = cfg.model
    backend = ThreadBackend(threads)
    frozen = simple if beh.requires else None  # train's default: None
    wall, steps, phys = [], [], []
    n_new = population  # genomes asked for a generation (known on a replay)
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "run"
        train(cfg.replace(generations=warmup), out, progress=False,
                   backend=backend, frozen=frozen)  # fmt: skip
        ga = make_optimizer(cfg.optimizer, beh.controller.num_params, cfg.seed)
        ga.load_state(rundir.read_checkpoint(
            out / rundir.CHECKPOINT,
            cfg.replace(frozen_digest=_digest(simple) if beh.requires else ""),
            beh.controller.num_params)[2])  # fmt: skip
        for g in range(warmup + 1, warmup + generations + 1):
            # one generation of the run (resumed: same backend, so the same
            # cached Batch), then at once the physics-only replay of its very
            # episodes, so both are timed under the same load of the machine
            train(cfg.replace(generations=g), out, progress=False,
                  backend=backend, resume=True, frozen=frozen)  # fmt: skip
            row = rundir.read_metrics(out / rundir.METRICS)
            wall.append(float(row["wall_s"][-1]))
            steps.append(int(row["control_steps"][-1]))
            genomes = ga.ask()
            n_new = len(genomes)
            fit, res = beh.evaluate(genomes, p, record=(*beh.record, "ctrl"),
                                    backend=backend, engine=cfg.engine)  # fmt: skip
            names = ga.descriptor_names
            ga.tell(fit, beh.describe(res, p, names) if names else None)
            phys.append(replay_seconds(beh, p, res["ctrl"], n_new, threads, repeats))
    return GenerationTimes(
        behaviour, wall, phys, steps, n_new, len(beh.start_states(p)), beh.n_steps
    )


def replay_seconds(
    beh: Behaviour,
    p: lm.LocustParams,
    ctrl: np.ndarray,
    n: int,
    threads: int,
    repeats: int,
) -> float:
    """Physics-only seconds of ``n`` genomes' episodes (servo targets
    ``ctrl``, terrain-major as ``evaluate`` concatenates them) on each of the
    behaviour's terrains, summed."""
    total, at = 0.0, 0
    for scene in beh.terrains.scenes:
        starts = beh.on(scene).start_states(p)
        k = n * len(starts)
        ep_starts = starts.take(np.tile(np.arange(len(starts)), n))
        total += physics_only_seconds(p, ep_starts, ctrl[at : at + k], threads,
                                      repeats, scene)  # fmt: skip
        at += k
    return total


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--behaviour", choices=list(BEHAVIOURS), default="kick")
    ap.add_argument("--optimizer", choices=optimizer_kinds(), default="rcga")
    ap.add_argument("--population", type=int, default=50)
    ap.add_argument("--generations", type=int, default=10, help="measured")
    ap.add_argument("--warmup", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--repeats", type=int, default=3, help="physics-only repeats")
    ap.add_argument(
        "--simple-from",
        metavar="DIR",
        help="composed: switch between the simple stages of this reproduction "
        "directory (default: random simple networks)",
    )
    args = ap.parse_args()

    t = measure(
        args.behaviour,
        population=args.population,
        warmup=args.warmup,
        generations=args.generations,
        threads=args.threads,
        repeats=args.repeats,
        simple=simple_genomes(args.simple_from)
        if args.behaviour == "composed"
        else None,
        optimizer=args.optimizer,
    )
    ratio = t.ratio
    print(
        f"{args.behaviour}, {args.optimizer}: population {args.population}, "
        f"{t.new_genomes} new "
        f"genomes x {t.start_states} start states x {t.n_steps} steps per "
        f"generation, {args.threads} threads, mujoco {mujoco.__version__}"
    )
    n = len(t.wall_s)
    print(f"generation (median of {n}): {t.median_wall_s * 1e3:8.1f} ms")
    print(f"physics only, same episodes (median): {t.median_physics_s * 1e3:8.1f} ms")
    print(f"control steps/s in training: {t.steps_per_s:,.0f}")
    verdict = "ok" if ratio <= TARGET else "OVER TARGET"
    print(
        f"generation / physics-only (median of per-generation ratios): {ratio:.3f} "
        f"(target <= {TARGET}: {verdict})"
    )


if __name__ == "__main__":
    main()
