"""The equivalent mutants of scripts/mutation.py's modules: mutants that no
test can tell from the original, each with the reason (docs/mutation.md lists
them from here): the optimizers' in ``scripts/mutation_equivalent_evo.py``,
the run directory's, training's and the command line's (added 2026-11-27)
in ``scripts/mutation_equivalent_runs.py``, the debris field's geometry and
the start states' in ``scripts/mutation_equivalent_sim.py``, the rest here."""

from mutation_equivalent_evo import EVO
from mutation_equivalent_runs import RUNS
from mutation_equivalent_sim import SIM
from mutation_reasons import SORT_CASE, ZIP, alike, cast, zip_strict

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
_PLACEHOLDER = (
    "a placeholder: the Comparison is replaced by one with verdict(c) before "
    "it is returned, and verdict reads no verdict"
)
_BOUNDS = (
    "hodges_lehmann returns both bounds finite or both infinite, so 'either "
    "is infinite' and 'both are' are the same test on every Comparison "
    "compare_samples makes"
)
_INF_CASE = "float() reads 'INF' as it reads 'inf'"
_NOT_AT_TOLERANCE = (
    "no float ratio r has r - 1 == 0.02 exactly (r - 1 is exact near 1, and "
    "1 + 0.02 is not a double), so > and >= never differ"
)
_FLOAT_BEST = (
    "the best column is read from metrics.csv as float64; an integer curve "
    "would give the same shares too"
)
_UPPER_F = (
    "'F' and 'f' differ only for inf and nan, which a diagnostic (the "
    "largest of finite episode values; an unstable episode's are made "
    "finite) never is"
)
_STRIDE_SEEDED = (
    "the default is never read: a terrain_stride is refused for a scene without "
    "a seed field (_stride), and config() reads the seed only with a stride"
)

_SAME_BEHAVIOUR = (
    "episode_steps makes the behaviour it is not given from the same "
    "configuration: the same counts, made twice (states passes it to save that)"
)

_CAST = "typing.cast returns its value unchanged, whatever the type named"

EQUIVALENT: dict[str, tuple[str, str]] = {
    **EVO,
    **RUNS,
    **SIM,
    **alike(
        "locustjump.present.compare.x_optimizer_label",
        _CAST,
        {
            7: "cast(None, params)",
            11: 'cast("XXDataclassInstanceXX", params)',
            12: 'cast("dataclassinstance", params)',
            13: 'cast("DATACLASSINSTANCE", params)',
        },
    ),
    **zip_strict(
        "locustjump.present.compare.x_frozen_evaluations",
        (15, 19, 20),
        "frozen.behaviours, frozen.sources, frozen.hashes",
        "FrozenGenomes.load checks that behaviours, sources and hashes hold one "
        "name per genome each",
    ),
    "locustjump.runs.study.x_states__mutmut_20": (
        "episode_steps(cfg, None)",
        _SAME_BEHAVIOUR,
    ),
    "locustjump.runs.study.x_states__mutmut_22": (
        "episode_steps(cfg, )",
        _SAME_BEHAVIOUR,
    ),
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
        _NOT_AT_TOLERANCE,
    ),
    "locustjump.present.compare.x_budget_note__mutmut_12": ('float("INF")', _INF_CASE),
    "locustjump.present.compare.x_budget_note__mutmut_16": (
        ">= BUDGET_TOLERANCE",
        _NOT_AT_TOLERANCE,
    ),
    "locustjump.runs.study_table.x_make_table__mutmut_219": ("'.4F'", _UPPER_F),
    "locustjump.runs.study_table.x_make_table__mutmut_227": ("'.2F'", _UPPER_F),
    "locustjump.tasks.descriptors.x_describe__mutmut_30": (
        "reshape(terrains, -2, per_controller)",
        _RESHAPE_NEG,
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
    "locustjump.sim.analysis.x_ground_profile__mutmut_9": ('kind="STABLE"', SORT_CASE),
    "locustjump.rundir.archive.x_read_archive__mutmut_122": ("else -2", _NOT_1D),
    "locustjump.rundir.archive.x_read_archive__mutmut_134": ('"XXiuXX"', _NO_KIND_X),
    # envs.py: the action's check
    "locustjump.envs.x__action__mutmut_5": (
        '"XXiufXX"',
        "NumPy has no dtype kind 'X': only 'i', 'u' and 'f' can match either way",
    ),
    "locustjump.envs.x__action__mutmut_28": (
        "a.astype(None)",
        "astype(None) casts to NumPy's default dtype, float64, as asked",
    ),
    # the four reshape(-1) of the reader's arrays, each mutated to -2
    **{
        f"locustjump.rundir.archive.x_read_archive__mutmut_{n}": (
            "reshape(-2)",
            _RESHAPE_NEG,
        )
        for n in (77, 85, 92, 99)
    },
    # zip(..., strict=True) mutated three ways where the lengths cannot differ
    **zip_strict(
        "locustjump.rundir.metrics.x_parse_row", (10, 13, 14), "names, cells", ZIP
    ),
    **zip_strict(
        "locustjump.rundir.config.x_coerce", (55, 58, 59), "value, default", ZIP
    ),
    **zip_strict(
        "locustjump.sim.analysis.x_find_jumps", (34, 37, 38), "starts, ends", _RISE_FALL
    ),
    # a cast mutated two ways (dtype=None, the dtype dropped) where the data
    # already has the type cast to
    **cast(
        "locustjump.runs.learning.x_late_gain",
        (4, 6),
        "np.asarray(best, )",
        _FLOAT_BEST,
    ),
    **cast(
        "locustjump.rundir.archive.x_write_archive",
        (33, 35),
        "np.array(a.dims, )",
        _DIMS_INT,
    ),
}
