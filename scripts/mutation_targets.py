"""What ``scripts/mutation.py`` mutates: each module, the focused test files
that state it, the functions mutated where not all of a module is, and what
the table of ``docs/mutation.md`` leaves out."""

from __future__ import annotations

#: module (under src/locustjump) -> the focused test files that state it
MODULES: dict[str, tuple[str, ...]] = {
    "evo/rcga.py": (
        "tests/test_rcga.py",
        "tests/test_rcga_behaviour.py",
        "tests/test_optimizers.py",
    ),
    "rundir/metrics.py": ("tests/test_metrics_contract.py",),
    "rundir/config.py": (
        "tests/test_config_contract.py",
        "tests/test_config_coerce.py",
        "tests/test_migrations.py",
    ),
    "sim/sensors.py": (
        "tests/test_sensors_inputs.py",
        "tests/test_sensors_controller.py",
    ),
    "sim/actuation.py": (
        "tests/test_actuation_rule.py",
        "tests/test_sensors_controller.py",
    ),
    "rundir/checkpoint.py": ("tests/test_checkpoint_contract.py",),
    "evo/base.py": (
        "tests/test_optimizer_contract.py",
        "tests/test_optimizer_registry.py",
        "tests/test_rcga_behaviour.py",
    ),
    "evo/random_search.py": ("tests/test_optimizer_contract.py",),
    "evo/cma.py": ("tests/test_cma_contract.py",),
    "evo/__init__.py": ("tests/test_optimizer_registry.py",),
    "tasks/kick.py": (
        "tests/test_kick_fitness.py",
        "tests/test_qd.py",
        "tests/test_qd_run.py",
    ),
    "tasks/getup.py": ("tests/test_task_fitness.py",),
    "tasks/return_legs.py": ("tests/test_task_fitness.py",),
    "tasks/base.py": ("tests/test_task_fitness.py",),
    "tasks/composed.py": ("tests/test_task_fitness.py",),
    # the statistics every comparison and every claim of docs/science.md rests on:
    # the exact rank tests, and the comparison, power and verdict made of them
    "present/ranktests.py": ("tests/test_ranktests.py", "tests/test_stats.py"),
    "present/stats.py": ("tests/test_stats.py", "tests/test_holm.py"),
    # the study table those claims are read from: its cells, budgets, pairs
    "runs/study_table.py": ("tests/test_study_table.py", "tests/test_late_gain.py"),
    # how an error names a setting on the command line: its option
    "cli/flags.py": ("tests/test_flags_units.py",),
    # the memory check every command makes before it allocates
    "sim/resources.py": ("tests/test_resources.py",),
    # a run's per-step CSV (replay, evaluate): each column's record
    "rundir/trajectory.py": ("tests/test_trajectory_table.py",),
    # the table's episode columns: terms, distance, jumps, walls, penetration
    "present/episodes.py": ("tests/test_episodes_units.py",),
    # the gain in the last third and the declared flattening rule it decides
    "runs/learning.py": ("tests/test_late_gain.py", "tests/test_study_table.py"),
    # the height-only ablation of issue #45: its answer rests on this fitness
    "tasks/height_only.py": ("tests/test_height_only.py",),
    # quality diversity (issue #46): descriptors, the archive, the optimizers
    "tasks/descriptors.py": (
        "tests/test_descriptors.py",
        "tests/test_qd.py",
        "tests/test_qd_run.py",
    ),
    "evo/archive.py": ("tests/test_archive.py",),
    "evo/qd.py": ("tests/test_qd_params.py",),
    "evo/map_elites.py": ("tests/test_qd_params.py",),
    "evo/cma_me.py": ("tests/test_qd_params.py",),
    "tasks/repertoire.py": ("tests/test_repertoire.py",),
    # the ground's height on debris, which every debris fitness subtracts
    "sim/debris.py": ("tests/test_rubble.py",),
    "sim/bvh.py": ("tests/test_bvh.py", "tests/test_debris.py"),
    "tasks/starts.py": ("tests/test_starts.py", "tests/test_recovery.py"),
    "sim/rubble.py": ("tests/test_rubble.py",),
    # what every engine strategy shares: the unstable rule, a job, its records
    "sim/engine/job.py": ("tests/test_job_units.py",),
    # one episode on one MjData: the reference loop and the environments' step
    "sim/engine/episode.py": (
        "tests/test_episode_units.py",
        "tests/test_rollout.py",
        "tests/test_envs_units.py",
    ),
    # the behaviours' registry: every name the command line and plugins use
    "tasks/__init__.py": ("tests/test_tasks_registry.py",),
    # the thread backend: its thread count and its cached batches
    "sim/engine/threads.py": ("tests/test_threads_units.py",),
    # where and how a rollout runs, chosen by name
    "sim/engine/backends.py": ("tests/test_backends_units.py",),
    "sim/engine/strategies.py": ("tests/test_backends_units.py",),
    # the engine's one loop and its NumPy control step (the reference strategy)
    "sim/engine/loop.py": ("tests/test_loop_units.py", "tests/test_rollout.py"),
    "sim/engine/numpy_step.py": ("tests/test_loop_units.py", "tests/test_rollout.py"),
    # Ctrl-C and SIGTERM: a command stops, says so, and resumes
    "cli/interrupts.py": ("tests/test_interrupts_units.py",),
    # where the command line shows the library's log records
    "cli/console.py": ("tests/test_console_units.py",),
    # the paper's network: every genome is read through its layout
    "sim/controller.py": ("tests/test_controller_units.py",),
    # the Gymnasium environments (the gym extra): observation, action, reward
    "envs.py": ("tests/test_envs_units.py", "tests/test_envs.py"),
    # the jumps, falls and heights every results table counts
    "sim/analysis.py": ("tests/test_analysis.py",),
    # a repertoire's file: written without pickle, read back only as written
    "rundir/archive.py": ("tests/test_archive_file.py",),
    # how long a study has left, as its processes take its runs
    "runs/study_plan.py": ("tests/test_study_forecast.py",),
    # which comparison a study's figure draws on which row
    "present/study_figure.py": ("tests/test_study_figure.py",),
    # every read of a file a user names: regular files only, bounded, no pickle
    "rundir/reads.py": (
        "tests/test_reads_units.py",
        "tests/test_reads_npz.py",
        "tests/test_reads.py",
    ),
    # where a command writes: checked first, never a run's own files, nothing
    # half-made left
    "rundir/outputs.py": ("tests/test_outputs.py",),
    # what a study file may say: every claim of a study rests on its arms,
    # seeds, budgets and held-out terrains being the ones declared
    "runs/studyfile.py": (
        "tests/test_studyfile.py",
        "tests/test_studyarms.py",
        "tests/test_study_primary.py",
    ),
    "runs/study_pairs.py": ("tests/test_study_primary.py", "tests/test_study_table.py"),
    "runs/studyarms.py": ("tests/test_studyarms.py", "tests/test_studyfile.py"),
    # one writer per directory: what keeps a run, a study's workers and a
    # command's output from being written twice at once
    "rundir/lock.py": ("tests/test_lock.py",),
    # a study's runs: how far each is, and that each on disk is the declared one
    "runs/study.py": ("tests/test_study_runs.py",),
    # the seeds a user asks for (--seeds, a study file's seeds)
    "runs/multiseed.py": ("tests/test_seeds.py",),
    # `compare`: groups of runs, their budgets and the table of their tests
    "present/compare.py": ("tests/test_compare_units.py", "tests/test_compare.py"),
    # every setting's range: what a command refuses, in one line, exit 2
    "ranges.py": ("tests/test_ranges_units.py", "tests/test_ranges.py"),
    # the parser's argument types: each option's value, or its one-line error
    "cli/argtypes.py": ("tests/test_argtypes.py",),
    # which elite of a repertoire `evaluate`, `render` and `view` play
    "rundir/elites.py": ("tests/test_elites.py",),
    # older run directories read as today's (a run's config, marker, files)
    "rundir/migrations.py": (
        "tests/test_migrations_units.py",
        "tests/test_migrations.py",
    ),
    # how every one-line error names its settings, and a behaviour's options
    "errors.py": ("tests/test_errors.py",),
    "tasks/options.py": ("tests/test_errors.py",),
    # a run's files written whole or not at all, its arrays read as written
    "rundir/files.py": ("tests/test_rundir_files.py",),
    "rundir/arrays.py": ("tests/test_rundir_files.py",),
    # the creature's numbers: what follows from them, what is refused
    "sim/params.py": ("tests/test_params.py",),
    # the terrains a genome is scored on, and how their fitness is combined
    "sim/scene.py": ("tests/test_terrains.py",),
    "sim/world.py": ("tests/test_terrains.py",),
    # what `evaluate` reports: the match with the record, the held-out gap
    "present/evaluate.py": ("tests/test_evaluation_records.py",),
    # what makes a directory a run (resume, refusals) and where derived files go
    "rundir/layout.py": ("tests/test_layout.py",),
    # a run read back: its config, best genome and the frozen genomes it needs
    "rundir/run.py": ("tests/test_run_files.py",),
    # the training loop: a row, a best genome and a checkpoint each generation
    "runs/loop.py": ("tests/test_loop.py",),
    # which run directory train may write, new or resumed, and what it refuses
    "runs/trainer.py": ("tests/test_trainer.py", "tests/test_loop.py"),
    # `train`'s options over a config file over the defaults; a command's terrains
    "cli/resolve.py": ("tests/test_resolve.py",),
    # plugins: what is registered or skipped, and what a run made with them needs
    "plugins.py": ("tests/test_plugin_loader.py",),
    # the paper's rules as a controller (the NumPy engine's), and the get-up
    # network taking over while overturned
    "tasks/rules.py": ("tests/test_rule_controller.py",),
    # how far the rule-based jumper got: the reference every report quotes
    "tasks/reference.py": ("tests/test_rules_outcome.py",),
    # the kick's ceiling: the open-loop controller and the apex rise
    "tasks/ceiling.py": ("tests/test_open_loop.py",),
    # the creature itself: its geometry, masses, joints, servos and sensors
    "sim/creature.py": ("tests/test_creature_units.py", "tests/test_scene.py"),
    # the document around it: solver, contact model, sensors, the keyframe
    "sim/model.py": (
        "tests/test_model_units.py",
        "tests/test_creature_units.py",
        "tests/test_scene.py",
    ),
    # the engine's entry point: the job it builds, the memory it checks first
    "sim/engine/rollout.py": ("tests/test_rollout_units.py", "tests/test_rollout.py"),
    # the raw offsets the compiled callback reads, or None: that path off
    "sim/engine/mjlayout.py": ("tests/test_mjlayout.py",),
    # what a reproduction of the paper is: budgets, stages, checks, command
    "runs/reproduction.py": ("tests/test_reproduction_units.py",),
    # the verdicts of results.md: each claim of the paper, its criterion and
    # why a run misses it; the composition question over seeds
    "present/stages/base.py": ("tests/test_claims_units.py",),
    "present/stages/__init__.py": ("tests/test_claims_units.py",),
    "present/stages/kick.py": ("tests/test_claims_units.py",),
    "present/stages/getup.py": ("tests/test_claims_units.py",),
    "present/stages/return_legs.py": ("tests/test_claims_units.py",),
    "present/stages/successive.py": ("tests/test_claims_units.py",),
    # results.md's numbers, budget table, reasons and held-out section
    "present/results.py": ("tests/test_results_units.py",),
}

