"""Controllers: flat genomes -> batched policies.

A controller is *stateless code plus per-episode arrays*, so that a batch of
episodes can be split anywhere (threads, processes, hosts) and give the same
result:

* ``params``: (n, num_params) float64, one row per episode (the genome);
* ``memory``: (n, memory_size) float64, one row per episode, for controllers
  that remember (the rule-based touch timer, the composed switcher);
* ``prepare(params) -> prepared``: once per rollout, whatever ``act`` wants
  of the genomes (for an MLP: its weight matrices, unpacked once rather than
  every control step);
* ``act(prepared, memory, obs, targets, step) -> (deltas, memory)``: ``obs``
  the (n, 9) paper inputs, ``targets`` the (n, 4) current servo targets
  (radians); deltas (n, 4) are the target changes in radians for this control
  step.

Every controller here satisfies the :class:`Controller` protocol; the rollout
engine (:mod:`locustjump.sim.engine.rollout`) only ever calls these four members.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal, NamedTuple, Protocol, runtime_checkable

import numpy as np

from locustjump.sim.actuation import MAX_DELTA, N_ACTUATORS
from locustjump.sim.kernels import OUTPUTS, Net, soa
from locustjump.sim.sensors import N_INPUTS


@runtime_checkable
class Controller(Protocol):
    """What the rollout engine needs of a controller."""

    @property
    def num_params(self) -> int: ...

    @property
    def memory_size(self) -> int: ...

    def prepare(self, params: np.ndarray) -> Any: ...

    def act(
        self,
        prepared: Any,
        memory: np.ndarray,
        obs: np.ndarray,
        targets: np.ndarray,
        step: int,
    ) -> tuple[np.ndarray, np.ndarray]: ...


#: A controller's compiled form (:mod:`locustjump.sim.kernels`): ``("mlp",
#: net, output code)`` for one network per episode (:func:`~.kernels.mlp`) or
#: ``("switch", switcher, nets, every)`` for the composed switcher
#: (:func:`~.kernels.switch`), networks episode-last
KernelSpec = tuple[Literal["mlp"], Net, int] | tuple[Literal["switch"], Net, Net, int]


@runtime_checkable
class CompiledController(Controller, Protocol):
    """A controller the compiled engine paths can step without Python: it
    offers its networks as a :data:`KernelSpec` (``MLP``, the composed
    switcher); any other controller runs its own ``act``."""

    def kernel(self, prepared: Any) -> KernelSpec: ...


class MLPWeights(NamedTuple):
    """One network per row: ``w1 (n, h, i)``, ``b1 (n, h)``, ``w2 (n, o, h)``,
    ``b2 (n, o)``."""

    w1: np.ndarray
    b1: np.ndarray
    w2: np.ndarray
    b2: np.ndarray


@dataclass(frozen=True)
class MLP:
    """Fully connected ``n_in - n_hidden - n_out`` network, tanh hidden units.

    Genome layout (row-major): ``W1 (n_hidden, n_in)``, ``b1 (n_hidden,)``,
    ``W2 (n_out, n_hidden)``, ``b2 (n_out,)``. Output squashing:

    * ``"delta"``: ``tanh(.) * 10 deg`` in radians, the paper's target changes;
    * ``"sigmoid"``: logistic, in [0, 1] (the composed behaviour's switcher);
    * ``"linear"``: no squashing.

    The paper's controller is ``MLP()`` = 9-10-4, 144 genes.
    """

    n_in: int = N_INPUTS
    n_hidden: int = 10
    n_out: int = N_ACTUATORS
    output: Literal["delta", "sigmoid", "linear"] = "delta"

    def __post_init__(self) -> None:
        if min(self.n_in, self.n_hidden, self.n_out) < 1:
            raise ValueError("MLP layer sizes must be >= 1")
        if self.output not in ("delta", "sigmoid", "linear"):
            raise ValueError(f"unknown MLP output {self.output!r}")

    @property
    def num_params(self) -> int:
        return self.n_hidden * (self.n_in + 1) + self.n_out * (self.n_hidden + 1)

    @property
    def memory_size(self) -> int:
        return 0

    def unflatten(self, params: np.ndarray) -> MLPWeights:
        """Views ``W1 (n, h, i), b1 (n, h), W2 (n, o, h), b2 (n, o)`` of (n, P)."""
        params = np.asarray(params, dtype=np.float64)
        if params.ndim != 2 or params.shape[1] != self.num_params:
            raise ValueError(
                f"genome has shape {params.shape}, expected (n, {self.num_params})"
            )
        n, i, h, o = params.shape[0], self.n_in, self.n_hidden, self.n_out
        a = h * i
        b = a + h
        c = b + o * h
        return MLPWeights(
            params[:, :a].reshape(n, h, i),
            params[:, a:b],
            params[:, b:c].reshape(n, o, h),
            params[:, c:],
        )

    def prepare(self, params: np.ndarray) -> MLPWeights:
        """The weights of (n, P) genomes, unpacked once for a rollout."""
        return MLPWeights(*(np.ascontiguousarray(a) for a in self.unflatten(params)))

    def forward(self, params: np.ndarray, obs: np.ndarray) -> np.ndarray:
        """Outputs (n, n_out) for inputs (n, n_in), one network per row."""
        return self.apply(self.prepare(params), obs)

    def apply(self, weights: MLPWeights, obs: np.ndarray) -> np.ndarray:
        """Outputs (n, n_out) of prepared networks for inputs (n, n_in)."""
        hidden = np.matmul(weights.w1, obs[:, :, None])[:, :, 0]
        hidden += weights.b1
        np.tanh(hidden, out=hidden)
        out: np.ndarray = np.matmul(weights.w2, hidden[:, :, None])[:, :, 0]
        out += weights.b2
        if self.output == "delta":
            np.tanh(out, out=out)
            out *= MAX_DELTA
        elif self.output == "sigmoid":
            np.negative(out, out=out)
            np.exp(out, out=out)
            out += 1.0
            np.divide(1.0, out, out=out)
        return out

    def act(
        self,
        prepared: MLPWeights,
        memory: np.ndarray,
        obs: np.ndarray,
        targets: np.ndarray,
        step: int,
    ) -> tuple[np.ndarray, np.ndarray]:
        return self.apply(prepared, obs), memory

    def kernel(self, prepared: MLPWeights) -> KernelSpec:
        """The compiled path's form of ``act`` (:mod:`locustjump.sim.kernels`):
        the weights episode-last and the output code."""
        return ("mlp", tuple(soa(w) for w in prepared), OUTPUTS[self.output])

    def random_genomes(
        self, rng: np.random.Generator, n: int, scale: float = 1.0
    ) -> np.ndarray:
        """(n, num_params) genomes uniform in [-scale, scale]."""
        return rng.uniform(-scale, scale, size=(n, self.num_params))
