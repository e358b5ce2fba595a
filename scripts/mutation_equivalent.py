"""The equivalent mutants of scripts/mutation.py's modules: mutants that no
test can tell from the original, each with the reason (docs/mutation.md lists
them from here)."""

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
_EDGES_FLOAT = "the edges are compared with 1 and -1, which floats hold exactly"
_RISE_FALL = (
    "the stretch mask is padded with 0 at both ends, so it has as many rises "
    "as falls: zip's strictness is never tested"
)
_PLATEAU = (
    "the later points of a flat-bottomed dip repeat the first one's test with "
    "nothing to gain: the stretch between them is as high as the point, so no "
    "split is made there (nor at a stretch's flat start, 0 below its start)"
)
_COUNT_FLOAT = (
    "the window sums of 0s and 1s are whole numbers, exact in floats, and "
    "compared with n exactly"
)
_SORT_CASE = (
    "NumPy reads the sort kind case-insensitively (checked: the same order as "
    "'stable' where the default sort differs)"
)
_NOT_1D = "any k below 0 is refused by the same check (0 <= k)"
_NO_KIND_X = "NumPy has no dtype kind 'X': only 'i' and 'u' can match either way"
_RESHAPE_NEG = (
    "NumPy 2 reads any negative size in reshape as the one unknown dimension "
    "(checked: reshape(2, -2, 3) of 12 values is (2, 2, 3))"
)
_DIMS_INT = (
    "a tuple of Python ints makes an int64 array (the default integer on Linux "
    "with NumPy 1 or 2, on every platform with NumPy 2)"
)
_TEMPLATE = "a type template for coerce: only its type is read"
_ZIP = (
    "the lengths were compared just above: a row (or array) of another "
    "length has already raised"
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
_PLACEHOLDER = (
    "a placeholder: the Comparison is replaced by one with verdict(c) before "
    "it is returned, and verdict reads no verdict"
)
_BOUNDS = (
    "hodges_lehmann returns both bounds finite or both infinite, so 'either "
    "is infinite' and 'both are' are the same test on every Comparison "
    "compare_samples makes"
)
#: mutant name -> (text of its mutated line, as mutmut's diff shows it,
#: without indentation; why no test can tell it from the original); matched
#: by function and text (:func:`listed`)
_INF_CASE = "float() reads 'INF' as it reads 'inf'"
_FLOAT_BEST = (
    "the best column is read from metrics.csv as float64; an integer curve "
    "would give the same shares too"
)
_UPPER_F = (
    "'F' and 'f' differ only for inf and nan, which a diagnostic (the "
    "largest of finite episode values; an unstable episode's are made "
    "finite) never is"
)


def _zip_strict(
    function: str, numbers: tuple[int, int, int], args: str, why: str
) -> dict[str, tuple[str, str]]:
    """The three mutants of ``zip(ARGS, strict=True)`` in ``function`` (their
    numbers in order: strict=None, the argument dropped, strict=False), which
    are equivalent where the lengths zipped cannot differ (``why``)."""
    texts = ("strict=None", f"zip({args}, )", "strict=False")
    return {
        f"{function}__mutmut_{n}": (text, why)
        for n, text in zip(numbers, texts, strict=True)
    }


def _cast(
    function: str, numbers: tuple[int, int], dropped: str, why: str
) -> dict[str, tuple[str, str]]:
    """The two mutants of a ``dtype=`` cast in ``function`` (their numbers in
    order: ``dtype=None``, then the dtype dropped, whose mutated text is
    ``dropped``), equivalent where the data already has that type (``why``)."""
    texts = ("dtype=None", dropped)
    return {
        f"{function}__mutmut_{n}": (text, why)
        for n, text in zip(numbers, texts, strict=True)
    }


_STRIDE_SEEDED = (
    "the default is never read: a terrain_stride is refused for a scene without "
    "a seed field (_stride), and config() reads the seed only with a stride"
)

EQUIVALENT: dict[str, tuple[str, str]] = {
    "locustjump.rundir.lock.x__take__mutmut_3": (
        "range(LOOK_TRIES + 2)",
        "the loop never runs out: its try number LOOK_TRIES raises InUse, so a "
        "longer range is never reached",
    ),
    "locustjump.runs.studyarms.x__template__mutmut_8": (
        "for seed in (1, INT64_MAX):",
        "no integer format spec formats 0 and fails on 1, or the other way; "
        "the largest seed is the one that can fail ({seed:c} overflows)",
    ),
    "locustjump.runs.studyarms.xǁArmǁconfig__mutmut_9": (
        'getattr(t.scene, "seed", None)',
        _STRIDE_SEEDED,
    ),
    "locustjump.runs.studyarms.xǁArmǁconfig__mutmut_12": (
        'getattr(t.scene, "seed", )',
        _STRIDE_SEEDED,
    ),
    "locustjump.runs.studyarms.xǁArmǁconfig__mutmut_15": (
        'getattr(t.scene, "seed", 1)',
        _STRIDE_SEEDED,
    ),
    "locustjump.rundir.outputs.x_prepare_out_file__mutmut_22": (
        "setting) and not out.parent.is_dir()",
        "a parent that exists and is not a directory never gets here: looking "
        "at the file under it (the _exists of out) fails first with 'Not a "
        "directory'; the is_dir test only guards a parent replaced meanwhile",
    ),
    "locustjump.rundir.reads.x__read_npz__mutmut_34": (
        "allow_pickle=None",
        "None is false, as False: NumPy unpickles nothing (the explicit False "
        "is kept so that no change of NumPy's default can; the test that makes "
        "it True fails)",
    ),
    "locustjump.rundir.reads.x__read_npz__mutmut_36": (
        "read_array(m, )",
        "NumPy's read_array defaults to allow_pickle=False (checked with "
        "inspect.signature, NumPy 2.4); written out so that no change of the "
        "default can unpickle",
    ),
    "locustjump.rundir.reads.x__article__mutmut_6": (
        '"XXaeiou.XX"',
        "the first letter is lower-cased before the test, and the added X are "
        "upper case: no lower-cased letter is one of them",
    ),
    "locustjump.rundir.reads.x_nesting__mutmut_19": (
        "if end <= 0 else end",
        "end is where the comment's line ends, found from the '#' at i >= 0, "
        "so it is -1 (none) or at least 1: never 0",
    ),
    "locustjump.rundir.reads.x_nesting__mutmut_20": (
        "if end < 1 else end",
        "end is where the comment's line ends, found from the '#' at i >= 0, "
        "so it is -1 (none) or at least 1: never 0",
    ),
    "locustjump.rundir.reads.x_read_toml__mutmut_12": (
        "nesting(text) >= MAX_NESTING",
        "a TOML text whose brackets nest 32 deep parses to a value at least 33 "
        "deep (the document's own table is a level), which the check after "
        "parsing refuses with the same words: only whether the parser runs "
        "differs",
    ),
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
    "locustjump.evo.rcga.xǁRCGAǁ_tell__mutmut_18": ('kind="STABLE"', _SORT_CASE),
    "locustjump.rundir.metrics.x_read_metrics__mutmut_10": (
        "if (rows) or True else",
        "np.array([], dtype) is the same empty array as np.zeros(0, dtype)",
    ),
    "locustjump.rundir.config.xǁTrainConfigǁ_from_dict__mutmut_8": (
        '"seed": 1,',
        _TEMPLATE,
    ),
    "locustjump.rundir.config.xǁTrainConfigǁ_from_dict__mutmut_11": (
        '"generations": 1001,',
        _TEMPLATE,
    ),
    "locustjump.rundir.config.xǁTrainConfigǁ_from_dict__mutmut_14": (
        '"frozen_digest": "XXXX"',
        _TEMPLATE,
    ),
    "locustjump.rundir.config.x_terrains_from_table__mutmut_17": (
        'top = {"terrains": 2,',
        _TEMPLATE + " (the default count is the one given to Terrains below)",
    ),
    "locustjump.rundir.config.x_terrains_from_table__mutmut_20": (
        '"aggregate": "XXmeanXX"}',
        _TEMPLATE + " (the default is the one given to Terrains below)",
    ),
    "locustjump.rundir.config.x_terrains_from_table__mutmut_21": (
        '"aggregate": "MEAN"}',
        _TEMPLATE + " (the default is the one given to Terrains below)",
    ),
    "locustjump.rundir.config.x_coerce__mutmut_37": ("coerce(v, 1, ", _TEMPLATE),
    "locustjump.rundir.config.x_coerce__mutmut_1": ("item: Any = 1", _TEMPLATE),
    "locustjump.rundir.config.x_from_table__mutmut_11": ('get("item", 1)', _TEMPLATE),
    "locustjump.sim.sensors.x_paper_inputs__mutmut_51": (
        "qpos[:, 3:8]",
        "up_axis_in_body reads the first four columns of what it is given",
    ),
    "locustjump.sim.sensors.x_paper_inputs__mutmut_53": (
        "out=obs[:, 6:10]",
        "obs has 9 columns: a slice to 10 ends at 9 as well",
    ),
    "locustjump.evo.base.xǁOptimizerǁ__init____mutmut_10": (
        "Range(1, integer=True)",
        "Range's hi defaults to None (no upper bound): the same range",
    ),
    "locustjump.evo.base.x_check_fitness__mutmut_8": (
        ".reshape(-2)",
        "NumPy reads any negative size in reshape as 'the rest' (checked)",
    ),
    "locustjump.tasks.getup.x_getup_summary__mutmut_20": (
        "reached.argmax(axis=1), -2)",
        "the mark of 'never' is only compared with >= 0: -1 and -2 read the same",
    ),
    "locustjump.tasks.base.xǁBehaviourǁfitness__mutmut_19": (
        ".reshape(-2, k)",
        "NumPy reads any negative size in reshape as 'the rest' (checked)",
    ),
    "locustjump.tasks.base.xǁBehaviourǁfitness_terms__mutmut_27": (
        ".reshape(-2, k)",
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
    "locustjump.sim.actuation.x_apply_deltas__mutmut_30": (
        "(out is None) and False else out",
        "without out the result is a new array either way: step is itself "
        "a fresh array (one allocation more, the same numbers)",
    ),
    "locustjump.present.ranktests.x__rank_sum_null__mutmut_14": (
        "c[0, 0] = 2.0",
        "the counts are divided by their sum at the end: a start of 2 doubles "
        "every count, not a probability",
    ),
    "locustjump.present.ranktests.x__rank_sum_null__mutmut_17": (
        "c[1:, r:] - c[:-1",
        "subtracting makes row k of the counts (-1)^k times the true counts; "
        "row m, the one read, is divided by its sum, which cancels the sign",
    ),
    "locustjump.present.ranktests.x__rank_sum_null__mutmut_8": (
        "np.zeros((m + 2, top + 1))",
        "one row more (subsets of m + 1 values), never read: row m is the same",
    ),
    "locustjump.present.ranktests.x_mann_whitney__mutmut_38": (
        "alternative=alternative, )",
        "SciPy's default method (auto) takes the normal approximation above 8 "
        "values a sample, and this branch has more than 50",
    ),
    "locustjump.present.ranktests.x_mann_whitney__mutmut_40": (
        'method="ASYMPTOTIC"',
        "SciPy's mannwhitneyu lower-cases its method (checked: 'ASYMPTOTIC' "
        "gives the p of 'asymptotic')",
    ),
    "locustjump.present.stats.x_compare_samples__mutmut_61": (
        "verdict=None,",
        _PLACEHOLDER,
    ),
    "locustjump.present.stats.x_compare_samples__mutmut_100": (
        'verdict="XXXX",',
        _PLACEHOLDER,
    ),
    "locustjump.present.ranktests.x_hodges_lehmann__mutmut_38": (
        "cdf <= (1 - confidence) / 2 * (1 - 1e-9)",
        "differs only where a cumulative probability of U equals alpha/2 x "
        "(1 - 1e-9) to the last bit, a number no sum of U's probabilities "
        "reaches at the levels used (the slack is there to keep a cdf that "
        "equals alpha/2 on the right side)",
    ),
    "locustjump.present.stats.x_interval_text__mutmut_2": (
        "isfinite(c.low) or math.isfinite(c.high)",
        _BOUNDS,
    ),
    "locustjump.present.stats.x_verdict__mutmut_12": (
        "isfinite(c.low) or math.isfinite(c.high)",
        _BOUNDS,
    ),
    "locustjump.runs.study_table.x__budget_note__mutmut_27": (
        'float("INF")',
        _INF_CASE,
    ),
    "locustjump.runs.study_table.x__budget_note__mutmut_39": (
        ">= BUDGET_TOLERANCE",
        "no float ratio r has r - 1 == 0.02 exactly (r - 1 is exact near 1, and "
        "1 + 0.02 is not a double), so > and >= never differ",
    ),
    "locustjump.runs.study_table.x_make_table__mutmut_219": ("'.4F'", _UPPER_F),
    "locustjump.runs.study_table.x_make_table__mutmut_227": ("'.2F'", _UPPER_F),
    "locustjump.tasks.descriptors.x_describe__mutmut_30": (
        "reshape(terrains, -2, per_controller)",
        _RESHAPE_NEG,
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
    "locustjump.sim.analysis.x_find_jumps__mutmut_21": (
        "high.astype(None)",
        _EDGES_FLOAT,
    ),
    "locustjump.sim.analysis.x_find_jumps__mutmut_50": (
        "(seg[1:-1] <= seg[:-2])",
        _PLATEAU,
    ),
    "locustjump.sim.analysis.x_stuck_overturned__mutmut_20": (
        "np.ones(n, None)",
        _COUNT_FLOAT,
    ),
    "locustjump.sim.analysis.x_stuck_overturned__mutmut_22": (
        "np.ones(n, )",
        _COUNT_FLOAT,
    ),
    "locustjump.sim.analysis.x_ground_profile__mutmut_9": ('kind="STABLE"', _SORT_CASE),
    "locustjump.rundir.archive.x_read_archive__mutmut_122": ("else -2", _NOT_1D),
    "locustjump.rundir.archive.x_read_archive__mutmut_134": ('"XXiuXX"', _NO_KIND_X),
    # the four reshape(-1) of the reader's arrays, each mutated to -2
    **{
        f"locustjump.rundir.archive.x_read_archive__mutmut_{n}": (
            "reshape(-2)",
            _RESHAPE_NEG,
        )
        for n in (77, 85, 92, 99)
    },
    # zip(..., strict=True) mutated three ways where the lengths cannot differ
    **_zip_strict(
        "locustjump.rundir.metrics.x_parse_row", (10, 13, 14), "names, cells", _ZIP
    ),
    **_zip_strict(
        "locustjump.rundir.config.x_coerce", (55, 58, 59), "value, default", _ZIP
    ),
    **_zip_strict(
        "locustjump.evo.archive.xǁArchiveǁat_cell", (9, 12, 13), "cell, self.dims", _ZIP
    ),
    **_zip_strict(
        "locustjump.evo.map_elites.xǁMapElitesǁ_emitters",
        (38, 42, 43),
        "starts, sizes, seeds",
        _PER_EMITTER,
    ),
    **_zip_strict(
        "locustjump.evo.map_elites.xǁMapElitesǁ_emitters",
        (59, 63, 64),
        "starts, sizes, seeds",
        _PER_EMITTER,
    ),
    **_zip_strict(
        "locustjump.evo.cma_me.xǁCMAMEǁ_emitters",
        (32, 35, 36),
        "p.batch_sizes(), seeds",
        _PER_EMITTER,
    ),
    **_zip_strict(
        "locustjump.evo.qd.xǁQDOptimizerǁ_set_state", (31, 34, 35), "f, m", _ZIP
    ),
    **_zip_strict(
        "locustjump.sim.analysis.x_find_jumps", (34, 37, 38), "starts, ends", _RISE_FALL
    ),
    # a cast mutated two ways (dtype=None, the dtype dropped) where the data
    # already has the type cast to
    **_cast(
        "locustjump.runs.learning.x_late_gain",
        (4, 6),
        "np.asarray(best, )",
        _FLOAT_BEST,
    ),
    **_cast(
        "locustjump.evo.qd.xǁQDOptimizerǁ_ask",
        (2, 4),
        "np.asarray(self._scheduler.ask(), )",
        _FLOATS_ASK,
    ),
    **_cast(
        "locustjump.evo.qd.xǁQDOptimizerǁarchive",
        (40, 42),
        'np.asarray(d["solution"], )',
        _RIBS_FLOATS,
    ),
    **_cast(
        "locustjump.evo.qd.xǁQDOptimizerǁarchive",
        (46, 48),
        'np.asarray(d["objective"], )',
        _RIBS_FLOATS,
    ),
    **_cast(
        "locustjump.evo.qd.xǁQDOptimizerǁarchive",
        (52, 54),
        'np.asarray(d["measures"], )',
        _RIBS_FLOATS,
    ),
    **_cast(
        "locustjump.evo.qd.xǁQDOptimizerǁarchive",
        (58, 60),
        'np.asarray(d["generation"], )',
        _RIBS_FLOATS,
    ),
    **_cast(
        "locustjump.evo.qd.xǁQDOptimizerǁ_set_state",
        (13, 15),
        'np.asarray(state["fitness_history"], )',
        _REPLAY,
    ),
    **_cast(
        "locustjump.evo.qd.xǁQDOptimizerǁ_set_state",
        (20, 22),
        'np.asarray(state["descriptor_history"], )',
        _REPLAY_M,
    ),
    **_cast(
        "locustjump.rundir.archive.x_write_archive",
        (33, 35),
        "np.array(a.dims, )",
        _DIMS_INT,
    ),
}
