"""The engine's serial work per control step, apart from the C calls.

On the step loops (``numpy``; ``numba-loop``, the compiled kernel called once a
control step) the engine runs, per control step and on one core whatever the
thread count: sensors, the networks, the actuation rule, the touch reduction,
the instability check, the recording and the Python side of the
``Batch.rollout`` call. On ``numba`` (the default path: the controllers inside
MuJoCo's control callback, :mod:`locustjump.sim.engine.incallback`) all of that runs in
the batch's C threads, beside the physics, and a rollout is one C call.

This script times whole rollouts of ``--episodes`` episodes (random 9-10-4
networks from the five getup start states, tiled, ``--steps`` control steps,
the training record) and the time spent inside the C calls (``Batch.rollout``:
the physics, and on ``numba`` the controllers too, on the batch's thread
pool); the difference is the serial work. Rollouts of two lengths separate its
per-step part (the slope) from the per-rollout part (setup, record
allocation). Prints medians of ``--repeats`` rollouts per path, next to the C
time of one control step on 1 and 2 threads; the C time of ``numba`` over that
of ``numba-loop`` (the same physics, stepped without the controllers) is the
cost of the controllers inside the threads. Issue target: serial <= 20 us a
step at 50 episodes, <= 50 us at 250.

    python benchmarks/serial.py [--episodes 50 250] [--paths numpy numba-loop numba]
"""

from __future__ import annotations

import argparse
import statistics
import time
from typing import Any

import numpy as np
from mujoco.batch import Batch

from locustjump.sim import model as lm
from locustjump.sim.controller import MLP
from locustjump.sim.engine.compiled import run_compiled
from locustjump.sim.engine.rollout import RolloutJob, run_batch
from locustjump.tasks import get_behaviour

TARGETS = {50: 20.0, 250: 50.0}
PATHS = ("numpy", "numba-loop", "numba")
CORES = (1, 2, 4, 8, 16, 32, 64)


class _TimedCore:
    """Stands in for a Batch's C object; adds up the time inside rollout()."""

    def __init__(self, core: Any) -> None:
        self._core = core
        self.seconds = 0.0

    def rollout(self, *args: Any) -> Any:
        t0 = time.perf_counter()
        try:
            return self._core.rollout(*args)
        finally:
            self.seconds += time.perf_counter() - t0

    def __getattr__(self, name: str) -> Any:
        return getattr(self._core, name)


def measure(n: int, steps: int, threads: int, path: str) -> tuple[float, float]:
    """(serial, in C) seconds per control step of one rollout on ``path``."""
    p = lm.LocustParams()
    beh = get_behaviour("getup")
    starts = beh.start_states(p)
    genomes = MLP().random_genomes(np.random.default_rng(n), n)
    job = RolloutJob(
        p, MLP(), genomes, starts.take(np.arange(n) % len(starts)), steps, beh.record,
        engine="numpy" if path == "numpy" else "numba",
    )  # fmt: skip
    batch = Batch(lm.load_model(p), n, threads, persistent=True)
    core = _TimedCore(batch._b)
    object.__setattr__(batch, "_b", core)
    t0 = time.perf_counter()
    (run_compiled if path == "numba-loop" else run_batch)(batch, job)
    wall = time.perf_counter() - t0
    return (wall - core.seconds) / steps, core.seconds / steps


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--episodes", type=int, nargs="+", default=[50, 250])
    ap.add_argument(
        "--steps",
        type=int,
        nargs=2,
        default=[100, 400],
        help="two episode lengths: the per-step part is the slope",
    )
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--paths", nargs="+", choices=PATHS, default=list(PATHS))
    args = ap.parse_args()
    t1, t2 = args.steps
    print(
        f"median of {args.repeats} rollouts of {t1} and of {t2} control steps; "
        "serial per step = slope, per rollout = the rest (setup, records)"
    )
    print(
        f"{'episodes':>8} {'path':>10} {'serial us/step':>15} {'per rollout':>12} "
        f"{'in C 1t':>11} {'in C 2t':>11} {'target':>8}"
    )
    model: list[tuple[int, str, float, float, float]] = []
    for n in args.episodes:
        for path in args.paths:
            measure(n, 20, 1, path)  # warm-up (and the kernel's compilation)
            runs = {
                (T, th): [measure(n, T, th, path) for _ in range(args.repeats)]
                for T in (t1, t2)
                for th in (1, 2)
            }
            total = {
                k: statistics.median(r[0] * k[0] for r in v) for k, v in runs.items()
            }
            phys = {
                th: statistics.median(r[1] for r in runs[(t2, th)]) for th in (1, 2)
            }
            per_step = (total[(t2, 1)] - total[(t1, 1)]) / (t2 - t1)
            fixed = total[(t1, 1)] - t1 * per_step
            s = per_step * 1e6
            target = TARGETS.get(n)
            ok = (
                ""
                if target is None
                else f"{'ok' if s <= target else 'OVER'} {target:g}"
            )
            model.append((n, path, per_step, phys[1], phys[2]))
            print(
                f"{n:>8} {path:>10} {s:>15.1f} {fixed * 1e3:>10.2f}ms "
                f"{phys[1] * 1e6:>11.1f} {phys[2] * 1e6:>11.1f} {ok:>8}",
                flush=True,
            )

    print_model(model)


def print_model(rows: list[tuple[int, str, float, float, float]]) -> None:
    """PREDICTION (Amdahl): a control step on k cores costs s + p1 / k (serial
    work s, C time p1 on one core; never more cores than episodes), checked
    against the 2-thread measurement."""
    print(
        "\nPREDICTION: speed-up of a control step on k cores, s + p1/k "
        "(check: predicted vs measured 2 threads)"
    )
    print(
        f"{'episodes':>8} {'path':>10} {'2t pred/meas':>13}"
        + "".join(f"{k:>7}" for k in CORES)
    )
    for n, path, s, p1, p2 in rows:
        one = s + p1
        pred2, meas2 = s + p1 / 2, s + p2
        cells = "".join(f"{one / (s + p1 / min(k, n)):>6.1f}x" for k in CORES)
        print(f"{n:>8} {path:>10} {pred2 / meas2:>13.2f}{cells}")


if __name__ == "__main__":
    main()
