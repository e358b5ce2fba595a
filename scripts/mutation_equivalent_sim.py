"""The equivalent mutants of the debris field's geometry (``sim/bvh.py``,
``sim/rubble.py``), the start states (``tasks/starts.py``) and the engine's
shared job, reference episode and loop (``sim/engine/job.py``,
``episode.py``, ``loop.py``, ``numpy_step.py``), taken on 2026-11-27, each
with the reason (``scripts/mutation_equivalent.py`` adds them to the rest)."""

from mutation_reasons import alike, zip_strict

_JOB = "locustjump.sim.engine.job"
_LOOP = "locustjump.sim.engine.loop"

SIM: dict[str, tuple[str, str]] = {
    # sim/bvh.py: NumPy's defaults, and what the tree's layout never reaches
    **alike(
        "locustjump.sim.bvh.x__split",
        "a ufunc's accumulate runs along axis 0 by default",
        {
            12: "np.minimum.accumulate(lo[order], )",
            20: "np.maximum.accumulate(hi[order], )",
            28: "accumulate(lo[order][::-1], )",
            39: "accumulate(hi[order][::-1], )",
        },
    ),  # fmt: skip
    **alike(
        "locustjump.sim.bvh.x_rebuild_bvh",
        "the last node of a pre-order tree is a leaf, which the loop skips "
        "(range(num - 2, ...) leaves it out, -2 adds node -1, the same leaf)",
        {109: "range(num - 2, -1, -1)", 111: "range(num - 1, -2, -1)"},
    ),
    **alike(
        "locustjump.sim.bvh.x_rebuild_bvh",
        "the arrays are written into MuJoCo's own (bvh_child, bvh_nodeid, "
        "bvh_depth), which cast the small integers they hold",
        {
            38: "dtype=None",
            41: "np.full((num, 2), -1, )",
            48: "dtype=None",
            51: "np.full(num, -1, )",
            56: "dtype=None",
            58: "np.zeros(num, )",
        },
    ),  # fmt: skip
    **alike(
        "locustjump.sim.bvh.x_rebuild_bvh",
        "the root has no parent: any negative parent is skipped, and its side "
        "is never read",
        {66: "0, -2, 0)", 67: "0, -1, 1)"},
    ),
    # sim/rubble.py: equalities of continuous draws, falsy flags, one cell more
    "locustjump.sim.rubble.x__boxes__mutmut_80": (
        "out[:, 1]) > d.clearing + reach]",
        "a box centre exactly at the clearing's edge plus its reach has "
        "probability 0 (uniform doubles)",
    ),
    **alike(
        "locustjump.sim.rubble.x__height_grid",
        "a cell centre exactly on a box's edge has probability 0 (uniform "
        "positions and yaws)",
        {108: "(np.abs(u) < sx / 2)", 112: "(np.abs(v) < sy / 2)"},
    ),
    **alike(
        "locustjump.sim.rubble.x__height_grid",
        "one cell more past a box's reach is tried, and found outside it",
        {72: "min(nx, i1 + 3)", 87: "min(ny, j1 + 3)"},
    ),
    "locustjump.sim.rubble.x__boxes__mutmut_82": (
        "out.flags.writeable = None",
        "None sets the flag as False does",
    ),
    "locustjump.sim.rubble.x__height_grid__mutmut_131": (
        "grid.flags.writeable = None",
        "None sets the flag as False does",
    ),
    "locustjump.tasks.starts.x_ground_top__mutmut_11": (
        "np.linspace(-bl, bl, 102)",
        "101 points 0.02 body lengths apart look at every cell of the height "
        "grid (HEIGHT_CELL_BL, 0.02); 102, a little closer, at every one too",
    ),
    # sim/engine/episode.py: row 0 written to every row (the index None adds an
    # axis), each row after it written again by its own step or filled
    **alike(
        "locustjump.sim.engine.episode.x_reference_rollout",
        "None as a row or episode index writes the start's values to every "
        "row of the one episode; each later row is written again by its own "
        "step, or by fill_from when the episode stops",
        {
            39: "rec.write(None, d.qpos[None]",
            50: "rec.write_contacts(None, 0",
            51: "rec.write_contacts(0, None",
        },
    ),
    "locustjump.sim.engine.episode.xǁEpisodeǁ_contacts__mutmut_7": (
        "if n else 1.0",
        "without a contact the distance only feeds depth(), which reads any "
        "distance >= 0 as no penetration",
    ),
    # sim/engine/loop.py and numpy_step.py: flags read only for their truth,
    # buffers given or made, writes that select no episode, an action no
    # physics follows
    **alike(
        f"{_LOOP}.x_begin",
        "row 0 is recorded without a check (the sub is not read) and before "
        "any episode stopped: None reads as False, an empty or one-row sub "
        "alike, and 'stopped' with every episode live writes the same targets",
        {
            28: "np.empty((1, job.model_params.substeps",
            30: "step(0, None, no_sub",
            33: "np.arange(job.n_episodes), None, True)",
            44: "np.arange(job.n_episodes), True, True)",
        },
    ),
    **alike(
        f"{_LOOP}.x_run_steps",
        "a flag read only for its truth: None reads as False",
        {150: "step(t + 1, None, no_sub", 55: "stopped = None"},
    ),
    **alike(
        f"{_LOOP}.x_run_steps",
        "the action after the last control step is applied to simulations "
        "that are not stepped again, after the last row is recorded: nothing "
        "reads it",
        {104: "act = t - 1 < T", 106: "act = t + 1 <= T"},
    ),
    f"{_LOOP}.x_run_steps__mutmut_126": (
        "newly[errors] = ~unstable[errors]",
        "newly is never set where unstable is, so '|=' and '=' agree there",
    ),
    **alike(
        f"{_LOOP}.x_run_steps",
        "until an episode stops none is unstable, so freezing the unstable "
        "ones freezes none",
        {168: "frozen = unstable if (stopped) or True"},
    ),
    "locustjump.sim.engine.numpy_step.xǁNumpyStepǁ__call____mutmut_31": (
        "frozen = self.unstable if (stopped) or True",
        "until an episode stops none is unstable, so freezing the unstable "
        "ones freezes none",
    ),
    f"{_LOOP}.x_run_steps__mutmut_18": (
        "if (records_contacts(job)) or True",
        "the contact rows are written only into the records the job keeps "
        "(Recorder.write_contacts skips a field not recorded)",
    ),
    **alike(
        f"{_LOOP}.x_run_steps",
        "after a failed call no episode is selected (live[:0]), so no value "
        "is written, whatever it is",
        {
            185: "live[:0], None, empty",
            186: "empty, None, np.ones",
            38: "empty = None",
            40: "empty = np.empty(1)",
        },
    ),  # fmt: skip
    **alike(
        f"{_LOOP}.x_run_steps",
        "the sensordata buffer is reused, not needed: without it (or under "
        "another name) mujoco.batch allocates the same values anew",
        {
            48: "sub = None",
            49: '"XXsensordataXX"',
            50: '"SENSORDATA"',
            80: "out=None)",
            83: 'record=("sensordata",), )',
        },
    ),  # fmt: skip
    f"{_LOOP}.x_run_steps__mutmut_56": (
        "stopped = True",
        "'stopped' with every episode live: the rollout of ids (all of them) "
        "and the indexed writes give what the whole-batch ones do",
    ),
    # sim/engine/job.py: zips of equal lengths by construction, no-op casts
    **zip_strict(
        f"{_JOB}.xǁRecorderǁwrite",
        (4, 7, 8),
        "self._order, self._step",
        "both are made from the same list of step records, one item each",
    ),
    **zip_strict(
        f"{_JOB}.xǁRolloutJobǁsplit",
        (42, 45, 49),
        "bounds[:-1], bounds[1:]",
        "two slices of one array, each one shorter than it",
    ),
    f"{_JOB}.x_contact_maxima__mutmut_6": (
        "astype(None)",
        "astype(None) casts to NumPy's default dtype, float64, as asked",
    ),
    f"{_JOB}.x_contact_maxima__mutmut_12": (
        "cast(None, wall)",
        "typing.cast does nothing when run: it only tells the type checker",
    ),
    "locustjump.sim.bvh.x_rebuild_bvh__mutmut_144": (
        "np.finfo(None).eps",
        "np.finfo(None) is float64's, as np.finfo(float)",
    ),
}
