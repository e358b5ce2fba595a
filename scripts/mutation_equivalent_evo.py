"""The equivalent mutants of the optimizers (``locustjump.evo``), each with
the reason (``scripts/mutation_equivalent.py`` adds them to the rest)."""

from mutation_reasons import SORT_CASE, ZIP, cast, zip_strict

_TIE = (
    "differs only when a uniform draw in [0, 1) equals the threshold exactly "
    "(probability 2**-53 a draw); both read 'with probability p' correctly"
)
_EINSUM = "einsum's subscripts are labels: upper case names the same sum"
_GEN0 = (
    "at generation 0 the population and its fitness are empty, so the first "
    "e rows of them are empty whatever e is"
)
_UNIQUE_CELLS = (
    "an archive's cells are distinct (Archive checks it), so every sort of "
    "them gives the same order, stable or not"
)
_PER_EMITTER = (
    "one entry per emitter each by construction: the first genomes are split "
    "by batch_sizes() (one size per emitter) and _start draws one seed per "
    "emitter, so zip's strictness is never tested"
)
_RIBS_DEFAULT = (
    "the argument left out is pyribs 0.12's default for EvolutionStrategyEmitter "
    "(checked with inspect.signature); it is written out so that another "
    "default cannot change CMA-ME, and tests/test_qd_params.py checks the "
    "emitter's ranker, strategy and rules"
)
_FLOATS_ASK = "pyribs asks float64 arrays, and Optimizer.ask converts to float64 anyway"
_INT64 = (
    "np.full of a Python int is int64 (the default integer on Linux with "
    "NumPy 1 or 2, on every platform with NumPy 2), and pyribs stores the "
    "field as the int64 it was declared"
)
_RIBS_FLOATS = (
    "pyribs' GridArchive stores solutions, objectives and measures as float64 "
    "(its default dtype) and the generation field as the declared int64"
)
_REPLAY_M = (
    "each replayed row goes through tell, whose check_descriptors makes it float64"
)
_FLOATS = "pycma asks float64 arrays, and Optimizer.ask converts to float64 anyway"
_REPLAY = "each replayed row goes through tell, whose check_fitness makes it float64"
_CASE = (
    "pycma matches option names case-insensitively (checked: {'POPSIZE': "
    "12} gives popsize 12)"
)
_SILENT = (
    "at verbose -9 (or below) pycma neither displays nor logs, whatever "
    "verb_disp and verb_log say (tests/test_cma_contract.py: no output, no "
    "file)"
)

