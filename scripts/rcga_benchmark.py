"""The RCGA on 10-D sphere and Rastrigin: the margins behind tests/test_rcga.py.

Population 50, 200 generations, initial genes uniform in [-5.12, 5.12], each
crossover operator with the default Gaussian mutation; 5 seeds. Prints the
median and worst best-fitness (maximised: minus the function value).

    python scripts/rcga_benchmark.py
"""

from __future__ import annotations

from typing import cast

import numpy as np

from locustjump.evo.rcga import CROSSOVERS, RCGA, RCGAParams


def sphere(x: np.ndarray) -> np.ndarray:
    return cast(np.ndarray, -np.sum(x**2, axis=1))  # (n,): a sum over axis 1


def rastrigin(x: np.ndarray) -> np.ndarray:
    value = 10 * x.shape[1] + np.sum(x**2 - 10 * np.cos(2 * np.pi * x), axis=1)
    return cast(np.ndarray, -value)  # (n,): a sum over axis 1


def main() -> None:
    cols = ["function", "crossover", "initial best (median)", "final best (median)"]
    print("| " + " | ".join([*cols, "final best (worst)"]) + " |")
    print("| --- | --- | --- | --- | --- |")
    for name, f in (("sphere", sphere), ("rastrigin", rastrigin)):
        for cx in CROSSOVERS:
            first, final = [], []
            for seed in range(5):
                ga = RCGA(10, RCGAParams(crossover=cx, init_scale=5.12), seed)
                for g in range(200):
                    x = ga.ask()
                    ga.tell(f(x))
                    if g == 0:
                        first.append(ga.best_fitness)
                final.append(ga.best_fitness)
            print(
                f"| {name} | {cx} | {np.median(first):.3g} | {np.median(final):.3g} "
                f"| {min(final):.3g} |"
            )


if __name__ == "__main__":
    main()
