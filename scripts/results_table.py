"""Markdown table of trained runs, as quoted in docs/results.md.

Re-simulates each run's best genome (``locustjump evaluate``); for getup runs
also runs the 180-state sweep (``locustjump sweep-getup``).

    python scripts/results_table.py runs/kick-paper-s0 runs/kick-paper-s1 ...
"""

from __future__ import annotations

import argparse
import statistics

from locustjump import rundir
from locustjump.present.evaluate import evaluate_run
from locustjump.tasks.getup import sweep_angles, sweep_getup


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", nargs="+")
    args = ap.parse_args(argv)
    rows: list[list[object]] = []
    header: list[str] = []  # nargs="+": set by the first run
    summary: list[float] = []
    kinds = {rundir.load_run(d)[0].behaviour for d in args.runs}
    if len(kinds) > 1:
        raise SystemExit(f"one behaviour per table, got {sorted(kinds)}")
    for d in args.runs:
        cfg, _, best = rundir.load_run(d)
        ev = evaluate_run(d)
        m = ev.metrics
        budget = f"{cfg.population} x {best.generation}/{cfg.generations}"
        if cfg.behaviour == "kick":
            header = ["seed", "pop x best-gen/gens", "E [m²]", "rule-based E",
                      "highest apex [m]", "apex / rule-based first apex",
                      "first-jump apex [m]", "take-off angle [deg]"]  # fmt: skip
            rows.append([cfg.seed, budget, f"{ev.fitness:.3f}",
                         f"{m['rules_fitness']:.3f}", f"{m['apex_height_m']:.2f}",
                         f"{m['apex_height_ratio_to_rules']:.2f}",
                         f"{m['first_jump_apex_height_m']:.2f}",
                         f"{m['takeoff_angle_deg']:.0f}"])  # fmt: skip
            summary.append(m["apex_height_ratio_to_rules"])
        elif cfg.behaviour == "getup":
            sw = sweep_getup(best.genome, cfg.model, sweep_angles(), engine=cfg.engine)
            header = ["seed", "pop x best-gen/gens", "fitness (mean U_z)",
                      "training states got up from", "sweep: got up from"]  # fmt: skip
            rows.append([cfg.seed, budget, f"{ev.fitness:.3f}", m["got_up_from"],
                         f"{sw.got_up} of {sw.n_sweep}"])  # fmt: skip
            summary.append(sw.got_up)
        else:
            header = ["seed", "pop x best-gen/gens", "fitness",
                      "final error hip_l/knee_l/hip_r/knee_r [deg]"]  # fmt: skip
            errs = "/".join(f"{e:.1f}" for e in m["final_error_deg"].values())
            rows.append([cfg.seed, budget, f"{ev.fitness:.4f}", errs])
        if not ev.matches:
            raise SystemExit(f"{d}: re-simulated fitness differs from the recorded one")
    print("| " + " | ".join(header) + " |")
    print("|" + " --- |" * len(header))
    for r in rows:
        print("| " + " | ".join(map(str, r)) + " |")
    if summary:
        print(f"\nmedian of the headline column: {statistics.median(summary):.3g}")


if __name__ == "__main__":
    main()
