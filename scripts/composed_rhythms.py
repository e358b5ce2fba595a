"""Issue #33: what the composed behaviour's switcher can reach with a
reproduction's three frozen simple networks — fixed rhythms scored on its
fitness (Eq. 4, the sum of the body's height over 3000 control steps, from
its start rolled 90 deg).

Each sequence picks one simple behaviour per switching period (120 control
steps, 25 periods), as the switcher does but blind to the sensors: named
rhythms (``G,R,K`` = getup, return-legs, kick, repeated) and ``--random N``
random sequences (seeded). Runs on the NumPy engine (the sequence controller
has no compiled form); a run's own switcher is scored on its engine by
``locustjump evaluate``.

Usage::

    .venv/bin/python scripts/composed_rhythms.py DIR [--random 60] [--seed 1]

where ``DIR`` holds ``kick/``, ``getup/`` and ``return-legs/`` runs (a
reproduction).
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from locustjump import rundir
from locustjump.sim import model as lm
from locustjump.sim.analysis import find_jumps
from locustjump.sim.controller import MLP, MLPWeights
from locustjump.sim.engine.rollout import rollout
from locustjump.tasks.composed import SIMPLE, SWITCH_EVERY, Composed, overturns

N_STEPS = Composed.n_steps
PERIODS = -(-N_STEPS // SWITCH_EVERY)
LETTERS = "KGR"  # SIMPLE's order: kick, getup, return-legs
RHYTHMS = ("G", "R", "K", "G,R,K", "G,K", "G,R,K,G", "G,R,R,K", "G,G,R,K",
           "G,K,K", "G,R,K,K")  # fmt: skip


@dataclass(frozen=True, eq=False)
class SequenceController:
    """Runs simple network ``seq[i, step // every]`` in episode ``i``;
    params (n, PERIODS) are indices into ``simple`` (3, 144)."""

    simple: np.ndarray
    every: int = SWITCH_EVERY
    network: MLP = field(default_factory=MLP)

    @property
    def num_params(self) -> int:
        return PERIODS

    @property
    def memory_size(self) -> int:
        return 1

    def prepare(self, params: np.ndarray) -> tuple[np.ndarray, MLPWeights]:
        return np.asarray(params), self.network.prepare(self.simple)

    def act(
        self,
        prepared: tuple[np.ndarray, MLPWeights],
        memory: np.ndarray,
        obs: np.ndarray,
        targets: np.ndarray,
        step: int,
    ) -> tuple[np.ndarray, np.ndarray]:
        seq, simple = prepared
        if step % self.every == 0:
            memory = seq[:, step // self.every].astype(np.float64)[:, None]
        chosen = memory[:, 0].astype(np.intp)
        weights = MLPWeights(*(w[chosen] for w in simple))
        return self.network.apply(weights, obs), memory


def rhythm(name: str) -> list[int]:
    """One period after another of ``name`` (e.g. ``G,R,K``), repeated."""
    cycle = [LETTERS.index(c) for c in name.split(",")]
    return [cycle[i % len(cycle)] for i in range(PERIODS)]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dir", type=Path, help="holds kick/, getup/, return-legs/")
    ap.add_argument("--random", type=int, default=60, help="random sequences")
    ap.add_argument("--seed", type=int, default=1, help="of the random sequences")
    args = ap.parse_args(argv)
    p = lm.LocustParams()
    dirs = {s: args.dir / s for s in SIMPLE}
    frozen = rundir.FrozenGenomes.from_runs(SIMPLE, dirs, p)
    rng = np.random.default_rng(args.seed)
    named = np.array([rhythm(n) for n in RHYTHMS], dtype=np.int64)
    rand = rng.integers(0, len(SIMPLE), (args.random, PERIODS))
    seqs = np.concatenate([named, rand])
    res = rollout(SequenceController(frozen.genomes), seqs,
                  Composed(frozen.genomes).start_states(p), N_STEPS,
                  model_params=p, record=("qpos", "obs"), engine="numpy")  # fmt: skip
    fit = res["qpos"][:, 1:, 2].sum(axis=1)
    rows = []
    for i in range(len(seqs)):
        over, rec = overturns(res["obs"][i, :, 8])
        rows.append((fit[i], len(find_jumps(res["qpos"][i], p)), over, rec))
    print("| sequence | E (m x steps) | jumps | overturned / recovered |")
    print("| --- | --- | --- | --- |")
    for name, (e, j, o, r) in zip(RHYTHMS, rows[: len(RHYTHMS)], strict=True):
        print(f"| {name} | {e:.1f} | {j} | {o} / {r} |")
    if args.random:
        e = np.array([r[0] for r in rows[len(RHYTHMS) :]])
        b = len(RHYTHMS) + int(np.argmax(e))
        best = "".join(LETTERS[k] for k in seqs[b])
        print(f"| {args.random} random: best {best} | {e.max():.1f} "
              f"(median {np.median(e):.1f}) | {rows[b][1]} | "
              f"{rows[b][2]} / {rows[b][3]} |")  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())
