"""The equivalent mutants of the debris field's geometry (``sim/bvh.py``,
``sim/rubble.py``), the start states (``tasks/starts.py``) and the engine's
shared job, reference episode and loop (``sim/engine/job.py``,
``episode.py``, ``loop.py``, ``numpy_step.py``), taken on 2026-11-27, each
with the reason (``scripts/mutation_equivalent.py`` adds them to the rest)."""

from mutation_reasons import alike, zip_strict

_JOB = "locustjump.sim.engine.job"
_CREATURE = "locustjump.sim.creature"
_TEXT = (
    "MuJoCo's XML reader ignores text between elements: the document compiles "
    "to the same model"
)
_MIRROR = "dividing by 1 or -1 is multiplying by it, exactly"
_LOOP = "locustjump.sim.engine.loop"

SIM: dict[str, tuple[str, str]] = {
    # sim/creature.py: the MJCF's text, and what only a direction is read of
    **alike(
        f"{_CREATURE}.x_creature_mjcf",
        _TEXT,
        {
            5: 'legs = "XXXX".join(',
            56: 'servos = "XXXX".join(',
            66: 'touch = "XXXX".join(',
            84: 'assets=\'XX<material name="cuticle"',
            86: '\'XX    <material name="leg"',
        },
    ),
    **alike(f"{_CREATURE}.x__defaults", _TEXT, {9: '"XXXX"'}),
    **alike(
        f"{_CREATURE}.x__defaults",
        "rigid struts are geoms of the body, with no joint: the strut class's "
        "joint default, written or not, is never used",
        {7: "if (p.strut_stiffness == 0) and False"},
    ),
    **zip_strict(
        f"{_CREATURE}.x_creature_mjcf",
        (59, 62, 63),
        "names.ACTUATORS, names.ACTUATED_JOINTS",
        "one servo per actuated joint: names.ACTUATORS is made from that tuple",
    ),
    **zip_strict(
        f"{_CREATURE}.x_creature_mjcf",
        (69, 72, 73),
        "names.TOUCH_SENSORS, names.TARSUS_SITES",
        "two constant tuples of two names each, one per side",
    ),
    **alike(f"{_CREATURE}.x__hind_leg", _MIRROR, {3: "s / np.array([1, sign, 1])"}),
    **alike(
        f"{_CREATURE}.x__strut",
        _MIRROR,
        {3: "s / np.array([1, sign, 1])", 10: "_unit(direction) / np.array"},
    ),
    **alike(
        f"{_CREATURE}.x__strut",
        "MuJoCo normalises a hinge's axis: a longer one is the same axis",
        {42: "np.cross(d, (0.0, 0.0, 2.0))"},
    ),
    **alike(
        f"{_CREATURE}.x__unit",
        "only a direction is read of it: a strut ends at a + d * drop / -d_z, "
        "the same point for any length of d, and MuJoCo normalises a joint axis",
        {7: "a * np.linalg.norm(a)"},
    ),
    **alike(
        f"{_CREATURE}.x__unit",
        "its callers pass tuples of floats, which NumPy makes float64 arrays",
        {3: "np.asarray(v, None)", 5: "np.asarray(v, )"},
    ),
    # sim/model.py: text MuJoCo ignores, a default it holds, and the flat
    # document the keyframe is settled in (made twice alike, or with a key)
    **alike(
        "locustjump.sim.model.x_to_mjcf",
        _TEXT,
        {
            9: 'pairs = "XXXX".join(',
            16: "flags = 'XX\\n    <flag",
            18: 'if world.broad_phase else "XXXX"',
        },
    ),
    **alike(
        "locustjump.sim.model.x_to_mjcf",
        "MuJoCo's default fifth friction coefficient of a pair is 0.0001, the "
        "value written",
        {29: "0.005, 0.0001)}", 30: "0.005, 0.0001, )}"},
    ),
    **alike(
        "locustjump.sim.model.x_to_mjcf",
        "on the flat floor the document without a keyframe is the one just "
        "written; with a keyframe, the settling does not read it (it starts "
        "from the written pose)",
        {
            44: "if (scene.is_flat) and False else",
            47: "to_mjcf(p, keyframe=None)",
            49: "to_mjcf(p, )",
            50: "to_mjcf(p, keyframe=True)",
        },
    ),
    **alike(
        "locustjump.sim.engine.rollout.x_rollout",
        "a rollout's memory counts the creature's records and MuJoCo's arena, "
        "the same in every scene here (checked on the debris field)",
        {35: "lm.load_model(model_params, ), params.shape[0] * k"},
    ),
    **alike(
        "locustjump.sim.engine.mjlayout.x_offsets",
        "the struct is cut after the last of the fields named in mjData's "
        "order, sensordata: the others come before it, named or not",
        {
            8: '_struct("mjData", "ctrl", "sensordata", "userdata")',
            9: '_struct("mjData", "qpos", "sensordata", "userdata")',
            11: '"sensordata", )',
        },
    ),
    **alike(
        "locustjump.sim.engine.mjlayout.x_offsets",
        _TEXT,
        {35: "'XX<joint name=", 37: "'XX<actuator>"},
    ),
    **alike(
        f"{_CREATURE}.x_leg_tip",
        "angles 2 pi apart: the same sine and cosine (to rounding, 1e-16 m)",
        {5: "t = h + math.pi + math.radians(knee_deg)"},
    ),
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
