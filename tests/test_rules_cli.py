import json

import mujoco
import numpy as np
import pytest

from locustjump import cli
from locustjump.rundir import TRAJECTORY_COLUMNS
from locustjump.sim import model as lm
from locustjump.sim import names
from locustjump.sim.controller import MLP
from locustjump.sim.engine.rollout import StartStates, rollout
from locustjump.tasks.composed import START_ROLL
from locustjump.tasks.getup import rolled_starts
from locustjump.tasks.reference import run_rules
from locustjump.tasks.rules import RuleController, RuleGetupController


def test_rule_based_jumps_at_least_three_times(params):
    run = run_rules(steps=3000, model_params=params)
    apexes = [round(j.apex_height, 3) for j in run.jumps]
    print(f"rule-based: {len(run.jumps)} jumps, apex heights [m]: {apexes}")
    assert len(run.jumps) >= 3
    assert not run.unstable
    assert all(j.rise > 0.1 * params.body_length for j in run.jumps)


def test_rules_kick_only_after_change_time(params):
    """Touch time < change time: legs stay at phi, the creature does not jump."""
    run = run_rules(change_time=100.0, steps=600, model_params=params)
    assert run.jumps == []
    np.testing.assert_allclose(run.ctrl[-1], params.ready_angles())


def test_rule_rate_bounds_each_target_change(params):
    base = RuleController.for_model(params)
    slow = RuleController(base.ready, base.extended, rate=np.radians(5.0))
    obs = np.zeros((2, 9))
    obs[:, 4] = [-1.0, 1.0]  # the first touches (and kicks), the second does not
    targets = np.array([base.ready, base.extended])
    for ctl, bound in ((base, 10.0), (slow, 5.0)):
        d, mem = ctl.act(ctl.prepare([[0.0], [0.0]]), np.zeros((2, 1)), obs, targets, 0)
        np.testing.assert_allclose(np.abs(d).max(axis=1), np.radians(bound))
        assert np.all(np.sign(d[0]) == np.sign(np.subtract(base.extended, base.ready)))
        np.testing.assert_array_equal(mem[:, 0], [1.0, 0.0])


def test_rules_with_getup_hand_over_below_the_threshold(params, rng):
    """The hybrid is the rules while U_z >= below and the get-up network while
    U_z < below, step for step and bit for bit (NumPy path: on the compiled
    one the network alone would run its kernel, within ulps of NumPy's)."""
    rules = RuleController.for_model(params)
    getup = MLP().random_genomes(rng, 1)[0]
    side = rolled_starts(params, (START_ROLL,))
    standing = StartStates.ready(lm.load_model(params))
    rec = ("qpos", "obs", "ctrl")

    def run(ctl, p, starts, steps=400):
        return rollout(ctl, p, starts, steps, model_params=params, record=rec,
                       engine="numpy")  # fmt: skip

    alone = run(rules, rules.params_for(0.5), standing)
    never = RuleGetupController(rules, below=-2.0)
    hybrid = run(never, never.params_for(0.5, getup), standing)
    for k in rec:
        np.testing.assert_array_equal(hybrid[k], alone[k])
    always = RuleGetupController(rules, below=2.0)
    net = run(MLP(), getup[None], side)
    hybrid = run(always, always.params_for(0.5, getup), side)
    for k in rec:
        np.testing.assert_array_equal(hybrid[k], net[k])
    assert always.num_params == 145 and always.memory_size == 1


def test_cli_model_writes_loadable_mjcf(tmp_path, capsys):
    out = tmp_path / "locust.xml"
    assert cli.main(["model", "--scale", "2", "--out", str(out)]) == 0
    m = mujoco.MjModel.from_xml_path(str(out))
    assert m.nu == 4 and m.key("ready").id == 0
    assert cli.main(["model", "--out", str(out)]) == 2  # exists: refused
    assert "file exists" in capsys.readouterr().err


def test_cli_model_file_is_the_engine_model(tmp_path):
    """The written MJCF is the whole world: stock MuJoCo loads it into the very
    model the engine simulates (floor, pairs and keyframe included)."""
    out = tmp_path / "locust.xml"
    argv = ["model", "--scale", "3", "--strut-stiffness", "1e-5", "--out", str(out)]
    assert cli.main(argv) == 0
    written = mujoco.MjModel.from_xml_path(str(out))
    engine = lm.load_model(lm.LocustParams(scale=3, strut_stiffness=1e-5))
    for size in ("nbody", "ngeom", "npair", "njnt", "nu", "nsensor", "nkey", "nq"):
        assert getattr(written, size) == getattr(engine, size), size
    assert written.npair > 0 and written.nkey == 1
    for name in dir(engine):
        value = getattr(engine, name)
        if isinstance(value, np.ndarray):
            np.testing.assert_array_equal(getattr(written, name), value, err_msg=name)