#: modules of which only some functions are mutated (mutmut's name patterns):
#: a task's fitness, not its episode set-up or its report
FUNCTIONS: dict[str, tuple[str, ...]] = {
    # what reads no directory (the rest: tests/test_reproduce.py)
    "present/results.py": tuple(
        f"locustjump.present.results.x_{f}__mutmut_*"
        for f in (
            "minutes",
            "_budget_table",
            "_whys",
            "_num",
            "_spread",
            "_seeds",
            "held_out_markdown",
        )
    ),  # fmt: skip
    # the claims and their reasons, not the figures or the get-up sweep
    "present/stages/base.py": (
        "locustjump.present.stages.base.xǁClaimǁ*",
        "locustjump.present.stages.base.x_yes__mutmut_*",
        "locustjump.present.stages.base.x_fmt__mutmut_*",
        *(
            f"locustjump.present.stages.base.xǁReporterǁ{f}__mutmut_*"
            for f in ("claims", "report_section", "across_seeds")
        ),
    ),
    "present/stages/kick.py": (
        "locustjump.present.stages.kick.xǁKickReporterǁclaims__mutmut_*",
        "locustjump.present.stages.kick.x__reason__mutmut_*",
        "locustjump.present.stages.kick.xǁCeilingReporterǁclaims__mutmut_*",
    ),
    "present/stages/getup.py": (
        "locustjump.present.stages.getup.xǁGetUpReporterǁclaims__mutmut_*",
    ),
    "present/stages/return_legs.py": (
        "locustjump.present.stages.return_legs.xǁReturnLegsReporterǁclaims__mutmut_*",
        "locustjump.present.stages.return_legs.x__reason__mutmut_*",
    ),
    "present/stages/successive.py": (
        "locustjump.present.stages.successive.xǁComposedReporterǁclaims__mutmut_*",
        "locustjump.present.stages.successive.xǁMonolithicReporterǁ*",
        *(
            f"locustjump.present.stages.successive.x_{f}__mutmut_*"
            for f in ("_jumps", "_composed_reason", "sign_test")
        ),
    ),
    # a reproduction's budgets, checks, command and markers, not its training
    # of a stage (tests/test_reproduce.py)
    "runs/reproduction.py": (
        "locustjump.runs.reproduction.xǁBudgetǁ*",
        *(
            f"locustjump.runs.reproduction.xǁReproductionǁ{f}__mutmut_*"
            for f in (
                "open",
                "seed_dir",
                "for_seed",
                "command",
                "marker",
                "check",
                "start",
                "stage_done",
                "train_config",
            )
        ),  # fmt: skip
        *(
            f"locustjump.runs.reproduction.x_{f}__mutmut_*"
            for f in ("budget_of", "stages_of", "requires", "_read_marker")
        ),
    ),
    # the groups and the table, not the figure's drawing
    "present/compare.py": tuple(
        f"locustjump.present.compare.x_{f}__mutmut_*"
        for f in (
            "optimizer_label",
            "scene_label",
            "_key",
            "frozen_evaluations",
            "load_groups",
            "table",
            "_tests",
            "budget_note",
        )
    ),
    # the records and their JSON, not the re-simulation (tests/test_runs.py)
    "present/evaluate.py": (
        "locustjump.present.evaluate.xǁEvaluationǁ*",
        "locustjump.present.evaluate.xǁTerrainEvaluationǁ*",
        "locustjump.present.evaluate.x_plain__mutmut_*",
    ),
    # the outcome and the head of a run, not its simulation (tests/test_debris.py)
    "tasks/reference.py": (
        "locustjump.tasks.reference.x_rules_outcome__mutmut_*",
        "locustjump.tasks.reference.xǁRulesRunǁhead__mutmut_*",
    ),
    # the open-loop controller and the apex rise, not the behaviours' set-up
    "tasks/ceiling.py": (
        "locustjump.tasks.ceiling.xǁOpenLoopǁ*",
        "locustjump.tasks.ceiling.x_apex_rise__mutmut_*",
    ),
    # the environment but its frames: mutmut runs each mutant in a forked
    # child, where EGL hangs (NO_OPENGL below), so no frame is drawn there
    "envs.py": tuple(
        f"locustjump.envs.xǁLocustEnvǁ{f}__mutmut_*"
        for f in ("__init__", "model_params", "scene", "n_starts", "reset", "step")
    )
    + tuple(
        f"locustjump.envs.x_{f}__mutmut_*"
        for f in ("tasks", "_action", "register_envs")
    ),
    # the seeds' parser, not the reproduction over seeds (tests/test_multiseed.py)
    "runs/multiseed.py": ("locustjump.runs.multiseed.x_parse_seeds__mutmut_*",),
    # the runs' states, costs and checks, not the training loop of the workers
    # (tests/test_study_workers.py) nor the copying of a run to extend
    "runs/study.py": (
        "locustjump.runs.study.xǁRunStateǁ*",
        *(
            f"locustjump.runs.study.x_{f}__mutmut_*"
            for f in (
                "behaviour_for",
                "episode_steps",
                "score_steps",
                "generations_done",
                "states",
                "check_run",
                "_check_config",
                "_differences",
                "frozen_genomes",
            )
        ),
    ),
    "tasks/kick.py": (
        "locustjump.tasks.kick.x_kick_fitness__mutmut_*",
        "locustjump.tasks.kick.x_takeoff__mutmut_*",
        "locustjump.tasks.kick.xǁKickRewardǁ*",
        "locustjump.tasks.kick.xǁKickǁepisode_fitness__mutmut_*",
        "locustjump.tasks.kick.x_kick_descriptors__mutmut_*",
        "locustjump.tasks.kick.xǁKickǁepisode_descriptors__mutmut_*",
    ),
    "tasks/getup.py": (
        "locustjump.tasks.getup.x_up_z__mutmut_*",
        "locustjump.tasks.getup.x_getup_summary__mutmut_*",
        "locustjump.tasks.getup.xǁUpRewardǁ*",
        "locustjump.tasks.getup.xǁGetUpǁepisode_fitness__mutmut_*",
    ),
    "tasks/return_legs.py": (
        "locustjump.tasks.return_legs.x_joint_errors__mutmut_*",
        "locustjump.tasks.return_legs.xǁLegsRewardǁ*",
        "locustjump.tasks.return_legs.xǁReturnLegsǁepisode_fitness__mutmut_*",
    ),
    "tasks/base.py": (
        "locustjump.tasks.base.xǁBehaviourǁfitness__mutmut_*",
        "locustjump.tasks.base.xǁBehaviourǁfitness_terms__mutmut_*",
    ),
    "tasks/composed.py": (
        "locustjump.tasks.composed.x_successive_fitness__mutmut_*",
        "locustjump.tasks.composed.x_successive_terms__mutmut_*",
        "locustjump.tasks.composed.x_overturns__mutmut_*",
        "locustjump.tasks.composed.xǁHeightRewardǁ*",
    ),
    # the forecast (the rest reads files and measures this machine)
    "runs/study_plan.py": ("locustjump.runs.study_plan.x_forecast__mutmut_*",),
    # what is drawn where, not how it looks (sizes, colours, fonts)
    "present/study_figure.py": tuple(
        f"locustjump.present.study_figure.x_{f}__mutmut_*"
        for f in ("resolution_label", "_resolutions", "shift_rows")
    ),
    # the ground's height (the rest is the scene's MJCF, checked by physics)
    "sim/debris.py": ("locustjump.sim.debris.xǁDebrisǁheights__mutmut_*",),
    # an episode's numbers from its records (the rest simulates and replays)
    "present/episodes.py": tuple(
        f"locustjump.present.episodes.x_{f}__mutmut_*"
        for f in ("episode_score", "_scenes")
    ),
    # how far learning got and the declared rule, not the budgets and figure
    # that moved here from runs/study_table.py (outside its selection there)
    "runs/learning.py": tuple(
        f"locustjump.runs.learning.x_{f}__mutmut_*" for f in ("late_gain", "flat_note")
    ),
    # the table from its rows, not the scoring and file work around it
    "runs/study_table.py": tuple(
        f"locustjump.runs.study_table.x_{f}__mutmut_*"
        for f in (
            "make_table",
            "_med",
            "_seeds_text",
            "_budget_note",
            "_reading",
            "_fmt",
            "_label",
            "_mean",
            "_max",
        )
    ),  # fmt: skip
}

