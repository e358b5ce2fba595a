"""The equivalent mutants of the modules mutation testing took on
2026-11-27 (the run directory, training, the command line, settings and
scenes), each with the reason (``scripts/mutation_equivalent.py`` adds them
to the rest)."""

from mutation_reasons import alike, cast, zip_strict

#: dtype kinds
_NO_KIND_X = "NumPy has no dtype kind 'X': only 'i' and 'u' can match either way"
_FLOATS = (
    "numbers in, floats out: the change time divided by the control step, the "
    "genome by the network's arithmetic; the rules read column 0 alone"
)
_BAR = "how the bar is drawn on a terminal, not what it says (tests write to a pipe)"

RUNS: dict[str, tuple[str, str]] = {
    # present/results.py
    **cast(
        "locustjump.present.results.x__spread",
        (6, 8),
        "np.asarray(values, )",
        "_num prints an integer array's median, min and max as it prints the "
        "same numbers as floats",
    ),
    # present/stages: the words of results.md
    **alike(
        "locustjump.present.stages.successive.x__composed_reason",
        "str.rsplit splits at runs of whitespace with None, at each single "
        "space with ' ': a label's words are one space apart",
        {10: "rsplit(None, 1)"},
    ),
    **alike(
        "locustjump.present.stages.successive.x__composed_reason",
        "the branch above took exactly one: here there are none or more than one",
        {19: "elif len(chosen) >= 1:"},
    ),
    **alike(
        "locustjump.present.stages.successive.x__composed_reason",
        "a record without final_up_z is read as upright: 1.0 and 2.0 are both >= 0",
        {60: 'c.get("final_up_z", 2.0)'},
    ),
    **alike(
        "locustjump.present.stages.successive.xǁComposedReporterǁclaims",
        "no ratios, as an empty list or as None, is nothing to compare",
        {
            17: 'c.get("apex_ratios_to_rules", None)',
            19: 'c.get("apex_ratios_to_rules", )',
        },
    ),
    **alike(
        "locustjump.present.stages.successive.xǁMonolithicReporterǁacross_seeds",
        "float() reads 'nan' case-insensitively",
        {29: 'float("NAN")'},
    ),
    **zip_strict(
        "locustjump.present.stages.successive.xǁMonolithicReporterǁacross_seeds",
        (43, 46, 47),
        "pairs.items(), ratios",
        "the ratios are made from the pairs, one each",
    ),
    # runs/reproduction.py
    **alike(
        "locustjump.runs.reproduction.xǁReproductionǁcommand",
        "a scene without a seed: None, as 0, reads as no seed",
        {37: 'getattr(t.scene, "seed", None)'},
    ),
    **alike(
        "locustjump.runs.reproduction.xǁReproductionǁtrain_config",
        "TrainConfig's model is LocustParams() by default",
        {20: "engine=self.engine,"},
    ),
    "locustjump.rundir.arrays.x_scalar__mutmut_13": ('"XXiuXX"', _NO_KIND_X),
    "locustjump.rundir.arrays.x_plain__mutmut_4": (
        '"XXbiufUXX"',
        "NumPy has no dtype kind 'X': only 'b', 'i', 'u', 'f' and 'U' can match",
    ),
    # the setting's name given to the check is replaced by the re-raise's
    **alike(
        "locustjump.tasks.options.xǁCommonOptionsǁ__post_init__",
        "an error of the check is raised again under score_substeps",
        {
            19: '"XXscore_substepsXX"',
            20: '"SCORE_SUBSTEPS"',
        },
    ),
    "locustjump.sim.scene.xǁTerrainsǁ__post_init____mutmut_59": (
        'getattr(self.scene, "seed", 1)',
        "a scene without a seed holds 1 terrain (checked just before), whose "
        "last seed, 0 or 1, is far from 2**63-1",
    ),
    "locustjump.rundir.layout.x_is_unstarted__mutmut_8": (
        'name.rpartition(".")',
        "frozen.npz, config.toml and metrics.csv hold one dot each: split alike",
    ),
    # how tqdm draws the bar on a terminal (its width, when it redraws), not
    # what it says; tests write to a pipe
    **alike(
        "locustjump.runs.loop.xǁTrainerǁrun",
        _BAR,
        {
            11: "dynamic_ncols=None",
            17: "- dynamic_ncols=True, | - ) | + )",
            21: "dynamic_ncols=False",
            129: "refresh=None",
            133: "- refresh=False, | - ) | + )",
            136: "refresh=True",
        },
    ),
    "locustjump.runs.loop.xǁTrainerǁrun__mutmut_148": (
        "failed = None",
        "only read as 'not failed': None and False alike",
    ),
    "locustjump.runs.loop.xǁTrainerǁ__init____mutmut_8": (
        'self.metrics_row = "XXXX"',
        "read only without a checkpoint, at generation 0, whose row "
        "truncate_metrics never writes, and for its commas: none in either",
    ),
    # a new run's metrics.csv: its header only (generation 0 reads no row)
    **alike(
        "locustjump.runs.trainer.x__create",
        "truncate_metrics reads the checkpoint's row only beyond generation 0",
        {
            11: "0, None, run.diagnostics",
            19: '0, "XXXX", run',
        },
    ),
    "locustjump.runs.trainer.x__check_new__mutmut_34": (
        "frozen is not None or cls.requires",
        "a behaviour built on no run ignores the genomes given (get_behaviour)",
    ),
    "locustjump.runs.trainer.x__check_new__mutmut_62": (
        "lm.load_model(cfg.model, )",
        "a rollout's memory counts the creature's records and MuJoCo's arena, "
        "the same in every scene here (checked on the debris field)",
    ),
    "locustjump.runs.trainer.x_train__mutmut_59": (
        "_check_new(out, cfg, cls, frozen, None)",
        "the second check's Trainer is thrown away: only what it refuses counts",
    ),
    "locustjump.cli.resolve.x_own_terrains__mutmut_12": (
        "(isinstance(summary, dict)) or True",
        "read_json gives a JSON object or refuses the file",
    ),
    "locustjump.cli.resolve.x_scene_override__mutmut_17": (
        "(t is None) and False",
        "terrains_arg gives None only when nothing is asked, returned before",
    ),
    "locustjump.ranges.xǁRangeǁ__str____mutmut_5": (
        '"XX[(XX"',
        "an interval's text starts with [, (, > or <, never with X",
    ),
    # a change time or genome of integers divides into floats either way, and
    # the rules read the change time alone
    **{
        f"locustjump.tasks.rules.xǁ{cls}ǁ{f}__mutmut_{n}": (text, _FLOATS)
        for cls, f, n, text in (
            ("RuleController", "params_for", 4, "dtype=None"),
            ("RuleController", "params_for", 6, "np.asarray(change_time, )"),
            ("RuleController", "prepare", 2, "dtype=None"),
            ("RuleController", "prepare", 4, "np.asarray(params, )"),
            ("RuleGetupController", "prepare", 3, "dtype=None"),
            ("RuleGetupController", "prepare", 5, "np.asarray(params, )"),
            ("RuleGetupController", "prepare", 7, "params[:, :2]"),
        )
    },
    "locustjump.tasks.rules.xǁRuleGetupControllerǁact__mutmut_7": (
        "targets, None)",
        "the rules read no step: the touch timer is their clock",
    ),
    **alike(
        "locustjump.tasks.ceiling.xǁOpenLoopǁprepare",
        "np.tanh makes float64 of integer genes either way (and of floats)",
        {
            3: "dtype=None",
            5: "np.asarray(params, )",
        },
    ),
    **alike(
        "locustjump.present.stats.x_family_table",
        "both lists come from tested, one adjusted p per comparison: equal lengths",
        {31: "strict=None", 34: "zip(tested, adjusted, )", 35: "strict=False"},
    ),
    **alike(
        "locustjump.present.episodes.x_episode_score",
        "the three records are arrays of one rollout: one row per start state each",
        {37: "strict=None", 42: "- strict=True, | - ) | + )", 49: "strict=False"},
    ),
    "locustjump.rundir.trajectory.x_write_trajectory_csv__mutmut_13": (
        '"%.6F"',
        "%F differs from %f only for inf and nan, and the time column is "
        "step x CONTROL_DT (finite)",
    ),
    "locustjump.present.stats.x_holm__mutmut_3": (
        "[2.0] * len(p)",
        "every place is written in the loop (it visits a permutation of the "
        "indices) before the list is returned",
    ),
    **alike(
        "locustjump.runs.study_pairs.x_families",
        "a resolution's rows are compared() over pairs(study): one per pair",
        {24: "strict=None", 27: "zip(pairs(study), rows, )", 29: "strict=False"},
    ),
    "locustjump.runs.study_pairs.x_families__mutmut_21": (
        "break",
        "rows are missing at every resolution or at none: an arm with fewer "
        "than 2 runs has fewer at all, and a height term is a task's, at every "
        "resolution or none",
    ),
    "locustjump.cli.resolve.x__checked__mutmut_12": (
        'option.lstrip("XX-XX")',
        "lstrip takes a set of characters: X and - strip an option's leading "
        "dashes alike (no option starts with X)",
    ),
    **alike(
        "locustjump.cli.console.xǁConsoleǁemit",
        "print writes to sys.stdout as it is at the call when given no file or None",
        {9: "print(text, file=None)", 11: "print(text, )"},
    ),
    "locustjump.cli.interrupts.x__handler__mutmut_12": (
        "_received.append(None)",
        "received() reads only whether a signal came, not which",
    ),
}