EVO: dict[str, tuple[str, str]] = {
    "locustjump.evo.rcga.x_sbx__mutmut_10": (
        "+ u < 0.5,",
        "at u = 0.5 both branches give beta = 1",
    ),
    "locustjump.evo.rcga.x_sbx__mutmut_38": ("<= 0.5, 1.0, -1.0)", _TIE),
    "locustjump.evo.rcga.x_gaussian_mutation__mutmut_3": ("<= rate", _TIE),
    "locustjump.evo.rcga.xǁRCGAǁ_children__mutmut_52": ("> p.crossover_rate", _TIE),
    "locustjump.evo.rcga.x_undx__mutmut_16": ('+ dn2 = np.einsum("IJ,IJ->I"', _EINSUM),
    "locustjump.evo.rcga.x_undx__mutmut_39": ('np.einsum("IJ,IJ->I", rel', _EINSUM),
    "locustjump.evo.rcga.x_undx__mutmut_80": ('np.einsum("IJ,IJ->I", eta', _EINSUM),
    "locustjump.evo.rcga.x_undx__mutmut_26": (
        "+ safe = np.where(dn2 > 0, dn2, 2.0)",
        "where dn2 = 0 the parents coincide, d = 0, and what is divided by "
        "safe is multiplied by d = 0",
    ),
    "locustjump.evo.rcga.x_undx__mutmut_62": (
        "rng.normal(0.0, size=(n, P))",
        "normal's scale is 1.0 by default",
    ),
    "locustjump.evo.rcga.x_tournament__mutmut_5": (
        "rng.integers(fitness.shape[0], size=(n, k))",
        "integers(high) draws from [0, high): the same numbers from the same "
        "generator (checked)",
    ),
    "locustjump.evo.rcga.xǁRCGAǁ__init____mutmut_40": (
        "np.array(init, dtype=None)",
        "Optimizer.ask converts what _ask returns to float64",
    ),
    "locustjump.evo.rcga.xǁRCGAǁ__init____mutmut_42": (
        "np.array(init, )",
        "Optimizer.ask converts what _ask returns to float64",
    ),
    "locustjump.evo.rcga.xǁRCGAǁ_tell__mutmut_3": ("or True else 0", _GEN0),
    "locustjump.evo.rcga.xǁRCGAǁ_tell__mutmut_4": (
        "self.generation >= 0 else 0",
        _GEN0,
    ),
    "locustjump.evo.rcga.xǁRCGAǁ_tell__mutmut_6": ("self.generation > 0 else 1", _GEN0),
    "locustjump.evo.rcga.xǁRCGAǁ_tell__mutmut_18": ('kind="STABLE"', SORT_CASE),
    "locustjump.evo.base.xǁOptimizerǁ__init____mutmut_10": (
        "Range(1, integer=True)",
        "Range's hi defaults to None (no upper bound): the same range",
    ),
    "locustjump.evo.base.x_check_fitness__mutmut_8": (
        ".reshape(-2)",
        "NumPy reads any negative size in reshape as 'the rest' (checked)",
    ),
    "locustjump.evo.cma.xǁCMAESǁ_ask__mutmut_2": ("dtype=None)", _FLOATS),
    "locustjump.evo.cma.xǁCMAESǁ_ask__mutmut_4": ("self.es.ask(), )", _FLOATS),
    "locustjump.evo.cma.xǁCMAESǁ_set_state__mutmut_3": ("dtype=None)", _REPLAY),
    "locustjump.evo.cma.xǁCMAESǁ_set_state__mutmut_5": (
        '["fitness_history"], )',
        _REPLAY,
    ),
    "locustjump.evo.cma.xǁCMAESǁ_start__mutmut_4": ('"POPSIZE"', _CASE),
    "locustjump.evo.cma.xǁCMAESǁ_start__mutmut_6": ('"SEED"', _CASE),
    "locustjump.evo.cma.xǁCMAESǁ_start__mutmut_8": ('"RANDN"', _CASE),
    "locustjump.evo.cma.xǁCMAESǁ_start__mutmut_12": ('"VERBOSE"', _CASE),
    "locustjump.evo.cma.xǁCMAESǁ_start__mutmut_16": ('"VERB_LOG"', _CASE),
    "locustjump.evo.cma.xǁCMAESǁ_start__mutmut_19": ('"VERB_DISP"', _CASE),
    "locustjump.evo.cma.xǁCMAESǁ_start__mutmut_14": ('"verbose": -10', _SILENT),
    "locustjump.evo.cma.xǁCMAESǁ_start__mutmut_17": ('"verb_log": 1', _SILENT),
    "locustjump.evo.cma.xǁCMAESǁ_start__mutmut_20": ('"verb_disp": 1', _SILENT),
    "locustjump.evo.x_register__mutmut_23": (
        'getattr(cls, "__abstractmethods__", )',
        "every subclass of Optimizer (an abc.ABC) has __abstractmethods__, so "
        "the default is never used",
    ),
    "locustjump.evo.archive.xǁArchiveǁqd_score__mutmut_4": ("kind=None", _UNIQUE_CELLS),
    "locustjump.evo.archive.xǁArchiveǁqd_score__mutmut_6": (
        "np.argsort(self.index, )",
        _UNIQUE_CELLS,
    ),
    "locustjump.evo.archive.xǁArchiveǁqd_score__mutmut_8": (
        'kind="STABLE"',
        _UNIQUE_CELLS,
    ),
    "locustjump.evo.archive.xǁArchiveǁin_cell_order__mutmut_3": (
        "kind=None",
        _UNIQUE_CELLS,
    ),
    "locustjump.evo.archive.xǁArchiveǁin_cell_order__mutmut_5": (
        "np.argsort(self.index, )",
        _UNIQUE_CELLS,
    ),
    "locustjump.evo.archive.xǁArchiveǁin_cell_order__mutmut_7": (
        'kind="STABLE"',
        _UNIQUE_CELLS,
    ),
    "locustjump.evo.cma_me.xǁCMAMEǁ_emitters__mutmut_15": (
        'ranker="2imp"',
        _RIBS_DEFAULT,
    ),
    "locustjump.evo.cma_me.xǁCMAMEǁ_emitters__mutmut_16": (
        'es="cma_es"',
        _RIBS_DEFAULT,
    ),
    "locustjump.evo.cma_me.xǁCMAMEǁ_emitters__mutmut_17": (
        'selection_rule="filter"',
        _RIBS_DEFAULT,
    ),
    "locustjump.evo.cma_me.xǁCMAMEǁ_emitters__mutmut_18": (
        'restart_rule="no_improvement"',
        _RIBS_DEFAULT,
    ),
    "locustjump.evo.qd.xǁQDOptimizerǁ_tell_described__mutmut_4": ("dtype=None", _INT64),
    "locustjump.evo.qd.xǁQDOptimizerǁ_tell_described__mutmut_7": (
        "self.generation + 1, )",
        _INT64,
    ),
    # zip(..., strict=True) mutated three ways where the lengths cannot differ
    **zip_strict(
        "locustjump.evo.archive.xǁArchiveǁat_cell", (9, 12, 13), "cell, self.dims", ZIP
    ),
    **zip_strict(
        "locustjump.evo.map_elites.xǁMapElitesǁ_emitters",
        (38, 42, 43),
        "starts, sizes, seeds",
        _PER_EMITTER,
    ),
    **zip_strict(
        "locustjump.evo.map_elites.xǁMapElitesǁ_emitters",
        (59, 63, 64),
        "starts, sizes, seeds",
        _PER_EMITTER,
    ),
    **zip_strict(
        "locustjump.evo.cma_me.xǁCMAMEǁ_emitters",
        (32, 35, 36),
        "p.batch_sizes(), seeds",
        _PER_EMITTER,
    ),
    **zip_strict(
        "locustjump.evo.qd.xǁQDOptimizerǁ_set_state", (31, 34, 35), "f, m", ZIP
    ),
    # a cast mutated two ways (dtype=None, the dtype dropped) where the data
    # already has the type cast to
    **cast(
        "locustjump.evo.qd.xǁQDOptimizerǁ_ask",
        (2, 4),
        "np.asarray(self._scheduler.ask(), )",
        _FLOATS_ASK,
    ),
    **cast(
        "locustjump.evo.qd.xǁQDOptimizerǁarchive",
        (40, 42),
        'np.asarray(d["solution"], )',
        _RIBS_FLOATS,
    ),
    **cast(
        "locustjump.evo.qd.xǁQDOptimizerǁarchive",
        (46, 48),
        'np.asarray(d["objective"], )',
        _RIBS_FLOATS,
    ),
    **cast(
        "locustjump.evo.qd.xǁQDOptimizerǁarchive",
        (52, 54),
        'np.asarray(d["measures"], )',
        _RIBS_FLOATS,
    ),
    **cast(
        "locustjump.evo.qd.xǁQDOptimizerǁarchive",
        (58, 60),
        'np.asarray(d["generation"], )',
        _RIBS_FLOATS,
    ),
    **cast(
        "locustjump.evo.qd.xǁQDOptimizerǁ_set_state",
        (13, 15),
        'np.asarray(state["fitness_history"], )',
        _REPLAY,
    ),
    **cast(
        "locustjump.evo.qd.xǁQDOptimizerǁ_set_state",
        (20, 22),
        'np.asarray(state["descriptor_history"], )',
        _REPLAY_M,
    ),
}
