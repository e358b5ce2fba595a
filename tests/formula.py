"""A behaviour whose fitness is a formula of the genome (no physics), for
tests of the training loop and of what ``train`` writes and refuses: every
generation takes milliseconds, and every row and best genome can be stated
exactly. The ``formula`` fixture (``conftest.py``) registers it."""

from types import SimpleNamespace

import numpy as np

from locustjump.evo import RCGAParams
from locustjump.rundir.config import TrainConfig
from locustjump.tasks.composed import Composed
from locustjump.tasks.kick import Kick

STEPS = 7  # control steps an "episode" of the formula counts


class Formula(Kick):
    """The kick's network, scored by how close its genes are to 0.3."""

    name = "formula"
    fail_at: int | None = None  # a generation whose evaluation raises
    coarse = False  # whole numbers: many genomes tie
    calls = 0
    #: what each evaluation and description was given beside the genomes
    given: list = []

    @classmethod
    def reset(cls) -> None:
        cls.fail_at, cls.calls, cls.coarse, cls.given = None, 0, False, []

    def evaluate(self, genomes, p, *, backend=None, engine="", record=None, label=""):
        Formula.calls += 1
        if Formula.calls > 20:  # no run here asks for as many generations
            raise AssertionError("the loop went past its budget")
        if Formula.fail_at == Formula.calls:
            raise RuntimeError("the simulation broke")
        Formula.given.append((p, backend, engine))
        fit = -((genomes - 0.3) ** 2).sum(axis=1)
        if Formula.coarse:
            fit = np.floor(fit / 10)
        return fit, SimpleNamespace(control_steps=STEPS * len(genomes), x=genomes)

    def describe(self, res, p, names):
        Formula.given.append((p, names))
        return np.stack([np.abs(np.tanh(res.x[:, i])) for i in range(len(names))], 1)


def formula_config(**kw) -> TrainConfig:
    """4 generations of 6 genomes of the formula, seed 5 (``kw`` changes it)."""
    args = {"behaviour": "formula", "seed": 5, "generations": 4,
            "optimizer": RCGAParams(population=6)}  # fmt: skip
    return TrainConfig(**{**args, **kw})


class FormulaComposed(Composed):
    """The composed switcher's network over frozen simple networks, scored
    by the same formula (what it is built on is checked, not simulated)."""

    name = "formula-composed"

    def evaluate(self, genomes, p, *, backend=None, engine="", record=None, label=""):
        assert self.frozen is not None  # built on the frozen genomes
        return Formula.evaluate(self, genomes, p, backend=backend, engine=engine)