#: what the table leaves out, and why (docs/mutation.md)
NOT_COVERED = """\
`sim/kernels.py` (with `sim/cephes.py`) is not in the table: every
kernel is compiled by Numba (`@njit`), and mutmut 3 does not mutate a
decorated function (it would have to wrap it in a Python trampoline,
which Numba cannot compile). Mutating the kernels needs a tool that
rewrites the file on disk for each mutant (cosmic-ray) and a test run
that cannot reuse compiled code: the kernels' tests
(`tests/test_engine.py`, `tests/test_incallback.py`: 19 tests when this was
measured, 22 now) pass with
`NUMBA_DISABLE_JIT=1` in 86 s, against 323 s from an empty cache
(compiling) and 30 s warm (measured 2026-11-25 on the busy 2-core VM),
so 1.5 to 5 minutes a mutant. No cached machine code can stand in for a
mutant of the modules above: Numba 0.68 keys a kernel's cache on a
SHA-256 of the kernel's own file, `kernels.py` reads no global from
another locustjump module but `cephes.py`'s functions, whose SHA-256 it
carries (`tests/test_incallback.py` checks both), the modules above are
plain NumPy, and each run starts with an empty Numba cache
(`NUMBA_CACHE_DIR`) and a fresh copy of the package under `mutants/src`.

`envs.py` is mutated all but its frames (`render`, `close`): mutmut runs
each mutant in a forked child, and EGL hangs in a forked child (a renderer
made in the parent, then one in the child, never returns), so the module's
tests run there with MuJoCo's rendering off (`MUJOCO_GL=disable`).
`tests/test_envs.py` draws a frame of each environment in the default run.
"""


