"""What Ray costs, measured on this machine against the thread backend.

Part ``generations``: for each stage, the same training run (population 50,
same seed) with ``--backend threads`` and with ``--backend ray`` (a local Ray
instance with this machine's CPUs; 1 thread per actor, one actor per CPU, and
one actor with every CPU), alternated ``--rounds`` times so that drift of the
machine hits both alike; the per-generation wall times of ``metrics.csv``
after a warm-up are pooled and their medians compared. The runs must end with
the identical best genome (checked). Issue target: ray / threads <= 1.10 for
getup and composed.

Part ``serial``: the parts of a Ray generation that do not shrink with more
nodes, for the cluster model in docs/performance.md: the round trip of an
empty actor call, and the time to ship a stage's rollout job out and its
result back, per genome and per episode.

Part ``driver``: the driver's own work per generation (optimizer, fitness,
metrics, checkpoint), i.e. the generation's wall time minus the time inside
the backend: it does not shrink with more nodes.

Part ``seeds``: ``reproduce --seeds 0,1 --budget quick --backend ray`` (tasks
of ``--threads`` CPUs) against the two single-seed reproductions back to back
on the thread backend, videos off. Issue target: <= 1.05.

    python benchmarks/ray_overhead.py [--parts generations serial seeds]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from types import ModuleType
from typing import TypedDict

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from generation import simple_genomes  # noqa: E402
from locustjump import rundir  # noqa: E402
from locustjump.evo import RCGAParams  # noqa: E402
from locustjump.rundir.config import TrainConfig  # noqa: E402
from locustjump.runs.trainer import train  # noqa: E402
from locustjump.sim.engine.backends import Backend, ThreadBackend  # noqa: E402
from locustjump.sim.engine.job import RolloutJob, RolloutResult  # noqa: E402
from locustjump.tasks import get_behaviour  # noqa: E402

STAGES = ("kick", "getup", "return-legs", "composed")
TARGET_GEN, TARGET_SEEDS = 1.10, 1.05


class _Quiet(TypedDict):
    """The keywords of ``reproduce`` and ``reproduce_seeds`` that silence them."""

    progress: bool
    log: Callable[[str], None]
    videos: bool


def _ray(cpus: int) -> ModuleType:
    import ray

    if not ray.is_initialized():
        ray.init(
            num_cpus=cpus,
            include_dashboard=False,
            log_to_driver=False,
            configure_logging=False,
        )
    return ray


def _train(
    stage: str, gens: int, backend: Backend, simple: rundir.FrozenGenomes, tmp: str
) -> tuple[list[float], bytes]:
    cfg = TrainConfig(stage, 0, gens, RCGAParams(population=50))
    out = Path(tempfile.mkdtemp(dir=tmp)) / "run"
    frozen = simple if stage == "composed" else None  # train's default: None
    train(cfg, out, progress=False, backend=backend, frozen=frozen)
    wall = [float(w) for w in rundir.read_metrics(out / rundir.METRICS)["wall_s"]]
    return wall, (out / rundir.BEST).read_bytes()


def part_generations(args: argparse.Namespace, cpus: int) -> None:
    from locustjump.sim.engine.ray_backend import RayBackend

    _ray(cpus)
    simple = simple_genomes(args.simple_from)
    # made anew for every run and closed after it: actors hold their CPUs
    backends: dict[str, Callable[[], Backend]] = {
        f"threads({cpus})": lambda: ThreadBackend(cpus),
        f"ray {cpus}x1": lambda: RayBackend(actors=cpus, threads=1),
        f"ray 1x{cpus}": lambda: RayBackend(actors=1, threads=cpus),
    }
    print(
        f"\n== per generation, population 50, {args.generations} generations "
        f"({args.warmup} warm-up) x {args.rounds} rounds, medians =="
    )
    names = list(backends)
    head = "".join(f"{n:>14}" for n in names)
    print(f"{'stage':<12}{head}" + "".join(f"{'/' + n[4:]:>12}" for n in names[1:]))
    with tempfile.TemporaryDirectory() as tmp:
        for stage in args.stages:
            walls: dict[str, list[float]] = {n: [] for n in names}
            bests = set()
            for _ in range(args.rounds):
                for n, make in backends.items():
                    b = make()
                    w, best = _train(
                        stage, args.warmup + args.generations, b, simple, tmp
                    )
                    getattr(b, "close", lambda: None)()
                    walls[n] += w[args.warmup :]
                    bests.add(best)
            assert len(bests) == 1, f"{stage}: backends disagree"
            med = {n: statistics.median(w) for n, w in walls.items()}
            ratios = [med[n] / med[names[0]] for n in names[1:]]
            print(
                f"{stage:<12}"
                + "".join(f"{med[n] * 1e3:>12.1f}ms" for n in names)
                + "".join(f"{r:>12.3f}" for r in ratios),
                flush=True,
            )
    print(
        f"(ratio ray / threads; target <= {TARGET_GEN} for getup and composed; "
        "every backend ended with the same best genome)"
    )


def part_serial(args: argparse.Namespace, cpus: int) -> None:
    ray = _ray(cpus)

    # ray.remote applied as a call, not as a decorator (as ray_backend.py
    # does): mypy types neither what a class decorator makes of its class nor
    # a function under ray's (a ModuleType's, so untyped) decorator
    class Echo:
        def size(self, job: RolloutJob) -> int:
            return job.params.nbytes + job.starts.qpos.nbytes

        def result(self, like: object) -> object:
            return like

    a = ray.remote(num_cpus=0)(Echo).remote()
    reps = args.repeats

    def median_s(fn: Callable[..., object]) -> float:
        fn()
        ts = []
        for _ in range(reps):
            t0 = time.perf_counter()
            fn()
            ts.append(time.perf_counter() - t0)
        return statistics.median(ts)

    def noop() -> None:
        return None

    remote_noop = ray.remote(num_cpus=0)(noop)

    print(f"\n== serial parts of a Ray generation (median of {reps}) ==")
    rtt = median_s(lambda: ray.get(a.result.remote(None)))
    task = median_s(lambda: ray.get(remote_noop.remote()))
    print(
        f"actor call round trip (empty): {rtt * 1e6:.0f} us; "
        f"task round trip: {task * 1e6:.0f} us"
    )
    simple = simple_genomes(args.simple_from).genomes
    rng = np.random.default_rng(0)
    print(
        f"{'stage':<12} {'episodes':>8} {'job MB':>8} {'result MB':>10} "
        f"{'ship job':>10} {'get result':>11} {'per genome':>11} {'per episode':>12}"
    )
    for stage in args.stages:
        beh = get_behaviour(stage, simple if stage == "composed" else None)
        p = TrainConfig(stage).model
        g = rng.uniform(-1.0, 1.0, (50, beh.controller.num_params))
        res = beh.simulate(g, p, record=beh.record, backend=ThreadBackend(cpus))
        from locustjump.sim.engine.rollout import RolloutJob

        starts = beh.start_states(p)
        n = len(starts) * 50
        job = RolloutJob(
            p,
            beh.controller,
            np.repeat(g, len(starts), axis=0),
            starts.take(np.tile(np.arange(len(starts)), 50)),
            beh.n_steps,
            beh.record,
        )
        ship = median_s(lambda job=job: ray.get(a.size.remote(job))) - rtt
        back = (
            median_s(lambda res=res: ray.get(a.result.remote(res))) - rtt
        )  # both ways
        mb_job = (
            job.params.nbytes
            + sum(getattr(job.starts, f).nbytes for f in ("qpos", "qvel", "ctrl"))
        ) / 1e6
        mb_res = sum(v.nbytes for v in res.records.values()) / 1e6
        print(
            f"{stage:<12} {n:>8} {mb_job:>8.2f} {mb_res:>10.2f} "
            f"{ship * 1e3:>8.2f}ms {back * 1e3:>9.2f}ms "
            f"{ship / 50 * 1e6:>9.1f}us {back / n * 1e6:>10.1f}us",
            flush=True,
        )
    print(
        "(ship job: driver -> actor; get result: the result to the actor and "
        "back, an upper bound of one way; same node: Ray's shared-memory "
        "object store, a cluster adds the network)"
    )


class _TimedThreads(ThreadBackend):
    """The thread backend, adding up the seconds inside run()."""

    seconds = 0.0

    def run(self, job: RolloutJob) -> RolloutResult:
        t0 = time.perf_counter()
        try:
            return super().run(job)
        finally:
            self.seconds += time.perf_counter() - t0


def part_driver(args: argparse.Namespace, cpus: int) -> None:
    """Per generation, the driver's own work (optimizer, fitness, metrics,
    checkpoint): generation wall time minus the time inside the backend."""
    simple = simple_genomes(args.simple_from)
    print(f"\n== driver work per generation (population 50, threads({cpus})) ==")
    print(f"{'stage':<12} {'generation':>11} {'in backend':>11} {'driver':>9}")
    with tempfile.TemporaryDirectory() as tmp:
        for stage in args.stages:
            b = _TimedThreads(cpus)
            _train(stage, args.warmup, b, simple, tmp)  # warm-up (compile, caches)
            b.seconds = 0.0
            wall, _ = _train(stage, args.generations, b, simple, tmp)
            total = sum(wall)
            per = total / len(wall)
            inside = b.seconds / len(wall)
            driver = per - inside
            print(
                f"{stage:<12} {per * 1e3:>9.1f}ms {inside * 1e3:>9.1f}ms "
                f"{driver * 1e3:>7.1f}ms",
                flush=True,
            )


def part_seeds(args: argparse.Namespace, cpus: int) -> None:
    from locustjump.runs.multiseed import reproduce_seeds
    from locustjump.runs.reproduce import reproduce

    _ray(cpus)
    quiet: _Quiet = {"progress": False, "log": lambda s: None, "videos": False}
    print(f"\n== two seeds x quick budget, {cpus} CPUs ==")
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        for s in (0, 1):
            reproduce(
                Path(tmp) / f"single-{s}",
                budget="quick",
                seed=s,
                backend=ThreadBackend(cpus),
                **quiet,
            )
        back_to_back = time.perf_counter() - t0
        print(f"back to back, threads({cpus}): {back_to_back / 60:.2f} min", flush=True)
        for threads in args.seed_threads:
            t0 = time.perf_counter()
            reproduce_seeds(
                Path(tmp) / f"ray-{threads}",
                [0, 1],
                budget="quick",
                backend="ray",
                threads=threads,
                **quiet,
            )
            wall = time.perf_counter() - t0
            print(
                f"reproduce --seeds 0,1 --backend ray --threads {threads}: "
                f"{wall / 60:.2f} min = {wall / back_to_back:.3f}x back to back "
                f"(target <= {TARGET_SEEDS})",
                flush=True,
            )
            for s in (0, 1):
                a = rundir.seed_dir(Path(tmp) / f"ray-{threads}", s) / "composed"
                b = Path(tmp) / f"single-{s}" / "composed"
                assert (a / rundir.BEST).read_bytes() == (b / rundir.BEST).read_bytes()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--parts",
        nargs="+",
        default=["generations", "serial", "driver", "seeds"],
        choices=["generations", "serial", "driver", "seeds"],
    )
    ap.add_argument("--stages", nargs="+", choices=STAGES, default=list(STAGES))
    ap.add_argument("--generations", type=int, default=4, help="measured per run")
    ap.add_argument("--warmup", type=int, default=1)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--repeats", type=int, default=9, help="serial: repeats")
    ap.add_argument("--seed-threads", type=int, nargs="+", default=[2, 1])
    ap.add_argument("--simple-from", metavar="DIR", default="results/quick-seed0")
    args = ap.parse_args()
    cpus = os.cpu_count() or 1
    import mujoco
    import ray

    print(f"mujoco {mujoco.__version__}, ray {ray.__version__}, {cpus} CPUs")
    for part in args.parts:
        globals()[f"part_{part}"](args, cpus)


if __name__ == "__main__":
    main()
