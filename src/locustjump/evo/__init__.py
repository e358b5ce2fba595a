"""Optimizers on one ask/tell base class (:mod:`locustjump.evo.base`).

=========  ==========================================  ===================
kind       what                                        module
=========  ==========================================  ===================
``rcga``   the paper's real-coded GA (the default)     :mod:`.rcga`
``cma``    CMA-ES from pycma (extra ``[cma]``)          :mod:`.cma`
``random`` random search, the floor to beat            :mod:`.random_search`
=========  ==========================================  ===================

Quality diversity (extra ``[qd]``, pyribs; the task's behaviour descriptors
come with each tell, the elites fill a grid archive, :mod:`.qd`):

==============  =====================================  ====================
kind            what                                   module
==============  =====================================  ====================
``map-elites``  MAP-Elites, Gaussian or iso-line        :mod:`.map_elites`
``cma-me``      CMA-ME, CMA-ES emitters                 :mod:`.cma_me`
==============  =====================================  ====================

A new optimizer subclasses :class:`Optimizer` (it writes ``_ask``, ``_tell``,
``_state``, ``_set_state``; the base does the bookkeeping) and has a frozen
settings dataclass; :func:`register` makes it available to ``TrainConfig``,
``config.toml`` and the command line by its ``kind``. Another package's
optimizers are found through the entry point group ``locustjump.optimizers``
(:mod:`locustjump.plugins`), loaded the first time a kind is not known.
"""

from __future__ import annotations

from typing import Any

from locustjump import plugins
from locustjump.evo.archive import Archive
from locustjump.evo.base import (
    Optimizer,
    OptimizerParams,
    rng_from_state,
    rng_state,
)
from locustjump.evo.cma import CMAES, CMAParams
from locustjump.evo.cma_me import CMAME, CMAMEParams
from locustjump.evo.map_elites import MapElites, MapElitesParams
from locustjump.evo.qd import QDOptimizer, QDParams
from locustjump.evo.random_search import RandomSearch, RandomSearchParams
from locustjump.evo.rcga import RCGA, RCGAParams

_REGISTRY: dict[str, type[Optimizer]] = {}


def register(cls: type[Optimizer]) -> type[Optimizer]:
    """Make optimizer class ``cls`` (with ``cls.Params.kind``) known by kind."""
    if not (isinstance(cls, type) and issubclass(cls, Optimizer)):
        raise TypeError(
            f"{getattr(cls, '__name__', cls)} is not a subclass of "
            "locustjump.evo.Optimizer"
        )
    if getattr(cls, "__abstractmethods__", None):
        missing = ", ".join(sorted(cls.__abstractmethods__))
        raise TypeError(f"{cls.__name__} does not define {missing}")
    if not isinstance(getattr(cls, "Params", None), type):
        raise TypeError(f"{cls.__name__} has no Params settings class")
    _REGISTRY[cls.Params.kind] = cls
    return cls


for _cls in (RCGA, CMAES, RandomSearch, MapElites, CMAME):
    register(_cls)


def optimizer_kinds() -> tuple[str, ...]:
    """Every kind, the plugins' too (``--optimizer`` choices)."""
    plugins.load(plugins.OPTIMIZERS, register)
    return tuple(_REGISTRY)


def params_class(kind: object) -> type[OptimizerParams]:
    """The settings dataclass of optimizer ``kind`` (``ValueError`` if it
    names none: ``TrainConfig`` passes the ``kind`` of whatever it is given)."""
    if isinstance(kind, str) and kind not in _REGISTRY:
        plugins.load(plugins.OPTIMIZERS, register)
    if isinstance(kind, str) and kind in _REGISTRY:
        return _REGISTRY[kind].Params
    raise ValueError(f"unknown optimizer {kind!r}; choose from {', '.join(_REGISTRY)}")


def optimizer_class(kind: str) -> type[Optimizer]:
    """The class of optimizer ``kind`` (``ValueError`` if unknown)."""
    params_class(kind)
    return _REGISTRY[kind]


def make_optimizer(params: Any, num_params: int, seed: int) -> Optimizer:
    """A fresh optimizer for settings ``params`` (its ``kind`` picks the class)."""
    return optimizer_class(params.kind)(num_params, params, seed)


__all__ = [
    "CMAES",
    "CMAME",
    "RCGA",
    "Archive",
    "CMAMEParams",
    "CMAParams",
    "MapElites",
    "MapElitesParams",
    "QDOptimizer",
    "QDParams",
    "Optimizer",
    "OptimizerParams",
    "RCGAParams",
    "RandomSearch",
    "RandomSearchParams",
    "make_optimizer",
    "optimizer_class",
    "optimizer_kinds",
    "params_class",
    "register",
    "rng_from_state",
    "rng_state",
]
