"""What every engine strategy shares (``sim/engine/job.py``), piece by
piece: the rule that decides which episodes failed, start states, a job's
checks and its split, a result's head and concatenation, the inputs'
addresses, the memory estimate, the contact records and the recorder."""

from types import SimpleNamespace

import mujoco
import numpy as np
import pytest

from locustjump.sim import model as lm
from locustjump.sim import sensors
from locustjump.sim.controller import MLP
from locustjump.sim.engine import job as jb
from locustjump.sim.engine.job import RolloutJob, RolloutResult, StartStates
from locustjump.sim.scene import Debris

NW = int(mujoco.mjtWarning.mjNWARNING)


# -- the unstable rule -------------------------------------------------------


def test_a_finite_episode_without_warnings_did_not_fail():
    got = jb.went_unstable(np.zeros((3, 5)), np.zeros((3, NW), int))
    assert got.dtype == bool and got.tolist() == [False, False, False]


@pytest.mark.parametrize("warning", [0, NW // 2, NW - 1])
def test_any_warning_counted_fails_its_episode(warning):
    counts = np.zeros((3, NW), int)
    counts[1, warning] = 2
    got = jb.went_unstable(np.zeros((3, 5)), counts)
    assert got.tolist() == [False, True, False]


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_a_position_not_finite_fails_its_episode(bad):
    qpos = np.zeros((3, 5))
    qpos[2, 4] = bad
    assert jb.went_unstable(qpos, np.zeros((3, NW), int)).tolist() == [
        False,
        False,
        True,
    ]


def test_an_episode_mujoco_raised_for_fails():
    ok = np.zeros((4, NW), int)
    got = jb.went_unstable(np.zeros((4, 5)), ok, np.array([0, 3]))
    assert got.tolist() == [True, False, False, True]
    counts = ok.copy()
    counts[1, 0] = 1
    got = jb.went_unstable(np.zeros((4, 5)), counts, np.array([2], int))
    assert got.tolist() == [False, True, True, False]


# -- start states ------------------------------------------------------------


def _states(k: int, offset: float = 0.0) -> StartStates:
    return StartStates(
        np.arange(k * 3.0).reshape(k, 3) + offset,
        np.arange(k * 2.0).reshape(k, 2) + offset,
        np.arange(k * 4.0).reshape(k, 4) + offset,
    )


def test_start_states_take_and_concat():
    s = _states(4)
    assert len(s) == 4
    t = s.take(np.array([3, 1]))
    np.testing.assert_array_equal(t.qpos, s.qpos[[3, 1]])
    np.testing.assert_array_equal(t.qvel, s.qvel[[3, 1]])
    np.testing.assert_array_equal(t.ctrl, s.ctrl[[3, 1]])
    both = StartStates.concat([s, _states(2, 100.0)])
    assert len(both) == 6
    np.testing.assert_array_equal(both.qvel[4:], _states(2, 100.0).qvel)
    np.testing.assert_array_equal(both.ctrl[:4], s.ctrl)


@pytest.mark.parametrize("which", ["qvel", "ctrl"])
def test_start_states_of_unequal_lengths_are_refused(which):
    arrays = {
        "qpos": np.zeros((3, 2)),
        "qvel": np.zeros((3, 2)),
        "ctrl": np.zeros((3, 4)),
    }
    arrays[which] = arrays[which][:2]
    with pytest.raises(ValueError) as got:
        StartStates(**arrays)
    assert str(got.value) == "StartStates arrays must have the same first dimension"


def test_the_ready_state_is_the_keyframes_copied(mjmodel):
    s = StartStates.ready(mjmodel)
    key = mjmodel.key(lm.READY_KEY)
    assert len(s) == 1
    for got, want in ((s.qpos, key.qpos), (s.qvel, key.qvel), (s.ctrl, key.ctrl)):
        np.testing.assert_array_equal(got[0], want)
    s.qpos[0, 0] += 1.0
    assert mjmodel.key(lm.READY_KEY).qpos[0] == key.qpos[0] != s.qpos[0, 0]


# -- a job -------------------------------------------------------------------

NET = MLP(9, 2, 4)


def _job(n: int = 10, **kw) -> RolloutJob:
    params = np.arange(n * NET.num_params, dtype=float).reshape(n, -1)
    starts = StartStates(np.zeros((n, 3)), np.zeros((n, 2)), np.zeros((n, 4)))
    return RolloutJob(lm.LocustParams(), NET, params, starts, 7, **kw)


def test_a_jobs_defaults():
    j = _job(3)
    assert j.record == ("qpos", "obs") and j.label == ""
    assert j.engine == jb.DEFAULT_ENGINE == "numba" and j.scene.is_flat
    assert j.n_episodes == 3 and jb.strategy_name(j) == "numba"
    assert jb.strategy_name(_job(3, engine="numpy")) == "numpy"


def test_a_jobs_bad_input_is_named():
    with pytest.raises(ValueError) as got:
        RolloutJob(lm.LocustParams(), NET, np.zeros((2, 5)), _states(2), 7)
    assert str(got.value) == f"params has shape (2, 5), expected (n, {NET.num_params})"
    with pytest.raises(ValueError, match=r"params has shape \(32,\)"):
        RolloutJob(lm.LocustParams(), NET, np.zeros(NET.num_params), _states(1), 7)
    with pytest.raises(ValueError) as got:
        RolloutJob(lm.LocustParams(), NET, np.zeros((2, NET.num_params)), _states(3), 7)
    assert str(got.value) == "params and starts must have one row per episode"
    with pytest.raises(ValueError) as got:
        _job(2, record=("qpos", "torque", "force"))
    assert str(got.value) == (
        f"cannot record ['force', 'torque']; choose from {jb.RECORDABLE}"
    )
    with pytest.raises(ValueError, match="n_steps must be"):
        RolloutJob(lm.LocustParams(), NET, np.zeros((1, NET.num_params)), _states(1), 0)
    assert _job(1).n_steps == 7
    numpy_int = RolloutJob(
        lm.LocustParams(), NET, np.zeros((1, NET.num_params)), _states(1), np.int64(7)
    )
    assert type(numpy_int.n_steps) is int  # stored as checked: a Python int
    one = RolloutJob(
        lm.LocustParams(), NET, np.zeros((1, NET.num_params)), _states(1), 1
    )
    assert one.n_steps == 1


@pytest.mark.parametrize(
    ("n", "k", "sizes"),
    [(10, 3, [3, 4, 3]), (10, 1, [10]), (3, 5, [1, 1, 1]), (4, 4, [1, 1, 1, 1])],
)
def test_split_covers_every_episode_in_order(n, k, sizes):
    j = _job(
        n,
        record=("qpos", "penetration"),
        label="x",
        engine="numpy",
        scene=Debris(seed=2),
    )
    parts = j.split(k)
    assert [p.n_episodes for p in parts] == sizes
    np.testing.assert_array_equal(np.concatenate([p.params for p in parts]), j.params)
    np.testing.assert_array_equal(
        np.concatenate([p.starts.qpos for p in parts]), j.starts.qpos
    )
    for p in parts:
        assert (p.model_params, p.controller, p.n_steps) == (j.model_params, NET, 7)
        assert (p.record, p.label, p.engine, p.scene) == (
            j.record,
            "x",
            "numpy",
            Debris(seed=2),
        )


def test_no_split_part_is_empty():
    for n in range(1, 41):
        for k in range(1, n + 3):
            sizes = [p.n_episodes for p in _job(n).split(k)]
            assert len(sizes) == min(k, n) and min(sizes) >= 1 and sum(sizes) == n


# -- a result ----------------------------------------------------------------


def _result(n: int, base: float, steps: int) -> RolloutResult:
    return RolloutResult(
        {"qpos": np.full((n, 3, 2), base), "obs": np.full((n, 3, 9), base + 1)},
        np.arange(n) % 2 == 1,
        np.arange(n) + base,
        steps,
    )


def test_a_result_reads_its_records_by_name_and_keeps_its_head():
    r = _result(4, 10.0, 99)
    assert r["obs"] is r.records["obs"]
    h = r.head(2)
    assert h.records["qpos"].shape == (2, 3, 2) and h["obs"].shape == (2, 3, 9)
    assert h.unstable.tolist() == [False, True] and h.steps.tolist() == [10, 11]
    assert h.control_steps == 99  # all of them were simulated
    assert RolloutResult({}, np.zeros(0, bool), np.zeros(0)).control_steps == 0


def test_results_concatenate_in_order_and_add_their_steps():
    c = RolloutResult.concat([_result(2, 1.0, 5), _result(3, 7.0, 8)])
    assert c["qpos"][:, 0, 0].tolist() == [1, 1, 7, 7, 7]
    assert c["obs"][:, 0, 0].tolist() == [2, 2, 8, 8, 8]
    assert c.unstable.tolist() == [False, True, False, True, False]
    assert c.steps.tolist() == [1, 2, 7, 8, 9] and c.control_steps == 13
    one = RolloutResult.concat([_result(2, 1.0, 5)])
    assert one["qpos"].shape == (2, 3, 2) and one.control_steps == 5


# -- inputs, memory, contacts ------------------------------------------------


def test_consecutive_addresses_become_a_slice_others_stay():
    assert jb._as_slice(np.array([3, 4, 5])) == slice(3, 6)
    assert jb._as_slice(np.array([7])) == slice(7, 8)
    gappy = jb._as_slice(np.array([3, 5, 6]))
    assert isinstance(gappy, np.ndarray) and gappy.tolist() == [3, 5, 6]
    assert jb._as_slice(np.array([5, 4])).tolist() == [5, 4]
    assert jb._as_slice(np.array([], int)).size == 0


def test_the_observer_reads_the_models_addresses(mjmodel, params):
    idx = lm.ModelIndex.of(mjmodel)
    d = mujoco.MjData(mjmodel)
    mujoco.mj_resetDataKeyframe(mjmodel, d, mjmodel.key(lm.READY_KEY).id)
    mujoco.mj_forward(mjmodel, d)
    qpos, sens = d.qpos[None].copy(), d.sensordata[None].copy()
    got = jb.observer(idx, params)(qpos, sens)
    want = sensors.paper_inputs(
        qpos,
        sens,
        joint_adr=idx.qpos_joints,
        touch_adr=idx.touch,
        body_length=params.body_length,
    )
    np.testing.assert_array_equal(got, want)
    other = jb.observer(idx, lm.LocustParams(scale=2 * params.scale))
    assert other(qpos, sens)[0, 5] != got[0, 5]  # 1 / (H + 1): H in body lengths


def test_the_record_shapes():
    assert jb.record_shapes(17, 3) == {
        "qpos": (17,),
        "obs": (9,),
        "ctrl": (4,),
        "memory": (3,),
        "penetration": (),
        "wall_contact": (),
    }
    assert set(jb.record_shapes(1, 1)) == set(jb.RECORDABLE)


def test_a_rollouts_memory_is_its_records_and_one_simulation_each(mjmodel):
    per_step = (mjmodel.nq + 9 + 1) * 8.0  # qpos, obs and a wall flag
    want = 3 * (11 * per_step + mjmodel.narena + 64 * 1024)
    got = jb.rollout_bytes(mjmodel, 3, 10, ("qpos", "obs", "wall_contact"))
    assert got == want and isinstance(got, float)
    memory = jb.rollout_bytes(mjmodel, 1, 10, ("memory",), nmem=5)
    assert memory == 11 * 5 * 8.0 + mjmodel.narena + 64 * 1024
    assert jb.rollout_bytes(mjmodel, 1, 10, ("memory",)) == (
        11 * 8.0 + mjmodel.narena + 64 * 1024
    )


def test_which_jobs_record_contacts():
    assert not jb.records_contacts(_job(1, record=("qpos", "obs", "ctrl", "memory")))
    assert jb.records_contacts(_job(1, record=("qpos", "penetration")))
    assert jb.records_contacts(_job(1, record=("wall_contact",)))


def test_depth_is_the_penetration_of_a_signed_distance():
    assert jb.depth(-0.03) == 0.03 and jb.depth(0.02) == 0.0 and jb.depth(0.0) == 0.0
    np.testing.assert_array_equal(jb.depth(np.array([-1, 2, -0.5])), [1, 0, 0.5])
    assert jb.depth(np.array([-1, 0])).dtype == np.float64
    single = jb.depth(np.array([-0.1, 0.2], dtype=np.float32))
    assert single.dtype == np.float64  # read in double precision


def test_a_control_steps_contacts_are_its_substeps_extremes():
    idx = SimpleNamespace(deepest=0, walls=np.array([2, 3]))
    sub = np.zeros((3, 2, 4))  # 3 episodes, 2 substeps, 4 sensor values
    sub[:, :, 0] = [[0.01, -0.02], [-0.05, -0.01], [0.3, 0.2]]  # signed distances
    sub[1, 1, 3] = 1.0  # episode 1 touches the second wall at its last substep
    sub[2, 0, 1] = 5.0  # not a wall's sensor
    pen, wall = jb.contact_maxima(sub, idx)
    np.testing.assert_array_equal(pen, [0.02, 0.05, 0.0])
    np.testing.assert_array_equal(wall, [0.0, 1.0, 0.0])
    assert wall.dtype == np.float64


def test_a_progress_bar_only_for_a_labelled_job(monkeypatch):
    """Over the job's control steps, named by its label, shown on a terminal
    only (``disable=None``)."""
    assert jb.progress(_job(2)) is None
    monkeypatch.setattr(jb, "tqdm", lambda **kw: kw)
    assert jb.progress(_job(2, label="kick")) == {
        "total": 7,
        "desc": "kick",
        "unit": "step",
        "disable": None,
        "dynamic_ncols": True,
    }


# -- the recorder ------------------------------------------------------------


def _recorder(names=("qpos", "obs", "ctrl", "memory", "penetration", "wall_contact")):
    return jb.Recorder(names, 2, 3, jb.record_shapes(5, 1))


def test_the_recorder_keeps_each_named_field_and_only_those():
    rec = _recorder(("obs", "penetration"))
    assert set(rec.arrays) == {"obs", "penetration"}
    assert rec.arrays["obs"].shape == (2, 4, 9) and rec.arrays["penetration"].shape == (
        2,
        4,
    )
    of = jb.Recorder.of(_job(3, record=("qpos", "memory")), nq=5)
    assert of.arrays["qpos"].shape == (3, 8, 5) and of.arrays["memory"].shape == (
        3,
        8,
        0,
    )


def test_the_recorder_writes_a_row_and_stopped_episodes_repeat_theirs():
    rec = _recorder(("memory", "qpos", "ctrl"))  # any order of names
    qpos, obs, ctrl, mem = (
        np.ones((2, 5)),
        np.zeros((2, 9)),
        np.full((2, 4), 2.0),
        np.full((2, 1), 3.0),
    )
    rec.write(0, qpos, obs, ctrl, mem)
    assert rec.arrays["qpos"][:, 0].tolist() == [[1.0] * 5] * 2
    assert rec.arrays["ctrl"][:, 0].tolist() == [[2.0] * 4] * 2
    assert rec.arrays["memory"][:, 0].tolist() == [[3.0]] * 2
    rec.write(1, qpos * 4, obs, ctrl * 4, mem * 4, stopped=np.array([False, True]))
    assert rec.arrays["qpos"][:, 1, 0].tolist() == [4.0, 1.0]
    assert rec.arrays["ctrl"][:, 1, 0].tolist() == [8.0, 2.0]
    assert rec.arrays["memory"][:, 1, 0].tolist() == [12.0, 3.0]


def test_the_recorder_writes_contacts_of_some_episodes():
    rec = _recorder(("qpos", "penetration", "wall_contact"))
    for a in rec.arrays.values():
        a[:] = np.nan  # what no write reaches stays NaN
    rec.write_contacts(0, np.array([0, 1]), np.array([0.1, 0.2]), np.array([0.0, 1.0]))
    rec.write_contacts(1, 1, 0.5, 1.0)
    rec.write_contacts(1, 0, 0.7, 0.0, stopped=np.array([True, False]))
    assert rec.arrays["penetration"][:, :2].tolist() == [[0.1, 0.1], [0.2, 0.5]]
    assert rec.arrays["wall_contact"][:, :2].tolist() == [[0.0, 0.0], [1.0, 1.0]]
    only = _recorder(("penetration",))
    only.write_contacts(0, 0, 0.3, 1.0)  # no wall record: nothing else written
    assert (
        set(only.arrays) == {"penetration"} and only.arrays["penetration"][0, 0] == 0.3
    )


def test_the_recorder_fills_the_rest_with_the_last_row():
    rec = _recorder(("qpos", "wall_contact"))
    rec.arrays["qpos"][:, 1] = 9.0
    rec.arrays["wall_contact"][:, 1] = 1.0
    rec.fill_from(2)
    assert (rec.arrays["qpos"][:, 2:] == 9.0).all()
    assert (rec.arrays["wall_contact"][:, 2:] == 1.0).all()