def test_cli_rules_writes_csv_and_figure(tmp_path, capsys):
    out = tmp_path / "rules"
    assert cli.main(["rules", "--steps", "400", "--out", str(out)]) == 0
    header = (out / "trajectory.csv").read_text().splitlines()[0]
    assert header.split(",") == TRAJECTORY_COLUMNS
    table = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    assert table.shape == (401, len(TRAJECTORY_COLUMNS))
    assert (out / "trajectory.png").stat().st_size > 1000
    assert "jumps in 400 steps" in capsys.readouterr().out


@pytest.mark.parametrize(
    "argv, needle",
    [
        (["rules", "--steps", "0", "--out", "X"], "--steps must be an integer in [1"),
        (["rules", "--steps", "-5", "--out", "X"], "--steps must be an integer in [1"),
        (["rules", "--change-time", "-1", "--out", "X"], "--change-time"),
        (["model", "--scale", "0", "--out", "X"], "--scale must be"),
        (["model", "--scale", "-2", "--out", "X"], "--scale must be"),
        (["rules", "--strut-stiffness", "-1", "--out", "X"], "--strut-stiffness"),
        (["rules", "--out", "X", "--bogus"], "unrecognized arguments: --bogus"),
    ],
)
def test_cli_bad_input_one_line_exit_2(tmp_path, capsys, argv, needle):
    argv = [str(tmp_path / a) if a == "X" else a for a in argv]
    with pytest.raises(SystemExit) as e:
        cli.main(argv)
    assert e.value.code == 2
    err = capsys.readouterr().err
    assert needle in err and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []  # nothing written


def test_cli_refuses_non_empty_out_dir(tmp_path, capsys):
    (tmp_path / "keep.txt").write_text("precious")
    assert cli.main(["rules", "--steps", "10", "--out", str(tmp_path)]) == 2
    assert "not empty" in capsys.readouterr().err
    assert [p.name for p in tmp_path.iterdir()] == ["keep.txt"]


def test_find_jumps_splits_at_a_bounce(params):
    from locustjump.sim.analysis import find_jumps

    stand = lm.standing_height(params)
    t = np.linspace(0, 1, 201)
    arc = 4 * t * (1 - t)  # one unit-high parabola
    z = np.concatenate([stand + arc, stand + 0.3 + arc, [stand]])  # bounce at +0.3
    q = np.zeros((z.size, 7))
    q[:, 0] = np.arange(z.size) * 0.01
    q[:, 2] = z
    jumps = find_jumps(q, params)
    assert len(jumps) == 2
    assert jumps[0].apex_height == pytest.approx(stand + 1, abs=1e-3)
    assert jumps[1].apex_height == pytest.approx(stand + 1.3, abs=1e-3)


def test_sprung_struts_are_an_option_and_leave_the_default_alone(tmp_path, capsys):
    """strut_stiffness > 0 hangs the fore and middle legs on sprung hinges; the
    default MJCF has no such joints, and the inputs still read the hind legs."""
    rigid = lm.load_model(lm.LocustParams())
    assert rigid.njnt == 5  # root + the four actuated hinges
    p = lm.LocustParams(strut_stiffness=1e-5)
    m = lm.load_model(p)
    struts = ["fore_l", "mid_l", "fore_r", "mid_r"]
    assert m.njnt == 9
    assert all(m.jnt_stiffness[m.joint(j).id] > 0 for j in struts)
    idx = lm.ModelIndex.of(m)
    assert [m.joint(m.jnt_qposadr.tolist().index(a)).name for a in idx.qpos_joints] == [
        "hip_l", "knee_l", "hip_r", "knee_r",
    ]  # fmt: skip
    # settled at the start state: the middle legs sag a little and hold
    mid = m.jnt_qposadr[m.joint(names.MID_LEGS[0]).id]
    sag = np.degrees(m.key(lm.READY_KEY).qpos[mid])
    assert 0.1 < sag < p.strut_swing
    out = tmp_path / "rules"
    argv = ["rules", "--steps", "600", "--strut-stiffness", "1e-5", "--out", str(out)]
    assert cli.main(argv) == 0
    assert "jumps in 600 steps" in capsys.readouterr().out
    summary = json.loads((out / "summary.json").read_text())
    assert summary["model"]["strut_stiffness"] == 1e-05
    # a video of it re-simulates the same creature, sprung struts included
    from locustjump.present.playback import source_of

    assert source_of(out).model_params == p
    with pytest.raises(ValueError, match="strut_stiffness"):
        lm.LocustParams(strut_stiffness=-1.0)