#: modules whose focused tests would render: mutmut forks a child per mutant
#: and EGL hangs in a forked child (measured: a renderer made in the parent,
#: then one in a child, never returns), so these run with MuJoCo's rendering
#: off (``MUJOCO_GL=disable``; the tests check what they can without frames)
NO_OPENGL = frozenset({"envs.py"})


#: what the functions of :data:`FUNCTIONS` are, in the table
PART = {
    "present/results.py": "what reads no directory",
    "present/stages/base.py": "the claim, its words",
    "present/stages/kick.py": "its claim",
    "present/stages/getup.py": "its claims",
    "present/stages/return_legs.py": "its claim",
    "present/stages/successive.py": "claims, composition",
    "runs/reproduction.py": "all but training a stage",
    "envs.py": "all but its frames",
    "runs/study.py": "the runs' checks and costs",
    "runs/multiseed.py": "the seeds' parser",
    "present/evaluate.py": "its records",
    "tasks/reference.py": "the outcome",
    "tasks/ceiling.py": "controller, apex",
    "present/compare.py": "groups and table",
    "runs/study_table.py": "the table",
    "runs/learning.py": "late gain, the flat rule",
    "present/episodes.py": "an episode's numbers",
    "runs/study_plan.py": "the forecast",
    "present/study_figure.py": "its rows",
    "sim/debris.py": "the ground's height",
    "tasks/kick.py": "fitness, descriptors",
    "tasks/composed.py": "fitness, falls and recoveries",
}
