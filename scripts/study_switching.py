"""Issue #20: can the frozen simple networks jump as well as the rule at all?

A hand-written switcher replaces the evolved one, so that no optimizer is
involved: every PERIOD control steps it selects get-up while the body is
overturned (U_z < 0.5), otherwise the kick after return-legs and return-legs
after the kick. Scored on the composed behaviour's fitness (Eq. 4, sum of z
over 3000 steps) from its start on the side (Fig. 11) and from standing, for
several periods (the paper's is 120) and kick networks.

Usage::

    .venv/bin/python scripts/study_switching.py results/paper-seed0 \\
        [--kick DIR ...] [--periods 30 60 120 240]

The get-up and return-legs networks come from the reproduction; the kick
network from it and from every ``--kick`` run directory (e.g. a kick-apex run).
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from locustjump import rundir
from locustjump.sim import model as lm
from locustjump.sim.analysis import find_jumps
from locustjump.sim.controller import MLP, MLPWeights
from locustjump.sim.engine.rollout import StartStates, rollout
from locustjump.tasks.composed import START_ROLL, overturns
from locustjump.tasks.getup import rolled_starts

STEPS = 3000
KICK, GETUP, RETURN = 0, 1, 2


@dataclass(frozen=True)
class HandSwitch:
    """Every ``every`` steps: get-up if overturned, else alternate kick and
    return-legs. params (n, 3 * 144): the three networks. Memory: selection."""

    every: int
    below: float = 0.5
    net: MLP = MLP()

    @property
    def num_params(self) -> int:
        return 3 * self.net.num_params

    @property
    def memory_size(self) -> int:
        return 1

    def prepare(self, params: np.ndarray) -> list[MLPWeights]:
        k = self.net.num_params
        return [self.net.prepare(params[:, i * k : (i + 1) * k]) for i in range(3)]

    def act(
        self,
        nets: list[MLPWeights],
        memory: np.ndarray,
        obs: np.ndarray,
        targets: np.ndarray,
        step: int,
    ) -> tuple[np.ndarray, np.ndarray]:
        if step % self.every == 0:
            last = memory[:, 0] if step else np.full(len(obs), float(RETURN))
            pick = np.where(last == KICK, RETURN, KICK)
            pick = np.where(obs[:, 8] < self.below, GETUP, pick)
            memory = pick.astype(np.float64)[:, None]
        sel = memory[:, 0].astype(int)
        out = np.stack([self.net.apply(w, obs) for w in nets])  # (3, n, 4)
        return out[sel, np.arange(len(obs))], memory


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("reproduction", type=Path)
    ap.add_argument("--kick", type=Path, nargs="*", default=[])
    ap.add_argument("--periods", type=int, nargs="+", default=[30, 60, 120, 240])
    args = ap.parse_args(argv)
    genome = {}
    for stage in ("kick", "getup", "return-legs"):
        if not rundir.is_run(args.reproduction / stage):
            print(f"error: {args.reproduction}: no {stage} run", file=sys.stderr)
            return 2
        genome[stage] = rundir.load_run(args.reproduction / stage)[2].genome
    kicks = {f"{args.reproduction.name} kick": genome["kick"]}
    for d in args.kick:
        kicks[f"{d.parent.name}/{d.name}"] = rundir.load_run(d)[2].genome
    p = lm.LocustParams()
    starts = {
        "side": rolled_starts(p, (START_ROLL,)),
        "standing": StartStates.ready(lm.load_model(p)),
    }
    print("| kick network | period | start | Σz | jumps | mean apex (m) | "
          "overturned / recovered |")  # fmt: skip
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for kname, kick in kicks.items():
        params = np.concatenate([kick, genome["getup"], genome["return-legs"]])[None]
        for every in args.periods:
            for sname, st in starts.items():
                res = rollout(HandSwitch(every), params, st, STEPS, model_params=p,
                              record=("qpos", "obs"))  # fmt: skip
                q, uz = res["qpos"][0], res["obs"][0, :, 8]
                jumps = find_jumps(q, p)
                apex = np.mean([j.apex_height for j in jumps]) if jumps else 0.0
                over, rec = overturns(uz)
                print(f"| {kname} | {every} | {sname} | {q[1:, 2].sum():.0f} | "
                      f"{len(jumps)} | {apex:.2f} | {over} / {rec} |")  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())
