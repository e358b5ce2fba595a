"""Stand tall: a behaviour whose module registers it (its entry point names
the module, ``stand-tall = tinyplug.stand``), with an option of its own."""

from dataclasses import dataclass

from locustjump.tasks import Behaviour, register_behaviour
from locustjump.tasks.base import CommonOptions, option
from locustjump.tasks.kick import ready_start

N_STEPS = 100  # control steps


@dataclass(frozen=True)
class StandOptions(CommonOptions):
    settle_steps: int = option(0, "steps that do not count (default 0)", "STEPS")

    def __post_init__(self) -> None:
        super().__post_init__()
        if not 0 <= self.settle_steps < N_STEPS:
            raise ValueError(
                f"settle_steps must be in [0, {N_STEPS}), got {self.settle_steps}"
            )


@register_behaviour
class StandTall(Behaviour):
    """Stand as tall as possible: fitness the mean body height (m) after
    ``settle_steps``."""

    name = "stand-tall"
    n_steps = N_STEPS
    Options = StandOptions

    def start_states(self, p):
        return ready_start(p)

    def episode_fitness(self, res, p):
        return res["qpos"][:, 1 + self.options.settle_steps :, 2].mean(axis=1)

    def metrics(self, res, p, genome, reference=None):
        return {"fitness": float(self.fitness(res, p)[0])}
