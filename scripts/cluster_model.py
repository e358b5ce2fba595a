"""A prediction, not a measurement: wall time of one training generation per
stage on N Ray nodes, from parts measured on one 2-core machine.

Model (docs/performance.md, "On a cluster"). A generation is

    T(N) = D + R(N) + T_steps * s + W * ceil(E / (N * c)) / E

* D: the driver's own work per generation (optimizer, fitness, metrics,
  checkpoint) — ``benchmarks/ray_overhead.py --parts driver``;
* R(N): Ray's part: an actor call's round trip, shipping the job, and the
  results (``--parts serial``) sent over the network at ``--gbit`` Gbit/s;
* T_steps * s: the engine's serial work per control step ``s``
  (``benchmarks/serial.py``) for the episode's T_steps control steps, paid by
  every actor in parallel, so once;
* W: the core-seconds of the generation's parallel work (physics and the
  per-episode share of the engine), from the measured 2-thread generation:
  W = 2 * (G2 - D - T_steps * s); split over N nodes of c cores, but never
  finer than one episode per core (E episodes).

The defaults are measurements of 2026-11-22 on this 2-core VM with the
compiled step loop (the controllers called from Python once a control step,
``--engine numba-loop`` of the benchmarks), before the controllers moved into
MuJoCo's threads; that path's serial part is 4.8 us a step instead of 62.5
(docs/performance.md), which only lowers the predictions below. Pass others
to model another machine.

    python scripts/cluster_model.py [--cores 16] [--gbit 10]
"""

from __future__ import annotations

import argparse
import math

#: stage: (episodes E, control steps, G2 generation s on 2 threads, driver D s,
#: result MB per generation) — measured, see the module doc
MEASURED = {
    "kick": (50, 300, 0.254, 0.0045, 1.32),
    "getup": (250, 1000, 5.006, 0.0058, 18.0),
    "return-legs": (50, 1000, 0.763, 0.0067, 3.6),
    "composed": (50, 3000, 2.462, 0.0054, 13.2),
}
#: s per control step of the engine's serial work (compiled path, 50
#: episodes; an actor of a big cluster holds fewer, so this is an upper bound)
SERIAL_S = 62.5e-6
#: Ray: actor call round trip + shipping a job (s), measured on one node
RAY_CALL_S = 1.1e-3 + 2.3e-3


def predict(stage: str, nodes: int, cores: int, gbit: float) -> float:
    e, steps, g2, d, mb = MEASURED[stage]
    w = 2.0 * (g2 - d - steps * SERIAL_S)
    r = RAY_CALL_S + mb * 8e-3 / gbit
    return d + r + steps * SERIAL_S + w * math.ceil(e / (nodes * cores)) / e


def check() -> None:
    """The model against this machine's own Ray runs: 2 actors of 1 CPU."""
    measured = {"kick": 0.2728, "getup": 4.914, "return-legs": 0.8439,
                "composed": 2.351}  # fmt: skip
    print("check: 2 nodes x 1 core (ray 2x1 on this machine), same-node transfer")
    for stage, m in measured.items():
        t = predict(stage, 2, 1, 1e9)
        print(f"  {stage:<12} predicted {t * 1e3:7.0f} ms, measured {m * 1e3:7.0f} ms")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cores", type=int, default=16, help="cores per node")
    ap.add_argument("--gbit", type=float, default=10.0, help="network, Gbit/s")
    ap.add_argument("--nodes", type=int, nargs="+", default=[1, 4, 16, 64])
    args = ap.parse_args()
    print(
        f"PREDICTION: generation wall time, {args.cores} cores per node, "
        f"{args.gbit:g} Gbit/s; speed-up over the measured 2-core machine"
    )
    head = "".join(f"{f'{n} node' + 's' * (n > 1):>20}" for n in args.nodes)
    print(f"{'stage':<12}{'2 cores (measured)':>20}{head}")
    for stage, (_, _, g2, _, _) in MEASURED.items():
        cells = ""
        for n in args.nodes:
            t = predict(stage, n, args.cores, args.gbit)
            cells += f"{f'{t * 1e3:.0f} ms ({g2 / t:.1f}x)':>20}"
        print(f"{stage:<12}{f'{g2 * 1e3:.0f} ms':>20}{cells}")
    check()


if __name__ == "__main__":
    main()
